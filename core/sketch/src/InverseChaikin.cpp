#include "vsculpt/sketch/InverseChaikin.h"

#include "vsculpt/sketch/Chaikin.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

namespace {

double cross(const glm::dvec2& a, const glm::dvec2& b) {
    return a.x * b.y - a.y * b.x;
}

void requireCurve(const Polyline2& curve, std::size_t minPoints, const char* what) {
    if (curve.size() < minPoints)
        throw std::invalid_argument(std::string(what) + ": need at least " +
                                    std::to_string(minPoints) + " points, got " +
                                    std::to_string(curve.size()));
    for (const auto& p : curve)
        if (!std::isfinite(p.x) || !std::isfinite(p.y))
            throw std::invalid_argument(std::string(what) + ": non-finite coordinate");
}

// Intersection of lines p + t·d and q + r·e; false when (nearly) parallel.
bool intersectLines(const glm::dvec2& p, const glm::dvec2& d, const glm::dvec2& q,
                    const glm::dvec2& e, glm::dvec2& out) {
    const double denominator = cross(d, e);
    const double scale = glm::length(d) * glm::length(e);
    if (!(std::abs(denominator) > 1e-12 * scale)) return false;
    out = p + d * (cross(q - p, e) / denominator);
    return true;
}

// A closed curve resampled at equal arc length; continuous parameter s ∈ [0, n) in samples.
class ClosedCurve {
  public:
    ClosedCurve(const Polyline2& curve, int count, const char* what) {
        requireCurve(curve, 8, what);
        if (count < 16) throw std::invalid_argument(std::string(what) + ": resampleCount < 16");
        const double total = length(curve, true);
        if (!(total > 0) || signedArea(curve) == 0.0)
            throw std::invalid_argument(std::string(what) + ": the curve has zero length or area");
        const std::size_t m = curve.size();
        points_.reserve(count);
        double walked = 0.0;
        std::size_t edge = 0;
        for (int k = 0; k < count; ++k) {
            const double target = total * k / count;
            while (edge < m) {
                const double segment = glm::length(curve[(edge + 1) % m] - curve[edge]);
                if (walked + segment >= target && segment > 0) {
                    const double t = (target - walked) / segment;
                    points_.push_back(curve[edge] + t * (curve[(edge + 1) % m] - curve[edge]));
                    break;
                }
                walked += segment;
                ++edge;
            }
            if (edge >= m) points_.push_back(curve.front());
        }
        step_ = total / count;
        // Turning per sample, smoothed over a window so that pen jitter on a clean curve does
        // not register as curvature sign changes.
        const int n = count;
        std::vector<double> turn(n);
        for (int i = 0; i < n; ++i) {
            const glm::dvec2 a = points_[i] - points_[(i + n - 1) % n];
            const glm::dvec2 b = points_[(i + 1) % n] - points_[i];
            turn[i] = std::atan2(cross(a, b), glm::dot(a, b));
        }
        const int window = std::max(1, n / 128);
        turning_.assign(n, 0.0);
        for (int i = 0; i < n; ++i)
            for (int j = -window; j <= window; ++j)
                turning_[i] += turn[(i + j + n) % n];
    }

    int size() const { return int(points_.size()); }
    double step() const { return step_; }
    const std::vector<double>& turning() const { return turning_; }

    double wrap(double s) const {
        const double n = size();
        double r = std::fmod(s, n);
        return r < 0 ? r + n : r;
    }
    glm::dvec2 point(double s) const {
        s = wrap(s);
        const int i = int(s);
        const double t = s - i;
        return (1 - t) * points_[i % size()] + t * points_[(i + 1) % size()];
    }
    glm::dvec2 tangent(double s) const {
        const glm::dvec2 d = point(s + 1.5) - point(s - 1.5);
        return d / glm::length(d);
    }

