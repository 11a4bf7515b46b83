// SPDX-License-Identifier: MIT
#include "vsculpt/devices/DeviceEvent.h"

#include <algorithm>
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

std::vector<uint8_t> arrivalBytes(uint16_t vendor, uint16_t product,
                                  std::span<const uint8_t> reportDescriptor) {
    // Sized once, then filled: growing a vector made from an initializer list trips GCC 12's
    // -Warray-bounds false positive at -O2 (the sanitizer build's log).
    std::vector<uint8_t> b(4 + reportDescriptor.size());
    b[0] = uint8_t(vendor & 0xff);
    b[1] = uint8_t(vendor >> 8);
    b[2] = uint8_t(product & 0xff);
    b[3] = uint8_t(product >> 8);
    std::copy(reportDescriptor.begin(), reportDescriptor.end(), b.begin() + 4);
    return b;
}

std::span<const uint8_t> arrivalDescriptor(const DeviceEvent& e) {
    if (e.kind != DeviceEventKind::Arrived || e.bytes.size() <= 4) return {};
    return std::span<const uint8_t>(e.bytes).subspan(4);
}

bool parseArrival(const DeviceEvent& e, uint16_t& vendor, uint16_t& product) {
    if (e.kind != DeviceEventKind::Arrived || e.bytes.size() < 4) return false;
    vendor = static_cast<uint16_t>(e.bytes[0] | (e.bytes[1] << 8));
    product = static_cast<uint16_t>(e.bytes[2] | (e.bytes[3] << 8));
    return true;
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
