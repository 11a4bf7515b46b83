// SPDX-License-Identifier: MIT
/// @file ExportDetail.h
/// @brief Whether a whole-sculpture export at a given grid spacing loses the sculpture's finest
/// detail, said in words for the user (play's warning, the window's status line).
#pragma once

#include <string>

namespace vsculpt::studio {
class Session;
}

namespace vsculpt::app {

/// When an export at `spacingMm` cannot hold the session's finest detail: a sentence saying so
/// and which --export-spacing would keep it; empty otherwise. The finest detail is the
/// smallest tool size among the strokes that built the sculpture (a sketched solid's: its
/// finest skeleton level), drawn from the coarsest zoom that offers that size; the suggestion
/// is that zoom's spacing, or the finest the whole-sculpture grid allows (1 024 cells per axis).
std::string exportDetailWarning(const studio::Session& session, double spacingMm);

}  // namespace vsculpt::app