  private:
    std::vector<glm::dvec2> points_;
    std::vector<double> turning_;
    double step_ = 0.0;
};

// Zero crossings of the smoothed curvature with hysteresis: a sign change counts only once
// the turning on the other side exceeds the threshold, so near-straight stretches do not
// produce spurious pairs.
std::vector<double> inflectionParameters(const ClosedCurve& curve) {
    const auto& turning = curve.turning();
    const int n = curve.size();
    double mean = 0;
    for (double t : turning)
        mean += std::abs(t);
    mean /= n;
    const double threshold = 0.05 * mean;
    int start = -1;
    for (int i = 0; i < n; ++i)
        if (std::abs(turning[i]) > threshold) {
            start = i;
            break;
        }
    std::vector<double> result;
    if (start < 0) return result;
    int sign = turning[start] > 0 ? 1 : -1;
    double lastCrossing = start;
    for (int k = 1; k <= n; ++k) {
        const int i = (start + k) % n;
        const int previous = (start + k - 1) % n;
        const double a = turning[previous], b = turning[i];
        if ((a > 0) != (b > 0) && a != b) lastCrossing = start + k - 1 + a / (a - b);
        if (std::abs(b) > threshold && (b > 0 ? 1 : -1) != sign) {
            sign = -sign;
            result.push_back(curve.wrap(lastCrossing));
        }
    }
    std::sort(result.begin(), result.end());
    return result;
}

// Solves A X = B in place (A is n×n row-major, B is n×cols); false when singular.
bool solveDense(std::vector<double>& A, std::vector<double>& B, int n, int cols) {
    auto at = [&](int r, int c) -> double& { return A[std::size_t(r) * n + c]; };
    for (int c = 0; c < n; ++c) {
        int pivot = c;
        for (int r = c + 1; r < n; ++r)
            if (std::abs(at(r, c)) > std::abs(at(pivot, c))) pivot = r;
        if (!(std::abs(at(pivot, c)) > 1e-14)) return false;
        if (pivot != c) {
            for (int k = 0; k < n; ++k)
                std::swap(at(c, k), at(pivot, k));
            for (int k = 0; k < cols; ++k)
                std::swap(B[std::size_t(c) * cols + k], B[std::size_t(pivot) * cols + k]);
        }
        for (int r = c + 1; r < n; ++r) {
            const double f = at(r, c) / at(c, c);
            if (f == 0) continue;
            for (int k = c; k < n; ++k)
                at(r, k) -= f * at(c, k);
            for (int k = 0; k < cols; ++k)
                B[std::size_t(r) * cols + k] -= f * B[std::size_t(c) * cols + k];
        }
    }
    for (int r = n - 1; r >= 0; --r)
        for (int k = 0; k < cols; ++k) {
            double sum = B[std::size_t(r) * cols + k];
            for (int c = r + 1; c < n; ++c)
                sum -= at(r, c) * B[std::size_t(c) * cols + k];
            B[std::size_t(r) * cols + k] = sum / at(r, r);
        }
    return true;
}

// Span index, local parameter and the three quadratic B-spline weights at u.
struct SplineBasis {
    int idx[3];
    double w[3];
    double t;
};
SplineBasis basisAt(double u, int n) {
    const double span = std::floor(u);
    SplineBasis b;
    b.t = u - span;
    int i = int(std::fmod(span, double(n)));
    if (i < 0) i += n;
    b.idx[0] = i;
    b.idx[1] = (i + 1) % n;
    b.idx[2] = (i + 2) % n;
    b.w[0] = 0.5 * (1 - b.t) * (1 - b.t);
    b.w[1] = 0.5 + b.t - b.t * b.t;
    b.w[2] = 0.5 * b.t * b.t;
    return b;
}

struct Tangent {
    double s;
    bool inflection;
    // 0: x extremum (tangent exactly vertical), 1: y extremum (exactly horizontal), −1: neither.
    int axis = -1;
};

// The tangent direction: exact for axis extrema, so sections whose extents agree give
// polygons whose extents agree too.
glm::dvec2 directionOf(const ClosedCurve& curve, const Tangent& t) {
    const glm::dvec2 d = curve.tangent(t.s);
    if (t.axis == 0) return {0.0, d.y > 0 ? 1.0 : -1.0};
    if (t.axis == 1) return {d.x > 0 ? 1.0 : -1.0, 0.0};
    return d;
}

// Tangent point between parameters a < b (b may exceed n) whose point is the midpoint of the
// edge cut from the corner of tangents a and b.
double midEdgeTangent(const ClosedCurve& curve, double a, double b, const glm::dvec2& ta,
                      const glm::dvec2& tb) {
    const glm::dvec2 pa = curve.point(a);
    const glm::dvec2 pb = curve.point(b);
    auto offset = [&](double s, bool& ok) {
        const glm::dvec2 p = curve.point(s), t = curve.tangent(s);
        glm::dvec2 c1, c2;
        ok = intersectLines(p, t, pa, ta, c1) && intersectLines(p, t, pb, tb, c2);
        return ok ? glm::dot(p - 0.5 * (c1 + c2), t) : 0.0;
    };
    double lo = -1, hi = -1;
    for (double s = std::floor(a) + 1; s < b; s += 1.0) {
        bool ok = false;
        const double f = offset(s, ok);
        if (!ok) continue;
        if (f < 0) {
            lo = s;
        } else if (lo >= 0) {
            hi = s;
            break;
        }
    }
    if (lo < 0 || hi < 0) return 0.5 * (a + b);
    for (int iteration = 0; iteration < 40; ++iteration) {
        const double mid = 0.5 * (lo + hi);
        bool ok = false;
        const double f = offset(mid, ok);
        if (!ok) break;
        (f < 0 ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

Polyline2 polygonOf(const ClosedCurve& curve, const std::vector<Tangent>& tangents) {
    std::vector<TangentLine> lines;
    for (const auto& t : tangents)
        lines.push_back({curve.point(t.s), directionOf(curve, t)});
    return polygonFromTangentLines(lines);
}

double angleBetween(const glm::dvec2& a, const glm::dvec2& b) {
    return std::abs(std::atan2(cross(a, b), glm::dot(a, b)));
}

}  // namespace

Polyline2 polygonFromTangentLines(const std::vector<TangentLine>& lines) {
    if (lines.size() < 3)
        throw std::invalid_argument("polygonFromTangentLines: need at least 3 tangent lines");
    Polyline2 polygon(lines.size());
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const auto& a = lines[i];
        const auto& b = lines[(i + 1) % lines.size()];
        if (!intersectLines(a.point, a.direction, b.point, b.direction, polygon[i]))
            throw std::invalid_argument("polygonFromTangentLines: tangent lines " +
                                        std::to_string(i) + " and " +
                                        std::to_string((i + 1) % lines.size()) + " are parallel");
    }
    return polygon;
}

InverseChaikinResult inverseChaikin(const Polyline2& input, const InverseChaikinOptions& options) {
    if (!(options.imbalanceThreshold > 0) || options.maxCorrectionRounds < 0 ||
        !(options.splitTurn > 0))
        throw std::invalid_argument("inverseChaikin: invalid options");
    const ClosedCurve curve(input, options.resampleCount, "inverseChaikin");
    const int n = curve.size();

    // 1. Tangent points: x and y extrema (tangent parallel to an axis) and inflections.
    std::vector<Tangent> candidates;
    for (int axis = 0; axis < 2; ++axis)
        for (int i = 0; i < n; ++i) {
            const double a = curve.tangent(i)[axis], b = curve.tangent(i + 1)[axis];
            if ((a > 0) != (b > 0) && a != b)
                candidates.push_back({curve.wrap(i + a / (a - b)), false, axis});
        }
    const std::vector<double> inflections = inflectionParameters(curve);
    for (double s : inflections)
        candidates.push_back({s, true});
    std::sort(candidates.begin(), candidates.end(),
              [](const Tangent& a, const Tangent& b) { return a.s < b.s; });
    // Merge candidates closer than 1% of the curve: their tangent lines nearly coincide.
    const double minGap = std::max(2.0, n / 100.0);
    std::vector<Tangent> tangents;
    for (const auto& c : candidates) {
        if (!tangents.empty() && c.s - tangents.back().s < minGap) {
            if (c.inflection) tangents.back() = c;
            continue;
        }
        tangents.push_back(c);
    }
    if (tangents.size() > 1 && tangents.front().s + n - tangents.back().s < minGap) {
        if (tangents.back().inflection) tangents.front() = {tangents.back().s - n, true};
        tangents.pop_back();
        if (tangents.front().s < 0) tangents.front().s += n;
        std::sort(tangents.begin(), tangents.end(),
                  [](const Tangent& a, const Tangent& b) { return a.s < b.s; });
    }
    if (tangents.size() < 3)
        throw std::invalid_argument("inverseChaikin: found fewer than 3 tangent points");

    auto next = [&](std::size_t k) {
        const double s = tangents[(k + 1) % tangents.size()].s;
        return k + 1 == tangents.size() ? s + n : s;
    };
    auto insertBetween = [&](std::vector<Tangent>& out, std::size_t k) {
        const Tangent& b = tangents[(k + 1) % tangents.size()];
        double s = midEdgeTangent(curve, tangents[k].s, next(k), directionOf(curve, tangents[k]),
                                  directionOf(curve, b));
        out.push_back({curve.wrap(s), false});
    };

    // 2–3. Split every corner whose tangents turn by more than splitTurn (one new tangent per
    // quadrant between axis extrema), placing the new tangent point mid-edge.
    {
        std::vector<Tangent> split;
        for (std::size_t k = 0; k < tangents.size(); ++k) {
            split.push_back(tangents[k]);
            if (angleBetween(directionOf(curve, tangents[k]),
                             directionOf(curve, tangents[(k + 1) % tangents.size()])) >
                options.splitTurn)
                insertBetween(split, k);
        }
        tangents = split;
        std::sort(tangents.begin(), tangents.end(),
                  [](const Tangent& a, const Tangent& b) { return a.s < b.s; });
    }

    // 4. d/l correction.
    InverseChaikinResult result;
    const std::size_t maxTangents = tangents.size() * 4;
    for (int round = 0;; ++round) {
        // Neighbouring tangents along a straight stretch are parallel and have no corner
        // between them: one of them says nothing the other does not.
        for (std::size_t k = 0; tangents.size() > 3 && k < tangents.size();) {
            const std::size_t j = (k + 1) % tangents.size();
            if (angleBetween(directionOf(curve, tangents[k]), directionOf(curve, tangents[j])) <
                1e-9)
                tangents.erase(tangents.begin() + std::ptrdiff_t(j > k ? j : 0));
            else
                ++k;
        }
        result.polygon = polygonOf(curve, tangents);
        const std::size_t m = tangents.size();
        // Edge k runs from vertex k−1 to vertex k; farAhead: the far vertex is vertex k.
        std::vector<double> imbalance(m);
        std::vector<char> farAhead(m);
        result.maxImbalance = 0;
        for (std::size_t k = 0; k < m; ++k) {
            const glm::dvec2 p = curve.point(tangents[k].s);
            const double l1 = glm::length(p - result.polygon[(k + m - 1) % m]);
            const double l2 = glm::length(p - result.polygon[k]);
            // Edges at inflections are left alone: the seed notes that correcting them adds
            // vertices for little gain, and their point must stay on the inflection.
            imbalance[k] = tangents[k].inflection ? 0.0 : std::abs(l2 - l1) / (l1 + l2);
            farAhead[k] = l2 > l1;
            result.maxImbalance = std::max(result.maxImbalance, imbalance[k]);
        }
        if (result.maxImbalance < options.imbalanceThreshold ||
            round >= options.maxCorrectionRounds || m >= maxTangents)
            break;
        std::vector<Tangent> corrected;
        bool changed = false;
        for (std::size_t k = 0; k < m; ++k) {
            const std::size_t j = (k + 1) % m;
            // Corner k (between tangents k and j): who has its long side there?
            const bool kLong = imbalance[k] >= options.imbalanceThreshold && farAhead[k];
            const bool jLong = imbalance[j] >= options.imbalanceThreshold && !farAhead[j];
            Tangent t = tangents[k];
            // (a) alone on the long side: slide the point toward the far vertex by d/2.
            const bool kBack = imbalance[k] >= options.imbalanceThreshold && !farAhead[k];
            const std::size_t prev = (k + m - 1) % m;
            const bool prevLong = imbalance[prev] >= options.imbalanceThreshold && farAhead[prev];
            // Extremum and inflection points stay put (they define the section's extents and
            // shape); their neighbours and cut corners do the balancing.
            const bool fixed = t.inflection || t.axis >= 0;
            // Signed slide in arc length: toward the far vertex by d/2 when alone on the long
            // side; toward a fixed extremum neighbour whose long side is alone at the shared
            // corner, which pulls that corner toward it.
            auto halfDifference = [&](std::size_t i) {
                const glm::dvec2 p = curve.point(tangents[i].s);
                const double l1 = glm::length(p - result.polygon[(i + m - 1) % m]);
                const double l2 = glm::length(p - result.polygon[i]);
                return 0.5 * std::abs(l2 - l1);
            };
            double slide = 0;
            if (!fixed && ((kLong && !jLong) || (kBack && !prevLong)))
                slide = farAhead[k] ? halfDifference(k) : -halfDifference(k);
            else if (!fixed && prevLong && !kBack && tangents[prev].axis >= 0)
                slide = -halfDifference(prev);
            else if (!fixed && jLong && !kLong && tangents[j].axis >= 0)
                slide = halfDifference(j);
            if (slide != 0) {
                const double lo = (k == 0 ? tangents[m - 1].s - n : tangents[prev].s) + minGap;
                const double hi = next(k) - minGap;
                const double s = std::clamp(t.s + slide / curve.step(), lo, hi);
                if (lo < hi && s != t.s) {
                    t.s = curve.wrap(s);
                    changed = true;
                }
            }
            corrected.push_back(t);
            // (b) both neighbours long on this corner: cut it with a new mid-edge tangent.
            if (kLong && jLong) {
                insertBetween(corrected, k);
                changed = true;
            }
        }
        if (!changed) break;
        tangents = corrected;
        std::sort(tangents.begin(), tangents.end(),
                  [](const Tangent& a, const Tangent& b) { return a.s < b.s; });
    }
    for (const auto& t : tangents)
        result.tangentPoints.push_back(curve.point(t.s));
    result.inflections = int(inflections.size());
    return result;
}

Polyline2 fitChaikinControlPolygon(const Polyline2& points, const std::vector<double>& parameters,
                                   int vertexCount) {
    if (vertexCount < 3)
        throw std::invalid_argument("fitChaikinControlPolygon: vertexCount must be at least 3");
    requireCurve(points, std::size_t(vertexCount), "fitChaikinControlPolygon");
    if (parameters.size() != points.size())
        throw std::invalid_argument("fitChaikinControlPolygon: one parameter per point needed");
    const int n = vertexCount;
    // Normal equations AᵀA P = Aᵀ D; each row of A has the three quadratic B-spline weights.
    std::vector<double> normal(std::size_t(n) * n, 0.0);
    std::vector<double> rhs(std::size_t(n) * 2, 0.0);
    for (std::size_t j = 0; j < points.size(); ++j) {
        if (!std::isfinite(parameters[j]))
            throw std::invalid_argument("fitChaikinControlPolygon: non-finite parameter");
        const SplineBasis basis = basisAt(parameters[j], n);
        for (int a = 0; a < 3; ++a) {
            rhs[2 * basis.idx[a]] += basis.w[a] * points[j].x;
            rhs[2 * basis.idx[a] + 1] += basis.w[a] * points[j].y;
            for (int b = 0; b < 3; ++b)
                normal[std::size_t(basis.idx[a]) * n + basis.idx[b]] += basis.w[a] * basis.w[b];
        }
    }
    if (!solveDense(normal, rhs, n, 2))
        throw std::invalid_argument(
            "fitChaikinControlPolygon: singular system (parameters do not cover every span)");
    Polyline2 polygon(n);
    for (int i = 0; i < n; ++i)
        polygon[i] = {rhs[2 * i], rhs[2 * i + 1]};
    return polygon;
}

Polyline2 inverseChaikinLeastSquares(const Polyline2& curve, int vertexCount, int iterations) {
    requireCurve(curve, 8, "inverseChaikinLeastSquares");
    if (vertexCount < 3 || std::size_t(vertexCount) * 2 > curve.size())
        throw std::invalid_argument(
            "inverseChaikinLeastSquares: need 3 ≤ vertexCount ≤ half the number of points");
    if (iterations < 0) throw std::invalid_argument("inverseChaikinLeastSquares: iterations < 0");
    const double total = length(curve, true);
    if (!(total > 0)) throw std::invalid_argument("inverseChaikinLeastSquares: zero-length curve");
    const int n = vertexCount;
    std::vector<double> u(curve.size());
    double walked = 0;
    for (std::size_t j = 0; j < curve.size(); ++j) {
        u[j] = n * walked / total;
        walked += glm::length(curve[(j + 1) % curve.size()] - curve[j]);
    }
    Polyline2 polygon = fitChaikinControlPolygon(curve, u, n);
    auto project = [&] {
        // Newton on (B(u) − d)·B'(u) = 0 for each point.
        for (std::size_t j = 0; j < curve.size(); ++j)
            for (int newton = 0; newton < 4; ++newton) {
                const SplineBasis basis = basisAt(u[j], n);
                const glm::dvec2& p0 = polygon[basis.idx[0]];
                const glm::dvec2& p1 = polygon[basis.idx[1]];
                const glm::dvec2& p2 = polygon[basis.idx[2]];
                const double t = basis.t;
                const glm::dvec2 b = basis.w[0] * p0 + basis.w[1] * p1 + basis.w[2] * p2;
                const glm::dvec2 d1 = -(1 - t) * p0 + (1 - 2 * t) * p1 + t * p2;
                const glm::dvec2 d2 = p0 - 2.0 * p1 + p2;
                const double g = glm::dot(b - curve[j], d1);
                const double dg = glm::dot(d1, d1) + glm::dot(b - curve[j], d2);
                if (!(dg > 0)) break;
                u[j] -= std::clamp(g / dg, -0.25, 0.25);
            }
    };
    // Gauss–Newton on points and parameters together, with the parameters eliminated (Schur
    // complement): each residual counts only along the curve normal ("tangent distance"),
    // which converges far faster than alternating fit and projection, whose parameters creep.
    for (int iteration = 0; iteration < iterations; ++iteration) {
        project();
        std::vector<double> M(std::size_t(4) * n * n, 0.0), g(std::size_t(2) * n, 0.0);
        const int m2 = 2 * n;
        for (std::size_t j = 0; j < curve.size(); ++j) {
            const SplineBasis basis = basisAt(u[j], n);
            const glm::dvec2& p0 = polygon[basis.idx[0]];
            const glm::dvec2& p1 = polygon[basis.idx[1]];
            const glm::dvec2& p2 = polygon[basis.idx[2]];
            const double t = basis.t;
            const glm::dvec2 r = basis.w[0] * p0 + basis.w[1] * p1 + basis.w[2] * p2 - curve[j];
            glm::dvec2 b = -(1 - t) * p0 + (1 - 2 * t) * p1 + t * p2;
            const double bb = glm::dot(b, b);
            if (!(bb > 0)) continue;
            // N = I − b bᵀ/|b|²
            const double N[2][2] = {{1 - b.x * b.x / bb, -b.x * b.y / bb},
                                    {-b.x * b.y / bb, 1 - b.y * b.y / bb}};
            for (int a = 0; a < 3; ++a) {
                const int ra = 2 * basis.idx[a];
                for (int k = 0; k < 2; ++k)
                    g[ra + k] += basis.w[a] * (N[k][0] * r.x + N[k][1] * r.y);
                for (int c = 0; c < 3; ++c) {
                    const int rc = 2 * basis.idx[c];
                    const double ww = basis.w[a] * basis.w[c];
                    for (int k = 0; k < 2; ++k)
                        for (int l = 0; l < 2; ++l)
                            M[std::size_t(ra + k) * m2 + rc + l] += ww * N[k][l];
                }
            }
        }
        // Small Levenberg term: sliding along the curve is (nearly) free in this metric.
        double trace = 0;
        for (int i = 0; i < m2; ++i)
            trace += M[std::size_t(i) * m2 + i];
        for (int i = 0; i < m2; ++i)
            M[std::size_t(i) * m2 + i] += 1e-6 * trace / m2;
        for (double& v : g)
            v = -v;
        if (!solveDense(M, g, m2, 1)) break;
        for (int i = 0; i < n; ++i)
            polygon[i] += glm::dvec2(g[2 * i], g[2 * i + 1]);
    }
    project();
    return polygon;
}

double differentialAreaError(const Polyline2& a, const Polyline2& b, int scanlines) {
    requireCurve(a, 3, "differentialAreaError");
    requireCurve(b, 3, "differentialAreaError");
    if (scanlines < 1) throw std::invalid_argument("differentialAreaError: scanlines < 1");
    double ymin = a[0].y, ymax = a[0].y;
    for (const auto* poly : {&a, &b})
        for (const auto& p : *poly) {
            ymin = std::min(ymin, p.y);
            ymax = std::max(ymax, p.y);
        }
    const double h = (ymax - ymin) / scanlines;
    if (!(h > 0)) throw std::invalid_argument("differentialAreaError: the shapes have no height");
    double difference = 0, unionLength = 0;
    std::vector<std::pair<double, int>> events;
    for (int line = 0; line < scanlines; ++line) {
        const double y = ymin + (line + 0.5) * h;
        events.clear();
        for (int which = 0; which < 2; ++which) {
            const Polyline2& poly = which == 0 ? a : b;
            for (std::size_t i = 0; i < poly.size(); ++i) {
                const glm::dvec2& p = poly[i];
                const glm::dvec2& q = poly[(i + 1) % poly.size()];
                if ((p.y <= y) != (q.y <= y))
                    events.push_back({p.x + (y - p.y) * (q.x - p.x) / (q.y - p.y), which});
            }
        }
        std::sort(events.begin(), events.end());
        bool inside[2] = {false, false};
        double previous = 0;
        for (const auto& [x, which] : events) {
            if (inside[0] != inside[1]) difference += x - previous;
            if (inside[0] || inside[1]) unionLength += x - previous;
            inside[which] = !inside[which];
            previous = x;
        }
    }
    if (!(unionLength > 0)) throw std::invalid_argument("differentialAreaError: empty shapes");
    return 100.0 * difference / unionLength;
}

int countInflections(const Polyline2& curve, int resampleCount) {
    const ClosedCurve resampled(curve, resampleCount, "countInflections");
    return int(inflectionParameters(resampled).size());
}

}  // namespace vsculpt::sketch
