// SPDX-License-Identifier: MIT
#include "UsbMock.h"

#include <linux/ioctl.h>
#include <linux/usbdevice_fs.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace vsculpt::devices::test {

namespace {

gboolean onIoctl(UMockdevIoctlBase*, UMockdevIoctlClient* client, gpointer self) {
    return static_cast<UsbMock*>(self)->handle(client) ? TRUE : FALSE;
}

std::string hex(const std::vector<uint8_t>& bytes) {
    std::string s;
    char b[3];
    for (uint8_t v : bytes) {
        std::snprintf(b, sizeof b, "%02x", v);
        s += b;
    }
    return s;
}

}  // namespace

std::vector<uint8_t> hidDescriptors(uint16_t vendor, uint16_t product, int inPacket, int outPacket,
                                    bool bulk) {
    const uint8_t endpoints = outPacket > 0 ? 2 : 1;
    const uint8_t type = bulk ? 0x02 : 0x03;
    const uint8_t interfaceClass = bulk ? 0xff : 0x03;
    std::vector<uint8_t> d = {// device: USB 2.0, class per interface, EP0 64 bytes, 1 configuration
                              18,
                              0x01,
                              0x00,
                              0x02,
                              0x00,
                              0x00,
                              0x00,
                              64,
                              uint8_t(vendor),
                              uint8_t(vendor >> 8),
                              uint8_t(product),
                              uint8_t(product >> 8),
                              0x00,
                              0x01,
                              0,
                              0,
                              0,
                              1};
    const uint16_t total = static_cast<uint16_t>(9 + 9 + (bulk ? 0 : 9) + 7 * endpoints);
    const std::vector<uint8_t> config = {9,    0x02, uint8_t(total), uint8_t(total >> 8), 1, 1, 0,
                                         0x80, 50};
    const std::vector<uint8_t> iface = {9, 0x04, 0, 0, endpoints, interfaceClass, 0, 0, 0};
    const std::vector<uint8_t> hid = {9, 0x21, 0x11, 0x01, 0, 1, 0x22, 0x40, 0x00};
    const std::vector<uint8_t> in = {7, 0x05, 0x81, type, uint8_t(inPacket), uint8_t(inPacket >> 8),
                                     1};
    const std::vector<uint8_t> out = {
        7, 0x05, 0x02, type, uint8_t(outPacket), uint8_t(outPacket >> 8), 1};
    for (const auto* part : {&config, &iface})
        d.insert(d.end(), part->begin(), part->end());
    if (!bulk) d.insert(d.end(), hid.begin(), hid.end());
    d.insert(d.end(), in.begin(), in.end());
    if (outPacket > 0) d.insert(d.end(), out.begin(), out.end());
    return d;
}

bool UsbMock::available() {
    const char* preload = std::getenv("LD_PRELOAD");
    return preload && std::strstr(preload, "umockdev");
}

UsbMock::UsbMock(int bus, int address, std::vector<uint8_t> descriptors)
    : mBus(bus), mAddress(address), mDescriptors(std::move(descriptors)) {
    mTestbed = umockdev_testbed_new();
    mHandler = umockdev_ioctl_base_new();
    g_signal_connect(mHandler, "handle-ioctl", G_CALLBACK(onIoctl), this);
}

UsbMock::~UsbMock() {
    {
        std::lock_guard lock(mMutex);
        for (auto* d : mFlyingIn)
            umockdev_ioctl_data_unref(d);
        for (auto* d : mReapable)
            umockdev_ioctl_data_unref(d);
        mFlyingIn.clear();
        mReapable.clear();
    }
    g_object_unref(mHandler);
    g_object_unref(mTestbed);
}

std::string UsbMock::sysPath() const {
    return "/sys/devices/usb" + std::to_string(mBus) + "/" + std::to_string(mBus) + "-" +
           std::to_string(mAddress);
}

void UsbMock::plug() {
    char dev[64], bus[8], num[8];
    std::snprintf(dev, sizeof dev, "/dev/bus/usb/%03d/%03d", mBus, mAddress);
    std::snprintf(bus, sizeof bus, "%03d", mBus);
    std::snprintf(num, sizeof num, "%03d", mAddress);
    {
        std::lock_guard lock(mMutex);
        mUnplugged = false;
        mPlugged = true;
    }
    GError* error = nullptr;
    if (!mAttached && !umockdev_testbed_attach_ioctl(mTestbed, dev, mHandler, &error))
        throw std::runtime_error(std::string("umockdev: attach_ioctl: ") +
                                 (error ? error->message : "?"));
    mAttached = true;
    const std::string sys = sysPath().substr(std::string("/sys").size());
    const std::string text =
        "P: " + sys + "\nN: " + std::string(dev + 5) +
        "\nE: SUBSYSTEM=usb\nE: DRIVER=usb\nE: BUSNUM=" + bus + "\nE: DEVNUM=" + num +
        "\nE: DEVNAME=" + dev +
        "\nE: DEVTYPE=usb_device\nA: bConfigurationValue=1\\n\nA: busnum=" + std::to_string(mBus) +
        "\\n\nA: devnum=" + std::to_string(mAddress) +
        "\\n\nA: speed=12\\n\nH: descriptors=" + hex(mDescriptors) + "\n";
    if (!umockdev_testbed_add_from_string(mTestbed, text.c_str(), &error))
        throw std::runtime_error(std::string("umockdev: add device: ") +
                                 (error ? error->message : "?"));
}

