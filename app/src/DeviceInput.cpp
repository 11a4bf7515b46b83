// SPDX-License-Identifier: MIT
#include "vsculpt/app/DeviceInput.h"

#include "vsculpt/app/XrInput.h"
#include "vsculpt/devices/HeadPose.h"
#include "vsculpt/devices/HidDescriptor.h"
#include "vsculpt/devices/HidDigitizer.h"
#include "vsculpt/devices/OrientationFusion.h"
#include "vsculpt/devices/Polhemus.h"
#include "vsculpt/devices/RiftImu.h"
#include "vsculpt/devices/SpaceMouse.h"
#include "vsculpt/devices/WacomLegacy.h"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace vsculpt::app {

using namespace vsculpt::studio;

using devices::DeviceDriver;
using devices::DeviceEvent;
using devices::DeviceEventKind;

std::vector<devices::DeviceRule> deviceRules(const core::DevicesConfig& cfg) {
    const auto& matches = cfg.match.empty() ? core::knownDeviceMatches() : cfg.match;
    std::vector<devices::DeviceRule> rules;
    for (const auto& m : matches) {
        devices::DeviceRule r;
        r.name = m.name;
        // The config loader validated both names.
        r.driver = devices::parseDeviceDriver(m.driver).value_or(DeviceDriver::SpaceMouse);
        r.access = devices::parseDeviceAccess(m.access).value_or(devices::DeviceAccess::Hidraw);
        r.vendor = static_cast<uint16_t>(m.vendor);
        for (int p : m.products)
            r.products.push_back(static_cast<uint16_t>(p));
        r.interfaceNumber = m.interfaceNumber;
        r.inEndpoint = static_cast<uint8_t>(m.inEndpoint);
        r.outEndpoint = static_cast<uint8_t>(m.outEndpoint);
        rules.push_back(r);
    }
    return rules;
}

namespace {

constexpr double kNsToS = 1e-9;
constexpr double kPi = 3.14159265358979323846;

glm::dquat eulerDegrees(const core::Vec3& deg) {
    // Rz * Ry * Rx, as documented for devices.tracker.world_from_tracker_rotation_deg.
    const core::Vec3 r = deg * (kPi / 180.0);
    return glm::angleAxis(r.z, core::Vec3(0, 0, 1)) * glm::angleAxis(r.y, core::Vec3(0, 1, 0)) *
           glm::angleAxis(r.x, core::Vec3(1, 0, 0));
}

}  // namespace

struct DeviceInput::State {
    struct Mouse {
        devices::AxisMapping mapping;
        devices::SpaceMouseAxes axes;  // held until the next report (the device reports changes)
        uint32_t buttons = 0;
        int64_t lastNs = 0;
        bool haveTime = false;
    };
    struct Tracker {
        std::unique_ptr<devices::PolhemusStreamDecoder> decoder;
        devices::PolhemusConfig config;
        bool stylus = false;  // the record carries the stylus switch
        int64_t lastPenNs = 0;
        // The last pen tip placed, and a sample held back because it jumped from there (see
        // penJumps): a glitch when the next sample is back near the pen, a real move (tracking
        // regained elsewhere) when the next is near it.
        struct PenTip {
            core::Vec3 world{0.0};
            int64_t ns = 0;
            uint32_t buttons = 0;
        };
        std::optional<PenTip> lastTip, heldJump;
        // The hand-held object station: the sculpture's pose relative to the receiver, fixed
        // when the receiver is first seen (so grabbing does not make the sculpture jump).
        std::optional<core::RigidTransform> stationFromObject;
    };
    struct Headset {
        devices::RiftImuStream stream;
        devices::OrientationFusion fusion;
        std::optional<devices::RiftIdentity> identity;
        int64_t lastKeepAliveNs = 0;
        uint16_t commandId = 1;
    };

    struct Tablet {
        std::optional<devices::WacomModel> model;  // legacy Wacom protocol
        devices::WacomPenState pen;
        std::optional<devices::HidDigitizerDecoder> digitizer;  // generic HID pen tablets
    };

