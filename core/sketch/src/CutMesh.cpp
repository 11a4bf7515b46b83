#include "vsculpt/sketch/CutMesh.h"

#include "TeddyCdt.h"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace vsculpt::sketch {

namespace {

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void requireView(const SketchView& view) {
    if (!finite(view.origin) || !finite(view.right) || !finite(view.up) ||
        std::abs(glm::length(view.right) - 1.0) > 1e-9 ||
        std::abs(glm::length(view.up) - 1.0) > 1e-9 ||
        std::abs(glm::dot(view.right, view.up)) > 1e-9)
        throw std::invalid_argument("cutMesh: view right/up must be finite and orthonormal");
}

glm::dvec3 toWorld(const SketchView& view, const glm::dvec2& p) {
    return view.origin + p.x * view.right + p.y * view.up;
}

glm::dvec2 toScreen(const SketchView& view, const glm::dvec3& p) {
    return {glm::dot(p - view.origin, view.right), glm::dot(p - view.origin, view.up)};
}

// True when p lies in (or on) the triangle, whatever the triangle's orientation.
bool inTriangle(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b,
                const glm::dvec2& c) {
    const auto side = [](const glm::dvec2& u, const glm::dvec2& v, const glm::dvec2& w) {
        return (v.x - u.x) * (w.y - u.y) - (v.y - u.y) * (w.x - u.x);
    };
    const double d1 = side(a, b, p), d2 = side(b, c, p), d3 = side(c, a, p);
    const bool hasNeg = d1 < 0 || d2 < 0 || d3 < 0;
    const bool hasPos = d1 > 0 || d2 > 0 || d3 > 0;
    return !(hasNeg && hasPos);
}

bool insideSilhouette(const PolyMesh& mesh, const SketchView& view, const glm::dvec2& p) {
    for (const auto& face : mesh.faces) {
        const glm::dvec2 a = toScreen(view, mesh.vertices[face[0]]);
        for (std::size_t i = 1; i + 1 < face.size(); ++i)
            if (inTriangle(p, a, toScreen(view, mesh.vertices[face[i]]),
                           toScreen(view, mesh.vertices[face[i + 1]])))
                return true;
    }
    return false;
}

}  // namespace

CutPlane cutPlaneFromStroke(const Polyline2& stroke, const SketchView& view) {
    requireView(view);
    if (stroke.size() < 2)
        throw std::invalid_argument("cutMesh: the cutting stroke needs at least 2 points");
    for (const auto& p : stroke)
        if (!std::isfinite(p.x) || !std::isfinite(p.y))
            throw std::invalid_argument("cutMesh: the cutting stroke has a non-finite point");
    const glm::dvec2 chord = stroke.back() - stroke.front();
    if (glm::length(chord) == 0.0)
        throw std::invalid_argument("cutMesh: the cutting stroke starts and ends at one point");
    // Left of the stroke direction on screen, (−t.y, t.x), is the discarded side.
    const glm::dvec3 left = -chord.y * view.right + chord.x * view.up;
    return {toWorld(view, stroke.front()), glm::normalize(left)};
}

