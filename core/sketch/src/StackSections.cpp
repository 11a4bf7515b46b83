#include "vsculpt/sketch/StackSections.h"

#include "vsculpt/sketch/Prism.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

// Angle of b relative to a, in [0, 2π).
double ccwFrom(double a, double b) {
    double d = std::fmod(b - a, kTwoPi);
    return d < 0 ? d + kTwoPi : d;
}

Polyline2 counterClockwise(Polyline2 polygon) {
    if (signedArea(polygon) < 0) std::reverse(polygon.begin(), polygon.end());
    return polygon;
}

}  // namespace

std::vector<SectorRun> sectorCorrespondence(const Polyline2& aIn, const Polyline2& bIn) {
    requireSimplePolygon(aIn, "sectorCorrespondence");
    requireSimplePolygon(bIn, "sectorCorrespondence");
    if (aIn.size() > bIn.size())
        throw std::invalid_argument(
            "sectorCorrespondence: ring a must not have more vertices than b");
    if (signedArea(aIn) < 0 || signedArea(bIn) < 0)
        throw std::invalid_argument("sectorCorrespondence: rings must be counter-clockwise");
    const Polyline2& a = aIn;
    const Polyline2& b = bIn;
    const int na = int(a.size()), nb = int(b.size());
    const glm::dvec2 ga = areaCentroid(a), gb = areaCentroid(b);
    std::vector<double> angleA(na), angleB(nb);
    for (int i = 0; i < na; ++i)
        angleA[i] = std::atan2(a[i].y - ga.y, a[i].x - ga.x);
    for (int j = 0; j < nb; ++j)
        angleB[j] = std::atan2(b[j].y - gb.y, b[j].x - gb.x);
    // Sector i starts at the bisector between rays i−1 and i.
    std::vector<double> sectorStart(na);
    for (int i = 0; i < na; ++i) {
        const double previous = angleA[(i + na - 1) % na];
        sectorStart[i] = previous + 0.5 * ccwFrom(previous, angleA[i]);
    }
    std::vector<int> owner(nb);
    for (int j = 0; j < nb; ++j) {
        owner[j] = -1;
        for (int i = 0; i < na; ++i) {
            const double width = ccwFrom(sectorStart[i], sectorStart[(i + 1) % na]);
            if (ccwFrom(sectorStart[i], angleB[j]) < width || (na == 1)) {
                owner[j] = i;
                break;
            }
        }
        if (owner[j] < 0) owner[j] = 0;  // rounding at a bisector
    }
    // Runs: start at a b-vertex whose owner differs from its predecessor's, then owners must
    // never go backwards around a.
    int startJ = 0;
    for (int j = 0; j < nb; ++j)
        if (owner[j] != owner[(j + nb - 1) % nb]) {
            startJ = j;
            break;
        }
    std::vector<SectorRun> runs(na, SectorRun{-1, 0});
    const int firstOwner = owner[startJ];
    int previousOffset = 0;
    for (int k = 0; k < nb; ++k) {
        const int j = (startJ + k) % nb;
        const int offset = (owner[j] - firstOwner + na) % na;
        if (offset < previousOffset)
            throw std::invalid_argument(
                "sectorCorrespondence: the rings are not star-shaped about their centroids");
        previousOffset = offset;
        if (runs[owner[j]].count++ == 0) runs[owner[j]].first = j;
    }
    // Empty sectors take the first index of the next run.
    for (int k = na - 1; k >= 0; --k) {
        const int i = (firstOwner + k) % na;
        if (runs[i].count == 0) runs[i].first = runs[(i + 1) % na].first;
    }
    // Fill empty sectors from the nearest sector holding two or more, shifting one vertex
    // through each sector in between.
    for (int i = 0; i < na; ++i) {
        if (runs[i].count > 0) continue;
        int best = -1, direction = 0;
        for (int d = 1; d < na && best < 0; ++d) {
            const int right = (i + d) % na, left = (i - d + na) % na;
            const bool rightOk = runs[right].count >= 2, leftOk = runs[left].count >= 2;
            if (rightOk && (!leftOk || runs[right].count >= runs[left].count)) {
                best = right;
                direction = +1;
            } else if (leftOk) {
                best = left;
                direction = -1;
            }
        }
        if (best < 0) throw std::logic_error("sectorCorrespondence: no donor sector");
        if (direction > 0) {
            // Each sector from best back to i+1 hands its first vertex to its predecessor.
            for (int s = best; s != i; s = (s - 1 + na) % na) {
                const int p = (s - 1 + na) % na;
                runs[s].first = (runs[s].first + 1) % nb;
                --runs[s].count;
                ++runs[p].count;
            }
        } else {
            // Each sector from best forward to i−1 hands its last vertex to its successor.
            for (int s = best; s != i; s = (s + 1) % na) {
                const int q = (s + 1) % na;
                --runs[s].count;
                runs[q].first = (runs[q].first - 1 + nb) % nb;
                ++runs[q].count;
            }
        }
    }
    return runs;
}

