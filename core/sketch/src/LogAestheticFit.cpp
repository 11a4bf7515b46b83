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

// Plain Nelder–Mead (reflection 1, expansion 2, contraction ½, shrink ½).
template <int kDim>
std::array<double, kDim> nelderMead(const std::function<double(const std::array<double, kDim>&)>& f,
                                    const std::array<double, kDim>& start,
                                    const std::array<double, kDim>& step, int maxIterations,
                                    double tolerance, int& evaluations) {
    using Vec = std::array<double, kDim>;
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

using Vec = std::array<double, 7>;

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
    const Polyline2 target = resampleByCount(clean, n);
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

    const double maxLogCurvature = std::log(1e6 / length);
    std::function<double(const Vec&)> objective = [&](const Vec& v) {
        for (double x : v)
            if (!std::isfinite(x)) return std::numeric_limits<double>::infinity();
        if (!(std::abs(v[0]) < 20.0) || !(v[1] > std::log(minCurvature)) ||
            !(v[2] > std::log(minCurvature)) || !(v[1] < maxLogCurvature) ||
            !(v[2] < maxLogCurvature) || !(std::abs(v[6] - std::log(length)) < 1.0))
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
        nelderMead<7>(objective, start, step, options.maxIterations, tolerance, result.evaluations);
    Vec restartStep = step;
    for (double& s : restartStep)
        s *= 0.1;
    best = nelderMead<7>(objective, best, restartStep, options.maxIterations, tolerance,
                         result.evaluations);

    result.params = paramsOf(best, sign);
    result.rmsError = std::sqrt(objective(best));
    result.maxError = maxDeviation(target, laPlanarCurve(result.params, 4 * n).points);
    return result;
}

namespace {

using Vec13 = std::array<double, 13>;

// Rotation of v about axis r by |r| radians (Rodrigues).
glm::dvec3 rotateBy(const glm::dvec3& r, const glm::dvec3& v) {
    const double angle = glm::length(r);
    if (angle < 1e-300) return v;
    const glm::dvec3 k = r / angle;
    return v * std::cos(angle) + glm::cross(k, v) * std::sin(angle) +
           k * glm::dot(k, v) * (1.0 - std::cos(angle));
}

double maxDeviation3(const Polyline3& points, const Polyline3& reference) {
    double worst = 0.0;
    for (const glm::dvec3& p : points) {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t i = 1; i < reference.size(); ++i) {
            const glm::dvec3 a = reference[i - 1], d = reference[i] - a;
            const double t = std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0);
            best = std::min(best, glm::distance(p, a + t * d));
        }
        worst = std::max(worst, best);
    }
    return worst;
}

}  // namespace

