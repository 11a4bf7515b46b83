// SPDX-License-Identifier: MIT
/// @file Recording.h
/// @brief Device recordings: every DeviceEvent as the consumer saw it, in order, so that a
/// session seen with hardware can be replayed through the same decoders and mapping without
/// it (`vsculpt record`, `vsculpt play FILE.vsrec`; docs/devices.md).
///
/// Format (text, one item per line, '#' starts a comment line):
///   vsculpt-recording 1
///   meta <key> <value to end of line>              any number, before the first event
///   device <name> <driver> <access> <vendor> <product,product,...>   ids in hex
///   <timeNs> <device> <kind> [<hex bytes>]         kind: report arrived left stalled resumed
/// Events keep the order the live consumer drained them in; timestamps are the host's
/// monotonic clock and need not be increasing across devices.
#pragma once

#include "vsculpt/devices/DeviceEvent.h"
#include "vsculpt/devices/DeviceRule.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace vsculpt::devices {

/// A bad recording file: the message names the file and line.
class RecordingError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

struct Recording {
    std::map<std::string, std::string> meta;
    std::vector<DeviceRule> devices;
    std::vector<DeviceEvent> events;
    /// What was read past, for the user ("FILE:LINE: ..."): a last line cut short, as a
    /// recorder killed mid-write leaves it, is dropped rather than refusing the recording.
    std::vector<std::string> warnings;
};

/// Writes a recording as events come. The header goes out on construction; every write is
/// flushed by flush() (call it once per frame) so a crash loses at most one frame.
class RecordingWriter {
  public:
    /// Throws RecordingError when the file cannot be created. Meta values must be one line.
    RecordingWriter(const std::filesystem::path& path, const std::vector<DeviceRule>& devices,
                    const std::map<std::string, std::string>& meta);
    void write(const DeviceEvent& event);
    void flush();
    uint64_t eventsWritten() const { return mEvents; }

  private:
    std::filesystem::path mPath;
    std::ofstream mOut;
    uint64_t mEvents = 0;
};

/// Reads a whole recording; throws RecordingError("file:line: reason") on anything malformed:
/// a missing header, an unknown device or kind, odd hex, an unknown driver.
Recording readRecording(const std::filesystem::path& path);
/// Whether the file starts like a recording (its first line is the magic), so a command that
/// takes scripts or recordings can tell them apart; false when it cannot be read.
bool isRecordingFile(const std::filesystem::path& path);
/// The same from text (sourceName is used in messages).
Recording parseRecording(const std::string& text, const std::string& sourceName);

}  // namespace vsculpt::devices
