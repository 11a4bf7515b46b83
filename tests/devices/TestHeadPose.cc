// SPDX-License-Identifier: MIT
// Head pose from the fused IMU orientation and a tracker position, the eye poses, heading
// recentring, time alignment, and the whole chain from Rift DK2 report bytes to eye poses.
#include "vsculpt/devices/HeadPose.h"
#include "vsculpt/devices/OrientationFusion.h"
#include "vsculpt/devices/RiftImu.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

using namespace vsculpt::devices;

namespace {

constexpr double kPi = 3.14159265358979323846;
const glm::dvec3 kX(1, 0, 0), kY(0, 1, 0), kZ(0, 0, 1), kForward(0, 0, -1);

glm::dquat axisAngle(double angle, const glm::dvec3& axis) {
    const glm::dvec3 n = glm::normalize(axis);
    return glm::dquat(std::cos(0.5 * angle), std::sin(0.5 * angle) * n);
}

const glm::dquat kUpright = axisAngle(kPi / 2, kX);  // Rift: IMU y up, looking along world +y

glm::dvec3 point(const glm::dmat4& m, const glm::dvec3& p) {
    return glm::dvec3(m * glm::dvec4(p, 1.0));
}

glm::dvec3 direction(const glm::dmat4& m, const glm::dvec3& d) {
    return glm::dvec3(m * glm::dvec4(d, 0.0));
}

TEST(HeadPose, UprightRiftWithASensorOnTopOfTheHead) {
    HeadCalibration cal;
    cal.sensorInHeadMm = glm::dvec3(0, 80, 0);  // 80 mm above the eyes
    const glm::dmat4 m = combineHeadPose(kUpright, glm::dvec3(100, 200, 300), cal);
    EXPECT_NEAR(glm::distance(glm::dvec3(m[3]), glm::dvec3(100, 200, 220)), 0.0, 1e-12);
    EXPECT_NEAR(glm::distance(direction(m, kForward), kY), 0.0, 1e-12);  // looks along +y
    EXPECT_NEAR(glm::distance(direction(m, kY), kZ), 0.0, 1e-12);        // head up = world up
    EXPECT_NEAR(glm::distance(direction(m, kX), kX), 0.0, 1e-12);        // right = world x
}

TEST(HeadPose, CalibrationChainPutsTheSensorWhereTheTrackerSawIt) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto randomRotation = [&] {
        return axisAngle(3.0 * u(rng), glm::dvec3(u(rng), u(rng), u(rng) + 2.0));
    };
    for (int i = 0; i < 200; ++i) {
        HeadCalibration cal;
        cal.headFromImu = randomRotation();
        cal.worldFromFusion = randomRotation();
        cal.sensorInHeadMm = 100.0 * glm::dvec3(u(rng), u(rng), u(rng));
        cal.worldFromTracker = glm::mat4_cast(randomRotation());
        cal.worldFromTracker[3] = glm::dvec4(1000.0 * u(rng), 1000.0 * u(rng), 500.0, 1.0);
        const glm::dquat fusionFromImu = randomRotation();
        const glm::dvec3 sensor = 800.0 * glm::dvec3(u(rng), u(rng), u(rng));
        const glm::dmat4 m = combineHeadPose(fusionFromImu, sensor, cal);
        // The head's sensor point lands on the tracked position...
        EXPECT_NEAR(
            glm::distance(point(m, cal.sensorInHeadMm), point(cal.worldFromTracker, sensor)), 0.0,
            1e-9);
        // ...and the IMU axes, carried through the head, point where the fusion says.
        const glm::dquat worldFromImu = cal.worldFromFusion * fusionFromImu;
        for (const glm::dvec3& axis : {kX, kY, kZ})
            EXPECT_NEAR(glm::distance(direction(m, cal.headFromImu * axis), worldFromImu * axis),
                        0.0, 1e-12);
        // A rigid transform.
        const glm::dmat3 r(m);
        const glm::dmat3 rtR = glm::transpose(r) * r;
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(rtR[c][k], c == k ? 1.0 : 0.0, 1e-12);
        EXPECT_NEAR(glm::determinant(r), 1.0, 1e-12);
    }
}

TEST(HeadPose, EyesAreSeparatedByTheIpdAlongHeadX) {
    HeadCalibration cal;
    const glm::dquat q = axisAngle(0.7, glm::dvec3(1, -2, 0.5));
    const glm::dmat4 head = combineHeadPose(q, glm::dvec3(-40, 310, 1650), cal);
    for (double ipd : {0.0, 58.0, 63.5, 72.0}) {
        const EyePoses e = eyePoses(head, ipd);
        const glm::dvec3 left(e.worldFromLeftEye[3]), right(e.worldFromRightEye[3]);
        EXPECT_NEAR(glm::distance(left, right), ipd, 1e-12);
        // The separation is along head x, left to right, centred on the head origin.
        EXPECT_NEAR(glm::distance(right - left, ipd * glm::dvec3(head[0])), 0.0, 1e-12);
        EXPECT_NEAR(glm::distance(0.5 * (left + right), glm::dvec3(head[3])), 0.0, 1e-12);
        // In the head frame, the eyes sit at exactly (-ipd/2, 0, 0) and (+ipd/2, 0, 0).
        const glm::dvec3 l = point(glm::inverse(head), left);
        EXPECT_NEAR(glm::distance(l, glm::dvec3(-0.5 * ipd, 0, 0)), 0.0, 1e-9);
        // Same axes as the head.
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(e.worldFromLeftEye[c], head[c]);
            EXPECT_EQ(e.worldFromRightEye[c], head[c]);
        }
    }
}