LaSpaceFitResult fitLaSpaceCurve(const Polyline3& drawn, const LaFitOptions& options) {
    if (options.samples < 8 || options.maxIterations < 1 || options.halfWindow < 0)
        throw std::invalid_argument(
            "fitLaSpaceCurve: need samples >= 8, maxIterations >= 1, halfWindow >= 0");
    if (drawn.size() < 3)
        throw std::invalid_argument("fitLaSpaceCurve: need at least 3 points, got " +
                                    std::to_string(drawn.size()));
    Polyline3 clean;
    for (const glm::dvec3& p : drawn) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw std::invalid_argument("fitLaSpaceCurve: curve has a non-finite coordinate");
        if (clean.empty() || p != clean.back()) clean.push_back(p);
    }
    if (clean.size() < 3)
        throw std::invalid_argument(
            "fitLaSpaceCurve: fewer than 3 distinct points (zero-length curve)");
    const int n = options.samples;
    const Polyline3 target = resampleByCount(clean, n);
    const double length = sketch::length(target, false);
    const int window = options.halfWindow > 0 ? options.halfWindow : std::max(2, n / 20);
    const CurveDifferential d = curveDifferential(target, window);

    LaSpaceFitResult result;
    const double torsionSum = std::accumulate(d.torsion.begin(), d.torsion.end(), 0.0);
    const double tauSign = torsionSum < 0.0 ? -1.0 : 1.0;
    const double minValue = 1e-6 / length;
    const double maxLog = std::log(1e6 / length);
    LogGraphOptions g;
    g.bins = std::clamp(n / 8, 5, 20);
    double alpha0 = 1.0, beta0 = 1.0;
    result.graphAlpha = result.graphBeta = std::numeric_limits<double>::quiet_NaN();
    try {
        result.graphAlpha = curvatureGraph(target, g, window).slope;
        alpha0 = std::clamp(result.graphAlpha, -3.0, 3.0);
    } catch (const std::invalid_argument&) {
    }
    try {
        result.graphBeta = torsionGraph(target, g, window).slope;
        beta0 = std::clamp(result.graphBeta, -3.0, 3.0);
    } catch (const std::invalid_argument&) {
    }
    // Start frame: the estimated Frenet frame, or any normal where the start is straight.
    FrenetStart frame0;
    frame0.point = target[0];
    frame0.tangent = d.tangent[0];
    frame0.normal = d.normal[0];
    if (!(glm::length(frame0.normal) > 0.5)) {
        const glm::dvec3 t = frame0.tangent;
        frame0.normal = glm::normalize(
            glm::cross(t, std::abs(t.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    }
    auto logOf = [&](double v) {
        return std::log(std::clamp(std::abs(v), minValue, 1e6 / length));
    };
    const Vec13 start{alpha0,
                      logOf(d.curvature.front()),
                      logOf(d.curvature.back()),
                      beta0,
                      logOf(d.torsion.front()),
                      logOf(d.torsion.back()),
                      target[0].x,
                      target[0].y,
                      target[0].z,
                      0.0,
                      0.0,
                      0.0,
                      std::log(length)};
    const double pos = 0.01 * length;
    const Vec13 step{0.5, 0.2, 0.2, 0.5, 0.3, 0.3, pos, pos, pos, 0.05, 0.05, 0.05, 0.01};

    auto paramsOf13 = [&](const Vec13& v) {
        LaSpaceParams p;
        p.length = std::exp(v[12]);
        p.alpha = v[0];
        const double k0 = std::exp(v[1]), k1 = std::exp(v[2]);
        p.startCurvature = k0;
        p.lambda = laLambdaForRadiusRatio(p.alpha, k0 / k1, p.length * k0);
        p.beta = v[3];
        const double t0 = std::exp(v[4]), t1 = std::exp(v[5]);
        p.startTorsion = tauSign * t0;
        p.omega = laLambdaForRadiusRatio(p.beta, t0 / t1, p.length * t0);
        const glm::dvec3 r(v[9], v[10], v[11]);
        p.start.point = {v[6], v[7], v[8]};
        p.start.tangent = rotateBy(r, frame0.tangent);
        p.start.normal = rotateBy(r, frame0.normal);
        return p;
    };
    std::function<double(const Vec13&)> objective = [&](const Vec13& v) {
        for (double x : v)
            if (!std::isfinite(x)) return std::numeric_limits<double>::infinity();
        for (int k : {1, 2, 4, 5})
            if (!(v[k] > std::log(minValue)) || !(v[k] < maxLog))
                return std::numeric_limits<double>::infinity();
        if (!(std::abs(v[0]) < 20.0) || !(std::abs(v[3]) < 20.0) ||
            !(std::abs(v[12] - std::log(length)) < 1.0))
            return std::numeric_limits<double>::infinity();
        const SpaceCurveSamples c = laSpaceCurve(paramsOf13(v), n, 2);
        double sum = 0.0;
        for (int i = 0; i < n; ++i) {
            const glm::dvec3 e = c.points[std::size_t(i)] - target[std::size_t(i)];
            sum += glm::dot(e, e);
        }
        return std::isfinite(sum) ? sum / n : std::numeric_limits<double>::infinity();
    };
    const double tolerance = 1e-16 * length * length;
    Vec13 best = nelderMead<13>(objective, start, step, options.maxIterations, tolerance,
                                result.evaluations);
    // In 13 dimensions the simplex stalls long before the optimum (β in particular moves the
    // curve little); restart with shrinking steps while that still pays.
    Vec13 restartStep = step;
    double previous = objective(best);
    for (int restart = 0; restart < 8; ++restart) {
        for (double& s : restartStep)
            s *= 0.5;
        best = nelderMead<13>(objective, best, restartStep, options.maxIterations, tolerance,
                              result.evaluations);
        const double now = objective(best);
        if (!(now < 0.99 * previous)) break;
        previous = now;
    }

    result.params = paramsOf13(best);
    result.rmsError = std::sqrt(objective(best));
    result.maxError = maxDeviation3(target, laSpaceCurve(result.params, 4 * n, 2).points);
    return result;
}

}  // namespace vsculpt::sketch