MeshCut cutMeshByPlane(const PolyMesh& input, const CutPlane& plane) {
    if (!finite(plane.point) || !finite(plane.normal) || glm::length(plane.normal) == 0.0)
        throw std::invalid_argument("cutMesh: the cut plane is not finite");
    if (!isClosedOriented(input))
        throw std::invalid_argument("cutMesh: the mesh is not closed and consistently oriented");
    const glm::dvec3 normal = glm::normalize(plane.normal);
    glm::dvec3 lo = input.vertices.empty() ? glm::dvec3(0) : input.vertices[0], hi = lo;
    for (const auto& v : input.vertices) {
        if (!finite(v)) throw std::invalid_argument("cutMesh: the mesh has a non-finite vertex");
        lo = glm::min(lo, v), hi = glm::max(hi, v);
    }
    const double snap = 1e-9 * glm::length(hi - lo);

    // Signed distances; vertices close to the plane are moved onto it so that slivers do not
    // appear and the cap is exactly planar.
    std::vector<glm::dvec3> positions = input.vertices;
    std::vector<double> distance(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i) {
        distance[i] = glm::dot(normal, positions[i] - plane.point);
        if (std::abs(distance[i]) <= snap) {
            positions[i] -= distance[i] * normal;
            distance[i] = 0.0;
        }
    }

    MeshCut result;
    result.plane = {plane.point, normal};
    PolyMesh& mesh = result.mesh;
    std::vector<int> keptIndex(positions.size(), -1);
    std::vector<char> onPlane;  // per output vertex
    const auto keep = [&](int v) {
        if (keptIndex[v] < 0) {
            keptIndex[v] = static_cast<int>(mesh.vertices.size());
            mesh.vertices.push_back(positions[v]);
            onPlane.push_back(distance[v] == 0.0);
        }
        return keptIndex[v];
    };
    std::map<std::pair<int, int>, int> crossing;  // undirected edge → new vertex
    const auto cross = [&](int a, int b) {
        if (a > b) std::swap(a, b);
        const auto [it, fresh] =
            crossing.try_emplace({a, b}, static_cast<int>(mesh.vertices.size()));
        if (fresh) {
            const double t = distance[a] / (distance[a] - distance[b]);
            glm::dvec3 p = positions[a] + (positions[b] - positions[a]) * t;
            p -= glm::dot(normal, p - plane.point) * normal;
            mesh.vertices.push_back(p);
            onPlane.push_back(true);
        }
        return it->second;
    };

    for (const auto& face : input.faces) {
        for (std::size_t i = 1; i + 1 < face.size(); ++i) {
            const std::array<int, 3> tri{face[0], face[i], face[i + 1]};
            std::vector<int> clipped;
            for (int k = 0; k < 3; ++k) {
                const int a = tri[k], b = tri[(k + 1) % 3];
                if (distance[a] <= 0.0) clipped.push_back(keep(a));
                if ((distance[a] < 0.0 && distance[b] > 0.0) ||
                    (distance[a] > 0.0 && distance[b] < 0.0))
                    clipped.push_back(cross(a, b));
            }
            if (clipped.size() < 3) continue;
            // A face lying in the cut plane is replaced by the cap.
            if (std::all_of(clipped.begin(), clipped.end(), [&](int v) { return onPlane[v]; }))
                continue;
            for (std::size_t j = 1; j + 1 < clipped.size(); ++j)
                mesh.faces.push_back({clipped[0], clipped[j], clipped[j + 1]});
        }
    }
    if (mesh.faces.empty())
        throw std::invalid_argument("cutMesh: the cut discards the whole solid");

    // Boundary half-edges of the kept part; the cap runs along each of them reversed.
    std::map<std::pair<int, int>, int> directed;
    for (const auto& f : mesh.faces)
        for (std::size_t k = 0; k < f.size(); ++k)
            ++directed[{f[k], f[(k + 1) % f.size()]}];
    std::map<int, int> capNext;  // cap boundary: vertex → next vertex
    for (const auto& [edge, uses] : directed) {
        if (directed.count({edge.second, edge.first})) continue;
        if (!onPlane[edge.first] || !onPlane[edge.second])
            throw std::logic_error("cutMesh: an open edge off the cut plane");
        if (!capNext.emplace(edge.second, edge.first).second)
            throw std::invalid_argument(
                "cutMesh: the section touches itself at a vertex; move the stroke slightly");
    }
    if (capNext.empty())
        throw std::invalid_argument("cutMesh: the cut plane does not cross the solid");

    // Chain the loops.
    std::map<int, bool> used;
    for (const auto& [start, next] : capNext) {
        if (used[start]) continue;
        std::vector<int> loop;
        int v = start;
        do {
            used[v] = true;
            loop.push_back(v);
            const auto it = capNext.find(v);
            if (it == capNext.end()) throw std::logic_error("cutMesh: open section loop");
            v = it->second;
        } while (v != start && loop.size() <= capNext.size());
        if (v != start) throw std::logic_error("cutMesh: section loop does not close");
        result.capLoops.push_back(loop);
    }

    // Cap: triangulate in plane coordinates (e1, e2) with e1 × e2 = normal, so that
    // counter-clockwise triangles face the discarded side (outward).
    const glm::dvec3 helper = std::abs(normal.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 e1 = glm::normalize(glm::cross(helper, normal));
    const glm::dvec3 e2 = glm::cross(normal, e1);
    std::vector<glm::dvec2> flat;
    std::vector<int> meshIndex;
    std::vector<std::vector<int>> loops;
    for (const auto& loop : result.capLoops) {
        std::vector<int> local;
        for (int v : loop) {
            local.push_back(static_cast<int>(flat.size()));
            flat.push_back({glm::dot(mesh.vertices[v] - plane.point, e1),
                            glm::dot(mesh.vertices[v] - plane.point, e2)});
            meshIndex.push_back(v);
        }
        loops.push_back(local);
    }
    std::vector<std::array<int, 3>> cap;
    try {
        cap = detail::triangulateLoops(flat, loops);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string("cutMesh: cannot cap the section: ") + e.what());
    }
    result.firstCapFace = mesh.faces.size();
    for (const auto& t : cap)
        mesh.faces.push_back({meshIndex[t[0]], meshIndex[t[1]], meshIndex[t[2]]});

    // Drop vertices no face uses (kept vertices are only added through faces, but a face
    // lying in the plane may have been skipped).
    std::vector<int> remap(mesh.vertices.size(), -1);
    std::vector<glm::dvec3> compact;
    for (auto& f : mesh.faces)
        for (int& v : f) {
            if (remap[v] < 0) {
                remap[v] = static_cast<int>(compact.size());
                compact.push_back(mesh.vertices[v]);
            }
            v = remap[v];
        }
    mesh.vertices = std::move(compact);
    for (auto& loop : result.capLoops)
        for (int& v : loop)
            v = remap[v];
    return result;
}

MeshCut cutMesh(const PolyMesh& mesh, const Polyline2& stroke, const SketchView& view) {
    const CutPlane plane = cutPlaneFromStroke(stroke, view);
    if (insideSilhouette(mesh, view, stroke.front()))
        throw std::invalid_argument("cutMesh: the cutting stroke starts inside the silhouette");
    if (insideSilhouette(mesh, view, stroke.back()))
        throw std::invalid_argument("cutMesh: the cutting stroke ends inside the silhouette");
    return cutMeshByPlane(mesh, plane);
}

}  // namespace vsculpt::sketch