PolyMesh stackSections(std::vector<StackedSection> sections) {
    if (sections.empty()) throw std::invalid_argument("stackSections: no sections");
    for (auto& s : sections) {
        requireSimplePolygon(s.polygon, "stackSections");
        if (!std::isfinite(s.z) || !std::isfinite(s.halfHeight) || !(s.halfHeight > 0))
            throw std::invalid_argument("stackSections: z must be finite and halfHeight > 0");
        s.polygon = counterClockwise(s.polygon);
    }
    std::sort(sections.begin(), sections.end(),
              [](const StackedSection& a, const StackedSection& b) { return a.z < b.z; });
    for (std::size_t k = 1; k < sections.size(); ++k)
        if (!(sections[k - 1].z + sections[k - 1].halfHeight <
              sections[k].z - sections[k].halfHeight))
            throw std::invalid_argument("stackSections: prisms " + std::to_string(k - 1) + " and " +
                                        std::to_string(k) + " overlap");
    PolyMesh mesh;
    std::vector<int> bottomStart, topStart;
    for (const auto& s : sections) {
        const int n = int(s.polygon.size());
        bottomStart.push_back(int(mesh.vertices.size()));
        for (const auto& p : s.polygon)
            mesh.vertices.push_back({p.x, p.y, s.z - s.halfHeight});
        topStart.push_back(int(mesh.vertices.size()));
        for (const auto& p : s.polygon)
            mesh.vertices.push_back({p.x, p.y, s.z + s.halfHeight});
        const int b = bottomStart.back(), t = topStart.back();
        for (int i = 0; i < n; ++i)
            mesh.faces.push_back({b + i, b + (i + 1) % n, t + (i + 1) % n, t + i});
    }
    // Caps.
    {
        std::vector<int> bottom;
        const int n = int(sections.front().polygon.size());
        for (int i = n - 1; i >= 0; --i)
            bottom.push_back(bottomStart.front() + i);
        mesh.faces.push_back(bottom);
        std::vector<int> top;
        const int m = int(sections.back().polygon.size());
        for (int i = 0; i < m; ++i)
            top.push_back(topStart.back() + i);
        mesh.faces.push_back(top);
    }
    // Bands between the top ring of section k and the bottom ring of section k + 1.
    for (std::size_t k = 0; k + 1 < sections.size(); ++k) {
        const Polyline2& lower = sections[k].polygon;
        const Polyline2& upper = sections[k + 1].polygon;
        const bool lowerIsA = lower.size() <= upper.size();
        const Polyline2& a = lowerIsA ? lower : upper;
        const Polyline2& b = lowerIsA ? upper : lower;
        const int aBase = lowerIsA ? topStart[k] : bottomStart[k + 1];
        const int bBase = lowerIsA ? bottomStart[k + 1] : topStart[k];
        const int na = int(a.size()), nb = int(b.size());
        const std::vector<SectorRun> runs = sectorCorrespondence(a, b);
        for (int i = 0; i < na; ++i) {
            const SectorRun run = runs[i];
            const int last = (run.first + run.count - 1) % nb;
            const int nextFirst = runs[(i + 1) % na].first;
            std::vector<int> fan;
            if (lowerIsA) {
                // Lower ring a: (a_i, a_i+1, b_nextFirst, b_last) and fan (a_i, b_last … b_first).
                mesh.faces.push_back(
                    {aBase + i, aBase + (i + 1) % na, bBase + nextFirst, bBase + last});
                if (run.count >= 2) {
                    fan.push_back(aBase + i);
                    for (int c = run.count - 1; c >= 0; --c)
                        fan.push_back(bBase + (run.first + c) % nb);
                }
            } else {
                mesh.faces.push_back(
                    {bBase + last, bBase + nextFirst, aBase + (i + 1) % na, aBase + i});
                if (run.count >= 2) {
                    for (int c = 0; c < run.count; ++c)
                        fan.push_back(bBase + (run.first + c) % nb);
                    fan.push_back(aBase + i);
                }
            }
            if (!fan.empty()) mesh.faces.push_back(fan);
        }
    }
    return mesh;
}

}  // namespace vsculpt::sketch
