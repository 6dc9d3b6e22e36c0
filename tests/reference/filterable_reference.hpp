// Double-precision ground truth of the filter's other representations (docs/formats.md,
// "Filterable representations"): each sample's warp, the mean over the texel's samples,
// the 9-tap Gaussian horizontally then vertically (clamp-to-edge), and the storage's
// codes (unorm16, IEEE half). Written from the formulas of the docs, not from kernels/.
#pragma once

#include "reference/filter_reference.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace msmcl::reference {

/// What a texel holds: (t, t^2); (p, p^2); (p, p^2, n, n^2); exp(c (t - 1)).
enum class Warp { vsm, evsm2, evsm4, esm };

/// Up to four values per texel (unused ones 0).
using Lanes = std::array<double, 4>;

/// t in [0,1] of a rendered depth: d for the [0,1] range, (d + 1)/2 for [-1,1].
double unit_depth(double d, bool zero_one);

/// The warped values of one depth t: x = 2t - 1, p = exp(c+ x), n = -exp(-c- x); ESM
/// exp(c+ (t - 1)).
Lanes warp(double t, Warp kind, double c_positive, double c_negative);

/// Warp per sample, mean over the samples, 9x9 Gaussian of `sigma`: per texel, row-major.
std::vector<Lanes> filter_warped(const DepthMap& map, double sigma, Warp kind, double c_positive, double c_negative);

/// The value of an IEEE 754 binary16 code (sign, 5 exponent bits, 10 mantissa bits).
double half_value(std::uint16_t code);
/// The spacing of halves around |v|: 2^(e - 10) for 2^e <= |v| < 2^(e+1), at least 2^-24.
double half_spacing(double v);

} // namespace msmcl::reference
