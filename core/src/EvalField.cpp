// SPDX-License-Identifier: MIT
#include "vsculpt/core/EvalField.h"

#include "SkeletonStoreImpl.h"
#include "vsculpt/core/Sculpture.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

namespace vsculpt::core {

namespace {

struct LevelView {
    double spacing = 0, invSpacing = 0, support = 0, support2 = 0, invSupport = 0;
};

/// Visits, in the one order every evaluator uses (brick coordinates ascending, then bit
/// order), the non-zero skeletons of a level that lie in bricks overlapping the index range
/// of [lo - R, hi + R]. `find(bx, by, bz)` returns a brick position or -1;
/// `visit(position, weight)` sees each skeleton. Summing in this order everywhere is what makes
/// FieldProbe, LocalField, and so partial and full polygonization, agree bit for bit.
template <typename Find, typename Visit>
inline void forEachSkeletonNear(const LevelBricks& L, double h, double R, const Vec3& lo,
                                const Vec3& hi, Find&& find, Visit&& visit) {
    const double inv = 1.0 / h;
    const int x0 = std::max(int(std::floor((lo.x - R) * inv)), L.min[0]);
    const int y0 = std::max(int(std::floor((lo.y - R) * inv)), L.min[1]);
    const int z0 = std::max(int(std::floor((lo.z - R) * inv)), L.min[2]);
    const int x1 = std::min(int(std::ceil((hi.x + R) * inv)), L.max[0]);
    const int y1 = std::min(int(std::ceil((hi.y + R) * inv)), L.max[1]);
    const int z1 = std::min(int(std::ceil((hi.z + R) * inv)), L.max[2]);
    if (x0 > x1 || y0 > y1 || z0 > z1) return;
    // The bits of a brick whose coordinate along an axis lies in [lo, hi] (brick-local). The
    // bricks at the ends of the range hold vertices outside it, a spacing or more beyond the
    // support of every point in [lo, hi]: masked out, they are never visited (every visitor
    // would reject them on distance anyway), which in a small box is most of them.
    auto axisBits = [](int lo, int hi, uint64_t unit, int stride) {
        uint64_t m = 0;
        for (int v = std::max(lo, 0); v <= std::min(hi, kBrickDim - 1); ++v)
            m |= unit << (stride * v);
        return m;
    };
    for (int bx = x0 >> 2; bx <= x1 >> 2; ++bx)
        for (int by = y0 >> 2; by <= y1 >> 2; ++by)
            for (int bz = z0 >> 2; bz <= z1 >> 2; ++bz) {
                const int64_t slot = find(bx, by, bz);
                if (slot < 0) continue;
                const Brick& b = L.bricks[size_t(slot)];
                const float* w = L.pool.data() + b.offset;
                uint64_t bits = b.mask & axisBits(x0 - b.ox, x1 - b.ox, 0xFFFFull, 16) &
                                axisBits(y0 - b.oy, y1 - b.oy, 0x000F000F000F000Full, 4) &
                                axisBits(z0 - b.oz, z1 - b.oz, 0x1111111111111111ull, 1);
                while (bits) {
                    const int n = std::countr_zero(bits);
                    bits &= bits - 1;
                    // Weights are stored in bit order: this one's is after those of the lower bits.
                    const int r = std::popcount(b.mask & ((uint64_t(1) << n) - 1));
                    if (w[r] == 0.0f) continue;
                    visit(Vec3((b.ox + (n >> 4)) * h, (b.oy + ((n >> 2) & 3)) * h,
                               (b.oz + (n & 3)) * h),
                          double(w[r]));
                }
            }
}

/// Direct-mapped cache of brick lookups: queries from one thread are spatially coherent
/// (polygonizer sweeps, stroke placement), so the same few bricks are asked for again and
/// again. Entries are tagged with the store's generation, so a brick created after a
/// "not there" answer is never missed.
struct BrickCache {
    static constexpr size_t kSize = 1024;
    struct Entry {
        uint64_t key = ~uint64_t(0);
        uint64_t generation = ~uint64_t(0);
        int64_t slot = -1;
        int level = -1;
    };
    std::vector<Entry> entries = std::vector<Entry>(kSize);

