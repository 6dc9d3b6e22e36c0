// msmcl-scatter-quality: prefiltered single scattering against ray marching with many samples
// (docs/methods.md, "Scattering quality"), as figures and images of the lit fraction of each
// view ray (radiance / radiance of the fully lit ray, so 0 = shadowed, 1 = lit).
//
//   msmcl-scatter-quality study SCENE.json [--map-size 1024] [--camera-width 640 --camera-height 480]
//                         [--rectified 1024] [--yaw DEG] [--light-direction X,Y,Z] [--steps 1024] [--json FILE]
//     Takes the banding apart: the default pipeline, then one ingredient at a time swapped for
//     its exact or finer counterpart (rectified resolution, float storage of the prefix sums,
//     the exact share of the resampled distribution instead of the bounds blend, the sigma of
//     the filtered resampling), each against ray marching: mean and 99th percentile of
//     |lit fraction error| and the banding measure (RMS of the error's high-pass component
//     where the truth is flat).
//
//   msmcl-scatter-quality compare SCENE.json SHADOW.exr CAMERA.exr [--steps 1024] [--truth TRUTH.exr]
//                         [--range 0.25] RESULT.exr:DIFF.png ...
//     The main job's images: ray marching of the hard shadow map in double (all cores) as the
//     truth, and for each result of `msmcl scatter` the signed difference of its lit fraction
//     from the truth's (tools/signed_difference.hpp: red lighter, blue darker, full colour at
//     +-range, legend bar below), with one line of figures per result.
#include "tools/scatter_geometry.hpp"
#include "tools/signed_difference.hpp"
#include "io/exr_io.hpp"
#include "io/scene_json.hpp"
#include "ops/scatter_params.hpp"
#include "reference/scatter_reference.hpp"
#include "tests/scatter_setup.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/scatter.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace msmcl;
namespace ref = msmcl::reference;

using msmcl::testing::rectification_of;
using msmcl::testing::setup_of;

ref::DepthMap depth_map_of(const DepthImage& image, const ScatterScene& scene) {
    ref::DepthMap map;
    map.width = image.width;
    map.height = image.height;
    map.samples = image.samples;
    map.depth = image.depth;
    map.zero_one = scene.light.depth_range == DepthRange::zero_one;
    return map;
}

/// A number as %g prints it.
std::string number_text(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", x);
    return text;
}

/// Runs f(row) for every row on all hardware threads.
void parallel_rows(int rows, const std::function<void(int)>& f) {
    const int count = std::max(1, std::min(static_cast<int>(std::thread::hardware_concurrency()), rows));
    std::vector<std::thread> workers;
    for (int w = 0; w < count; ++w)
        workers.emplace_back([&, w] {
            for (int row = w; row < rows; row += count) f(row);
        });
    for (std::thread& worker : workers) worker.join();
}

/// f(pixel, ray, distance, lookup) for every camera pixel, on all cores: the view ray, its
/// length and where it lands in the rectified map, as the device's evaluation finds them.
void for_each_lookup(const msm_scatter_params& p, const std::vector<float>& camera_depth,
                     const std::function<void(std::size_t, const msm_view_ray&, float, const msm_scatter_lookup&)>& f) {
    parallel_rows(p.cam_height, [&](int py) {
        for (int px = 0; px < p.cam_width; ++px) {
            const std::size_t pixel = static_cast<std::size_t>(py) * p.cam_width + px;
            const msm_view_ray ray = msm_scatter_view_ray(p, px, py);
            const float distance = msm_scatter_eye_depth(p, camera_depth[pixel]) * ray.length_scale;
            f(pixel, ray, distance, msm_scatter_lookup_at(p, ray, distance));
        }
    });
}

