// msmcl-quality: the quality table of issue 7. For each sample scene, shades the view's
// receivers with every msmcl format (filter + shade, bilinear lookup) and with variance
// shadow maps (32 and 64 bit) of the same resolve and blur, and compares the shadow
// intensities against 128-bit moments and against the percentage-closer ground truth of
// the same 9x9 Gaussian. Writes a Markdown table (stdout), optional JSON, and PNGs.
#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/formats.hpp>
#include <msmcl/shade.hpp>

#include "io/exr_io.hpp"
#include "io/png_io.hpp"
#include "data/tools/msaa_pattern.hpp"
#include "reference/filter_reference.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace {

constexpr double blur_sigma = 2.4;          // the library's default blur
constexpr double depth_bias = 1e-3;         // internal depth, shade's default
constexpr double error_threshold = 0.03;    // "off by more than 3%"
constexpr double large_error_threshold = 0.10;
constexpr double vsm_min_variance = 1e-5;   // in [0,1] depth units
constexpr double leak_truth_min = 0.99;     // ground truth "fully shadowed"
constexpr double leak_gap_max = 0.05;       // receiver-to-occluder gap, internal depth
constexpr double leak_lit_below = 0.9;      // a leaking receiver is shaded under this

struct Scene {
    std::string name;
    std::string depth_path;
    std::string receivers_path;
};

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

/// Ground truth at one receiver: the PCF share and the mean depth of the occluding samples.
struct TruthAtReceiver {
    double shadow = 0;
    double occluder_depth = 0; ///< weighted mean internal depth of occluding samples (0 if none)
    bool has_occluder = false;
};

/// Percentage-closer filtering with the 9x9 Gaussian of the filter, in double: per texel
/// the weighted share of samples with internal depth < receiver depth - bias, bilinear
/// between texel centres like the lookup. Clamp-to-edge like the filter.
class PercentageCloser {
public:
    PercentageCloser(const msmcl::DepthImage& depth, double sigma)
        : depth_(depth), weights_(msmcl::reference::gaussian_weights(sigma)),
          sample_offsets_(msmcl::data::standard_sample_pattern(depth.samples)) {}

