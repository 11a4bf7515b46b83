// SPDX-License-Identifier: MIT
/// @file LiveDevices.h
/// @brief The device layer wired for a live run: both transports (libusb and hidraw) feeding
/// one EventQueue, pumped once per frame on the frame thread.
#pragma once

#include "vsculpt/app/DeviceInput.h"
#include "vsculpt/core/Config.h"
#include "vsculpt/devices/DeviceEvent.h"
#include "vsculpt/devices/Transport.h"

#include <functional>
#include <iosfwd>
#include <memory>
#include <vector>

namespace vsculpt::app {

class LiveDevices {
  public:
    /// Starts the transports for the config's rules. A transport that cannot start (no USB
    /// stack, no /sys) is logged as a warning and left out; nothing here throws for a missing
    /// device: they may arrive later.
    explicit LiveDevices(const core::DevicesConfig& cfg);
    ~LiveDevices();

    /// Hands every queued event, oldest first, to `sink`.
    void pump(const std::function<void(const devices::DeviceEvent&)>& sink);
    /// Sends what DeviceInput asked for; failures are counted by the transport.
    void send(const std::vector<DeviceOutput>& output);
    std::vector<devices::ConnectedDevice> connected() const;
    const std::vector<devices::DeviceRule>& rules() const { return mRules; }
    uint64_t droppedReports() const { return mQueue.dropped(); }

  private:
    std::vector<devices::DeviceRule> mRules;
    devices::EventQueue mQueue;
    std::vector<std::unique_ptr<devices::Transport>> mTransports;
    std::vector<devices::DeviceEvent> mScratch;
};

}  // namespace vsculpt::app
