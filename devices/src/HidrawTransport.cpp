// SPDX-License-Identifier: MIT
#include "vsculpt/devices/HidrawTransport.h"

#include <fcntl.h>
#include <linux/hidraw.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <condition_variable>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include <spdlog/spdlog.h>

namespace fs = std::filesystem;

namespace vsculpt::devices {

namespace {

constexpr int64_t kNsPerS = 1'000'000'000;

std::string readSmallFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string ueventValue(const std::string& text, const std::string& key) {
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line))
        if (line.rfind(key + "=", 0) == 0) return line.substr(key.size() + 1);
    return {};
}

fs::path hidDeviceDir(const fs::path& classEntry) {
    std::error_code ec;
    const fs::path real = fs::canonical(classEntry, ec);
    if (ec) return {};
    return real.parent_path().parent_path();
}

bool streams(DeviceDriver d) {
    return d == DeviceDriver::Polhemus || d == DeviceDriver::RiftImu;
}

// RAII file descriptor.
struct Fd {
    int fd = -1;
    Fd() = default;
    explicit Fd(int f) : fd(f) {}
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
};

}  // namespace

bool parseHidId(const std::string& ueventText, uint16_t& bus, uint16_t& vendor, uint16_t& product) {
    const std::string id = ueventValue(ueventText, "HID_ID");
    unsigned b = 0, v = 0, p = 0;
    char tail = 0;
    if (id.size() != 22 || std::sscanf(id.c_str(), "%4x:%8x:%8x%c", &b, &v, &p, &tail) != 3)
        return false;
    if (v > 0xffff || p > 0xffff) return false;
    bus = static_cast<uint16_t>(b);
    vendor = static_cast<uint16_t>(v);
    product = static_cast<uint16_t>(p);
    return true;
}

std::vector<HidrawNodeInfo> listHidrawNodes(const fs::path& sysClass, const fs::path& devDir) {
    std::vector<HidrawNodeInfo> out;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(sysClass, ec)) {
        HidrawNodeInfo info;
        info.node = entry.path().filename().string();
        // /sys/class/hidraw/hidrawN links to .../<hid device>/hidraw/hidrawN; the HID device
        // (with HID_ID) is two levels up, its USB interface three.
        const fs::path hidDevice = hidDeviceDir(entry.path());
        if (hidDevice.empty()) continue;
        const std::string uevent = readSmallFile(hidDevice / "uevent");
        if (!parseHidId(uevent, info.bus, info.vendor, info.product)) continue;
        info.name = ueventValue(uevent, "HID_NAME");
        info.hidDevice = hidDevice;
        info.readable = ::access((devDir / info.node).c_str(), R_OK) == 0;
        out.push_back(info);
    }
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.node < b.node; });
    return out;
}

struct HidrawTransport::Impl {
    struct OpenDevice {
        const DeviceRule* rule = nullptr;
        std::string node;
        uint16_t vendor = 0, product = 0;
        Fd fd;
        std::thread reader;
        std::atomic<bool> gone{false};
        std::atomic<bool> finished{false};
        std::atomic<int64_t> lastReportNs{0};
        bool stalled = false;        // watcher thread only
        TransportCounters counters;  // guarded by Impl::mutex
    };

    TransportOptions options;
    EventQueue& queue;
    fs::path sysClass, devDir;
    std::atomic<bool> stop{false};
    std::thread watcher;
    std::mutex wakeMutex;
    std::condition_variable wake;
    mutable std::mutex mutex;  // guards `devices` and counters
    std::vector<std::unique_ptr<OpenDevice>> devices;
    std::set<std::string> warned;

    Impl(TransportOptions o, EventQueue& q, fs::path s, fs::path d)
        : options(std::move(o)), queue(q), sysClass(std::move(s)), devDir(std::move(d)) {
        std::erase_if(options.rules,
                      [](const DeviceRule& r) { return r.access != DeviceAccess::Hidraw; });
    }

    ~Impl() {
        stop = true;
        wake.notify_all();
        if (watcher.joinable()) watcher.join();
        std::vector<std::unique_ptr<OpenDevice>> all;
        {
            std::lock_guard lock(mutex);
            all.swap(devices);
        }
        // Readers take `mutex` for their counters: join them without holding it.
        for (auto& d : all) {
            d->gone = true;
            if (d->reader.joinable()) d->reader.join();
        }
    }

