// SPDX-License-Identifier: MIT
#include "vsculpt/devices/UsbTransport.h"

#include <libusb.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include <spdlog/spdlog.h>

namespace vsculpt::devices {

namespace {

constexpr int64_t kNsPerS = 1'000'000'000;

// RAII for the C handles: a libusb_device reference and a device list.
struct DeviceRef {
    libusb_device* dev = nullptr;
    explicit DeviceRef(libusb_device* d) : dev(libusb_ref_device(d)) {}
    DeviceRef(const DeviceRef&) = delete;
    DeviceRef& operator=(const DeviceRef&) = delete;
    ~DeviceRef() { libusb_unref_device(dev); }
};

struct DeviceList {
    libusb_device** list = nullptr;
    ssize_t count = 0;
    explicit DeviceList(libusb_context* ctx) { count = libusb_get_device_list(ctx, &list); }
    ~DeviceList() {
        if (list) libusb_free_device_list(list, 1);
    }
    DeviceList(const DeviceList&) = delete;
    DeviceList& operator=(const DeviceList&) = delete;
};

struct ConfigDescriptor {
    libusb_config_descriptor* cfg = nullptr;
    explicit ConfigDescriptor(libusb_device* dev) {
        if (libusb_get_active_config_descriptor(dev, &cfg) != 0) cfg = nullptr;
    }
    ~ConfigDescriptor() {
        if (cfg) libusb_free_config_descriptor(cfg);
    }
    ConfigDescriptor(const ConfigDescriptor&) = delete;
    ConfigDescriptor& operator=(const ConfigDescriptor&) = delete;
};

bool streams(DeviceDriver d) {
    // Trackers in continuous mode and IMUs report all the time; 3D mice and tablets are
    // silent when nobody touches them, so silence from them is no stall.
    return d == DeviceDriver::Polhemus || d == DeviceDriver::RiftImu;
}

std::string whereOf(libusb_device* dev) {
    return "usb " + std::to_string(libusb_get_bus_number(dev)) + ":" +
           std::to_string(libusb_get_device_address(dev));
}

}  // namespace

struct UsbTransport::Impl {
    struct OpenDevice {
        Impl* owner = nullptr;
        const DeviceRule* rule = nullptr;
        std::unique_ptr<DeviceRef> ref;
        libusb_device_handle* handle = nullptr;
        uint8_t inEndpoint = 0, outEndpoint = 0;
        uint8_t outType = LIBUSB_TRANSFER_TYPE_INTERRUPT;
        std::vector<libusb_transfer*> transfers;
        std::vector<std::vector<uint8_t>> buffers;
        int inFlight = 0;     // event thread only
        int outInFlight = 0;  // guarded by Impl::mutex
        int consecutiveErrors = 0;
        bool gone = false;  // event thread only
        bool stalled = false;
        int64_t lastReportNs = 0;
        TransportCounters counters;  // guarded by Impl::mutex
        std::string where;
        uint16_t vendor = 0, product = 0;
    };

    TransportOptions options;
    EventQueue& queue;
    libusb_context* ctx = nullptr;
    bool hotplug = false;
    libusb_hotplug_callback_handle hotplugHandle{};
    std::thread thread;
    std::atomic<bool> stop{false};
    bool started = false;

    mutable std::mutex mutex;  // guards `devices` membership and counters against readers
    std::vector<std::unique_ptr<OpenDevice>> devices;
    // Filled by hotplug callbacks, consumed by the event loop (both on the event thread).
    std::vector<std::unique_ptr<DeviceRef>> pendingArrivals;
    std::vector<std::unique_ptr<DeviceRef>> pendingLefts;
    std::set<std::pair<int, int>> warnedOpenFailures;  // (bus, address)

