// SPDX-License-Identifier: MIT
// Device events -> sculpting, with events built from the documented report layouts: the
// thesis's 3D-mouse mapping, tracker strokes, faults (unplug mid-stroke, garbage, out of
// order), and determinism (the same events give the same sculpture).
#include "DeviceReports.h"

#include "vsculpt/app/DeviceInput.h"
#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/Mesh.h"

#include <gtest/gtest.h>

#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

using namespace vsculpt;
using namespace vsculpt::app;
using namespace vsculpt::studio;
using devices::DeviceEvent;
using devices::DeviceEventKind;
using test::Bytes;

namespace {

core::SculptConfig config() {
    core::SculptConfig cfg;
    cfg.sphereRadiusMm = 30;
    cfg.polygonizer.gridN = 32;
    cfg.devices.match = {
        {"mouse", "spacemouse", "hidraw", 0x256f, {0xc635}, 0, 0, 0},
        {"tracker", "polhemus", "libusb", 0x0f44, {0xff20}, 0, 0, 0},
    };
    cfg.devices.mouseDeadZone = 0.0;
    return cfg;
}

DeviceEvent arrived(int64_t t, const std::string& name, uint16_t vendor, uint16_t product) {
    return {DeviceEventKind::Arrived, t, name, devices::arrivalBytes(vendor, product)};
}

constexpr int64_t kMs = 1'000'000;

TEST(DeviceInput, MouseButtonsFollowTheThesis) {
    const core::SculptConfig cfg = config();
    Studio studio(cfg);
    const Session& s = studio.session();
    Interaction ui(studio);
    DeviceInput input(cfg.devices, deviceRules(cfg.devices), ui, studio);
    input.handle(arrived(0, "mouse", 0x256f, 0xc635));
    EXPECT_EQ(s.tool(), ToolKind::Add);
    EXPECT_EQ(s.size(), 7);
    // Right button (bit 1): add -> carve; held down it does nothing more.
    input.handle(test::report(1 * kMs, "mouse", test::mouseButtons(0x02)));
    input.handle(test::report(2 * kMs, "mouse", test::mouseButtons(0x02)));
    EXPECT_EQ(s.tool(), ToolKind::Carve);
    input.handle(test::report(3 * kMs, "mouse", test::mouseButtons(0x00)));
    // Left button (bit 0): one size step per press.
    input.handle(test::report(4 * kMs, "mouse", test::mouseButtons(0x01)));
    input.handle(test::report(5 * kMs, "mouse", test::mouseButtons(0x00)));
    input.handle(test::report(6 * kMs, "mouse", test::mouseButtons(0x01)));
    EXPECT_EQ(s.size(), 5);
    EXPECT_EQ(input.counters().at("mouse").samples, 6u);
}

TEST(DeviceInput, MouseAxesTurnTheObjectAtTheConfiguredRate) {
    const core::SculptConfig cfg = config();
    Studio studio(cfg);
    const Session& s = studio.session();
    Interaction ui(studio);
    DeviceInput input(cfg.devices, deviceRules(cfg.devices), ui, studio);
    input.handle(arrived(0, "mouse", 0x256f, 0xc635));
    // Full deflection of one rotation axis, held for 0.5 s (reports every 10 ms).
    for (int i = 0; i <= 50; ++i)
        input.handle(test::report(i * 10 * kMs, "mouse", test::mouseAxes(0x02, 0, 0, 350)));
    const double angle = glm::angle(s.objectPose().rotation);
    EXPECT_NEAR(angle, cfg.devices.objectRotateDegPerS * 0.5 * M_PI / 180.0, 1e-9);
    EXPECT_NEAR(glm::length(s.objectPose().translation), 0.0, 1e-12);
    // Unplugged while deflected: the motion stops, a later report moves nothing.
    input.handle({DeviceEventKind::Left, 510 * kMs, "mouse", {}});
    const glm::dquat before = s.objectPose().rotation;
    input.handle(arrived(600 * kMs, "mouse", 0x256f, 0xc635));
    input.handle(test::report(900 * kMs, "mouse", test::mouseAxes(0x02, 0, 0, 0)));
    EXPECT_EQ(s.objectPose().rotation, before);
}

std::vector<DeviceEvent> penStroke(int64_t t0, int frames, double zCm) {
    std::vector<DeviceEvent> events;
    for (int i = 0; i < frames; ++i) {
        // Across the top of the 30 mm sphere, 1 mm per frame.
        const double xCm = -1.5 + 0.1 * i;
        events.push_back(
            test::report(t0 + i * 8 * kMs, "tracker", test::libertyRecord(1, xCm, 0.0, zCm, i)));
    }
    return events;
}

TEST(DeviceInput, TrackerPenSculptsAndStartsTheTracker) {
    const core::SculptConfig cfg = config();
    Studio studio(cfg);
    const Session& s = studio.session();
    Interaction ui(studio, /*alwaysEngaged=*/true);
    DeviceInput input(cfg.devices, deviceRules(cfg.devices), ui, studio);
    const uint64_t before = core::canonicalMeshHash(s.wholeMesh());
    input.handle(arrived(0, "tracker", 0x0f44, 0xff20));
    const auto out = input.takeOutput();
    ASSERT_FALSE(out.empty());  // the start-up commands
    EXPECT_EQ(out.front().device, "tracker");
    EXPECT_FALSE(out.front().feature);
    for (const auto& e : penStroke(kMs, 30, 3.2))
        input.handle(e);
    EXPECT_TRUE(s.inStroke());
    ASSERT_TRUE(input.toolWorld());
    EXPECT_NEAR(input.toolWorld()->z, 32.0, 1e-4);  // cm -> mm
    EXPECT_NEAR(input.toolWorld()->x, 14.0, 1e-4);
    // Unplugged mid-stroke: the stroke ends cleanly, the edit is kept and can be undone.
    input.handle({DeviceEventKind::Left, 400 * kMs, "tracker", {}});
    EXPECT_FALSE(s.inStroke());
    const uint64_t after = core::canonicalMeshHash(s.wholeMesh());
    EXPECT_NE(after, before);
    EXPECT_TRUE(studio.undo());
    EXPECT_EQ(core::canonicalMeshHash(s.wholeMesh()), before);
    EXPECT_EQ(input.counters().at("tracker").samples, 30u);
    EXPECT_EQ(input.counters().at("tracker").departures, 1u);
}

// Found by fuzzing recordings: one tracker record at 1 km mid-stroke swept the tool along a
// 1 km line (41 s, 2.1 GB). A pose beyond any tracker's reach is a glitch: dropped, counted,
// and the stroke goes on from the last good sample as if the record had not come.
TEST(DeviceInput, APoseBeyondAnyTrackersReachIsDroppedAsAGlitch) {
    const core::SculptConfig cfg = config();
    Studio plain(cfg), glitched(cfg);
    for (Studio* studio : {&plain, &glitched}) {
        Interaction ui(*studio, /*alwaysEngaged=*/true);
        DeviceInput input(cfg.devices, deviceRules(cfg.devices), ui, *studio);
        input.handle(arrived(0, "tracker", 0x0f44, 0xff20));
        const auto stroke = penStroke(kMs, 30, 3.2);
        for (size_t i = 0; i < stroke.size(); ++i) {
            input.handle(stroke[i]);
            if (studio == &glitched && i == 14) {
                input.handle(test::report(stroke[i].timeNs + kMs, "tracker",
                                          test::libertyRecord(1, 99999.0, 0.0, 3.2, 100)));
            }
        }
        input.handle({DeviceEventKind::Left, 400 * kMs, "tracker", {}});
        EXPECT_EQ(input.counters().at("tracker").samples, 30u);
        EXPECT_EQ(input.counters().at("tracker").outOfReach, studio == &glitched ? 1u : 0u);
        EXPECT_NEAR(input.toolWorld().value_or(core::Vec3(0.0)).x, 14.0, 1e-4);
    }
    EXPECT_EQ(plain.session().sculpture().counts().total(),
              glitched.session().sculpture().counts().total());
    EXPECT_EQ(core::canonicalMeshHash(plain.session().wholeMesh()),
              core::canonicalMeshHash(glitched.session().wholeMesh()));
}

// Found by QA: a record glitched 3.5 m out, inside the trackers' reach, swept a tube 3.5 m
// long. A pen sample faster than a hand (5 m/s, 30 mm) and back is dropped: the sculpture is
// the clean stroke's. A jump that stays (tracking regained elsewhere) is followed, as a new
// stroke: never one stroke swept across the gap.
TEST(DeviceInput, APenJumpFasterThanAHandIsDroppedOrStartsANewStroke) {
    const core::SculptConfig cfg = config();
    Studio plain(cfg), glitched(cfg), moved(cfg);
    for (Studio* studio : {&plain, &glitched, &moved}) {
        Interaction ui(*studio, /*alwaysEngaged=*/true);
        DeviceInput input(cfg.devices, deviceRules(cfg.devices), ui, *studio);
        input.handle(arrived(0, "tracker", 0x0f44, 0xff20));
        auto stroke = penStroke(kMs, 30, 3.2);
        if (studio == &moved)  // from sample 15 on, 60 mm along +y (tracking regained there)
            for (size_t i = 15; i < stroke.size(); ++i)
                stroke[i] = test::report(
                    stroke[i].timeNs, "tracker",
                    test::libertyRecord(1, -1.5 + 0.1 * double(i), 6.0, 3.2, uint32_t(i)));
        for (size_t i = 0; i < stroke.size(); ++i) {
            input.handle(stroke[i]);
            if (studio == &glitched && i == 14)
                input.handle(test::report(stroke[i].timeNs + kMs, "tracker",
                                          test::libertyRecord(1, 350.0, 0.0, 3.2, 100)));
        }
        input.handle({DeviceEventKind::Left, 400 * kMs, "tracker", {}});
        EXPECT_EQ(input.counters().at("tracker").jumps, studio == &glitched ? 1u : 0u);
    }
    EXPECT_EQ(core::canonicalMeshHash(plain.session().wholeMesh()),
              core::canonicalMeshHash(glitched.session().wholeMesh()));
    // Moved: two strokes, none across the 60 mm gap (the clay between them untouched).
    EXPECT_EQ(moved.session().history().done().size(), 2u);
    core::FieldProbe f(moved.session().sculpture());
    EXPECT_LT(f.value(core::Vec3(0, 30, 32)), 0) << "a stroke was swept across the jump";
}

TEST(DeviceInput, HandHeldObjectStationMovesTheSculpture) {
    core::SculptConfig cfg = config();
    cfg.devices.objectStation = 3;
    Studio studio(cfg);
    const Session& s = studio.session();
    Interaction ui(studio);
    DeviceInput input(cfg.devices, deviceRules(cfg.devices), ui, studio);
    input.handle(arrived(0, "tracker", 0x0f44, 0xff20));
    // First sample: grabbed where it is, no jump.
    input.handle(test::report(kMs, "tracker", test::libertyRecord(3, 10, 20, 30, 0)));
    EXPECT_EQ(s.objectPose().translation, core::Vec3(0.0));
    // 1 cm along x: the sculpture follows by 10 mm.
    input.handle(test::report(2 * kMs, "tracker", test::libertyRecord(3, 11, 20, 30, 1)));
    EXPECT_NEAR(s.objectPose().translation.x, 10.0, 1e-4);
    EXPECT_NEAR(glm::length(s.objectPose().translation - core::Vec3(10, 0, 0)), 0.0, 1e-4);
    // Receiver turned 90 degrees about z: the sculpture turns 90 degrees about the receiver.
    const float quarter[4] = {float(std::sqrt(0.5)), 0, 0, float(std::sqrt(0.5))};
    input.handle(test::report(3 * kMs, "tracker", test::libertyRecord(3, 11, 20, 30, 2, quarter)));
    EXPECT_NEAR(glm::angle(s.objectPose().rotation), M_PI / 2, 1e-6);
    // The sculpture's centre, 10 mm right of where it started, circles the receiver at
    // (110, 200, 300): it was at (-100, -200, -300) relative, now at (200, -100, -300).
    EXPECT_NEAR(glm::length(s.objectPose().translation - core::Vec3(310, 100, 0)), 0.0, 1e-3);
    EXPECT_EQ(input.counters().at("tracker").samples, 3u);
}

TEST(DeviceInput, GarbageAndSplitRecordsAreHandled) {
    const core::SculptConfig cfg = config();
    Studio studio(cfg);
    Interaction ui(studio, true);
    DeviceInput input(cfg.devices, deviceRules(cfg.devices), ui, studio);
    input.handle(arrived(0, "tracker", 0x0f44, 0xff20));
    // Records cut at arbitrary places and garbage in between: the framer resyncs.
    Bytes stream;
    for (const auto& e : penStroke(kMs, 10, 3.2)) {
        stream.insert(stream.end(), e.bytes.begin(), e.bytes.end());
        if (e.bytes[2] == 1) stream.insert(stream.end(), {0xde, 0xad, 0xbe, 0xef});
    }
    for (size_t i = 0; i < stream.size(); i += 17) {
        Bytes chunk(stream.begin() + i, stream.begin() + std::min(stream.size(), i + 17));
        input.handle(test::report(int64_t(i) * 1000, "tracker", chunk));
    }
    EXPECT_EQ(input.counters().at("tracker").samples, 10u);
    EXPECT_GE(input.counters().at("tracker").droppedBytes, 4u);
    // A 3D-mouse report with an unknown id or cut short: counted, nothing moves.
    input.handle(test::report(kMs, "mouse", Bytes{0x42, 1, 2}));
    input.handle(test::report(kMs, "mouse", Bytes{0x01, 1}));
    EXPECT_EQ(input.counters().at("mouse").decodeErrors, 2u);
    // Events of devices the config does not name are ignored.
    input.handle(test::report(kMs, "joystick", Bytes{1, 2, 3}));
    EXPECT_EQ(input.counters().count("joystick"), 0u);
}

TEST(DeviceInput, SameEventsGiveTheSameSculpture) {
    const core::SculptConfig cfg = config();
    std::vector<DeviceEvent> events{arrived(0, "tracker", 0x0f44, 0xff20),
                                    arrived(0, "mouse", 0x256f, 0xc635)};
    for (const auto& e : penStroke(kMs, 20, 3.2))
        events.push_back(e);
    events.push_back(test::report(200 * kMs, "mouse", test::mouseButtons(0x02)));  // carve
    for (int i = 0; i < 20; ++i)
        events.push_back(test::report((210 + i) * kMs, "mouse", test::mouseAxes(0x02, 100, 0, 0)));
    for (const auto& e : penStroke(300 * kMs, 20, 2.9))
        events.push_back(e);
    auto run = [&] {
        Studio studio(cfg);
        const Session& s = studio.session();
        Interaction ui(studio, true);
        DeviceInput input(cfg.devices, deviceRules(cfg.devices), ui, studio);
        for (const auto& e : events)
            input.handle(e);
        studio.endStroke();
        return core::canonicalMeshHash(s.wholeMesh());
    };
    const uint64_t first = run();
    EXPECT_EQ(run(), first);
    Session fresh(cfg);
    EXPECT_NE(first, core::canonicalMeshHash(fresh.wholeMesh()));
}

}  // namespace

