// Double-precision reference of the filterable shadow maps beside the moment formats
// (docs/math.md, "Shading VSM, EVSM and ESM"), written from the papers and the docs, never
// from kernels/: the warps of VSM (Donnelly and Lauritzen, "Variance Shadow Maps", 2006),
// EVSM (Lauritzen and McCool, "Layered Variance Shadow Maps", 2008) and ESM (Annen et al.,
// "Exponential Shadow Maps", 2008), their mean over a depth distribution, the filter's
// texels (warp per sample, mean over the samples, the 9x9 Gaussian of filter_reference;
// docs/formats.md, "Filterable representations"), and the shadow intensity (0 lit,
// 1 shadowed) each gives a receiver.
#pragma once

#include "reference/filter_reference.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace msmcl::reference {

/// The representations: what a texel stores and how it is shaded.
enum class Warp { vsm, evsm2, evsm4, esm };

/// The stored channels of a texel (R, G, B, A; unused ones 0): VSM (t, t^2), EVSM2 (p, p^2),
/// EVSM4 (p, p^2, n, n^2) with p = exp(c+ x), n = -exp(-c- x), x = 2t - 1, ESM exp(c (t - 1)).
using Channels = std::array<double, 4>;

/// How a texel is shaded: the exponents (ESM: c = positive), the minimum variance V of the
/// receiver's depth t in [0, 1], the light-bleed reduction R.
struct WarpShading {
    Warp warp = Warp::vsm;
    double positive = 0, negative = 0;
    double min_variance = 0;
    double light_bleed_reduction = 0;
};

/// The channels of one depth t in [0, 1].
Channels warp_channels(Warp warp, double t, double positive, double negative);
/// The weighted mean of the channels of depths t (weights normalized): a filtered texel.
Channels warp_channels(Warp warp, const std::vector<double>& t, const std::vector<double>& weight, double positive,
                       double negative);

/// Chebyshev's one-sided bound on the share at or behind `receiver`: 1 where receiver <= mean,
/// else s^2 / (s^2 + (receiver - mean)^2), s^2 = max(mean_square - mean^2, min_variance).
double chebyshev_upper(double mean, double mean_square, double min_variance, double receiver);

/// Shadow intensity of stored channels at receiver depth t_r (clamped to [0, 1]): 1 - the
/// visibility of docs/math.md (VSM, EVSM: the bound, for EVSM4 the smaller of the two
/// warps', rescaled from [R, 1] to [0, 1]; ESM: clamp(exp(-c (t_r - 1)) stored, 0, 1)).
double warp_shadow(const Channels& stored, double receiver_t, const WarpShading& shading);

/// An IEEE binary16 code as its value (every code; NaN for NaN codes).
double half_value(std::uint16_t code);
/// The spacing of halves around |v|: 2^(e - 10) for 2^e <= |v| < 2^(e+1), at least 2^-24.
double half_spacing(double v);

/// t in [0,1] of a rendered depth: d for the [0,1] range, (d + 1)/2 for [-1,1].
double unit_depth(double d, bool zero_one);

/// The filter's texels of `map`: each sample's channels (warp_channels), their mean over
/// the texel's samples, the 9x9 Gaussian of `sigma` horizontally then vertically
/// (clamp-to-edge); per texel, row-major.
std::vector<Channels> filter_warped(const DepthMap& map, double sigma, Warp warp, double positive, double negative);

} // namespace msmcl::reference
