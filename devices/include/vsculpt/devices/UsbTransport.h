// SPDX-License-Identifier: MIT
/// @file UsbTransport.h
/// @brief The libusb transport: one libusb context with its own event thread, asynchronous
/// IN transfers kept in flight per device, hotplug arrival and removal (or a periodic rescan
/// where libusb has no hotplug), commands and feature reports sent asynchronously.
///
/// Threads: every libusb callback runs on the event thread and only copies bytes into the
/// EventQueue and resubmits; opening, closing and clearing halts happen on the same thread
/// outside callbacks. A device whose transfers fail with NO_DEVICE, or fail
/// `errorsBeforeLeft` times in a row, is closed and reported as Left; it is opened again
/// when it arrives again.
#pragma once

#include "vsculpt/devices/Transport.h"

#include <memory>

namespace vsculpt::devices {

class UsbTransport final : public Transport {
  public:
    /// Creates the libusb context; throws TransportError when libusb cannot start. Only rules
    /// with access == Libusb are used. `queue` must outlive the transport.
    UsbTransport(TransportOptions options, EventQueue& queue);
    /// Stops the event thread, cancels transfers, releases interfaces (the kernel driver is
    /// re-attached by libusb) and closes the context.
    ~UsbTransport() override;

    void start() override;
    std::vector<ConnectedDevice> connected() const override;
    SendStatus sendOutput(const std::string& device, std::span<const uint8_t> bytes) override;
    SendStatus sendFeature(const std::string& device, std::span<const uint8_t> bytes) override;

    /// True when this libusb reports hotplug support (else arrivals come from rescans).
    bool hasHotplug() const;

    struct Impl;

  private:
    std::unique_ptr<Impl> mImpl;
};

/// One USB device as `vsculpt devices` lists it.
struct UsbDeviceInfo {
    uint16_t vendor = 0, product = 0;
    int bus = 0, address = 0;
    std::string productName;  ///< from the string descriptor when readable, else empty
    bool openable = false;    ///< libusb_open succeeded (permissions, not claimed)
    std::string openError;    ///< why not, when !openable
};

/// Every USB device libusb sees. Throws TransportError when libusb cannot start.
std::vector<UsbDeviceInfo> listUsbDevices(bool tryOpen);

}  // namespace vsculpt::devices