namespace {

// Seeded fuzz: random and mutated events for every driver never throw out of handle(), and
// the session stays consistent (the mesh check passes after all of it).
TEST(DeviceInput, RandomEventsNeverBreakTheSession) {
    core::SculptConfig cfg = config();
    cfg.devices.match.push_back({"headset", "rift", "hidraw", 0x2833, {0x0021}, 0, 0, 0});
    cfg.devices.match.push_back({"tablet", "hid-digitizer", "hidraw", 0x056a, {0x0374}, 0, 0, 0});
    Studio studio(cfg);
    const Session& s = studio.session();
    Interaction ui(studio);
    DeviceInput input(cfg.devices, deviceRules(cfg.devices), ui, studio);
    std::mt19937 rng(5);
    const char* names[] = {"mouse", "tracker", "headset", "tablet", "other"};
    int64_t t = 0;
    for (int i = 0; i < 20000; ++i) {
        DeviceEvent e;
        e.device = names[rng() % 5];
        t += int64_t(rng() % 20) * kMs - 2 * kMs;  // sometimes backwards
        e.timeNs = t;
        const unsigned k = rng() % 100;
        e.kind = k < 2   ? DeviceEventKind::Arrived
                 : k < 4 ? DeviceEventKind::Left
                 : k < 5 ? DeviceEventKind::Stalled
                         : DeviceEventKind::Report;
        if (e.kind == DeviceEventKind::Arrived && rng() % 2)
            e.bytes = devices::arrivalBytes(uint16_t(rng()), uint16_t(rng()));
        if (e.kind == DeviceEventKind::Report) {
            if (e.device == std::string("tracker") && rng() % 2) {
                e.bytes = test::libertyRecord(1 + int(rng() % 3), (int(rng() % 200) - 100) * 0.05,
                                              (int(rng() % 200) - 100) * 0.05,
                                              (int(rng() % 200) - 100) * 0.05, uint32_t(i));
                if (rng() % 4 == 0) e.bytes[rng() % e.bytes.size()] = uint8_t(rng());
            } else {
                e.bytes.resize(1 + rng() % 70);
                for (auto& b : e.bytes)
                    b = uint8_t(rng());
                if (rng() % 2) e.bytes[0] = uint8_t(1 + rng() % 3);  // plausible report ids
            }
        }
        ASSERT_NO_THROW(input.handle(e)) << "event " << i;
        input.takeOutput();
    }
    studio.endStroke();
    EXPECT_EQ(s.verifyMesh(), "");
}

}  // namespace

