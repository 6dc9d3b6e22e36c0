// The warps and shading of docs/math.md, "Shading VSM, EVSM and ESM", in double precision.
#include "reference/filterable_reference.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace msmcl::reference {

Channels warp_channels(Warp warp, double t, double positive, double negative) {
    if (warp == Warp::vsm) return {t, t * t, 0, 0};
    if (warp == Warp::esm) return {std::exp(positive * (t - 1.0)), 0, 0, 0};
    const double x = 2.0 * t - 1.0;
    const double p = std::exp(positive * x);
    if (warp == Warp::evsm2) return {p, p * p, 0, 0};
    const double n = -std::exp(-negative * x);
    return {p, p * p, n, n * n};
}

Channels warp_channels(Warp warp, const std::vector<double>& t, const std::vector<double>& weight, double positive,
                       double negative) {
    Channels sum{0, 0, 0, 0};
    double total = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
        const Channels c = warp_channels(warp, t[i], positive, negative);
        for (int k = 0; k < 4; ++k) sum[k] += weight[i] * c[k];
        total += weight[i];
    }
    for (double& s : sum) s /= total;
    return sum;
}

double chebyshev_upper(double mean, double mean_square, double min_variance, double receiver) {
    if (receiver <= mean) return 1.0;
    const double variance = std::max(mean_square - mean * mean, min_variance);
    const double d = receiver - mean;
    return variance / (variance + d * d);
}

double warp_shadow(const Channels& stored, double receiver_t, const WarpShading& s) {
    const double t = std::clamp(receiver_t, 0.0, 1.0);
    if (s.warp == Warp::esm) return 1.0 - std::clamp(std::exp(-s.positive * (t - 1.0)) * stored[0], 0.0, 1.0);
    double visible;
    if (s.warp == Warp::vsm) {
        visible = chebyshev_upper(stored[0], stored[1], s.min_variance, t);
    } else {
        // The receiver warped as the texels are; V scaled by the warp's slope dw/dt = 2 c w.
        const Channels r = warp_channels(s.warp, t, s.positive, s.negative);
        const double slope_p = 2.0 * s.positive * r[0];
        visible = chebyshev_upper(stored[0], stored[1], s.min_variance * slope_p * slope_p, r[0]);
        if (s.warp == Warp::evsm4) {
            const double slope_n = 2.0 * s.negative * r[2];
            visible = std::min(visible, chebyshev_upper(stored[2], stored[3], s.min_variance * slope_n * slope_n, r[2]));
        }
    }
    const double reduced = std::clamp((visible - s.light_bleed_reduction) / (1.0 - s.light_bleed_reduction), 0.0, 1.0);
    return 1.0 - reduced;
}

double half_value(std::uint16_t code) {
    const double sign = (code & 0x8000u) ? -1.0 : 1.0;
    const int exponent = (code >> 10) & 0x1f;
    const int mantissa = code & 0x3ff;
    if (exponent == 31)
        return mantissa ? std::numeric_limits<double>::quiet_NaN() : sign * std::numeric_limits<double>::infinity();
    if (exponent == 0) return sign * std::ldexp(mantissa, -24);
    return sign * std::ldexp(1024 + mantissa, exponent - 25);
}

double half_spacing(double v) {
    const double a = std::fabs(v);
    if (a < std::ldexp(1.0, -14)) return std::ldexp(1.0, -24);
    int exponent = 0;
    std::frexp(a, &exponent); // a = f 2^exponent, f in [0.5, 1)
    return std::ldexp(1.0, exponent - 11);
}

double unit_depth(double d, bool zero_one) { return zero_one ? d : 0.5 * (d + 1.0); }

std::vector<Channels> filter_warped(const DepthMap& map, double sigma, Warp warp, double positive, double negative) {
    const std::size_t texels = static_cast<std::size_t>(map.width) * map.height;
    // The mean of the warped samples of each texel.
    std::vector<Channels> resolved(texels, Channels{});
    for (std::size_t texel = 0; texel < texels; ++texel)
        for (int s = 0; s < map.samples; ++s) {
            const Channels w =
                warp_channels(warp, unit_depth(map.depth[texel * map.samples + s], map.zero_one), positive, negative);
            for (int k = 0; k < 4; ++k) resolved[texel][k] += w[k] / map.samples;
        }
    // Horizontal, then vertical 9-tap pass; taps outside the image read the edge texel.
    const std::array<double, 9> weights = gaussian_weights(sigma);
    const auto pass = [&](const std::vector<Channels>& in, bool horizontal) {
        std::vector<Channels> out(texels, Channels{});
        for (int y = 0; y < map.height; ++y)
            for (int x = 0; x < map.width; ++x)
                for (int i = -4; i <= 4; ++i) {
                    const int sx = horizontal ? std::clamp(x + i, 0, map.width - 1) : x;
                    const int sy = horizontal ? y : std::clamp(y + i, 0, map.height - 1);
                    const Channels& source = in[static_cast<std::size_t>(sy) * map.width + sx];
                    for (int k = 0; k < 4; ++k)
                        out[static_cast<std::size_t>(y) * map.width + x][k] += weights[i + 4] * source[k];
                }
        return out;
    };
    return pass(pass(resolved, true), false);
}

} // namespace msmcl::reference
