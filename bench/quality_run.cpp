// msmcl-quality, run: the device's shadows of every format, the PCF ground truth and
// the double-precision decomposition of nlq64 - moments128 (bench/quality.hpp).
#include "quality.hpp"

#include <msmcl/shade.hpp>

#include "runtime/texture_kinds.hpp"

#include "reference/filter_reference.hpp"
#include "reference/moment_math.hpp"
#include "tools/msaa_pattern.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace quality {

namespace {

namespace ref = msmcl::reference;

/// Runs body(i) for i in [0, count) on the host's cores (each i writes only its own slot).
void parallel_for(std::size_t count, const std::function<void(std::size_t)>& body) {
    const std::size_t threads = std::max(1u, std::thread::hardware_concurrency());
    if (threads == 1 || count < 1024) {
        for (std::size_t i = 0; i < count; ++i) body(i);
        return;
    }
    std::vector<std::thread> pool;
    for (std::size_t t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (std::size_t i = t * count / threads; i < (t + 1) * count / threads; ++i) body(i);
        });
    for (std::thread& thread : pool) thread.join();
}

/// The four texel centres around (u - 0.5, v - 0.5), clamped to the edge, and weights.
struct BilinearTaps {
    int x0, x1, y0, y1;
    double fx, fy;
};

BilinearTaps bilinear_taps(double u, double v, int width, int height) {
    const double su = u - 0.5, sv = v - 0.5;
    const double fx0 = std::floor(su), fy0 = std::floor(sv);
    BilinearTaps taps;
    taps.fx = su - fx0;
    taps.fy = sv - fy0;
    const int ix = static_cast<int>(fx0), iy = static_cast<int>(fy0);
    taps.x0 = std::clamp(ix, 0, width - 1);
    taps.x1 = std::clamp(ix + 1, 0, width - 1);
    taps.y0 = std::clamp(iy, 0, height - 1);
    taps.y1 = std::clamp(iy + 1, 0, height - 1);
    return taps;
}

/// The texel a nearest lookup reads: floor(u), floor(v), clamped.
std::size_t nearest_texel(double u, double v, int width, int height) {
    const int x = std::clamp(static_cast<int>(std::floor(u)), 0, width - 1);
    const int y = std::clamp(static_cast<int>(std::floor(v)), 0, height - 1);
    return static_cast<std::size_t>(y) * width + x;
}

/// Percentage-closer filtering with the 9x9 Gaussian of the filter, in double: per texel
/// the weighted share of samples with internal depth < receiver depth - bias, bilinear
/// between texel centres like the lookup. Clamp-to-edge like the filter.
class PercentageCloser {
public:
    PercentageCloser(const msmcl::DepthImage& depth, double sigma)
        : depth_(depth), weights_(ref::gaussian_weights(sigma)),
          sample_offsets_(msmcl::data::standard_sample_pattern(depth.samples)) {}

    /// `gradient_x/y`: the receiver plane's internal depth per texel (0, 0 = constant depth).
    double at(double u, double v, double receiver_z, double gradient_x = 0, double gradient_y = 0) const {
        double shadow = 0;
        for_each_sample(u, v, receiver_z, gradient_x, gradient_y, [&](double weight, double z, double plane_z) {
            if (z < plane_z - depth_bias) shadow += weight;
        });
        return shadow;
    }

    /// Spread (max - min) of the samples' depth minus the receiver plane there, over every
    /// sample the bilinear lookup at (u, v) filters: ~0 where the footprint is one plane.
    double plane_spread(double u, double v, double receiver_z, double gradient_x, double gradient_y) const {
        double low = 1e30, high = -1e30;
        for_each_sample(u, v, receiver_z, gradient_x, gradient_y, [&](double, double z, double plane_z) {
            low = std::min(low, z - plane_z);
            high = std::max(high, z - plane_z);
        });
        return high - low;
    }