namespace {

// A Wacom Graphire (legacy protocol) in Wacom mode: arrival switches it out of mouse mode,
// its pen reports are queued for the sketch canvas, byte-exact, and never touch the sculpture.
TEST(DeviceInput, TabletPenSamplesAreQueuedForTheSketchCanvas) {
    core::SculptConfig cfg = config();
    cfg.devices.match.push_back({"tablet", "wacom", "hidraw", 0x056a, {0x0010}, 0, 0, 0});
    Studio studio(cfg);
    const Session& s = studio.session();
    Interaction ui(studio);
    DeviceInput input(cfg.devices, deviceRules(cfg.devices), ui, studio);
    const uint64_t before = core::canonicalMeshHash(s.view().mesh());
    input.handle(arrived(0, "tablet", 0x056a, 0x0010));
    const std::vector<DeviceOutput> out = input.takeOutput();
    ASSERT_EQ(out.size(), 1u);
    EXPECT_TRUE(out[0].feature);
    EXPECT_EQ(out[0].bytes, (std::vector<uint8_t>{2, 2}));  // feature report 2 = Wacom mode
    // Pen in proximity, tip down, x = 5103, y = 3711 counts (80 per mm), full pressure.
    input.handle(
        test::report(5 * kMs, "tablet", Bytes{2, 0x80 | 0x01, 0xEF, 0x13, 0x7F, 0x0E, 0xFF, 0x01}));
    input.handle(test::report(6 * kMs, "tablet", Bytes{2, 0, 0, 0, 0, 0, 0, 0}));  // away
    input.handle(test::report(7 * kMs, "tablet", Bytes{1, 0, 0}));  // boot mouse report
    const std::vector<devices::PenSample> pen = input.takePenSamples();
    ASSERT_EQ(pen.size(), 2u);
    EXPECT_EQ(pen[0].timeNs, 5 * kMs);
    EXPECT_TRUE(pen[0].touching);
    EXPECT_DOUBLE_EQ(pen[0].positionMm.x, 5103 / 80.0);
    EXPECT_DOUBLE_EQ(pen[0].positionMm.y, 3711 / 80.0);
    EXPECT_DOUBLE_EQ(pen[0].pressure, 1.0);
    EXPECT_FALSE(pen[1].inProximity);
    EXPECT_TRUE(input.takePenSamples().empty());
    EXPECT_EQ(input.counters().at("tablet").samples, 2u);
    EXPECT_EQ(input.counters().at("tablet").decodeErrors, 1u);
    EXPECT_EQ(core::canonicalMeshHash(s.view().mesh()), before);
}

}  // namespace