    core::DevicesConfig cfg;
    std::vector<devices::DeviceRule> rules;
    std::map<std::string, Tablet> tablets;
    std::vector<devices::PenSample> penSamples;
    Interaction& interaction;
    studio::Studio& studio;
    const studio::Session& session;
    core::RigidTransform worldFromTracker;
    std::map<std::string, Mouse> mice;
    std::map<std::string, Tracker> trackers;
    std::map<std::string, Headset> headsets;
    devices::HeadPoseTracker head;
    std::optional<core::Vec3> toolWorld;
    std::vector<DeviceOutput> output;
    // Recorded OpenXR controllers, one mapping per device.
    core::XrConfig xrCfg;
    std::map<std::string, std::unique_ptr<XrInput>> xrHands;

    State(const core::DevicesConfig& c, std::vector<devices::DeviceRule> r, Interaction& i,
          studio::Studio& s, const core::XrConfig& x)
        : cfg(c),
          rules(std::move(r)),
          interaction(i),
          studio(s),
          session(s.session()),
          head(headCalibration(c)),
          xrCfg(x) {
        worldFromTracker.rotation = eulerDegrees(c.worldFromTrackerRotationDeg);
        worldFromTracker.translation = c.worldFromTrackerTranslationMm;
    }

    static devices::HeadCalibration headCalibration(const core::DevicesConfig& c) {
        devices::HeadCalibration cal;
        cal.worldFromTracker = core::RigidTransform{eulerDegrees(c.worldFromTrackerRotationDeg),
                                                    c.worldFromTrackerTranslationMm}
                                   .matrix();
        return cal;
    }

    const devices::DeviceRule* rule(const std::string& name) const {
        for (const auto& r : rules)
            if (r.name == name) return &r;
        return nullptr;
    }

    Tracker& tracker(const devices::DeviceRule& r, uint16_t product) {
        Tracker& t = trackers[r.name];
        if (!t.decoder) {
            auto model = devices::findPolhemusModel(r.vendor, product);
            if (!model && !r.products.empty())
                model = devices::findPolhemusModel(r.vendor, r.products.front());
            t.config = model ? devices::defaultPolhemusConfig(*model) : devices::PolhemusConfig{};
            t.stylus = std::find(t.config.items.begin(), t.config.items.end(),
                                 devices::PolhemusItem::StylusButton) != t.config.items.end();
            t.decoder = std::make_unique<devices::PolhemusStreamDecoder>(t.config);
        }
        return t;
    }

    // A pen that leaves or stalls must not leave a stroke open: the edit so far is kept as
    // one undo step, as if the pen had been lifted.
    void liftPen() {
        if (session.inStroke()) studio.endStroke();
        interaction.setEngaged(false);
    }

    void arrived(const devices::DeviceRule& r, const DeviceEvent& e, DeviceCounters& n) {
        ++n.arrivals;
        uint16_t vendor = r.vendor, product = r.products.empty() ? 0 : r.products.front();
        devices::parseArrival(e, vendor, product);
        switch (r.driver) {
            case DeviceDriver::Polhemus: {
                trackers.erase(r.name);  // a fresh stream: forget half records
                Tracker& t = tracker(r, product);
                try {
                    for (auto& c : devices::polhemusStartupCommands(t.config))
                        output.push_back({r.name, c, false});
                } catch (const std::exception&) {
                    // An unsupported family: it is listed, but we cannot drive it.
                }
                break;
            }
            case DeviceDriver::SpaceMouse: {
                Mouse& m = mice[r.name];
                m = Mouse{};
                m.mapping.fullScale = cfg.mouseFullScale;
                m.mapping.deadZone = cfg.mouseDeadZone;
                const auto model = devices::findSpaceMouseModel(vendor, product);
                m.mapping.swapInvertYZ = model ? model->swapInvertYZ : true;
                break;
            }
            case DeviceDriver::WacomLegacy: {
                Tablet& t = tablets[r.name];
                t = Tablet{};
                t.model = devices::findWacomModel(vendor, product);
                // Out of its boot mouse mode into Wacom mode (the transport retries).
                const auto mode = devices::wacomModeSwitchReport();
                output.push_back({r.name, {mode.begin(), mode.end()}, true});
                break;
            }
            case DeviceDriver::HidDigitizer: {
                // Generic tablets describe their pen with HID usages: the decoder comes from
                // the report descriptor the transport read at arrival.
                Tablet& t = tablets[r.name];
                t = Tablet{};
                const auto descriptor = devices::parseHidDescriptor(devices::arrivalDescriptor(e));
                if (descriptor)
                    t.digitizer = devices::HidDigitizerDecoder::fromDescriptor(*descriptor);
                break;
            }
            case DeviceDriver::RiftImu: {
                Headset& h = headsets[r.name];
                h.stream.reset();
                h.identity = devices::findRiftModel(vendor, product);
                h.lastKeepAliveNs = e.timeNs;
                const auto config = devices::buildRiftSensorConfig(h.commandId++);
                output.push_back({r.name, {config.begin(), config.end()}, true});
                keepAlive(r, h);
                break;
            }
            default:
                break;
        }
    }

