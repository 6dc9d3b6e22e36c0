// References for summed-area tables and soft shadows, written from docs/math.md and
// Peters et al., i3D 2016, section 3 without kernels/: direct sums instead of tables, Gaussian elimination
// instead of Cholesky, explicit overlap areas instead of 3x3 sub-rectangles.
#include "reference/sat_reference.hpp"

#include <algorithm>
#include <cmath>

namespace msmcl::reference {

namespace {

using Real = long double;

// Overlap of texel i ([i, i+1)) with [low, high).
double overlap(int i, double low, double high) {
    return std::max(0.0, std::min(high, i + 1.0) - std::max(low, double(i)));
}

Moments bias_float(const Moments& b, double alpha) { return bias(b, alpha, bstar_float); }

} // namespace

// Texel-aligned K x K search square around (u, v), clipped: odd K centred on the texel of
// (u, v), even K on the texel corner nearest to it.
TexelSquare search_square(int width, int height, double u, double v, int k) {
    const int start_x = static_cast<int>(std::floor(u + 0.5 - 0.5 * k));
    const int start_y = static_cast<int>(std::floor(v + 0.5 - 0.5 * k));
    return {std::max(start_x, 0), std::max(start_y, 0), std::min(start_x + k - 1, width - 1),
            std::min(start_y + k - 1, height - 1)};
}

double filter_side(const SoftParams& p, double zf, double blocker_depth) {
    return std::clamp(p.light_size * std::max(zf - blocker_depth, 0.0), p.min_filter_size, p.max_filter_size);
}

std::uint32_t sat_scale(std::uint64_t max_kernel_texels) {
    return static_cast<std::uint32_t>(4294967295ull / max_kernel_texels);
}

std::vector<double> affine_channels(const DepthMap& map) {
    const std::vector<Moments> moments = resolve(map);
    std::vector<double> channels;
    channels.reserve(4 * moments.size());
    for (const Moments& m : moments)
        for (double c : msm64_affine(m)) channels.push_back(c);
    return channels;
}

SatTexels quantize_depth_map(const DepthMap& map, std::uint32_t scale) {
    SatTexels texels;
    texels.width = map.width;
    texels.height = map.height;
    for (double c : affine_channels(map)) {
        const double q = std::floor(c * double(scale) + 0.5);
        texels.values.push_back(static_cast<std::uint32_t>(std::clamp(q, 0.0, double(scale))));
    }
    return texels;
}

std::vector<std::uint32_t> prefix_sums(const SatTexels& t) {
    // Column sums so far per channel, then the running row sum: S(x,y) = S(x,y-1) + row prefix.
    std::vector<std::uint64_t> table(t.values.size());
    for (int y = 0; y < t.height; ++y) {
        std::uint64_t row[4] = {0, 0, 0, 0};
        for (int x = 0; x < t.width; ++x) {
            for (int c = 0; c < 4; ++c) {
                row[c] += t.at(x, y, c);
                const std::size_t at = 4 * (static_cast<std::size_t>(y) * t.width + x) + c;
                table[at] = row[c] + (y > 0 ? table[at - 4 * static_cast<std::size_t>(t.width)] : 0);
            }
        }
    }
    std::vector<std::uint32_t> wrapped(table.size());
    for (std::size_t i = 0; i < table.size(); ++i) wrapped[i] = static_cast<std::uint32_t>(table[i] % 4294967296ull);
    return wrapped;
}

std::array<std::uint64_t, 4> direct_sum(const SatTexels& t, int x0, int y0, int x1, int y1) {
    std::array<std::uint64_t, 4> sum{0, 0, 0, 0};
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x)
            for (int c = 0; c < 4; ++c) sum[c] += t.at(x, y, c);
    return sum;
}

std::array<double, 4> area_weighted_mean(const SatTexels& t, double left, double top, double right, double bottom) {
    std::array<double, 4> sum{0, 0, 0, 0};
    for (int y = static_cast<int>(std::floor(top)); y < static_cast<int>(std::ceil(bottom)); ++y) {
        const double wy = overlap(y, top, bottom);
        for (int x = static_cast<int>(std::floor(left)); x < static_cast<int>(std::ceil(right)); ++x) {
            const double w = wy * overlap(x, left, right);
            for (int c = 0; c < 4; ++c) sum[c] += w * t.at(x, y, c);
        }
    }
    const double area = (right - left) * (bottom - top);
    for (double& s : sum) s /= area;
    return sum;
}

Moments moments_of_channel_mean(const std::array<double, 4>& mean_integers, std::uint32_t scale) {
    return msm64_affine_inverse({mean_integers[0] / scale, mean_integers[1] / scale, mean_integers[2] / scale,
                                 mean_integers[3] / scale});
}

