// Double-precision ground truth of the filter (docs/math.md): resolve, 9-tap Gaussian
// with clamp-to-edge, horizontal then vertical. Independent of kernels/ and of the
// library: plain loops over plain arrays. The moment math (bias, Algorithm 2, encoders)
// is in reference/moment_math.hpp.
#pragma once

#include "reference/moment_math.hpp"

#include <array>
#include <vector>

namespace msmcl::reference {

/// A (multisampled) depth map: `depth[(y * width + x) * samples + s]`.
struct DepthMap {
    int width = 0;
    int height = 0;
    int samples = 1;
    std::vector<float> depth;
    bool zero_one = true; ///< rendered depth in [0,1] (z = 2d - 1), else in [-1,1] (z = d)
};

/// Moment b_j (j = 1..4) of `m`.
double moment(const Moments& m, int j);

/// The 9 normalized weights w_{-4..4} = exp(-i^2 / (2 sigma^2)) / sum; sigma 0 = impulse.
std::array<double, 9> gaussian_weights(double sigma);

/// Per texel (row-major) the mean of (z, z^2, z^3, z^4) over its samples.
std::vector<Moments> resolve(const DepthMap& map);

/// One 9-tap pass with clamp-to-edge, along x (horizontal) or y.
std::vector<Moments> blur(const std::vector<Moments>& moments, int width, int height,
                          const std::array<double, 9>& weights, bool horizontal);

/// The filtered moments of texel (x, y) alone, as one direct 9x9 sum (for spot checks
/// of large maps).
Moments filter_moments_at(const DepthMap& map, double sigma, int x, int y);

/// resolve, horizontal blur, vertical blur: the filtered moments per texel (row-major).
std::vector<Moments> filter_moments(const DepthMap& map, double sigma);

} // namespace msmcl::reference
