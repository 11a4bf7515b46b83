// SPDX-License-Identifier: MIT
#include "vsculpt/studio/Interaction.h"

#include <algorithm>

namespace vsculpt::studio {

using namespace vsculpt::core;

Interaction::Interaction(Studio& studio, bool alwaysEngaged)
    : mStudio(studio), mAlwaysEngaged(alwaysEngaged), mEngaged(alwaysEngaged) {}

void Interaction::cycleTool() {
    switch (session().tool()) {
        case ToolKind::Add:
            mStudio.setTool(ToolKind::Carve);
            break;
        case ToolKind::Carve:
            // Thesis placement has no smooth tool (unit weights): the cycle skips it there.
            mStudio.setTool(session().sculpture().config().placement != PlacementMode::Thesis
                                ? ToolKind::Smooth
                                : ToolKind::Select);
            break;
        case ToolKind::Smooth:
            mStudio.setTool(ToolKind::Select);
            break;
        case ToolKind::Select:
            mStudio.setTool(ToolKind::Add);
            break;
    }
}

void Interaction::cycleMirror() {
    const MirrorAxis next[] = {MirrorAxis::X, MirrorAxis::Y, MirrorAxis::Z, MirrorAxis::None};
    mStudio.setMirror(next[int(session().mirror())]);
}

std::vector<int> Interaction::offeredSizes() const {
    std::vector<int> sizes = session().sculpture().config().zoom.allowedSizes[session().zoom() - 1];
    std::sort(sizes.rbegin(), sizes.rend());  // largest first
    return sizes;
}

void Interaction::step(const Vec3& toolPos) {
    if (session().tool() == ToolKind::Select) {
        if (session().zoom() < kZoomLevels) mStudio.setZoom(session().zoom() + 1, toolPos);
        return;
    }
    const std::vector<int> sizes = offeredSizes();  // descending
    auto it = std::find(sizes.begin(), sizes.end(), session().size());
    const int next = (it == sizes.end() || it + 1 == sizes.end()) ? sizes.front() : *(it + 1);
    mStudio.setSize(next);
}

bool Interaction::jumpToSize(int level) {
    if (!toolAllowedAtZoom(session().sculpture().config(), session().zoom(), level)) return false;
    mStudio.setSize(level);
    return true;
}

bool Interaction::jumpToZoom(int zoom, const Vec3& center) {
    if (zoom < 1 || zoom > kZoomLevels) return false;
    mStudio.setZoom(zoom, center);
    return true;
}

void Interaction::overview() {
    mStudio.setZoom(1, Vec3(0.0));
}

void Interaction::setEngaged(bool engaged) {
    mEngaged = engaged || mAlwaysEngaged;
    if (!mEngaged) mStudio.endStroke();
}

void Interaction::moveTool(const Vec3& worldPos) {
    if (!mEngaged || session().tool() == ToolKind::Select) {
        mStudio.endStroke();
        return;
    }
    if (!session().inStroke()) mStudio.beginStroke();
    mStudio.strokeSample(worldPos, true);
}

}  // namespace vsculpt::studio
