// msmcl-vulkan: a headless Vulkan 1.2 compute consumer of msmcl's KTX2 textures.
//
// It does what a renderer does with them: reads the KTX2 file (msmcl's reader, host/io;
// Debian 12 packages no KTX2 library), creates a VkImage of exactly the file's format,
// uploads it through a staging buffer, builds a sampler as docs/shaders.md prescribes for that
// texture (linear where filtering is allowed, nearest where not, clamp to edge) and runs a
// compute shader that includes shaders/msm.glsl (or, with --hlsl, shaders/msm.hlsl through
// glslang's HLSL front end), both compiled to SPIR-V at build time. Results are EXR files
// laid out like msmcl's own (`Y` on the receivers' grid), so that they compare one to one
// with `msmcl shade`, `msmcl soft` and `msmcl scatter`.
//
//   msmcl-vulkan devices
//   msmcl-vulkan shade MAP.ktx2 RECEIVERS.exr OUT.exr [--lookup nearest|bilinear|dither|hardware] [--frame N]
//                [--depth-bias B] [--depth-range 0,1|-1,1] [--accurate] [--layer L|all] [--hlsl]
//                [--min-variance V] [--light-bleed-reduction R]   (VSM, EVSM)
//     (a texture array: layer L into channel Y, or every layer i into channel layer<i>.Y)
//   msmcl-vulkan soft SAT.ktx2 RECEIVERS.exr OUT.exr --light-size L [--search-size K] [--min-filter F] [--published]
//                [--depth-bias B] [--depth-range R] [--hlsl]
//   msmcl-vulkan scatter SCENE.json MAP.ktx2 CAMERA_DEPTH.exr OUT.exr [--beta adaptive|B] [--hlsl]
//   msmcl-vulkan compare A.exr B.exr [--channel Y] [--diff-png D.png] [--diff-scale S]
//
// Exit codes: 0 success, 1 runtime failure, 2 bad input or usage, 3 no Vulkan device.
#include "vulkan_compute.hpp"

#include "io/exr_io.hpp"
#include "io/gpu_image.hpp"
#include "io/ktx2.hpp"
#include "io/png_io.hpp"
#include "io/scene_json.hpp"
#include "io/texture_metadata.hpp"
#include "ops/scatter_params.hpp"
#include "runtime/texture_kinds.hpp"
#include "kernels/msm_filterable_shading.clh"
#include "tools/signed_difference.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/formats.hpp>
#include <msmcl/sat.hpp>
#include <msmcl/scatter.hpp>
#include <msmcl/shade.hpp>
#include <msmcl/device_math.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <iterator>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

// SPIR-V compiled at build time (glslangValidator --vn): shade_<language>_<format>, soft_*, scatter_*.
#include "scatter4_glsl.h"
#include "scatter4_hlsl.h"
#include "scatter6_glsl.h"
#include "scatter6_hlsl.h"
#include "shade_array_glsl_0.h"
#include "shade_array_glsl_1.h"
#include "shade_array_glsl_2.h"
#include "shade_array_glsl_3.h"
#include "shade_array_glsl_4.h"
#include "shade_array_glsl_5.h"
#include "shade_array_glsl_6.h"
#include "shade_array_glsl_7.h"
#include "shade_array_glsl_8.h"
#include "shade_array_glsl_9.h"
#include "shade_array_hlsl_0.h"
#include "shade_array_hlsl_1.h"
#include "shade_array_hlsl_2.h"
#include "shade_array_hlsl_3.h"
#include "shade_array_hlsl_4.h"
#include "shade_array_hlsl_5.h"
#include "shade_array_hlsl_6.h"
#include "shade_array_hlsl_7.h"
#include "shade_array_hlsl_8.h"
#include "shade_array_hlsl_9.h"
#include "shade_glsl_0.h"
#include "shade_glsl_1.h"
#include "shade_glsl_2.h"
#include "shade_glsl_3.h"
#include "shade_glsl_4.h"
#include "shade_glsl_5.h"
#include "shade_glsl_6.h"
#include "shade_glsl_7.h"
#include "shade_glsl_8.h"
#include "shade_glsl_9.h"
#include "shade_hlsl_0.h"
#include "shade_hlsl_1.h"
#include "shade_hlsl_2.h"
#include "shade_hlsl_3.h"
#include "shade_hlsl_4.h"
#include "shade_hlsl_5.h"
#include "shade_hlsl_6.h"
#include "shade_hlsl_7.h"
#include "shade_hlsl_8.h"
#include "shade_hlsl_9.h"
#include "soft_glsl.h"
#include "soft_hlsl.h"

