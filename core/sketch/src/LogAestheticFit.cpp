#include "vsculpt/sketch/LogAestheticFit.h"

#include "vsculpt/sketch/CurveCurvature.h"
#include "vsculpt/sketch/LogAestheticGraph.h"
#include "vsculpt/sketch/LogAestheticTwoView.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

namespace {

constexpr int kDim = 7;
using Vec = std::array<double, kDim>;

// Plain Nelder–Mead (reflection 1, expansion 2, contraction ½, shrink ½).
Vec nelderMead(const std::function<double(const Vec&)>& f, const Vec& start, const Vec& step,
               int maxIterations, double tolerance, int& evaluations) {
    std::array<Vec, kDim + 1> x;
    std::array<double, kDim + 1> fx;
    for (int i = 0; i <= kDim; ++i) {
        x[i] = start;
        if (i > 0) x[i][i - 1] += step[i - 1];
        fx[i] = f(x[i]);
        ++evaluations;
    }
    std::array<int, kDim + 1> order;
    for (int it = 0; it < maxIterations; ++it) {
        std::iota(order.begin(), order.end(), 0);
        std::sort(order.begin(), order.end(), [&](int a, int b) { return fx[a] < fx[b]; });
        const int best = order[0], worst = order[kDim], second = order[kDim - 1];
        if (fx[worst] - fx[best] <= tolerance) break;
        Vec centroid{};
        for (int i = 0; i < kDim; ++i)
            for (int d = 0; d < kDim; ++d)
                centroid[d] += x[order[i]][d] / kDim;
        auto along = [&](double t) {
            Vec p;
            for (int d = 0; d < kDim; ++d)
                p[d] = centroid[d] + t * (x[worst][d] - centroid[d]);
            return p;
        };
        const Vec r = along(-1.0);
        const double fr = f(r);
        ++evaluations;
        if (fr < fx[best]) {
            const Vec e = along(-2.0);
            const double fe = f(e);
            ++evaluations;
            if (fe < fr) {
                x[worst] = e, fx[worst] = fe;
            } else {
                x[worst] = r, fx[worst] = fr;
            }
        } else if (fr < fx[second]) {
            x[worst] = r, fx[worst] = fr;
        } else {
            const Vec c = fr < fx[worst] ? along(-0.5) : along(0.5);
            const double fc = f(c);
            ++evaluations;
            if (fc < std::min(fr, fx[worst])) {
                x[worst] = c, fx[worst] = fc;
            } else {
                for (int i = 1; i <= kDim; ++i) {
                    Vec& p = x[order[i]];
                    for (int d = 0; d < kDim; ++d)
                        p[d] = x[best][d] + 0.5 * (p[d] - x[best][d]);
                    fx[order[i]] = f(p);
                    ++evaluations;
                }
            }
        }
    }
    return x[std::size_t(std::min_element(fx.begin(), fx.end()) - fx.begin())];
}

LaPlanarParams paramsOf(const Vec& v, double sign) {
    LaPlanarParams p;
    p.alpha = v[0];
    const double k0 = std::exp(v[1]), k1 = std::exp(v[2]);
    p.length = std::exp(v[6]);
    p.startCurvature = sign * k0;
    p.lambda = laLambdaForRadiusRatio(p.alpha, k0 / k1, p.length * k0);
    p.startAngle = v[3];
    p.start = {v[4], v[5]};
    return p;
}

}  // namespace

LaFitResult fitLaPlanarCurve(const Polyline2& drawn, const LaFitOptions& options) {
    if (options.samples < 8 || options.maxIterations < 1 || options.halfWindow < 0)
        throw std::invalid_argument(
            "fitLaPlanarCurve: need samples >= 8, maxIterations >= 1, halfWindow >= 0");
    if (drawn.size() < 3)
        throw std::invalid_argument("fitLaPlanarCurve: need at least 3 points, got " +
                                    std::to_string(drawn.size()));
    Polyline2 clean;
    for (const glm::dvec2& p : drawn) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y))
            throw std::invalid_argument("fitLaPlanarCurve: stroke has a non-finite coordinate");
        if (clean.empty() || p != clean.back()) clean.push_back(p);  // pen at rest repeats points
    }
    if (clean.size() < 3)
        throw std::invalid_argument(
            "fitLaPlanarCurve: fewer than 3 distinct points (zero-length stroke)");
    const int n = options.samples;
    const Polyline2 target = resampleByArcLength(clean, n);
    const double length = sketch::length(target, false);
    const int window = options.halfWindow > 0 ? options.halfWindow : std::max(2, n / 20);
    const CurveDifferential d = curveDifferential(target, window);

    LaFitResult result;
    const double turning = std::accumulate(d.curvature.begin(), d.curvature.end(), 0.0);
    const double sign = turning < 0.0 ? -1.0 : 1.0;
    const double minCurvature = 1e-6 / length;
    double alpha0 = 1.0;
    try {
        LogGraphOptions g;
        g.bins = std::clamp(n / 8, 5, 20);
        result.graphAlpha = curvatureGraph(target, g, window).slope;
        alpha0 = std::clamp(result.graphAlpha, -3.0, 3.0);
    } catch (const std::invalid_argument&) {
        result.graphAlpha = std::numeric_limits<double>::quiet_NaN();
    }
    const Vec start{alpha0,
                    std::log(std::max(minCurvature, std::abs(d.curvature.front()))),
                    std::log(std::max(minCurvature, std::abs(d.curvature.back()))),
                    std::atan2(d.tangent[0].y, d.tangent[0].x),
                    target[0].x,
                    target[0].y,
                    std::log(length)};
    const Vec step{0.5, 0.2, 0.2, 0.05, 0.01 * length, 0.01 * length, 0.01};

    auto objective = [&](const Vec& v) {
        if (!(std::abs(v[0]) < 20.0) || !(v[1] > std::log(minCurvature)) ||
            !(v[2] > std::log(minCurvature)))
            return std::numeric_limits<double>::infinity();
        const LaPlanarCurve c = laPlanarCurve(paramsOf(v, sign), n);
        double sum = 0.0;
        for (int i = 0; i < n; ++i) {
            const glm::dvec2 e = c.points[std::size_t(i)] - target[std::size_t(i)];
            sum += glm::dot(e, e);
        }
        return std::isfinite(sum) ? sum / n : std::numeric_limits<double>::infinity();
    };
    const double tolerance = 1e-16 * length * length;
    Vec best =
        nelderMead(objective, start, step, options.maxIterations, tolerance, result.evaluations);
    Vec restartStep = step;
    for (double& s : restartStep)
        s *= 0.1;
    best = nelderMead(objective, best, restartStep, options.maxIterations, tolerance,
                      result.evaluations);

    result.params = paramsOf(best, sign);
    result.rmsError = std::sqrt(objective(best));
    result.maxError = maxDeviation(target, laPlanarCurve(result.params, 4 * n).points);
    return result;
}

}  // namespace vsculpt::sketch
