// msmcl-quality: the quality table (docs/methods.md). For each scene, shades the view's receivers
// with every msmcl format (filter + shade on the device) and with variance shadow maps
// (32 and 64 bit) of the same resolve and blur, and compares the shadow intensities with
// 128-bit moments and with the percentage-closer ground truth of the same 9x9 Gaussian.
// Then it takes the nlq64 - moments128 difference apart with double-precision shading
// (lookup, 16-bit format, float32 encoder, float32 shading), says where the receivers that
// differ by more than 3% are, and measures light leaking on the railing scene's banner.
// Writes Markdown tables (stdout), optional JSON, and PNGs. --kernel picks the filter kernel of
// every device map (default: the one the library picks for the device).
// Three steps (bench/quality.hpp): load a scene's files (quality_load.cpp), run the
// measurements (quality_run.cpp), report them (quality_report.cpp).
#include "quality.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace {

/// The --kernel names, in msmcl::FilterKernel terms.
msmcl::FilterKernel parse_kernel(const std::string& name) {
    if (name == "fused_paper") return msmcl::FilterKernel::fused_paper;
    if (name == "fused_cpu") return msmcl::FilterKernel::fused_cpu;
    if (name == "three_pass") return msmcl::FilterKernel::three_pass;
    return msmcl::FilterKernel::automatic;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"msmcl-quality: shadow quality of every format and of VSM against 128-bit moments "
                 "and the percentage-closer ground truth"};
    std::vector<std::string> scene_specs;
    std::string data_dir = MSMCL_QUALITY_DATA_DIR;
    std::string build_data_dir = MSMCL_QUALITY_BUILD_DATA_DIR;
    std::string out_dir;
    std::string json_path;
    std::string device;
    std::string kernel_name = "automatic";
    bool large = false;
    app.add_option("--scene", scene_specs,
                   "NAME:DEPTH.exr:RECEIVERS.exr[:MATERIALS.exr] (repeatable; materials: channel M of "
                   "msmcl-scene --materials, 2 = banner; default: the committed railing and wuson scenes)");
    app.add_flag("--large", large,
                 "the 1024^2 scenes with 640x480 views of the build's data directory "
                 "(cmake --build BUILD --target msmcl_sample_data) instead of the committed ones");
    app.add_option("--data", data_dir, "directory of the committed sample scenes")->capture_default_str();
    app.add_option("--build-data", build_data_dir, "the build's data directory (materials, --large scenes)")
        ->capture_default_str();
    app.add_option("--out", out_dir, "directory for PNG images (shadow and error per scene and method)");
    app.add_option("--json", json_path, "write the results as JSON");
    app.add_option("--device", device, "OpenCL device spec (gpu, cpu, index, P:D or name substring)");
    app.add_option("--kernel", kernel_name,
                   "filter kernel of every device map: automatic (the device's pick: fused_cpu on CPU devices, "
                   "fused_paper elsewhere), fused_paper, fused_cpu or three_pass")
        ->check(CLI::IsMember({"automatic", "fused_paper", "fused_cpu", "three_pass"}))
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);

    using namespace quality;
    try {
        // Load: which scenes (the committed sample data, materials made by the build, unless given).
        const std::vector<Scene> scenes = scenes_to_measure(scene_specs, large, data_dir, build_data_dir);
        if (!out_dir.empty()) std::filesystem::create_directories(out_dir);

        msmcl::DeviceSelection selection;
        selection.device = device;
        selection.strict = !device.empty();
        msmcl::Context context(selection);
        const msmcl::FilterKernel kernel = parse_kernel(kernel_name);

        print_preamble(context.device().name, kernel_name);
        nlohmann::json json_scenes = nlohmann::json::array();
        for (const Scene& scene : scenes) {
            // Load, run, report one scene at a time.
            const SceneResult result = measure_scene(context, scene, load_scene(scene), kernel);
            print_scene(result);
            if (!out_dir.empty()) write_scene_images(result, out_dir);
            json_scenes.push_back(scene_json(result));
        }

        if (!json_path.empty()) {
            std::ofstream file(json_path);
            file << results_json(context.device().name, kernel_name, std::move(json_scenes)).dump(2) << "\n";
            if (!file) {
                std::cerr << "msmcl-quality: cannot write " << json_path << "\n";
                return 1;
            }
        }
    } catch (const msmcl::input_error& e) {
        std::cerr << "msmcl-quality: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "msmcl-quality: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
