// SPDX-License-Identifier: MIT
/// @file DeviceInput.h
/// @brief Device events -> sculpting: decodes each event with its device's driver and maps
/// it the thesis's way (docs/devices.md):
///   - tracker pen station -> the tool position (worldFromTracker * trackerFromPen * tip);
///     the stylus switch, when the tracker reports one, engages the tool;
///   - 3D mouse axes -> the object pose (rate control), right button -> cycle tool type,
///     left button -> size step, or zoom step with the select tool;
///   - headset IMU (fused) + tracker head station -> the head pose for the stereo eyes.
/// Live runs and replays go through the same handle(), which depends only on the events
/// (their order, bytes and timestamps), never on the wall clock: a recording replays to the
/// same sculpture.
///
/// Faults never throw out of handle(): undecodable reports, samples the lattices cannot
/// hold, out-of-order tracker or IMU data are counted and dropped. A device that leaves or
/// stalls ends the stroke in progress (the session keeps everything before it) and stops
/// object motion.
#pragma once

#include "vsculpt/core/Config.h"
#include "vsculpt/devices/DeviceEvent.h"
#include "vsculpt/devices/DeviceRule.h"
#include "vsculpt/devices/PenSample.h"
#include "vsculpt/studio/Interaction.h"
#include "vsculpt/studio/Studio.h"

#include <glm/mat4x4.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace vsculpt::app {

/// The device rules of a config: its "devices.match" list, or the built-in table.
std::vector<devices::DeviceRule> deviceRules(const core::DevicesConfig& cfg);

/// No tracker and no room-scale headset reaches farther from its origin (a Polhemus field a
/// few metres, a room): a pose beyond is a glitch, dropped. A stroke to it would sweep the tool
/// across kilometres of lattice (seconds and gigabytes, found by fuzzing recordings).
inline constexpr double kTrackerReachMm = 10'000;

struct DeviceCounters {
    uint64_t reports = 0;        ///< report events seen
    uint64_t samples = 0;        ///< decoded samples used
    uint64_t decodeErrors = 0;   ///< reports no decoder accepted
    uint64_t droppedBytes = 0;   ///< stream bytes skipped while resynchronising (trackers)
    uint64_t outOfOrder = 0;     ///< samples older than the previous one, dropped
    uint64_t rejectedEdits = 0;  ///< tool samples the sculpture could not take
    uint64_t outOfReach = 0;     ///< poses beyond kTrackerReachMm from the tracker, dropped
    uint64_t jumps = 0;          ///< pen samples that jumped faster than a hand and back, dropped
    uint64_t arrivals = 0, departures = 0, stalls = 0;
};

/// Bytes a live run must send to a device (start-up commands, keep-alives).
struct DeviceOutput {
    std::string device;
    std::vector<uint8_t> bytes;
    bool feature = false;  ///< a HID feature report rather than OUT data
};

class DeviceInput {
  public:
    /// `interaction` and `session` must outlive this object.
    /// `xr` maps recorded OpenXR controllers (driver "openxr", XrInput.h).
    DeviceInput(const core::DevicesConfig& cfg, std::vector<devices::DeviceRule> rules,
                studio::Interaction& interaction, studio::Studio& studio,
                const core::XrConfig& xr = {});
    ~DeviceInput();

    void handle(const devices::DeviceEvent& event);

    /// What to send now; empties the list. Replays ignore it.
    std::vector<DeviceOutput> takeOutput();
    /// Pen-tablet samples decoded since the last call, oldest first (the sketch canvas's
    /// input; Wacom tablets in Wacom mode).
    std::vector<devices::PenSample> takePenSamples();

    /// The tool tip in world space, mm, as the pen last put it.
    std::optional<core::Vec3> toolWorld() const;
    /// worldFromHead (rigid, mm) at host time `timeNs`, when a headset and the head station
    /// have both reported recently.
    std::optional<glm::dmat4> worldFromHead(int64_t timeNs) const;
    /// The "recenter" action of the head-tracked view: the headset's IMU knows up but not
    /// which way the room faces, so its heading (the calibration's worldFromFusion, a turn about
    /// world z) is set so that the head, as it is at host time `timeNs`, looks toward
    /// `worldTargetMm` in plan. Returns the line for the status bar. Throws std::runtime_error,
    /// saying why, when there is no head pose yet or the head looks (or the target lies)
    /// straight up or down.
    std::string recenterHead(int64_t timeNs, const glm::dvec3& worldTargetMm);
    /// The windows' recenter action: recenterHead now, toward the centre of the box the view
    /// frames (object space; the object origin when empty).
    std::string recenterHeadOn(const core::Aabb& framedObjectBox,
                               const glm::dmat4& worldFromObject);

    const std::map<std::string, DeviceCounters>& counters() const { return mCounters; }
    /// One line per device: "name: N reports, M samples, ..." for logs and `play` output.
    std::string summary() const;

    struct State;

  private:
    std::unique_ptr<State> mState;
    std::map<std::string, DeviceCounters> mCounters;
};

}  // namespace vsculpt::app
