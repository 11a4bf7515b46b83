// SPDX-License-Identifier: MIT
/// @file DeviceCommands.h
/// @brief `vsculpt devices` (what is connected and usable) and `vsculpt record` (sculpt with
/// the connected devices headless while writing every raw report to a recording that
/// `vsculpt play FILE` replays to the same sculpture).
#pragma once

#include "vsculpt/app/Log.h"

#include <iosfwd>
#include <string>

namespace vsculpt::app {

/// Lists connected USB and hidraw devices, which the config's rules match and whether
/// vsculpt can open them; says plainly when nothing usable is there. Exit code 0, or 2 for a
/// bad config.
int runDevices(const std::string& configPath, std::ostream& out, std::ostream& err,
               Verbosity verbosity = Verbosity::Normal);

struct RecordOptions {
    std::string outPath;          ///< the recording (.vsrec)
    std::string configPath;       ///< "" = configs/sculpt.json
    double seconds = 0;           ///< stop after this long (0: on Ctrl-C only)
    bool untilUnplugged = false;  ///< stop once every device that arrived has left again
    bool alwaysEngaged = true;    ///< the thesis: the tool acts whenever it moves
    Verbosity verbosity = Verbosity::Normal;  ///< --quiet / --verbose (Log.h)
};

/// Exit code 0, 1 on a write failure, 2 on bad input (config, output path).
int runRecord(const RecordOptions& options, std::ostream& out, std::ostream& err);

}  // namespace vsculpt::app
