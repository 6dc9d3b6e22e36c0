// Double-precision reference of the moment math (docs/math.md, Peters, HPG 2017), written
// independently of kernels/*.clh: moments, bias, Algorithm 2, Psi4, the texel encoders and
// decoders, a generic 4MSM (Algorithm 1 of Peters, HPG 2017) and exact filtered shadows.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace msmcl::reference {

/// Power moments b1..b4 (b0 = 1 implied).
struct Moments {
    double b1 = 0, b2 = 0, b3 = 0, b4 = 0;
};

/// Non-linear representation (Algorithm 2): depths y1 <= y2, weight v2 of y2, offset xi4.
struct Nlq {
    double y1 = 0, y2 = 0, v2 = 0, xi4 = 0;
};

/// Bounds on the share of depth below zf: lower = mass strictly below, upper = lower + the
/// mass the minimizing distribution puts at zf.
struct Bounds {
    double lower = 0, upper = 0;
};

/// A discrete depth distribution: depths with non-negative weights (normalized on use).
struct Distribution {
    std::vector<double> depth;
    std::vector<double> weight;
};

inline constexpr double alpha_float = 3e-7;
inline constexpr double bstar_float = 0.375;
inline constexpr double alpha_msm64 = 6e-5;
inline constexpr double bstar_msm64 = 0.628;

/// z = 2d - 1 (range [0,1]) or d (range [-1,1]).
double internal_depth(double d, bool depth_range_zero_one);

Moments moments_of(double z);
/// Weighted mean of b(z) over the distribution.
Moments moments_of(const Distribution& distribution);
/// (1 - alpha) b + alpha (0, bstar, 0, bstar).
Moments bias(const Moments& b, double alpha, double bstar);
/// Moments of z from the moments of z - c.
Moments unshift(const Moments& shifted, double c);
/// Moments of z - c from the moments of z.
Moments shift(const Moments& b, double c);

/// Algorithm 2 in long double. A (numerically) zero variance gives y1 = y2 = b1, v2 = 1/2,
/// xi4 = 0. Nothing is clamped.
Nlq nlq_from_moments(const Moments& biased);
/// Eq. 4 of Peters, HPG 2017: (1 - v2) b(y1) + v2 b(y2) + (0, 0, 0, xi4).
Moments moments_from_nlq(const Nlq& nlq);

/// Psi4 of docs/math.md (xi4 clamped to [1.2e-7, 0.25]) and its inverse.
double psi4(double xi4);
double psi4_inverse(double psi);

/// The affine basis of msm64 (R, G, B, A) of moments and back, unquantized.
std::array<double, 4> msm64_affine(const Moments& b);
Moments msm64_affine_inverse(const std::array<double, 4>& rgba);

/// 16-bit codes of the 64-bit formats, channel order R, G, B, A.
using Codes16 = std::array<std::uint16_t, 4>;
/// Two little-endian words of a 64-bit texel (channel 0 low half of word 0, ...).
std::array<std::uint32_t, 2> pack_codes16(const Codes16& codes);
Codes16 unpack_codes16(const std::array<std::uint32_t, 2>& words);

Codes16 encode_msm64(const Moments& b);
Moments decode_msm64(const Codes16& codes);
Codes16 encode_nlq64(const Nlq& nlq);
Nlq decode_nlq64(const Codes16& codes);

/// Fields of an nlq32 texel before packing.
struct Nlq32Fields {
    std::uint32_t psi = 0;     ///< ceil(63 Psi4)
    std::uint32_t sqrt_v2 = 0; ///< round(127 sqrt(v2))
    std::uint32_t t1 = 0;      ///< 9-bit folded depth code
    std::uint32_t t2 = 0;      ///< 10-bit folded depth code
};
Nlq32Fields nlq32_fields(const Nlq& nlq);
std::uint32_t pack_nlq32(const Nlq32Fields& fields);
Nlq32Fields unpack_nlq32(std::uint32_t word);
std::uint32_t encode_nlq32(const Nlq& nlq);
Nlq decode_nlq32(std::uint32_t word);

/// Generic 4MSM (Algorithm 1 of Peters, HPG 2017) on biased moments, in long double: Hankel system
/// B q = (1, zf, zf^2), roots of the quadratic, weights from the Vandermonde system.
/// Singular B (at most two points of support): the exact shares of that distribution.
Bounds hamburger4(const Moments& biased, double zf);

/// Shadow of an nlq texel: moments rebuilt by Eq. 4, then the generic 4MSM lower bound.
/// With algorithm3_clamps, first the clamps that Algorithm 3 of docs/math.md applies:
/// y2 - y1 >= 1e-6, 1e-6 <= v2 <= 1 - 1e-6 (the texel the shading actually sees).
double nlq_shadow(const Nlq& nlq, double zf, bool algorithm3_clamps = true);

/// Exact filtered shadow: share of the mass strictly below zf.
double exact_shadow(const Distribution& distribution, double zf);

} // namespace msmcl::reference
