// SPDX-License-Identifier: MIT
#include "vsculpt/devices/HeadPose.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vsculpt::devices {

namespace {

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

bool usable(const glm::dquat& q) {
    const double n = glm::length(q);
    return std::isfinite(n) && n > 0.0;
}

bool finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

[[noreturn]] void bad(const std::string& what) {
    throw std::invalid_argument("head pose: " + what);
}

// a - b in seconds, without overflowing for any pair of int64 times.
double secondsBetween(int64_t a, int64_t b) {
    return a >= b ? double(uint64_t(a) - uint64_t(b)) * 1e-9
                  : -double(uint64_t(b) - uint64_t(a)) * 1e-9;
}

glm::dquat rotationVector(const glm::dvec3& v) {
    const double angle = glm::length(v);
    if (!(angle > 0.0)) return glm::dquat(1.0, 0.0, 0.0, 0.0);
    return glm::dquat(std::cos(0.5 * angle), (std::sin(0.5 * angle) / angle) * v);
}

// The horizontal part of a direction, unit length; throws when it is about vertical.
glm::dvec3 horizontal(const glm::dvec3& d, const char* what) {
    const double n = glm::length(d), h = std::hypot(d.x, d.y);
    if (!std::isfinite(n) || !(h > 0.0087 * n))  // sin(0.5 degree)
        bad(std::string(what) + " is vertical, zero or not finite: no heading to align");
    return glm::dvec3(d.x / h, d.y / h, 0.0);
}

}  // namespace

glm::dmat4 combineHeadPose(const glm::dquat& fusionFromImu, const glm::dvec3& sensorInTrackerMm,
                           const HeadCalibration& cal) {
    if (!usable(fusionFromImu)) bad("fusionFromImu is zero or not finite");
    if (!finite(sensorInTrackerMm)) bad("tracker sensor position is not finite");
    if (!usable(cal.headFromImu)) bad("calibration headFromImu is zero or not finite");
    if (!usable(cal.worldFromFusion)) bad("calibration worldFromFusion is zero or not finite");
    if (!finite(cal.sensorInHeadMm)) bad("calibration sensorInHeadMm is not finite");
    if (!finite(cal.worldFromTracker)) bad("calibration worldFromTracker is not finite");
    const glm::dquat worldFromHead =
        glm::normalize(glm::normalize(cal.worldFromFusion) * glm::normalize(fusionFromImu) *
                       glm::conjugate(glm::normalize(cal.headFromImu)));
    const glm::dvec3 sensorInWorld =
        glm::dvec3(cal.worldFromTracker * glm::dvec4(sensorInTrackerMm, 1.0));
    glm::dmat4 m = glm::mat4_cast(worldFromHead);
    m[3] = glm::dvec4(sensorInWorld - worldFromHead * cal.sensorInHeadMm, 1.0);
    return m;
}

EyePoses eyePoses(const glm::dmat4& worldFromHead, double ipdMm) {
    if (!(ipdMm >= 0.0) || !std::isfinite(ipdMm))
        bad("IPD must be finite and >= 0 mm, got " + std::to_string(ipdMm));
    EyePoses e;
    e.worldFromLeftEye = e.worldFromRightEye = worldFromHead;
    // Moving along the head's own x axis: column 0 of worldFromHead.
    e.worldFromLeftEye[3] -= (0.5 * ipdMm) * worldFromHead[0];
    e.worldFromRightEye[3] += (0.5 * ipdMm) * worldFromHead[0];
    return e;
}

glm::dquat recenterHeading(const glm::dquat& fusionFromImu, const glm::dquat& headFromImu,
                           const glm::dvec3& worldDirection) {
    if (!usable(fusionFromImu) || !usable(headFromImu))
        bad("recenterHeading: orientation is zero or not finite");
    const glm::dvec3 gaze = glm::normalize(fusionFromImu) *
                            (glm::conjugate(glm::normalize(headFromImu)) * glm::dvec3(0, 0, -1));
    const glm::dvec3 from = horizontal(gaze, "the gaze");
    const glm::dvec3 to = horizontal(worldDirection, "the target direction");
    const double angle = std::atan2(from.x * to.y - from.y * to.x, glm::dot(from, to));
    return glm::dquat(std::cos(0.5 * angle), 0.0, 0.0, std::sin(0.5 * angle));
}

HeadPoseTracker::HeadPoseTracker(const HeadCalibration& calibration, double maxExtrapolationS)
    : mCalibration(calibration) {
    if (!(maxExtrapolationS >= 0.0) || !(maxExtrapolationS < 1e6))
        bad("maxExtrapolationS must be finite and >= 0, got " + std::to_string(maxExtrapolationS));
    mMaxExtrapolationNs = int64_t(std::llround(maxExtrapolationS * 1e9));
}

bool HeadPoseTracker::addOrientation(int64_t timeNs, const glm::dquat& q, const glm::dvec3& w) {
    if (!usable(q) || !finite(w)) return false;
    if (mHaveOrientation && timeNs < mOrientationTimeNs) return false;
    mHaveOrientation = true;
    mOrientationTimeNs = timeNs;
    mOrientation = glm::normalize(q);
    mAngularVelocity = w;
    return true;
}

bool HeadPoseTracker::addTrackerPosition(int64_t timeNs, const glm::dvec3& p) {
    if (!finite(p)) return false;
    if (mPositions > 0) {
        Stamped& newest = mPosition[mPositions - 1];
        if (timeNs < newest.timeNs) return false;
        if (timeNs == newest.timeNs) {
            newest.position = p;
            return true;
        }
    }
    if (mPositions == 2) mPosition[0] = mPosition[1];
    mPositions = std::min(mPositions + 1, 2);
    mPosition[mPositions - 1] = Stamped{timeNs, p};
    return true;
}

std::optional<glm::dmat4> HeadPoseTracker::worldFromHeadAt(int64_t timeNs) const {
    if (!mHaveOrientation || mPositions == 0) return std::nullopt;
    const double maxS = double(mMaxExtrapolationNs) * 1e-9;

    const double dtOrientation = secondsBetween(timeNs, mOrientationTimeNs);
    if (std::abs(dtOrientation) > maxS) return std::nullopt;
    // Body-frame rotation by the latest rate: exact for a constant angular velocity.
    const glm::dquat q = mOrientation * rotationVector(mAngularVelocity * dtOrientation);

    glm::dvec3 p = mPosition[mPositions - 1].position;
    if (mPositions == 1) {
        if (std::abs(secondsBetween(timeNs, mPosition[0].timeNs)) > maxS) return std::nullopt;
    } else {
        const Stamped &a = mPosition[0], &b = mPosition[1];
        const double fromA = secondsBetween(timeNs, a.timeNs);
        const double fromB = secondsBetween(timeNs, b.timeNs);
        if (fromB > maxS || -fromA > maxS) return std::nullopt;  // too far ahead or behind
        const double span = secondsBetween(b.timeNs, a.timeNs);  // > 0 by construction
        p = a.position + (b.position - a.position) * (fromA / span);
    }
    return combineHeadPose(q, p, mCalibration);
}

}  // namespace vsculpt::devices