namespace {

std::vector<uint8_t> hexFile(const std::string& name) {
    std::ifstream in(std::string(VSCULPT_DEVICES_DATA_DIR) + "/" + name);
    EXPECT_TRUE(in) << name;
    std::vector<uint8_t> out;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream words(line);
        for (std::string w; words >> w;)
            out.push_back(uint8_t(std::stoul(w, nullptr, 16)));
    }
    return out;
}

// A generic HID pen tablet (XP-Pen Deco 01 v3, its real report descriptor): the decoder is
// built from the descriptor that arrives with the device, and its reports become canvas
// samples in millimetres with pressure and tilt.
TEST(DeviceInput, GenericHidTabletIsDecodedFromItsArrivingDescriptor) {
    core::SculptConfig cfg = config();
    cfg.devices.match.push_back({"xppen", "hid-digitizer", "hidraw", 0x28bd, {0x0905}, 0, 0, 0});
    Studio studio(cfg);
    Interaction ui(studio);
    DeviceInput input(cfg.devices, deviceRules(cfg.devices), ui, studio);
    // Without a descriptor nothing can be decoded.
    input.handle(arrived(0, "xppen", 0x28bd, 0x0905));
    const Bytes touch{7, 0x23, 0x00, 0x40, 0xFF, 0x7F, 0x00, 0x20, 0xE2, 0x2D};
    input.handle(test::report(1 * kMs, "xppen", touch));
    EXPECT_TRUE(input.takePenSamples().empty());
    EXPECT_EQ(input.counters().at("xppen").decodeErrors, 1u);
    // With it: tip + barrel + in range; x = 16384, y = 32767 of a 254 x 158.75 mm area,
    // pressure 8192 of 16383, tilt (-30, 45) degrees.
    const std::vector<uint8_t> rdesc = hexFile("xppen-deco01v3-pen.rdesc.hex");
    input.handle(
        {DeviceEventKind::Arrived, 2 * kMs, "xppen", devices::arrivalBytes(0x28bd, 0x0905, rdesc)});
    input.handle(test::report(3 * kMs, "xppen", touch));
    const std::vector<devices::PenSample> pen = input.takePenSamples();
    ASSERT_EQ(pen.size(), 1u);
    EXPECT_TRUE(pen[0].touching && pen[0].hasTilt);
    EXPECT_NEAR(pen[0].positionMm.x, 16384.0 / 32767.0 * 254.0, 1e-9);
    EXPECT_NEAR(pen[0].positionNormalized.y, 1.0, 1e-12);
    EXPECT_NEAR(pen[0].pressure, 8192.0 / 16383.0, 1e-12);
    EXPECT_NEAR(pen[0].tiltRad.y, 45 * M_PI / 180, 1e-12);
    uint16_t v = 0, p = 0;
    const DeviceEvent a{DeviceEventKind::Arrived, 0, "xppen", devices::arrivalBytes(1, 2, rdesc)};
    ASSERT_TRUE(devices::parseArrival(a, v, p));
    EXPECT_EQ(v, 1);
    EXPECT_EQ(p, 2);
    EXPECT_EQ(devices::arrivalDescriptor(a).size(), rdesc.size());
}

}  // namespace

