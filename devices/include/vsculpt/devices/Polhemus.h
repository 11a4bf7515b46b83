// SPDX-License-Identifier: MIT
/// @file Polhemus.h
/// @brief Polhemus magnetic trackers (FASTRAK, Liberty, Liberty HS/Latus, Patriot): the model
/// table by USB id, the start-up commands as bytes, and a stream decoder (incremental framer +
/// record decoder) for their binary P&O records. No USB here: the transport writes the
/// commands to the bulk OUT endpoint and feeds whatever the IN endpoint returns.
///
/// Facts: devices_report.md §1 (VRPN, Polhemus' Tracker Terminal, the shadow/ipab ROS drivers,
/// libpolhemus). Record layouts:
///  - Liberty/Patriot/Latus: 8-byte header {tag "LY"/"PA"/"LU", station (1-based, binary),
///    command ('C' continuous, 'P' single), error byte, reserved, uint16 LE payload length},
///    then the output-list items in the order requested, floats IEEE-754 LE.
///  - FASTRAK: {'0', station as ASCII '1'..'4', status (' ' or a letter)}, then the items.
#pragma once

#include "vsculpt/devices/DecodeStatus.h"
#include "vsculpt/devices/TrackerSample.h"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace vsculpt::devices {

enum class PolhemusFamily { Fastrak, Liberty, Patriot, G4, Viper };

struct PolhemusModel {
    uint16_t vendor = 0, product = 0;
    const char* name = "";
    PolhemusFamily family = PolhemusFamily::Liberty;
    /// The pre-firmware id: the device needs its firmware loaded (fxload) first and then
    /// re-enumerates with the operational id. Nothing can be decoded from it.
    bool needsFirmware = false;
    bool highSpeed = false;  ///< Liberty HS / Latus / Patriot HS: send "@B0" (no USB buffering)
    uint8_t writeEndpoint = 0, readEndpoint = 0;  ///< 0 = find from the descriptors
    int maxStations = 0;
    /// Our decoder speaks this model's binary records (FASTRAK, Liberty, Patriot families).
    bool supported = false;
};

/// Known models by USB vendor/product id; nullopt for anything else.
std::optional<PolhemusModel> findPolhemusModel(uint16_t vendor, uint16_t product);

enum class PolhemusUnits { Inches, Centimetres };

/// Output-list items (the device's numbers differ between families; see the .cpp).
enum class PolhemusItem {
    Space,         ///< one ' ' byte: lets the framer check alignment; ask for it last
    CrLf,          ///< "\r\n"
    Position,      ///< x, y, z: 3 x float32
    Euler,         ///< azimuth, elevation, roll in degrees: 3 x float32
    Quaternion,    ///< w, x, y, z: 4 x float32
    Timestamp,     ///< Liberty/Patriot: uint32 ms
    FrameCount,    ///< Liberty/Patriot: uint32
    StylusButton,  ///< Liberty/Patriot: uint32 flag; FASTRAK: 2 bytes, the second '0'/'1'
    Distortion,    ///< Liberty: int32 level
};

/// The default output list: Liberty/Patriot position, quaternion, timestamp, frame count,
/// space (VRPN's "O*,2,7,8,9,0", 45-byte records); FASTRAK position, quaternion, stylus, space.
std::vector<PolhemusItem> polhemusDefaultItems(PolhemusFamily family);

struct PolhemusConfig {
    PolhemusFamily family = PolhemusFamily::Liberty;
    PolhemusUnits units = PolhemusUnits::Centimetres;
    std::vector<PolhemusItem> items = polhemusDefaultItems(PolhemusFamily::Liberty);
    int station = 0;         ///< 0 = all stations
    bool highSpeed = false;  ///< from PolhemusModel::highSpeed
    int maxStations = 16;
};

/// A sensible configuration for a model: its family, cm, the default item list (FASTRAK:
/// position, quaternion, stylus button, space).
PolhemusConfig defaultPolhemusConfig(const PolhemusModel& model);

/// The commands that bring the tracker from power-on to continuous binary output, in order,
/// each complete with its terminator: stop output, binary format, units, output list, (HS:
/// unbuffered USB), continuous. The transport drains the IN endpoint after the first one.
/// @throw std::invalid_argument if the family is not supported or an item has no number in it.
std::vector<std::vector<uint8_t>> polhemusStartupCommands(const PolhemusConfig& config);

/// The command that stops continuous output (send on shutdown).
std::vector<uint8_t> polhemusStopCommand(PolhemusFamily family);

/// Bytes of one P&O record for this configuration, header included.
size_t polhemusRecordBytes(const PolhemusConfig& config);

/// Decodes one complete record (exactly one record's bytes; extra bytes are ignored).
/// Truncated when shorter than the layout; UnknownReport for a Liberty reply to another
/// command (its header is valid, its command byte is not 'C'/'P'); Malformed for a bad tag,
/// station, length, trailing space, or non-finite values.
std::optional<TrackerSample> decodePolhemusRecord(std::span<const uint8_t> record,
                                                  const PolhemusConfig& config, int64_t timeNs,
                                                  DecodeStatus* status = nullptr);

/// Incremental framer: USB reads cut records anywhere and may hold several back to back.
/// Feed every read; complete records come out, garbage is skipped byte by byte until a record
/// decodes again (resync), and every skipped byte is counted.
class PolhemusStreamDecoder {
  public:
    explicit PolhemusStreamDecoder(PolhemusConfig config);

    /// Appends the bytes of one read and appends every record now complete to `out`, stamped
    /// with `timeNs` (the host time of this read). Returns how many samples were appended.
    size_t feed(std::span<const uint8_t> bytes, int64_t timeNs, std::vector<TrackerSample>& out);

    uint64_t droppedBytes() const { return mDropped; }  ///< skipped while resyncing
    uint64_t records() const { return mRecords; }       ///< decoded P&O records
    uint64_t otherReplies() const { return mReplies; }  ///< well-framed non-P&O records
    uint64_t otherReplyBytes() const { return mReplyBytes; }
    size_t pendingBytes() const { return mBuffer.size(); }
    void reset();  ///< forget buffered bytes (after a restart); counters stay

  private:
    PolhemusConfig mConfig;
    size_t mRecordBytes;
    std::vector<uint8_t> mBuffer;
    uint64_t mDropped = 0, mRecords = 0, mReplies = 0, mReplyBytes = 0;
};

}  // namespace vsculpt::devices
