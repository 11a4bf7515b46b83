// SPDX-License-Identifier: MIT
/// @file Summary.h
/// @brief The headless main job until the window exists: a report on the initial sculpture.
#pragma once

#include <iosfwd>

namespace vsculpt::core {
class Sculpture;
}

namespace vsculpt::app {

/// Writes the tool-level table, the calibration quality and the initial sculpture's state.
void printSummary(const core::Sculpture& sculpture, std::ostream& out);

}  // namespace vsculpt::app