    Impl(TransportOptions o, EventQueue& q) : options(std::move(o)), queue(q) {
        std::erase_if(options.rules,
                      [](const DeviceRule& r) { return r.access != DeviceAccess::Libusb; });
        const int r = libusb_init(&ctx);
        if (r != 0)
            throw TransportError(std::string("libusb: cannot initialise: ") + libusb_strerror(r));
        hotplug = libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG) != 0;
    }

    ~Impl() {
        if (started) {
            stop = true;
            libusb_interrupt_event_handler(ctx);
            thread.join();
        }
        libusb_exit(ctx);
    }

    const DeviceRule* ruleFor(libusb_device* dev) const {
        libusb_device_descriptor d{};
        if (libusb_get_device_descriptor(dev, &d) != 0) return nullptr;
        return findRule(options.rules, d.idVendor, d.idProduct, DeviceAccess::Libusb);
    }

    OpenDevice* findOpen(libusb_device* dev) {
        for (auto& d : devices)
            if (d->ref->dev == dev ||
                (libusb_get_bus_number(d->ref->dev) == libusb_get_bus_number(dev) &&
                 libusb_get_device_address(d->ref->dev) == libusb_get_device_address(dev)))
                return d.get();
        return nullptr;
    }

    void push(DeviceEventKind kind, const std::string& name, std::vector<uint8_t> bytes = {}) {
        queue.push(DeviceEvent{kind, monotonicNowNs(), name, std::move(bytes)});
    }

    static int LIBUSB_CALL onHotplug(libusb_context*, libusb_device* dev,
                                     libusb_hotplug_event event, void* user) {
        auto* self = static_cast<Impl*>(user);
        if (!self->ruleFor(dev)) return 0;
        // Minimal work here: remember the device; the loop opens or closes it.
        if (event == LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED)
            self->pendingArrivals.push_back(std::make_unique<DeviceRef>(dev));
        else
            self->pendingLefts.push_back(std::make_unique<DeviceRef>(dev));
        return 0;  // stay registered
    }

    static void LIBUSB_CALL onTransfer(libusb_transfer* t) {
        auto* d = static_cast<OpenDevice*>(t->user_data);
        Impl& self = *d->owner;
        switch (t->status) {
            case LIBUSB_TRANSFER_COMPLETED: {
                // Copy first: the buffer is reused by the resubmitted transfer.
                std::vector<uint8_t> bytes(t->buffer, t->buffer + t->actual_length);
                d->consecutiveErrors = 0;
                if (self.stop || d->gone || libusb_submit_transfer(t) != 0) {
                    --d->inFlight;
                    if (!self.stop) d->gone = true;
                }
                if (bytes.empty()) return;
                const int64_t now = monotonicNowNs();
                d->lastReportNs = now;
                if (d->stalled) {
                    d->stalled = false;
                    self.push(DeviceEventKind::Resumed, d->rule->name);
                }
                {
                    std::lock_guard lock(self.mutex);
                    ++d->counters.reports;
                    d->counters.bytes += bytes.size();
                }
                self.queue.push(
                    DeviceEvent{DeviceEventKind::Report, now, d->rule->name, std::move(bytes)});
                return;
            }
            case LIBUSB_TRANSFER_CANCELLED:
                --d->inFlight;
                return;
            case LIBUSB_TRANSFER_NO_DEVICE:
                --d->inFlight;
                d->gone = true;
                return;
            case LIBUSB_TRANSFER_TIMED_OUT:
            case LIBUSB_TRANSFER_STALL:
            case LIBUSB_TRANSFER_OVERFLOW:
            case LIBUSB_TRANSFER_ERROR:
            default: {
                {
                    std::lock_guard lock(self.mutex);
                    ++d->counters.errors;
                }
                if (++d->consecutiveErrors >= self.options.errorsBeforeLeft || self.stop ||
                    d->gone || libusb_submit_transfer(t) != 0) {
                    --d->inFlight;
                    if (!self.stop) d->gone = true;
                }
                return;
            }
        }
    }

