#include "cli/commands.hpp"
#include "cli/file_checks.hpp"
#include "cli/batch.hpp"
#include "cli/option_values.hpp"
#include "cli/stages.hpp"
#include "cli/texture_files.hpp"

#include "io/exr_io.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/shade.hpp>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>

namespace msmcl::cli {
namespace {

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

namespace {

/// One file of `msmcl filter`: the command line's options, overridden by the manifest's.
MapJob filter_job(const FilterArguments& arguments, const BatchEntry& entry) {
    // Check the option values before touching any file.
    const std::string format_text = entry_option(entry, "format", arguments.format);
    if (format_text.empty()) throw usage_error("--format is required");
    const std::optional<Format> format = parse_format(format_text);
    if (!format) throw usage_error(unknown_value_message("--format", format_text, format_names()));
    const WarpExponents exponents = parse_exponent_options(*format, entry_option(entry, "exponents", arguments.exponents),
                                                           entry_option(entry, "exponent", arguments.exponent));
    const std::string sigma_text = entry_option(entry, "sigma", arguments.sigma);
    const float sigma = parse_finite_float("--sigma", sigma_text);
    if (sigma < 0.0f) throw usage_error("--sigma must be >= 0, got '" + sigma_text + "'");
    const DepthRange range = parse_depth_range_option(entry_option(entry, "depth-range", arguments.depth_range));
    const Container container =
        output_container(entry_option(entry, "out-container", arguments.out_container), entry.output);
    const std::string kernel_text = entry_option(entry, "kernel", arguments.kernel);
    const std::optional<FilterKernel> kernel = parse_filter_kernel(kernel_text);
    if (!kernel)
        throw usage_error(
            unknown_value_message("--kernel", kernel_text, {"automatic", "fused_paper", "fused_cpu", "three_pass"}));

    FilterOptions options;
    options.format = *format;
    options.sigma = sigma;
    options.depth_range = range;
    options.kernel = *kernel;
    options.exponents = exponents;
    // A DDS file keeps no record of the exponents: its readers assume the defaults.
    if (container == Container::dds && exponents != default_exponents(*format))
        throw usage_error(entry.output + ": a DDS file keeps no record of the exponents and is read with the " +
                          "defaults; write .ktx2 or .exr for other exponents");
    // Filter on the device, then publish the texture with what it was made from (DDS has
    // no place for the record).
    return map_job(
        entry, range, "filter",
        [options](Context& context, const io::TranslucentDepth& layered, const StageObserver& on_stage) {
            FilterOptions timed = options;
            timed.on_stage = on_stage;
            return filter(context, layered.depth, layered.layers, timed);
        },
        [options, container, output = entry.output, array = entry.array](const Texture& texture, int samples) {
            write_texture_file(output, container, texture, io::TextureInfo{options.sigma, samples, options.depth_range},
                               array);
        });
}

} // namespace

int run_filter(const GlobalArguments& global, const FilterArguments& arguments, const BatchArguments& batch) {
    MapCommand command;
    command.name = "filter";
    command.manifest_keys = {"format", "sigma", "depth-range", "kernel", "out-container", "exponents", "exponent"};
    command.out_container = arguments.out_container;
    command.make_job = [&](const BatchEntry& entry) { return filter_job(arguments, entry); };
    return run_map_command(global, batch, command);
}

namespace {

/// A shading option that is a number in [lowest, highest] (`open_top`: below highest), else
/// usage_error naming the option.
float parse_ranged_float(const std::string& option, const std::string& text, float lowest, float highest,
                         bool open_top) {
    const float value = parse_finite_float(option, text);
    if (value < lowest || value > highest || (open_top && value == highest))
        throw usage_error(option + " must be in [" + float_text(lowest) + ", " + float_text(highest) +
                          (open_top ? ")" : "]") + ", got '" + text + "'");
    return value;
}

/// The shading options of a map of `format`: the format's defaults where the command line
/// leaves them; an option the format's shading has no use for is refused, naming the map.
ShadeOptions shade_options_for(Format format, const ShadeArguments& arguments, std::optional<Lookup> lookup,
                               std::optional<float> min_variance, std::optional<float> light_bleed_reduction) {
    ShadeOptions options = shade_defaults(format);
    if (lookup) options.lookup = *lookup;
    if (!arguments.depth_bias.empty()) options.depth_bias = parse_finite_float("--depth-bias", arguments.depth_bias);
    const bool variance_bound = options.min_variance.has_value();
    for (const auto& [option, given] : {std::make_pair("--min-variance", min_variance.has_value()),
                                        std::make_pair("--light-bleed-reduction", light_bleed_reduction.has_value())})
        if (given && !variance_bound)
            throw input_error(arguments.map + ": " + option + " is for VSM and EVSM maps, not " + format_name(format));
    if (min_variance) options.min_variance = *min_variance;
    if (light_bleed_reduction) options.light_bleed_reduction = *light_bleed_reduction;
    return options;
}

} // namespace

void run_shade(const GlobalArguments& global, const ShadeArguments& arguments) {
    // Check the option values before touching any file.
    std::optional<Lookup> lookup;
    if (!arguments.lookup.empty()) {
        lookup = parse_lookup(arguments.lookup);
        if (!lookup)
            throw usage_error(unknown_value_message("--lookup", arguments.lookup, {"nearest", "bilinear", "dither"}));
    }
    if (!arguments.depth_bias.empty()) parse_finite_float("--depth-bias", arguments.depth_bias);
    std::optional<float> min_variance, light_bleed_reduction;
    if (!arguments.min_variance.empty())
        min_variance = parse_ranged_float("--min-variance", arguments.min_variance, 0.0f, 0.25f, false);
    if (!arguments.light_bleed_reduction.empty())
        light_bleed_reduction =
            parse_ranged_float("--light-bleed-reduction", arguments.light_bleed_reduction, 0.0f, 1.0f, true);
    const std::uint32_t frame = parse_frame(arguments.frame);
    std::optional<DepthRange> range;
    if (!arguments.depth_range.empty()) range = parse_depth_range_option(arguments.depth_range);
    std::optional<Format> format;
    if (!arguments.format.empty()) {
        format = parse_format(arguments.format);
        if (!format)
            throw usage_error(unknown_value_message("--format", arguments.format, format_names()));
        // A shading option the named format has no use for: refused before any file is read.
        shade_options_for(*format, arguments, lookup, min_variance, light_bleed_reduction);
    }
    require_exr_output(arguments.output);
    // The output is no spelling of an input, and can be written, before any work.
    check_distinct_files({{arguments.map, NamedFile::Role::input},
                          {arguments.receivers, NamedFile::Role::input},
                          {arguments.output, NamedFile::Role::output}});
    check_output_path(arguments.output, false);
    Stages stages(global.verbose, global.verbose ? 7 : 4);

    // Read the map (EXR, KTX2 or DDS) and the receivers; the receivers' depth follows the
    // map's convention unless --depth-range says otherwise.
    const io::TextureFile map = stages.run("read map", [&] { return read_texture_file(arguments.map, format); });
    const io::ReceiverGrid receivers =
        stages.run("read receivers", [&] { return io::read_receivers_exr(arguments.receivers); });
    ShadeOptions options = shade_options_for(map.texture.format, arguments, lookup, min_variance, light_bleed_reduction);
    options.frame = frame;
    options.depth_range = range.value_or(map.info.depth_range);
    // Screen pixels for dither: the PX, PY channels, else the receivers' own grid.
    options.screen_width = static_cast<std::uint32_t>(receivers.width);

    // Shade on the device.
    Context context = stages.run("device setup", [&] { return Context(global.selection()); });
    std::vector<float> intensity;
    try {
        intensity = stages.run_call("shade", [&](const StageObserver& on_stage) {
            options.on_stage = on_stage;
            return shade(context, map.texture, receivers.points, receivers.pixels, options);
        });
    } catch (const input_error& e) {
        rethrow_with_file(arguments.receivers, e);
    }

    // One intensity per receiver, on the receivers' grid.
    stages.run("write",
               [&] { io::write_intensity_exr(arguments.output, receivers.width, receivers.height, intensity); });
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
