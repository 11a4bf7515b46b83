#include "vsculpt/sketch/TeddyInflate.h"

#include "TeddyCdt.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

namespace {

double cross2(const glm::dvec2& a, const glm::dvec2& b) {
    return a.x * b.y - a.y * b.x;
}

double orient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
    return cross2(b - a, c - a);
}

std::string formatPoint(const glm::dvec2& p) {
    std::ostringstream text;
    text << '(' << p.x << ", " << p.y << ')';
    return text.str();
}

// Where closed segments [a, b] and [c, d] meet, if they do (a point of the overlap when they
// are collinear).
std::optional<glm::dvec2> segmentsMeet(const glm::dvec2& a, const glm::dvec2& b,
                                       const glm::dvec2& c, const glm::dvec2& d) {
    const double o1 = orient(a, b, c), o2 = orient(a, b, d);
    const double o3 = orient(c, d, a), o4 = orient(c, d, b);
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
        return a + (b - a) * (o3 / (o3 - o4));
    // Touching or collinear cases: an endpoint lying on the other segment.
    const auto onSegment = [](const glm::dvec2& p, const glm::dvec2& q, const glm::dvec2& r,
                              double o) {
        return o == 0.0 && std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) &&
               std::min(p.y, q.y) <= r.y && r.y <= std::max(p.y, q.y);
    };
    if (onSegment(a, b, c, o1)) return c;
    if (onSegment(a, b, d, o2)) return d;
    if (onSegment(c, d, a, o3)) return a;
    if (onSegment(c, d, b, o4)) return b;
    return std::nullopt;
}

// Throws when the closed polygon crosses or touches itself; `what` says which polygon.
void requireSimple(const Polyline2& polygon, const char* what) {
    const std::size_t n = polygon.size();
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2& a = polygon[i];
        const glm::dvec2& b = polygon[(i + 1) % n];
        // Adjacent segments share a point; they only intersect when they fold back.
        {
            const glm::dvec2& c = polygon[(i + 2) % n];
            if (orient(a, b, c) == 0.0 && glm::dot(b - a, c - b) < 0.0)
                throw std::invalid_argument(std::string("Teddy: ") + what +
                                            " folds back on itself at point " +
                                            std::to_string((i + 1) % n) + ' ' + formatPoint(b));
        }
        for (std::size_t j = i + 2; j < n; ++j) {
            if (i == 0 && j == n - 1) continue;  // adjacent through the closing segment
            const auto hit = segmentsMeet(a, b, polygon[j], polygon[(j + 1) % n]);
            if (hit)
                throw std::invalid_argument(std::string("Teddy: ") + what +
                                            " self-intersects: segment " + std::to_string(i) +
                                            " crosses segment " + std::to_string(j) + " at " +
                                            formatPoint(*hit));
        }
    }
}

// Finite, distinct consecutive points, no repeated closing point, ≥ 3 points, non-zero area,
// simple. Orientation is left as drawn.
Polyline2 validated(const Polyline2& outline) {
    Polyline2 points;
    points.reserve(outline.size());
    for (std::size_t i = 0; i < outline.size(); ++i) {
        const glm::dvec2& p = outline[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y))
            throw std::invalid_argument("Teddy: outline point " + std::to_string(i) +
                                        " is not finite");
        if (points.empty() || p != points.back()) points.push_back(p);
    }
    while (points.size() > 1 && points.back() == points.front())
        points.pop_back();
    if (points.size() < 3)
        throw std::invalid_argument("Teddy: outline needs at least 3 distinct points, got " +
                                    std::to_string(points.size()));
    glm::dvec2 lo = points[0], hi = points[0];
    for (const auto& p : points)
        lo = glm::min(lo, p), hi = glm::max(hi, p);
    const double extent = glm::length(hi - lo);
    // Points on one line enclose nothing. Otherwise simplicity first: a symmetric figure
    // eight's signed area is zero too, and "crosses itself" is what the designer can fix
    // (found by QA).
    std::size_t far = 0;
    for (std::size_t i = 1; i < points.size(); ++i)
        if (glm::distance(points[i], points[0]) > glm::distance(points[far], points[0])) far = i;
    bool onALine = true;
    for (const auto& p : points)
        onALine = onALine && std::abs(orient(points[0], points[far], p)) <= 1e-12 * extent * extent;
    if (!onALine) requireSimple(points, "outline");
    if (std::abs(signedArea(points)) <= 1e-12 * extent * extent)
        throw std::invalid_argument("Teddy: outline encloses zero area");
    requireSimple(points, "outline");
    return points;
}

