// Logarithmic distribution graphs of curvature (CLDG, Harada) and torsion (TLDG, Inoue et al.)
// and their least-squares slopes α and β (paper 002, §1). Units: mm, natural logarithms of mm.
//
// Construction: the radius r (ρ = 1/|κ| or μ = 1/|τ|) is taken as varying linearly in ln r
// between consecutive samples; [ln r_min, ln r_max] is split into `bins` bins of equal width
// Δ, and each segment's arc length is shared among the bins its ln r range overlaps (pro rata).
// A bin's value is y = ln(length in bin / Δ), the discrete form of ln(r·|ds/dr|), so that a
// log-aesthetic curve (r^α = c0·s + c1, or ln r = c0·s + c1 for α = 0) plots as the straight
// line y = α·ln r + c whatever the bin count. The slope is fitted by unweighted least squares
// over the non-empty bins. The graph is meant for one segment with monotone curvature (or
// torsion); on other curves the bins mix the pieces, as in the original histogram.
#pragma once

#include "vsculpt/sketch/Polyline.h"

#include <vector>

namespace vsculpt::sketch {

struct LogDistributionGraph {
    std::vector<double> logRadius;   // bin centres, ln(mm)
    std::vector<double> logDensity;  // ln(bin length / bin width), ln(mm)
    std::vector<double> binLength;   // arc length in each bin, mm (empty bins kept, as 0)
    double slope = 0.0;              // α (curvature) or β (torsion)
    double intercept = 0.0;
    double rSquared = 0.0;  // of the line fit; 1 for an exact log-aesthetic curve
};

struct LogGraphOptions {
    int bins = 20;
    // Drops the first and last bin from the line fit: they hold the curve ends, where curvature
    // estimates of sampled curves are least accurate.
    bool dropEndBins = true;
    // A radius range ln(r_max / r_min) below this counts as constant (a circle or helix, whose
    // estimated radius only wobbles by discretisation error): the graph is refused.
    double minLogRange = 0.01;
};

// Graph of radius values r[i] (> 0; ∞, 0 or NaN mark samples where the radius is undefined,
// whose segments are left out) at increasing arc lengths s[i]. Throws std::invalid_argument when
// the sizes differ, fewer than 3 samples are given, s is not increasing, the radius is constant
// within minLogRange (the graph degenerates: α = ±∞, a circle or helix) or fewer than 3 bins
// remain for the fit.
LogDistributionGraph logDistributionGraph(const std::vector<double>& arcLength,
                                          const std::vector<double>& radius,
                                          const LogGraphOptions& options = {});

// CLDG of a sampled curve, curvature estimated with curveDifferential(line, halfWindow).
LogDistributionGraph curvatureGraph(const Polyline2& line, const LogGraphOptions& options = {},
                                    int halfWindow = 2);
LogDistributionGraph curvatureGraph(const Polyline3& line, const LogGraphOptions& options = {},
                                    int halfWindow = 2);
// TLDG of a sampled space curve (radius of torsion μ = 1/|τ|).
LogDistributionGraph torsionGraph(const Polyline3& line, const LogGraphOptions& options = {},
                                  int halfWindow = 2);

}  // namespace vsculpt::sketch