    static void LIBUSB_CALL onOutTransfer(libusb_transfer* t) {
        auto* d = static_cast<OpenDevice*>(t->user_data);
        std::lock_guard lock(d->owner->mutex);
        --d->outInFlight;
        if (t->status != LIBUSB_TRANSFER_COMPLETED) ++d->counters.errors;
        // LIBUSB_TRANSFER_FREE_BUFFER | FREE_TRANSFER release the rest.
    }

    void warnOnce(libusb_device* dev, const std::string& what) {
        const auto key =
            std::make_pair(int(libusb_get_bus_number(dev)), int(libusb_get_device_address(dev)));
        if (warnedOpenFailures.insert(key).second) spdlog::warn("{}", what);
    }

    void open(libusb_device* dev) {
        const DeviceRule* rule = ruleFor(dev);
        if (!rule || findOpen(dev)) return;  // hotplug may announce an arrival twice
        auto d = std::make_unique<OpenDevice>();
        d->owner = this;
        d->rule = rule;
        d->ref = std::make_unique<DeviceRef>(dev);
        d->where = whereOf(dev);
        {
            libusb_device_descriptor desc{};
            libusb_get_device_descriptor(dev, &desc);
            d->vendor = desc.idVendor;
            d->product = desc.idProduct;
        }
        const std::string label = "device '" + rule->name + "' (" + d->where + ")";

        int r = libusb_open(dev, &d->handle);
        if (r != 0) {
            warnOnce(dev,
                     label + ": cannot open: " + libusb_strerror(r) +
                         (r == LIBUSB_ERROR_ACCESS ? " (install the udev rule 70-vsculpt.rules and "
                                                     "replug it, see docs/devices.md)"
                                                   : ""));
            return;
        }
        // HID through libusb takes the device from the kernel driver; libusb re-attaches it on
        // release. Not supported off Linux, which is fine: there is no driver to detach.
        libusb_set_auto_detach_kernel_driver(d->handle, 1);
        r = libusb_claim_interface(d->handle, rule->interfaceNumber);
        if (r != 0) {
            warnOnce(dev, label + ": cannot claim interface " +
                              std::to_string(rule->interfaceNumber) + ": " + libusb_strerror(r));
            libusb_close(d->handle);
            return;
        }

        int inSize = 0;
        uint8_t inType = LIBUSB_TRANSFER_TYPE_INTERRUPT;
        {
            ConfigDescriptor cfg(dev);
            if (cfg.cfg) {
                for (int i = 0; i < cfg.cfg->bNumInterfaces; ++i) {
                    const libusb_interface& itf = cfg.cfg->interface[i];
                    if (itf.num_altsetting < 1 ||
                        itf.altsetting[0].bInterfaceNumber != rule->interfaceNumber)
                        continue;
                    const libusb_interface_descriptor& alt = itf.altsetting[0];
                    for (int e = 0; e < alt.bNumEndpoints; ++e) {
                        const libusb_endpoint_descriptor& ep = alt.endpoint[e];
                        const uint8_t type = ep.bmAttributes & 0x3;
                        if (type != LIBUSB_TRANSFER_TYPE_INTERRUPT &&
                            type != LIBUSB_TRANSFER_TYPE_BULK)
                            continue;
                        const bool in = (ep.bEndpointAddress & LIBUSB_ENDPOINT_IN) != 0;
                        if (in && !d->inEndpoint &&
                            (!rule->inEndpoint || rule->inEndpoint == ep.bEndpointAddress)) {
                            d->inEndpoint = ep.bEndpointAddress;
                            inType = type;
                            inSize = ep.wMaxPacketSize & 0x7ff;
                        }
                        if (!in && !d->outEndpoint &&
                            (!rule->outEndpoint || rule->outEndpoint == ep.bEndpointAddress)) {
                            d->outEndpoint = ep.bEndpointAddress;
                            d->outType = type;
                        }
                    }
                }
            }
        }
        if (!d->inEndpoint || inSize <= 0) {
            warnOnce(dev, label + ": interface " + std::to_string(rule->interfaceNumber) +
                              " has no IN endpoint");
            libusb_release_interface(d->handle, rule->interfaceNumber);
            libusb_close(d->handle);
            return;
        }
        // Bulk streams (trackers) take several packets per transfer; an IN buffer must be a
        // multiple of wMaxPacketSize or the host reports an overflow.
        const int bufferSize = inType == LIBUSB_TRANSFER_TYPE_BULK ? inSize * 8 : inSize;
        const int n = std::max(1, options.transfersInFlight);
        d->buffers.assign(n, std::vector<uint8_t>(bufferSize));
        for (int i = 0; i < n; ++i) {
            libusb_transfer* t = libusb_alloc_transfer(0);
            if (inType == LIBUSB_TRANSFER_TYPE_BULK)
                libusb_fill_bulk_transfer(t, d->handle, d->inEndpoint, d->buffers[i].data(),
                                          bufferSize, &Impl::onTransfer, d.get(), 0);
            else
                libusb_fill_interrupt_transfer(t, d->handle, d->inEndpoint, d->buffers[i].data(),
                                               bufferSize, &Impl::onTransfer, d.get(), 0);
            d->transfers.push_back(t);
            if (libusb_submit_transfer(t) == 0) ++d->inFlight;
        }
        if (d->inFlight == 0) {
            warnOnce(dev, label + ": cannot start reading");
            closeHandle(*d);
            return;
        }
        d->lastReportNs = monotonicNowNs();
        const uint16_t vendor = d->vendor, product = d->product;
        {
            std::lock_guard lock(mutex);
            ++d->counters.arrivals;
            devices.push_back(std::move(d));
        }
        warnedOpenFailures.erase({libusb_get_bus_number(dev), libusb_get_device_address(dev)});
        push(DeviceEventKind::Arrived, rule->name, arrivalBytes(vendor, product));
    }

