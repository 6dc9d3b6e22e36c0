// Double-precision reference of the VSM, EVSM and ESM filter (docs/formats.md).
#include "reference/filterable_reference.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace msmcl::reference {

double unit_depth(double d, bool zero_one) { return zero_one ? d : 0.5 * (d + 1.0); }

Lanes warp(double t, Warp kind, double c_positive, double c_negative) {
    const double x = 2.0 * t - 1.0;
    switch (kind) {
    case Warp::vsm: return {t, t * t, 0.0, 0.0};
    case Warp::evsm2: {
        const double p = std::exp(c_positive * x);
        return {p, p * p, 0.0, 0.0};
    }
    case Warp::evsm4: {
        const double p = std::exp(c_positive * x), n = -std::exp(-c_negative * x);
        return {p, p * p, n, n * n};
    }
    case Warp::esm: return {std::exp(c_positive * (t - 1.0)), 0.0, 0.0, 0.0};
    }
    return {};
}

std::vector<Lanes> filter_warped(const DepthMap& map, double sigma, Warp kind, double c_positive, double c_negative) {
    const std::size_t texels = static_cast<std::size_t>(map.width) * map.height;
    // The mean of the warped samples of each texel.
    std::vector<Lanes> resolved(texels, Lanes{});
    for (std::size_t texel = 0; texel < texels; ++texel)
        for (int s = 0; s < map.samples; ++s) {
            const Lanes w = warp(unit_depth(map.depth[texel * map.samples + s], map.zero_one), kind, c_positive, c_negative);
            for (int k = 0; k < 4; ++k) resolved[texel][k] += w[k] / map.samples;
        }
    // Horizontal, then vertical 9-tap pass; taps outside the image read the edge texel.
    const std::array<double, 9> weights = gaussian_weights(sigma);
    const auto pass = [&](const std::vector<Lanes>& in, bool horizontal) {
        std::vector<Lanes> out(texels, Lanes{});
        for (int y = 0; y < map.height; ++y)
            for (int x = 0; x < map.width; ++x)
                for (int i = -4; i <= 4; ++i) {
                    const int sx = horizontal ? std::clamp(x + i, 0, map.width - 1) : x;
                    const int sy = horizontal ? y : std::clamp(y + i, 0, map.height - 1);
                    const Lanes& source = in[static_cast<std::size_t>(sy) * map.width + sx];
                    for (int k = 0; k < 4; ++k)
                        out[static_cast<std::size_t>(y) * map.width + x][k] += weights[i + 4] * source[k];
                }
        return out;
    };
    return pass(pass(resolved, true), false);
}

double half_value(std::uint16_t code) {
    const double sign = (code & 0x8000u) ? -1.0 : 1.0;
    const int exponent = (code >> 10) & 0x1f;
    const int mantissa = code & 0x3ff;
    if (exponent == 0) return sign * std::ldexp(mantissa, -24);
    if (exponent == 31) return mantissa == 0 ? sign * HUGE_VAL : std::nan("");
    return sign * std::ldexp(1024 + mantissa, exponent - 25);
}

double half_spacing(double v) {
    const double a = std::fabs(v);
    if (a < std::ldexp(1.0, -14)) return std::ldexp(1.0, -24);
    int exponent = 0;
    std::frexp(a, &exponent); // a = f 2^exponent, f in [0.5, 1)
    return std::ldexp(1.0, exponent - 11);
}

} // namespace msmcl::reference