    /// The 4MSM lower bound (128-bit bias, double) of the receiver's plane alone: the depths
    /// the plane would put at the footprint's samples, with their weights. The self-shadowing
    /// of a filtered moment map on a surface that is sloped in light space.
    double plane_self_shadow(double u, double v, double receiver_z, double gradient_x, double gradient_y) const {
        ref::Distribution plane;
        for_each_sample(u, v, receiver_z, gradient_x, gradient_y, [&](double weight, double, double plane_z) {
            plane.depth.push_back(std::clamp(plane_z, -1.0, 1.0));
            plane.weight.push_back(weight);
        });
        const ref::Moments moments = ref::bias(ref::moments_of(plane), alpha_128, bstar_128);
        return std::clamp(ref::hamburger4(moments, receiver_z - depth_bias).lower, 0.0, 1.0);
    }

private:
    /// Calls visit(weight, sample depth, receiver plane depth at the sample) for every sample
    /// of the 9x9 footprints of the four bilinear texels (weights sum to 1).
    template <typename Visit>
    void for_each_sample(double u, double v, double receiver_z, double gradient_x, double gradient_y,
                         Visit&& visit) const {
        const BilinearTaps taps = bilinear_taps(u, v, depth_.width, depth_.height);
        const int base_x = static_cast<int>(std::floor(u - 0.5)), base_y = static_cast<int>(std::floor(v - 0.5));
        const std::array<std::array<int, 2>, 4> positions = {{{base_x, base_y}, {base_x + 1, base_y},
                                                              {base_x, base_y + 1}, {base_x + 1, base_y + 1}}};
        const std::array<std::array<int, 2>, 4> texels = {{{taps.x0, taps.y0}, {taps.x1, taps.y0},
                                                           {taps.x0, taps.y1}, {taps.x1, taps.y1}}};
        const std::array<double, 4> blend = {(1 - taps.fx) * (1 - taps.fy), taps.fx * (1 - taps.fy),
                                             (1 - taps.fx) * taps.fy, taps.fx * taps.fy};
        for (int t = 0; t < 4; ++t) {
            // Blur footprint of one texel: 9x9 taps, S samples each.
            for (int j = -4; j <= 4; ++j) {
                const int y = std::clamp(texels[t][1] + j, 0, depth_.height - 1);
                for (int i = -4; i <= 4; ++i) {
                    const int x = std::clamp(texels[t][0] + i, 0, depth_.width - 1);
                    const double w = blend[t] * weights_[i + 4] * weights_[j + 4] / depth_.samples;
                    // The receiver plane continued to this tap's texel centre ...
                    const double centre_z = receiver_z + gradient_x * (positions[t][0] + i + 0.5 - u) +
                                            gradient_y * (positions[t][1] + j + 0.5 - v);
                    for (int s = 0; s < depth_.samples; ++s) {
                        // ... and to the sample's position (standard D3D pattern of the sample data).
                        const double plane_z = centre_z + gradient_x * sample_offsets_[s].x16 / 16.0 +
                                               gradient_y * sample_offsets_[s].y16 / 16.0;
                        visit(w, 2.0 * depth_.at(x, y, s) - 1.0, plane_z);
                    }
                }
            }
        }
    }

    const msmcl::DepthImage& depth_;
    std::array<double, 9> weights_;
    std::vector<msmcl::data::SampleOffset> sample_offsets_; ///< where the samples were rendered
};

/// Receiver-plane depth gradient (internal depth per texel) of receiver (x, y) of the view
/// grid, from its neighbours like a shader's ddx/ddy: per screen axis the neighbour with the
/// smaller depth step (so a silhouette is not crossed), then the 2x2 solve. Zero where the
/// neighbours are degenerate; clamped to max_gradient per axis.
std::array<double, 2> receiver_plane_gradient(const msmcl::io::ReceiverGrid& grid, int x, int y) {
    constexpr double max_gradient = 0.05;
    const msmcl::Receivers& r = grid.points;
    auto index = [&](int px, int py) { return static_cast<std::size_t>(py) * grid.width + px; };
    const std::size_t centre = index(x, y);
    auto step = [&](int dx, int dy, std::array<double, 3>& out) {
        std::array<double, 3> best{};
        bool found = false;
        for (int sign : {1, -1}) {
            const int nx = x + sign * dx, ny = y + sign * dy;
            if (nx < 0 || ny < 0 || nx >= grid.width || ny >= grid.height) continue;
            const std::size_t n = index(nx, ny);
            const std::array<double, 3> d = {static_cast<double>(r.u[n]) - r.u[centre], static_cast<double>(r.v[n]) - r.v[centre],
                                             2.0 * (static_cast<double>(r.z[n]) - r.z[centre])};
            if (!found || std::abs(d[2]) < std::abs(best[2])) best = d;
            found = true;
        }
        out = best;
        return found;
    };
    std::array<double, 3> a{}, b{};
    if (!step(1, 0, a) || !step(0, 1, b)) return {0, 0};
    const double determinant = a[0] * b[1] - a[1] * b[0];
    if (std::abs(determinant) < 1e-9) return {0, 0};
    const double gx = (a[2] * b[1] - a[1] * b[2]) / determinant;
    const double gy = (a[0] * b[2] - a[2] * b[0]) / determinant;
    return {std::clamp(gx, -max_gradient, max_gradient), std::clamp(gy, -max_gradient, max_gradient)};
}

