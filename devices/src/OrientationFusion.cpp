// SPDX-License-Identifier: MIT
#include "vsculpt/devices/OrientationFusion.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vsculpt::devices {

namespace {

const glm::dvec3 kUp(0.0, 0.0, 1.0);

// Beyond any real IMU (the Rift's range is about 105 in both units); larger values would
// overflow the step's trigonometry, so they are refused like NaN.
constexpr double kMaxPlausible = 1e6;

bool plausible(const glm::dvec3& v) {
    for (int i = 0; i < 3; ++i)
        if (!(std::abs(v[i]) <= kMaxPlausible)) return false;  // also false for NaN
    return true;
}

void requireNonNegative(double v, const char* name) {
    if (!(v >= 0.0) || !std::isfinite(v))
        throw std::invalid_argument(std::string("FusionParams::") + name +
                                    " must be finite and >= 0, got " + std::to_string(v));
}

void requirePositive(double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v))
        throw std::invalid_argument(std::string("FusionParams::") + name +
                                    " must be finite and > 0, got " + std::to_string(v));
}

// Turns `q` (fusionFromImu) by the body-frame rotation vector w dt: exact for a constant w.
glm::dquat rotateBody(const glm::dquat& q, const glm::dvec3& w, double dt) {
    const double rate = glm::length(w);
    if (!(rate * dt > 0.0)) return q;
    const double half = 0.5 * rate * dt;
    return glm::normalize(q * glm::dquat(std::cos(half), (std::sin(half) / rate) * w));
}

}  // namespace

OrientationFusion::OrientationFusion(const FusionParams& p) : mParams(p) {
    requireNonNegative(p.gravityGain, "gravityGain");
    requireNonNegative(p.biasGain, "biasGain");
    requireNonNegative(p.maxBiasRadps, "maxBiasRadps");
    requireNonNegative(p.accelToleranceMps2, "accelToleranceMps2");
    requirePositive(p.standardGravityMps2, "standardGravityMps2");
    requirePositive(p.maxStepS, "maxStepS");
}

void OrientationFusion::reset() {
    const FusionStats stats = mStats;
    *this = OrientationFusion(mParams);
    mStats = stats;
}

void OrientationFusion::reset(const glm::dquat& q, int64_t timeNs) {
    const double n = glm::length(q);
    if (!std::isfinite(n) || n == 0.0)
        throw std::invalid_argument("OrientationFusion::reset: orientation is zero or not finite");
    mQ = q / n;
    mTimeNs = timeNs;
    mHaveSample = true;
    mHaveGyro = false;
    mTiltKnown = true;
}

glm::dvec3 OrientationFusion::upInImu() const {
    return glm::conjugate(mQ) * kUp;
}

FusionStep OrientationFusion::update(const ImuSample& s) {
    if (!plausible(s.accelMps2) || !plausible(s.gyroRadps) ||
        (mHaveSample && s.deviceTimeNs <= mTimeNs)) {
        ++mStats.rejected;
        return FusionStep::Rejected;
    }
    const FusionParams& p = mParams;
    const double accelNorm = glm::length(s.accelMps2);
    const bool accelUsable =
        accelNorm > 0.0 && std::abs(accelNorm - p.standardGravityMps2) <= p.accelToleranceMps2;
    const glm::dvec3 accelDir = accelUsable ? s.accelMps2 / accelNorm : glm::dvec3(0.0);

    FusionStep step = FusionStep::Integrated;
    if (mHaveSample) {
        // Unsigned difference: exact for any pair of int64 times in order.
        double dt = double(uint64_t(s.deviceTimeNs) - uint64_t(mTimeNs)) * 1e-9;
        const bool gap = dt > p.maxStepS;
        if (gap) {
            dt = p.maxStepS;
            ++mStats.clampedSteps;
        }
        const glm::dvec3 w =
            ((gap || !mHaveGyro) ? s.gyroRadps : 0.5 * (s.gyroRadps + mLastGyro)) - mBias;
        mQ = rotateBody(mQ, w, dt);
        if (accelUsable && mTiltKnown && p.gravityGain > 0.0) {
            // Compared after the gyro step, so that the accelerometer and the estimate refer
            // to the same instant (before it, a rotating head reads as a tilt of w dt).
            const glm::dvec3 e = glm::cross(accelDir, upInImu());
            mQ = rotateBody(mQ, p.gravityGain * e, dt);
            if (p.biasGain > 0.0)
                mBias = glm::clamp(mBias - p.biasGain * dt * e, -p.maxBiasRadps, p.maxBiasRadps);
            step = FusionStep::Corrected;
        }
        ++mStats.integrated;
    }
    if (!mTiltKnown && accelUsable) {
        if (p.initialiseFromAccel) {
            // Rotate the estimate by the least amount that makes it agree with gravity.
            mQ = glm::normalize(shortestArc(mQ * accelDir, kUp) * mQ);
            step = FusionStep::Initialised;
        }
        mTiltKnown = true;
    }
    if (step == FusionStep::Corrected) ++mStats.corrected;
    mHaveSample = true;
    mHaveGyro = true;
    mTimeNs = s.deviceTimeNs;
    mLastGyro = s.gyroRadps;
    mOmega = s.gyroRadps - mBias;
    return step;
}

glm::dquat shortestArc(const glm::dvec3& from, const glm::dvec3& to) {
    const double d = glm::dot(from, to);
    if (d < -1.0 + 1e-12) {
        // Opposite: any perpendicular axis will do; take the one furthest from `from`'s
        // dominant component to keep the cross product well conditioned.
        const glm::dvec3 other =
            std::abs(from.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
        const glm::dvec3 axis = glm::normalize(glm::cross(from, other));
        return glm::dquat(0.0, axis);
    }
    const glm::dvec3 c = glm::cross(from, to);
    return glm::normalize(glm::dquat(1.0 + d, c));
}

double angleBetween(const glm::dquat& a, const glm::dquat& b) {
    const glm::dquat d = glm::conjugate(a) * b;
    return 2.0 * std::atan2(glm::length(glm::dvec3(d.x, d.y, d.z)), std::abs(d.w));
}

}  // namespace vsculpt::devices