    int64_t find(const LevelBricks& L, int level, int32_t bx, int32_t by, int32_t bz,
                 uint64_t generation) {
        const uint64_t key = brickKey(bx, by, bz);
        const uint64_t h =
            (key ^ (uint64_t(level) * 0x9E3779B97F4A7C15ull)) * 0xBF58476D1CE4E5B9ull;
        Entry& e = entries[(h >> 40) & (kSize - 1)];
        if (e.key == key && e.level == level && (e.slot >= 0 || e.generation == generation))
            return e.slot;
        e.key = key;
        e.level = level;
        e.generation = generation;
        e.slot = L.find(bx, by, bz);
        return e.slot;
    }
};

}  // namespace

struct FieldProbe::Impl {
    const Sculpture& sculpture;
    const HermiteFalloff& falloff;
    std::array<LevelView, kLevelCount> levels;
    BrickCache cache;

    explicit Impl(const Sculpture& s) : sculpture(s), falloff(s.levels().falloff()) {
        for (int i = 0; i < kLevelCount; ++i) {
            const ToolLevel& tl = s.levels().level(i + 1);
            LevelView& v = levels[i];
            v.spacing = tl.spacingMm;
            v.invSpacing = 1.0 / tl.spacingMm;
            v.support = tl.supportMm;
            v.support2 = tl.supportMm * tl.supportMm;
            v.invSupport = 1.0 / tl.supportMm;
        }
    }

    template <bool WithGradient>
    double accumulate(const Vec3& p, Vec3* grad) {
        double sum = 0;
        for (const PointSkeleton& s : sculpture.pointSkeletons()) {
            const Vec3 d = p - s.centerMm;
            const double r2 = glm::dot(d, d);
            if (r2 >= s.supportMm * s.supportMm) continue;
            // Same operations, in the same order, as LocalField: results agree bit for bit.
            const double inv = 1.0 / s.supportMm;
            const double r = std::sqrt(r2);
            const double u = r * inv;
            sum += s.weight * falloff.value(u);
            if constexpr (WithGradient) {
                if (r > 0) *grad += d * (s.weight * falloff.derivative(u) * inv / r);
            }
        }
        const SkeletonStore::Impl& store = sculpture.store().impl();
        for (int i = 0; i < kLevelCount; ++i) {
            const LevelBricks& L = store.levels[i];
            if (L.count == 0) continue;
            const LevelView& v = levels[i];
            forEachSkeletonNear(
                L, v.spacing, v.support, p, p,
                [&](int bx, int by, int bz) {
                    return cache.find(L, i, bx, by, bz, store.generation);
                },
                [&](const Vec3& pos, double w) {
                    const Vec3 d = p - pos;
                    const double r2 = glm::dot(d, d);
                    if (r2 >= v.support2) return;
                    const double dist = std::sqrt(r2);
                    const double u = dist * v.invSupport;
                    sum += w * falloff.value(u);
                    if constexpr (WithGradient) {
                        if (dist > 0)
                            *grad += d * (w * falloff.derivative(u) * v.invSupport / dist);
                    }
                });
        }
        return sum;
    }
};

FieldProbe::FieldProbe(const Sculpture& sculpture)
    : mImpl(std::make_unique<Impl>(sculpture)), mIso(sculpture.levels().iso()) {}
FieldProbe::~FieldProbe() = default;
FieldProbe::FieldProbe(FieldProbe&&) noexcept = default;

double FieldProbe::value(const Vec3& p) {
    return mImpl->accumulate<false>(p, nullptr) - mIso;
}

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
        for (size_t i = 0; i < points.size(); ++i)
            values[i] = probe.value(points[i]);
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
    for (const PointSkeleton& s : sculpture.pointSkeletons())
        add(s.centerMm, s.supportMm, s.weight);
    sculpture.store().forEach([&](const SkeletonEntry& e) {
        const ToolLevel& tl = sculpture.levels().level(e.level);
        add(Vec3(e.coord.x, e.coord.y, e.coord.z) * tl.spacingMm, tl.supportMm, e.weight);
    });
    out.value = sum - sculpture.levels().iso();
    return out;
}

}  // namespace vsculpt::core

