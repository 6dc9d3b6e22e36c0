// Double-precision reference of resolve + separable Gaussian blur.
#include "reference/filter_reference.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace msmcl::reference {

namespace {

// m += w * (z, z^2, z^3, z^4)
void add_weighted_powers(Moments& m, double w, double z) {
    m.b1 += w * z;
    m.b2 += w * z * z;
    m.b3 += w * z * z * z;
    m.b4 += w * z * z * z * z;
}

// m += w * source
void add_weighted(Moments& m, double w, const Moments& source) {
    m.b1 += w * source.b1;
    m.b2 += w * source.b2;
    m.b3 += w * source.b3;
    m.b4 += w * source.b4;
}

} // namespace

double moment(const Moments& m, int j) {
    return j == 1 ? m.b1 : j == 2 ? m.b2 : j == 3 ? m.b3 : m.b4;
}

std::array<double, 9> gaussian_weights(double sigma) {
    std::array<double, 9> weights{};
    // sigma 0: no blur, all weight on the centre tap.
    if (sigma == 0.0) {
        weights[4] = 1.0;
        return weights;
    }
    double total = 0.0;
    for (int i = -4; i <= 4; ++i) {
        weights[i + 4] = std::exp(-double(i * i) / (2.0 * sigma * sigma));
        total += weights[i + 4];
    }
    for (double& w : weights) w /= total;
    return weights;
}

std::vector<Moments> resolve(const DepthMap& map) {
    std::vector<Moments> moments(static_cast<std::size_t>(map.width) * map.height);
    for (std::size_t texel = 0; texel < moments.size(); ++texel) {
        // Mean over the samples of the texel.
        for (int s = 0; s < map.samples; ++s)
            add_weighted_powers(moments[texel], 1.0 / map.samples,
                                internal_depth(map.depth[texel * map.samples + s], map.zero_one));
    }
    return moments;
}

std::vector<Moments> blur(const std::vector<Moments>& moments, int width, int height,
                          const std::array<double, 9>& weights, bool horizontal) {
    std::vector<Moments> blurred(moments.size());
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            Moments& sum = blurred[static_cast<std::size_t>(y) * width + x];
            for (int i = -4; i <= 4; ++i) {
                // Clamp-to-edge: taps outside the image read the edge texel.
                const int sx = horizontal ? std::clamp(x + i, 0, width - 1) : x;
                const int sy = horizontal ? y : std::clamp(y + i, 0, height - 1);
                add_weighted(sum, weights[i + 4], moments[static_cast<std::size_t>(sy) * width + sx]);
            }
        }
    }
    return blurred;
}

Moments filter_moments_at(const DepthMap& map, double sigma, int x, int y) {
    const std::array<double, 9> weights = gaussian_weights(sigma);
    Moments sum;
    for (int dy = -4; dy <= 4; ++dy) {
        for (int dx = -4; dx <= 4; ++dx) {
            // Clamp-to-edge in both directions; the 2D weight is the product of the 1D ones.
            const int sx = std::clamp(x + dx, 0, map.width - 1);
            const int sy = std::clamp(y + dy, 0, map.height - 1);
            const std::size_t texel = static_cast<std::size_t>(sy) * map.width + sx;
            const double w = weights[dx + 4] * weights[dy + 4] / map.samples;
            for (int s = 0; s < map.samples; ++s)
                add_weighted_powers(sum, w, internal_depth(map.depth[texel * map.samples + s], map.zero_one));
        }
    }
    return sum;
}

std::vector<Moments> filter_moments(const DepthMap& map, double sigma) {
    const std::array<double, 9> weights = gaussian_weights(sigma);
    const std::vector<Moments> resolved = resolve(map);
    const std::vector<Moments> rows = blur(resolved, map.width, map.height, weights, true);
    return blur(rows, map.width, map.height, weights, false);
}

} // namespace msmcl::reference