/// Lit fractions: radiance / the radiance of the fully lit view ray, pixel by pixel.
std::vector<double> lit_fractions(const ref::ScatterSetup& setup, const std::vector<float>& camera_depth,
                                  const std::vector<double>& radiance) {
    std::vector<double> lit(radiance.size());
    for (int py = 0; py < setup.camera_height; ++py)
        for (int px = 0; px < setup.camera_width; ++px) {
            const std::size_t i = static_cast<std::size_t>(py) * setup.camera_width + px;
            const double full = ref::unshadowed_radiance(setup, px, py, camera_depth[i]);
            lit[i] = full > 0 ? radiance[i] / full : 1.0;
        }
    return lit;
}

std::vector<double> to_double(const std::vector<float>& v) { return {v.begin(), v.end()}; }

/// Mean and 99th percentile of |estimate - truth|, and the banding measure: the RMS of the
/// error's high-pass component (error minus its 3x3 box mean) over the image's interior.
struct ErrorFigures {
    double mean = 0, p99 = 0, banding = 0;
};
ErrorFigures error_figures(const std::vector<double>& estimate, const std::vector<double>& truth, int width,
                           int height) {
    std::vector<double> error(estimate.size()), magnitude(estimate.size());
    for (std::size_t i = 0; i < error.size(); ++i) {
        error[i] = estimate[i] - truth[i];
        magnitude[i] = std::fabs(error[i]);
    }
    ErrorFigures f;
    for (double x : magnitude) f.mean += x;
    f.mean /= static_cast<double>(magnitude.size());
    std::sort(magnitude.begin(), magnitude.end());
    f.p99 = magnitude[static_cast<std::size_t>(0.99 * static_cast<double>(magnitude.size() - 1))];
    double energy = 0;
    std::size_t count = 0;
    // Only where the truth is flat (its values within a 7x7 window differ by < 1e-3): there
    // the error's high-pass is banding, not the truth's own edges.
    const auto truth_flat = [&](int x, int y) {
        double lo = 1e30, hi = -1e30;
        for (int dy = -3; dy <= 3; ++dy)
            for (int dx = -3; dx <= 3; ++dx) {
                const int xx = std::clamp(x + dx, 0, width - 1), yy = std::clamp(y + dy, 0, height - 1);
                lo = std::min(lo, truth[static_cast<std::size_t>(yy) * width + xx]);
                hi = std::max(hi, truth[static_cast<std::size_t>(yy) * width + xx]);
            }
        return hi - lo < 1e-3;
    };
    for (int y = 1; y + 1 < height; ++y)
        for (int x = 1; x + 1 < width; ++x) {
            if (!truth_flat(x, y)) continue;
            double box = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) box += error[static_cast<std::size_t>(y + dy) * width + x + dx];
            const double high = error[static_cast<std::size_t>(y) * width + x] - box / 9;
            energy += high * high;
            ++count;
        }
    f.banding = count ? std::sqrt(energy / static_cast<double>(count)) : 0;
    return f;
}

/// The device's per-pixel evaluation (kernels/msm_scatter.clh compiled for the host) on float
/// prefix sums (`moments` per texel): what the kernel computes if the map stored floats.
std::vector<double> evaluate_float_sums(const ScatterScene& scene, const std::vector<float>& sums, int moments,
                                        const std::vector<float>& camera_depth, float beta, bool gdc_blend = false) {
    const msm_scatter_params p =
        detail::make_scatter_params(scene, rectification_bounds(scene), 1, 1, 1, gdc_blend ? -1.0f : beta);
    std::vector<double> radiance(camera_depth.size());
    for_each_lookup(p, camera_depth, [&](std::size_t pixel, const msm_view_ray& ray, float distance,
                                         const msm_scatter_lookup& l) {
        const auto texel = [&](int x, int y, int k) {
            return sums[(static_cast<std::size_t>(y) * p.rect_width + x) * moments + k];
        };
        float b[6] = {0, 0, 0, 0, 0, 0};
        for (int k = 0; k < moments; ++k) {
            const float top = msm_lerp(texel(l.x0, l.y0, k), texel(l.x1, l.y0, k), l.tx);
            const float bottom = msm_lerp(texel(l.x0, l.y1, k), texel(l.x1, l.y1, k), l.tx);
            b[k] = msm_lerp(top, bottom, l.ty);
        }
        // gdc_blend: the adaptive factor itself as the fixed blend of this ray (the GDC Europe
        // 2016 talk's blend, msmcl's default before it scaled the factor by the upper bound).
        const float blend = gdc_blend ? -msm_scatter_beta(p, ray) : msm_scatter_beta(p, ray);
        float shadow;
        if (moments == 6) {
            const msm_moments6 m{b[0], b[1], b[2], b[3], b[4], b[5]};
            shadow = msm_scatter_shadow6(m, l.depth, blend);
        } else {
            const msm_moments m{b[0], b[1], b[2], b[3]};
            shadow = msm_scatter_shadow4(m, l.depth, blend);
        }
        radiance[pixel] = (1.0f - shadow) * msm_scatter_unshadowed(p, ray, distance);
    });
    return radiance;
}

