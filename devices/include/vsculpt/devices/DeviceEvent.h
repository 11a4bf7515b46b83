// SPDX-License-Identifier: MIT
/// @file DeviceEvent.h
/// @brief What a transport hands to the frame thread: raw reports and connection changes,
/// timestamped on the host's monotonic clock, plus the bounded queue between them.
///
/// Transports never decode: the reader thread (or libusb event thread) copies the bytes,
/// stamps them and pushes; the consumer decodes, records and maps them. The same events read
/// back from a recording go through the same consumer, which is what makes replay faithful.
#pragma once

#include <cstdint>
#include <deque>
#include <mutex>
#include <span>
#include <string>
#include <vector>

namespace vsculpt::devices {

enum class DeviceEventKind : uint8_t {
    Report,   ///< one input report / bulk chunk in `bytes`
    Arrived,  ///< the device was opened and its transfers are running
    Left,     ///< unplugged or failed: no more reports until it arrives again
    Stalled,  ///< no report for longer than the stall timeout (a warning, not a Left)
    Resumed,  ///< reports flow again after a stall
};

const char* toString(DeviceEventKind k);

struct DeviceEvent {
    DeviceEventKind kind = DeviceEventKind::Report;
    int64_t timeNs = 0;  ///< host steady clock, ns, when the transport received it
    std::string device;  ///< the config rule's name ("spacemouse", "tracker", ...)
    /// Report: the report as read. Arrived: the device's USB vendor and product id, 2 bytes
    /// each, little-endian, then its HID report descriptor when the transport could read it
    /// (arrivalBytes). Otherwise empty.
    std::vector<uint8_t> bytes;
};

std::vector<uint8_t> arrivalBytes(uint16_t vendor, uint16_t product,
                                  std::span<const uint8_t> reportDescriptor = {});
/// Vendor and product from an Arrived event's bytes; false when there are fewer than 4.
bool parseArrival(const DeviceEvent& e, uint16_t& vendor, uint16_t& product);
/// The HID report descriptor an Arrived event carries (empty when none).
std::span<const uint8_t> arrivalDescriptor(const DeviceEvent& e);

/// Host monotonic time in ns (std::chrono::steady_clock), the clock of DeviceEvent::timeNs.
int64_t monotonicNowNs();

/// Multi-producer, single-consumer queue with a bound. A full queue drops incoming reports
/// (counted) but never connection events, so the consumer always learns about Left/Arrived.
/// Pushing holds a mutex for a deque append: short enough for a libusb callback.
class EventQueue {
  public:
    explicit EventQueue(std::size_t maxReports = 8192) : mMaxReports(maxReports) {}

    /// Returns false when a report was dropped because the queue is full.
    bool push(DeviceEvent event);
    /// Moves every queued event into `out` (appending), oldest first.
    void drain(std::vector<DeviceEvent>& out);
    uint64_t dropped() const;

  private:
    mutable std::mutex mMutex;
    std::deque<DeviceEvent> mEvents;
    std::size_t mMaxReports;
    std::size_t mReports = 0;
    uint64_t mDropped = 0;
};

}  // namespace vsculpt::devices