void UsbMock::unplug() {
    {
        std::lock_guard lock(mMutex);
        mUnplugged = true;
        mPlugged = false;
        // What the kernel does on disconnect: every pending URB completes with ENODEV.
        for (auto* d : mFlyingIn) {
            auto* urb = reinterpret_cast<usbdevfs_urb*>(d->data);
            urb->status = -ENODEV;
            urb->actual_length = 0;
            mReapable.push_back(d);
        }
        mFlyingIn.clear();
    }
    umockdev_testbed_remove_device(mTestbed, sysPath().c_str());
}

void UsbMock::queueIn(std::vector<uint8_t> report) {
    std::lock_guard lock(mMutex);
    mIn.push_back(std::move(report));
}

bool UsbMock::drained() {
    std::lock_guard lock(mMutex);
    return mIn.empty() && mReapable.empty();
}

std::vector<std::vector<uint8_t>> UsbMock::sent() {
    std::lock_guard lock(mMutex);
    return mSent;
}

bool UsbMock::handle(UMockdevIoctlClient* client) {
    const gulong request = umockdev_ioctl_client_get_request(client);
    UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
    std::lock_guard lock(mMutex);
    switch (request) {
        case USBDEVFS_GET_CAPABILITIES: {
            UMockdevIoctlData* d = umockdev_ioctl_data_resolve(arg, 0, sizeof(guint32), nullptr);
            *reinterpret_cast<guint32*>(d->data) =
                USBDEVFS_CAP_BULK_CONTINUATION | USBDEVFS_CAP_NO_PACKET_SIZE_LIM |
                USBDEVFS_CAP_REAP_AFTER_DISCONNECT | USBDEVFS_CAP_ZERO_PACKET;
            umockdev_ioctl_data_unref(d);
            umockdev_ioctl_client_complete(client, 0, 0);
            return true;
        }
        case USBDEVFS_CLAIMINTERFACE:
        case USBDEVFS_RELEASEINTERFACE:
        case USBDEVFS_DISCONNECT_CLAIM:
        case USBDEVFS_CLEAR_HALT:
        case USBDEVFS_RESET:
        case USBDEVFS_RESETEP:
            umockdev_ioctl_client_complete(client, mUnplugged ? -1 : 0, mUnplugged ? ENODEV : 0);
            return true;
        case USBDEVFS_GETDRIVER:
        case USBDEVFS_IOCTL:
            // No kernel driver bound in the emulation.
            umockdev_ioctl_client_complete(client, -1, ENODATA);
            return true;
        case USBDEVFS_SUBMITURB: {
            if (mUnplugged) {
                umockdev_ioctl_client_complete(client, -1, ENODEV);
                return true;
            }
            UMockdevIoctlData* urbData =
                umockdev_ioctl_data_resolve(arg, 0, sizeof(usbdevfs_urb), nullptr);
            auto* urb = reinterpret_cast<usbdevfs_urb*>(urbData->data);
            UMockdevIoctlData* buffer = umockdev_ioctl_data_resolve(
                urbData, G_STRUCT_OFFSET(usbdevfs_urb, buffer), urb->buffer_length, nullptr);
            if (urb->type == USBDEVFS_URB_TYPE_CONTROL || !(urb->endpoint & 0x80)) {
                // OUT data or a control request: record it, complete at once.
                mSent.emplace_back(buffer->data, buffer->data + urb->buffer_length);
                urb->actual_length = urb->buffer_length;
                urb->status = 0;
                mReapable.push_back(urbData);
            } else {
                mFlyingIn.push_back(urbData);
            }
            umockdev_ioctl_data_unref(buffer);
            umockdev_ioctl_client_complete(client, 0, 0);
            return true;
        }
        case USBDEVFS_DISCARDURB: {
            const gulong addr = *reinterpret_cast<gulong*>(arg->data);
            for (auto it = mFlyingIn.begin(); it != mFlyingIn.end(); ++it) {
                if ((*it)->client_addr != addr) continue;
                auto* urb = reinterpret_cast<usbdevfs_urb*>((*it)->data);
                urb->status = -ENOENT;
                urb->actual_length = 0;
                mReapable.push_back(*it);
                mFlyingIn.erase(it);
                umockdev_ioctl_client_complete(client, 0, 0);
                return true;
            }
            umockdev_ioctl_client_complete(client, -1, EINVAL);
            return true;
        }
        case USBDEVFS_REAPURB:
        case USBDEVFS_REAPURBNDELAY: {
            // Pair waiting IN URBs with scripted reports.
            while (!mFlyingIn.empty() && !mIn.empty()) {
                UMockdevIoctlData* urbData = mFlyingIn.front();
                mFlyingIn.pop_front();
                auto* urb = reinterpret_cast<usbdevfs_urb*>(urbData->data);
                const std::vector<uint8_t> report = std::move(mIn.front());
                mIn.pop_front();
                const int n = std::min<int>(static_cast<int>(report.size()), urb->buffer_length);
                // The handler runs in the test process, so the client's buffer pointer is
                // valid here (as in libusb's own umockdev tests).
                std::memcpy(urb->buffer, report.data(), n);
                urb->actual_length = n;
                urb->status = 0;
                mReapable.push_back(urbData);
            }
            if (mReapable.empty()) {
                umockdev_ioctl_client_complete(client, -1, EAGAIN);
                return true;
            }
            UMockdevIoctlData* done = mReapable.front();
            mReapable.pop_front();
            UMockdevIoctlData* ptr = umockdev_ioctl_data_resolve(arg, 0, sizeof(gpointer), nullptr);
            umockdev_ioctl_data_set_ptr(ptr, 0, done);
            umockdev_ioctl_data_unref(ptr);
            umockdev_ioctl_data_unref(done);
            umockdev_ioctl_client_complete(client, 0, 0);
            return true;
        }
        default:
            return false;
    }
}

}  // namespace vsculpt::devices::test