TEST(HeadPose, BadInputIsRefusedWithAMessage) {
    HeadCalibration cal;
    const glm::dmat4 head = combineHeadPose(kUpright, glm::dvec3(0), cal);
    EXPECT_THROW(eyePoses(head, -1.0), std::invalid_argument);
    try {
        eyePoses(head, std::nan(""));
        FAIL() << "NaN IPD accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("IPD"), std::string::npos) << e.what();
    }
    EXPECT_THROW(combineHeadPose(glm::dquat(0, 0, 0, 0), glm::dvec3(0), cal),
                 std::invalid_argument);
    EXPECT_THROW(combineHeadPose(kUpright, glm::dvec3(0, std::nan(""), 0), cal),
                 std::invalid_argument);
    cal.sensorInHeadMm.x = std::numeric_limits<double>::infinity();
    EXPECT_THROW(combineHeadPose(kUpright, glm::dvec3(0), cal), std::invalid_argument);
    // Looking straight down: no heading to recentre on.
    EXPECT_THROW(recenterHeading(axisAngle(0.0, kX), glm::dquat(1, 0, 0, 0), kY),
                 std::invalid_argument);
    EXPECT_THROW(recenterHeading(kUpright, glm::dquat(1, 0, 0, 0), kZ), std::invalid_argument);
    EXPECT_THROW(HeadPoseTracker(HeadCalibration{}, -0.1), std::invalid_argument);
}

TEST(HeadPose, RecenteringTurnsTheGazeToTheTargetAndKeepsTheTilt) {
    // Head yawed by 2 rad and pitched down by 0.3 rad in the fusion frame.
    const glm::dquat q = axisAngle(2.0, kZ) * axisAngle(-0.3, kX) * kUpright;
    const glm::dquat headFromImu(1, 0, 0, 0);
    const glm::dvec3 target = glm::normalize(glm::dvec3(1, 1, 0.4));  // its tilt is ignored
    HeadCalibration cal;
    cal.worldFromFusion = recenterHeading(q, headFromImu, target);
    const glm::dmat4 m = combineHeadPose(q, glm::dvec3(0), cal);
    const glm::dvec3 gaze = direction(m, kForward);
    EXPECT_NEAR(std::atan2(gaze.y, gaze.x), kPi / 4, 1e-12);  // heading of the target
    EXPECT_NEAR(gaze.z, -std::sin(0.3), 1e-12);               // pitch unchanged
    EXPECT_NEAR(glm::length(glm::dvec3(cal.worldFromFusion.x, cal.worldFromFusion.y, 0)), 0.0,
                1e-15);  // a rotation about z only
}