    // Pen tablets drive the sketch canvas, not the sculpting tool: samples are queued for the
    // sketch window (takePenSamples).
    void tabletReport(const devices::DeviceRule& r, const DeviceEvent& e, DeviceCounters& n) {
        std::optional<devices::PenSample> s;
        auto it = tablets.find(r.name);
        if (it != tablets.end()) {
            Tablet& t = it->second;
            if (r.driver == DeviceDriver::WacomLegacy && t.model)
                s = devices::decodeWacomLegacyReport(e.bytes, *t.model, t.pen, e.timeNs);
            else if (r.driver == DeviceDriver::HidDigitizer && t.digitizer)
                s = t.digitizer->decode(e.bytes, e.timeNs);
        }
        // No arrival seen, a model we do not know, no usable descriptor, or undecodable.
        if (!s) {
            ++n.decodeErrors;
            return;
        }
        ++n.samples;
        penSamples.push_back(*s);
    }

    void keepAlive(const devices::DeviceRule& r, Headset& h) {
        if (h.identity && h.identity->model == devices::RiftModel::Dk1) {
            const auto k = devices::buildRiftDk1KeepAlive(h.commandId++);
            output.push_back({r.name, {k.begin(), k.end()}, true});
        } else {
            const auto k = devices::buildRiftDk2KeepAlive(h.commandId++, false);
            output.push_back({r.name, {k.begin(), k.end()}, true});
        }
    }

    XrInput& xrInput(const devices::DeviceRule& r) {
        auto& x = xrHands[r.name];
        if (!x) x = std::make_unique<XrInput>(xrCfg, interaction, studio);
        return *x;
    }

    // A frame of recorded OpenXR controllers, mapped as the live headset session did.
    void xrReport(const devices::DeviceRule& r, const DeviceEvent& e, DeviceCounters& n) {
        const std::optional<XrHands> h = parseXrHandsReport(e.bytes);
        if (!h) {
            ++n.decodeErrors;
            return;
        }
        ++n.samples;
        xrInput(r).handle(*h);
        if (h->worldFromPen) toolWorld = xrInput(r).toolWorld();
    }

    void left(const devices::DeviceRule& r, bool stalled, DeviceCounters& n) {
        (stalled ? n.stalls : n.departures)++;
        switch (r.driver) {
            case DeviceDriver::OpenXr:
                // No controllers: the stroke ends, the sculpture is let go.
                xrInput(r).handle(XrHands{});
                break;
            case DeviceDriver::Polhemus:
                liftPen();
                break;
            case DeviceDriver::SpaceMouse: {
                auto it = mice.find(r.name);
                if (it != mice.end()) {
                    it->second.axes = {};
                    it->second.buttons = 0;
                    it->second.haveTime = false;
                }
                break;
            }
            default:
                break;
        }
    }

