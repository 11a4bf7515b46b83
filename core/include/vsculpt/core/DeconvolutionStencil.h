// SPDX-License-Identifier: MIT
#pragma once
/// The lattice deconvolution that turns a swept stroke's target changes of the field into
/// skeleton weights (docs/placement.md, "Weights" and "Stability").
///
/// A weight w at a lattice vertex changes the field at the vertices around it by w F(d / R):
/// the realised change is the weights blurred by K, the falloff sampled on the lattice
/// (19 taps at R / h = 1.66). Weights = P * change undo most of that blur.
#include "vsculpt/core/Falloff.h"

#include <array>
#include <vector>

namespace vsculpt::core {

/// One tap of a lattice stencil: offset in lattice spacings, and its coefficient.
struct StencilTap {
    std::array<int, 3> offset;
    double weight;
};

/// K: the falloff F sampled at the lattice offsets within the support (unnormalised).
/// @param supportOverSpacing R / h, the support radius in lattice spacings
std::vector<StencilTap> latticeBlur(const HermiteFalloff& falloff, double supportOverSpacing);

/// P = (1/S) sum_{j=0..steps} (I - K/S)^j, S = sum K: Richardson steps of the deconvolution.
/// Its realised response K^ P^ = 1 - (1 - K^/S)^(steps+1) is close to 1 where the target is
/// smooth. Where K^ < 0 (near the lattice's checkerboard frequencies: at R/h = 1.66 K^/S
/// reaches -0.1 there) the response is negative, -0.33 with 2 steps: a change there comes out
/// with the opposite sign. With `stabilised`, P is reduced near those frequencies (by 3 times
/// the sum over the three axis pairs of (1 - cos a)^2 (1 - cos b)^2 (1 - cos c) / 32: on the
/// zone's edges, where a and b are pi, it rises from 0 to 1 as c goes to pi, as K^ turns
/// negative; at zero frequency it is of tenth order), so that the
/// response stays within [-0.031, 1] at every frequency while it changes by less than 1 %
/// for |frequency| <= 2 rad per spacing.
std::vector<StencilTap> deconvolutionStencil(const HermiteFalloff& falloff,
                                             double supportOverSpacing, int steps, bool stabilised);

/// The realised response K^(w) P^(w) at the lattice frequency w (radians per spacing): what a
/// target change of that frequency comes out as (1 = exactly). For tests and docs.
double realisedResponse(const std::vector<StencilTap>& blur, const std::vector<StencilTap>& p,
                        const std::array<double, 3>& frequency);

}  // namespace vsculpt::core
