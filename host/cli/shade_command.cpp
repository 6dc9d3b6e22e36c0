#include "cli/shade_command.hpp"
#include "cli/file_checks.hpp"
#include "cli/option_values.hpp"
#include "cli/stages.hpp"
#include "cli/texture_files.hpp"

#include "io/exr_io.hpp"

#include <msmcl/shade.hpp>

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <memory>
#include <optional>

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

} // namespace

Subcommand add_shade_command(CLI::App& app) {
    const auto parsed = std::make_shared<ShadeArguments>();
    ShadeArguments& shade = *parsed;
    CLI::App* shade_command =
        app.add_subcommand("shade", "Filtered map + receivers (EXR U,V,Z) -> shadow intensity (EXR Y)");
    shade_command->add_option("map", shade.map, "texture written by msmcl filter (EXR, KTX2 or DDS)")->required();
    shade_command->add_option("receivers", shade.receivers,
                              "receivers EXR (FLOAT U, V in texels, Z depth; optional PX, PY screen pixels)")
        ->required();
    shade_command->add_option("output", shade.output, "intensity EXR to write (channel Y)")->required();
    shade_command->add_option("--lookup", shade.lookup,
                              "nearest, bilinear or dither (blue noise, one texel); default: the format's (bilinear)")
        ->type_name("LOOKUP");
    shade_command->add_option("--frame", shade.frame, "dither: frame number (picks the blue-noise texture and shift)")
        ->capture_default_str()
        ->type_name("N");
    shade_command->add_option("--depth-bias", shade.depth_bias,
                              "subtracted from the receiver's internal depth; default: the format's (1e-3)")
        ->type_name("FLOAT");
    shade_command->add_option("--min-variance", shade.min_variance,
                              "VSM and EVSM maps: least variance of the depth in [0,1] for Chebyshev's bound, "
                              "in [0, 0.25]; default: the format's (docs/formats.md)")
        ->type_name("V");
    shade_command->add_option("--light-bleed-reduction", shade.light_bleed_reduction,
                              "VSM and EVSM maps: rescale the bound from [R,1] to [0,1], R in [0,1); default 0")
        ->type_name("R");
    shade_command->add_option("--depth-range", shade.depth_range,
                              "depth convention of the receivers: 0,1 or -1,1 (default: the map's)")
        ->type_name("RANGE");
    shade_command->add_option("--format", shade.format,
                              "the map's format (default: the file's; required for DDS msm64/nlq64 maps)")
        ->type_name("FORMAT");
    return {shade_command, [parsed](const GlobalArguments& global) {
                run_shade(global, *parsed);
                return 0;
            }};
}

} // namespace msmcl::cli