    /// `gradient_x/y`: the receiver plane's internal depth per texel (0, 0 = constant depth).
    TruthAtReceiver at(double u, double v, double receiver_z, double gradient_x = 0, double gradient_y = 0) const {
        const BilinearTaps taps = bilinear_taps(u, v, depth_.width, depth_.height);
        const int base_x = static_cast<int>(std::floor(u - 0.5)), base_y = static_cast<int>(std::floor(v - 0.5));
        const std::array<std::array<int, 2>, 4> positions = {{{base_x, base_y}, {base_x + 1, base_y},
                                                              {base_x, base_y + 1}, {base_x + 1, base_y + 1}}};
        const std::array<std::array<int, 2>, 4> texels = {{{taps.x0, taps.y0}, {taps.x1, taps.y0},
                                                           {taps.x0, taps.y1}, {taps.x1, taps.y1}}};
        const std::array<double, 4> blend = {(1 - taps.fx) * (1 - taps.fy), taps.fx * (1 - taps.fy),
                                             (1 - taps.fx) * taps.fy, taps.fx * taps.fy};
        TruthAtReceiver truth;
        double occluder_weight = 0, occluder_depth_sum = 0;
        for (int t = 0; t < 4; ++t) {
            // Blur footprint of one texel: 9x9 taps, S samples each.
            for (int j = -4; j <= 4; ++j) {
                const int y = std::clamp(texels[t][1] + j, 0, depth_.height - 1);
                for (int i = -4; i <= 4; ++i) {
                    const int x = std::clamp(texels[t][0] + i, 0, depth_.width - 1);
                    const double w = blend[t] * weights_[i + 4] * weights_[j + 4] / depth_.samples;
                    // The receiver plane continued to this tap's texel centre, minus the bias.
                    const double centre_z = receiver_z + gradient_x * (positions[t][0] + i + 0.5 - u) +
                                            gradient_y * (positions[t][1] + j + 0.5 - v);
                    for (int s = 0; s < depth_.samples; ++s) {
                        // ... and to the sample's position (standard D3D pattern of the sample data).
                        const double threshold = centre_z + gradient_x * sample_offsets_[s].x16 / 16.0 +
                                                 gradient_y * sample_offsets_[s].y16 / 16.0 - depth_bias;
                        const double z = 2.0 * depth_.at(x, y, s) - 1.0;
                        if (z < threshold) {
                            truth.shadow += w;
                            occluder_weight += w;
                            occluder_depth_sum += w * z;
                        }
                    }
                }
            }
        }
        if (occluder_weight > 0) {
            truth.has_occluder = true;
            truth.occluder_depth = occluder_depth_sum / occluder_weight;
        }
        return truth;
    }

private:
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

/// A variance shadow map: per texel (mu, E[d^2]) of d in [0,1], as stored.
struct VarianceMap {
    int width = 0, height = 0;
    std::vector<float> mean, mean_square;
};

/// VSM from the double reference moments: b1, b2 of internal z -> d = (z + 1) / 2.
/// 32 bit: two unorm16 codes (round to nearest); 64 bit: two float32.
VarianceMap variance_map(const std::vector<msmcl::reference::Moments>& moments, int width, int height,
                         bool unorm16) {
    VarianceMap map;
    map.width = width;
    map.height = height;
    map.mean.resize(moments.size());
    map.mean_square.resize(moments.size());
    auto store = [unorm16](double value) {
        if (!unorm16) return static_cast<float>(value);
        const double code = std::round(std::clamp(value, 0.0, 1.0) * 65535.0);
        return static_cast<float>(code / 65535.0);
    };
    for (std::size_t i = 0; i < moments.size(); ++i) {
        const auto& m = moments[i];
        map.mean[i] = store((m.b1 + 1.0) / 2.0);
        map.mean_square[i] = store((m.b2 + 2.0 * m.b1 + 1.0) / 4.0);
    }
    return map;
}

/// VSM lookup as a shader does it, in float32: bilinear filtering of the stored moments,
/// then Chebyshev's one-sided inequality: shadow >= 1 - var / (var + (zf - mu)^2), zf > mu.
float shade_variance(const VarianceMap& map, float u, float v, float receiver_d) {
    const BilinearTaps taps = bilinear_taps(u, v, map.width, map.height);
    const float fx = static_cast<float>(taps.fx), fy = static_cast<float>(taps.fy);
    auto fetch = [&](const std::vector<float>& channel) {
        auto at = [&](int x, int y) { return channel[static_cast<std::size_t>(y) * map.width + x]; };
        const float top = at(taps.x0, taps.y0) * (1 - fx) + at(taps.x1, taps.y0) * fx;
        const float bottom = at(taps.x0, taps.y1) * (1 - fx) + at(taps.x1, taps.y1) * fx;
        return top * (1 - fy) + bottom * fy;
    };
    const float mu = fetch(map.mean);
    const float mean_square = fetch(map.mean_square);
    // The bias of 1e-3 in internal depth is 5e-4 in [0,1] depth.
    const float zf = receiver_d - static_cast<float>(depth_bias / 2.0);
    if (zf <= mu) return 0.0f;
    const float variance = std::max(mean_square - mu * mu, static_cast<float>(vsm_min_variance));
    const float distance = zf - mu;
    return 1.0f - variance / (variance + distance * distance);
}

struct ErrorStats {
    double share_above = 0;       ///< share of receivers with |error| > 0.03
    std::size_t count_above = 0;
    std::size_t count_above_large = 0; ///< |error| > 0.10
    double max = 0;
    double mean = 0;
};

ErrorStats compare(const std::vector<float>& shadow, const std::vector<double>& truth) {
    ErrorStats stats;
    double sum = 0;
    for (std::size_t i = 0; i < shadow.size(); ++i) {
        const double error = std::abs(static_cast<double>(shadow[i]) - truth[i]);
        sum += error;
        stats.max = std::max(stats.max, error);
        if (error > error_threshold) ++stats.count_above;
        if (error > large_error_threshold) ++stats.count_above_large;
    }
    stats.mean = shadow.empty() ? 0 : sum / shadow.size();
    stats.share_above = shadow.empty() ? 0 : static_cast<double>(stats.count_above) / shadow.size();
    return stats;
}

struct LeakStats {
    std::size_t receivers = 0;  ///< receivers in the leak set
    double mean_shadow = 0;
    double share_below = 0;     ///< share shaded under 0.9
};

LeakStats light_leak(const std::vector<float>& shadow, const std::vector<std::size_t>& leak_set) {
    LeakStats stats;
    stats.receivers = leak_set.size();
    if (leak_set.empty()) return stats;
    std::size_t below = 0;
    double sum = 0;
    for (std::size_t i : leak_set) {
        sum += shadow[i];
        if (shadow[i] < leak_lit_below) ++below;
    }
    stats.mean_shadow = sum / leak_set.size();
    stats.share_below = static_cast<double>(below) / leak_set.size();
    return stats;
}

/// Signed error as RGB: red where the method is too light (leaks), blue where too dark;
/// full intensity at an error of 0.1.
std::vector<float> error_image(const std::vector<float>& shadow, const std::vector<double>& truth) {
    std::vector<float> rgb(shadow.size() * 3, 0.0f);
    for (std::size_t i = 0; i < shadow.size(); ++i) {
        const double error = shadow[i] - truth[i];
        rgb[3 * i + 0] = static_cast<float>(std::max(-error, 0.0) / large_error_threshold);
        rgb[3 * i + 2] = static_cast<float>(std::max(error, 0.0) / large_error_threshold);
    }
    return rgb;
}

std::string percent(double share) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f%%", 100.0 * share);
    return text;
}