/// Double-precision shading of the filtered moments (reference/filter_reference.hpp), for
/// taking the nlq64 - moments128 difference apart: 128-bit moments blended then shaded,
/// and per-texel non-linear representations (exact, 16-bit, or the device's codes) shaded
/// per texel and blended like the library's nlq lookup.
class DoubleShading {
public:
    /// Per-texel representations of one map.
    enum class Texels { exact_nlq, nlq64, nlq64_psi_only, nlq64_depths_weight_only, device_nlq64 };

    DoubleShading(std::vector<ref::Moments> moments, int width, int height, const msmcl::Texture* device_nlq64)
        : moments_(std::move(moments)), width_(width), height_(height) {
        const std::size_t texels = moments_.size();
        for (auto& list : nlq_) list.resize(texels);
        parallel_for(texels, [&](std::size_t t) {
            // Algorithm 2 on the biased moments, then the 16-bit codes of docs/formats.md.
            const ref::Nlq exact = ref::nlq_from_moments(ref::bias(moments_[t], alpha_128, bstar_128));
            const ref::Nlq quantized = ref::decode_nlq64(ref::encode_nlq64(exact));
            nlq_[index(Texels::exact_nlq)][t] = exact;
            nlq_[index(Texels::nlq64)][t] = quantized;
            nlq_[index(Texels::nlq64_psi_only)][t] = {exact.y1, exact.y2, exact.v2, quantized.xi4};
            nlq_[index(Texels::nlq64_depths_weight_only)][t] = {quantized.y1, quantized.y2, quantized.v2, exact.xi4};
            if (device_nlq64) {
                const int x = static_cast<int>(t % width_), y = static_cast<int>(t / width_);
                nlq_[index(Texels::device_nlq64)][t] =
                    ref::decode_nlq64({device_nlq64->code16(x, y, 0), device_nlq64->code16(x, y, 1),
                                       device_nlq64->code16(x, y, 2), device_nlq64->code16(x, y, 3)});
            }
        });
    }

    /// 128-bit moments: bilinear blend of the moments (or the nearest texel), bias, 4MSM lower bound.
    double moments128(double u, double v, double zf, bool bilinear) const {
        ref::Moments m;
        if (bilinear) {
            const BilinearTaps taps = bilinear_taps(u, v, width_, height_);
            const std::array<std::pair<std::size_t, double>, 4> blend = texel_weights(taps);
            for (const auto& [texel, weight] : blend) {
                const ref::Moments& source = moments_[texel];
                m.b1 += weight * source.b1;
                m.b2 += weight * source.b2;
                m.b3 += weight * source.b3;
                m.b4 += weight * source.b4;
            }
        } else {
            m = moments_[nearest_texel(u, v, width_, height_)];
        }
        return std::clamp(ref::hamburger4(ref::bias(m, alpha_128, bstar_128), zf).lower, 0.0, 1.0);
    }

    /// A non-linear representation: Algorithm 3's result per texel, blended bilinearly.
    double nlq(Texels kind, double u, double v, double zf, bool bilinear) const {
        const std::vector<ref::Nlq>& texels = nlq_[index(kind)];
        auto shade = [&](std::size_t t) { return std::clamp(ref::nlq_shadow(texels[t], zf), 0.0, 1.0); };
        if (!bilinear) return shade(nearest_texel(u, v, width_, height_));
        double shadow = 0;
        for (const auto& [texel, weight] : texel_weights(bilinear_taps(u, v, width_, height_)))
            if (weight > 0) shadow += weight * shade(texel);
        return shadow;
    }

