#include "cli/commands.hpp"
#include "cli/option_values.hpp"

#include "io/dds.hpp"
#include "io/exr_io.hpp"
#include "io/gpu_image.hpp"
#include "io/ktx2.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/shade.hpp>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace msmcl::cli {
namespace {

enum class Container { exr, ktx2, dds };

/// --out-container, else the output's extension (.ktx2, .dds; anything else is EXR).
Container parse_container_option(const std::string& text, const std::string& output) {
    if (text.empty()) {
        const auto ends_with = [&](const char* suffix) {
            const std::string tail(suffix);
            if (output.size() < tail.size()) return false;
            std::string end = output.substr(output.size() - tail.size());
            for (char& c : end) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
            return end == tail;
        };
        return ends_with(".ktx2") ? Container::ktx2 : ends_with(".dds") ? Container::dds : Container::exr;
    }
    if (text == "exr") return Container::exr;
    if (text == "ktx2") return Container::ktx2;
    if (text == "dds") return Container::dds;
    throw usage_error("unknown --out-container '" + text + "' (expected exr, ktx2 or dds)");
}

/// A float as the shortest text that reads back to it.
std::string float_text(float value) {
    char text[32];
    for (int digits = 6; digits <= 9; ++digits) {
        std::snprintf(text, sizeof text, "%.*g", digits, static_cast<double>(value));
        if (std::strtof(text, nullptr) == value) break;
    }
    return text;
}

/// --frame: a whole number in [0, 2^32 - 1].
std::uint32_t parse_frame(const std::string& text) {
    char* end = nullptr;
    errno = 0;
    const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
    if (text.empty() || !std::isdigit(static_cast<unsigned char>(text[0])) || end != text.c_str() + text.size() ||
        errno == ERANGE || value > 0xffffffffull)
        throw usage_error("--frame must be a whole number in [0, 4294967295], got '" + text + "'");
    return static_cast<std::uint32_t>(value);
}

/// Library input errors do not know the file; put it in front.
[[noreturn]] void rethrow_with_file(const std::string& path, const input_error& e) {
    throw input_error(path + ": " + e.what());
}

} // namespace

DeviceSelection GlobalArguments::selection() const {
    DeviceSelection selection;
    selection.device = device;
    // A --device that matches nothing is an error, not a silent fallback.
    selection.strict = !device.empty();
    return selection;
}

void run_filter(const GlobalArguments& global, const FilterArguments& arguments) {
    // Check the option values before touching any file.
    const std::optional<Format> format = parse_format(arguments.format);
    if (!format)
        throw usage_error("unknown --format '" + arguments.format + "' (expected moments128, msm64, nlq64 or nlq32)");
    const float sigma = parse_finite_float("--sigma", arguments.sigma);
    if (sigma < 0.0f) throw usage_error("--sigma must be >= 0, got '" + arguments.sigma + "'");
    const DepthRange range = parse_depth_range_option(arguments.depth_range);
    const Container container = parse_container_option(arguments.out_container, arguments.output);
    const std::optional<FilterKernel> kernel = parse_filter_kernel(arguments.kernel);
    if (!kernel)
        throw usage_error("unknown --kernel '" + arguments.kernel +
                          "' (expected automatic, fused_paper, fused_cpu or three_pass)");

    // Read and validate the depth map and its translucent layers (layer<k>.Z, layer<k>.A).
    const io::TranslucentDepth layered = io::read_translucent_depth_exr(arguments.input, range);
    const DepthImage& depth = layered.depth;

    // Filter on the device.
    Context context(global.selection());
    FilterOptions options;
    options.format = *format;
    options.sigma = sigma;
    options.depth_range = range;
    options.kernel = *kernel;
    Texture texture;
    try {
        texture = filter(context, depth, layered.layers, options);
    } catch (const input_error& e) {
        rethrow_with_file(arguments.input, e);
    }

    // Publish the texture with what it was made from (DDS has no place for the record).
    if (container == Container::exr) {
        io::write_texture_exr(arguments.output, texture, io::TextureInfo{sigma, depth.samples, range});
        return;
    }
    const io::GpuImage image = io::gpu_image_of(texture, {{"msmcl:sigma", float_text(sigma)},
                                                          {"msmcl:samples", std::to_string(depth.samples)},
                                                          {"msmcl:depthRange", depth_range_name(range)}});
    if (container == Container::ktx2)
        io::write_ktx2(arguments.output, image);
    else
        io::write_dds(arguments.output, image);
}

void run_shade(const GlobalArguments& global, const ShadeArguments& arguments) {
    // Check the option values before touching any file.
    ShadeOptions options;
    const std::optional<Lookup> lookup = parse_lookup(arguments.lookup);
    if (!lookup) throw usage_error("unknown --lookup '" + arguments.lookup + "' (expected nearest, bilinear or dither)");
    options.lookup = *lookup;
    options.depth_bias = parse_finite_float("--depth-bias", arguments.depth_bias);
    options.frame = parse_frame(arguments.frame);
    std::optional<DepthRange> range;
    if (!arguments.depth_range.empty()) range = parse_depth_range_option(arguments.depth_range);

    // Read the map and the receivers; the receivers' depth follows the map's convention
    // unless --depth-range says otherwise.
    const io::TextureFile map = io::read_texture_exr(arguments.map);
    const io::ReceiverGrid receivers = io::read_receivers_exr(arguments.receivers);
    options.depth_range = range.value_or(map.info.depth_range);
    // Screen pixels for dither: the PX, PY channels, else the receivers' own grid.
    options.screen_width = static_cast<std::uint32_t>(receivers.width);

    // Shade on the device.
    Context context(global.selection());
    std::vector<float> intensity;
    try {
        intensity = shade(context, map.texture, receivers.points, receivers.pixels, options);
    } catch (const input_error& e) {
        rethrow_with_file(arguments.receivers, e);
    }

    // One intensity per receiver, on the receivers' grid.
    io::write_intensity_exr(arguments.output, receivers.width, receivers.height, intensity);
}

void run_devices(const GlobalArguments& global) {
    const std::vector<DeviceInfo> devices = list_devices();
    if (devices.empty()) throw device_error("no OpenCL device found (is an ICD such as pocl-opencl-icd installed?)");

    // The device a Context would pick with these options and the environment.
    const Context context(global.selection());
    const DeviceInfo& picked = context.device();
    const char* mark = global.device.empty() ? "  [default]" : "  [selected]";

    for (const DeviceInfo& device : devices) {
        const char* type = device.is_gpu ? "GPU" : device.is_cpu ? "CPU" : "other";
        const bool is_picked =
            device.platform_index == picked.platform_index && device.device_index == picked.device_index;
        std::cout << device.platform_index << ':' << device.device_index << "  " << device.name << "  (" << type
                  << ", driver " << device.driver_version << ", platform " << device.platform_name << ")"
                  << (is_picked ? mark : "") << '\n';
    }
    std::cout.flush();
}

} // namespace msmcl::cli