std::string fixed(double value, int digits = 4) {
    char text[32];
    std::snprintf(text, sizeof text, "%.*f", digits, value);
    return text;
}

struct MethodResult {
    std::string name;
    std::vector<float> shadow;
    ErrorStats vs_moments128;
    ErrorStats vs_truth;
    ErrorStats vs_truth_constant_bias;
    LeakStats leak;
};

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"msmcl-quality: shadow quality of every format and of VSM against 128-bit moments "
                 "and the percentage-closer ground truth"};
    std::vector<std::string> scene_specs;
    std::string data_dir = MSMCL_QUALITY_DATA_DIR;
    std::string out_dir;
    std::string json_path;
    std::string device;
    app.add_option("--scene", scene_specs,
                   "NAME:DEPTH.exr:RECEIVERS.exr (repeatable; default: railing and wuson sample scenes)");
    app.add_option("--data", data_dir, "directory of the default sample scenes")->capture_default_str();
    app.add_option("--out", out_dir, "directory for PNG images (shadow and error per scene and method)");
    app.add_option("--json", json_path, "write the results as JSON");
    app.add_option("--device", device, "OpenCL device spec (gpu, cpu, index, P:D or name substring)");
    CLI11_PARSE(app, argc, argv);

    // The scenes: the committed sample data unless given.
    std::vector<Scene> scenes;
    if (scene_specs.empty()) {
        scenes.push_back({"railing", data_dir + "/railing_256x256_4x.exr", data_dir + "/railing_view_160x120.exr"});
        scenes.push_back({"wuson", data_dir + "/wuson_256x256_4x.exr", data_dir + "/wuson_view_160x120.exr"});
    }
    for (const std::string& spec : scene_specs) {
        const auto first = spec.find(':');
        const auto second = first == std::string::npos ? first : spec.find(':', first + 1);
        if (second == std::string::npos) {
            std::cerr << "msmcl-quality: --scene wants NAME:DEPTH:RECEIVERS, got '" << spec << "'\n";
            return 2;
        }
        scenes.push_back({spec.substr(0, first), spec.substr(first + 1, second - first - 1), spec.substr(second + 1)});
    }
    if (!out_dir.empty()) std::filesystem::create_directories(out_dir);

    try {
        msmcl::DeviceSelection selection;
        selection.device = device;
        selection.strict = !device.empty();
        msmcl::Context context(selection);

        nlohmann::json json_scenes = nlohmann::json::array();
        std::cout << "# msmcl quality table\n\n"
                  << "device: " << context.device().name << "; blur sigma " << blur_sigma
                  << ", depth bias " << depth_bias << " (internal depth), bilinear lookup; VSM minimum variance "
                  << vsm_min_variance << " ([0,1] depth)\n\n"
                  << "Errors are |shadow - reference| over all receivers of the view. Leak set: receivers whose "
                     "ground truth is >= "
                  << leak_truth_min << " and whose depth minus the weighted mean depth of their occluding samples is < "
                  << leak_gap_max << " (internal depth); leak = mean shadow there and share shaded < " << leak_lit_below
                  << ".\n\n";

        for (const Scene& scene : scenes) {
            // Inputs: the depth map ([0,1] convention) and the view's receivers.
            const msmcl::DepthImage depth = msmcl::io::read_depth_exr(scene.depth_path, msmcl::DepthRange::zero_one);
            const msmcl::io::ReceiverGrid grid = msmcl::io::read_receivers_exr(scene.receivers_path);
            const msmcl::Receivers& receivers = grid.points;
            const std::size_t count = receivers.size();

            // Ground truth per receiver, and the leak set.
            const PercentageCloser pcf(depth, blur_sigma);
            std::vector<double> truth(count), truth_constant_bias(count);
            std::vector<std::size_t> leak_set;
            for (std::size_t i = 0; i < count; ++i) {
                const double receiver_z = 2.0 * receivers.z[i] - 1.0;
                const auto gradient = receiver_plane_gradient(grid, static_cast<int>(i % grid.width),
                                                              static_cast<int>(i / grid.width));
                const TruthAtReceiver t = pcf.at(receivers.u[i], receivers.v[i], receiver_z, gradient[0], gradient[1]);
                truth[i] = t.shadow;
                truth_constant_bias[i] = pcf.at(receivers.u[i], receivers.v[i], receiver_z).shadow;
                if (t.shadow >= leak_truth_min && t.has_occluder && receiver_z - t.occluder_depth < leak_gap_max)
                    leak_set.push_back(i);
            }

            // Moment shadow maps: filter + shade for every format.
            std::vector<MethodResult> methods;
            for (msmcl::Format format : {msmcl::Format::moments128, msmcl::Format::msm64, msmcl::Format::nlq64,
                                         msmcl::Format::nlq32}) {
                msmcl::FilterOptions filter_options;
                filter_options.format = format;
                filter_options.sigma = static_cast<float>(blur_sigma);
                const msmcl::Texture map = msmcl::filter(context, depth, filter_options);
                msmcl::ShadeOptions shade_options;
                shade_options.lookup = msmcl::Lookup::bilinear;
                shade_options.depth_bias = static_cast<float>(depth_bias);
                methods.push_back({msmcl::format_name(format), msmcl::shade(context, map, receivers, shade_options), {}, {}, {}, {}});
            }

            // Variance shadow maps of the same resolve and blur (double reference moments).
            msmcl::reference::DepthMap reference_depth{depth.width, depth.height, depth.samples, depth.depth, true};
            const auto moments = msmcl::reference::filter_moments(reference_depth, blur_sigma);
            for (bool unorm16 : {true, false}) {
                const VarianceMap map = variance_map(moments, depth.width, depth.height, unorm16);
                std::vector<float> shadow(count);
                for (std::size_t i = 0; i < count; ++i)
                    shadow[i] = shade_variance(map, receivers.u[i], receivers.v[i], receivers.z[i]);
                methods.push_back({unorm16 ? "vsm32" : "vsm64", std::move(shadow), {}, {}, {}, {}});
            }

            // Errors against 128-bit moments and the ground truth; the leak figure.
            const std::vector<double> moments128(methods[0].shadow.begin(), methods[0].shadow.end());
            for (MethodResult& method : methods) {
                method.vs_moments128 = compare(method.shadow, moments128);
                method.vs_truth = compare(method.shadow, truth);
                method.vs_truth_constant_bias = compare(method.shadow, truth_constant_bias);
                method.leak = light_leak(method.shadow, leak_set);
            }

            // The table.
            std::cout << "## " << scene.name << " (" << depth.width << "x" << depth.height << ", " << depth.samples
                      << "x MSAA; " << grid.width << "x" << grid.height << " = " << count << " receivers; leak set "
                      << leak_set.size() << ")\n\n"
                      << "| method | vs 128-bit: >3% | >10% | max | mean | vs PCF truth: >3% | >10% | max | mean | "
                         "leak: mean shadow | leak: share < 0.9 | vs constant-bias PCF: >3% | mean |\n"
                      << "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
            for (const MethodResult& m : methods) {
                std::cout << "| " << m.name << " | " << percent(m.vs_moments128.share_above) << " ("
                          << m.vs_moments128.count_above << ") | " << m.vs_moments128.count_above_large << " | "
                          << fixed(m.vs_moments128.max) << " | " << fixed(m.vs_moments128.mean, 5) << " | "
                          << percent(m.vs_truth.share_above) << " (" << m.vs_truth.count_above << ") | "
                          << m.vs_truth.count_above_large << " | " << fixed(m.vs_truth.max) << " | "
                          << fixed(m.vs_truth.mean, 5) << " | " << fixed(m.leak.mean_shadow) << " | "
                          << percent(m.leak.share_below) << " | " << percent(m.vs_truth_constant_bias.share_above)
                          << " | " << fixed(m.vs_truth_constant_bias.mean, 5) << " |\n";
            }
            std::cout << "\n";

            // Images: ground truth, and shadow and error per method.
            if (!out_dir.empty()) {
                const std::string prefix = out_dir + "/" + scene.name + "_";
                const std::vector<float> truth_image(truth.begin(), truth.end());
                msmcl::io::write_png_preview(prefix + "pcf_truth.png", grid.width, grid.height, 1, truth_image);
                const std::vector<float> constant_image(truth_constant_bias.begin(), truth_constant_bias.end());
                msmcl::io::write_png_preview(prefix + "pcf_constant_bias.png", grid.width, grid.height, 1, constant_image);
                for (const MethodResult& m : methods) {
                    msmcl::io::write_png_preview(prefix + m.name + "_shadow.png", grid.width, grid.height, 1, m.shadow);
                    msmcl::io::write_png_preview(prefix + m.name + "_error.png", grid.width, grid.height, 3,
                                                 error_image(m.shadow, truth));
                }
            }

            // JSON.
            auto stats_json = [](const ErrorStats& s) {
                return nlohmann::json{{"share_above_3pct", s.share_above}, {"count_above_3pct", s.count_above},
                                      {"count_above_10pct", s.count_above_large}, {"max", s.max}, {"mean", s.mean}};
            };
            nlohmann::json json_methods = nlohmann::json::array();
            for (const MethodResult& m : methods) {
                json_methods.push_back({{"method", m.name},
                                        {"vs_moments128", stats_json(m.vs_moments128)},
                                        {"vs_pcf_truth", stats_json(m.vs_truth)},
                                        {"vs_pcf_constant_bias", stats_json(m.vs_truth_constant_bias)},
                                        {"leak_mean_shadow", m.leak.mean_shadow},
                                        {"leak_share_below_0_9", m.leak.share_below}});
            }
            json_scenes.push_back({{"scene", scene.name},
                                   {"depth", scene.depth_path},
                                   {"receivers", scene.receivers_path},
                                   {"receiver_count", count},
                                   {"leak_set_count", leak_set.size()},
                                   {"methods", json_methods}});
        }

        if (!json_path.empty()) {
            nlohmann::json root{{"device", context.device().name},
                                {"sigma", blur_sigma},
                                {"depth_bias", depth_bias},
                                {"vsm_min_variance", vsm_min_variance},
                                {"leak_definition",
                                 "ground truth >= 0.99 and receiver depth - weighted mean occluder depth < 0.05 (internal)"},
                                {"scenes", json_scenes}};
            std::ofstream file(json_path);
            file << root.dump(2) << "\n";
            if (!file) {
                std::cerr << "msmcl-quality: cannot write " << json_path << "\n";
                return 1;
            }
        }
    } catch (const std::exception& e) {
        std::cerr << "msmcl-quality: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