    const std::vector<ref::Moments>& moments() const { return moments_; }

private:
    static std::size_t index(Texels kind) { return static_cast<std::size_t>(kind); }
    std::array<std::pair<std::size_t, double>, 4> texel_weights(const BilinearTaps& taps) const {
        auto at = [&](int x, int y) { return static_cast<std::size_t>(y) * width_ + x; };
        return {{{at(taps.x0, taps.y0), (1 - taps.fx) * (1 - taps.fy)},
                 {at(taps.x1, taps.y0), taps.fx * (1 - taps.fy)},
                 {at(taps.x0, taps.y1), (1 - taps.fx) * taps.fy},
                 {at(taps.x1, taps.y1), taps.fx * taps.fy}}};
    }

    std::vector<ref::Moments> moments_;
    int width_, height_;
    std::array<std::vector<ref::Nlq>, 5> nlq_;
};

ErrorStats compare(const std::vector<double>& shadow, const std::vector<double>& reference) {
    ErrorStats stats;
    double sum = 0;
    for (std::size_t i = 0; i < shadow.size(); ++i) {
        const double error = std::abs(shadow[i] - reference[i]);
        sum += error;
        stats.max = std::max(stats.max, error);
        if (error > error_threshold) ++stats.count_above;
        if (error > large_error_threshold) ++stats.count_above_large;
    }
    stats.mean = shadow.empty() ? 0 : sum / shadow.size();
    stats.share_above = shadow.empty() ? 0 : static_cast<double>(stats.count_above) / shadow.size();
    return stats;
}

LeakStats banner_leak(const std::vector<double>& shadow, const std::vector<double>& truth,
                      const std::vector<std::size_t>& leak_set, bool available) {
    LeakStats stats;
    stats.available = available;
    stats.receivers = leak_set.size();
    if (leak_set.empty()) return stats;
    std::size_t leaking = 0;
    for (std::size_t i : leak_set) {
        const double leak = std::max(0.0, truth[i] - shadow[i]);
        stats.mean_truth += truth[i];
        stats.mean_leak += leak;
        if (leak > leak_significant) ++leaking;
    }
    stats.mean_truth /= leak_set.size();
    stats.mean_leak /= leak_set.size();
    stats.share_leaking = static_cast<double>(leaking) / leak_set.size();
    return stats;
}

/// Device shadow for every receiver, as double.
std::vector<double> device_shadow(msmcl::Context& context, const msmcl::Texture& map, const msmcl::Receivers& receivers,
                                  msmcl::Lookup lookup, float light_bleed_reduction = 0.0f) {
    msmcl::ShadeOptions options;
    options.lookup = lookup;
    options.depth_bias = static_cast<float>(depth_bias);
    if (light_bleed_reduction > 0.0f) options.light_bleed_reduction = light_bleed_reduction;
    const std::vector<float> shadow = msmcl::shade(context, map, receivers, options);
    return {shadow.begin(), shadow.end()};
}

/// The PCF ground truth per receiver (its plane, and a constant depth for comparison), the
/// receiver plane's gradient, and how far the samples each lookup filters stray from it.
struct GroundTruth {
    std::vector<double> truth, truth_constant_bias, spread;
    std::vector<std::array<double, 2>> gradients;
};

GroundTruth ground_truth(const PercentageCloser& pcf, const msmcl::io::ReceiverGrid& grid) {
    const msmcl::Receivers& receivers = grid.points;
    const std::size_t count = receivers.size();
    GroundTruth g{std::vector<double>(count), std::vector<double>(count), std::vector<double>(count),
                  std::vector<std::array<double, 2>>(count)};
    parallel_for(count, [&](std::size_t i) {
        const double receiver_z = 2.0 * receivers.z[i] - 1.0;
        g.gradients[i] = receiver_plane_gradient(grid, static_cast<int>(i % grid.width), static_cast<int>(i / grid.width));
        const auto& gradient = g.gradients[i];
        g.truth[i] = pcf.at(receivers.u[i], receivers.v[i], receiver_z, gradient[0], gradient[1]);
        g.truth_constant_bias[i] = pcf.at(receivers.u[i], receivers.v[i], receiver_z);
        g.spread[i] = pcf.plane_spread(receivers.u[i], receivers.v[i], receiver_z, gradient[0], gradient[1]);
    });
    return g;
}

