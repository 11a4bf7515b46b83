#include "vsculpt/sketch/NaturalSpline.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace vsculpt::sketch {

namespace {

template <typename Vec>
bool isFinite(const Vec& p) {
    for (int i = 0; i < Vec::length(); ++i)
        if (!std::isfinite(p[i])) return false;
    return true;
}

template <typename Vec>
std::vector<Vec> mergedKnots(const std::vector<Vec>& points, bool closed) {
    double extent = 0.0;
    for (const Vec& p : points) {
        if (!isFinite(p))
            throw std::invalid_argument("sampleNaturalSpline: non-finite point coordinate");
        extent = std::max(extent, glm::distance(p, points.front()));
    }
    // Relative tolerance: a merge threshold in mm would be wrong for both micro and huge inputs.
    const double tol = 1e-12 * std::max(extent, 1e-300);
    std::vector<Vec> knots;
    knots.reserve(points.size());
    for (const Vec& p : points)
        if (knots.empty() || glm::distance(knots.back(), p) > tol) knots.push_back(p);
    if (closed && knots.size() > 1 && glm::distance(knots.back(), knots.front()) <= tol)
        knots.pop_back();
    return knots;
}

// Solves the tridiagonal system sub[i] x[i-1] + diag[i] x[i] + sup[i] x[i+1] = rhs[i]
// (Thomas algorithm); the matrices here are strictly diagonally dominant, so no pivoting.
template <typename Vec>
std::vector<Vec> solveTridiagonal(const std::vector<double>& sub, std::vector<double> diag,
                                  const std::vector<double>& sup, std::vector<Vec> rhs) {
    const std::size_t n = diag.size();
    for (std::size_t i = 1; i < n; ++i) {
        const double m = sub[i] / diag[i - 1];
        diag[i] -= m * sup[i - 1];
        rhs[i] -= m * rhs[i - 1];
    }
    std::vector<Vec> x(n);
    x[n - 1] = rhs[n - 1] / diag[n - 1];
    for (std::size_t i = n - 1; i-- > 0;)
        x[i] = (rhs[i] - sup[i] * x[i + 1]) / diag[i];
    return x;
}

// Second derivatives (with respect to chord length) at the knots.
template <typename Vec>
std::vector<Vec> secondDerivatives(const std::vector<Vec>& p, const std::vector<double>& h,
                                   bool closed) {
    const std::size_t n = p.size();
    if (!closed) {
        std::vector<Vec> m(n, Vec(0.0));
        if (n < 3) return m;
        const std::size_t k = n - 2;  // interior knots; natural ends fix m[0] = m[n-1] = 0
        std::vector<double> sub(k), diag(k), sup(k);
        std::vector<Vec> rhs(k);
        for (std::size_t j = 0; j < k; ++j) {
            const std::size_t i = j + 1;
            sub[j] = h[i - 1];
            diag[j] = 2.0 * (h[i - 1] + h[i]);
            sup[j] = h[i];
            rhs[j] = 6.0 * ((p[i + 1] - p[i]) / h[i] - (p[i] - p[i - 1]) / h[i - 1]);
        }
        const std::vector<Vec> inner = solveTridiagonal(sub, diag, sup, rhs);
        for (std::size_t j = 0; j < k; ++j)
            m[j + 1] = inner[j];
        return m;
    }
    // Periodic: cyclic tridiagonal system, reduced to two ordinary solves (Sherman-Morrison).
    std::vector<double> sub(n), diag(n), sup(n);
    std::vector<Vec> rhs(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t prev = (i + n - 1) % n, next = (i + 1) % n;
        sub[i] = h[prev];
        diag[i] = 2.0 * (h[prev] + h[i]);
        sup[i] = h[i];
        rhs[i] = 6.0 * ((p[next] - p[i]) / h[i] - (p[i] - p[prev]) / h[prev]);
    }
    const double alpha = sup[n - 1];  // A[n-1][0]
    const double beta = sub[0];       // A[0][n-1]
    const double gamma = -diag[0];
    std::vector<double> d = diag;
    d[0] -= gamma;
    d[n - 1] -= alpha * beta / gamma;
    const std::vector<Vec> x = solveTridiagonal(sub, d, sup, rhs);
    std::vector<double> u(n, 0.0);
    u[0] = gamma;
    u[n - 1] = alpha;
    const std::vector<double> z = solveTridiagonal(sub, d, sup, u);
    const Vec vx = x[0] + (beta / gamma) * x[n - 1];
    const double vz = z[0] + (beta / gamma) * z[n - 1];
    std::vector<Vec> m(n);
    for (std::size_t i = 0; i < n; ++i)
        m[i] = x[i] - (vx / (1.0 + vz)) * z[i];
    return m;
}

template <typename Vec>
std::vector<Vec> sampleSpline(const std::vector<Vec>& points, bool closed, int samplesPerSpan) {
    if (samplesPerSpan < 1)
        throw std::invalid_argument("sampleNaturalSpline: samplesPerSpan must be >= 1, got " +
                                    std::to_string(samplesPerSpan));
    const std::vector<Vec> p = mergedKnots(points, closed);
    const std::size_t minKnots = closed ? 3 : 2;
    if (p.size() < minKnots)
        throw std::invalid_argument("sampleNaturalSpline: need at least " +
                                    std::to_string(minKnots) + " distinct points, got " +
                                    std::to_string(p.size()));
    const std::size_t n = p.size();
    const std::size_t spans = closed ? n : n - 1;
    std::vector<double> h(spans);
    for (std::size_t i = 0; i < spans; ++i)
        h[i] = glm::distance(p[i], p[(i + 1) % n]);
    const std::vector<Vec> m = secondDerivatives(p, h, closed);

    std::vector<Vec> out;
    out.reserve(spans * std::size_t(samplesPerSpan) + 1);
    for (std::size_t i = 0; i < spans; ++i) {
        const std::size_t j = (i + 1) % n;
        const double hh6 = h[i] * h[i] / 6.0;
        for (int s = 0; s < samplesPerSpan; ++s) {
            const double u = double(s) / samplesPerSpan;
            const double v = 1.0 - u;
            out.push_back(v * p[i] + u * p[j] +
                          hh6 * ((v * v * v - v) * m[i] + (u * u * u - u) * m[j]));
        }
    }
    if (!closed) out.push_back(p.back());
    return out;
}

}  // namespace

Polyline2 sampleNaturalSpline(const Polyline2& points, bool closed, int samplesPerSpan) {
    return sampleSpline(points, closed, samplesPerSpan);
}

Polyline3 sampleNaturalSpline(const Polyline3& points, bool closed, int samplesPerSpan) {
    return sampleSpline(points, closed, samplesPerSpan);
}

}  // namespace vsculpt::sketch
