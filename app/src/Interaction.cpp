// SPDX-License-Identifier: MIT
#include "vsculpt/app/Interaction.h"

#include <algorithm>

namespace vsculpt::app {

using namespace vsculpt::core;

Interaction::Interaction(Session& session, bool alwaysEngaged)
    : mSession(session), mAlwaysEngaged(alwaysEngaged), mEngaged(alwaysEngaged) {}

void Interaction::cycleTool() {
    switch (mSession.tool()) {
        case ToolKind::Add:
            mSession.setTool(ToolKind::Carve);
            break;
        case ToolKind::Carve:
            mSession.setTool(ToolKind::Select);
            break;
        case ToolKind::Select:
            mSession.setTool(ToolKind::Add);
            break;
    }
}

std::vector<int> Interaction::offeredSizes() const {
    std::vector<int> sizes = mSession.sculpture().config().zoom.allowedSizes[mSession.zoom() - 1];
    std::sort(sizes.rbegin(), sizes.rend());  // largest first
    return sizes;
}

void Interaction::step(const Vec3& toolPos) {
    if (mSession.tool() == ToolKind::Select) {
        if (mSession.zoom() < kZoomLevels) mSession.setZoom(mSession.zoom() + 1, toolPos);
        return;
    }
    const std::vector<int> sizes = offeredSizes();  // descending
    auto it = std::find(sizes.begin(), sizes.end(), mSession.size());
    const int next = (it == sizes.end() || it + 1 == sizes.end()) ? sizes.front() : *(it + 1);
    mSession.setSize(next);
}

bool Interaction::jumpToSize(int level) {
    if (!toolAllowedAtZoom(mSession.sculpture().config(), mSession.zoom(), level)) return false;
    mSession.setSize(level);
    return true;
}

bool Interaction::jumpToZoom(int zoom, const Vec3& center) {
    if (zoom < 1 || zoom > kZoomLevels) return false;
    mSession.setZoom(zoom, center);
    return true;
}

void Interaction::overview() {
    mSession.setZoom(1, Vec3(0.0));
}

void Interaction::setEngaged(bool engaged) {
    mEngaged = engaged || mAlwaysEngaged;
    if (!mEngaged) mSession.endStroke();
}

void Interaction::moveTool(const Vec3& worldPos) {
    if (!mEngaged || mSession.tool() == ToolKind::Select) {
        mSession.endStroke();
        return;
    }
    if (!mSession.inStroke()) mSession.beginStroke();
    mSession.strokeSample(worldPos, true);
}

}  // namespace vsculpt::app
