#include "vsculpt/sketch/ExtrudeMesh.h"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

namespace {

constexpr double kMinViewAngleSine = 0.2;

bool finite3(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void requireFiniteStroke(const Polyline2& stroke, const char* what) {
    for (const auto& p : stroke)
        if (!std::isfinite(p.x) || !std::isfinite(p.y))
            throw std::invalid_argument(std::string("extrudeMesh: the ") + what +
                                        " stroke has a non-finite point");
}

glm::dvec3 towardViewer(const SketchView& view) {
    if (!finite3(view.origin) || !finite3(view.right) || !finite3(view.up) ||
        std::abs(glm::length(view.right) - 1.0) > 1e-9 ||
        std::abs(glm::length(view.up) - 1.0) > 1e-9 ||
        std::abs(glm::dot(view.right, view.up)) > 1e-9)
        throw std::invalid_argument("extrudeMesh: view right/up must be finite and orthonormal");
    return glm::cross(view.right, view.up);
}

// Even–odd point-in-polygon test; the polygon's last point joins its first.
bool insidePolygon(const Polyline2& polygon, const glm::dvec2& p) {
    bool inside = false;
    for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
        const glm::dvec2 &a = polygon[i], &b = polygon[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (b.x - a.x) * (p.y - a.y) / (b.y - a.y))
            inside = !inside;
    }
    return inside;
}

// Points every `step` along the polyline, keeping both ends.
Polyline3 resample(const Polyline3& line, double step) {
    const double total = length(line, false);
    const int segments = std::max(2, static_cast<int>(std::round(total / step)));
    Polyline3 out;
    std::size_t edge = 0;
    double edgeStart = 0.0;
    for (int k = 0; k <= segments; ++k) {
        const double s = total * k / segments;
        double edgeLength = glm::length(line[edge + 1] - line[edge]);
        while (edge + 2 < line.size() && edgeStart + edgeLength < s) {
            edgeStart += edgeLength;
            ++edge;
            edgeLength = glm::length(line[edge + 1] - line[edge]);
        }
        const double t = edgeLength > 0 ? std::clamp((s - edgeStart) / edgeLength, 0.0, 1.0) : 0.0;
        out.push_back(line[edge] + (line[edge + 1] - line[edge]) * t);
    }
    return out;
}

}  // namespace

glm::dvec3 newellNormal(const Polyline3& loop) {
    glm::dvec3 sum(0.0);
    for (std::size_t i = 0; i < loop.size(); ++i)
        sum += glm::cross(loop[i], loop[(i + 1) % loop.size()]);
    return 0.5 * sum;
}

std::vector<int> facesInsideStroke(const PolyMesh& mesh, const Polyline2& stroke,
                                   const SketchView& view) {
    const glm::dvec3 c = towardViewer(view);
    if (stroke.size() < 3)
        throw std::invalid_argument("extrudeMesh: the base stroke needs at least 3 points");
    requireFiniteStroke(stroke, "base");
    std::vector<int> faces;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        Polyline3 corners;
        glm::dvec3 centroid(0.0);
        for (int v : mesh.faces[f]) {
            corners.push_back(mesh.vertices[v]);
            centroid += mesh.vertices[v];
        }
        centroid /= static_cast<double>(corners.size());
        if (glm::dot(newellNormal(corners), c) <= 0.0) continue;
        const glm::dvec2 screen{glm::dot(centroid - view.origin, view.right),
                                glm::dot(centroid - view.origin, view.up)};
        if (insidePolygon(stroke, screen)) faces.push_back(static_cast<int>(f));
    }
    return faces;
}

