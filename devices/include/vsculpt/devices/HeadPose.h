// SPDX-License-Identifier: MIT
/// @file HeadPose.h
/// @brief The head pose for the stereo renderer: orientation from the headset IMU's fusion
/// (OrientationFusion.h), position from a tracker sensor worn on the head (a Polhemus station,
/// mm), and the two eye poses for an IPD.
///
/// Frames (all right-handed, millimetres):
/// - world: the vsculpt world, z up;
/// - tracker: the tracker's source frame, placed in the world by `worldFromTracker`;
/// - fusion: the orientation filter's frame, z up with its own heading, placed in the world
///   by `worldFromFusion` (a rotation, normally about z only: see recenterHeading());
/// - head: origin between the eyes, x right, y up, looking down -z (the renderer's head frame,
///   render/StereoCamera.h);
/// - IMU: the headset's IMU frame, placed in the head by `headFromImu` (identity for a Rift
///   reporting in its HMD frame);
/// - eye: the head frame moved to one eye's centre, -ipd/2 (left) or +ipd/2 (right) along
///   head x; same axes as the head.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>

namespace vsculpt::devices {

struct HeadCalibration {
    glm::dquat headFromImu{1.0, 0.0, 0.0, 0.0};
    /// The tracker sensor's origin in the head frame, mm: the translation of
    /// headFromTrackerSensor (the sensor's own orientation is not used; the IMU gives it).
    glm::dvec3 sensorInHeadMm{0.0};
    glm::dquat worldFromFusion{1.0, 0.0, 0.0, 0.0};
    glm::dmat4 worldFromTracker{1.0};  ///< rigid, mm
};

/// worldFromHead (rigid, mm) from the fused orientation and the sensor position measured in
/// the tracker frame: the head is turned as the IMU says and placed so that its sensor point
/// lands on the measured position. Throws std::invalid_argument, naming the input, on a
/// non-finite value or a zero quaternion.
glm::dmat4 combineHeadPose(const glm::dquat& fusionFromImu, const glm::dvec3& sensorInTrackerMm,
                           const HeadCalibration& calibration);

struct EyePoses {
    glm::dmat4 worldFromLeftEye{1.0}, worldFromRightEye{1.0};
};

/// The eye frames for an interpupillary distance in mm: the head frame translated by
/// -ipdMm/2 and +ipdMm/2 along head x. Throws std::invalid_argument if ipdMm is negative or
/// not finite.
EyePoses eyePoses(const glm::dmat4& worldFromHead, double ipdMm);

/// The worldFromFusion heading (a rotation about world z) that makes the head, at the given
/// fused orientation, look along `worldDirection` once both are projected on the horizontal
/// plane: the "recentre" action. Throws std::invalid_argument if the gaze or the direction is
/// within about 0.5 degrees of vertical, or not finite.
glm::dquat recenterHeading(const glm::dquat& fusionFromImu, const glm::dquat& headFromImu,
                           const glm::dvec3& worldDirection);

/// Lines up the IMU orientation (about 1 kHz) and the tracker position (about 100-250 Hz),
/// each stamped on the host's monotonic clock, and answers worldFromHead at any nearby time:
/// the orientation is turned on from its latest sample by the latest angular velocity, the
/// position is interpolated between the two latest tracker samples, or extrapolated from them
/// at constant velocity. Holds only the latest samples: not thread-safe, one owner.
class HeadPoseTracker {
  public:
    /// `maxExtrapolationS`: how far past (or before) its latest sample each input may be
    /// carried, s. Throws std::invalid_argument if not finite and >= 0.
    explicit HeadPoseTracker(const HeadCalibration& calibration, double maxExtrapolationS = 0.05);

    /// The fused orientation at host time `timeNs`, with the bias-corrected angular velocity
    /// in the IMU frame (OrientationFusion::angularVelocityRadps()). Older than the latest:
    /// ignored. Non-finite input: ignored (returns false).
    bool addOrientation(int64_t timeNs, const glm::dquat& fusionFromImu,
                        const glm::dvec3& angularVelocityRadps);
    /// The tracker sensor's position in the tracker frame at host time `timeNs`, mm. Same
    /// rules as addOrientation().
    bool addTrackerPosition(int64_t timeNs, const glm::dvec3& sensorInTrackerMm);

    /// worldFromHead at host time `timeNs`; nullopt until both inputs have a sample, or when
    /// either would be carried further than maxExtrapolationS. Throws std::invalid_argument
    /// like combineHeadPose() if the calibration was set to non-finite values.
    std::optional<glm::dmat4> worldFromHeadAt(int64_t timeNs) const;

    /// The latest fused orientation (fusionFromImu), as given; nullopt before the first.
    std::optional<glm::dquat> latestOrientation() const {
        return mHaveOrientation ? std::optional<glm::dquat>(mOrientation) : std::nullopt;
    }

    HeadCalibration& calibration() { return mCalibration; }
    const HeadCalibration& calibration() const { return mCalibration; }

  private:
    struct Stamped {
        int64_t timeNs = 0;
        glm::dvec3 position{0.0};
    };
    HeadCalibration mCalibration;
    int64_t mMaxExtrapolationNs = 0;
    bool mHaveOrientation = false;
    int64_t mOrientationTimeNs = 0;
    glm::dquat mOrientation{1.0, 0.0, 0.0, 0.0};
    glm::dvec3 mAngularVelocity{0.0};
    int mPositions = 0;  // 0, 1 or 2 valid entries in mPosition, newest last
    Stamped mPosition[2];
};

}  // namespace vsculpt::devices
