#include "vsculpt/sketch/TriangulatePolyMesh.h"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {
namespace {

double cross2(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Projects the face onto the plane of its Newell normal, as a counter-clockwise 2D polygon when
// the face is counter-clockwise around that normal (always, by the Newell construction).
std::vector<glm::dvec2> project(const PolyMesh& mesh, const std::vector<int>& face) {
    glm::dvec3 n(0.0);
    const std::size_t k = face.size();
    for (std::size_t i = 0; i < k; ++i) {
        const glm::dvec3& a = mesh.vertices[face[i]];
        const glm::dvec3& b = mesh.vertices[face[(i + 1) % k]];
        n += glm::cross(a, b);
    }
    std::vector<glm::dvec2> out(k);
    const double len = glm::length(n);
    if (!(len > 0)) return {};  // degenerate face: caller fans it
    n /= len;
    const glm::dvec3 helper = std::abs(n.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 u = glm::normalize(glm::cross(helper, n));
    const glm::dvec3 v = glm::cross(n, u);
    for (std::size_t i = 0; i < k; ++i) {
        const glm::dvec3& p = mesh.vertices[face[i]];
        out[i] = {glm::dot(p, u), glm::dot(p, v)};
    }
    return out;
}

bool strictlyConvex(const std::vector<glm::dvec2>& p) {
    const std::size_t k = p.size();
    for (std::size_t i = 0; i < k; ++i)
        if (!(cross2(p[(i + k - 1) % k], p[i], p[(i + 1) % k]) > 0)) return false;
    return true;
}

bool insideTriangle(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c,
                    const glm::dvec2& p) {
    return cross2(a, b, p) >= 0 && cross2(b, c, p) >= 0 && cross2(c, a, p) >= 0;
}

// Ear clipping of a counter-clockwise simple polygon; ears are convex corners whose triangle
// holds no other remaining corner. Collinear corners (merged faces keep vertices on straight
// edges) are clipped last as zero-area ears so every corner is used.
void earClip(const std::vector<int>& face, const std::vector<glm::dvec2>& p,
             std::vector<std::uint32_t>& out) {
    std::vector<std::size_t> ring(face.size());
    for (std::size_t i = 0; i < ring.size(); ++i)
        ring[i] = i;
    while (ring.size() > 3) {
        const std::size_t m = ring.size();
        std::size_t best = m;
        for (int pass = 0; pass < 2 && best == m; ++pass)
            for (std::size_t i = 0; i < m && best == m; ++i) {
                const std::size_t a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
                const double turn = cross2(p[a], p[b], p[c]);
                if (pass == 0 ? !(turn > 0) : !(turn >= 0)) continue;
                bool blocked = false;
                for (std::size_t j = 0; j < m && !blocked; ++j) {
                    const std::size_t q = ring[j];
                    if (q == a || q == b || q == c) continue;
                    if (p[q] == p[a] || p[q] == p[b] || p[q] == p[c]) continue;
                    blocked = turn > 0 && insideTriangle(p[a], p[b], p[c], p[q]);
                }
                if (!blocked) best = i;
            }
        if (best == m) best = 0;  // not simple in projection: clip anyway, topology stays right
        const std::size_t a = ring[(best + m - 1) % m], b = ring[best], c = ring[(best + 1) % m];
        out.insert(out.end(),
                   {std::uint32_t(face[a]), std::uint32_t(face[b]), std::uint32_t(face[c])});
        ring.erase(ring.begin() + std::ptrdiff_t(best));
    }
    out.insert(out.end(), {std::uint32_t(face[ring[0]]), std::uint32_t(face[ring[1]]),
                           std::uint32_t(face[ring[2]])});
}

}  // namespace

TriangleMesh triangulatePolyMesh(const PolyMesh& mesh) {
    if (mesh.vertices.size() > std::numeric_limits<std::uint32_t>::max())
        throw std::invalid_argument("triangulatePolyMesh: more vertices than uint32 indices hold");
    TriangleMesh out;
    out.positions = mesh.vertices;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const std::vector<int>& face = mesh.faces[f];
        if (face.size() < 3)
            throw std::invalid_argument("triangulatePolyMesh: face " + std::to_string(f) +
                                        " has fewer than 3 corners");
        for (int v : face)
            if (v < 0 || std::size_t(v) >= mesh.vertices.size())
                throw std::invalid_argument("triangulatePolyMesh: face " + std::to_string(f) +
                                            " has vertex index " + std::to_string(v) +
                                            " out of range");
        const std::vector<glm::dvec2> p =
            face.size() > 3 ? project(mesh, face) : std::vector<glm::dvec2>{};
        if (face.size() == 3 || p.empty() || strictlyConvex(p)) {
            for (std::size_t i = 1; i + 1 < face.size(); ++i)
                out.indices.insert(
                    out.indices.end(),
                    {std::uint32_t(face[0]), std::uint32_t(face[i]), std::uint32_t(face[i + 1])});
        } else {
            earClip(face, p, out.indices);
        }
    }
    return out;
}

PolyMesh toPolyMesh(const TriangleMesh& mesh) {
    PolyMesh out;
    out.vertices = mesh.positions;
    out.faces.reserve(mesh.indices.size() / 3);
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
        out.faces.push_back(
            {int(mesh.indices[t]), int(mesh.indices[t + 1]), int(mesh.indices[t + 2])});
    return out;
}

}  // namespace vsculpt::sketch