/// No moments at all: the exact transmittance-weighted share of the resampled two-depth
/// distributions (reference resampling of the device's moments128 map) below each pixel's
/// rectified depth, looked up as the device looks up the map (bilinear in r and phi).
std::vector<double> evaluate_exact_share(const ScatterScene& scene, const Texture& moment_map,
                                         const std::vector<float>& camera_depth, bool per_ray_weights) {
    const RectificationBounds bounds = rectification_bounds(scene);
    const msm_scatter_params p = detail::make_scatter_params(scene, bounds, 1, 1, 1, -1.0f);
    const ref::ScatterSetup setup = setup_of(scene);
    const ref::ScatterRectification rect = rectification_of(bounds);
    std::vector<ref::Moments> moments(static_cast<std::size_t>(moment_map.width) * moment_map.height);
    for (int y = 0; y < moment_map.height; ++y)
        for (int x = 0; x < moment_map.width; ++x)
            moments[static_cast<std::size_t>(y) * moment_map.width + x] = {
                moment_map.moment(x, y, 1), moment_map.moment(x, y, 2), moment_map.moment(x, y, 3),
                moment_map.moment(x, y, 4)};
    const int width = scene.rectified_width, height = scene.rectified_height;
    std::vector<ref::RectifiedDepths> texels(static_cast<std::size_t>(width) * height);
    parallel_rows(height, [&](int j) {
        for (int i = 0; i < width; ++i)
            texels[static_cast<std::size_t>(j) * width + i] =
                ref::resample_filtered_depths(setup, rect, moments, moment_map.width, moment_map.height, i, j);
    });
    // Relative prefix weights exp(-s D i) (their common factor cancels).
    std::vector<double> weight(width);
    for (int i = 0; i < width; ++i) weight[i] = std::exp(-scene.medium.extinction * bounds.texel_distance * i);
    const auto shadow_at = [&](int column, int row, double zf, double decay) {
        double below = 0, total = 0, w = 1;
        for (int i = 0; i <= column; ++i) {
            const ref::RectifiedDepths& d = texels[static_cast<std::size_t>(row) * width + i];
            const double wi = per_ray_weights ? w : weight[i];
            below += wi * ((d.d2 < zf ? 1 - d.w3 : 0) + (d.d3 < zf ? d.w3 : 0));
            total += wi;
            w *= decay;
        }
        return below / total;
    };
    std::vector<double> radiance(camera_depth.size());
    for_each_lookup(p, camera_depth, [&](std::size_t pixel, const msm_view_ray& ray, float distance,
                                         const msm_scatter_lookup& l) {
        // Per ray: world distance per texel step dr / sin(theta) of this view ray.
        const double sine = std::max(std::sqrt(double(ray.x) * ray.x + double(ray.y) * ray.y), 1e-6);
        const double decay = std::exp(-scene.medium.extinction * bounds.r_max / width / sine);
        const double top = (1 - l.tx) * shadow_at(l.x0, l.y0, l.depth, decay) + l.tx * shadow_at(l.x1, l.y0, l.depth, decay);
        const double bottom =
            (1 - l.tx) * shadow_at(l.x0, l.y1, l.depth, decay) + l.tx * shadow_at(l.x1, l.y1, l.depth, decay);
        const double shadow = (1 - l.ty) * top + l.ty * bottom;
        radiance[pixel] = (1 - shadow) * msm_scatter_unshadowed(p, ray, distance);
    });
    return radiance;
}

