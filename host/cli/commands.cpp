#include "cli/commands.hpp"

#include "io/exr_io.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/shade.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace msmcl::cli {
namespace {

/// The whole of `text` as a finite float, else usage_error naming the option.
float parse_finite_float(const std::string& option, const std::string& text) {
    char* end = nullptr;
    errno = 0;
    const float value = std::strtof(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(value))
        throw usage_error(option + " must be a finite number, got '" + text + "'");
    return value;
}

DepthRange parse_depth_range_option(const std::string& text) {
    const std::optional<DepthRange> range = parse_depth_range(text);
    if (!range) throw usage_error("--depth-range must be 0,1 or -1,1, got '" + text + "'");
    return *range;
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

    // Read and validate the depth map.
    const DepthImage depth = io::read_depth_exr(arguments.input, range);

    // Filter on the device.
    Context context(global.selection());
    FilterOptions options;
    options.format = *format;
    options.sigma = sigma;
    options.depth_range = range;
    Texture texture;
    try {
        texture = filter(context, depth, options);
    } catch (const input_error& e) {
        rethrow_with_file(arguments.input, e);
    }

    // Publish the texture with what it was made from.
    io::write_texture_exr(arguments.output, texture, io::TextureInfo{sigma, depth.samples, range});
}

void run_shade(const GlobalArguments& global, const ShadeArguments& arguments) {
    // Check the option values before touching any file.
    ShadeOptions options;
    if (arguments.lookup == "dither")
        throw usage_error("--lookup dither is not supported yet (use nearest or bilinear)");
    const std::optional<Lookup> lookup = parse_lookup(arguments.lookup);
    if (!lookup || (*lookup != Lookup::nearest && *lookup != Lookup::bilinear))
        throw usage_error("unknown --lookup '" + arguments.lookup + "' (expected nearest or bilinear)");
    options.lookup = *lookup;
    options.depth_bias = parse_finite_float("--depth-bias", arguments.depth_bias);
    std::optional<DepthRange> range;
    if (!arguments.depth_range.empty()) range = parse_depth_range_option(arguments.depth_range);

    // Read the map and the receivers; the receivers' depth follows the map's convention
    // unless --depth-range says otherwise.
    const io::TextureFile map = io::read_texture_exr(arguments.map);
    const io::ReceiverGrid receivers = io::read_receivers_exr(arguments.receivers);
    options.depth_range = range.value_or(map.info.depth_range);

    // Shade on the device.
    Context context(global.selection());
    std::vector<float> intensity;
    try {
        intensity = shade(context, map.texture, receivers.points, options);
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