ThreePoints three_point_reconstruction(const Moments& b, double zf_in) {
    const Real zf = zf_in;
    ThreePoints points;
    // B c = (1, zf, zf^2) with the Hankel matrix B of (1, b1, b2, b3, b4).
    Real hankel[3][3] = {{1, b.b1, b.b2}, {b.b1, b.b2, b.b3}, {b.b2, b.b3, b.b4}};
    Real rhs[3] = {1, zf, zf * zf};
    Real c[3];
    const Real variance = Real(b.b2) - Real(b.b1) * b.b1;
    if (!(variance > 1e-15L) || !solve3(hankel, rhs, c)) {
        // A single depth: all weight at b1.
        points.count = 1;
        points.depth[0] = b.b1;
        points.weight[0] = 1;
        return points;
    }
    // The other two support points: roots of c2 z^2 + c1 z + c0.
    Real z[3] = {zf, 0, 0};
    const Real discriminant = std::max(c[1] * c[1] - 4 * c[2] * c[0], Real(0));
    if (std::fabs(c[2]) <= 1e-18L * std::max(std::fabs(c[1]), std::fabs(c[0]))) {
        z[1] = -c[0] / c[1];
        z[2] = z[1];
    } else {
        const Real t = -0.5L * (c[1] + (c[1] >= 0 ? std::sqrt(discriminant) : -std::sqrt(discriminant)));
        z[1] = t / c[2];
        z[2] = t != 0 ? c[0] / t : z[1];
    }
    // Weights: Vandermonde system on (1, b1, b2).
    Real w[3];
    Real vandermonde[3][3] = {{1, 1, 1}, {z[0], z[1], z[2]}, {z[0] * z[0], z[1] * z[1], z[2] * z[2]}};
    Real moments[3] = {1, b.b1, b.b2};
    if (z[1] == z[2] || !solve3(vandermonde, moments, w)) {
        // Two points zf and z1: w1 from b1.
        w[1] = (Real(b.b1) - zf) / (z[1] - zf);
        w[0] = 1 - w[1];
        w[2] = 0;
        points.count = 2;
    }
    for (int i = 0; i < 3; ++i) {
        points.depth[i] = static_cast<double>(z[i]);
        points.weight[i] = static_cast<double>(w[i]);
    }
    return points;
}

SoftResult moment_soft_shadow(const SatTexels& t, std::uint32_t scale, double u, double v, double zf,
                              const SoftParams& p) {
    SoftResult result;
    u = std::clamp(u, 0.0, double(t.width));
    v = std::clamp(v, 0.0, double(t.height));
    // Blocker search: mean moments of the search square, three depths.
    const TexelSquare s = search_square(t.width, t.height, u, v, p.search_size);
    const std::array<std::uint64_t, 4> sums = direct_sum(t, s.x0, s.y0, s.x1, s.y1);
    const double texels = double(s.x1 - s.x0 + 1) * (s.y1 - s.y0 + 1);
    const Moments search = bias_float(
        moments_of_channel_mean({sums[0] / texels, sums[1] / texels, sums[2] / texels, sums[3] / texels}, scale),
        p.alpha);
    const ThreePoints points = three_point_reconstruction(search, zf);
    double share = 0, weighted = 0;
    for (int i = 0; i < 3; ++i) {
        // The receiver's own point zf never counts; the others when in front of it.
        const bool is_receiver = points.count > 1 && i == 0;
        if (!is_receiver && points.depth[i] < zf) {
            share += points.weight[i];
            weighted += points.weight[i] * points.depth[i];
        }
    }
    result.blocker_shadow = share;
    result.blocker_depth = (p.blocker_eps * zf + weighted) / (p.blocker_eps + share);
    // Umbra early-out.
    if (share > 1 - p.umbra_eps) {
        result.shadow = 1;
        return result;
    }
    // Filter square from the penumbra estimate, clipped to the map, area-weighted.
    result.filter_size = filter_side(p, zf, result.blocker_depth);
    const double half = 0.5 * result.filter_size;
    const double left = std::max(u - half, 0.0), right = std::min(u + half, double(t.width));
    const double top = std::max(v - half, 0.0), bottom = std::min(v + half, double(t.height));
    const Moments filtered = bias_float(moments_of_channel_mean(area_weighted_mean(t, left, top, right, bottom), scale),
                                        p.alpha);
    result.shadow = std::clamp(hamburger4(filtered, zf).lower, 0.0, 1.0);
    return result;
}

SoftResult pcss_shadow(const DepthMap& map, double u, double v, double zf, const SoftParams& p) {
    SoftResult result;
    u = std::clamp(u, 0.0, double(map.width));
    v = std::clamp(v, 0.0, double(map.height));
    const auto sample_z = [&](int x, int y, int s) {
        return internal_depth(map.depth[(static_cast<std::size_t>(y) * map.width + x) * map.samples + s], map.zero_one);
    };
    // Blocker search over every sample of the search square.
    const TexelSquare s = search_square(map.width, map.height, u, v, p.search_size);
    double blockers = 0, depth_sum = 0;
    for (int y = s.y0; y <= s.y1; ++y)
        for (int x = s.x0; x <= s.x1; ++x)
            for (int k = 0; k < map.samples; ++k) {
                const double z = sample_z(x, y, k);
                if (z < zf) {
                    blockers += 1;
                    depth_sum += z;
                }
            }
    const double total = double(s.x1 - s.x0 + 1) * (s.y1 - s.y0 + 1) * map.samples;
    result.blocker_shadow = blockers / total;
    if (blockers == 0) {
        result.blocker_depth = zf;
        return result; // fully lit
    }
    result.blocker_depth = depth_sum / blockers;
    // Percentage-closer filtering over the filter square, area-weighted.
    result.filter_size = filter_side(p, zf, result.blocker_depth);
    const double half = 0.5 * result.filter_size;
    const double left = std::max(u - half, 0.0), right = std::min(u + half, double(map.width));
    const double top = std::max(v - half, 0.0), bottom = std::min(v + half, double(map.height));
    double shadow = 0;
    for (int y = static_cast<int>(std::floor(top)); y < static_cast<int>(std::ceil(bottom)); ++y) {
        const double wy = overlap(y, top, bottom);
        for (int x = static_cast<int>(std::floor(left)); x < static_cast<int>(std::ceil(right)); ++x) {
            double in_front = 0;
            for (int k = 0; k < map.samples; ++k) in_front += sample_z(x, y, k) < zf ? 1 : 0;
            shadow += wy * overlap(x, left, right) * in_front / map.samples;
        }
    }
    result.shadow = shadow / ((right - left) * (bottom - top));
    return result;
}

} // namespace msmcl::reference