namespace {

// The head-tracked view (a Rift DK1 on the head, the tracker's head station for its
// position): the IMU knows up but not which way the room faces, so its heading is arbitrary
// until the recenter action turns it, about the vertical only, to look toward the target.
TEST(DeviceInput, RecenterTurnsTheHeadTrackedViewTowardTheTarget) {
    core::SculptConfig cfg = config();
    cfg.devices.match.push_back({"headset", "rift", "hidraw", 0x2833, {0x0001}, 0, 0, 0});
    Studio studio(cfg);
    Interaction ui(studio);
    DeviceInput input(cfg.devices, deviceRules(cfg.devices), ui, studio);
    // No head pose yet: refused, saying why.
    try {
        input.recenterHead(0, glm::dvec3(0.0));
        ADD_FAILURE() << "recentred without a head pose";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("no head pose"), std::string::npos) << e.what();
    }
    input.handle(arrived(0, "headset", 0x2833, 0x0001));
    input.handle(arrived(0, "tracker", 0x0f44, 0xff20));
    // A still head, tilted a little down (gravity mostly along the IMU's +y), its station
    // 600 mm from the tracker's source along +x.
    const int32_t accel[3] = {0, 96000, -20000};
    int64_t t = 0;
    uint32_t frame = 0;
    auto run = [&](int reports) {
        for (int i = 0; i < reports; ++i) {
            t += kMs;
            input.handle(test::report(t, "headset", test::riftDk1Report(uint16_t(t / kMs), accel)));
            if (i % 4 == 0)
                input.handle(test::report(
                    t, "tracker", test::libertyRecord(cfg.devices.headStation, 60, 0, 0, ++frame)));
            input.takeOutput();
        }
    };
    run(200);
    const std::optional<glm::dmat4> before = input.worldFromHead(t);
    ASSERT_TRUE(before.has_value());
    const glm::dvec3 head((*before)[3]);
    // The gaze is the head frame's -z; the target: the world origin, seen from the head.
    auto planAngleDeg = [&](const glm::dmat4& worldFromHead, const glm::dvec3& target) {
        const glm::dvec3 gaze = -glm::dvec3(worldFromHead[2]);
        const glm::dvec2 g = glm::normalize(glm::dvec2(gaze)),
                         d = glm::normalize(glm::dvec2(target - head));
        return glm::degrees(std::acos(std::clamp(glm::dot(g, d), -1.0, 1.0)));
    };
    const glm::dvec3 target(0.0);
    ASSERT_GT(planAngleDeg(*before, target), 20.0);  // the premise: it looked elsewhere

    const std::string said = input.recenterHead(t, target);
    EXPECT_NE(said.find("view recentred: the heading turned by"), std::string::npos) << said;
    run(100);  // the turn is kept as the head keeps reporting
    const std::optional<glm::dmat4> after = input.worldFromHead(t);
    ASSERT_TRUE(after.has_value());
    EXPECT_LT(planAngleDeg(*after, target), 0.5);
    // A turn about the vertical only: the head's tilt and position are as they were.
    EXPECT_NEAR((*after)[2].z, (*before)[2].z, 1e-6);
    EXPECT_NEAR(glm::length(glm::dvec3((*after)[3]) - head), 0.0, 1e-6);
    // A target straight below the head has no direction in plan: refused, nothing turned.
    EXPECT_THROW(input.recenterHead(t, head - glm::dvec3(0, 0, 500)), std::runtime_error);
    EXPECT_LT(planAngleDeg(*input.worldFromHead(t), target), 0.5);
}

}  // namespace
