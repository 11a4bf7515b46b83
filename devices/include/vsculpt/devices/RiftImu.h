// SPDX-License-Identifier: MIT
/// @file RiftImu.h
/// @brief Oculus Rift DK1 / DK2 / CV1 head IMU: USB identities, the feature reports the host
/// must send (sensor config, keep-alive, CV1 component enable), the pure tracker-report decoder
/// and a small stateful stream that turns reports into timestamped ImuSamples (timestamp
/// unwrap, out-of-order rejection, dropped-sample counting). No USB here: the transport reads
/// the HID interface (hidraw) and hands each input report, report id first, to
/// RiftImuStream::push(); it sends the feature-report bytes built here with HIDIOCSFEATURE.
///
/// Report layouts (devices_report.md §4.1, all little-endian):
/// - DK1 tracker report, id 1, 62 bytes: [1] sample count, [2..3] timestamp u16 in ms,
///   [4..5] last command id, [6..7] temperature i16 in 0.01 degC, [8..55] three samples of
///   accel (8 bytes) + gyro (8 bytes), [56..61] magnetometer 3 x i16.
/// - DK2/CV1 tracker report, id 11, 64 bytes: [1..2] last command id, [3] sample count,
///   [4..5] total sample count u16 (before this report), [6..7] temperature, [8..11] timestamp
///   u32 in us, [12..43] two samples, [44..49] magnetometer, [50..63] camera-sync fields.
/// - Each 8-byte vector packs three signed 21-bit values MSB first:
///   x = b0<<13 | b1<<5 | b2>>3, y = (b2&7)<<18 | b3<<10 | b4<<2 | b5>>6,
///   z = (b5&0x3f)<<15 | b6<<7 | b7>>1, sign-extended from bit 20.
/// - Scales: accel 1e-4 m/s^2, gyro 1e-4 rad/s, magnetometer 1e-4 gauss per count.
#pragma once