Polyline2 resampleValidated(const Polyline2& points, int segments) {
    const std::size_t n = points.size();
    const double perimeter = length(points, true);
    Polyline2 result;
    result.reserve(segments);
    const double step = perimeter / segments;
    std::size_t edge = 0;
    double edgeStart = 0.0;  // arc length at points[edge]
    for (int k = 0; k < segments; ++k) {
        const double s = k * step;
        double edgeLength = glm::length(points[(edge + 1) % n] - points[edge]);
        while (edge + 1 < n && edgeStart + edgeLength < s) {
            edgeStart += edgeLength;
            ++edge;
            edgeLength = glm::length(points[(edge + 1) % n] - points[edge]);
        }
        const double t = std::clamp((s - edgeStart) / edgeLength, 0.0, 1.0);
        result.push_back(points[edge] + (points[(edge + 1) % n] - points[edge]) * t);
    }
    if (signedArea(result) < 0.0) std::reverse(result.begin() + 1, result.end());
    if (signedArea(result) == 0.0)
        throw std::invalid_argument(
            "Teddy: resampled outline encloses zero area; use a "
            "shorter edge length");
    requireSimple(result, "resampled outline (use a shorter edge length)");
    return result;
}

constexpr int kNone = -1;

// A pruned branch: the outline chain chainStart, chainStart+1, …, chainEnd (cyclic) fanned
// from one spine vertex, the midpoint of its stop edge or the centroid of the junction
// triangle that absorbed it.
struct Fan {
    std::int64_t centerKey;
    int chainStart;
    int chainEnd;
};

}  // namespace

Polyline2 resampleOutline(const Polyline2& outline, int segments) {
    if (segments < 3) throw std::invalid_argument("Teddy: resampling needs at least 3 segments");
    return resampleValidated(validated(outline), segments);
}

