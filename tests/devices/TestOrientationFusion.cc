// SPDX-License-Identifier: MIT
// The complementary filter on synthetic IMU streams of known motion: constant rate, a
// sequence of rotations, smooth non-commuting head motion, a stationary IMU with gyro bias
// (the tilt error stays bounded), linear-acceleration gating, bad input and random input.
#include "vsculpt/devices/OrientationFusion.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>

using namespace vsculpt::devices;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.80665;
constexpr int64_t kMs = 1'000'000;
const glm::dvec3 kX(1, 0, 0), kY(0, 1, 0), kZ(0, 0, 1);

glm::dquat axisAngle(double angle, const glm::dvec3& axis) {
    const glm::dvec3 n = glm::normalize(axis);
    return glm::dquat(std::cos(0.5 * angle), std::sin(0.5 * angle) * n);
}

// An upright Rift: IMU y up (world z), looking down IMU -z (world +y).
const glm::dquat kUpright = axisAngle(kPi / 2, kX);

// What a perfect IMU at orientation `fusionFromImu` rotating at `gyro` (IMU frame) reads,
// plus an optional linear acceleration (fusion frame).
ImuSample perfect(int64_t tNs, const glm::dquat& fusionFromImu, const glm::dvec3& gyro,
                  const glm::dvec3& linearAccel = glm::dvec3(0.0)) {
    ImuSample s;
    s.deviceTimeNs = tNs;
    s.accelMps2 = glm::conjugate(fusionFromImu) * (kG * kZ + linearAccel);
    s.gyroRadps = gyro;
    return s;
}