/// Codes the float32 encoder writes against the double encoding of the double moments
/// (result.codes_off, texels_off, texels_off_one_depth, texel_count).
void count_codes_off(const msmcl::Texture& device_nlq64, const std::vector<ref::Moments>& moments,
                     SceneResult& result) {
    for (int y = 0; y < device_nlq64.height; ++y)
        for (int x = 0; x < device_nlq64.width; ++x) {
            const ref::Moments& m = moments[static_cast<std::size_t>(y) * device_nlq64.width + x];
            const ref::Codes16 expected = ref::encode_nlq64(ref::nlq_from_moments(ref::bias(m, alpha_128, bstar_128)));
            bool off = false;
            for (int c = 0; c < 4; ++c)
                if (std::abs(static_cast<int>(device_nlq64.code16(x, y, c)) - static_cast<int>(expected[c])) > 1) {
                    ++result.codes_off[c];
                    off = true;
                }
            result.texels_off += off;
            // One depth (variance < 1e-7): y1, y2, v2 hardly constrained, any codes shade alike.
            if (off && m.b2 - m.b1 * m.b1 < 1e-7) ++result.texels_off_one_depth;
        }
    result.texel_count = static_cast<double>(device_nlq64.width) * device_nlq64.height;
}

/// Self-shadowing check: moments128's receivers off the truth by > 3%, darker than a lit
/// truth; how many of them the 4MSM bound of their own plane alone explains
/// (result.moments128_above, _lighter, _darker_lit, _self_shadow).
void check_self_shadowing(const PercentageCloser& pcf, const msmcl::Receivers& receivers, const GroundTruth& g,
                          const std::vector<double>& moments128, SceneResult& result) {
    const std::vector<double>& truth = g.truth;
    std::vector<std::size_t> darker_lit;
    for (std::size_t i = 0; i < receivers.size(); ++i) {
        if (std::abs(moments128[i] - truth[i]) <= error_threshold) continue;
        ++result.moments128_above;
        if (moments128[i] < truth[i]) ++result.moments128_lighter;
        else if (truth[i] < error_threshold) darker_lit.push_back(i);
    }
    result.moments128_darker_lit = darker_lit.size();
    std::vector<char> explained(darker_lit.size());
    parallel_for(darker_lit.size(), [&](std::size_t k) {
        const std::size_t i = darker_lit[k];
        const double self_shadow = pcf.plane_self_shadow(receivers.u[i], receivers.v[i], 2.0 * receivers.z[i] - 1.0,
                                                         g.gradients[i][0], g.gradients[i][1]);
        explained[k] = std::abs(self_shadow - (moments128[i] - truth[i])) <= error_threshold;
    });
    for (char e : explained) result.moments128_self_shadow += e;
}

/// Banner receivers in the railing's shadow (none without materials).
std::vector<std::size_t> banner_leak_set(const std::vector<float>& materials, const std::vector<double>& truth) {
    std::vector<std::size_t> leak_set;
    for (std::size_t i = 0; i < materials.size(); ++i)
        if (static_cast<int>(materials[i]) == banner_material && truth[i] >= leak_truth_min) leak_set.push_back(i);
    return leak_set;
}

/// The device's shadow maps: one method per filter format (the library's texture and
/// shading, bilinear lookups) and EVSM again with light-bleed reduction 0.15; the
/// moments128 and nlq64 textures with their nearest-texel shadows (the paper's setting).
struct DeviceMaps {
    std::vector<MethodResult> methods; ///< every filter format in Format order, then EVSM with R = 0.15
    msmcl::Texture moments128, nlq64;
    std::vector<double> nearest_moments128, nearest_nlq64;
};

/// The filter of `format`, and the median of its kernel stage over timed_filter_runs more runs.
msmcl::Texture timed_filter(msmcl::Context& context, const msmcl::DepthImage& depth, msmcl::Format format,
                            msmcl::FilterKernel kernel, double& kernel_ms) {
    msmcl::FilterOptions options;
    options.format = format;
    options.sigma = static_cast<float>(blur_sigma);
    options.kernel = kernel;
    msmcl::Texture map = msmcl::filter(context, depth, options);
    std::vector<double> times;
    options.on_stage = [&](const msmcl::StageTime& stage) {
        if (std::string(stage.stage) == "kernel") times.push_back(stage.milliseconds);
    };
    for (int run = 0; run < timed_filter_runs; ++run) msmcl::filter(context, depth, options);
    std::sort(times.begin(), times.end());
    kernel_ms = times.empty() ? 0.0 : times[times.size() / 2];
    return map;
}

