// SPDX-License-Identifier: MIT
/// @file OrientationFusion.h
/// @brief Head orientation from a 6-axis IMU: a Mahony-style complementary filter. The gyro
/// is integrated with quaternions; the accelerometer, when it reads about 1 g, pulls the
/// estimated "up" towards the measured one with a proportional gain, and optionally an
/// integral gain learns the gyro bias. Deterministic: the same samples give the same bits.
///
/// Frames. The filter estimates `fusionFromImu`, the rotation taking IMU-frame vectors to
/// the fusion frame. The fusion frame has +z up (the vsculpt world's up, opposite to gravity)
/// and an arbitrary heading: without a magnetometer (unusable next to a Polhemus transmitter)
/// yaw is unobservable and drifts with the gyro's yaw bias. At initialisation the heading is
/// the one the shortest rotation from the measured up to +z gives, which for an upright Rift
/// (IMU y up, looking down -z) makes the gaze +y. HeadPose.h aligns the heading with the world.
///
/// One update, for a sample at time t_k after one at t_{k-1} (dt = t_k - t_{k-1}):
///   w = (gyro_k + gyro_{k-1}) / 2 - bias             trapezoid rule, second order in dt
///   q = q * exp(w dt / 2)                            gyro step (q = fusionFromImu)
///   if | |a_k| - g | <= accelToleranceMps2:
///       e = (a_k / |a_k|) x (q^-1 * up)              tilt error, IMU frame, |e| = sin(angle)
///       q = q * exp(gravityGain * e dt / 2)          correction, after the gyro step so that
///                                                    both refer to t_k
///       bias -= biasGain * e * dt                    (clamped to maxBiasRadps)
///   q is renormalised after each rotation.
/// The tilt error relaxes with the time constant 1 / gravityGain; an uncorrected tilt bias b
/// (biasGain = 0) leaves a steady tilt error of about |b| / gravityGain rad.
#pragma once

#include "vsculpt/devices/ImuSample.h"

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include <cstdint>

namespace vsculpt::devices {

struct FusionParams {
    /// Proportional gain of the gravity correction, 1/s (rad/s per unit of sin(tilt error)).
    /// 0 turns the correction off (pure gyro integration).
    double gravityGain = 0.5;
    /// Integral gain of the gyro-bias estimate, 1/s^2. 0 turns bias estimation off. Only the
    /// tilt components of the bias are observable; the yaw (up-axis) component is not learnt.
    /// The default, gravityGain^2 / 4, makes the tilt-error dynamics critically damped (both
    /// poles at gravityGain / 2 = 0.25/s, a 4 s time constant).
    double biasGain = 0.0625;
    double maxBiasRadps = 0.2;  ///< clamp on each component of the bias estimate, rad/s
    /// The accelerometer corrects only when its magnitude is within this of standardGravity,
    /// m/s^2, so that head accelerations are not mistaken for a tilt.
    double accelToleranceMps2 = 1.0;
    double standardGravityMps2 = 9.80665;
    /// Longest interval integrated in one step, s: after a longer gap (lost reports) the
    /// sample's rate is integrated over this much only, and the trapezoid rule is skipped.
    double maxStepS = 0.05;
    /// Snap the tilt to the accelerometer at the first sample that reads about 1 g, instead of
    /// letting the gravity gain converge from the identity.
    bool initialiseFromAccel = true;
};

/// What update() did with a sample.
enum class FusionStep {
    Integrated,   ///< gyro integrated, no accelerometer correction (not about 1 g)
    Corrected,    ///< gyro integrated with the gravity correction (and bias learning)
    Initialised,  ///< first usable sample: the tilt was set from the accelerometer
    Rejected,     ///< not used: non-finite value, or time not after the previous sample
};

struct FusionStats {
    uint64_t integrated = 0, corrected = 0, rejected = 0, clampedSteps = 0;
};

class OrientationFusion {
  public:
    /// Throws std::invalid_argument, naming the field, if a parameter is negative or not
    /// finite, or standardGravityMps2 / maxStepS is not positive.
    explicit OrientationFusion(const FusionParams& params = {});

    /// Feeds one sample (uses deviceTimeNs, accelMps2, gyroRadps); samples must come in time
    /// order. Never throws.
    FusionStep update(const ImuSample& sample);

    /// Restarts from a known orientation at time `timeNs` (e.g. from a reference pose in a
    /// test or after recentring); keeps the bias estimate. Throws std::invalid_argument if the
    /// quaternion is zero or not finite.
    void reset(const glm::dquat& fusionFromImu, int64_t timeNs);
    /// Forgets everything, including the bias estimate.
    void reset();

    /// The estimate, unit length. Identity before the first sample.
    glm::dquat fusionFromImu() const { return mQ; }
    /// The fusion frame's up (+z) seen in the IMU frame: the gravity direction reversed.
    glm::dvec3 upInImu() const;
    glm::dvec3 gyroBias() const { return mBias; }
    /// The last bias-corrected angular velocity, IMU frame, rad/s (for prediction).
    glm::dvec3 angularVelocityRadps() const { return mOmega; }
    int64_t timeNs() const { return mTimeNs; }
    bool hasSamples() const { return mHaveSample; }
    const FusionStats& stats() const { return mStats; }
    const FusionParams& params() const { return mParams; }

  private:
    FusionParams mParams;
    glm::dquat mQ{1.0, 0.0, 0.0, 0.0};
    glm::dvec3 mBias{0.0}, mOmega{0.0}, mLastGyro{0.0};
    int64_t mTimeNs = 0;
    bool mHaveSample = false, mHaveGyro = false, mTiltKnown = false;
    FusionStats mStats;
};

/// The shortest rotation taking unit direction `from` onto unit direction `to` (a half turn
/// about an axis perpendicular to both when they are opposite).
glm::dquat shortestArc(const glm::dvec3& from, const glm::dvec3& to);

/// The rotation angle between two orientations, rad, in [0, pi] (q and -q are the same).
double angleBetween(const glm::dquat& a, const glm::dquat& b);

}  // namespace vsculpt::devices