namespace vsculpt::core {

LocalField::LocalField(const Sculpture& sculpture, const Aabb& box)
    : mFalloff(&sculpture.levels().falloff()), mIso(sculpture.levels().iso()), mBox(box) {
    // Room for what a block of piled-up clay usually gathers (tens of skeletons): the
    // polygonizer gathers one LocalField per rebuilt block, and growing six arrays from empty
    // cost a dozen or more allocations each time.
    constexpr size_t kUsual = 64;
    for (auto* v : {&mX, &mY, &mZ, &mW, &mInvR, &mR2})
        v->reserve(kUsual);
    auto push = [&](const Vec3& pos, double w, double support) {
        mX.push_back(pos.x);
        mY.push_back(pos.y);
        mZ.push_back(pos.z);
        mW.push_back(w);
        mInvR.push_back(1.0 / support);
        mR2.push_back(support * support);
    };
    auto reaches = [&](const Vec3& pos, double support) {
        const Vec3 q = glm::clamp(pos, box.min, box.max);
        const Vec3 d = pos - q;
        return glm::dot(d, d) < support * support;
    };
    for (const PointSkeleton& s : sculpture.pointSkeletons())
        if (reaches(s.centerMm, s.supportMm)) push(s.centerMm, s.weight, s.supportMm);
    const SkeletonStore::Impl& store = sculpture.store().impl();
    for (int i = 0; i < kLevelCount; ++i) {
        const LevelBricks& L = store.levels[i];
        if (L.count == 0) continue;
        const ToolLevel& tl = sculpture.levels().level(i + 1);
        const double R = tl.supportMm;
        forEachSkeletonNear(
            L, tl.spacingMm, R, box.min, box.max,
            [&](int bx, int by, int bz) { return L.find(bx, by, bz); },
            [&](const Vec3& pos, double w) {
                if (reaches(pos, R)) push(pos, w, R);
            });
    }
}

double LocalField::value(const Vec3& p) const {
    // Two passes: squared distances for all skeletons (a loop the compiler vectorises), then
    // the falloff only for those in reach, in the same order as FieldProbe.
    const size_t n = mX.size();
    double r2[kDistanceChunk];
    double sum = 0;
    for (size_t base = 0; base < n; base += kDistanceChunk) {
        const size_t m = std::min(kDistanceChunk, n - base);
        squaredDistances(p, base, m, r2);
        for (size_t i = 0; i < m; ++i) {
            if (r2[i] >= mR2[base + i]) continue;
            sum += mW[base + i] * mFalloff->value(std::sqrt(r2[i]) * mInvR[base + i]);
        }
    }
    return sum - mIso;
}

void LocalField::gridValues(std::span<const double> xs, std::span<const double> ys,
                            std::span<const double> zs, double* out) const {
    const size_t nx = xs.size(), ny = ys.size(), nz = zs.size();
    std::fill(out, out + nx * ny * nz, 0.0);
    // The vertices along one axis a skeleton may reach: a conservative index range (one
    // vertex of slack each side); the exact test is r2 < R2 below, as in value().
    auto range = [](std::span<const double> v, double c, double r, size_t& lo, size_t& hi) {
        const double h = v.size() > 1 ? v[1] - v[0] : 1.0;
        const double a = std::floor((c - r - v[0]) / h) - 1, b = std::ceil((c + r - v[0]) / h) + 1;
        lo = size_t(std::clamp(a, 0.0, double(v.size())));
        hi = size_t(std::clamp(b + 1, 0.0, double(v.size())));  // exclusive
    };
    double dx2[16], dy2[16], dz2[16];
    if (nx > 16 || ny > 16 || nz > 16) throw std::invalid_argument("gridValues: at most 16^3");
    for (size_t s = 0; s < mX.size(); ++s) {
        const double r = std::sqrt(mR2[s]);
        size_t i0, i1, j0, j1, k0, k1;
        range(xs, mX[s], r, i0, i1);
        range(ys, mY[s], r, j0, j1);
        range(zs, mZ[s], r, k0, k1);
        if (i0 >= i1 || j0 >= j1 || k0 >= k1) continue;
        // The same products as value(): (dx*dx + dy*dy) + dz*dz.
        for (size_t i = i0; i < i1; ++i) {
            const double d = xs[i] - mX[s];
            dx2[i] = d * d;
        }
        for (size_t j = j0; j < j1; ++j) {
            const double d = ys[j] - mY[s];
            dy2[j] = d * d;
        }
        for (size_t k = k0; k < k1; ++k) {
            const double d = zs[k] - mZ[s];
            dz2[k] = d * d;
        }
        for (size_t i = i0; i < i1; ++i)
            for (size_t j = j0; j < j1; ++j) {
                const double xy = dx2[i] + dy2[j];
                if (xy >= mR2[s]) continue;
                double* row = out + (i * ny + j) * nz;
                for (size_t k = k0; k < k1; ++k) {
                    const double r2 = xy + dz2[k];
                    if (r2 >= mR2[s]) continue;
                    row[k] += mW[s] * mFalloff->value(std::sqrt(r2) * mInvR[s]);
                }
            }
    }
    for (size_t q = 0; q < nx * ny * nz; ++q)
        out[q] -= mIso;
}

namespace {

/// Calls at(vertex, d2) for every vertex of a regular grid (at most 16 per axis, laid out as
/// in LocalField::gridValues) within the support of a skeleton at c: d2 < r2, with the
/// squared distance computed as (dx*dx + dy*dy) + dz*dz, as everywhere else.
template <typename At>
void forEachVertexInReach(const Vec3& c, double r2, std::span<const double> xs,
                          std::span<const double> ys, std::span<const double> zs, FixedSum* out,
                          At&& at) {
    const size_t ny = ys.size(), nz = zs.size();
    if (xs.size() > 16 || ny > 16 || nz > 16)
        throw std::invalid_argument("splatFixed: at most 16^3");
    // A conservative index range per axis (one vertex of slack each side); the exact test
    // is d2 < r2 below.
    const double r = std::sqrt(r2);
    auto range = [r](std::span<const double> v, double center, size_t& lo, size_t& hi) {
        const double h = v.size() > 1 ? v[1] - v[0] : 1.0;
        const double a = std::floor((center - r - v[0]) / h) - 1,
                     b = std::ceil((center + r - v[0]) / h) + 1;
        lo = size_t(std::clamp(a, 0.0, double(v.size())));
        hi = size_t(std::clamp(b + 1, 0.0, double(v.size())));  // exclusive
    };
    size_t i0, i1, j0, j1, k0, k1;
    range(xs, c.x, i0, i1);
    range(ys, c.y, j0, j1);
    range(zs, c.z, k0, k1);
    if (i0 >= i1 || j0 >= j1 || k0 >= k1) return;
    double dx2[16], dy2[16], dz2[16];
    for (size_t i = i0; i < i1; ++i)
        dx2[i] = (xs[i] - c.x) * (xs[i] - c.x);
    for (size_t j = j0; j < j1; ++j)
        dy2[j] = (ys[j] - c.y) * (ys[j] - c.y);
    for (size_t k = k0; k < k1; ++k)
        dz2[k] = (zs[k] - c.z) * (zs[k] - c.z);
    for (size_t i = i0; i < i1; ++i)
        for (size_t j = j0; j < j1; ++j) {
            const double xy = dx2[i] + dy2[j];
            if (xy >= r2) continue;
            FixedSum* row = out + (i * ny + j) * nz;
            for (size_t k = k0; k < k1; ++k) {
                const double d2 = xy + dz2[k];
                if (d2 >= r2) continue;
                at(row[k], d2);
            }
        }
}

}  // namespace

void splatFixed(const HermiteFalloff& falloff, const Vec3& c, double w, double invR, double r2,
                std::span<const double> xs, std::span<const double> ys, std::span<const double> zs,
                FixedSum* out) {
    forEachVertexInReach(c, r2, xs, ys, zs, out, [&](FixedSum& sum, double d2) {
        sum += fixedTerm(w * falloff.value(std::sqrt(d2) * invR));
    });
}

void splatFixedChange(const HermiteFalloff& falloff, const Vec3& c, double before, double after,
                      double invR, double r2, std::span<const double> xs,
                      std::span<const double> ys, std::span<const double> zs, FixedSum* out) {
    forEachVertexInReach(c, r2, xs, ys, zs, out, [&](FixedSum& sum, double d2) {
        // F once for both terms: each is still w * F, as splatFixed computes it.
        const double f = falloff.value(std::sqrt(d2) * invR);
        sum += fixedTerm(after * f) - fixedTerm(before * f);
    });
}

void LocalField::squaredDistances(const Vec3& p, size_t base, size_t m, double* out) const {
    const double* x = mX.data() + base;
    const double* y = mY.data() + base;
    const double* z = mZ.data() + base;
    for (size_t i = 0; i < m; ++i) {
        const double dx = p.x - x[i], dy = p.y - y[i], dz = p.z - z[i];
        out[i] = dx * dx + dy * dy + dz * dz;
    }
}

void LocalField::gridSums(std::span<const double> xs, std::span<const double> ys,
                          std::span<const double> zs, FixedSum* out) const {
    std::fill(out, out + xs.size() * ys.size() * zs.size(), FixedSum(0));
    for (size_t s = 0; s < mX.size(); ++s)
        splatFixed(*mFalloff, Vec3(mX[s], mY[s], mZ[s]), mW[s], mInvR[s], mR2[s], xs, ys, zs, out);
}

FieldSample LocalField::sample(const Vec3& p) const {
    // Two passes as in value(): squared distances for all skeletons (vectorised), then value
    // and gradient terms only for those in reach, with FieldProbe's operations and order.
    FieldSample out;
    double sum = 0;
    const size_t n = mX.size();
    double r2s[kDistanceChunk];
    uint8_t near[kDistanceChunk];
    for (size_t base = 0; base < n; base += kDistanceChunk) {
        const size_t m = std::min(kDistanceChunk, n - base);
        squaredDistances(p, base, m, r2s);
        // The skeletons in reach listed first, without a branch per skeleton: in piled-up
        // clay a block gathers many that reach only part of it, and a branch on each
        // mispredicts often. The terms are then added in the same order as before.
        size_t k = 0;
        for (size_t q = 0; q < m; ++q) {
            near[k] = uint8_t(q);
            k += !(r2s[q] >= mR2[base + q]);
        }
        for (size_t j = 0; j < k; ++j) {
            const size_t q = near[j];
            const size_t i = base + q;
            const double r2 = r2s[q];
            const Vec3 d(p.x - mX[i], p.y - mY[i], p.z - mZ[i]);
            const double r = std::sqrt(r2);
            const double u = r * mInvR[i];
            sum += mW[i] * mFalloff->value(u);
            if (r > 0) out.gradient += d * (mW[i] * mFalloff->derivative(u) * mInvR[i] / r);
        }
    }
    out.value = sum - mIso;
    return out;
}

FieldBounds LocalField::bounds() const {
    double lo = 0, hi = 0, magnitude = 0;
    for (size_t i = 0; i < mX.size(); ++i) {
        const Vec3 c(mX[i], mY[i], mZ[i]);
        const Vec3 nearest = glm::clamp(c, mBox.min, mBox.max);
        const Vec3 far(c.x < 0.5 * (mBox.min.x + mBox.max.x) ? mBox.max.x : mBox.min.x,
                       c.y < 0.5 * (mBox.min.y + mBox.max.y) ? mBox.max.y : mBox.min.y,
                       c.z < 0.5 * (mBox.min.z + mBox.max.z) ? mBox.max.z : mBox.min.z);
        const double fNear = mFalloff->value(glm::length(c - nearest) * mInvR[i]);
        const double fFar = mFalloff->value(glm::length(c - far) * mInvR[i]);
        magnitude += std::abs(mW[i]) * fNear;
        if (mW[i] > 0) {
            lo += mW[i] * fFar;
            hi += mW[i] * fNear;
        } else {
            lo += mW[i] * fNear;
            hi += mW[i] * fFar;
        }
    }
    // Widen by a rounding margin: the bounds decide what the polygonizer may skip, and must
    // hold for f summed in any order (terms of both signs cancel: the margin follows their
    // magnitudes) and for the polygonizer's fixed-point sums (2^-40 per term).
    const double margin = 1e-9 * (1 + magnitude) + double(mX.size()) / kFixedPerUnit;
    return FieldBounds{lo - mIso - margin, hi - mIso + margin};
}

}  // namespace vsculpt::core