    // Cancels the IN transfers and waits (handling events: we are the event thread) until
    // every callback has run, then releases and closes.
    void closeHandle(OpenDevice& d) {
        for (libusb_transfer* t : d.transfers)
            libusb_cancel_transfer(t);
        const int64_t deadline = monotonicNowNs() + kNsPerS;
        auto busy = [&] {
            std::lock_guard lock(mutex);
            return d.inFlight > 0 || d.outInFlight > 0;
        };
        while (busy() && monotonicNowNs() < deadline) {
            timeval tv{0, 10'000};
            libusb_handle_events_timeout_completed(ctx, &tv, nullptr);
        }
        if (busy()) {
            // A callback that never came would touch freed memory: leak instead.
            spdlog::error("device '{}': transfers did not cancel; leaking them", d.rule->name);
            d.transfers.clear();
        }
        for (libusb_transfer* t : d.transfers)
            libusb_free_transfer(t);
        d.transfers.clear();
        if (!d.gone) libusb_release_interface(d.handle, d.rule->interfaceNumber);
        libusb_close(d.handle);
        d.handle = nullptr;
    }

    void close(OpenDevice* d, bool announce) {
        closeHandle(*d);
        const std::string name = d->rule->name;
        {
            std::lock_guard lock(mutex);
            ++d->counters.departures;
            std::erase_if(devices, [d](const auto& p) { return p.get() == d; });
        }
        if (announce) push(DeviceEventKind::Left, name);
    }

    void rescan() {
        DeviceList list(ctx);
        for (ssize_t i = 0; i < list.count; ++i)
            if (ruleFor(list.list[i]) && !findOpen(list.list[i])) open(list.list[i]);
    }

    void loop() {
        if (hotplug) {
            const int r = libusb_hotplug_register_callback(
                ctx, LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED | LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT,
                LIBUSB_HOTPLUG_ENUMERATE, LIBUSB_HOTPLUG_MATCH_ANY, LIBUSB_HOTPLUG_MATCH_ANY,
                LIBUSB_HOTPLUG_MATCH_ANY, &Impl::onHotplug, this, &hotplugHandle);
            if (r != 0) hotplug = false;
        }
        int64_t nextRescan = 0;
        const int64_t rescanNs = static_cast<int64_t>(options.rescanIntervalS * kNsPerS);
        const int64_t stallNs = static_cast<int64_t>(options.stallTimeoutS * kNsPerS);
        while (!stop) {
            timeval tv{0, 50'000};
            libusb_handle_events_timeout_completed(ctx, &tv, nullptr);

            auto arrivals = std::move(pendingArrivals);
            pendingArrivals.clear();
            for (auto& a : arrivals)
                open(a->dev);
            auto lefts = std::move(pendingLefts);
            pendingLefts.clear();
            for (auto& l : lefts)
                if (OpenDevice* d = findOpen(l->dev)) {
                    d->gone = true;
                    close(d, true);
                }
            std::vector<OpenDevice*> gone;
            for (auto& d : devices)
                if (d->gone || d->inFlight == 0) gone.push_back(d.get());
            for (OpenDevice* d : gone) {
                d->gone = true;
                close(d, true);
            }

            const int64_t now = monotonicNowNs();
            for (auto& d : devices) {
                if (!streams(d->rule->driver) || d->stalled || now - d->lastReportNs < stallNs)
                    continue;
                d->stalled = true;
                {
                    std::lock_guard lock(mutex);
                    ++d->counters.stalls;
                }
                spdlog::warn("device '{}': no data for {} s (stalled?)", d->rule->name,
                             options.stallTimeoutS);
                push(DeviceEventKind::Stalled, d->rule->name);
            }
            // Without hotplug, and as a safety net for devices that failed to open (e.g. the
            // udev rule applied late), look again now and then.
            if (now >= nextRescan) {
                rescan();
                nextRescan = now + rescanNs;
            }
        }
        if (hotplug) libusb_hotplug_deregister_callback(ctx, hotplugHandle);
        while (!devices.empty())
            close(devices.back().get(), false);
    }

    OpenDevice* byName(const std::string& name) {
        for (auto& d : devices)
            if (d->rule->name == name) return d.get();
        return nullptr;
    }

    SendStatus submitOut(const std::string& name, std::span<const uint8_t> bytes, bool feature) {
        std::lock_guard lock(mutex);
        OpenDevice* d = byName(name);
        if (!d || !d->handle) return SendStatus::NotConnected;
        if (!feature && !d->outEndpoint) return SendStatus::NoEndpoint;
        if (feature && bytes.empty()) return SendStatus::Failed;
        libusb_transfer* t = libusb_alloc_transfer(0);
        if (!t) return SendStatus::Failed;
        unsigned char* buffer = nullptr;
        if (feature) {
            // HID SET_REPORT(feature): class request to the interface (HID 1.11 §7.2.2).
            buffer = static_cast<unsigned char*>(malloc(LIBUSB_CONTROL_SETUP_SIZE + bytes.size()));
            libusb_fill_control_setup(buffer,
                                      uint8_t{LIBUSB_REQUEST_TYPE_CLASS} |
                                          uint8_t{LIBUSB_RECIPIENT_INTERFACE} |
                                          uint8_t{LIBUSB_ENDPOINT_OUT},
                                      0x09, static_cast<uint16_t>((3 << 8) | bytes[0]),
                                      static_cast<uint16_t>(d->rule->interfaceNumber),
                                      static_cast<uint16_t>(bytes.size()));
            std::memcpy(buffer + LIBUSB_CONTROL_SETUP_SIZE, bytes.data(), bytes.size());
            libusb_fill_control_transfer(t, d->handle, buffer, &Impl::onOutTransfer, d, 1000);
        } else {
            buffer = static_cast<unsigned char*>(malloc(bytes.size()));
            std::memcpy(buffer, bytes.data(), bytes.size());
            if (d->outType == LIBUSB_TRANSFER_TYPE_BULK)
                libusb_fill_bulk_transfer(t, d->handle, d->outEndpoint, buffer,
                                          static_cast<int>(bytes.size()), &Impl::onOutTransfer, d,
                                          1000);
            else
                libusb_fill_interrupt_transfer(t, d->handle, d->outEndpoint, buffer,
                                               static_cast<int>(bytes.size()), &Impl::onOutTransfer,
                                               d, 1000);
        }
        t->flags = LIBUSB_TRANSFER_FREE_BUFFER | LIBUSB_TRANSFER_FREE_TRANSFER;
        if (libusb_submit_transfer(t) != 0) {
            libusb_free_transfer(t);
            return SendStatus::Failed;
        }
        ++d->outInFlight;
        return SendStatus::Ok;
    }
};

UsbTransport::UsbTransport(TransportOptions options, EventQueue& queue)
    : mImpl(std::make_unique<Impl>(std::move(options), queue)) {}

UsbTransport::~UsbTransport() = default;

void UsbTransport::start() {
    if (mImpl->started) return;
    mImpl->started = true;
    mImpl->thread = std::thread([impl = mImpl.get()] { impl->loop(); });
}

bool UsbTransport::hasHotplug() const {
    return mImpl->hotplug;
}

std::vector<ConnectedDevice> UsbTransport::connected() const {
    std::lock_guard lock(mImpl->mutex);
    std::vector<ConnectedDevice> out;
    for (const auto& d : mImpl->devices)
        out.push_back({d->rule->name, d->vendor, d->product, d->where, d->counters});
    return out;
}

SendStatus UsbTransport::sendOutput(const std::string& device, std::span<const uint8_t> bytes) {
    return mImpl->submitOut(device, bytes, false);
}

SendStatus UsbTransport::sendFeature(const std::string& device, std::span<const uint8_t> bytes) {
    return mImpl->submitOut(device, bytes, true);
}

const char* toString(SendStatus s) {
    switch (s) {
        case SendStatus::Ok:
            return "ok";
        case SendStatus::NotConnected:
            return "not connected";
        case SendStatus::NoEndpoint:
            return "no OUT endpoint";
        case SendStatus::Failed:
            return "failed";
    }
    return "?";
}

std::vector<UsbDeviceInfo> listUsbDevices(bool tryOpen) {
    libusb_context* ctx = nullptr;
    const int r = libusb_init(&ctx);
    if (r != 0)
        throw TransportError(std::string("libusb: cannot initialise: ") + libusb_strerror(r));
    std::vector<UsbDeviceInfo> out;
    {
        DeviceList list(ctx);
        for (ssize_t i = 0; i < list.count; ++i) {
            libusb_device* dev = list.list[i];
            libusb_device_descriptor d{};
            if (libusb_get_device_descriptor(dev, &d) != 0) continue;
            UsbDeviceInfo info;
            info.vendor = d.idVendor;
            info.product = d.idProduct;
            info.bus = libusb_get_bus_number(dev);
            info.address = libusb_get_device_address(dev);
            if (tryOpen) {
                libusb_device_handle* h = nullptr;
                const int o = libusb_open(dev, &h);
                info.openable = o == 0;
                if (o != 0) info.openError = libusb_strerror(o);
                if (h) {
                    unsigned char text[128] = {};
                    if (d.iProduct &&
                        libusb_get_string_descriptor_ascii(h, d.iProduct, text, sizeof text) > 0)
                        info.productName = reinterpret_cast<const char*>(text);
                    libusb_close(h);
                }
            }
            out.push_back(info);
        }
    }
    libusb_exit(ctx);
    return out;
}

}  // namespace vsculpt::devices