    void spaceMouseReport(const devices::DeviceRule& r, const DeviceEvent& e, DeviceCounters& n) {
        Mouse& m = mice[r.name];
        if (!m.haveTime) {  // no Arrived seen (recording started late): defaults from config
            m.mapping.fullScale = cfg.mouseFullScale;
            m.mapping.deadZone = cfg.mouseDeadZone;
        }
        const auto sample = devices::decodeSpaceMouseReport(e.bytes, e.timeNs);
        if (!sample) {
            ++n.decodeErrors;
            return;
        }
        ++n.samples;
        // Rate control: the axes held since the previous report act over the time between.
        if (m.haveTime) {
            if (e.timeNs < m.lastNs) {
                ++n.outOfOrder;
            } else {
                const double dt = std::min((e.timeNs - m.lastNs) * kNsToS, 0.1);
                moveObject(m.axes, dt);
            }
        }
        m.lastNs = std::max(m.lastNs, e.timeNs);
        m.haveTime = true;
        // Each report carries some of the axes; keep the others.
        std::array<int16_t, 3> t{}, rot{};
        const devices::SpaceMouseAxes now =
            devices::mapAxes(sample->hasTranslation ? sample->translation : t,
                             sample->hasRotation ? sample->rotation : rot, m.mapping);
        if (sample->hasTranslation) m.axes.translation = now.translation;
        if (sample->hasRotation) m.axes.rotation = now.rotation;
        if (sample->hasButtons) {
            const uint32_t pressed = sample->buttons & ~m.buttons;
            m.buttons = sample->buttons;
            // A refused command (zooming in at a point the lattices cannot hold: the tracker's
            // pose is garbage) is the user's to see, not the end of the session.
            try {
                if (pressed & 1u) {
                    const core::Vec3 tool = toolWorld.value_or(core::Vec3(0.0));
                    interaction.step(session.objectPose().inverse().apply(tool));
                }
                if (pressed & 2u) interaction.cycleTool();
            } catch (const studio::SessionError& err) {
                spdlog::warn("3D mouse button: {}", err.what());
            }
        }
    }

    void moveObject(const devices::SpaceMouseAxes& a, double dt) {
        const core::Vec3 v(a.translation[0], a.translation[1], a.translation[2]);
        const core::Vec3 w(a.rotation[0], a.rotation[1], a.rotation[2]);
        if (dt <= 0 || (glm::length(v) == 0 && glm::length(w) == 0)) return;
        core::RigidTransform pose = session.objectPose();
        pose.translation += v * (cfg.objectTranslateMmPerS * dt);
        const double speed = glm::length(w);
        if (speed > 0) {
            const double angle = speed * cfg.objectRotateDegPerS * (kPi / 180.0) * dt;
            // Turn about the object's own centre, about world axes (what the hand does).
            pose.rotation = glm::normalize(glm::angleAxis(angle, w / speed) * pose.rotation);
        }
        studio.setObjectPose(pose);
    }

    void trackerReport(const devices::DeviceRule& r, const DeviceEvent& e, DeviceCounters& n) {
        Tracker& t = tracker(r, r.products.empty() ? 0 : r.products.front());
        std::vector<devices::TrackerSample> samples;
        const uint64_t droppedBefore = t.decoder->droppedBytes();
        t.decoder->feed(e.bytes, e.timeNs, samples);
        n.droppedBytes += t.decoder->droppedBytes() - droppedBefore;
        for (const auto& s : samples) {
            if (!s.hasPosition) continue;
            if (!(glm::length(s.positionMm) <= kTrackerReachMm)) {  // NaN too
                ++n.outOfReach;
                continue;
            }
            if (cfg.objectStation != 0 && s.station == cfg.objectStation) {
                const core::RigidTransform worldFromStation =
                    worldFromTracker *
                    core::RigidTransform{glm::normalize(s.orientation), s.positionMm};
                if (!core::isUsablePoint(worldFromStation.translation)) continue;
                if (!t.stationFromObject)
                    t.stationFromObject = worldFromStation.inverse() * session.objectPose();
                // Pen samples use the pose current at their time, so sculpting while turning
                // leaves material where the tool touched.
                studio.setObjectPose(worldFromStation * *t.stationFromObject);
                ++n.samples;
                continue;
            }
            if (s.station == cfg.headStation) {
                head.addTrackerPosition(s.timeNs, s.positionMm);
                ++n.samples;
                continue;
            }
            if (s.station != cfg.penStation) continue;
            if (s.timeNs < t.lastPenNs) {
                ++n.outOfOrder;
                continue;
            }
            t.lastPenNs = s.timeNs;
            ++n.samples;
            const core::Vec3 tipInTracker = s.positionMm + s.orientation * cfg.penTipMm;
            const core::Vec3 world = worldFromTracker.apply(tipInTracker);
            if (!core::isUsablePoint(world)) {
                ++n.rejectedEdits;
                continue;
            }
            const Tracker::PenTip tip{world, s.timeNs, s.buttons};
            if (t.heldJump) {
                const Tracker::PenTip held = *t.heldJump;
                t.heldJump.reset();
                if (!penJumps(held, tip)) {
                    // The pen is there: tracking regained elsewhere. Never one stroke across
                    // (ended here even when the pen is always engaged).
                    studio.endStroke();
                    placePen(t, held, n);
                } else {
                    ++n.jumps;  // it was a glitch: dropped
                }
            }
            if (t.lastTip && penJumps(*t.lastTip, tip)) {
                t.heldJump = tip;
                continue;
            }
            placePen(t, tip, n);
        }
    }

