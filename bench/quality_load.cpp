// msmcl-quality, load: which scenes to measure and what their files hold (bench/quality.hpp).
#include "quality.hpp"

#include <msmcl/errors.hpp>

#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace quality {

namespace {

Scene parse_scene(const std::string& spec) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (std::size_t colon = spec.find(':'); colon != std::string::npos; colon = spec.find(':', start)) {
        parts.push_back(spec.substr(start, colon - start));
        start = colon + 1;
    }
    parts.push_back(spec.substr(start));
    if (parts.size() < 3 || parts.size() > 4)
        throw msmcl::input_error("--scene wants NAME:DEPTH:RECEIVERS[:MATERIALS], got '" + spec + "'");
    return {parts[0], parts[1], parts[2], parts.size() == 4 ? parts[3] : ""};
}

} // namespace

/// The scenes to measure: the 1024^2 ones of the build's data directory (--large), else the
/// committed sample data (materials made by the build, when there), plus every --scene.
/// Throws input_error naming a missing file.
std::vector<Scene> scenes_to_measure(const std::vector<std::string>& scene_specs, bool large,
                                     const std::string& data_dir, const std::string& build_data_dir) {
    std::vector<Scene> scenes;
    if (large) {
        scenes.push_back({"railing", build_data_dir + "/railing_1024x1024_8x.exr",
                          build_data_dir + "/railing_view_640x480.exr",
                          build_data_dir + "/railing_view_640x480_materials.exr"});
        scenes.push_back({"wuson", build_data_dir + "/wuson_1024x1024_4x.exr",
                          build_data_dir + "/wuson_view_640x480.exr", ""});
    } else if (scene_specs.empty()) {
        std::string materials = build_data_dir + "/railing_view_160x120_materials.exr";
        if (!std::filesystem::exists(materials)) {
            std::cerr << "msmcl-quality: no " << materials
                      << " (cmake --build BUILD --target msmcl_sample_materials): no banner leak figure\n";
            materials.clear();
        }
        scenes.push_back({"railing", data_dir + "/railing_256x256_4x.exr", data_dir + "/railing_view_160x120.exr",
                          materials});
        scenes.push_back({"wuson", data_dir + "/wuson_256x256_4x.exr", data_dir + "/wuson_view_160x120.exr", ""});
    }
    for (const std::string& spec : scene_specs) scenes.push_back(parse_scene(spec));
    for (const Scene& scene : scenes)
        for (const std::string& path : {scene.depth_path, scene.receivers_path, scene.materials_path})
            if (!path.empty() && !std::filesystem::exists(path))
                throw msmcl::input_error(path + ": no such file" +
                                         (large ? " (cmake --build BUILD --target msmcl_sample_data)" : ""));
    return scenes;
}

SceneInputs load_scene(const Scene& scene) {
    SceneInputs inputs;
    inputs.depth = msmcl::io::read_depth_exr(scene.depth_path, msmcl::DepthRange::zero_one);
    inputs.grid = msmcl::io::read_receivers_exr(scene.receivers_path);
    if (!scene.materials_path.empty()) {
        const msmcl::io::ExrImage image = msmcl::io::read_exr(scene.materials_path);
        const msmcl::io::ExrChannel* channel = image.find_channel("M");
        if (!channel || image.width != inputs.grid.width || image.height != inputs.grid.height)
            throw msmcl::input_error(scene.materials_path + ": wants a channel M on the receivers' " +
                                     std::to_string(inputs.grid.width) + "x" + std::to_string(inputs.grid.height) +
                                     " grid");
        inputs.materials = channel->values;
    }
    return inputs;
}

} // namespace quality