    void push(DeviceEventKind kind, const std::string& name, std::vector<uint8_t> bytes = {}) {
        queue.push(DeviceEvent{kind, monotonicNowNs(), name, std::move(bytes)});
    }

    void read(OpenDevice* d) {
        std::vector<uint8_t> buffer(4096);
        int consecutiveErrors = 0;
        while (!stop && !d->gone) {
            pollfd p{d->fd.fd, POLLIN, 0};
            const int r = ::poll(&p, 1, 100);
            if (r < 0 && errno != EINTR) break;
            if (r <= 0) continue;
            if (p.revents & (POLLHUP | POLLERR | POLLNVAL)) break;
            const ssize_t n = ::read(d->fd.fd, buffer.data(), buffer.size());
            if (n < 0) {
                if (errno == EAGAIN || errno == EINTR) continue;
                if (errno == ENODEV || ++consecutiveErrors >= options.errorsBeforeLeft) break;
                std::lock_guard lock(mutex);
                ++d->counters.errors;
                continue;
            }
            if (n == 0) break;  // end of file: the node went away
            consecutiveErrors = 0;
            const int64_t now = monotonicNowNs();
            d->lastReportNs = now;
            {
                std::lock_guard lock(mutex);
                ++d->counters.reports;
                d->counters.bytes += static_cast<uint64_t>(n);
            }
            queue.push(DeviceEvent{DeviceEventKind::Report, now, d->rule->name,
                                   std::vector<uint8_t>(buffer.begin(), buffer.begin() + n)});
        }
        d->finished = true;
        wake.notify_all();
    }

    bool isOpen(const std::string& node) const {
        for (const auto& d : devices)
            if (d->node == node) return true;
        return false;
    }

    void scan() {
        // Arrivals.
        for (const HidrawNodeInfo& node : listHidrawNodes(sysClass, devDir)) {
            const DeviceRule* rule =
                findRule(options.rules, node.vendor, node.product, DeviceAccess::Hidraw);
            if (!rule) continue;
            {
                std::lock_guard lock(mutex);
                if (isOpen(node.node)) continue;
                // One device per rule: a second interface of the same device is ignored
                // unless it names the configured interface.
                bool ruleBusy = false;
                for (const auto& d : devices)
                    ruleBusy |= d->rule == rule;
                if (ruleBusy) continue;
            }
            const fs::path ifaceFile =
                hidDeviceDir(sysClass / node.node).parent_path() / "bInterfaceNumber";
            if (fs::exists(ifaceFile)) {
                const int iface =
                    static_cast<int>(std::strtol(readSmallFile(ifaceFile).c_str(), nullptr, 16));
                if (iface != rule->interfaceNumber) continue;
            }
            // The report descriptor travels with the arrival: generic decoders (pen tablets
            // described by HID usages) are built from it, and recordings keep it. Read before
            // opening the node, so its reader starts as soon as the node is open.
            const std::string rdesc = readSmallFile(node.hidDevice / "report_descriptor");
            const std::vector<uint8_t> descriptor(rdesc.begin(), rdesc.end());
            const fs::path path = devDir / node.node;
            int fd = ::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
            if (fd < 0) fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
            if (fd < 0) {
                if (warned.insert(node.node).second)
                    spdlog::warn("device '{}' ({}): cannot open: {}{}", rule->name, path.string(),
                                 std::strerror(errno),
                                 errno == EACCES ? " (install the udev rule 70-vsculpt.rules and "
                                                   "replug it, see docs/devices.md)"
                                                 : "");
                continue;
            }
            warned.erase(node.node);
            auto d = std::make_unique<OpenDevice>();
            d->rule = rule;
            d->node = node.node;
            d->vendor = node.vendor;
            d->product = node.product;
            d->fd.fd = fd;
            d->lastReportNs = monotonicNowNs();
            d->counters.arrivals = 1;
            OpenDevice* raw = d.get();
            push(DeviceEventKind::Arrived, rule->name,
                 arrivalBytes(node.vendor, node.product, descriptor));
            {
                std::lock_guard lock(mutex);
                devices.push_back(std::move(d));
            }
            raw->reader = std::thread([this, raw] { read(raw); });
        }
        // Removals: a node gone from sysfs, or a reader that stopped.
        std::vector<std::unique_ptr<OpenDevice>> leaving;
        {
            std::lock_guard lock(mutex);
            for (auto& d : devices)
                if (!fs::exists(sysClass / d->node)) d->gone = true;
            for (auto it = devices.begin(); it != devices.end();) {
                if ((*it)->gone || (*it)->finished) {
                    leaving.push_back(std::move(*it));
                    it = devices.erase(it);
                } else {
                    ++it;
                }
            }
        }
        for (auto& d : leaving) {
            d->gone = true;
            if (d->reader.joinable()) d->reader.join();
            push(DeviceEventKind::Left, d->rule->name);
        }
        // Stalls (streaming devices only).
        const int64_t now = monotonicNowNs();
        const int64_t stallNs = static_cast<int64_t>(options.stallTimeoutS * kNsPerS);
        std::lock_guard lock(mutex);
        for (auto& d : devices) {
            if (!streams(d->rule->driver)) continue;
            const bool silent = now - d->lastReportNs > stallNs;
            if (silent && !d->stalled) {
                d->stalled = true;
                ++d->counters.stalls;
                spdlog::warn("device '{}': no data for {} s (stalled?)", d->rule->name,
                             options.stallTimeoutS);
                push(DeviceEventKind::Stalled, d->rule->name);
            } else if (!silent && d->stalled) {
                d->stalled = false;
                push(DeviceEventKind::Resumed, d->rule->name);
            }
        }
    }

