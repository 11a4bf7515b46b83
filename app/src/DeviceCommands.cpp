// SPDX-License-Identifier: MIT
#include "vsculpt/app/DeviceCommands.h"

#include "vsculpt/app/CliChecks.h"
#include "vsculpt/app/DeviceInput.h"
#include "vsculpt/app/Interrupt.h"
#include "vsculpt/app/LiveDevices.h"
#include "vsculpt/core/Config.h"
#include "vsculpt/core/Mesh.h"
#include "vsculpt/devices/HidrawTransport.h"
#include "vsculpt/devices/Recording.h"
#include "vsculpt/devices/UsbTransport.h"
#include "vsculpt/studio/Interaction.h"
#include "vsculpt/studio/Session.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <ostream>
#include <set>
#include <thread>

namespace vsculpt::app {

using namespace vsculpt::studio;

namespace {

std::string usbId(uint16_t vendor, uint16_t product) {
    char b[16];
    std::snprintf(b, sizeof b, "%04x:%04x", vendor, product);
    return b;
}

const devices::DeviceRule* match(const std::vector<devices::DeviceRule>& rules, uint16_t vendor,
                                 uint16_t product, devices::DeviceAccess access) {
    return devices::findRule(rules, vendor, product, access);
}

}  // namespace

int runDevices(const std::string& configPath, std::ostream& out, std::ostream& err,
               Verbosity verbosity) {
    LogScope log(err, verbosity, "vsculpt devices");
    core::SculptConfig cfg;
    try {
        cfg = core::loadConfig(configPath.empty() ? core::defaultConfigPath()
                                                  : std::filesystem::path(configPath));
    } catch (const core::ConfigError& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    spdlog::debug("config: {}", cfg.source);
    const auto rules = deviceRules(cfg.devices);
    int usable = 0, found = 0;

    std::vector<devices::UsbDeviceInfo> usb;
    try {
        usb = devices::listUsbDevices(true);
    } catch (const devices::TransportError& e) {
        out << "USB: not available (" << e.what() << ")\n";
    }
    const auto hidraw = devices::listHidrawNodes();

    out << "Devices vsculpt can use (rules: "
        << (cfg.devices.match.empty() ? "built-in table" : "devices.match") << "):\n";
    for (const auto& d : usb) {
        const auto* viaUsb = match(rules, d.vendor, d.product, devices::DeviceAccess::Libusb);
        const auto* viaHid = match(rules, d.vendor, d.product, devices::DeviceAccess::Hidraw);
        if (!viaUsb && !viaHid) continue;
        ++found;
        const auto* rule = viaUsb ? viaUsb : viaHid;
        out << "  " << rule->name << "  " << usbId(d.vendor, d.product) << "  usb " << d.bus << ":"
            << d.address;
        if (!d.productName.empty()) out << "  \"" << d.productName << "\"";
        out << "  " << devices::toString(rule->driver) << " via " << devices::toString(rule->access)
            << "  ";
        if (viaUsb) {
            if (d.openable) {
                out << "ready\n";
                ++usable;
            } else {
                out << "cannot open (" << d.openError
                    << "): install the udev rule 70-vsculpt.rules and replug it, see "
                       "docs/devices.md\n";
            }
        } else {
            bool readable = false, present = false;
            for (const auto& h : hidraw)
                if (h.vendor == d.vendor && h.product == d.product) {
                    present = true;
                    readable |= h.readable;
                }
            if (readable) {
                out << "ready\n";
                ++usable;
            } else if (present) {
                out << "no permission on its hidraw node: install the udev rule 70-vsculpt.rules "
                       "and replug it, see "
                       "docs/devices.md\n";
            } else {
                out << "no hidraw node (is the kernel's hid driver loaded?)\n";
            }
        }
    }
    // Bluetooth HID devices have hidraw nodes but no USB entry.
    for (const auto& h : hidraw) {
        bool listed = false;
        for (const auto& d : usb)
            listed |= d.vendor == h.vendor && d.product == h.product;
        const auto* rule = match(rules, h.vendor, h.product, devices::DeviceAccess::Hidraw);
        if (listed || !rule) continue;
        ++found;
        out << "  " << rule->name << "  " << usbId(h.vendor, h.product) << "  /dev/" << h.node
            << "  \"" << h.name << "\"  " << devices::toString(rule->driver) << " via hidraw  "
            << (h.readable ? "ready"
                           : "no permission: install the udev rule 70-vsculpt.rules and replug it")
            << "\n";
        usable += h.readable;
    }
    if (found == 0) {
        out << "  none. No supported tracker, 3D mouse, pen tablet or headset is connected.\n"
               "  In the window, the mouse and keyboard stand in for the pen and the 3D mouse "
               "(docs/window.md).\n";
    }
    out << usb.size() << " USB device(s) in all, " << found << " supported, " << usable
        << " usable.\n";
    return 0;
}

int runRecord(const RecordOptions& o, std::ostream& out, std::ostream& err) {
    (void)out;  // the recording is the data (written to its file); people read stderr
    LogScope log(err, o.verbosity, "vsculpt record");
    core::SculptConfig cfg;
    try {
        cfg = core::loadConfig(o.configPath.empty() ? core::defaultConfigPath()
                                                    : std::filesystem::path(o.configPath));
    } catch (const core::ConfigError& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    if (o.outPath.empty()) {
        spdlog::error("--out FILE is required");
        return 2;
    }
    try {
        requireRecordingPath(o.outPath, "--out");
        if (const std::string clash = outputClash({{"--out", o.outPath}}, "", o.configPath, "");
            !clash.empty())
            throw std::invalid_argument(clash);
    } catch (const std::invalid_argument& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    std::unique_ptr<devices::RecordingWriter> writer;
    try {
        writer = std::make_unique<devices::RecordingWriter>(
            o.outPath, deviceRules(cfg.devices),
            std::map<std::string, std::string>{
                {"config", nlohmann::json::parse(core::configToJson(cfg)).dump()},
                {"vsculpt", "0.1.0"}});
    } catch (const devices::RecordingError& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    Studio studio(cfg);
    Interaction interaction(studio);
    LiveDevices live(cfg.devices);
    DeviceInput input(cfg.devices, live.rules(), interaction, studio);

    // Ctrl-C (or SIGTERM, SIGHUP) is how a recording ends: the loop stops and the
    // recording is finished normally; a second one ends the process at once.
    std::optional<InterruptScope> interrupts(std::in_place);
    const auto start = std::chrono::steady_clock::now();
    bool warnedNone = false;
    std::set<std::string> present;
    bool anyArrived = false;
    int code = 0;
    spdlog::info("recording to {} (Ctrl-C to stop)", o.outPath);
    while (interruptSignal() == 0) {
        try {
            live.pump([&](const devices::DeviceEvent& e) {
                writer->write(e);
                input.handle(e);
                if (e.kind == devices::DeviceEventKind::Arrived) {
                    present.insert(e.device);
                    anyArrived = true;
                    spdlog::info("{} connected", e.device);
                } else if (e.kind == devices::DeviceEventKind::Left) {
                    present.erase(e.device);
                    spdlog::info("{} disconnected", e.device);
                }
            });
            live.send(input.takeOutput());
            writer->flush();
        } catch (const devices::RecordingError& e) {
            spdlog::error("{}", e.what());
            code = 1;
            break;
        }
        const double elapsed =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!warnedNone && !anyArrived && elapsed > 2.0) {
            warnedNone = true;
            spdlog::info(
                "no supported device is connected; waiting for one (`vsculpt devices` "
                "lists what is there)");
        }
        if (o.seconds > 0 && elapsed >= o.seconds) break;
        if (o.untilUnplugged && anyArrived && present.empty()) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    takeInterruptSignal();
    interrupts.reset();
    if (!anyArrived)
        spdlog::warn(
            "no supported device was connected: {} holds no events (`vsculpt devices` lists what "
            "is there)",
            o.outPath);
    studio.endStroke();
    const core::Mesh mesh = studio.session().wholeMesh();
    char hash[17];
    std::snprintf(hash, sizeof hash, "%016llx",
                  static_cast<unsigned long long>(core::canonicalMeshHash(mesh)));
    logLines(spdlog::level::info, input.summary());
    spdlog::info("wrote {} event(s) to {}, mesh hash {}", writer->eventsWritten(), o.outPath, hash);
    if (live.droppedReports() > 0)
        spdlog::warn("{} report(s) dropped (queue full)", live.droppedReports());
    return code;
}

}  // namespace vsculpt::app