TEST(HeadPoseTracker, InterpolatesPositionAndTurnsOrientationOnToTheQueryTime) {
    HeadCalibration cal;
    HeadPoseTracker t(cal, 0.05);
    EXPECT_FALSE(t.worldFromHeadAt(0));
    const glm::dvec3 w(0, 1.5, 0);  // rad/s about IMU y = world up for an upright Rift
    ASSERT_TRUE(t.addOrientation(1'000'000'000, kUpright, w));
    EXPECT_FALSE(t.worldFromHeadAt(1'000'000'000));  // no position yet
    ASSERT_TRUE(t.addTrackerPosition(990'000'000, glm::dvec3(0, 0, 1000)));
    ASSERT_TRUE(t.addTrackerPosition(1'000'000'000, glm::dvec3(10, 0, 1000)));
    EXPECT_FALSE(t.addTrackerPosition(995'000'000, glm::dvec3(0)));  // older: ignored
    EXPECT_FALSE(t.addTrackerPosition(1'001'000'000, glm::dvec3(0, std::nan(""), 0)));

    // Between the two tracker samples: interpolated; orientation turned back by 4 ms.
    auto m = t.worldFromHeadAt(996'000'000);
    ASSERT_TRUE(m);
    EXPECT_NEAR(glm::distance(glm::dvec3((*m)[3]), glm::dvec3(6, 0, 1000)), 0.0, 1e-9);
    glm::dvec3 gaze = direction(*m, kForward);
    EXPECT_NEAR(std::atan2(-gaze.x, gaze.y), -1.5 * 0.004, 1e-12);

    // 20 ms ahead: position extrapolated at 1 mm/ms, orientation predicted by 0.03 rad.
    m = t.worldFromHeadAt(1'020'000'000);
    ASSERT_TRUE(m);
    EXPECT_NEAR(glm::distance(glm::dvec3((*m)[3]), glm::dvec3(30, 0, 1000)), 0.0, 1e-9);
    gaze = direction(*m, kForward);
    EXPECT_NEAR(std::atan2(-gaze.x, gaze.y), 0.03, 1e-12);

    EXPECT_FALSE(t.worldFromHeadAt(1'051'000'000));  // too far ahead
    EXPECT_FALSE(t.worldFromHeadAt(939'000'000));    // too far behind
}

// ---- The whole chain: DK2 report bytes -> samples -> fusion -> head and eye poses. ----------

std::array<uint8_t, 8> pack21(const std::array<int32_t, 3>& v) {
    constexpr uint64_t kMask = 0x1FFFFF;
    const uint64_t word = (uint64_t(uint32_t(v[0])) & kMask) << 43 |
                          (uint64_t(uint32_t(v[1])) & kMask) << 22 |
                          (uint64_t(uint32_t(v[2])) & kMask) << 1;
    std::array<uint8_t, 8> b{};
    for (int i = 0; i < 8; ++i)
        b[size_t(i)] = uint8_t(word >> (56 - 8 * i));
    return b;
}

TEST(HeadPose, RiftReportsToEyePoses) {
    // An upright head turning left about world up at 0.5 rad/s for 2 s, the tracker sensor
    // 100 mm above the eyes seeing a fixed position; DK2 reports of 2 samples every 2 ms.
    const int32_t gyroUp = 5000;    // 0.5 rad/s in 1e-4 rad/s counts, about IMU y
    const int32_t accelUp = 98067;  // 9.8067 m/s^2 along IMU y
    HeadCalibration cal;
    cal.sensorInHeadMm = glm::dvec3(0, 100, 0);
    const int64_t hostOffsetNs = 5'000'000'000, latencyNs = 2'000'000;

    RiftImuStream stream;
    OrientationFusion fusion;
    HeadPoseTracker tracker(cal);
    std::vector<ImuSample> samples;
    uint16_t total = 0;
    int64_t lastHostNs = 0;
    for (int k = 1; k <= 1000; ++k) {
        std::vector<uint8_t> r(64, 0);
        r[0] = 11;
        r[3] = 2;
        r[4] = uint8_t(total);
        r[5] = uint8_t(total >> 8);
        const uint32_t timestampUs = uint32_t(2000 * k);
        for (int i = 0; i < 4; ++i)
            r[8 + size_t(i)] = uint8_t(timestampUs >> (8 * i));
        for (size_t s = 0; s < 2; ++s) {
            const auto a = pack21({0, accelUp, 0}), g = pack21({0, gyroUp, 0});
            std::copy(a.begin(), a.end(), r.begin() + long(12 + 16 * s));
            std::copy(g.begin(), g.end(), r.begin() + long(20 + 16 * s));
        }
        total = uint16_t(total + 2);
        samples.clear();
        lastHostNs = hostOffsetNs + int64_t(timestampUs) * 1000 + latencyNs;
        ASSERT_EQ(stream.push(r, lastHostNs, samples).samples, 2);
        for (const ImuSample& s : samples) {
            ASSERT_NE(fusion.update(s), FusionStep::Rejected);
            tracker.addOrientation(s.hostTimeNs, fusion.fusionFromImu(),
                                   fusion.angularVelocityRadps());
        }
        if (k % 4 == 0)  // a 125 Hz tracker
            tracker.addTrackerPosition(lastHostNs - latencyNs, glm::dvec3(0, -500, 1600));
    }
    EXPECT_EQ(stream.stats().missedSamples, 0u);
    // 1999 ms of rotation since the first sample, seen 8 ms later than the last sample.
    const auto head = tracker.worldFromHeadAt(lastHostNs + 8'000'000);
    ASSERT_TRUE(head);
    const double expectedYaw = 0.5 * (1.999 + 0.008);
    const glm::dvec3 gaze = direction(*head, kForward);
    EXPECT_NEAR(std::atan2(-gaze.x, gaze.y), expectedYaw, 1e-6);
    EXPECT_NEAR(gaze.z, 0.0, 1e-6);
    EXPECT_NEAR(glm::distance(glm::dvec3((*head)[3]), glm::dvec3(0, -500, 1500)), 0.0, 1e-3);
    const EyePoses eyes = eyePoses(*head, 64.0);
    const glm::dvec3 rightward(std::cos(expectedYaw), std::sin(expectedYaw), 0.0);
    EXPECT_NEAR(
        glm::distance(glm::dvec3(eyes.worldFromRightEye[3]) - glm::dvec3(eyes.worldFromLeftEye[3]),
                      64.0 * rightward),
        0.0, 1e-3);
}

}  // namespace
