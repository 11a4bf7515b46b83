// SPDX-License-Identifier: MIT
#include "vsculpt/app/LiveDevices.h"

#include "vsculpt/devices/HidrawTransport.h"
#include "vsculpt/devices/UsbTransport.h"

#include <spdlog/spdlog.h>

namespace vsculpt::app {

LiveDevices::LiveDevices(const core::DevicesConfig& cfg) : mRules(deviceRules(cfg)) {
    devices::TransportOptions options;
    options.rules = mRules;
    options.transfersInFlight = cfg.transfersInFlight;
    options.stallTimeoutS = cfg.stallTimeoutS;
    options.rescanIntervalS = cfg.rescanIntervalS;
    bool wantUsb = false, wantHidraw = false;
    for (const auto& r : mRules)
        (r.access == devices::DeviceAccess::Libusb ? wantUsb : wantHidraw) = true;
    if (wantUsb) {
        try {
            mTransports.push_back(std::make_unique<devices::UsbTransport>(options, mQueue));
        } catch (const devices::TransportError& e) {
            spdlog::warn("{}; libusb devices are not available", e.what());
        }
    }
    if (wantHidraw)
        mTransports.push_back(std::make_unique<devices::HidrawTransport>(options, mQueue));
    for (auto& t : mTransports)
        t->start();
}

LiveDevices::~LiveDevices() = default;

void LiveDevices::pump(const std::function<void(const devices::DeviceEvent&)>& sink) {
    mScratch.clear();
    mQueue.drain(mScratch);
    for (const auto& e : mScratch)
        sink(e);
}

void LiveDevices::send(const std::vector<DeviceOutput>& output) {
    for (const auto& o : output)
        for (auto& t : mTransports) {
            const auto status =
                o.feature ? t->sendFeature(o.device, o.bytes) : t->sendOutput(o.device, o.bytes);
            if (status != devices::SendStatus::NotConnected) break;
        }
}

std::vector<devices::ConnectedDevice> LiveDevices::connected() const {
    std::vector<devices::ConnectedDevice> all;
    for (const auto& t : mTransports) {
        auto c = t->connected();
        all.insert(all.end(), c.begin(), c.end());
    }
    return all;
}

}  // namespace vsculpt::app
