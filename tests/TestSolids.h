// SPDX-License-Identifier: MIT
// Closed test solids (object space, mm) for the sketched-solid tests.
#pragma once

#include "vsculpt/core/Mesh.h"

#include <cmath>

namespace vsculpt::core {

// Closed, outward-oriented UV sphere: poles are single vertices.
inline Mesh sphereMesh(const Vec3& c, double r, int rings = 48, int segments = 96) {
    Mesh m;
    m.positions.push_back(c + Vec3(0, 0, r));
    for (int i = 1; i < rings; ++i) {
        const double th = M_PI * i / rings;
        for (int j = 0; j < segments; ++j) {
            const double ph = 2 * M_PI * j / segments;
            m.positions.push_back(c + r * Vec3(std::sin(th) * std::cos(ph),
                                               std::sin(th) * std::sin(ph), std::cos(th)));
        }
    }
    m.positions.push_back(c + Vec3(0, 0, -r));
    const uint32_t south = uint32_t(m.positions.size() - 1);
    auto ring = [&](int i, int j) { return uint32_t(1 + (i - 1) * segments + (j % segments)); };
    auto tri = [&](uint32_t a, uint32_t b, uint32_t d) {
        m.indices.insert(m.indices.end(), {a, b, d});
    };
    for (int j = 0; j < segments; ++j) {
        tri(0, ring(1, j), ring(1, j + 1));
        tri(south, ring(rings - 1, j + 1), ring(rings - 1, j));
        for (int i = 1; i < rings - 1; ++i) {
            tri(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
            tri(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
        }
    }
    return m;
}

inline Mesh boxMesh(const Vec3& lo, const Vec3& hi) {
    Mesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back(Vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z));
    // Each face counter-clockwise seen from outside.
    const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads)
        m.indices.insert(m.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    return m;
}

}  // namespace vsculpt::core