DeviceMaps filter_and_shade(msmcl::Context& context, const msmcl::DepthImage& depth,
                            const msmcl::Receivers& receivers, msmcl::FilterKernel kernel) {
    DeviceMaps device;
    std::vector<MethodResult> reduced;
    for (msmcl::Format format : msmcl::detail::filter_formats()) {
        MethodResult method;
        method.name = msmcl::format_name(format);
        method.format = format;
        msmcl::Texture map = timed_filter(context, depth, format, kernel, method.kernel_ms);
        method.shadow = device_shadow(context, map, receivers, msmcl::Lookup::bilinear);
        // EVSM as Filament shades it: the bound rescaled from [0.15, 1].
        const msmcl::detail::Representation representation = msmcl::detail::representation_of(format);
        if (representation == msmcl::detail::Representation::evsm2 ||
            representation == msmcl::detail::Representation::evsm4) {
            MethodResult lbr = method;
            lbr.name += "_lbr0.15";
            lbr.light_bleed_reduction = filament_light_bleed_reduction;
            lbr.shadow =
                device_shadow(context, map, receivers, msmcl::Lookup::bilinear, filament_light_bleed_reduction);
            reduced.push_back(std::move(lbr));
        }
        device.methods.push_back(std::move(method));
        if (format == msmcl::Format::moments128) {
            device.nearest_moments128 = device_shadow(context, map, receivers, msmcl::Lookup::nearest);
            device.moments128 = map;
        }
        if (format == msmcl::Format::nlq64) {
            device.nearest_nlq64 = device_shadow(context, map, receivers, msmcl::Lookup::nearest);
            device.nlq64 = std::move(map);
        }
    }
    for (MethodResult& method : reduced) device.methods.push_back(std::move(method));
    return device;
}

/// The device's float32 filtered moments (its moments128 texels) in double.
std::vector<ref::Moments> texel_moments(const msmcl::Texture& moments128) {
    std::vector<ref::Moments> moments(moments128.words.size() / 4);
    for (std::size_t t = 0; t < moments.size(); ++t) {
        const int x = static_cast<int>(t % moments128.width), y = static_cast<int>(t / moments128.width);
        moments[t] = {moments128.moment(x, y, 1), moments128.moment(x, y, 2), moments128.moment(x, y, 3),
                      moments128.moment(x, y, 4)};
    }
    return moments;
}

/// Each method's errors against 128-bit moments (methods[0]) and the ground truth, and its
/// leak on the banner.
void score_methods(std::vector<MethodResult>& methods, const GroundTruth& g, const std::vector<std::size_t>& leak_set,
                   bool has_materials) {
    const std::vector<double>& moments128 = methods[0].shadow;
    for (MethodResult& method : methods) {
        method.vs_moments128 = compare(method.shadow, moments128);
        method.vs_truth = compare(method.shadow, g.truth);
        method.vs_truth_constant_bias = compare(method.shadow, g.truth_constant_bias);
        method.leak = banner_leak(method.shadow, g.truth, leak_set, has_materials);
    }
}

/// Double-precision shadows of the same filtered moments, per receiver: the double
/// moments (reference) and the device's float32 texels (float_*), each as 128-bit moments
/// and in the nlq representations; bilinear unless *_nearest.
struct DoubleShadows {
    std::vector<double> moments128, moments128_nearest;
    std::vector<double> exact_nlq, nlq64, nlq64_nearest, psi_only, depths_weight_only, device_codes;
    std::vector<double> float128, float128_nearest, float_nlq64, float_nlq64_nearest;
};