namespace {

using namespace msmcl_vulkan;

constexpr int exit_runtime_failure = 1;
constexpr int exit_bad_input = 2;
constexpr int exit_no_device = 3;

struct usage_error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

template <std::size_t N>
std::vector<std::uint32_t> words(const std::uint32_t (&code)[N]) {
    return std::vector<std::uint32_t>(code, code + N);
}

// The shading language of the compute shaders: GLSL binds combined image samplers, the
// HLSL route separate images and a sampler (binding 4), as D3D does.
struct Language {
    bool hlsl = false;
    const char* entry() const { return "main"; }
};

// The receiver record of the shaders (std430 / StructuredBuffer: 5 x 4 bytes).
struct ReceiverRecord {
    float u, v, z;
    std::uint32_t px, py;
};
static_assert(sizeof(ReceiverRecord) == 20, "receiver record layout");

std::vector<ReceiverRecord> receiver_records(const msmcl::io::ReceiverGrid& grid) {
    std::vector<ReceiverRecord> records(grid.points.size());
    for (std::size_t i = 0; i < records.size(); ++i) {
        const bool has_pixels = !grid.pixels.x.empty();
        const auto width = static_cast<std::uint32_t>(std::max(grid.width, 1));
        records[i] = {grid.points.u[i], grid.points.v[i], grid.points.z[i],
                      has_pixels ? grid.pixels.x[i] : static_cast<std::uint32_t>(i % width),
                      has_pixels ? grid.pixels.y[i] : static_cast<std::uint32_t>(i / width)};
    }
    return records;
}

VkFormat vk_format_of(const msmcl::io::GpuImage& image) {
    return static_cast<VkFormat>(msmcl::io::gpu_format_info(image.format).vk_format);
}

// A texture binding: one combined image sampler (GLSL), or a sampled image plus, where the
// shader filters, the sampler at binding 4 (HLSL).
void bind_texture(std::vector<Binding>& bindings, const Language& language, std::uint32_t binding, VkImageView view,
                  VkSampler sampler) {
    if (!language.hlsl) {
        bindings.push_back({binding, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, view, sampler, VK_NULL_HANDLE});
        return;
    }
    bindings.push_back({binding, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, view, VK_NULL_HANDLE, VK_NULL_HANDLE});
}

// Runs `spirv` over `count` items with the texture bindings, an input buffer at binding 2
// and `count` floats out at binding 3.
std::vector<float> run_pass(VulkanCompute& vulkan, const std::vector<std::uint32_t>& spirv, const Language& language,
                            std::vector<Binding> bindings, VkSampler hlsl_sampler, const void* input,
                            std::size_t input_bytes, const void* push, std::uint32_t push_bytes, std::uint32_t count) {
    Buffer in = vulkan.create_buffer(std::max<std::size_t>(input_bytes, 4));
    Buffer out = vulkan.create_buffer(std::max<std::size_t>(count * sizeof(float), 4));
    vulkan.write_buffer(in, input, input_bytes);
    bindings.push_back({2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_NULL_HANDLE, VK_NULL_HANDLE, in.buffer});
    bindings.push_back({3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_NULL_HANDLE, VK_NULL_HANDLE, out.buffer});
    if (language.hlsl && hlsl_sampler != VK_NULL_HANDLE)
        bindings.push_back({4, VK_DESCRIPTOR_TYPE_SAMPLER, VK_NULL_HANDLE, hlsl_sampler, VK_NULL_HANDLE});
    vulkan.dispatch(spirv, language.entry(), bindings, push, push_bytes, count, 64);
    std::vector<float> result(count);
    vulkan.read_buffer(out, result.data(), count * sizeof(float));
    vulkan.destroy(in);
    vulkan.destroy(out);
    return result;
}

std::optional<msmcl::DepthRange> depth_range_option(const std::string& text) {
    if (text.empty()) return std::nullopt;
    const std::optional<msmcl::DepthRange> range = msmcl::parse_depth_range(text);
    if (!range) throw usage_error("--depth-range must be 0,1 or -1,1, got '" + text + "'");
    return range;
}

msmcl::DepthRange depth_range_of(const msmcl::io::GpuImage& image, const std::optional<msmcl::DepthRange>& option) {
    if (option) return *option;
    const std::optional<std::string> text = image.find_metadata("msmcl:depthRange");
    const std::optional<msmcl::DepthRange> range = text ? msmcl::parse_depth_range(*text) : std::nullopt;
    return range.value_or(msmcl::DepthRange::zero_one);
}

float float_option(const char* name, const std::string& text) {
    try {
        std::size_t used = 0;
        const float value = std::stof(text, &used);
        if (used == text.size() && std::isfinite(value)) return value;
    } catch (const std::exception&) {
    }
    throw usage_error(std::string(name) + " must be a finite number, got '" + text + "'");
}

// ---- shade: every format, every lookup.
struct ShadeArguments {
    std::string map, receivers, output;
    std::string lookup = "bilinear";
    std::uint32_t frame = 0;
    std::string depth_bias; ///< empty: the format's (msmcl::shade_defaults)
    std::string depth_range;
    bool accurate = false;
    std::string layer; ///< texture arrays: a layer, or all (also when empty)
    std::string min_variance;          ///< VSM, EVSM; empty: the format's
    std::string light_bleed_reduction; ///< VSM, EVSM; empty: 0
};

struct ShadePush {
    std::int32_t width, height;
    std::uint32_t count;
    std::int32_t lookup;
    float depth_bias;
    std::uint32_t zero_one;
    std::uint32_t noise_texture, noise_offset_x, noise_offset_y;
    std::uint32_t accurate;
    std::int32_t layer; ///< texture arrays: the layer shaded
    // VSM, EVSM, ESM: msm_warp_shading (msm_filterable_shading.clh) as msmcl shade makes it.
    std::int32_t representation;
    float warp_positive, warp_negative, min_variance, light_bleed_reduction;
};

/// How msmcl shade shades a VSM, EVSM or ESM texture: its representation (the format table),
/// the exponents it was made with, and the options' minimum variance and light-bleed reduction.
msm_warp_shading warp_shading_of(const msmcl::Texture& texture, const msmcl::ShadeOptions& options) {
    const msmcl::WarpExponents c = msmcl::effective_exponents(texture.format, texture.exponents, "shade");
    const float v = options.min_variance.value_or(0.0f), r = options.light_bleed_reduction;
    switch (msmcl::detail::texture_kind(texture.format).representation) {
    case msmcl::detail::Representation::vsm: return msm_warp_shading_vsm(v, r);
    case msmcl::detail::Representation::evsm2: return msm_warp_shading_evsm2(c.positive, v, r);
    case msmcl::detail::Representation::evsm4: return msm_warp_shading_evsm4(c.positive, c.negative, v, r);
    case msmcl::detail::Representation::esm: return msm_warp_shading_esm(c.positive);
    case msmcl::detail::Representation::moments: break;
    }
    return msm_warp_shading_vsm(0.0f, 0.0f); // the moment formats' shaders read none of it
}

/// The layers --layer picks from a texture array of `layers` layers: one, or all of them.
std::vector<int> layers_to_shade(const std::string& option, int layers, const std::string& map) {
    std::vector<int> picked;
    if (option.empty() || option == "all") {
        for (int layer = 0; layer < layers; ++layer) picked.push_back(layer);
        return picked;
    }
    std::size_t used = 0;
    int layer = -1;
    try {
        layer = std::stoi(option, &used);
    } catch (const std::exception&) {
    }
    if (used != option.size() || layer < 0 || layer >= layers)
        throw usage_error("--layer must be all or a layer in [0, " + std::to_string(layers - 1) + "] of " + map +
                          ", got '" + option + "'");
    return {layer};
}

void run_shade(VulkanCompute& vulkan, const Language& language, const ShadeArguments& a) {
    // Options first, then the files.
    const std::vector<std::string> lookups = {"nearest", "bilinear", "dither", "hardware"};
    const auto lookup = std::find(lookups.begin(), lookups.end(), a.lookup);
    if (lookup == lookups.end())
        throw usage_error("unknown --lookup '" + a.lookup + "' (expected nearest, bilinear, dither or hardware)");
    if (!a.depth_bias.empty()) float_option("--depth-bias", a.depth_bias);
    const std::optional<msmcl::DepthRange> range_option = depth_range_option(a.depth_range);

    const msmcl::io::GpuImage image = msmcl::io::read_ktx2(a.map);
    const std::optional<std::string> format_text = image.find_metadata("msmcl:format");
    const std::optional<msmcl::Format> format = format_text ? msmcl::parse_format(*format_text) : std::nullopt;
    if (!format) throw msmcl::input_error(a.map + ": no msmcl:format of a shadow map (msmcl filter ... .ktx2)");
    // Validates the file's vkFormat against the table of docs/shaders.md for this texture, and its
    // record (sigma, samples, depth range, exponents) as msmcl does.
    const msmcl::Texture texture = msmcl::io::texture_of(image, *format, a.map);
    // The shading options as msmcl shade takes them: the format's defaults, the command line's values.
    msmcl::ShadeOptions options = msmcl::shade_defaults(*format);
    if (!a.depth_bias.empty()) options.depth_bias = float_option("--depth-bias", a.depth_bias);
    if (!a.min_variance.empty()) options.min_variance = float_option("--min-variance", a.min_variance);
    if (!a.light_bleed_reduction.empty())
        options.light_bleed_reduction = float_option("--light-bleed-reduction", a.light_bleed_reduction);
    const bool variance_bound = msmcl::shade_defaults(*format).min_variance.has_value();
    if ((!a.min_variance.empty() || !a.light_bleed_reduction.empty()) && !variance_bound)
        throw usage_error("--min-variance and --light-bleed-reduction are for VSM and EVSM maps, not " +
                          std::string(msmcl::format_name(*format)));
    if (options.min_variance && !(*options.min_variance >= 0.0f && *options.min_variance <= 0.25f))
        throw usage_error("--min-variance must be in [0, 0.25], got '" + a.min_variance + "'");
    if (!(options.light_bleed_reduction >= 0.0f && options.light_bleed_reduction < 1.0f))
        throw usage_error("--light-bleed-reduction must be in [0, 1), got '" + a.light_bleed_reduction + "'");
    const msm_warp_shading warp = warp_shading_of(texture, options);
    (void)msmcl::io::texture_info_of(image, a.map);
    // A 2D map, or a texture array (a cascade set) shaded layer by layer through sampler2DArray.
    const bool array = image.array || image.layers != 1;
    if (!array && !a.layer.empty())
        throw usage_error("--layer picks a layer of a texture array; " + a.map + " is one 2D map");
    const std::vector<int> layers = array ? layers_to_shade(a.layer, image.layers, a.map) : std::vector<int>{0};
    const int lookup_index = static_cast<int>(lookup - lookups.begin());
    // Linear filtering where a bilinear lookup blends the stored values (the format table).
    const bool filterable = msmcl::detail::texture_kind(*format).blends_moments;
    if (lookup_index == 3 && !filterable)
        throw usage_error("--lookup hardware filters the texture, which the formats that blend their stored values "
                          "allow, not " + std::string(msmcl::format_name(*format)) +
                          " (shaded per texel, then blended)");
    if (a.accurate && (*format != msmcl::Format::moments128 || lookup_index == 3))
        throw usage_error("--accurate is the float-float path of moments128 with the nearest, bilinear or dither lookup");
    const msmcl::io::ReceiverGrid grid = msmcl::io::read_receivers_exr(a.receivers);

    // The texture in its documented format; linear filtering where docs/shaders.md allows it.
    const VkFormat vk_format = vk_format_of(image);
    if (!vulkan.supports_sampling(vk_format, filterable))
        throw msmcl::error("the Vulkan device cannot sample " + std::string(msmcl::io::gpu_format_info(image.format).name) +
                           (filterable ? " with linear filtering" : ""));
    Image map = vulkan.upload_image(vk_format, image.width, image.height, static_cast<std::uint32_t>(image.layers),
                                    image.bytes, array);
    const VkSampler map_sampler = vulkan.create_sampler(filterable ? VK_FILTER_LINEAR : VK_FILTER_NEAREST,
                                                        VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
                                                        VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
    // The blue noise: 64 textures of 64 x 64 stacked into one 64 x 4096 R8G8_UINT image.
    const std::vector<std::uint8_t> noise_bytes(msmcl::blue_noise_textures(),
                                                msmcl::blue_noise_textures() + msmcl::blue_noise_bytes());
    Image noise = vulkan.upload_image(VK_FORMAT_R8G8_UINT, 64, 4096, 1, noise_bytes);
    const VkSampler nearest = vulkan.create_sampler(VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
                                                    VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);

    std::vector<Binding> bindings;
    bind_texture(bindings, language, 0, map.view, map_sampler);
    bind_texture(bindings, language, 1, noise.view, nearest);
    const msmcl::BlueNoiseFrame frame = msmcl::blue_noise_frame(a.frame);
    const std::vector<ReceiverRecord> records = receiver_records(grid);
    ShadePush push{image.width,
                   image.height,
                   static_cast<std::uint32_t>(records.size()),
                   lookup_index,
                   options.depth_bias,
                   depth_range_of(image, range_option) == msmcl::DepthRange::zero_one ? 1u : 0u,
                   frame.texture,
                   frame.offset_x,
                   frame.offset_y,
                   a.accurate ? 1u : 0u,
                   0,
                   warp.representation,
                   warp.positive,
                   warp.negative,
                   warp.min_variance,
                   warp.light_bleed_reduction};
    // One SPIR-V per format (MSM_FORMAT, examples/vulkan/CMakeLists.txt), in Format order.
#define MSMCL_SHADE_SPIRV(prefix)                                                                                   \
    {words(prefix##_0), words(prefix##_1), words(prefix##_2), words(prefix##_3), words(prefix##_4),                  \
     words(prefix##_5), words(prefix##_6), words(prefix##_7), words(prefix##_8), words(prefix##_9)}
    static const std::vector<std::uint32_t> glsl[] = MSMCL_SHADE_SPIRV(shade_glsl);
    static const std::vector<std::uint32_t> hlsl[] = MSMCL_SHADE_SPIRV(shade_hlsl);
    static const std::vector<std::uint32_t> glsl_array[] = MSMCL_SHADE_SPIRV(shade_array_glsl);
    static const std::vector<std::uint32_t> hlsl_array[] = MSMCL_SHADE_SPIRV(shade_array_hlsl);
#undef MSMCL_SHADE_SPIRV
    static_assert(std::size(glsl) == msmcl::detail::kFilterFormats, "one shader per format");
    const int f = static_cast<int>(*format);
    const std::vector<std::uint32_t>& spirv =
        array ? (language.hlsl ? hlsl_array[f] : glsl_array[f]) : (language.hlsl ? hlsl[f] : glsl[f]);
    // One pass per layer: channel Y for a 2D map or one chosen layer, layer<i>.Y for all.
    msmcl::io::ExrImage out;
    out.width = grid.width;
    out.height = grid.height;
    for (int layer : layers) {
        push.layer = layer;
        const std::vector<float> shadow = run_pass(vulkan, spirv, language, bindings, map_sampler, records.data(),
                                                   records.size() * sizeof(ReceiverRecord), &push, sizeof push, push.count);
        const bool chosen_layer = !array || (!a.layer.empty() && a.layer != "all");
        out.channels.push_back({chosen_layer ? "Y" : "layer" + std::to_string(layer) + ".Y",
                                msmcl::io::SampleType::float32, shadow, {}});
    }
    vulkan.destroy(map);
    vulkan.destroy(noise);
    if (out.channels.size() == 1 && out.channels[0].name == "Y")
        msmcl::io::write_intensity_exr(a.output, grid.width, grid.height, out.channels[0].values);
    else
        msmcl::io::write_exr(a.output, out);
}

// ---- soft: moment soft shadows from the R32G32B32A32_UINT summed-area table.
struct SoftArguments {
    std::string table, receivers, output;
    std::string light_size;
    int search_size = 0;
    std::string min_filter = "1";
    std::string depth_bias = "1e-3";
    std::string depth_range;
    std::string receiver_weight = "0.1";
    int filter_parts = 2;
    bool published = false;
};

struct SoftPush {
    std::int32_t width, height;
    std::uint32_t count, scale;
    std::int32_t search_size;
    float light_size, min_filter_size, max_filter_size, depth_bias;
    std::uint32_t zero_one;
    float receiver_weight;
    std::int32_t filter_parts;
};

void run_soft(VulkanCompute& vulkan, const Language& language, const SoftArguments& a) {
    msmcl::SoftShadowOptions options;
    options.light_size = float_option("--light-size", a.light_size);
    options.search_size = a.search_size;
    options.min_filter_size = float_option("--min-filter", a.min_filter);
    options.depth_bias = float_option("--depth-bias", a.depth_bias);
    options.receiver_blocker_weight = a.published ? 0.0f : float_option("--receiver-weight", a.receiver_weight);
    options.filter_parts = a.published ? 1 : a.filter_parts;
    const std::optional<msmcl::DepthRange> range_option = depth_range_option(a.depth_range);

    const msmcl::io::GpuImage image = msmcl::io::read_ktx2(a.table);
    if (image.format != msmcl::io::GpuFormat::r32g32b32a32_uint || image.array ||
        image.find_metadata("msmcl:format") != std::optional<std::string>("sat"))
        throw msmcl::input_error(a.table + ": not a summed-area table (R32G32B32A32_UINT, msmcl:format sat)");
    // N, msmcl:scale and the record checked as msmcl checks them.
    const std::uint32_t max_kernel = msmcl::io::sat_max_kernel_of(image, a.table, std::nullopt, "KTX2");
    (void)msmcl::io::texture_info_of(image, a.table);
    msmcl::SoftShadowLimits limits;
    try {
        limits = msmcl::soft_shadow_limits(static_cast<std::uint32_t>(max_kernel), options);
    } catch (const msmcl::input_error& e) {
        throw usage_error(std::string(e.what()) + " (" + a.table + " has N = " + std::to_string(max_kernel) + ")");
    }
    const msmcl::io::ReceiverGrid grid = msmcl::io::read_receivers_exr(a.receivers);

    // Integer texels: sampled image with a nearest sampler, read by texelFetch only.
    const VkFormat vk_format = vk_format_of(image);
    if (!vulkan.supports_sampling(vk_format, false))
        throw msmcl::error("the Vulkan device cannot sample r32g32b32a32_uint images");
    Image table = vulkan.upload_image(vk_format, image.width, image.height, 1, image.bytes);
    const VkSampler nearest = vulkan.create_sampler(VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
                                                    VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
    std::vector<Binding> bindings;
    bind_texture(bindings, language, 0, table.view, nearest);
    const std::vector<ReceiverRecord> records = receiver_records(grid);
    const SoftPush push{image.width,
                        image.height,
                        static_cast<std::uint32_t>(records.size()),
                        msmcl::sat_scale(static_cast<std::uint32_t>(max_kernel)),
                        limits.search_size,
                        options.light_size,
                        options.min_filter_size,
                        limits.max_filter_size,
                        options.depth_bias,
                        depth_range_of(image, range_option) == msmcl::DepthRange::zero_one ? 1u : 0u,
                        options.receiver_blocker_weight,
                        options.filter_parts};
    static const std::vector<std::uint32_t> glsl = words(soft_glsl), hlsl = words(soft_hlsl);
    const std::vector<float> shadow =
        run_pass(vulkan, language.hlsl ? hlsl : glsl, language, bindings, VK_NULL_HANDLE, records.data(),
                 records.size() * sizeof(ReceiverRecord), &push, sizeof push, push.count);
    vulkan.destroy(table);
    msmcl::io::write_intensity_exr(a.output, grid.width, grid.height, shadow);
}

// ---- scatter: the six-moment evaluation from the two A2B10G10R10 layers (or four moments
// from one R16G16B16A16_UNORM image).
struct ScatterArguments {
    std::string scene, map, camera_depth, output;
    std::string beta = "adaptive";
};

struct RayRecord {
    float u, v, zf, beta, unshadowed;
};
struct ScatterPush {
    std::int32_t width, height;
    std::uint32_t count;
};

void run_scatter(VulkanCompute& vulkan, const Language& language, const ScatterArguments& a) {
    float beta = -1.0f;
    if (a.beta != "adaptive") {
        beta = float_option("--beta", a.beta);
        if (beta < 0.0f || beta > 1.0f) throw usage_error("--beta must be adaptive or in [0, 1], got '" + a.beta + "'");
    }
    const msmcl::ScatterScene scene = msmcl::load_scatter_scene(a.scene);
    const msmcl::io::GpuImage image = msmcl::io::read_ktx2(a.map);
    const bool six = image.format == msmcl::io::GpuFormat::a2b10g10r10_unorm_pack32 && image.array && image.layers == 2;
    const bool four = image.format == msmcl::io::GpuFormat::r16g16b16a16_unorm && !image.array &&
                      image.find_metadata("msmcl:format") == std::optional<std::string>("scatter4");
    if (!six && !four)
        throw msmcl::input_error(a.map + ": not a scattering map (msmcl scatter --map: 2 layers of "
                                         "a2b10g10r10_unorm_pack32, or r16g16b16a16_unorm with msmcl:format scatter4)");
    if (image.width != scene.rectified_width || image.height != scene.rectified_height)
        throw msmcl::input_error(a.map + ": " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                                 ", the scene's rectified map is " + std::to_string(scene.rectified_width) + "x" +
                                 std::to_string(scene.rectified_height));
    const msmcl::io::ExrImage depth_image = msmcl::io::read_exr(a.camera_depth);
    const msmcl::io::ExrChannel* depth = depth_image.find_channel("Z");
    if (!depth || depth->type == msmcl::io::SampleType::uint32 || depth_image.width != scene.camera.width ||
        depth_image.height != scene.camera.height)
        throw msmcl::input_error(a.camera_depth + ": no HALF or FLOAT channel Z of the camera's size");

    // Per pixel, on the host, the geometry of kernels/msm_scatter.clh: where the view ray
    // ends in the rectified map (texel units for the sampler), its rectified depth, the
    // blend of the bounds and the radiance of the unshadowed ray.
    const msmcl::RectificationBounds bounds = msmcl::rectification_bounds(scene);
    const msm_scatter_params p = msmcl::detail::make_scatter_params(scene, bounds, 1, 1, 1, beta);
    std::vector<RayRecord> rays(static_cast<std::size_t>(scene.camera.width) * scene.camera.height);
    for (int py = 0; py < scene.camera.height; ++py)
        for (int px = 0; px < scene.camera.width; ++px) {
            const std::size_t pixel = static_cast<std::size_t>(py) * scene.camera.width + px;
            const msm_view_ray ray = msm_scatter_view_ray(p, px, py);
            const float distance = msm_scatter_eye_depth(p, depth->values[pixel]) * ray.length_scale;
            const msm_scatter_lookup l = msm_scatter_lookup_at(p, ray, distance);
            rays[pixel] = {static_cast<float>(l.x0) + l.tx + 0.5f, static_cast<float>(l.y0) + l.ty + 0.5f, l.depth,
                           msm_scatter_beta(p, ray), msm_scatter_unshadowed(p, ray, distance)};
        }

    // Bilinear filtering, clamped along r; along phi the rows wrap around for a full circle.
    const VkFormat vk_format = vk_format_of(image);
    if (!vulkan.supports_sampling(vk_format, true))
        throw msmcl::error("the Vulkan device cannot filter " + std::string(msmcl::io::gpu_format_info(image.format).name) +
                           " images linearly");
    Image map = vulkan.upload_image(vk_format, image.width, image.height, image.layers, image.bytes);
    const VkSampler linear = vulkan.create_sampler(
        VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
        bounds.full_circle ? VK_SAMPLER_ADDRESS_MODE_REPEAT : VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
    std::vector<Binding> bindings;
    bind_texture(bindings, language, 0, map.view, linear);
    const ScatterPush push{image.width, image.height, static_cast<std::uint32_t>(rays.size())};
    static const std::vector<std::uint32_t> glsl[2] = {words(scatter4_glsl), words(scatter6_glsl)};
    static const std::vector<std::uint32_t> hlsl[2] = {words(scatter4_hlsl), words(scatter6_hlsl)};
    const std::vector<float> radiance = run_pass(vulkan, (language.hlsl ? hlsl : glsl)[six ? 1 : 0], language, bindings, linear,
                                                 rays.data(), rays.size() * sizeof(RayRecord), &push, sizeof push,
                                                 push.count);
    vulkan.destroy(map);
    msmcl::io::ExrImage out;
    out.width = scene.camera.width;
    out.height = scene.camera.height;
    out.channels = {{"Y", msmcl::io::SampleType::float32, radiance, {}}};
    out.attributes = {{"msmcl:scatterMethod", std::string(six ? "vulkan_prefiltered_6" : "vulkan_prefiltered_4")}};
    msmcl::io::write_exr(a.output, out);
}

// ---- compare: differences of two images of one channel, and a signed difference PNG.
struct CompareArguments {
    std::string a, b;
    std::string channel = "Y";
    std::string diff_png;
    std::string diff_scale = "0.05";
};

void run_compare(const CompareArguments& c) {
    const float scale = float_option("--diff-scale", c.diff_scale);
    if (!(scale > 0.0f)) throw usage_error("--diff-scale must be > 0");
    const msmcl::io::ExrImage a = msmcl::io::read_exr(c.a);
    const msmcl::io::ExrImage b = msmcl::io::read_exr(c.b);
    const msmcl::io::ExrChannel* ca = a.find_channel(c.channel);
    const msmcl::io::ExrChannel* cb = b.find_channel(c.channel);
    if (!ca || ca->type == msmcl::io::SampleType::uint32) throw msmcl::input_error(c.a + ": no float channel " + c.channel);
    if (!cb || cb->type == msmcl::io::SampleType::uint32) throw msmcl::input_error(c.b + ": no float channel " + c.channel);
    if (a.width != b.width || a.height != b.height)
        throw msmcl::input_error(c.b + ": " + std::to_string(b.width) + "x" + std::to_string(b.height) + ", " + c.a +
                                 " is " + std::to_string(a.width) + "x" + std::to_string(a.height));
    // Statistics of b - a. The PNG shows b - a in the colour map of every difference figure
    // (tools/signed_difference.hpp): red where b is larger, blue where smaller, white where
    // equal, full colour at --diff-scale, with the labelled colour bar below.
    double sum_squares = 0, largest = 0;
    std::size_t above_1e3 = 0, above_1e2 = 0, above_1e1 = 0;
    std::vector<double> difference(ca->values.size());
    for (std::size_t i = 0; i < ca->values.size(); ++i) {
        const double d = static_cast<double>(cb->values[i]) - ca->values[i];
        sum_squares += d * d;
        largest = std::max(largest, std::fabs(d));
        above_1e3 += std::fabs(d) > 1e-3;
        above_1e2 += std::fabs(d) > 1e-2;
        above_1e1 += std::fabs(d) > 1e-1;
        difference[i] = d;
    }
    const std::size_t n = ca->values.size();
    std::printf("%zu values: max |b - a| %.3g, rms %.3g, above 1e-3: %zu, above 1e-2: %zu, above 0.1: %zu\n", n,
                largest, n ? std::sqrt(sum_squares / n) : 0.0, above_1e3, above_1e2, above_1e1);
    if (!c.diff_png.empty())
        msmcl::tools::write_signed_difference_png(c.diff_png, a.width, a.height, difference, scale,
                                                  {"b smaller", "b larger"});
}

int report(const std::string& message, int code) {
    std::cerr << "msmcl-vulkan: " << message << '\n';
    return code;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"msmcl-vulkan: msmcl's KTX2 textures sampled by a headless Vulkan 1.2 compute consumer"};
    app.require_subcommand(1);
    // --hlsl and --device also after the subcommand's arguments.
    app.fallthrough();
    Language language;
    int device_index = -1;
    app.add_flag("--hlsl", language.hlsl, "run the HLSL route (shaders/msm.hlsl) instead of GLSL");
    app.add_option("--device", device_index, "Vulkan physical device index (default: the first with compute)");

    CLI::App* devices_command = app.add_subcommand("devices", "List Vulkan devices (exit 3 when there is none)");

    ShadeArguments shade;
    CLI::App* shade_command = app.add_subcommand("shade", "KTX2 shadow map + receivers EXR -> shadow EXR (Y)");
    shade_command->add_option("map", shade.map, "a shadow map KTX2 of any format (msmcl filter ... .ktx2)")
        ->required();
    shade_command->add_option("receivers", shade.receivers, "receivers EXR (U, V, Z; optional PX, PY)")->required();
    shade_command->add_option("output", shade.output, "shadow EXR to write")->required();
    shade_command->add_option("--lookup", shade.lookup, "nearest, bilinear, dither, or hardware (linear sampler)")
        ->capture_default_str();
    shade_command->add_option("--frame", shade.frame, "frame number of the dithered lookup")->capture_default_str();
    shade_command->add_option("--depth-bias", shade.depth_bias,
                              "subtracted from the internal depth (default: the format's, as msmcl shade)");
    shade_command->add_option("--depth-range", shade.depth_range, "0,1 or -1,1 (default: the map's)");
    shade_command->add_option("--min-variance", shade.min_variance,
                              "VSM, EVSM: least variance of the depth in [0,1] (default: the format's, as msmcl shade)");
    shade_command->add_option("--light-bleed-reduction", shade.light_bleed_reduction,
                              "VSM, EVSM: the bound rescaled from [R,1] to [0,1], R in [0,1) (default 0)");
    shade_command->add_option("--layer", shade.layer,
                              "texture arrays: shade layer L (channel Y), or all layers (default; channels layer<i>.Y)")
        ->type_name("L|all");
    shade_command->add_flag("--accurate", shade.accurate,
                            "moments128: shade in float-float (msm_lookup_moments128_accurate), as msmcl does");

    SoftArguments soft;
    CLI::App* soft_command = app.add_subcommand("soft", "SAT KTX2 + receivers EXR -> soft shadow EXR (Y)");
    soft_command->add_option("table", soft.table, "summed-area table KTX2 (msmcl sat ... .ktx2)")->required();
    soft_command->add_option("receivers", soft.receivers, "receivers EXR")->required();
    soft_command->add_option("output", soft.output, "shadow EXR to write")->required();
    soft_command->add_option("--light-size", soft.light_size, "penumbra texels per unit of depth")->required();
    soft_command->add_option("--search-size", soft.search_size, "blocker search side (0: floor(sqrt(N)))")
        ->capture_default_str();
    soft_command->add_option("--min-filter", soft.min_filter, "smallest filter side")->capture_default_str();
    soft_command->add_option("--receiver-weight", soft.receiver_weight, "as msmcl soft (0 = published)")
        ->capture_default_str();
    soft_command->add_option("--filter-parts", soft.filter_parts, "as msmcl soft (1 = published)")
        ->capture_default_str();
    soft_command->add_flag("--published", soft.published, "as msmcl soft: --receiver-weight 0 --filter-parts 1");
    soft_command->add_option("--depth-bias", soft.depth_bias, "subtracted from the internal depth")
        ->capture_default_str();
    soft_command->add_option("--depth-range", soft.depth_range, "0,1 or -1,1 (default: the table's)");

    ScatterArguments scatter;
    CLI::App* scatter_command =
        app.add_subcommand("scatter", "scene JSON + prefiltered map KTX2 + camera depth EXR -> radiance EXR (Y)");
    scatter_command->add_option("scene", scatter.scene, "scene JSON (msmcl scatter's)")->required();
    scatter_command->add_option("map", scatter.map, "prefiltered map KTX2 (msmcl scatter --map)")->required();
    scatter_command->add_option("camera_depth", scatter.camera_depth, "camera depth EXR (Z)")->required();
    scatter_command->add_option("output", scatter.output, "radiance EXR to write")->required();
    scatter_command->add_option("--beta", scatter.beta, "adaptive, or B in [0, 1]")->capture_default_str();

    CompareArguments compare;
    CLI::App* compare_command = app.add_subcommand("compare", "Difference statistics of two EXR images (b - a)");
    compare_command->add_option("a", compare.a, "first EXR")->required();
    compare_command->add_option("b", compare.b, "second EXR")->required();
    compare_command->add_option("--channel", compare.channel, "channel to compare")->capture_default_str();
    compare_command->add_option("--diff-png", compare.diff_png, "signed difference PNG (red: b larger, blue: smaller)");
    compare_command->add_option("--diff-scale", compare.diff_scale, "difference shown at full colour")
        ->capture_default_str();

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        return report(e.what(), exit_bad_input);
    }

    try {
        if (compare_command->parsed()) {
            run_compare(compare);
            return 0;
        }
        if (devices_command->parsed()) {
            const std::vector<std::string> names = VulkanCompute::device_names();
            if (names.empty()) return report("no Vulkan device", exit_no_device);
            for (std::size_t i = 0; i < names.size(); ++i) std::cout << i << "  " << names[i] << '\n';
            return 0;
        }
        VulkanCompute vulkan(device_index);
        if (shade_command->parsed()) run_shade(vulkan, language, shade);
        else if (soft_command->parsed()) run_soft(vulkan, language, soft);
        else if (scatter_command->parsed()) run_scatter(vulkan, language, scatter);
        return 0;
    } catch (const usage_error& e) {
        return report(e.what(), exit_bad_input);
    } catch (const msmcl::input_error& e) {
        return report(e.what(), exit_bad_input);
    } catch (const NoVulkanDevice& e) {
        return report(e.what(), exit_no_device);
    } catch (const std::exception& e) {
        return report(e.what(), exit_runtime_failure);
    }
}
