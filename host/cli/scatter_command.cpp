#include "cli/scatter_command.hpp"
#include "cli/option_values.hpp"
#include "cli/stages.hpp"
#include "cli/texture_files.hpp"

#include "io/exr_io.hpp"
#include "io/scene_json.hpp"
#include "io/gpu_image.hpp"
#include "io/ktx2.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/scatter.hpp>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <memory>

namespace msmcl::cli {
namespace {

/// The camera depth buffer: one HALF or FLOAT channel Z of the camera's size.
std::vector<float> read_camera_depth(const std::string& path, const ScatterScene& scene) {
    const io::ExrImage image = io::read_exr(path);
    const io::ExrChannel* channel = image.find_channel("Z");
    if (!channel || channel->type == io::SampleType::uint32)
        throw input_error(path + ": no HALF or FLOAT channel Z (the camera's depth buffer)");
    if (image.width != scene.camera.width || image.height != scene.camera.height)
        throw input_error(path + ": the depth buffer is " + std::to_string(image.width) + "x" +
                          std::to_string(image.height) + ", the scene's camera " + std::to_string(scene.camera.width) +
                          "x" + std::to_string(scene.camera.height));
    return channel->values;
}

/// Float moments (k per texel) as channels b1..bk of a width x height EXR.
void write_moments_exr(const std::string& path, int width, int height, int moments, const std::vector<float>& values,
                       const std::string& what) {
    io::ExrImage image;
    image.width = width;
    image.height = height;
    const std::size_t texels = static_cast<std::size_t>(width) * height;
    for (int k = 0; k < moments; ++k) {
        io::ExrChannel channel;
        channel.name = "b" + std::to_string(k + 1);
        channel.values.resize(texels);
        for (std::size_t t = 0; t < texels; ++t) channel.values[t] = values[t * moments + k];
        image.channels.push_back(std::move(channel));
    }
    image.attributes = {{"msmcl:scatterMap", what}, {"msmcl:scatterMoments", moments}};
    io::write_exr(path, image);
}

/// The prefiltered map as a renderer uploads it (KTX2): 6 moments as a 2-layer array of
/// A2B10G10R10_UNORM_PACK32 (layer 0 the odd powers, layer 1 the even ones), 4 moments as
/// R16G16B16A16_UNORM (the msm64 layout).
void write_scatter_map_ktx2(const std::string& path, const ScatterMap& map) {
    io::GpuImage image;
    image.width = map.width;
    image.height = map.height;
    const detail::TextureKind& kind = map.moments == 6 ? detail::kScatter6Kind : detail::kScatter4Kind;
    image.format = kind.gpu_format;
    if (map.moments == 6) {
        image.layers = 2;
        image.array = true;
    }
    image.bytes.resize(map.words.size() * sizeof(std::uint32_t));
    for (std::size_t i = 0; i < map.words.size(); ++i)
        for (int b = 0; b < 4; ++b) image.bytes[4 * i + b] = static_cast<std::uint8_t>(map.words[i] >> (8 * b));
    image.metadata = {{"msmcl:format", kind.name},
                      {"msmcl:scatterMoments", std::to_string(map.moments)}};
    io::write_ktx2(path, image);
}

void run_scatter(const GlobalArguments& global, const ScatterArguments& a) {
    // Check the option values before touching any file.
    ScatterOptions options;
    options.moments = static_cast<int>(parse_integer("--moments", a.moments, 4, 6));
    if (options.moments != 4 && options.moments != 6) throw usage_error("--moments must be 4 or 6, got '" + a.moments + "'");
    options.filtered = !a.no_filter;
    options.filter_sigma = parse_finite_float("--sigma", a.sigma);
    if (options.filter_sigma < 0) throw usage_error("--sigma must be >= 0, got '" + a.sigma + "'");
    if (a.beta == "adaptive") {
        options.beta = -1.0f;
    } else {
        options.beta = parse_finite_float("--beta", a.beta);
        if (options.beta < 0 || options.beta > 1) throw usage_error("--beta must be adaptive or in [0, 1], got '" + a.beta + "'");
    }
    const std::optional<ScatterKernel> kernel = parse_scatter_kernel(a.kernel);
    if (!kernel) throw usage_error(unknown_value_message("--kernel", a.kernel, {"automatic", "rows_gpu", "rows_cpu"}));
    options.kernel = *kernel;
    const std::optional<FilterKernel> filter_kernel = parse_filter_kernel(a.filter_kernel);
    if (!filter_kernel)
        throw usage_error(unknown_value_message("--filter-kernel", a.filter_kernel,
                                                {"automatic", "fused_paper", "fused_cpu", "three_pass"}));
    options.filter_kernel = *filter_kernel;
    const int ray_steps = a.ray_march.empty() ? 0 : static_cast<int>(parse_integer("--ray-march", a.ray_march, 1, 1 << 20));
    const auto jitter = static_cast<std::uint32_t>(parse_integer("--jitter", a.jitter, 0, 0xffffffffL));
    if (ray_steps > 0 && (!a.rectified.empty() || !a.prefix_sums.empty() || !a.map.empty()))
        throw usage_error("--rectified, --prefix-sums and --map need the prefiltered method (no --ray-march)");
    // Every output of scatter is OpenEXR but the renderer's map (KTX2).
    require_exr_output(a.output);
    if (!a.rectified.empty()) require_exr_output(a.rectified);
    if (!a.prefix_sums.empty()) require_exr_output(a.prefix_sums);

    Stages stages(global.verbose, 6);

    // Read and check the inputs.
    const ScatterScene scene = stages.run("read scene", [&] { return load_scatter_scene(a.scene); });
    const DepthImage shadow_map =
        stages.run("read shadow map", [&] { return io::read_depth_exr(a.shadow_map, scene.light.depth_range); });
    const std::vector<float> camera_depth =
        stages.run("read camera depth", [&] { return read_camera_depth(a.camera_depth, scene); });
    try {
        validate_scatter_inputs(scene, shadow_map, camera_depth);
    } catch (const input_error& e) {
        // read_depth_exr checked the shadow map already: what is left is the camera's.
        throw input_error(a.camera_depth + ": " + e.what());
    }

    // Compute on the device.
    Context context = stages.run("device setup", [&] { return Context(global.selection()); });
    std::vector<float> radiance;
    std::string method;
    stages.run("scatter (program, upload, kernels, download)", [&] {
        if (ray_steps > 0) {
            radiance = scatter_ray_march(context, scene, shadow_map, camera_depth, ray_steps, jitter);
            method = "ray_march_" + std::to_string(ray_steps);
        } else {
            radiance = scatter(context, scene, shadow_map, camera_depth, options);
            method = "prefiltered_" + std::to_string(options.moments) + (options.filtered ? "_filtered" : "_unfiltered");
        }
    });
    if (!a.rectified.empty())
        write_moments_exr(a.rectified, scene.rectified_width, scene.rectified_height, options.moments,
                          scatter_rectified_moments(context, scene, shadow_map, options, false), "resampled");
    if (!a.prefix_sums.empty() || !a.map.empty()) {
        const ScatterMap map = scatter_prefilter(context, scene, shadow_map, options);
        if (!a.prefix_sums.empty())
            write_moments_exr(a.prefix_sums, map.width, map.height, map.moments, decode_scatter_map(map), "prefix sums");
        if (!a.map.empty()) write_scatter_map_ktx2(a.map, map);
    }

    // The radiance per camera pixel.
    io::ExrImage image;
    image.width = scene.camera.width;
    image.height = scene.camera.height;
    image.channels = {{"Y", io::SampleType::float32, radiance, {}}};
    image.attributes = {{"msmcl:scatterMethod", method}};
    stages.run("write", [&] { io::write_exr(a.output, image); });
}

} // namespace

Subcommand add_scatter_command(CLI::App& app) {
    const auto parsed = std::make_shared<ScatterArguments>();
    ScatterArguments& a = *parsed;
    CLI::App* command = app.add_subcommand(
        "scatter", "Scene JSON + light depth map + camera depth buffer -> single-scattered radiance (EXR Y)");
    command->add_option("scene", a.scene, "scene JSON (light, camera, medium, rectified map)")->required();
    command->add_option("shadow_map", a.shadow_map, "light depth map EXR (Z or sample<N>.Z, the light's depth_range)")
        ->required();
    command->add_option("camera_depth", a.camera_depth, "camera depth buffer EXR (Z, the camera's convention)")->required();
    command->add_option("output", a.output, "radiance EXR to write (channel Y)")->required();
    command->add_option("--moments", a.moments, "4 or 6")->capture_default_str()->type_name("N");
    command->add_flag("--no-filter", a.no_filter, "resample one depth sample per texel instead of a filtered moment sample");
    command->add_option("--sigma", a.sigma, "Gaussian sigma (texels) of the moment map filtered resampling reads")
        ->capture_default_str()
        ->type_name("FLOAT");
    command->add_option("--beta", a.beta, "bounds blend: adaptive, or B in [0,1] (0 lower bound, 1 upper bound)")
        ->capture_default_str()
        ->type_name("BETA");
    command->add_option("--ray-march", a.ray_march, "ray march the shadow map with N samples instead (ground truth)")
        ->type_name("N");
    command->add_option("--jitter", a.jitter, "with --ray-march: per-pixel jitter seed (0 = midpoints)")
        ->capture_default_str()
        ->type_name("SEED");
    command->add_option("--rectified", a.rectified, "also write the resampled rectified moments (EXR b1..bk)")
        ->type_name("FILE");
    command->add_option("--prefix-sums", a.prefix_sums, "also write the stored prefix sums, decoded (EXR b1..bk)")
        ->type_name("FILE");
    command->add_option("--kernel", a.kernel,
                        "the prefilter's work per rectified row: automatic (by the device's type), rows_gpu (128 "
                        "work-items, 2 texels each) or rows_cpu (64 work-items, 8 texels each); same bits")
        ->capture_default_str()
        ->type_name("KERNEL");
    command->add_option("--filter-kernel", a.filter_kernel,
                        "kernel of the moment map filtered resampling reads: automatic, fused_paper, fused_cpu or "
                        "three_pass (as msmcl filter --kernel)")
        ->capture_default_str()
        ->type_name("KERNEL");
    command->add_option("--map", a.map,
                        "also write the prefiltered map as KTX2 (6 moments: 2 layers of A2B10G10R10_UNORM_PACK32, "
                        "4: R16G16B16A16_UNORM)")
        ->type_name("FILE.ktx2");
    return {command, [parsed](const GlobalArguments& global) {
                run_scatter(global, *parsed);
                return 0;
            }};
}

} // namespace msmcl::cli
