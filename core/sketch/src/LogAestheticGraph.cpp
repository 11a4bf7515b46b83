#include "vsculpt/sketch/LogAestheticGraph.h"

#include "vsculpt/sketch/CurveCurvature.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

LogDistributionGraph logDistributionGraph(const std::vector<double>& arcLength,
                                          const std::vector<double>& radius,
                                          const LogGraphOptions& options) {
    if (arcLength.size() != radius.size())
        throw std::invalid_argument("logDistributionGraph: arc length and radius sizes differ");
    if (arcLength.size() < 3)
        throw std::invalid_argument("logDistributionGraph: need at least 3 samples");
    if (options.bins < 3) throw std::invalid_argument("logDistributionGraph: need at least 3 bins");
    const std::size_t n = arcLength.size();
    for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(arcLength[i]))
            throw std::invalid_argument("logDistributionGraph: arc length " + std::to_string(i) +
                                        " is not finite");
        if (i > 0 && !(arcLength[i] > arcLength[i - 1]))
            throw std::invalid_argument("logDistributionGraph: arc length must increase");
    }
    std::vector<double> x(n, std::numeric_limits<double>::quiet_NaN());
    double lo = std::numeric_limits<double>::infinity();
    double hi = -lo;
    for (std::size_t i = 0; i < n; ++i) {
        if (radius[i] > 0.0 && std::isfinite(radius[i])) {
            x[i] = std::log(radius[i]);
            lo = std::min(lo, x[i]);
            hi = std::max(hi, x[i]);
        }
    }
    if (!(hi - lo > std::max(options.minLogRange, 1e-12)))
        throw std::invalid_argument(
            "logDistributionGraph: radius is constant or undefined; the graph degenerates "
            "(slope ±infinity, a circle or helix)");

    const int bins = options.bins;
    const double width = (hi - lo) / bins;
    LogDistributionGraph g;
    g.binLength.assign(std::size_t(bins), 0.0);
    auto binOf = [&](double v) { return std::clamp(int((v - lo) / width), 0, bins - 1); };
    for (std::size_t i = 0; i + 1 < n; ++i) {
        if (std::isnan(x[i]) || std::isnan(x[i + 1])) continue;
        const double ds = arcLength[i + 1] - arcLength[i];
        const double a = std::min(x[i], x[i + 1]);
        const double b = std::max(x[i], x[i + 1]);
        if (b - a <= 1e-15 * std::max(1.0, std::abs(a))) {
            g.binLength[std::size_t(binOf(a))] += ds;
            continue;
        }
        for (int k = binOf(a); k <= binOf(b); ++k) {
            const double overlap = std::min(b, lo + (k + 1) * width) - std::max(a, lo + k * width);
            if (overlap > 0.0) g.binLength[std::size_t(k)] += ds * overlap / (b - a);
        }
    }

    const int first = options.dropEndBins ? 1 : 0;
    const int last = options.dropEndBins ? bins - 2 : bins - 1;
    double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
    int count = 0;
    for (int k = 0; k < bins; ++k) {
        const double centre = lo + (k + 0.5) * width;
        const double len = g.binLength[std::size_t(k)];
        g.logRadius.push_back(centre);
        g.logDensity.push_back(len > 0.0 ? std::log(len / width)
                                         : -std::numeric_limits<double>::infinity());
        if (k < first || k > last || !(len > 0.0)) continue;
        const double y = g.logDensity.back();
        sx += centre;
        sy += y;
        sxx += centre * centre;
        sxy += centre * y;
        syy += y * y;
        ++count;
    }
    if (count < 3)
        throw std::invalid_argument("logDistributionGraph: fewer than 3 non-empty bins to fit");
    const double mx = sx / count, my = sy / count;
    const double vxx = sxx / count - mx * mx;
    const double vxy = sxy / count - mx * my;
    const double vyy = syy / count - my * my;
    g.slope = vxy / vxx;
    g.intercept = my - g.slope * mx;
    g.rSquared = vyy > 0.0 ? (vxy * vxy) / (vxx * vyy) : 1.0;
    return g;
}

namespace {
std::vector<double> radiusOf(const std::vector<double>& values) {
    std::vector<double> r(values.size());
    for (std::size_t i = 0; i < values.size(); ++i)
        r[i] =
            values[i] != 0.0 ? 1.0 / std::abs(values[i]) : std::numeric_limits<double>::infinity();
    return r;
}
}  // namespace

LogDistributionGraph curvatureGraph(const Polyline2& line, const LogGraphOptions& options,
                                    int halfWindow) {
    const CurveDifferential d = curveDifferential(line, halfWindow);
    return logDistributionGraph(d.arcLength, radiusOf(d.curvature), options);
}

LogDistributionGraph curvatureGraph(const Polyline3& line, const LogGraphOptions& options,
                                    int halfWindow) {
    const CurveDifferential d = curveDifferential(line, halfWindow);
    return logDistributionGraph(d.arcLength, radiusOf(d.curvature), options);
}

LogDistributionGraph torsionGraph(const Polyline3& line, const LogGraphOptions& options,
                                  int halfWindow) {
    const CurveDifferential d = curveDifferential(line, halfWindow);
    return logDistributionGraph(d.arcLength, radiusOf(d.torsion), options);
}

}  // namespace vsculpt::sketch