    // Faster than a hand moves the pen (5 m/s) and farther than 30 mm: a tracker glitch, or
    // tracking lost and regained elsewhere (found by QA: one glitched record 3.5 m out swept
    // a tube 3.5 m long, 1.5 GB). Such a sample is held back one sample to tell which.
    static bool penJumps(const Tracker::PenTip& from, const Tracker::PenTip& to) {
        const double mm = glm::length(to.world - from.world);
        const double seconds = std::max<int64_t>(0, to.ns - from.ns) * 1e-9;
        return mm > std::max(30.0, 5000.0 * seconds);
    }

    void placePen(Tracker& t, const Tracker::PenTip& tip, DeviceCounters& n) {
        t.lastTip = tip;
        toolWorld = tip.world;
        // The thesis: always engaged. Otherwise the stylus switch, when the records carry
        // it; without one the tool is engaged elsewhere (a window's mouse button).
        if (cfg.penAlwaysEngaged)
            interaction.setEngaged(true);
        else if (t.stylus)
            interaction.setEngaged((tip.buttons & 1u) != 0);
        try {
            interaction.moveTool(tip.world);
        } catch (const studio::SessionError&) {
            // The lattices refused the point: the stroke was cancelled by the session.
            // (An invariant failure, std::logic_error, is a bug and is not counted.)
            ++n.rejectedEdits;
        }
    }

    void headsetReport(const devices::DeviceRule& r, const DeviceEvent& e, DeviceCounters& n) {
        Headset& h = headsets[r.name];
        std::vector<devices::ImuSample> samples;
        const devices::RiftPushResult res = h.stream.push(e.bytes, e.timeNs, samples);
        if (res.status != devices::DecodeStatus::Ok) ++n.decodeErrors;
        if (res.outOfOrder) ++n.outOfOrder;
        for (const auto& s : samples) {
            if (h.fusion.update(s) == devices::FusionStep::Rejected) continue;
            ++n.samples;
            head.addOrientation(s.hostTimeNs, h.fusion.fusionFromImu(),
                                h.fusion.angularVelocityRadps());
        }
        if (e.timeNs - h.lastKeepAliveNs > devices::riftKeepAliveResendNs(10000)) {
            h.lastKeepAliveNs = e.timeNs;
            keepAlive(r, h);
        }
    }
};

DeviceInput::DeviceInput(const core::DevicesConfig& cfg, std::vector<devices::DeviceRule> rules,
                         Interaction& interaction, studio::Studio& studio, const core::XrConfig& xr)
    : mState(std::make_unique<State>(cfg, std::move(rules), interaction, studio, xr)) {}

DeviceInput::~DeviceInput() = default;

