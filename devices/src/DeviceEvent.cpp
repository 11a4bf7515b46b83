// SPDX-License-Identifier: MIT
#include "vsculpt/devices/DeviceEvent.h"

#include <chrono>

namespace vsculpt::devices {

const char* toString(DeviceEventKind k) {
    switch (k) {
        case DeviceEventKind::Report:
            return "report";
        case DeviceEventKind::Arrived:
            return "arrived";
        case DeviceEventKind::Left:
            return "left";
        case DeviceEventKind::Stalled:
            return "stalled";
        case DeviceEventKind::Resumed:
            return "resumed";
    }
    return "?";
}

int64_t monotonicNowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

bool EventQueue::push(DeviceEvent event) {
    std::lock_guard lock(mMutex);
    const bool report = event.kind == DeviceEventKind::Report;
    if (report) {
        if (mReports >= mMaxReports) {
            ++mDropped;
            return false;
        }
        ++mReports;
    }
    mEvents.push_back(std::move(event));
    return true;
}

void EventQueue::drain(std::vector<DeviceEvent>& out) {
    std::lock_guard lock(mMutex);
    for (auto& e : mEvents)
        out.push_back(std::move(e));
    mEvents.clear();
    mReports = 0;
}

uint64_t EventQueue::dropped() const {
    std::lock_guard lock(mMutex);
    return mDropped;
}

}  // namespace vsculpt::devices
