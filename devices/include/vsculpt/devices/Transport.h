// SPDX-License-Identifier: MIT
/// @file Transport.h
/// @brief The seam between device I/O and everything else. A transport opens the devices its
/// rules name, reads them on its own thread(s) and pushes DeviceEvents into an EventQueue; it
/// never decodes. UsbTransport (libusb) and HidrawTransport (Linux hidraw) implement it.
#pragma once

#include "vsculpt/devices/DeviceEvent.h"
#include "vsculpt/devices/DeviceRule.h"

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace vsculpt::devices {

/// The transport could not start at all (no libusb context, no /sys): a user-facing message.
class TransportError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// Result of a send; device I/O never throws.
enum class SendStatus { Ok, NotConnected, NoEndpoint, Failed };
const char* toString(SendStatus s);

struct TransportCounters {
    uint64_t reports = 0;     ///< reports pushed to the queue
    uint64_t bytes = 0;       ///< bytes in those reports
    uint64_t errors = 0;      ///< failed transfers / reads (each one counted)
    uint64_t arrivals = 0;    ///< times the device was opened
    uint64_t departures = 0;  ///< times it left (unplug or too many errors)
    uint64_t stalls = 0;      ///< stall warnings raised
};

struct ConnectedDevice {
    std::string name;  ///< the rule's name
    uint16_t vendor = 0, product = 0;
    std::string where;  ///< "usb 1:5" or "/dev/hidraw3"
    TransportCounters counters;
};

class Transport {
  public:
    virtual ~Transport() = default;
    /// Starts the I/O thread(s): opens what is connected now, then follows arrivals and
    /// removals until the destructor.
    virtual void start() = 0;
    /// Devices open right now, with their counters.
    virtual std::vector<ConnectedDevice> connected() const = 0;
    /// Sends bytes to the device's OUT endpoint (commands, e.g. Polhemus start-up).
    virtual SendStatus sendOutput(const std::string& device, std::span<const uint8_t> bytes) = 0;
    /// Sends a HID feature report; bytes[0] is the report id (e.g. a headset keep-alive).
    virtual SendStatus sendFeature(const std::string& device, std::span<const uint8_t> bytes) = 0;
};

struct TransportOptions {
    std::vector<DeviceRule> rules;
    int transfersInFlight = 4;     ///< libusb: IN transfers kept submitted per device
    double stallTimeoutS = 2.0;    ///< no report for this long: a Stalled event
    double rescanIntervalS = 1.0;  ///< hidraw, and libusb without hotplug: look for arrivals
    int errorsBeforeLeft = 10;     ///< consecutive failed transfers that count as unplugged
};

}  // namespace vsculpt::devices