#include "vsculpt/devices/DecodeStatus.h"
#include "vsculpt/devices/ImuSample.h"

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace vsculpt::devices {

// ---- USB identity -------------------------------------------------------------------------

enum class RiftModel { Dk1, Dk2, Cv1 };

struct RiftIdentity {
    uint16_t vendor = 0, product = 0;
    RiftModel model = RiftModel::Dk1;
    const char* name = "";
    int imuInterface = 0;  ///< HID interface that carries the tracker reports
};

inline constexpr uint16_t kOculusVendorId = 0x2833;

/// The known Rift headsets by USB vendor and product id (DK1 0x0001, DK2 0x0021 and 0x2021,
/// CV1 0x0031 whose interface 1 is the Touch radio, not the IMU); nullopt for anything else.
std::optional<RiftIdentity> findRiftModel(uint16_t vendor, uint16_t product);

// ---- Feature reports to send ----------------------------------------------------------------

/// Sensor-config flags (feature report 0x02).
enum RiftConfigFlags : uint8_t {
    kRiftConfigRawMode = 0x01,
    kRiftConfigUseCalibration = 0x04,
    kRiftConfigAutoCalibration = 0x08,
    kRiftConfigMotionKeepAlive = 0x10,
    kRiftConfigCommandKeepAlive = 0x20,
    kRiftConfigSensorCoordinates = 0x40,  ///< report in the sensor chip's frame, not the HMD's
};

/// Sensor config, 7 bytes: 0x02, command id u16, flags u8, packet interval u8 (0 = every
/// sample), keep-alive interval u16 in ms. The default flags (calibrated, auto-calibrating,
/// HMD frame) are what OpenHMD sends and give the IMU frame documented in ImuSample.h.
std::array<uint8_t, 7> buildRiftSensorConfig(uint16_t commandId,
                                             uint8_t flags = kRiftConfigUseCalibration |
                                                             kRiftConfigAutoCalibration,
                                             uint8_t packetInterval = 0,
                                             uint16_t keepAliveMs = 10000);

/// DK1 keep-alive, 5 bytes: 0x08, command id u16, interval u16 in ms. The headset stops
/// streaming when the interval passes without a new keep-alive; resend every
/// riftKeepAliveResendNs(intervalMs).
std::array<uint8_t, 5> buildRiftDk1KeepAlive(uint16_t commandId, uint16_t intervalMs = 10000);

/// DK2/CV1 keep-alive, 6 bytes: 0x11, command id u16, flags u8 (0x0b with the tracking LEDs
/// on, 0x01 without), interval u16 in ms.
std::array<uint8_t, 6> buildRiftDk2KeepAlive(uint16_t commandId, bool leds,
                                             uint16_t intervalMs = 10000);

/// CV1 "enable components", 4 bytes: 0x1d, command id u16, flags (1 display, 2 audio,
/// 4 LEDs). The CV1 panels stay dark until the display bit is sent.
std::array<uint8_t, 4> buildRiftCv1EnableComponents(uint16_t commandId, bool display, bool audio,
                                                    bool leds);

/// How often to resend a keep-alive of the given interval: 200 ms before it runs out (at
/// least 1 ms), in ns.
int64_t riftKeepAliveResendNs(uint16_t intervalMs);

// ---- Pure decoder -----------------------------------------------------------------------------

enum class RiftReportFormat { Dk1, Dk2 };  ///< id 1 (DK1) or id 11 (DK2 and CV1)

inline constexpr uint8_t kRiftDk1TrackerReportId = 1;
inline constexpr uint8_t kRiftDk2TrackerReportId = 11;
inline constexpr size_t kRiftDk1TrackerReportSize = 62;
inline constexpr size_t kRiftDk2TrackerReportSize = 64;

/// The raw content of one tracker report. Counts, not physical units: see the scales above.
struct RiftTrackerReport {
    RiftReportFormat format = RiftReportFormat::Dk1;
    uint16_t lastCommandId = 0;
    /// Samples the device says it took since its previous report; on the DK1 it can exceed
    /// the three slots (the host was late and older samples were lost).
    uint8_t numSamples = 0;
    int samplesInReport = 0;  ///< valid slots: min(numSamples, 3 on DK1 / 2 on DK2)
    /// Device timestamp of the newest sample: ms, 16 bits (DK1) or us, 32 bits (DK2).
    uint32_t timestamp = 0;
    uint16_t totalSampleCount = 0;  ///< DK2: samples taken before this report (wraps)
    int16_t temperature = 0;        ///< 0.01 degC
    std::array<std::array<int32_t, 3>, 3> accel{}, gyro{};  ///< oldest first, 21-bit values
    std::array<int16_t, 3> magnetometer{};
    // DK2/CV1 camera-sync fields, zero on the DK1.
    uint16_t frameCount = 0;
    uint32_t frameTimestampUs = 0;
    uint8_t frameId = 0, ledPatternPhase = 0;
    uint16_t exposureCount = 0;
    uint32_t exposureTimestampUs = 0;
};

/// Unpacks one 8-byte vector into three sign-extended 21-bit values (x, y, z).
std::array<int32_t, 3> unpackRift21(std::span<const uint8_t, 8> bytes);

/// Decodes one tracker input report (byte 0 = report id). Never reads past the span and never
/// throws: an empty span gives Empty, an unknown id UnknownReport, a short report Truncated
/// (all three: nullopt). Bytes past the documented length are ignored.
std::optional<RiftTrackerReport> decodeRiftTrackerReport(std::span<const uint8_t> report,
                                                         DecodeStatus* status = nullptr);

/// The report's samples in physical units, oldest first, with deviceTimeNs/hostTimeNs left 0
/// (the stream fills them in). Returns how many of `out` were written.
int riftSamplesToSi(const RiftTrackerReport& report, std::array<ImuSample, 3>& out);

// ---- Stateful stream --------------------------------------------------------------------------

struct RiftStreamStats {
    uint64_t reports = 0;        ///< accepted reports
    uint64_t samples = 0;        ///< samples emitted
    uint64_t decodeErrors = 0;   ///< empty, truncated, unknown id
    uint64_t outOfOrder = 0;     ///< reports dropped because their timestamp went back or repeated
    uint64_t missedSamples = 0;  ///< samples the device took that never reached us
    uint64_t resyncs = 0;        ///< timeline restarts (device reset, long gap)
};

/// What push() did with one report.
struct RiftPushResult {
    DecodeStatus status = DecodeStatus::Ok;  ///< decode result; Ok for out-of-order reports too
    bool outOfOrder = false;                 ///< dropped: older than or equal to the last one
    int samples = 0;                         ///< samples appended to `out`
    int missedSamples = 0;                   ///< gap before this report's oldest sample
};

/// Turns consecutive tracker reports of one headset into ImuSamples on a 64-bit timeline.
/// The device timestamp wraps (DK1 every 65.5 s, DK2 every 71.6 min); the stream unwraps it
/// by taking the forward difference modulo the counter width, so a gap longer than half the
/// wrap period (32.8 s / 35.8 min) without a single report is misread. A report whose forward
/// difference is zero or in the backward half is out of order and dropped; after
/// kResyncAfter such reports in a row the stream assumes the device restarted its clock and
/// resynchronises on it (time keeps increasing by one sample period).
///
/// Timing within a report follows OpenHMD's reading: the report timestamp is the newest
/// sample's, older samples lie one nominal period (1 ms) apart before it, and are pushed later
/// when that would not come after the previous report's newest sample.
class RiftImuStream {
  public:
    static constexpr int kResyncAfter = 16;

    /// Decodes `report`, received at host monotonic time `hostTimeNs`, and appends its new
    /// samples to `out`, oldest first. Never throws on device bytes.
    RiftPushResult push(std::span<const uint8_t> report, int64_t hostTimeNs,
                        std::vector<ImuSample>& out);

    const RiftStreamStats& stats() const { return mStats; }
    /// Forgets the device clock (after reopening the device); keeps the statistics, and the
    /// next samples still come after the last ones on the deviceTimeNs timeline.
    void reset();

  private:
    bool mStarted = false;      // a timeline to unwrap against
    bool mEverStarted = false;  // any report accepted since construction
    RiftReportFormat mFormat = RiftReportFormat::Dk1;
    uint32_t mLastRaw = 0;
    int64_t mLastReportNs = 0;    // unwrapped timestamp of the last accepted report
    int64_t mLastSampleNs = 0;    // deviceTimeNs of the newest emitted sample
    uint16_t mExpectedTotal = 0;  // DK2: totalSampleCount the next report should carry
    int mBackwardRun = 0;
    RiftStreamStats mStats;
};

}  // namespace vsculpt::devices