void DeviceInput::handle(const DeviceEvent& e) {
    const devices::DeviceRule* r = mState->rule(e.device);
    if (!r) return;  // not a device of this config: nothing to map it to
    DeviceCounters& n = mCounters[e.device];
    switch (e.kind) {
        case DeviceEventKind::Arrived:
            mState->arrived(*r, e, n);
            return;
        case DeviceEventKind::Left:
            mState->left(*r, false, n);
            return;
        case DeviceEventKind::Stalled:
            mState->left(*r, true, n);
            return;
        case DeviceEventKind::Resumed:
            return;
        case DeviceEventKind::Report:
            break;
    }
    ++n.reports;
    switch (r->driver) {
        case DeviceDriver::SpaceMouse:
            mState->spaceMouseReport(*r, e, n);
            break;
        case DeviceDriver::Polhemus:
            mState->trackerReport(*r, e, n);
            break;
        case DeviceDriver::RiftImu:
            mState->headsetReport(*r, e, n);
            break;
        case DeviceDriver::WacomLegacy:
        case DeviceDriver::HidDigitizer:
            mState->tabletReport(*r, e, n);
            break;
        case DeviceDriver::OpenXr:
            mState->xrReport(*r, e, n);
            break;
    }
}

std::vector<devices::PenSample> DeviceInput::takePenSamples() {
    return std::exchange(mState->penSamples, {});
}

std::vector<DeviceOutput> DeviceInput::takeOutput() {
    return std::exchange(mState->output, {});
}

std::optional<core::Vec3> DeviceInput::toolWorld() const {
    return mState->toolWorld;
}

std::optional<glm::dmat4> DeviceInput::worldFromHead(int64_t timeNs) const {
    try {
        return mState->head.worldFromHeadAt(timeNs);
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

std::string DeviceInput::recenterHead(int64_t timeNs, const glm::dvec3& worldTargetMm) {
    devices::HeadPoseTracker& head = mState->head;
    const std::optional<glm::dquat> orientation = head.latestOrientation();
    const std::optional<glm::dmat4> worldFromHeadNow = worldFromHead(timeNs);
    if (!orientation || !worldFromHeadNow)
        throw std::runtime_error(
            "recenter: no head pose (the headset and the tracker's head station must both be "
            "reporting)");
    devices::HeadCalibration& cal = head.calibration();
    const glm::dvec3 headMm((*worldFromHeadNow)[3]);
    glm::dquat heading;
    try {
        heading = devices::recenterHeading(*orientation, cal.headFromImu, worldTargetMm - headMm);
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error(std::string("recenter: ") + e.what());
    }
    // The turn as people read it: the new heading against the old, about world z.
    const glm::dquat turn = heading * glm::conjugate(cal.worldFromFusion);
    const double degrees = glm::degrees(2.0 * std::atan2(turn.z, turn.w));
    cal.worldFromFusion = heading;
    return fmt::format("view recentred: the heading turned by {:.0f} degrees",
                       std::remainder(degrees, 360.0));
}

std::string DeviceInput::recenterHeadOn(const core::Aabb& box, const glm::dmat4& worldFromObject) {
    const core::Vec3 centre = box.empty() ? core::Vec3(0.0) : 0.5 * (box.min + box.max);
    return recenterHead(devices::monotonicNowNs(),
                        core::Vec3(worldFromObject * glm::dvec4(centre, 1)));
}

std::string DeviceInput::summary() const {
    std::ostringstream s;
    for (const auto& [name, c] : mCounters) {
        s << name << ": " << c.reports << " reports, " << c.samples << " samples";
        if (c.decodeErrors) s << ", " << c.decodeErrors << " undecodable";
        if (c.droppedBytes) s << ", " << c.droppedBytes << " bytes skipped";
        if (c.outOfOrder) s << ", " << c.outOfOrder << " out of order";
        if (c.rejectedEdits) s << ", " << c.rejectedEdits << " tool samples refused";
        if (c.outOfReach) s << ", " << c.outOfReach << " out of reach (dropped)";
        if (c.jumps) s << ", " << c.jumps << " jump(s) faster than a hand (dropped)";
        if (c.departures) s << ", left " << c.departures << "x";
        if (c.stalls) s << ", stalled " << c.stalls << "x";
        s << "\n";
    }
    return s.str();
}

}  // namespace vsculpt::app