TeddyInflation inflateOutlineDetailed(const Polyline2& input, const TeddyParams& params) {
    if (!(params.edgeLength > 0.0) || !std::isfinite(params.edgeLength))
        throw std::invalid_argument("Teddy: edgeLength must be positive and finite");
    if (!(params.heightScale > 0.0) || !std::isfinite(params.heightScale))
        throw std::invalid_argument("Teddy: heightScale must be positive and finite");
    if (params.ellipseSegments < 1 || params.ellipseSegments > 256)
        throw std::invalid_argument("Teddy: ellipseSegments must be in [1, 256]");
    if (params.minSegments < 4 || params.minSegments > 100000)
        throw std::invalid_argument("Teddy: minSegments must be in [4, 100000]");

    const Polyline2 cleaned = validated(input);
    const double segmentsWanted = std::round(length(cleaned, true) / params.edgeLength);
    if (segmentsWanted > 100000.0)
        throw std::invalid_argument("Teddy: edgeLength gives more than 100000 outline segments");
    const int n = std::max(params.minSegments, static_cast<int>(segmentsWanted));

    TeddyInflation out;
    out.outline = resampleValidated(cleaned, n);
    const Polyline2& poly = out.outline;
    double extent = 0.0;
    for (const auto& p : poly)
        extent = std::max(extent, glm::length(p - poly[0]));
    const double minArea = 1e-14 * extent * extent;

    // --- CDT and classification -------------------------------------------------------------
    std::vector<int> loop(n);
    for (int i = 0; i < n; ++i)
        loop[i] = i;
    out.cdtTriangles = detail::triangulateLoops(poly, {loop});
    const auto& tris = out.cdtTriangles;
    const int triCount = static_cast<int>(tris.size());
    if (triCount != n - 2)
        throw std::logic_error("Teddy: CDT of a simple " + std::to_string(n) + "-gon gave " +
                               std::to_string(triCount) + " triangles");

    const auto isOutlineEdge = [n](int a, int b) {
        const int d = std::abs(a - b);
        return d == 1 || d == n - 1;
    };
    const auto edgeKey = [n](int a, int b) {
        return static_cast<std::int64_t>(std::min(a, b)) * n + std::max(a, b);
    };
    // neighbor[t][k]: triangle across local edge k (tris[t][k] → tris[t][k+1]), or kNone.
    std::vector<std::array<int, 3>> neighbor(triCount, {kNone, kNone, kNone});
    {
        std::map<std::int64_t, std::pair<int, int>> firstUse;
        for (int t = 0; t < triCount; ++t)
            for (int k = 0; k < 3; ++k) {
                const int a = tris[t][k], b = tris[t][(k + 1) % 3];
                if (isOutlineEdge(a, b)) continue;
                const auto [it, fresh] = firstUse.try_emplace(edgeKey(a, b), t, k);
                if (!fresh) {
                    neighbor[t][k] = it->second.first;
                    neighbor[it->second.first][it->second.second] = t;
                }
            }
    }
    out.classes.resize(triCount);
    for (int t = 0; t < triCount; ++t) {
        int external = 0;
        for (int k = 0; k < 3; ++k)
            external += neighbor[t][k] == kNone;
        if (external == 3) throw std::logic_error("Teddy: isolated CDT triangle");
        out.classes[t] = external == 2   ? TeddyTriangleClass::Terminal
                         : external == 1 ? TeddyTriangleClass::Sleeve
                                         : TeddyTriangleClass::Junction;
    }
    const auto& classes = out.classes;
    const auto centroid = [&](int t) {
        return (poly[tris[t][0]] + poly[tris[t][1]] + poly[tris[t][2]]) / 3.0;
    };

    // --- Chordal axis before pruning --------------------------------------------------------
    {
        std::map<std::int64_t, int> midpointIndex;
        const auto midpoint = [&](int a, int b) {
            const auto [it, fresh] = midpointIndex.try_emplace(
                edgeKey(a, b), static_cast<int>(out.chordalAxis.points.size()));
            if (fresh) out.chordalAxis.points.push_back((poly[a] + poly[b]) * 0.5);
            return it->second;
        };
        for (int t = 0; t < triCount; ++t) {
            std::vector<int> mids;
            for (int k = 0; k < 3; ++k)
                if (neighbor[t][k] != kNone)
                    mids.push_back(midpoint(tris[t][k], tris[t][(k + 1) % 3]));
            if (classes[t] == TeddyTriangleClass::Sleeve) {
                out.chordalAxis.edges.push_back({mids[0], mids[1]});
            } else if (classes[t] == TeddyTriangleClass::Junction) {
                const int center = static_cast<int>(out.chordalAxis.points.size());
                out.chordalAxis.points.push_back(centroid(t));
                for (int m : mids)
                    out.chordalAxis.edges.push_back({center, m});
            }
        }
    }

    // --- Pruning ----------------------------------------------------------------------------
    // A spine vertex is the midpoint of an internal edge (key = edge key ≥ 0) or the centroid
    // of a junction triangle (key = -(t + 1)).
    const auto junctionKey = [](int t) { return -static_cast<std::int64_t>(t) - 1; };
    const auto keyPoint = [&](std::int64_t key) {
        if (key < 0) return centroid(static_cast<int>(-key - 1));
        const int a = static_cast<int>(key / n), b = static_cast<int>(key % n);
        return (poly[a] + poly[b]) * 0.5;
    };
    // A fan is usable when every triangle (center, p_i, p_{i+1}) is counter-clockwise.
    const auto fanValid = [&](const glm::dvec2& center, int start, int end) {
        for (int i = start; i != end; i = (i + 1) % n)
            if (orient(center, poly[i], poly[(i + 1) % n]) <= minArea) return false;
        return true;
    };

    std::vector<int> owner(triCount, kNone);              // fan (region) owning a triangle
    std::set<std::pair<int, int>> absorbedJunctionEdges;  // (junction, local edge)
    std::vector<Fan> fans;
    for (int terminal = 0; terminal < triCount; ++terminal) {
        if (classes[terminal] != TeddyTriangleClass::Terminal || owner[terminal] != kNone) continue;
        const int fanId = static_cast<int>(fans.size());
        // The region's boundary crosses its open edge as tris[tri][k] → tris[tri][k+1]; the
        // region's outline chain then runs from the second of these to the first.
        struct Step {
            int tri, k, chainStart, chainEnd;
            std::size_t regionSize;
            bool valid;
        };
        std::vector<int> region{terminal};
        owner[terminal] = fanId;
        int k0 = 0;
        while (neighbor[terminal][k0] == kNone)
            ++k0;
        std::vector<Step> steps;
        {
            const int x = tris[terminal][k0], y = tris[terminal][(k0 + 1) % 3];
            steps.push_back({terminal, k0, y, x, 1, true});
        }
        std::optional<Fan> junctionFan;
        while (true) {
            const Step cur = steps.back();
            const int x = tris[cur.tri][cur.k], y = tris[cur.tri][(cur.k + 1) % 3];
            const int next = neighbor[cur.tri][cur.k];
            if (owner[next] != kNone || classes[next] == TeddyTriangleClass::Terminal) break;
            // Diameter-circle test on the chain's inner vertices.
            const glm::dvec2 mid = (poly[x] + poly[y]) * 0.5;
            const double radius2 = glm::dot(poly[x] - mid, poly[x] - mid) * (1.0 + 1e-9);
            bool inside = true;
            for (int i = (cur.chainStart + 1) % n; i != cur.chainEnd && inside; i = (i + 1) % n)
                inside = glm::dot(poly[i] - mid, poly[i] - mid) <= radius2;
            if (!inside) break;
            int kk = 0;
            while (tris[next][kk] != y)
                ++kk;  // next = (y, x, w), local edge kk = y → x
            if (classes[next] == TeddyTriangleClass::Junction) {
                if (fanValid(centroid(next), cur.chainStart, cur.chainEnd)) {
                    junctionFan = Fan{junctionKey(next), cur.chainStart, cur.chainEnd};
                    absorbedJunctionEdges.insert({next, kk});
                }
                break;
            }
            owner[next] = fanId;
            region.push_back(next);
            const int w = tris[next][(kk + 2) % 3];
            Step step{};
            if (neighbor[next][(kk + 1) % 3] == kNone)  // x → w is on the outline
                step = {next, (kk + 2) % 3, cur.chainStart, w, region.size(), false};
            else  // w → y is on the outline
                step = {next, (kk + 1) % 3, w, cur.chainEnd, region.size(), false};
            step.valid =
                fanValid((poly[tris[next][step.k]] + poly[tris[next][(step.k + 1) % 3]]) * 0.5,
                         step.chainStart, step.chainEnd);
            steps.push_back(step);
        }
        if (junctionFan) {
            fans.push_back(*junctionFan);
            continue;
        }
        // Stop at the last edge whose fan is valid; give back the triangles beyond it.
        while (!steps.back().valid)
            steps.pop_back();
        const Step& stop = steps.back();
        for (std::size_t i = stop.regionSize; i < region.size(); ++i)
            owner[region[i]] = kNone;
        fans.push_back({edgeKey(tris[stop.tri][stop.k], tris[stop.tri][(stop.k + 1) % 3]),
                        stop.chainStart, stop.chainEnd});
    }

    // --- Flat triangulation along the spine -------------------------------------------------
    out.flatVertices = poly;
    std::map<std::int64_t, int> spineIndex;  // key → flat vertex index
    const auto spineVertex = [&](std::int64_t key) {
        const auto [it, fresh] =
            spineIndex.try_emplace(key, static_cast<int>(out.flatVertices.size()));
        if (fresh) {
            out.flatVertices.push_back(keyPoint(key));
            out.spine.points.push_back(out.flatVertices.back());
        }
        return it->second;
    };
    auto& flat = out.flatTriangles;
    for (const Fan& fan : fans) {
        const int c = spineVertex(fan.centerKey);
        for (int i = fan.chainStart; i != fan.chainEnd; i = (i + 1) % n)
            flat.push_back({c, i, (i + 1) % n});
    }
    const int base = n;  // spine.points[i] is flat vertex base + i
    for (int t = 0; t < triCount; ++t) {
        if (owner[t] != kNone) continue;
        const auto& v = tris[t];
        if (classes[t] == TeddyTriangleClass::Sleeve) {
            int k = 0;
            while (neighbor[t][k] != kNone)
                ++k;  // v[k] → v[k+1] is the outline edge
            const int a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
            const int m1 = spineVertex(edgeKey(b, c)), m2 = spineVertex(edgeKey(c, a));
            flat.push_back({m1, c, m2});
            const auto& fv = out.flatVertices;
            if (glm::length(fv[a] - fv[m1]) <= glm::length(fv[b] - fv[m2])) {
                flat.push_back({a, b, m1});
                flat.push_back({a, m1, m2});
            } else {
                flat.push_back({a, b, m2});
                flat.push_back({b, m1, m2});
            }
            out.spine.edges.push_back({m1 - base, m2 - base});
        } else if (classes[t] == TeddyTriangleClass::Junction) {
            const int g = spineVertex(junctionKey(t));
            for (int k = 0; k < 3; ++k) {
                if (absorbedJunctionEdges.count({t, k})) continue;
                const int x = v[k], y = v[(k + 1) % 3];
                const int m = spineVertex(edgeKey(x, y));
                flat.push_back({g, x, m});
                flat.push_back({g, m, y});
                out.spine.edges.push_back({g - base, m - base});
            }
        } else {
            throw std::logic_error("Teddy: a terminal triangle escaped pruning");
        }
    }

    // --- Spine heights ----------------------------------------------------------------------
    const int spineCount = static_cast<int>(out.spine.points.size());
    std::vector<std::set<int>> joined(spineCount);
    for (const auto& tri : flat)
        for (int s : tri)
            if (s >= base)
                for (int p : tri)
                    if (p < base) joined[s - base].insert(p);
    out.spineHeights.resize(spineCount);
    for (int s = 0; s < spineCount; ++s) {
        if (joined[s].empty()) throw std::logic_error("Teddy: spine vertex without perimeter");
        double sum = 0.0;
        for (int p : joined[s])
            sum += glm::length(poly[p] - out.spine.points[s]);
        out.spineHeights[s] = params.heightScale * sum / static_cast<double>(joined[s].size());
    }

    // --- Lift and sew -----------------------------------------------------------------------
    // Mesh vertices: outline (z = 0), front spine, back spine, then front/back samples of
    // each lifted spine-to-perimeter edge.
    const int segs = params.ellipseSegments;
    PolyMesh& mesh = out.mesh;
    for (const auto& p : poly)
        mesh.vertices.push_back({p.x, p.y, 0.0});
    for (int s = 0; s < spineCount; ++s)
        mesh.vertices.push_back({out.spine.points[s], out.spineHeights[s]});
    for (int s = 0; s < spineCount; ++s)
        mesh.vertices.push_back({out.spine.points[s], -out.spineHeights[s]});
    // (spine flat index, perimeter index) → index of the first front sample; front sample j
    // (1 ≤ j < segs) is at first + 2(j − 1), its mirror right after it.
    std::map<std::pair<int, int>, int> samples;
    const auto level = [&](int s, int p, int j, bool front) {
        if (j == 0) return n + (s - base) + (front ? 0 : spineCount);
        if (j == segs) return p;
        auto it = samples.find({s, p});
        if (it == samples.end()) {
            const int first = static_cast<int>(mesh.vertices.size());
            const glm::dvec2 from = out.flatVertices[s], to = poly[p];
            const double h = out.spineHeights[s - base];
            for (int q = 1; q < segs; ++q) {
                const double theta = 0.5 * std::numbers::pi * q / segs;
                const glm::dvec2 xy = from + (to - from) * std::sin(theta);
                mesh.vertices.push_back({xy, h * std::cos(theta)});
                mesh.vertices.push_back({xy, -h * std::cos(theta)});
            }
            it = samples.emplace(std::make_pair(s, p), first).first;
        }
        return it->second + 2 * (j - 1) + (front ? 0 : 1);
    };
    const auto emit = [&](int a, int b, int c, bool front) {
        if (front)
            mesh.faces.push_back({a, b, c});
        else
            mesh.faces.push_back({a, c, b});
    };
    for (auto tri : flat) {
        const int spines = (tri[0] >= base) + (tri[1] >= base) + (tri[2] >= base);
        for (const bool front : {true, false}) {
            if (spines == 1) {
                while (tri[0] < base)
                    std::rotate(tri.begin(), tri.begin() + 1, tri.end());
                const int s = tri[0], p1 = tri[1], p2 = tri[2];
                emit(level(s, p1, 0, front), level(s, p1, 1, front), level(s, p2, 1, front), front);
                for (int j = 1; j < segs; ++j) {
                    emit(level(s, p1, j, front), level(s, p1, j + 1, front),
                         level(s, p2, j + 1, front), front);
                    emit(level(s, p1, j, front), level(s, p2, j + 1, front), level(s, p2, j, front),
                         front);
                }
            } else if (spines == 2) {
                while (tri[2] >= base)
                    std::rotate(tri.begin(), tri.begin() + 1, tri.end());
                const int s1 = tri[0], s2 = tri[1], p = tri[2];
                for (int j = 0; j + 1 < segs; ++j) {
                    emit(level(s1, p, j, front), level(s2, p, j, front), level(s2, p, j + 1, front),
                         front);
                    emit(level(s1, p, j, front), level(s2, p, j + 1, front),
                         level(s1, p, j + 1, front), front);
                }
                emit(level(s1, p, segs - 1, front), level(s2, p, segs - 1, front), p, front);
            } else {
                throw std::logic_error("Teddy: flat triangle with " + std::to_string(spines) +
                                       " spine vertices");
            }
        }
    }
    return out;
}

PolyMesh inflateOutline(const Polyline2& outline, const TeddyParams& params) {
    return inflateOutlineDetailed(outline, params).mesh;
}

}  // namespace vsculpt::sketch