DoubleShadows shade_in_double(const DoubleShading& reference, const DoubleShading& from_float_moments,
                              const msmcl::Receivers& receivers) {
    using Texels = DoubleShading::Texels;
    auto double_shadow = [&](const std::function<double(double, double, double)>& shade) {
        std::vector<double> shadow(receivers.size());
        parallel_for(receivers.size(), [&](std::size_t i) {
            shadow[i] = shade(receivers.u[i], receivers.v[i], 2.0 * receivers.z[i] - 1.0 - depth_bias);
        });
        return shadow;
    };
    auto nlq_shadow = [&](Texels kind, bool bilinear) {
        return double_shadow([&](double u, double v, double zf) { return reference.nlq(kind, u, v, zf, bilinear); });
    };
    auto float_moments_shadow = [&](bool bilinear, bool as_nlq64) {
        return double_shadow([&](double u, double v, double zf) {
            return as_nlq64 ? from_float_moments.nlq(Texels::nlq64, u, v, zf, bilinear)
                            : from_float_moments.moments128(u, v, zf, bilinear);
        });
    };
    DoubleShadows d;
    d.moments128 = double_shadow([&](double u, double v, double zf) { return reference.moments128(u, v, zf, true); });
    d.moments128_nearest =
        double_shadow([&](double u, double v, double zf) { return reference.moments128(u, v, zf, false); });
    d.exact_nlq = nlq_shadow(Texels::exact_nlq, true);
    d.nlq64 = nlq_shadow(Texels::nlq64, true);
    d.psi_only = nlq_shadow(Texels::nlq64_psi_only, true);
    d.depths_weight_only = nlq_shadow(Texels::nlq64_depths_weight_only, true);
    d.device_codes = nlq_shadow(Texels::device_nlq64, true);
    d.nlq64_nearest = nlq_shadow(Texels::nlq64, false);
    d.float128 = float_moments_shadow(true, false);
    d.float128_nearest = float_moments_shadow(false, false);
    d.float_nlq64 = float_moments_shadow(true, true);
    d.float_nlq64_nearest = float_moments_shadow(false, true);
    return d;
}

/// The decomposition of nlq64 - moments128: one step per source of difference.
std::vector<Step> decomposition(const DeviceMaps& device, const DoubleShadows& d) {
    const std::vector<double>& moments128 = device.methods[0].shadow;
    const std::vector<double>& nlq64 = device.methods[2].shadow;
    return {
        {"nlq64 vs moments128 (device, bilinear)", "the table's figure", compare(nlq64, moments128)},
        {"nlq64 (device) vs 128-bit (double)", "against 128-bit moments without float32 rounding",
         compare(nlq64, d.moments128)},
        {"moments128: device texels in double vs double", "float32 filter and storage of the moments",
         compare(d.float128, d.moments128)},
        {"moments128: device vs its texels in double", "float32 shading", compare(moments128, d.float128)},
        {"exact nlq vs 128-bit (double)", "lookup: shade 4 texels, blend intensities instead of blending moments",
         compare(d.exact_nlq, d.moments128)},
        {"nlq64 vs exact nlq (double)", "16-bit format: y1, y2, v2 rounded, Psi4 rounded up",
         compare(d.nlq64, d.exact_nlq)},
        {"  Psi4 only vs exact nlq", "  only Psi4(xi4) quantized", compare(d.psi_only, d.exact_nlq)},
        {"  y1, y2, v2 only vs exact nlq", "  only y1, y2, v2 quantized", compare(d.depths_weight_only, d.exact_nlq)},
        {"nlq64 vs 128-bit (double)", "lookup and format together", compare(d.nlq64, d.moments128)},
        {"nlq64 of the float32 moments vs of the double moments", "float32 moments128 texels into double Algorithm 2",
         compare(d.float_nlq64, d.nlq64)},
        {"device codes vs double codes", "float32 filter and Algorithm 2 (codes shaded in double)",
         compare(d.device_codes, d.nlq64)},
        {"device nlq64 vs device codes in double", "float32 Algorithm 3", compare(nlq64, d.device_codes)},
        {"nearest: nlq64 vs moments128 (device)", "the paper's setting (nearest texel on both)",
         compare(device.nearest_nlq64, device.nearest_moments128)},
        {"nearest: nlq64 (device) vs 128-bit (double)", "against 128-bit moments without float32 rounding",
         compare(device.nearest_nlq64, d.moments128_nearest)},
        {"nearest: nlq64 vs 128-bit (double)", "format alone", compare(d.nlq64_nearest, d.moments128_nearest)},
        {"nearest: moments128 device texels in double vs double", "float32 filter and storage of the moments",
         compare(d.float128_nearest, d.moments128_nearest)},
        {"nearest: moments128 device vs double", "float32 filter, storage and shading",
         compare(device.nearest_moments128, d.moments128_nearest)},
        {"nearest: nlq64 of the float32 moments vs of the double moments", "float32 moments128 texels into double Algorithm 2",
         compare(d.float_nlq64_nearest, d.nlq64_nearest)},
        {"nearest: device nlq64 vs double nlq64", "float32 filter, Algorithm 2 and 3",
         compare(device.nearest_nlq64, d.nlq64_nearest)},
    };
}

