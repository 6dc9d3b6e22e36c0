// msmcl-scatter-scene: renders the depth buffers of a box scene for `msmcl scatter` (the
// light's shadow map and the camera's depth buffer, data/scatter/scatter_geometry.hpp), and
// measures the quality figures of prefiltered single scattering on it (--figures), over
// `frames` views of the camera turned by `yaw_step` degrees each about the vertical axis:
//   - error of 4 and 6 moments (filtered and unfiltered resampling) against ray marching
//     with 128 samples (and with 1024): mean, 99th percentile and largest |difference| over
//     all pixels, also as shares of the mean radiance of fully lit view rays;
//   - frame-to-frame change of each result, mean |R_{k+1} - R_k|, and its flicker: the part
//     that ray marching with 1024 samples does not show, mean |dR - dF|.
#include "scatter_geometry.hpp"

#include "io/exr_io.hpp"
#include "io/scene_json.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/scatter.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

namespace {

using namespace msmcl;

struct Options {
    std::string scene_path;
    std::string shadow_map_path, camera_depth_path, scene_out_path;
    int map_size = 0, samples = 1, camera_width = 0, camera_height = 0, rectified_size = 0;
    double yaw = 0;
    bool figures = false;
    int frames = 6;
    double yaw_step = 0.2;
    int ray_steps = 128;
    float filter_sigma = 1.0f;
    float beta = -1.0f;
    std::string json_path;
};

std::string read_text(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw input_error(path + ": cannot open");
    std::ostringstream text;
    text << file.rdbuf();
    return text.str();
}

void write_camera_depth(const std::string& path, const ScatterScene& scene, const std::vector<float>& depth) {
    io::ExrImage image;
    image.width = scene.camera.width;
    image.height = scene.camera.height;
    image.channels = {{"Z", io::SampleType::float32, depth, {}}};
    io::write_exr(path, image);
}

/// Mean and 99th percentile of |a - b|.
struct ErrorFigures {
    double mean = 0, p99 = 0, max = 0;
};
ErrorFigures error_figures(const std::vector<float>& a, const std::vector<float>& b) {
    std::vector<double> e(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) e[i] = std::fabs(static_cast<double>(a[i]) - b[i]);
    ErrorFigures f;
    for (double x : e) f.mean += x;
    f.mean /= e.size();
    std::sort(e.begin(), e.end());
    f.p99 = e[static_cast<std::size_t>(0.99 * (e.size() - 1))];
    f.max = e.back();
    return f;
}

double mean_of(const std::vector<float>& v) {
    double s = 0;
    for (float x : v) s += x;
    return s / v.size();
}

struct Variant {
    const char* name;
    int moments;
    bool filtered;
};
const Variant variants[] = {{"4_filtered", 4, true}, {"4_unfiltered", 4, false}, {"6_filtered", 6, true},
                            {"6_unfiltered", 6, false}};

nlohmann::json run_figures(const Options& options, const ScatterScene& scene, const scatter_data::Geometry& geometry,
                           int map_size) {
    Context context;
    nlohmann::json result;
    result["scene"] = options.scene_path;
    result["device"] = context.device().name;
    result["shadow_map"] = map_size;
    result["camera"] = {scene.camera.width, scene.camera.height};
    result["rectified"] = {scene.rectified_width, scene.rectified_height};
    result["ray_march_steps"] = options.ray_steps;
    result["filter_sigma"] = options.filter_sigma;
    result["beta"] = options.beta < 0 ? nlohmann::json("adaptive") : nlohmann::json(options.beta);
    const DepthImage shadow = scatter_data::render_shadow_map(scene, geometry, map_size, map_size, options.samples);
    // A map with nothing in it: ray marching it gives the radiance of fully lit view rays.
    DepthImage empty = shadow;
    std::fill(empty.depth.begin(), empty.depth.end(), 1.0f);

    // Frames: the camera turned by k * yaw_step degrees. References: ray marching with
    // ray_steps samples (the accuracy target) and with 8x as many (to tell its own flicker).
    const int fine_steps = 8 * options.ray_steps;
    std::vector<std::vector<float>> reference(options.frames), fine(options.frames);
    std::vector<std::vector<std::vector<float>>> estimates(std::size(variants),
                                                           std::vector<std::vector<float>>(options.frames));
    double lit_sum = 0;
    std::size_t lit_count = 0;
    for (int k = 0; k < options.frames; ++k) {
        const ScatterScene frame = scatter_data::yawed(scene, k * options.yaw_step);
        const std::vector<float> depth = scatter_data::render_camera_depth(frame, geometry);
        reference[k] = scatter_ray_march(context, frame, shadow, depth, options.ray_steps);
        fine[k] = scatter_ray_march(context, frame, shadow, depth, fine_steps);
        for (float x : scatter_ray_march(context, frame, empty, depth, 1)) lit_sum += x, ++lit_count;
        for (std::size_t v = 0; v < std::size(variants); ++v) {
            ScatterOptions so;
            so.moments = variants[v].moments;
            so.filtered = variants[v].filtered;
            so.filter_sigma = options.filter_sigma;
            so.beta = options.beta;
            estimates[v][k] = scatter(context, frame, shadow, depth, so);
        }
    }
    const double lit = lit_sum / lit_count;
    result["unshadowed_mean_radiance"] = lit;
    result["ray_march_mean_radiance"] = mean_of(reference[0]);

    // Errors over all frames' pixels, absolute and as shares of the unshadowed radiance.
    const auto flatten = [&](const std::vector<std::vector<float>>& frames) {
        std::vector<float> all;
        for (const std::vector<float>& f : frames) all.insert(all.end(), f.begin(), f.end());
        return all;
    };
    const auto errors = [&](const std::vector<float>& estimate, const std::vector<float>& truth) {
        const ErrorFigures e = error_figures(estimate, truth);
        return nlohmann::json{{"mean", e.mean}, {"p99", e.p99}, {"max", e.max}, {"mean_of_unshadowed", e.mean / lit},
                              {"p99_of_unshadowed", e.p99 / lit}};
    };
    const std::vector<float> all_reference = flatten(reference), all_fine = flatten(fine);
    const std::string coarse_name = "ray_march_" + std::to_string(options.ray_steps);
    const std::string fine_name = "ray_march_" + std::to_string(fine_steps);
    result["error_vs_" + coarse_name][fine_name] = errors(all_fine, all_reference);
    for (std::size_t v = 0; v < std::size(variants); ++v) {
        const std::vector<float> all = flatten(estimates[v]);
        result["error_vs_" + coarse_name][variants[v].name] = errors(all, all_reference);
        result["error_vs_" + fine_name][variants[v].name] = errors(all, all_fine);
    }

    // Frame-to-frame change: mean |R_{k+1} - R_k|, and the part the fine ray marching does
    // not show, mean |(R_{k+1} - R_k) - (F_{k+1} - F_k)| (aliasing, flicker).
    const auto change = [&](const std::vector<std::vector<float>>& frames, const std::vector<std::vector<float>>* minus) {
        double sum = 0;
        std::size_t count = 0;
        for (int k = 0; k + 1 < options.frames; ++k)
            for (std::size_t i = 0; i < frames[k].size(); ++i) {
                double d = frames[k + 1][i] - frames[k][i];
                if (minus) d -= (*minus)[k + 1][i] - (*minus)[k][i];
                sum += std::fabs(d);
                ++count;
            }
        return count ? sum / count : 0.0;
    };
    result["frames"] = options.frames;
    result["yaw_step_degrees"] = options.yaw_step;
    result["frame_change"][coarse_name] = change(reference, nullptr);
    result["frame_change"][fine_name] = change(fine, nullptr);
    result["flicker"][coarse_name] = change(reference, &fine);
    for (std::size_t v = 0; v < std::size(variants); ++v) {
        result["frame_change"][variants[v].name] = change(estimates[v], nullptr);
        result["flicker"][variants[v].name] = change(estimates[v], &fine);
    }
    return result;
}

int run(const Options& options) {
    const std::string text = read_text(options.scene_path);
    ScatterScene scene;
    scatter_data::Geometry geometry;
    try {
        scene = parse_scatter_scene(text);
        geometry = scatter_data::parse_geometry(text);
    } catch (const input_error& e) {
        throw input_error(options.scene_path + ": " + e.what());
    }
    if (options.camera_width > 0) scene.camera.width = options.camera_width;
    if (options.camera_height > 0) scene.camera.height = options.camera_height;
    if (options.rectified_size > 0) scene.rectified_width = scene.rectified_height = options.rectified_size;
    scene = scatter_data::yawed(scene, options.yaw);
    const int map_size = options.map_size > 0 ? options.map_size : 256;

    if (options.figures) {
        const nlohmann::json figures = run_figures(options, scene, geometry, map_size);
        if (options.json_path.empty()) {
            std::cout << figures.dump(2) << std::endl;
        } else {
            std::ofstream(options.json_path) << figures.dump(2) << '\n';
        }
        return 0;
    }
    if (!options.shadow_map_path.empty())
        io::write_depth_exr(options.shadow_map_path,
                            scatter_data::render_shadow_map(scene, geometry, map_size, map_size, options.samples));
    if (!options.camera_depth_path.empty())
        write_camera_depth(options.camera_depth_path, scene, scatter_data::render_camera_depth(scene, geometry));
    if (!options.scene_out_path.empty()) {
        // The scene as rendered (size overrides and yaw applied), geometry kept.
        nlohmann::json document = nlohmann::json::parse(text);
        document["camera"].erase("target");
        document["camera"]["forward"] = scene.camera.forward;
        document["camera"]["up"] = scene.camera.up;
        document["camera"]["width"] = scene.camera.width;
        document["camera"]["height"] = scene.camera.height;
        document["rectified"]["width"] = scene.rectified_width;
        document["rectified"]["height"] = scene.rectified_height;
        std::ofstream(options.scene_out_path) << document.dump(2) << '\n';
    }
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"msmcl-scatter-scene: depth buffers of a box scene for msmcl scatter, and its quality figures",
                 "msmcl-scatter-scene"};
    Options options;
    app.add_option("scene", options.scene_path, "scene JSON with a \"geometry\" section")->required();
    app.add_option("--shadow-map", options.shadow_map_path, "light depth EXR to write (Z or sample<N>.Z)");
    app.add_option("--camera-depth", options.camera_depth_path, "camera depth EXR to write (Z)");
    app.add_option("--write-scene", options.scene_out_path, "the scene JSON with overrides and yaw applied");
    app.add_option("--map-size", options.map_size, "shadow map side in texels (default 256)")->check(CLI::Range(8, 16384));
    app.add_option("--samples", options.samples, "shadow map samples per texel")->check(CLI::IsMember({1, 2, 4, 8, 16}));
    app.add_option("--camera-width", options.camera_width, "override the camera width")->check(CLI::Range(1, 16384));
    app.add_option("--camera-height", options.camera_height, "override the camera height")->check(CLI::Range(1, 16384));
    app.add_option("--rectified-size", options.rectified_size, "override the rectified map (square)")
        ->check(CLI::Range(1, 16384));
    app.add_option("--yaw", options.yaw, "turn the camera about the world y axis (degrees)");
    app.add_flag("--figures", options.figures, "measure the quality figures (needs an OpenCL device)");
    app.add_option("--frames", options.frames, "frames of the turning camera")->capture_default_str()->check(CLI::Range(2, 1000));
    app.add_option("--yaw-step", options.yaw_step, "degrees between frames")->capture_default_str();
    app.add_option("--ray-steps", options.ray_steps, "samples of the ray-marching reference")->capture_default_str();
    app.add_option("--filter-sigma", options.filter_sigma, "sigma of the moment map filtered resampling samples")
        ->capture_default_str();
    app.add_option("--beta", options.beta, "bounds blend in [0,1]; negative: adaptive")->capture_default_str();
    app.add_option("--json", options.json_path, "write the figures here instead of stdout");
    CLI11_PARSE(app, argc, argv);
    try {
        return run(options);
    } catch (const std::exception& e) {
        std::cerr << "msmcl-scatter-scene: " << e.what() << std::endl;
        return dynamic_cast<const input_error*>(&e) ? 2 : 1;
    }
}