    void watch() {
        const auto interval = std::chrono::duration<double>(
            std::min(options.rescanIntervalS, options.stallTimeoutS / 2));
        while (!stop) {
            scan();
            std::unique_lock lock(wakeMutex);
            wake.wait_for(lock, interval, [this] {
                if (stop) return true;
                std::lock_guard l(mutex);
                for (auto& d : devices)
                    if (d->finished) return true;
                return false;
            });
        }
    }

    SendStatus send(const std::string& name, std::span<const uint8_t> bytes, bool feature) {
        std::lock_guard lock(mutex);
        for (auto& d : devices) {
            if (d->rule->name != name) continue;
            if (bytes.empty()) return SendStatus::Failed;
            std::vector<uint8_t> copy(bytes.begin(), bytes.end());
            const long r = feature ? ::ioctl(d->fd.fd, HIDIOCSFEATURE(copy.size()), copy.data())
                                   : ::write(d->fd.fd, copy.data(), copy.size());
            if (r < 0) {
                ++d->counters.errors;
                return SendStatus::Failed;
            }
            return SendStatus::Ok;
        }
        return SendStatus::NotConnected;
    }
};

HidrawTransport::HidrawTransport(TransportOptions options, EventQueue& queue, fs::path sysClass,
                                 fs::path devDir)
    : mImpl(std::make_unique<Impl>(std::move(options), queue, std::move(sysClass),
                                   std::move(devDir))) {}

HidrawTransport::~HidrawTransport() = default;

void HidrawTransport::start() {
    if (mImpl->watcher.joinable()) return;
    mImpl->watcher = std::thread([impl = mImpl.get()] { impl->watch(); });
}

std::vector<ConnectedDevice> HidrawTransport::connected() const {
    std::lock_guard lock(mImpl->mutex);
    std::vector<ConnectedDevice> out;
    for (const auto& d : mImpl->devices)
        out.push_back({d->rule->name, d->vendor, d->product, (mImpl->devDir / d->node).string(),
                       d->counters});
    return out;
}

SendStatus HidrawTransport::sendOutput(const std::string& device, std::span<const uint8_t> bytes) {
    return mImpl->send(device, bytes, false);
}

SendStatus HidrawTransport::sendFeature(const std::string& device, std::span<const uint8_t> bytes) {
    return mImpl->send(device, bytes, true);
}

}  // namespace vsculpt::devices