Extrusion extrudeRegion(const PolyMesh& input, const std::vector<int>& region,
                        const Polyline2& silhouette, const SketchView& view,
                        const ExtrudeParams& params) {
    const glm::dvec3 c = towardViewer(view);
    if (!(params.stepLength > 0.0) || !std::isfinite(params.stepLength))
        throw std::invalid_argument("extrudeMesh: stepLength must be positive and finite");
    if (!isClosedOriented(input))
        throw std::invalid_argument(
            "extrudeMesh: the mesh is not closed and consistently oriented");
    requireFiniteStroke(silhouette, "silhouette");
    const std::set<int> regionSet(region.begin(), region.end());
    if (regionSet.empty()) throw std::invalid_argument("extrudeMesh: the base region is empty");
    if (regionSet.size() >= input.faces.size())
        throw std::invalid_argument("extrudeMesh: the base region is the whole mesh");
    for (int f : regionSet)
        if (f < 0 || f >= static_cast<int>(input.faces.size()))
            throw std::invalid_argument("extrudeMesh: base face index out of range");

    // Region boundary: its directed edges whose reverse belongs to a face outside it.
    std::map<std::pair<int, int>, int> regionEdges;  // directed edge → count
    std::set<int> regionVertices;
    for (int f : regionSet) {
        const auto& face = input.faces[f];
        for (std::size_t k = 0; k < face.size(); ++k) {
            ++regionEdges[{face[k], face[(k + 1) % face.size()]}];
            regionVertices.insert(face[k]);
        }
    }
    std::map<int, int> next;  // boundary, in the region's own (counter-clockwise) direction
    std::size_t undirected = 0;
    for (const auto& [edge, uses] : regionEdges) {
        if (!regionEdges.count({edge.second, edge.first})) {
            if (!next.emplace(edge.first, edge.second).second)
                throw std::invalid_argument(
                    "extrudeMesh: the base region's boundary touches itself at a vertex");
            ++undirected;
        } else if (edge.first < edge.second) {
            ++undirected;
        }
    }
    const long euler = static_cast<long>(regionVertices.size()) - static_cast<long>(undirected) +
                       static_cast<long>(regionSet.size());
    if (next.empty() || euler != 1)
        throw std::invalid_argument(
            "extrudeMesh: the base region is not a disk (Euler "
            "characteristic " +
            std::to_string(euler) + ")");
    std::vector<int> loop;
    {
        int v = next.begin()->first;
        do {
            loop.push_back(v);
            v = next.at(v);
        } while (v != loop.front() && loop.size() <= next.size());
        if (loop.size() != next.size())
            throw std::invalid_argument("extrudeMesh: the base region has several boundary loops");
    }

    // Keep the faces outside the region and the vertices they use (base loop included).
    Extrusion out;
    PolyMesh& mesh = out.mesh;
    std::vector<int> remap(input.vertices.size(), -1);
    const auto keep = [&](int v) {
        if (remap[v] < 0) {
            remap[v] = static_cast<int>(mesh.vertices.size());
            mesh.vertices.push_back(input.vertices[v]);
        }
        return remap[v];
    };
    for (std::size_t f = 0; f < input.faces.size(); ++f) {
        if (regionSet.count(static_cast<int>(f))) continue;
        std::vector<int> face;
        for (int v : input.faces[f])
            face.push_back(keep(v));
        mesh.faces.push_back(face);
    }
    Polyline3 base;
    for (int v : loop) {
        out.baseLoop.push_back(keep(v));
        base.push_back(input.vertices[v]);
    }

    // Sweep plane through the base centroid, containing the base normal, facing the viewer.
    out.baseNormal = newellNormal(base);
    if (glm::length(out.baseNormal) == 0.0)
        throw std::invalid_argument("extrudeMesh: the base loop encloses no area");
    const glm::dvec3 v = glm::normalize(out.baseNormal);
    glm::dvec3 g(0.0);
    for (const auto& p : base)
        g += p;
    g /= static_cast<double>(base.size());
    const glm::dvec3 planeNormal = c - glm::dot(c, v) * v;
    // Casting onto the plane magnifies depth by 1 / sin(angle between view and base normal);
    // below ~11.5° (sin < 0.2) a small wobble of the pen becomes a long spike.
    if (glm::length(planeNormal) < kMinViewAngleSine)
        throw std::invalid_argument(
            "extrudeMesh: the view looks almost straight along the base normal (within "
            "11.5 degrees); rotate before drawing the silhouette");
    out.sweepPlanePoint = g;
    out.sweepPlaneNormal = glm::normalize(planeNormal);

    // Cast the silhouette stroke along the view onto the plane.
    Polyline3 projected;
    for (const auto& p : silhouette) {
        const glm::dvec3 origin = view.origin + p.x * view.right + p.y * view.up;
        const double t =
            glm::dot(out.sweepPlaneNormal, g - origin) / glm::dot(out.sweepPlaneNormal, c);
        const glm::dvec3 q = origin + t * c;
        if (projected.empty() || q != projected.back()) projected.push_back(q);
    }
    if (projected.size() < 2)
        throw std::invalid_argument("extrudeMesh: the silhouette stroke needs 2 distinct points");
    out.sweepStroke = resample(projected, params.stepLength);
    const Polyline3& s = out.sweepStroke;
    const int last = static_cast<int>(s.size()) - 1;

    // Two pointers moving inward.
    const auto tangent = [&](int k) {
        const glm::dvec3 d = s[std::min(k + 1, last)] - s[std::max(k - 1, 0)];
        return glm::length(d) > 0 ? glm::normalize(d) : d;
    };
    const auto obliqueness = [&](int a, int b) {
        const glm::dvec3 d = s[b] - s[a];
        if (glm::length(d) == 0.0) return 2.0;
        const glm::dvec3 u = glm::normalize(d);
        return std::abs(glm::dot(u, tangent(a))) + std::abs(glm::dot(u, tangent(b)));
    };
    int i = 0, j = last;
    out.pointerPairs.push_back({i, j});
    while (j - i > 1) {
        if (obliqueness(i + 1, j) <= obliqueness(i, j - 1))
            ++i;
        else
            --j;
        out.pointerPairs.push_back({i, j});
    }

    // Copies of the base loop, one per pointer pair after the first. The base loop's width
    // is measured across the silhouette, along w (in the sweep plane, perpendicular to v).
    const glm::dvec3 sweepNormal = out.sweepPlaneNormal;
    const glm::dvec3 w = glm::normalize(glm::cross(sweepNormal, v));
    double lo = glm::dot(base[0] - g, w), hi = lo;
    for (const auto& b : base) {
        lo = std::min(lo, glm::dot(b - g, w));
        hi = std::max(hi, glm::dot(b - g, w));
    }
    if (hi - lo <= 0.0)
        throw std::invalid_argument(
            "extrudeMesh: the base loop has no extent across the "
            "silhouette");
    const double centre = 0.5 * (lo + hi);
    std::vector<int> previous = out.baseLoop;
    const int n = static_cast<int>(loop.size());
    out.firstNewFace = mesh.faces.size();
    const auto quad = [&](int a, int b, int c2, int d) {
        mesh.faces.push_back({a, b, c2});
        mesh.faces.push_back({a, c2, d});
    };
    for (std::size_t pair = 1; pair < out.pointerPairs.size(); ++pair) {
        const glm::dvec3 p = s[out.pointerPairs[pair].first], q = s[out.pointerPairs[pair].second];
        const glm::dvec3 mid = 0.5 * (p + q);
        const double width = glm::length(q - p);
        if (width == 0.0) break;
        // Turn the copy about the sweep-plane normal so its width direction w lies along the
        // pointer segment (the nearer of its two directions): both pointers are then on the
        // copy's silhouette, and a bent stroke gives a bent protrusion, not a sheared one.
        glm::dvec3 u = (q - p) / width;
        if (glm::dot(u, w) < 0.0) u = -u;
        const double cosTurn = glm::dot(w, u);
        const double sinTurn = glm::dot(sweepNormal, glm::cross(w, u));
        const auto turn = [&](const glm::dvec3& x) {
            return x * cosTurn + glm::cross(sweepNormal, x) * sinTurn +
                   sweepNormal * glm::dot(sweepNormal, x) * (1.0 - cosTurn);
        };
        const double scale = width / (hi - lo);
        std::vector<int> ring;
        for (const auto& b : base) {
            ring.push_back(static_cast<int>(mesh.vertices.size()));
            mesh.vertices.push_back(mid + scale * turn(b - g - centre * w));
        }
        // The kept faces use the base loop backwards; the tube uses it forwards.
        for (int k = 0; k < n; ++k)
            quad(previous[k], previous[(k + 1) % n], ring[(k + 1) % n], ring[k]);
        previous = ring;
    }
    const auto& lastPair = out.pointerPairs.back();
    const int tip = static_cast<int>(mesh.vertices.size());
    mesh.vertices.push_back(0.5 * (s[lastPair.first] + s[lastPair.second]));
    for (int k = 0; k < n; ++k)
        mesh.faces.push_back({previous[k], previous[(k + 1) % n], tip});
    return out;
}

Extrusion extrudeMesh(const PolyMesh& mesh, const Polyline2& baseStroke, const SketchView& baseView,
                      const Polyline2& silhouette, const SketchView& silhouetteView,
                      const ExtrudeParams& params) {
    const std::vector<int> region = facesInsideStroke(mesh, baseStroke, baseView);
    if (region.empty())
        throw std::invalid_argument("extrudeMesh: the base stroke encloses no visible face");
    return extrudeRegion(mesh, region, silhouette, silhouetteView, params);
}

}  // namespace vsculpt::sketch
