// Independent references of the summed-area table work (docs/math.md, Peters et al., i3D 2016, section 3):
// integer texels, 64-bit direct rectangle sums and prefix sums, area-weighted float
// integrals, moment soft shadows evaluated from direct sums in long double, and brute-force
// percentage-closer soft shadows (PCSS) on the depth samples. Plain loops, no kernels/.
#pragma once

#include "reference/filter_reference.hpp"
#include "reference/moment_math.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace msmcl::reference {

/// floor((2^32 - 1) / N).
std::uint32_t sat_scale(std::uint64_t max_kernel_texels);

/// Integer texels: 4 per texel (channels R, G, B, A), row-major.
struct SatTexels {
    int width = 0;
    int height = 0;
    std::vector<std::uint32_t> values;

    std::uint32_t at(int x, int y, int c) const {
        return values[4 * (static_cast<std::size_t>(y) * width + x) + c];
    }
};

/// Each texel: resolved moments (double), msm64 affine channels, round(c * scale) half up,
/// clamped to [0, scale].
SatTexels quantize_depth_map(const DepthMap& map, std::uint32_t scale);

/// The channels before rounding (double), for error bounds: 4 per texel.
std::vector<double> affine_channels(const DepthMap& map);

/// 2D prefix sums in 64 bits, reduced mod 2^32 at the end: the table the kernels must produce.
std::vector<std::uint32_t> prefix_sums(const SatTexels& texels);

/// Exact 64-bit channel sums over texels [x0, x1] x [y0, y1] (inclusive), by direct summation.
std::array<std::uint64_t, 4> direct_sum(const SatTexels& texels, int x0, int y0, int x1, int y1);

/// Area-weighted mean of the texel values (in units of the texel integers) over
/// [left, right) x [top, bottom), texel i covering [i, i + 1).
std::array<double, 4> area_weighted_mean(const SatTexels& texels, double left, double top, double right,
                                         double bottom);

/// Power moments of mean channels (integers / scale), by the inverse affine basis.
Moments moments_of_channel_mean(const std::array<double, 4>& mean_integers, std::uint32_t scale);

/// Three-point reconstruction at zf behind the 4MSM bound (Peters et al., i3D 2016, section 1.2): depths
/// zf, z2, z3 with weights matching b0..b4. Long double Gaussian elimination.
struct ThreePoints {
    double depth[3] = {0, 0, 0};
    double weight[3] = {0, 0, 0};
    int count = 3; ///< 2 or 1 when the moments have fewer points of support
};
ThreePoints three_point_reconstruction(const Moments& biased, double zf);

/// The parameters shared by moment soft shadows and PCSS (texel units, internal depth).
struct SoftParams {
    int search_size = 27;          ///< K, texel-aligned square
    double light_size = 64;        ///< filter side per unit of depth difference
    double min_filter_size = 1;
    double max_filter_size = 27;
    double alpha = 5e-6;           ///< moment bias (towards b* = (0, 3/8, 0, 3/8))
    double blocker_eps = 0.01;
    double umbra_eps = 0.01;
};

/// Texel-aligned K x K blocker search square around (u, v), clipped to the map: odd K
/// centred on the texel of (u, v), even K on the texel corner nearest to it. Inclusive.
struct TexelSquare {
    int x0, y0, x1, y1;
};
TexelSquare search_square(int width, int height, double u, double v, int k);

/// Filter side light_size * (zf - blocker_depth), clamped to [min, max] filter size.
double filter_side(const SoftParams& params, double zf, double blocker_depth);

/// What a soft shadow evaluation found, for diagnostics.
struct SoftResult {
    double shadow = 0;
    double blocker_shadow = 0; ///< share of the search region in front of zf
    double blocker_depth = 0;
    double filter_size = 0;
};

/// Moment soft shadow mapping from the integer texels by direct sums (no table): search
/// square, three depths, eps-weighted blocker depth, umbra early-out, filter square clipped to
/// the map with area weights, 4MSM lower bound (reference::hamburger4). u, v in texels
/// (clamped to the map), zf internal depth.
SoftResult moment_soft_shadow(const SatTexels& texels, std::uint32_t scale, double u, double v, double zf,
                              const SoftParams& params);

/// Brute-force PCSS on the depth samples: the same search square; average depth of the
/// samples in front of zf (none: fully lit); filter side light_size * (zf - average),
/// clamped as above; area-weighted share of samples in front of zf over the filter square
/// clipped to the map.
SoftResult pcss_shadow(const DepthMap& map, double u, double v, double zf, const SoftParams& params);

} // namespace msmcl::reference
