// SPDX-License-Identifier: MIT
#include "vsculpt/core/EvalField.h"

#include "SkeletonStoreImpl.h"
#include "vsculpt/core/Sculpture.h"

#include <bit>
#include <cmath>
#include <stdexcept>

namespace vsculpt::core {

namespace {

using Accessor = openvdb::tree::ValueAccessor<const SkeletonTree>;

struct LevelView {
    const SkeletonTree* tree = nullptr;
    double spacing = 0, invSpacing = 0, support = 0, support2 = 0, invSupport = 0;
    openvdb::CoordBBox bounds;  // occupied index bounds, grown by the support in index units
    bool empty = true;
};

}  // namespace

struct FieldProbe::Impl {
    const Sculpture& sculpture;
    const HermiteFalloff& falloff;
    std::array<LevelView, kLevelCount> levels;
    std::vector<std::optional<Accessor>> accessors;

    explicit Impl(const Sculpture& s)
        : sculpture(s), falloff(s.levels().falloff()), accessors(kLevelCount) {
        const SkeletonStore::Impl& store = s.store().impl();
        for (int i = 0; i < kLevelCount; ++i) {
            const ToolLevel& tl = s.levels().level(i + 1);
            LevelView& v = levels[i];
            v.tree = &store.trees[i];
            v.spacing = tl.spacingMm;
            v.invSpacing = 1.0 / tl.spacingMm;
            v.support = tl.supportMm;
            v.support2 = tl.supportMm * tl.supportMm;
            v.invSupport = 1.0 / tl.supportMm;
            accessors[i].emplace(*v.tree);
        }
    }

    // Refreshed per query: edits may have happened since the probe was made.
    void refreshBounds(int i) {
        const SkeletonStore::Impl& store = sculpture.store().impl();
        LevelView& v = levels[i];
        v.empty = store.counts[i] == 0;
        if (!v.empty) v.bounds = store.bounds[i];
    }

    template <bool WithGradient>
    double accumulate(const Vec3& p, Vec3* grad) {
        double sum = 0;
        for (const PointSkeleton& s : sculpture.pointSkeletons()) {
            const Vec3 d = p - s.centerMm;
            const double r2 = glm::dot(d, d);
            if (r2 >= s.supportMm * s.supportMm) continue;
            const double r = std::sqrt(r2);
            const double u = r / s.supportMm;
            sum += s.weight * falloff.value(u);
            if constexpr (WithGradient) {
                if (r > 0) *grad += d * (s.weight * falloff.derivative(u) / (s.supportMm * r));
            }
        }
        for (int i = 0; i < kLevelCount; ++i) {
            refreshBounds(i);
            const LevelView& v = levels[i];
            if (v.empty) continue;
            // Lattice index range whose vertices can lie within the support of p.
            const int x0 = int(std::floor((p.x - v.support) * v.invSpacing));
            const int y0 = int(std::floor((p.y - v.support) * v.invSpacing));
            const int z0 = int(std::floor((p.z - v.support) * v.invSpacing));
            const int x1 = int(std::ceil((p.x + v.support) * v.invSpacing));
            const int y1 = int(std::ceil((p.y + v.support) * v.invSpacing));
            const int z1 = int(std::ceil((p.z + v.support) * v.invSpacing));
            const openvdb::Coord& bmin = v.bounds.min();
            const openvdb::Coord& bmax = v.bounds.max();
            if (x1 < bmin.x() || x0 > bmax.x() || y1 < bmin.y() || y0 > bmax.y() ||
                z1 < bmin.z() || z0 > bmax.z())
                continue;
            Accessor& acc = *accessors[i];
            constexpr int kMask = ~int(SkeletonLeaf::DIM - 1);
            for (int lx = x0 & kMask; lx <= x1; lx += SkeletonLeaf::DIM)
                for (int ly = y0 & kMask; ly <= y1; ly += SkeletonLeaf::DIM)
                    for (int lz = z0 & kMask; lz <= z1; lz += SkeletonLeaf::DIM) {
                        const SkeletonLeaf* leaf = acc.probeConstLeaf(openvdb::Coord(lx, ly, lz));
                        if (!leaf) continue;
                        uint64_t bits = leaf->getValueMask().template getWord<uint64_t>(0);
                        const float* w = leaf->buffer().data();
                        while (bits) {
                            const int n = std::countr_zero(bits);
                            bits &= bits - 1;
                            // Leaf offset layout: x * 16 + y * 4 + z.
                            const Vec3 pos((lx + (n >> 4)) * v.spacing,
                                           (ly + ((n >> 2) & 3)) * v.spacing,
                                           (lz + (n & 3)) * v.spacing);
                            const Vec3 d = p - pos;
                            const double r2 = glm::dot(d, d);
                            if (r2 >= v.support2 || w[n] == 0.0f) continue;
                            const double r = std::sqrt(r2);
                            const double u = r * v.invSupport;
                            sum += double(w[n]) * falloff.value(u);
                            if constexpr (WithGradient) {
                                if (r > 0)
                                    *grad +=
                                        d * (double(w[n]) * falloff.derivative(u) * v.invSupport / r);
                            }
                        }
                    }
        }
        return sum;
    }
};

FieldProbe::FieldProbe(const Sculpture& sculpture)
    : mImpl(std::make_unique<Impl>(sculpture)), mIso(sculpture.levels().iso()) {}
FieldProbe::~FieldProbe() = default;
FieldProbe::FieldProbe(FieldProbe&&) noexcept = default;

double FieldProbe::value(const Vec3& p) { return mImpl->accumulate<false>(p, nullptr) - mIso; }

FieldSample FieldProbe::sample(const Vec3& p) {
    FieldSample s;
    s.value = mImpl->accumulate<true>(p, &s.gradient) - mIso;
    return s;
}

void evalFieldBatch(const Sculpture& sculpture, std::span<const Vec3> points,
                    std::span<double> values, std::span<Vec3> gradients) {
    if (values.size() != points.size() || (!gradients.empty() && gradients.size() != points.size()))
        throw std::invalid_argument("evalFieldBatch: output spans must match the point count");
    FieldProbe probe(sculpture);
    if (gradients.empty()) {
        for (size_t i = 0; i < points.size(); ++i) values[i] = probe.value(points[i]);
    } else {
        for (size_t i = 0; i < points.size(); ++i) {
            const FieldSample s = probe.sample(points[i]);
            values[i] = s.value;
            gradients[i] = s.gradient;
        }
    }
}

FieldSample evalFieldBruteForce(const Sculpture& sculpture, const Vec3& p) {
    const HermiteFalloff& F = sculpture.levels().falloff();
    FieldSample out;
    double sum = 0;
    auto add = [&](const Vec3& center, double support, double w) {
        const Vec3 d = p - center;
        const double r = glm::length(d);
        if (r >= support) return;
        sum += w * F.value(r / support);
        if (r > 0) out.gradient += d * (w * F.derivative(r / support) / (support * r));
    };
    for (const PointSkeleton& s : sculpture.pointSkeletons()) add(s.centerMm, s.supportMm, s.weight);
    sculpture.store().forEach([&](const SkeletonEntry& e) {
        const ToolLevel& tl = sculpture.levels().level(e.level);
        add(Vec3(e.coord.x, e.coord.y, e.coord.z) * tl.spacingMm, tl.supportMm, e.weight);
    });
    out.value = sum - sculpture.levels().iso();
    return out;
}

}  // namespace vsculpt::core