struct StudyOptions {
    std::string scene_path, json_path, dump_dir;
    int map_size = 1024, camera_width = 640, camera_height = 480, rectified = 1024, steps = 1024;
    double yaw = 0;
    std::vector<double> light_direction;
};

int run_study(const StudyOptions& options) {
    ScatterScene scene = load_scatter_scene(options.scene_path);
    const scatter_data::Geometry geometry = scatter_data::load_geometry(options.scene_path);
    scene.camera.width = options.camera_width;
    scene.camera.height = options.camera_height;
    scene.rectified_width = scene.rectified_height = options.rectified;
    if (options.light_direction.size() == 3)
        scene.light.direction = {options.light_direction[0], options.light_direction[1], options.light_direction[2]};
    scene = scatter_data::yawed(scene, options.yaw);
    const DepthImage shadow = scatter_data::render_shadow_map(scene, geometry, options.map_size, options.map_size);
    const std::vector<float> camera = scatter_data::render_camera_depth(scene, geometry);
    const ref::ScatterSetup setup = setup_of(scene);
    const int width = scene.camera.width, height = scene.camera.height;

    // The truth: ray marching the hard shadow map, double precision.
    const std::vector<double> truth =
        lit_fractions(setup, camera, ref::ray_march_image(setup, depth_map_of(shadow, scene), camera, options.steps));
    if (!options.dump_dir.empty())
        std::ofstream(options.dump_dir + "/truth.f64", std::ios::binary)
            .write(reinterpret_cast<const char*>(truth.data()), truth.size() * sizeof(double));
    Context context;
    nlohmann::json rows = nlohmann::json::array();
    std::printf("%s (yaw %g): map %d^2, camera %dx%d, rectified %d^2, truth: %d-sample ray marching\n",
                options.scene_path.c_str(), options.yaw, options.map_size, width, height, options.rectified,
                options.steps);
    std::printf("%-44s %8s %8s %9s\n", "variant", "mean", "p99", "banding");
    const auto report = [&](const std::string& name, int moments, const std::vector<double>& radiance) {
        const std::vector<double> lit = lit_fractions(setup, camera, radiance);
        const ErrorFigures f = error_figures(lit, truth, width, height);
        if (!options.dump_dir.empty()) {
            std::string file = name;
            for (char& c : file) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
            std::ofstream(options.dump_dir + "/" + file + ".f64", std::ios::binary)
                .write(reinterpret_cast<const char*>(lit.data()), lit.size() * sizeof(double));
        }
        std::printf("%-44s %8.4f %8.4f %9.5f\n", name.c_str(), f.mean, f.p99, f.banding);
        std::fflush(stdout);
        rows.push_back({{"variant", name}, {"moments", moments}, {"mean", f.mean}, {"p99", f.p99},
                        {"banding", f.banding}});
    };
    for (int moments : {6, 4}) {
        const std::string m = std::to_string(moments) + " moments";
        ScatterOptions defaults;
        defaults.moments = moments;
        // The default pipeline on the device, and its map decoded and evaluated on the host.
        report(m + ": default", moments, to_double(scatter(context, scene, shadow, camera, defaults)));
        const ScatterMap map = scatter_prefilter(context, scene, shadow, defaults);
        report(m + ": default, host evaluation", moments,
               evaluate_float_sums(scene, decode_scatter_map(map), moments, camera, defaults.beta));
        // Float storage of the prefix sums.
        report(m + ": float storage", moments,
               evaluate_float_sums(scene, scatter_rectified_moments(context, scene, shadow, defaults, true), moments,
                                   camera, defaults.beta));
        // The bounds blend of the GDC Europe 2016 talk (the default before), on the same map.
        report(m + ": blend (1 + cos) / 2, unscaled", moments,
               evaluate_float_sums(scene, decode_scatter_map(map), moments, camera, -1.0f, true));
        // Rectified resolution doubled along r, along phi, both.
        for (const auto& [name, wide, tall] : {std::tuple{"2x r", 2, 1}, {"2x phi", 1, 2}, {"2x both", 2, 2}}) {
            ScatterScene finer = scene;
            finer.rectified_width *= wide;
            finer.rectified_height *= tall;
            report(m + ": rectified " + name, moments, to_double(scatter(context, finer, shadow, camera, defaults)));
        }
        // The filtered resampling's sigma (0: bilinear samples of the unblurred moments),
        // unfiltered resampling, and fixed blends of the bounds.
        std::vector<std::pair<std::string, ScatterOptions>> swaps;
        for (float sigma : {0.0f, 0.5f, 2.0f}) {
            swaps.emplace_back(": sigma " + number_text(sigma), defaults);
            swaps.back().second.filter_sigma = sigma;
        }
        swaps.emplace_back(": unfiltered resampling", defaults);
        swaps.back().second.filtered = false;
        for (float beta : {0.0f, 0.5f, 1.0f}) {
            swaps.emplace_back(": beta " + number_text(beta), defaults);
            swaps.back().second.beta = beta;
        }
        for (const auto& [name, o] : swaps)
            report(m + name, moments, to_double(scatter(context, scene, shadow, camera, o)));
    }
    FilterOptions filter_options;
    filter_options.format = Format::moments128;
    filter_options.sigma = ScatterOptions{}.filter_sigma;
    filter_options.depth_range = scene.light.depth_range;
    const Texture moment_map = filter(context, shadow, filter_options);
    report("exact share of the resampled distribution", 0, evaluate_exact_share(scene, moment_map, camera, false));
    report("exact share, per-ray transmittance weights", 0, evaluate_exact_share(scene, moment_map, camera, true));
    if (!options.json_path.empty()) {
        const nlohmann::json document{{"scene", options.scene_path}, {"yaw", options.yaw},
                                      {"map_size", options.map_size}, {"camera", {width, height}},
                                      {"rectified", options.rectified}, {"steps", options.steps}, {"rows", rows}};
        std::ofstream(options.json_path) << document.dump(2) << '\n';
    }
    return 0;
}

