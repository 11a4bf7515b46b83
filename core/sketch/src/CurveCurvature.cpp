#include "vsculpt/sketch/CurveCurvature.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

namespace {

template <typename Points>
std::vector<double> checkedChordLengths(const Points& line, const char* what) {
    if (line.size() < 3)
        throw std::invalid_argument(std::string(what) + ": need at least 3 points, got " +
                                    std::to_string(line.size()));
    std::vector<double> s(line.size(), 0.0);
    for (std::size_t i = 0; i < line.size(); ++i) {
        for (int c = 0; c < line[i].length(); ++c)
            if (!std::isfinite(line[i][c]))
                throw std::invalid_argument(std::string(what) + ": point " + std::to_string(i) +
                                            " is not finite");
        if (i > 0) {
            const double d = glm::distance(line[i - 1], line[i]);
            if (!(d > 0.0))
                throw std::invalid_argument(std::string(what) + ": points " +
                                            std::to_string(i - 1) + " and " + std::to_string(i) +
                                            " coincide (zero-length segment)");
            s[i] = s[i - 1] + d;
        }
    }
    return s;
}

// Solves the (n×n, n ≤ 4) system a·x = b by Gaussian elimination with partial pivoting.
template <std::size_t N>
std::array<double, N> solveSmall(std::array<std::array<double, N>, N> a, std::array<double, N> b,
                                 int n) {
    for (int col = 0; col < n; ++col) {
        int pivot = col;
        for (int r = col + 1; r < n; ++r)
            if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
        std::swap(a[col], a[pivot]);
        std::swap(b[col], b[pivot]);
        for (int r = col + 1; r < n; ++r) {
            const double f = a[r][col] / a[col][col];
            for (int c = col; c < n; ++c)
                a[r][c] -= f * a[col][c];
            b[r] -= f * b[col];
        }
    }
    std::array<double, N> x{};
    for (int r = n - 1; r >= 0; --r) {
        double v = b[r];
        for (int c = r + 1; c < n; ++c)
            v -= a[r][c] * x[c];
        x[r] = v / a[r][r];
    }
    return x;
}

// First three derivatives (with respect to chord length) of the local polynomial fit at i.
struct LocalDerivatives {
    glm::dvec3 d1{0.0}, d2{0.0}, d3{0.0};
};

template <typename Points>
LocalDerivatives localFit(const Points& line, const std::vector<double>& s, int i, int halfWindow) {
    const int n = int(line.size());
    const int width = std::min(n, 2 * halfWindow + 1);
    const int first = std::clamp(i - halfWindow, 0, n - width);
    const int degree = std::min(3, width - 1);
    const int m = degree + 1;
    double scale = 0.0;
    for (int j = first; j < first + width; ++j)
        scale = std::max(scale, std::abs(s[j] - s[i]));
    // Normal equations on parameters scaled to [−1, 1] keep the 4×4 system well conditioned.
    std::array<std::array<double, 4>, 4> ata{};
    std::array<std::array<double, 4>, 3> atb{};
    for (int j = first; j < first + width; ++j) {
        const double t = (s[j] - s[i]) / scale;
        std::array<double, 4> pw{1.0, t, t * t, t * t * t};
        for (int r = 0; r < m; ++r) {
            for (int c = 0; c < m; ++c)
                ata[r][c] += pw[r] * pw[c];
            for (int k = 0; k < line[j].length(); ++k)
                atb[k][r] += pw[r] * line[j][k];
        }
    }
    LocalDerivatives d;
    for (int k = 0; k < line[0].length(); ++k) {
        const std::array<double, 4> coef = solveSmall<4>(ata, atb[k], m);
        d.d1[k] = coef[1] / scale;
        d.d2[k] = 2.0 * coef[2] / (scale * scale);
        d.d3[k] = degree >= 3 ? 6.0 * coef[3] / (scale * scale * scale) : 0.0;
    }
    return d;
}

void checkWindow(int halfWindow) {
    if (halfWindow < 1)
        throw std::invalid_argument("curveDifferential: halfWindow must be >= 1, got " +
                                    std::to_string(halfWindow));
}

template <typename Points>
Points resample(const Points& line, int count) {
    const std::vector<double> s = checkedChordLengths(line, "resampleByCount");
    if (count < 2)
        throw std::invalid_argument("resampleByCount: count must be >= 2, got " +
                                    std::to_string(count));
    Points out;
    out.reserve(std::size_t(count));
    std::size_t seg = 1;
    for (int k = 0; k < count; ++k) {
        const double target = s.back() * double(k) / double(count - 1);
        while (seg + 1 < s.size() && s[seg] < target)
            ++seg;
        const double f = std::clamp((target - s[seg - 1]) / (s[seg] - s[seg - 1]), 0.0, 1.0);
        out.push_back(line[seg - 1] + f * (line[seg] - line[seg - 1]));
    }
    out.back() = line.back();
    return out;
}

}  // namespace

CurveDifferential curveDifferential(const Polyline2& line, int halfWindow) {
    checkWindow(halfWindow);
    CurveDifferential out;
    out.arcLength = checkedChordLengths(line, "curveDifferential");
    const std::size_t n = line.size();
    out.curvature.resize(n);
    out.torsion.assign(n, 0.0);
    out.tangent.resize(n);
    out.normal.resize(n);
    out.binormal.assign(n, glm::dvec3(0.0, 0.0, 1.0));
    for (std::size_t i = 0; i < n; ++i) {
        const LocalDerivatives d = localFit(line, out.arcLength, int(i), halfWindow);
        const double speed = std::hypot(d.d1.x, d.d1.y);
        out.curvature[i] = (d.d1.x * d.d2.y - d.d1.y * d.d2.x) / (speed * speed * speed);
        out.tangent[i] = glm::dvec3(d.d1.x / speed, d.d1.y / speed, 0.0);
        // Left normal, so that a positive (counter-clockwise) curvature bends towards it.
        out.normal[i] = glm::dvec3(-out.tangent[i].y, out.tangent[i].x, 0.0);
    }
    return out;
}

CurveDifferential curveDifferential(const Polyline3& line, int halfWindow) {
    checkWindow(halfWindow);
    CurveDifferential out;
    out.arcLength = checkedChordLengths(line, "curveDifferential");
    const std::size_t n = line.size();
    const double straightLimit = 1e-12 / out.arcLength.back();
    out.curvature.resize(n);
    out.torsion.resize(n);
    out.tangent.resize(n);
    out.normal.assign(n, glm::dvec3(0.0));
    out.binormal.assign(n, glm::dvec3(0.0));
    for (std::size_t i = 0; i < n; ++i) {
        const LocalDerivatives d = localFit(line, out.arcLength, int(i), halfWindow);
        const double speed = glm::length(d.d1);
        const glm::dvec3 cross = glm::cross(d.d1, d.d2);
        const double crossLen = glm::length(cross);
        out.tangent[i] = d.d1 / speed;
        out.curvature[i] = crossLen / (speed * speed * speed);
        if (out.curvature[i] > straightLimit) {
            out.torsion[i] = glm::dot(cross, d.d3) / (crossLen * crossLen);
            out.binormal[i] = cross / crossLen;
            out.normal[i] = glm::cross(out.binormal[i], out.tangent[i]);
        } else {
            out.torsion[i] = 0.0;
        }
    }
    return out;
}

Polyline2 resampleByCount(const Polyline2& line, int count) {
    return resample(line, count);
}
Polyline3 resampleByCount(const Polyline3& line, int count) {
    return resample(line, count);
}

}  // namespace vsculpt::sketch
