// msmcl-quality (bench/quality.cpp): what its three steps share. Load (quality_load.cpp)
// reads a scene's files, run (quality_run.cpp) filters and shades it with every format and
// computes the references and the decomposition, report (quality_report.cpp) writes the
// Markdown tables, the images and the JSON.
#pragma once

#include <msmcl/context.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/formats.hpp>

#include "io/exr_io.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace quality {

inline constexpr double blur_sigma = 2.4;          // the library's default blur
inline constexpr double depth_bias = 1e-3;         // internal depth, shade's default
inline constexpr double error_threshold = 0.03;    // "off by more than 3%"
inline constexpr double large_error_threshold = 0.10;
// Filament's default light-bleed reduction, shaded beside EVSM as published.
inline constexpr float filament_light_bleed_reduction = 0.15f;
// Timed runs of the filter per format (after one untimed): the median kernel stage.
inline constexpr int timed_filter_runs = 5;
inline constexpr double alpha_128 = 3e-7;          // moments128 bias and Algorithm 2's input bias (docs/math.md)
inline constexpr double bstar_128 = 0.375;
// Light leak on the banner: receivers there that the railing shadows (truth >= 0.5); a
// receiver leaks when the method is lighter than the truth by more than 0.1.
inline constexpr double leak_truth_min = 0.5;
inline constexpr double leak_significant = 0.1;
inline constexpr int banner_material = 2;          // msmcl-scene --materials: 0 sky, 1 ground, 2 banner, 3 railing
// Classes of receivers by the spread (max - min, internal depth) of the samples their
// bilinear lookup filters (10x10 texels), measured from the receiver's plane: one surface
// (flat or sloped), a short-range step (railing over banner, 14 cm apart), a long-range
// step (a silhouette against far depths).
inline constexpr std::array<double, 2> spread_bounds = {0.02, 0.2};
inline const std::array<const char*, 3> spread_class_names = {"one surface (spread < 0.02)", "short-range step (0.02-0.2)",
                                                              "long-range step (>= 0.2)"};

struct Scene {
    std::string name;
    std::string depth_path;
    std::string receivers_path;
    std::string materials_path; ///< optional: channel M per receiver
};

/// What one scene's files hold.
struct SceneInputs {
    msmcl::DepthImage depth;       ///< [0,1] convention
    msmcl::io::ReceiverGrid grid;  ///< the view's receivers
    std::vector<float> materials;  ///< channel M per receiver, or empty
};

struct ErrorStats {
    double share_above = 0;       ///< share of receivers with |error| > 0.03
    std::size_t count_above = 0;
    std::size_t count_above_large = 0; ///< |error| > 0.10
    double max = 0;
    double mean = 0;
};

/// Light leaked on the banner where the railing shadows it.
struct LeakStats {
    bool available = false;      ///< the scene has materials
    std::size_t receivers = 0;   ///< banner receivers with truth >= 0.5
    double mean_truth = 0;
    double mean_leak = 0;        ///< mean of max(0, truth - method)
    double share_leaking = 0;    ///< share with truth - method > 0.1
};

struct MethodResult {
    std::string name;             ///< the format, "_lbr0.15" where shaded with light-bleed reduction 0.15
    msmcl::Format format = msmcl::Format::moments128;
    float light_bleed_reduction = 0; ///< VSM and EVSM: R of the shading (0: as published)
    double kernel_ms = 0;         ///< the filter's kernel stage, median of the timed runs (ms)
    std::vector<double> shadow;
    ErrorStats vs_moments128;
    ErrorStats vs_truth;
    ErrorStats vs_truth_constant_bias;
    LeakStats leak;
};

/// One step of the nlq64 - moments128 decomposition: `shadow` against `reference`.
struct Step {
    std::string name;
    std::string what;
    ErrorStats stats;
};

/// Receivers of one footprint class (spread_bounds) and how many of them differ.
struct FootprintClass {
    std::size_t receivers = 0, nlq64_above = 0, lookup_above = 0, nlq64_above_large = 0;
    std::size_t nearest_above = 0, nearest_encoder_above = 0;
};

/// Everything the report says about one scene.
struct SceneResult {
    Scene scene;
    int width = 0, height = 0, samples = 0;           ///< the depth map
    int view_width = 0, view_height = 0;              ///< the receivers' grid
    std::size_t count = 0;                            ///< receivers
    bool has_materials = false;
    std::size_t leak_set_size = 0;                    ///< banner receivers in the railing's shadow
    std::vector<double> truth, truth_constant_bias;   ///< PCF ground truth per receiver
    std::vector<MethodResult> methods;                ///< every filter format in Format order, then EVSM with R = 0.15
    std::vector<Step> steps;                          ///< the nlq64 - moments128 decomposition
    std::array<std::size_t, 4> codes_off{};           ///< nlq64 codes > 1 step from the double encoding
    std::size_t texels_off = 0, texels_off_one_depth = 0;
    double texel_count = 0;
    std::array<FootprintClass, 3> classes{};
    std::size_t moments128_above = 0, moments128_lighter = 0, moments128_darker_lit = 0, moments128_self_shadow = 0;
};

// ---- Load (quality_load.cpp)

/// The scenes to measure: the 1024^2 ones of the build's data directory (--large), else the
/// committed sample data (materials made by the build, when there), plus every --scene
/// (NAME:DEPTH:RECEIVERS[:MATERIALS]). Throws input_error naming a missing file.
std::vector<Scene> scenes_to_measure(const std::vector<std::string>& scene_specs, bool large,
                                     const std::string& data_dir, const std::string& build_data_dir);
/// The depth map ([0,1] convention), the view's receivers, their materials.
SceneInputs load_scene(const Scene& scene);

// ---- Run (quality_run.cpp)

/// Filters and shades the scene with every format (kernel: the filter kernel; the library's
/// textures and shading), times the filter's kernel per format, computes the PCF truth, the
/// errors, the decomposition and the classes.
SceneResult measure_scene(msmcl::Context& context, const Scene& scene, const SceneInputs& inputs,
                          msmcl::FilterKernel kernel);

// ---- Report (quality_report.cpp)

/// The Markdown title and the definitions (stdout).
void print_preamble(const std::string& device_name, const std::string& kernel_name);
/// One scene's tables (stdout).
void print_scene(const SceneResult& result);
/// Ground truth, shadow and error per method, nlq64's > 3% receivers, as PNGs in `out_dir`.
void write_scene_images(const SceneResult& result, const std::string& out_dir);
/// One scene's entry of the JSON.
nlohmann::json scene_json(const SceneResult& result);

/// The whole JSON: the settings and every scene.
nlohmann::json results_json(const std::string& device_name, const std::string& kernel_name, nlohmann::json scenes);

} // namespace quality
