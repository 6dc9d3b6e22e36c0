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

void run_shade(const GlobalArguments& global, const ShadeArguments& arguments) {
    // Check the option values before touching any file.
    ShadeOptions options;
    const std::optional<Lookup> lookup = parse_lookup(arguments.lookup);
    if (!lookup) throw usage_error(unknown_value_message("--lookup", arguments.lookup, {"nearest", "bilinear", "dither"}));
    options.lookup = *lookup;
    options.depth_bias = parse_finite_float("--depth-bias", arguments.depth_bias);
    options.frame = parse_frame(arguments.frame);
    std::optional<DepthRange> range;
    if (!arguments.depth_range.empty()) range = parse_depth_range_option(arguments.depth_range);
    std::optional<Format> format;
    if (!arguments.format.empty()) {
        format = parse_format(arguments.format);
        if (!format)
            throw usage_error(unknown_value_message("--format", arguments.format, {"moments128", "msm64", "nlq64", "nlq32"}));
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
    shade_command->add_option("--lookup", shade.lookup, "nearest, bilinear or dither (blue noise, one texel)")
        ->capture_default_str()
        ->type_name("LOOKUP");
    shade_command->add_option("--frame", shade.frame, "dither: frame number (picks the blue-noise texture and shift)")
        ->capture_default_str()
        ->type_name("N");
    shade_command->add_option("--depth-bias", shade.depth_bias, "subtracted from the receiver's internal depth")
        ->capture_default_str()
        ->type_name("FLOAT");
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
