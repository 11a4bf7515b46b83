// SPDX-License-Identifier: MIT
/// @file ExportDetail.h
/// @brief The grid spacing a whole-sculpture export needs to keep the sculpture's finest
/// detail, and whether a given spacing loses it, said in words for the user (play's warning,
/// the window's status line).
#pragma once

#include <string>

namespace vsculpt::studio {
class Session;
}

namespace vsculpt::app {

/// The finest detail of a session and the spacing that keeps it. The finest detail is the
/// smallest tool size among the strokes that built the sculpture (a sketched solid's: its
/// finest skeleton level), drawn from the coarsest zoom that offers that size.
struct ExportDetail {
    int finestSize = 0;    ///< 0: nothing finer than the initial sphere was made
    int zoom = 0;          ///< the coarsest zoom that offers finestSize
    double detailMm = 0;   ///< that zoom's grid spacing
    double keepingMm = 0;  ///< detailMm, or the finest the whole-sculpture grid allows
    bool capped = false;   ///< keepingMm is the grid's limit, coarser than detailMm
};
/// @param zoom1Mm the zoom-1 spacing: keepingMm when nothing finer was made.
ExportDetail exportDetail(const studio::Session& session, double zoom1Mm);

/// The finest spacing at which Session::wholeMesh can mesh the whole sculpture (its grid holds
/// kWholeMeshMaxCells per axis, a few of them margin), rounded up to three significant digits;
/// 0 for an empty sculpture.
double wholeMeshFinestSpacing(const studio::Session& session);

/// The spacing a whole-sculpture mesh takes when `spacingMm` is asked for: that spacing when
/// the grid holds the sculpture at it. Otherwise a spacing the user gave with `option` is
/// refused (studio::SessionError naming the option and the value that works, or that none up
/// to `maxMm` does), and a default one (`option` empty) becomes the finest the grid allows, a
/// sentence saying so left in `warning`.
double wholeMeshSpacing(const studio::Session& session, double spacingMm, const std::string& option,
                        double maxMm, std::string& warning);

/// When an export at `spacingMm` cannot hold the session's finest detail: a sentence saying so
/// and which --export-spacing would keep it; empty otherwise. The suggestion is
/// exportDetail's keepingMm rounded to three digits (down to keep the detail, up to fit the
/// grid's 1 024 cells per axis). `what` and `option` name the mesh and its option for other
/// commands (`vsculpt render`: "the still's mesh spacing", "--spacing").
std::string exportDetailWarning(const studio::Session& session, double spacingMm,
                                const std::string& what = "the export's grid spacing",
                                const std::string& option = "--export-spacing");

}  // namespace vsculpt::app