std::string sci(double v) {  // measured numbers for --gtest_output=xml
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

double tiltError(const OrientationFusion& f, const glm::dquat& truth) {
    const glm::dvec3 a = f.upInImu(), b = glm::conjugate(truth) * kZ;
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

FusionParams pureGyro() {
    FusionParams p;
    p.gravityGain = 0.0;
    p.biasGain = 0.0;
    return p;
}

// Feeds `steps` samples at 1 kHz of the motion given by truth(t) and its body rate w(t);
// returns the largest orientation error.
double track(OrientationFusion& f, int steps, const std::function<glm::dquat(double)>& truth,
             const std::function<glm::dvec3(double)>& rate) {
    f.reset(truth(0.0), 0);
    double worst = 0.0;
    for (int k = 1; k <= steps; ++k) {
        const double t = k * 1e-3;
        const glm::dquat q = truth(t);
        EXPECT_NE(f.update(perfect(k * kMs, q, rate(t))), FusionStep::Rejected);
        worst = std::max(worst, angleBetween(f.fusionFromImu(), q));
    }
    return worst;
}

TEST(OrientationFusion, ConstantRateAboutAnAxisIsRecovered) {
    const glm::dvec3 w = 2.0 * glm::normalize(glm::dvec3(1, 2, 3));  // rad/s, IMU frame
    const auto truth = [&](double t) { return kUpright * axisAngle(2.0 * t, w); };
    const auto rate = [&](double) { return w; };
    for (const FusionParams& p : {pureGyro(), FusionParams{}}) {
        OrientationFusion f(p);
        const double err = track(f, 5000, truth, rate);  // 10 rad in 5 s
        RecordProperty(p.gravityGain > 0 ? "maxErrorFusedRad" : "maxErrorGyroRad", sci(err));
        EXPECT_LT(err, 1e-9) << "gravityGain " << p.gravityGain;
        EXPECT_LT(glm::length(f.gyroBias()), 1e-9);
    }
}

TEST(OrientationFusion, SequenceOfRotationsIsRecovered) {
    // Body-frame rotations, each with a raised-cosine rate profile (starts and ends at rest).
    struct Segment {
        glm::dvec3 axis;
        double angle, duration;
    };
    const std::vector<Segment> segments{{kX, kPi / 2, 0.5},
                                        {kY, kPi / 2, 0.5},
                                        {kZ, -kPi, 1.0},
                                        {glm::normalize(glm::dvec3(1, 1, 0)), kPi / 4, 0.25},
                                        {glm::normalize(glm::dvec3(-1, 2, 5)), 3.0, 1.5}};
    double start = 0.0;
    std::vector<std::pair<double, glm::dquat>> starts;  // segment start time, orientation
    glm::dquat q = kUpright;
    for (const Segment& s : segments) {
        starts.emplace_back(start, q);
        q = q * axisAngle(s.angle, s.axis);
        start += s.duration;
    }
    const glm::dquat finalTruth = q;
    auto where = [&](double t) {  // the segment that time t falls in
        size_t i = 0;
        while (i + 1 < segments.size() && t >= starts[i + 1].first)
            ++i;
        return i;
    };
    const auto truth = [&](double t) {
        const size_t i = where(t);
        const Segment& s = segments[i];
        const double tau = std::min(t - starts[i].first, s.duration), T = s.duration;
        const double theta = s.angle / T * (tau - T / (2 * kPi) * std::sin(2 * kPi * tau / T));
        return starts[i].second * axisAngle(theta, s.axis);
    };
    const auto rate = [&](double t) {
        const size_t i = where(t);
        const Segment& s = segments[i];
        const double tau = std::min(t - starts[i].first, s.duration), T = s.duration;
        return s.axis * (s.angle / T * (1 - std::cos(2 * kPi * tau / T)));
    };
    const int steps = int(std::lround(start * 1000));
    for (const FusionParams& p : {pureGyro(), FusionParams{}}) {
        OrientationFusion f(p);
        const double err = track(f, steps, truth, rate);
        RecordProperty(p.gravityGain > 0 ? "maxErrorFusedRad" : "maxErrorGyroRad", sci(err));
        // The trapezoid rule's error, dt^2 / 12 x max |dw/dt|, is 6.6e-6 rad for the
        // fastest segment (pi/4 in 0.25 s: 79 rad/s^2); it vanishes at each segment's end.
        EXPECT_LT(err, 1e-5) << "gravityGain " << p.gravityGain;
        EXPECT_LT(angleBetween(f.fusionFromImu(), finalTruth), 1e-6);
    }
}

TEST(OrientationFusion, SmoothNonCommutingHeadMotionIsRecovered) {
    // q(t) = Rz(a) Rx(b) Ry(c) U with smooth angles; body rate from the chain rule.
    const auto a = [](double t) { return 1.0 * std::sin(0.8 * t); };
    const auto b = [](double t) { return 0.5 * std::sin(1.3 * t + 0.4); };
    const auto c = [](double t) { return 0.6 * std::sin(2.1 * t); };
    const auto da = [](double t) { return 0.8 * std::cos(0.8 * t); };
    const auto db = [](double t) { return 0.65 * std::cos(1.3 * t + 0.4); };
    const auto dc = [](double t) { return 1.26 * std::cos(2.1 * t); };
    const auto truth = [&](double t) {
        return axisAngle(a(t), kZ) * axisAngle(b(t), kX) * axisAngle(c(t), kY) * kUpright;
    };
    const auto rate = [&](double t) {
        const glm::dquat B = axisAngle(b(t), kX), C = axisAngle(c(t), kY);
        const glm::dvec3 wAbc = glm::conjugate(C) * (glm::conjugate(B) * (da(t) * kZ)) +
                                glm::conjugate(C) * (db(t) * kX) + dc(t) * kY;
        return glm::conjugate(kUpright) * wAbc;
    };
    for (const FusionParams& p : {pureGyro(), FusionParams{}}) {
        OrientationFusion f(p);
        const double err = track(f, 20000, truth, rate);
        RecordProperty(p.gravityGain > 0 ? "maxErrorFusedRad" : "maxErrorGyroRad", sci(err));
        EXPECT_LT(err, 2e-6) << "gravityGain " << p.gravityGain;
    }
}

TEST(OrientationFusion, GravityCorrectionBoundsTheTiltErrorOfABiasedGyro) {
    // Stationary upright IMU; its gyro reads a constant bias. IMU x and z are horizontal
    // (tilt), IMU y is up (yaw, unobservable without a magnetometer).
    const glm::dvec3 bias(0.02, 0.01, -0.015);  // rad/s; tilt part 0.025 rad/s
    auto run = [&](const FusionParams& p, double seconds, std::vector<double>* tiltAt) {
        OrientationFusion f(p);
        f.reset(kUpright, 0);
        for (int k = 1; k <= int(seconds * 1000); ++k) {
            f.update(perfect(k * kMs, kUpright, bias));
            if (k % 10000 == 0 && tiltAt) tiltAt->push_back(tiltError(f, kUpright));
        }
        return f;
    };
    // Without correction the estimate turns about the bias axis n at |bias|: the tilt error
    // is the angle between up and up turned by |bias| t about n.
    std::vector<double> free;
    run(pureGyro(), 120, &free);
    const double c = bias.y / glm::length(bias);  // cos(angle between n and up)
    for (size_t i = 0; i < free.size(); ++i) {
        const double theta = glm::length(bias) * 10.0 * double(i + 1);
        EXPECT_NEAR(free[i], std::acos(std::cos(theta) + (1 - std::cos(theta)) * c * c), 1e-6);
    }
    EXPECT_GT(free[5], 1.4);  // 60 s

    // Proportional correction only: bounded at about |tilt bias| / gain = 0.05 rad.
    FusionParams prop;
    prop.biasGain = 0.0;
    std::vector<double> bounded;
    run(prop, 120, &bounded);
    RecordProperty("tiltAt60sNoCorrectionRad", sci(free[5]));
    RecordProperty("tiltAt60sProportionalRad", sci(bounded[5]));
    RecordProperty("tiltAt120sProportionalRad", sci(bounded.back()));
    EXPECT_NEAR(bounded.back(), 0.025 / prop.gravityGain, 0.002);
    EXPECT_NEAR(bounded[5], bounded.back(), 1e-6);  // at 60 s and 120 s: not growing

    // With bias estimation (the defaults) the tilt part of the bias is learnt and the error
    // goes to zero; the yaw part is not observable and is not learnt.
    std::vector<double> learnt;
    const OrientationFusion f = run(FusionParams{}, 120, &learnt);
    RecordProperty("tiltAt60sWithBiasRad", sci(learnt[5]));
    RecordProperty("tiltAt120sWithBiasRad", sci(learnt.back()));
    EXPECT_LT(learnt.back(), 1e-3);
    EXPECT_NEAR(f.gyroBias().x, bias.x, 1e-3);
    EXPECT_NEAR(f.gyroBias().z, bias.z, 1e-3);
    EXPECT_NEAR(f.gyroBias().y, 0.0, 1e-9);
}

TEST(OrientationFusion, NoisyBiasedMovingHeadKeepsTiltWithinHalfADegreeOnceTheBiasIsLearnt) {
    // Realistic noise on a moving head: gyro white noise 0.005 rad/s, accel 0.05 m/s^2,
    // a gyro bias, 60 s of the smooth motion from above (rotation about the IMU centre).
    std::mt19937 rng(7);
    std::normal_distribution<double> gyroNoise(0.0, 0.005), accelNoise(0.0, 0.05);
    const glm::dvec3 bias(0.01, -0.008, 0.006);
    const auto truth = [](double t) {
        return axisAngle(0.8 * std::sin(0.5 * t), kZ) * axisAngle(0.3 * std::sin(0.9 * t), kX) *
               kUpright;
    };
    OrientationFusion f;
    double worst = 0.0, worstAfter20s = 0.0;
    for (int k = 0; k <= 60000; ++k) {
        const double t = k * 1e-3, h = 1e-6;
        const glm::dquat q = truth(t);
        const glm::dquat dq = (truth(t + h) - truth(t - h)) / (2 * h);
        const glm::dquat w = 2.0 * (glm::conjugate(q) * dq);  // body rate, numerically
        ImuSample s = perfect(k * kMs, q, glm::dvec3(w.x, w.y, w.z) + bias);
        s.gyroRadps += glm::dvec3(gyroNoise(rng), gyroNoise(rng), gyroNoise(rng));
        s.accelMps2 += glm::dvec3(accelNoise(rng), accelNoise(rng), accelNoise(rng));
        f.update(s);
        worst = std::max(worst, tiltError(f, q));
        if (t >= 20.0) worstAfter20s = std::max(worstAfter20s, tiltError(f, q));
    }
    // While the bias is being learnt (time constant 4 s) the error peaks at about
    // |tilt bias| / gravityGain; once it is learnt, only the noise is left.
    RecordProperty("worstTiltRad", sci(worst));
    RecordProperty("worstTiltAfter20sRad", sci(worstAfter20s));
    EXPECT_LT(worst, 1.5 * kPi / 180);
    EXPECT_LT(worstAfter20s, 0.5 * kPi / 180);
}

TEST(OrientationFusion, LinearAccelerationIsNotMistakenForTilt) {
    // A stationary orientation, pushed sideways at 6 m/s^2 for 2 s (|a| = 11.5 m/s^2).
    auto run = [](double tolerance) {
        FusionParams p;
        p.accelToleranceMps2 = tolerance;
        OrientationFusion f(p);
        f.reset(kUpright, 0);
        for (int k = 1; k <= 2000; ++k)
            f.update(perfect(k * kMs, kUpright, glm::dvec3(0.0), glm::dvec3(6.0, 0.0, 0.0)));
        return tiltError(f, kUpright);
    };
    EXPECT_LT(run(1.0), 1e-12);  // gated: the accelerometer is ignored
    EXPECT_GT(run(100.0), 0.1);  // without the gate, the push reads as a tilt
}

TEST(OrientationFusion, InitialisesTiltFromTheAccelerometer) {
    OrientationFusion upright;
    ImuSample still;
    still.deviceTimeNs = 5;
    still.accelMps2 = glm::dvec3(0, kG, 0);  // IMU y up
    EXPECT_EQ(upright.update(still), FusionStep::Initialised);
    const glm::dvec3 gaze = upright.fusionFromImu() * glm::dvec3(0, 0, -1);
    EXPECT_NEAR(glm::distance(gaze, kY), 0.0, 1e-12);  // looks along +y

    // An arbitrary tilt, with no usable accelerometer on the first sample.
    const glm::dquat truth = axisAngle(2.1, glm::dvec3(0.3, -0.7, 0.2));
    OrientationFusion f;
    ImuSample moving = perfect(0, truth, glm::dvec3(0.0), glm::dvec3(0, 0, 5.0));
    EXPECT_EQ(f.update(moving), FusionStep::Integrated);
    EXPECT_EQ(f.update(perfect(1 * kMs, truth, glm::dvec3(0.0))), FusionStep::Initialised);
    EXPECT_LT(tiltError(f, truth), 1e-12);
    // The estimate differs from the truth by a heading only: a rotation about +z.
    const glm::dquat heading = f.fusionFromImu() * glm::conjugate(truth);
    EXPECT_NEAR(glm::distance(heading * kZ, kZ), 0.0, 1e-12);
    EXPECT_EQ(f.update(perfect(2 * kMs, truth, glm::dvec3(0.0))), FusionStep::Corrected);
}

TEST(OrientationFusion, AGapIsIntegratedOverAtMostMaxStep) {
    FusionParams p = pureGyro();
    OrientationFusion f(p);
    f.reset(glm::dquat(1, 0, 0, 0), 0);
    ImuSample s;
    s.gyroRadps = glm::dvec3(0, 0, 1.0);
    s.deviceTimeNs = 1'000'000'000;  // 1 s after the last sample
    f.update(s);
    EXPECT_NEAR(angleBetween(f.fusionFromImu(), glm::dquat(1, 0, 0, 0)), p.maxStepS, 1e-12);
    EXPECT_EQ(f.stats().clampedSteps, 1u);
}

TEST(OrientationFusion, IsDeterministic) {
    auto run = [] {
        std::mt19937 rng(99);
        std::normal_distribution<double> n(0.0, 0.3);
        OrientationFusion f;
        for (int k = 0; k < 5000; ++k) {
            ImuSample s;
            s.deviceTimeNs = k * kMs;
            s.gyroRadps = glm::dvec3(n(rng), n(rng), n(rng));
            s.accelMps2 = glm::dvec3(n(rng), kG + n(rng), n(rng));
            f.update(s);
        }
        return f;
    };
    const OrientationFusion a = run(), b = run();
    EXPECT_EQ(a.fusionFromImu().w, b.fusionFromImu().w);
    EXPECT_EQ(a.fusionFromImu().x, b.fusionFromImu().x);
    EXPECT_EQ(a.fusionFromImu().y, b.fusionFromImu().y);
    EXPECT_EQ(a.fusionFromImu().z, b.fusionFromImu().z);
    EXPECT_EQ(a.gyroBias(), b.gyroBias());
}

TEST(OrientationFusion, BadInputIsRejectedWithoutChangingTheState) {
    OrientationFusion f;
    f.update(perfect(10 * kMs, kUpright, glm::dvec3(0.1, 0, 0)));
    const glm::dquat before = f.fusionFromImu();
    ImuSample bad = perfect(11 * kMs, kUpright, glm::dvec3(0.0));
    bad.gyroRadps.y = std::nan("");
    EXPECT_EQ(f.update(bad), FusionStep::Rejected);
    bad = perfect(11 * kMs, kUpright, glm::dvec3(0.0));
    bad.accelMps2.x = std::numeric_limits<double>::infinity();
    EXPECT_EQ(f.update(bad), FusionStep::Rejected);
    bad = perfect(11 * kMs, kUpright, glm::dvec3(1e300, 0, 0));
    EXPECT_EQ(f.update(bad), FusionStep::Rejected);
    EXPECT_EQ(f.update(perfect(10 * kMs, kUpright, glm::dvec3(1, 0, 0))), FusionStep::Rejected);
    EXPECT_EQ(f.update(perfect(9 * kMs, kUpright, glm::dvec3(1, 0, 0))), FusionStep::Rejected);
    EXPECT_EQ(f.stats().rejected, 5u);
    EXPECT_EQ(f.fusionFromImu(), before);
    EXPECT_EQ(f.timeNs(), 10 * kMs);

    FusionParams p;
    p.gravityGain = -1;
    try {
        OrientationFusion bad(p);
        FAIL() << "negative gain accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("gravityGain"), std::string::npos) << e.what();
    }
    p = FusionParams{};
    p.maxStepS = 0;
    EXPECT_THROW(OrientationFusion{p}, std::invalid_argument);
    p = FusionParams{};
    p.biasGain = std::nan("");
    EXPECT_THROW(OrientationFusion{p}, std::invalid_argument);
    EXPECT_THROW(f.reset(glm::dquat(0, 0, 0, 0), 0), std::invalid_argument);
}

TEST(OrientationFusion, RandomSamplesKeepAUnitQuaternion) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> any(-200.0, 200.0);
    std::uniform_int_distribution<int> pick(0, 19), dt(-2'000'000, 80'000'000);
    const double specials[] = {std::nan(""), std::numeric_limits<double>::infinity(), 1e9, 0.0,
                               -1e-300};
    OrientationFusion f;
    int64_t t = 0;
    for (int i = 0; i < 200000; ++i) {
        ImuSample s;
        t += dt(rng);
        s.deviceTimeNs = t;
        s.gyroRadps = glm::dvec3(any(rng), any(rng), any(rng)) * (pick(rng) < 10 ? 0.01 : 1.0);
        s.accelMps2 = glm::dvec3(any(rng), any(rng), any(rng)) * (pick(rng) < 10 ? 0.05 : 1.0);
        if (pick(rng) == 0) s.gyroRadps[pick(rng) % 3] = specials[pick(rng) % 5];
        if (pick(rng) == 0) s.accelMps2[pick(rng) % 3] = specials[pick(rng) % 5];
        f.update(s);
        const glm::dquat q = f.fusionFromImu();
        ASSERT_NEAR(glm::length(q), 1.0, 1e-12) << i;
        ASSERT_LE(std::abs(f.gyroBias().x), f.params().maxBiasRadps);
    }
    EXPECT_GT(f.stats().rejected, 1000u);
    EXPECT_GT(f.stats().corrected, 1000u);
}

}  // namespace
