// SPDX-License-Identifier: MIT
/// @file Geometry.h
/// @brief Small value types shared by the core: points, boxes, lattice coordinates, poses.
///
/// Units: millimetres everywhere. Frames are named in variable names (`objectPos`,
/// `worldFromObject`); the types themselves carry no frame.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>

namespace vsculpt::core {

using Vec3 = glm::dvec3;

/// Axis-aligned box in millimetres. Default-constructed boxes are empty.
struct Aabb {
    Vec3 min{std::numeric_limits<double>::infinity()};
    Vec3 max{-std::numeric_limits<double>::infinity()};

    bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    void expand(const Vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void expand(const Aabb& b) {
        if (b.empty()) return;
        expand(b.min);
        expand(b.max);
    }
    /// The box grown by `r` on every side (no-op on an empty box).
    Aabb padded(double r) const {
        if (empty()) return *this;
        return Aabb{min - Vec3(r), max + Vec3(r)};
    }
    bool intersects(const Aabb& b) const {
        return !empty() && !b.empty() && min.x <= b.max.x && b.min.x <= max.x && min.y <= b.max.y &&
               b.min.y <= max.y && min.z <= b.max.z && b.min.z <= max.z;
    }
    bool contains(const Vec3& p) const {
        return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y && p.z >= min.z &&
               p.z <= max.z;
    }
};

/// Integer index of a vertex of one level's skeleton lattice; its position is `spacing * index`.
struct LatticeCoord {
    int32_t x = 0, y = 0, z = 0;
    friend bool operator==(const LatticeCoord&, const LatticeCoord&) = default;
    friend auto operator<=>(const LatticeCoord&, const LatticeCoord&) = default;
};

struct LatticeCoordHash {
    size_t operator()(const LatticeCoord& c) const noexcept {
        // Large odd multipliers spread neighbouring coordinates over the buckets.
        uint64_t h = uint64_t(uint32_t(c.x)) * 0x9E3779B97F4A7C15ull;
        h ^= uint64_t(uint32_t(c.y)) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
        h ^= uint64_t(uint32_t(c.z)) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
        return size_t(h);
    }
};

/// A rigid motion `to_from_from`: p_to = rotation * p_from + translation.
/// Name instances after their frames, e.g. `worldFromObject`.
struct RigidTransform {
    glm::dquat rotation{1.0, 0.0, 0.0, 0.0};  // (w, x, y, z), unit length
    Vec3 translation{0.0};

    Vec3 apply(const Vec3& p) const { return rotation * p + translation; }
    Vec3 applyToVector(const Vec3& v) const { return rotation * v; }
    RigidTransform inverse() const {
        const glm::dquat inv = glm::conjugate(rotation);
        return RigidTransform{inv, -(inv * translation)};
    }
    /// Composition, right to left: (a * b).apply(p) == a.apply(b.apply(p)).
    friend RigidTransform operator*(const RigidTransform& a, const RigidTransform& b) {
        return RigidTransform{a.rotation * b.rotation, a.rotation * b.translation + a.translation};
    }
    /// The same transform as a 4x4 matrix (column vectors: m * (p, 1) == (apply(p), 1)).
    glm::dmat4 matrix() const {
        glm::dmat4 m = glm::mat4_cast(rotation);
        m[3] = glm::dvec4(translation, 1.0);
        return m;
    }
};

/// True when every component is finite and within the range the lattices can index.
inline bool isUsablePoint(const Vec3& p) {
    constexpr double kLimitMm = 1.0e6;  // 1 km: far beyond any sculpture, far below int32 overflow
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) &&
           std::abs(p.x) < kLimitMm && std::abs(p.y) < kLimitMm && std::abs(p.z) < kLimitMm;
}

}  // namespace vsculpt::core
