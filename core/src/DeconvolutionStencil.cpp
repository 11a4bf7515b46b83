// SPDX-License-Identifier: MIT
#include "vsculpt/core/DeconvolutionStencil.h"

#include <cmath>
#include <map>

namespace vsculpt::core {
namespace {

using Stencil = std::map<std::array<int, 3>, double>;

Stencil convolve(const Stencil& a, const Stencil& b) {
    Stencil c;
    for (const auto& [oa, wa] : a)
        for (const auto& [ob, wb] : b)
            c[{oa[0] + ob[0], oa[1] + ob[1], oa[2] + ob[2]}] += wa * wb;
    return c;
}

// (1 - cos w) / 2 along one axis: 1 at the checkerboard frequency, w^2 / 4 near zero.
Stencil highPass(int axis) {
    Stencil s;
    for (int i = -1; i <= 1; ++i) {
        std::array<int, 3> o{0, 0, 0};
        o[axis] = i;
        s[o] = i == 0 ? 0.5 : -0.25;
    }
    return s;
}

}  // namespace

std::vector<StencilTap> latticeBlur(const HermiteFalloff& falloff, double supportOverSpacing) {
    std::vector<StencilTap> taps;
    const int n = int(std::ceil(supportOverSpacing));
    for (int x = -n; x <= n; ++x)
        for (int y = -n; y <= n; ++y)
            for (int z = -n; z <= n; ++z) {
                const double d = std::sqrt(double(x * x + y * y + z * z)) / supportOverSpacing;
                if (d >= 1) continue;
                const double k = falloff.value(d);
                if (k > 0) taps.push_back({{x, y, z}, k});
            }
    return taps;
}

std::vector<StencilTap> deconvolutionStencil(const HermiteFalloff& falloff,
                                             double supportOverSpacing, int steps,
                                             bool stabilised) {
    double S = 0;
    Stencil M;  // I - K/S
    const std::vector<StencilTap> blur = latticeBlur(falloff, supportOverSpacing);
    for (const StencilTap& t : blur)
        S += t.weight;
    for (const StencilTap& t : blur)
        M[t.offset] = -t.weight / S;
    M[{0, 0, 0}] += 1.0;
    Stencil Q = {{{0, 0, 0}, 1.0}}, P = Q;
    for (int j = 0; j < steps; ++j) {
        Q = convolve(Q, M);
        for (const auto& [o, w] : Q)
            P[o] += w;
    }
    if (stabilised) {
        // Where K^ < 0 the Richardson sum is about 3.3 (with 2 steps) while the response should
        // not be negative: subtract a bump that rises along the zone's edges (two frequencies at
        // pi) to 1 at the corner, where K^ is negative, and vanishes to tenth order at zero. Across
        // a sequence of strokes each one's targets are read from the field the others left, so a
        // response below zero is a loop gain above one: adds and carves alternating in one place
        // grew the weights without bound (x1e5 in 300 strokes, docs/placement.md "Stability"). The
        // factor 3 was chosen from the response (min -0.031) and that scrubbing test; 2 still grows
        // slowly, 1 as before.
        constexpr double kStabiliser = 3.0;
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            const Stencil pair = convolve(highPass(a), highPass(b));
            const Stencil bump = convolve(convolve(pair, pair), highPass(c));
            for (const auto& [o, w] : bump)
                P[o] -= kStabiliser * w;
        }
    }
    std::vector<StencilTap> taps;
    for (const auto& [o, w] : P)
        if (std::abs(w) > 1e-12 * S) taps.push_back({o, w / S});
    return taps;
}

double realisedResponse(const std::vector<StencilTap>& blur, const std::vector<StencilTap>& p,
                        const std::array<double, 3>& frequency) {
    auto transform = [&](const std::vector<StencilTap>& s) {
        double sum = 0;
        for (const StencilTap& t : s)
            sum += t.weight * std::cos(t.offset[0] * frequency[0] + t.offset[1] * frequency[1] +
                                       t.offset[2] * frequency[2]);
        return sum;
    };
    return transform(blur) * transform(p);
}

}  // namespace vsculpt::core
