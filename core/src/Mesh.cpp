// SPDX-License-Identifier: MIT
#include "vsculpt/core/Mesh.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <map>
#include <numeric>
#include <sstream>
#include <unordered_map>

namespace vsculpt::core {

namespace {

using Tri = std::array<Vec3, 3>;

bool lessVec(const Vec3& a, const Vec3& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
}

bool lessTri(const Tri& a, const Tri& b) {
    for (int i = 0; i < 3; ++i) {
        if (lessVec(a[i], b[i])) return true;
        if (lessVec(b[i], a[i])) return false;
    }
    return false;
}

/// Triangles as position triples, each rotated to start at its smallest vertex, sorted.
std::vector<Tri> canonicalTriangles(const Mesh& m) {
    std::vector<Tri> tris(m.triangleCount());
    for (size_t t = 0; t < tris.size(); ++t) {
        Tri tri{m.positions[m.indices[3 * t]], m.positions[m.indices[3 * t + 1]],
                m.positions[m.indices[3 * t + 2]]};
        int first = 0;
        for (int i = 1; i < 3; ++i)
            if (lessVec(tri[i], tri[first])) first = i;
        std::rotate(tri.begin(), tri.begin() + first, tri.end());
        tris[t] = tri;
    }
    std::sort(tris.begin(), tris.end(), lessTri);
    return tris;
}

uint64_t mix(uint64_t h, uint64_t v) {
    h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    return h * 0xBF58476D1CE4E5B9ull;
}

uint64_t bitsOf(double d) {
    if (d == 0) d = 0;  // -0 and +0 hash alike
    uint64_t u;
    std::memcpy(&u, &d, sizeof u);
    return u;
}

std::string describe(const Tri& t) {
    std::ostringstream s;
    s.precision(17);
    s << "[(" << t[0].x << ", " << t[0].y << ", " << t[0].z << ") (" << t[1].x << ", " << t[1].y
      << ", " << t[1].z << ") (" << t[2].x << ", " << t[2].y << ", " << t[2].z << ")]";
    return s.str();
}

}  // namespace

uint64_t canonicalMeshHash(const Mesh& mesh) {
    uint64_t h = 0x51ED270B27AB1E5Dull;
    h = mix(h, mesh.triangleCount());
    for (const Tri& t : canonicalTriangles(mesh))
        for (const Vec3& p : t)
            h = mix(mix(mix(h, bitsOf(p.x)), bitsOf(p.y)), bitsOf(p.z));
    return h;
}

MeshTopology analyzeTopology(const Mesh& m) {
    MeshTopology out;
    out.triangles = m.triangleCount();
    // Directed edge counts per undirected edge.
    std::unordered_map<uint64_t, std::array<uint32_t, 2>> edges;
    edges.reserve(out.triangles * 2);
    std::vector<uint32_t> parent(m.positions.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](uint32_t x) {
        while (parent[x] != x)
            x = parent[x] = parent[parent[x]];
        return x;
    };
    std::vector<char> used(m.positions.size(), 0);
    for (size_t t = 0; t < out.triangles; ++t) {
        for (int i = 0; i < 3; ++i) {
            const uint32_t a = m.indices[3 * t + i], b = m.indices[3 * t + (i + 1) % 3];
            used[a] = 1;
            const uint64_t key = a < b ? (uint64_t(a) << 32 | b) : (uint64_t(b) << 32 | a);
            ++edges[key][a < b ? 0 : 1];
            parent[find(a)] = find(b);
        }
    }
    for (const auto& [key, c] : edges) {
        const uint32_t n = c[0] + c[1];
        if (n == 1) ++out.boundaryEdges;
        if (n > 2) ++out.nonManifoldEdges;
        if (n == 2 && (c[0] != 1 || c[1] != 1)) ++out.misorientedEdges;
    }
    out.edges = edges.size();
    for (size_t v = 0; v < used.size(); ++v) {
        if (!used[v]) continue;
        ++out.vertices;
        if (find(uint32_t(v)) == v) ++out.components;
    }
    out.eulerCharacteristic = long(out.vertices) - long(out.edges) + long(out.triangles);
    return out;
}

double meshVolume(const Mesh& m) {
    double v = 0;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const Vec3& a = m.positions[m.indices[3 * t]];
        const Vec3& b = m.positions[m.indices[3 * t + 1]];
        const Vec3& c = m.positions[m.indices[3 * t + 2]];
        v += glm::dot(a, glm::cross(b, c));
    }
    return v / 6.0;
}

Aabb meshBounds(const Mesh& m) {
    Aabb box;
    for (uint32_t i : m.indices)
        box.expand(m.positions[i]);
    return box;
}

std::string firstMeshDifference(const Mesh& a, const Mesh& b) {
    const auto ta = canonicalTriangles(a), tb = canonicalTriangles(b);
    size_t i = 0, j = 0;
    while (i < ta.size() && j < tb.size()) {
        if (lessTri(ta[i], tb[j])) return "triangle only in the first mesh: " + describe(ta[i]);
        if (lessTri(tb[j], ta[i])) return "triangle only in the second mesh: " + describe(tb[j]);
        ++i;
        ++j;
    }
    if (i < ta.size()) return "triangle only in the first mesh: " + describe(ta[i]);
    if (j < tb.size()) return "triangle only in the second mesh: " + describe(tb[j]);
    return "";
}

}  // namespace vsculpt::core