struct CompareOptions {
    std::string scene_path, shadow_path, camera_path, truth_path;
    int steps = 1024;
    double range = 0.25;
    std::vector<std::string> pairs;
};

int run_compare(const CompareOptions& options) {
    const ScatterScene scene = load_scatter_scene(options.scene_path);
    const DepthImage shadow = io::read_depth_exr(options.shadow_path, scene.light.depth_range);
    const io::ExrImage camera_image = io::read_exr(options.camera_path);
    const io::ExrChannel* z = camera_image.find_channel("Z");
    if (!z || z->values.size() != static_cast<std::size_t>(scene.camera.width) * scene.camera.height)
        throw input_error(options.camera_path + ": needs a channel Z of the scene's camera size");
    // Every result and its image name, checked before the work.
    std::vector<std::pair<std::string, std::string>> results;
    for (const std::string& pair : options.pairs) {
        const std::size_t colon = pair.rfind(':');
        if (colon == std::string::npos || colon == 0 || colon + 1 == pair.size())
            throw input_error(pair + ": expected RESULT.exr:DIFF.png");
        results.emplace_back(pair.substr(0, colon), pair.substr(colon + 1));
    }
    const ref::ScatterSetup setup = setup_of(scene);
    const std::vector<float>& camera = z->values;
    const std::vector<double> marched = ref::ray_march_image(setup, depth_map_of(shadow, scene), camera, options.steps);
    if (!options.truth_path.empty()) {
        io::ExrImage truth_image;
        truth_image.width = scene.camera.width;
        truth_image.height = scene.camera.height;
        truth_image.channels = {{"Y", io::SampleType::float32, std::vector<float>(marched.begin(), marched.end()), {}}};
        io::write_exr(options.truth_path, truth_image);
    }
    const std::vector<double> truth = lit_fractions(setup, camera, marched);
    for (const auto& [result_path, png_path] : results) {
        const io::ExrImage image = io::read_exr(result_path);
        const io::ExrChannel* y = image.find_channel("Y");
        if (!y || y->values.size() != truth.size())
            throw input_error(result_path + ": needs a channel Y of the scene's camera size");
        const std::vector<double> lit = lit_fractions(setup, camera, to_double(y->values));
        // The lit fractions' signed difference, drawn, and its figures.
        const std::vector<double> difference = tools::signed_difference(
            std::vector<float>(lit.begin(), lit.end()), std::vector<float>(truth.begin(), truth.end()),
            tools::Quantity::light);
        tools::write_signed_difference_png(png_path, scene.camera.width, scene.camera.height, difference,
                                           options.range);
        const ErrorFigures f = error_figures(lit, truth, scene.camera.width, scene.camera.height);
        std::printf("%s vs %d-sample ray marching, lit fraction: mean %.4f, p99 %.4f, banding %.5f -> %s\n",
                    result_path.c_str(), options.steps, f.mean, f.p99, f.banding, png_path.c_str());
    }
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"msmcl-scatter-quality: prefiltered single scattering against ray marching", "msmcl-scatter-quality"};
    app.require_subcommand(1);
    StudyOptions study;
    CLI::App* study_command = app.add_subcommand("study", "take the error and the banding apart, one ingredient at a time");
    study_command->add_option("scene", study.scene_path, "scene JSON with a \"geometry\" section")->required();
    study_command->add_option("--map-size", study.map_size, "shadow map side")->capture_default_str()->check(CLI::Range(16, 8192));
    study_command->add_option("--camera-width", study.camera_width, "camera width")->capture_default_str()->check(CLI::Range(1, 8192));
    study_command->add_option("--camera-height", study.camera_height, "camera height")->capture_default_str()->check(CLI::Range(1, 8192));
    study_command->add_option("--rectified", study.rectified, "rectified map side")->capture_default_str()->check(CLI::Range(16, 8192));
    study_command->add_option("--steps", study.steps, "ray-marching samples of the truth")->capture_default_str()->check(CLI::Range(1, 1 << 16));
    study_command->add_option("--yaw", study.yaw, "turn the camera about the world y axis (degrees)");
    study_command->add_option("--light-direction", study.light_direction, "override the light direction X,Y,Z")
        ->expected(3)->delimiter(',');
    study_command->add_option("--json", study.json_path, "also write the rows as JSON");
    study_command->add_option("--dump", study.dump_dir, "write every lit-fraction image as raw doubles into this folder");
    CompareOptions compare;
    CLI::App* compare_command =
        app.add_subcommand("compare", "signed-difference images of msmcl scatter results against ray marching");
    compare_command->add_option("scene", compare.scene_path, "scene JSON as rendered (msmcl-scatter-scene --write-scene)")->required();
    compare_command->add_option("shadow_map", compare.shadow_path, "light depth map EXR")->required();
    compare_command->add_option("camera_depth", compare.camera_path, "camera depth buffer EXR")->required();
    compare_command->add_option("results", compare.pairs, "RESULT.exr:DIFF.png, one per result")->required();
    compare_command->add_option("--steps", compare.steps, "ray-marching samples of the truth")->capture_default_str()->check(CLI::Range(1, 1 << 16));
    compare_command->add_option("--truth", compare.truth_path, "also write the truth's radiance (EXR Y)");
    compare_command->add_option("--range", compare.range, "|lit fraction difference| drawn in full colour")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    CLI11_PARSE(app, argc, argv);
    try {
        if (compare_command->parsed()) return run_compare(compare);
        return run_study(study);
    } catch (const std::exception& e) {
        std::cerr << "msmcl-scatter-quality: " << e.what() << std::endl;
        return dynamic_cast<const input_error*>(&e) ? 2 : 1;
    }
}
