#include "cli/soft_command.hpp"
#include "cli/option_values.hpp"
#include "cli/stages.hpp"
#include "cli/texture_files.hpp"

#include "io/exr_io.hpp"
#include "io/sat_exr.hpp"

#include <msmcl/sat.hpp>

#include <memory>
#include <optional>

namespace msmcl::cli {
namespace {

void run_soft(const GlobalArguments& global, const SoftArguments& arguments) {
    // Check the option values before touching any file.
    SoftShadowOptions options;
    options.light_size = parse_finite_float("--light-size", arguments.light_size);
    if (options.light_size < 0.0f) throw usage_error("--light-size must be >= 0, got '" + arguments.light_size + "'");
    options.search_size = static_cast<int>(parse_integer("--search-size", arguments.search_size, 0, 46340));
    options.min_filter_size = parse_finite_float("--min-filter", arguments.min_filter);
    if (options.min_filter_size <= 0.0f)
        throw usage_error("--min-filter must be > 0, got '" + arguments.min_filter + "'");
    options.depth_bias = parse_finite_float("--depth-bias", arguments.depth_bias);
    options.receiver_blocker_weight = parse_finite_float("--receiver-weight", arguments.receiver_weight);
    if (options.receiver_blocker_weight < 0.0f || options.receiver_blocker_weight > 1.0f)
        throw usage_error("--receiver-weight must be in [0, 1], got '" + arguments.receiver_weight + "'");
    options.filter_parts = static_cast<int>(parse_integer("--filter-parts", arguments.filter_parts, 1, 4));
    if (arguments.published) {
        options.receiver_blocker_weight = 0.0f;
        options.filter_parts = 1;
    }
    std::optional<DepthRange> range;
    if (!arguments.depth_range.empty()) range = parse_depth_range_option(arguments.depth_range);
    std::optional<std::uint32_t> max_kernel;
    if (!arguments.max_kernel.empty())
        max_kernel = static_cast<std::uint32_t>(
            parse_integer("--max-kernel", arguments.max_kernel, sat_min_kernel_texels, sat_max_kernel_texels));
    require_exr_output(arguments.output);

    // Read the table (EXR, KTX2 or DDS) and the receivers; limits that depend on the table's
    // N are checked here.
    Stages stages(global.verbose, global.verbose ? 8 : 5);
    const io::SatFile table = stages.run("read table", [&] { return read_sat_file(arguments.table, max_kernel); });
    const io::ReceiverGrid receivers =
        stages.run("read receivers", [&] { return io::read_receivers_exr(arguments.receivers); });
    options.depth_range = range.value_or(table.info.depth_range);
    try {
        soft_shadow_limits(table.table.max_kernel_texels, options);
    } catch (const input_error& e) {
        throw usage_error(std::string(e.what()) + " (" + arguments.table + " has N = " +
                          std::to_string(table.table.max_kernel_texels) + ")");
    }

    // Shade on the device.
    Context context = stages.run("device setup", [&] { return Context(global.selection()); });
    std::vector<float> intensity;
    try {
        intensity = stages.run_call("soft shadows", [&](const StageObserver& on_stage) {
            options.on_stage = on_stage;
            return soft_shade(context, table.table, receivers.points, options);
        });
    } catch (const input_error& e) {
        rethrow_with_file(arguments.receivers, e);
    }
    stages.run("write",
               [&] { io::write_intensity_exr(arguments.output, receivers.width, receivers.height, intensity); });
}

} // namespace

Subcommand add_soft_command(CLI::App& app) {
    const auto parsed = std::make_shared<SoftArguments>();
    SoftArguments& soft = *parsed;
    // msmcl soft SAT.exr RECEIVERS.exr OUT.exr --light-size L [--search-size K] ...
    CLI::App* soft_command = app.add_subcommand(
        "soft", "Summed-area table + receivers (EXR U,V,Z) -> soft shadow intensity (EXR Y), directional light");
    soft_command->add_option("table", soft.table, "table written by msmcl sat (EXR, KTX2 or DDS)")->required();
    soft_command->add_option("receivers", soft.receivers, "receivers EXR (FLOAT U, V in texels, Z depth)")->required();
    soft_command->add_option("output", soft.output, "intensity EXR to write (channel Y)")->required();
    soft_command->add_option("--light-size", soft.light_size,
                             "penumbra width in texels per unit of internal depth between receiver and blocker")
        ->required()
        ->type_name("L");
    soft_command->add_option("--search-size", soft.search_size,
                             "side of the blocker search square in texels, K^2 <= N (0 = floor(sqrt(N)))")
        ->capture_default_str()
        ->type_name("K");
    soft_command->add_option("--min-filter", soft.min_filter, "smallest filter side in texels")
        ->capture_default_str()
        ->type_name("FLOAT");
    soft_command->add_option("--depth-bias", soft.depth_bias, "subtracted from the receiver's internal depth")
        ->capture_default_str()
        ->type_name("FLOAT");
    soft_command->add_option("--depth-range", soft.depth_range,
                             "depth convention of the receivers: 0,1 or -1,1 (default: the table's)")
        ->type_name("RANGE");
    soft_command->add_option("--max-kernel", soft.max_kernel,
                             "N the table was built for (default: the table's; required for DDS tables)")
        ->type_name("N");
    CLI::Option* receiver_weight = soft_command->add_option("--receiver-weight", soft.receiver_weight,
                             "share of the receiver's own surface the blocker search counts as blockers at its "
                             "depth, in [0, 1] (0 = published; docs/soft_shadows.md)")
        ->capture_default_str()
        ->type_name("K");
    CLI::Option* filter_parts = soft_command->add_option("--filter-parts", soft.filter_parts,
                             "filter square split into P x P parts, each its own 4MSM bound, P in [1, 4] "
                             "(1 = published)")
        ->capture_default_str()
        ->type_name("P");
    soft_command->add_flag("--published", soft.published,
                           "the method of Peters et al., i3D 2016 as published: --receiver-weight 0 --filter-parts 1")
        ->excludes(receiver_weight)
        ->excludes(filter_parts);
    return {soft_command, [parsed](const GlobalArguments& global) {
                run_soft(global, *parsed);
                return 0;
            }};
}

} // namespace msmcl::cli