/// Where the receivers with nlq64 off by > 3% are: classes by the depth range of their
/// footprint (spread_bounds).
std::array<FootprintClass, 3> footprint_classes(const std::vector<double>& spread, const DeviceMaps& device,
                                                const DoubleShadows& d) {
    const std::vector<double>& moments128 = device.methods[0].shadow;
    const std::vector<double>& nlq64 = device.methods[2].shadow;
    std::array<FootprintClass, 3> classes{};
    for (std::size_t i = 0; i < spread.size(); ++i) {
        const int k = spread[i] < spread_bounds[0] ? 0 : spread[i] < spread_bounds[1] ? 1 : 2;
        ++classes[k].receivers;
        const double error = std::abs(nlq64[i] - moments128[i]);
        if (error > error_threshold) {
            ++classes[k].nlq64_above;
            if (std::abs(d.exact_nlq[i] - d.moments128[i]) > error_threshold) ++classes[k].lookup_above;
        }
        if (error > large_error_threshold) ++classes[k].nlq64_above_large;
        if (std::abs(device.nearest_nlq64[i] - device.nearest_moments128[i]) > error_threshold)
            ++classes[k].nearest_above;
        if (std::abs(device.nearest_nlq64[i] - d.nlq64_nearest[i]) > error_threshold)
            ++classes[k].nearest_encoder_above;
    }
    return classes;
}

} // namespace

SceneResult measure_scene(msmcl::Context& context, const Scene& scene, const SceneInputs& inputs,
                          msmcl::FilterKernel kernel) {
    const msmcl::DepthImage& depth = inputs.depth;
    const msmcl::io::ReceiverGrid& grid = inputs.grid;
    const msmcl::Receivers& receivers = grid.points;
    const bool has_materials = !inputs.materials.empty();

    // Ground truth per receiver; how far the samples each lookup filters stray from the receiver's plane.
    const PercentageCloser pcf(depth, blur_sigma);
    const GroundTruth g = ground_truth(pcf, grid);
    const std::vector<std::size_t> leak_set = banner_leak_set(inputs.materials, g.truth);

    // Moment shadow maps: filter + shade for every format.
    DeviceMaps device = filter_and_shade(context, depth, receivers, kernel);

    // The double reference moments of the same resolve and blur, and the device's float32 ones.
    const ref::DepthMap reference_depth{depth.width, depth.height, depth.samples, depth.depth, true};
    const DoubleShading reference(ref::filter_moments(reference_depth, blur_sigma), depth.width, depth.height,
                                  &device.nlq64);
    const DoubleShading from_float_moments(texel_moments(device.moments128), depth.width, depth.height, nullptr);

    // Every method against 128-bit moments and the ground truth.
    score_methods(device.methods, g, leak_set, has_materials);

    // Double-precision shading of the same filtered moments: the decomposition, and where
    // the receivers with large differences lie.
    const DoubleShadows doubles = shade_in_double(reference, from_float_moments, receivers);

    SceneResult result;
    result.scene = scene;
    result.width = depth.width, result.height = depth.height, result.samples = depth.samples;
    result.view_width = grid.width, result.view_height = grid.height;
    result.count = receivers.size();
    result.has_materials = has_materials;
    result.leak_set_size = leak_set.size();
    result.truth = g.truth;
    result.truth_constant_bias = g.truth_constant_bias;
    result.steps = decomposition(device, doubles);
    result.classes = footprint_classes(g.spread, device, doubles);
    result.methods = std::move(device.methods);
    // Codes the float32 encoder writes against the double encoding of the double moments.
    count_codes_off(device.nlq64, reference.moments(), result);
    // Self-shadowing check of moments128 against the truth.
    check_self_shadowing(pcf, receivers, g, result.methods[0].shadow, result);
    return result;
}

} // namespace quality
