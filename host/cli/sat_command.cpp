#include "cli/sat_command.hpp"
#include "cli/batch.hpp"
#include "cli/option_values.hpp"
#include "cli/texture_files.hpp"

#include "io/sat_exr.hpp"

#include <msmcl/sat.hpp>

#include <memory>

namespace msmcl::cli {
namespace {

/// One file of `msmcl sat`: the command line's options, overridden by the manifest's.
MapJob sat_job(const SatArguments& arguments, const BatchEntry& entry) {
    // Check the option values before touching any file.
    SatOptions options;
    options.max_kernel_texels = static_cast<std::uint32_t>(parse_integer(
        "--max-kernel", entry_option(entry, "max-kernel", arguments.max_kernel), sat_min_kernel_texels,
        sat_max_kernel_texels));
    options.depth_range = parse_depth_range_option(entry_option(entry, "depth-range", arguments.depth_range));
    const Container container =
        output_container(entry_option(entry, "out-container", arguments.out_container), entry.output);
    const std::string kernel_text = entry_option(entry, "kernel", arguments.kernel);
    const std::optional<SatKernel> kernel = parse_sat_kernel(kernel_text);
    if (!kernel)
        throw usage_error(
            unknown_value_message("--kernel", kernel_text, {"automatic", "tiled_gpu", "tiled_cpu", "row_per_thread"}));
    options.kernel = *kernel;
    // Build the table on the device, then publish it with what a reader needs to query it.
    return map_job(
        entry, options.depth_range, "table build",
        [options](Context& context, const io::TranslucentDepth& layered, const StageObserver& on_stage) {
            SatOptions timed = options;
            timed.on_stage = on_stage;
            return build_sat(context, layered.depth, layered.layers, timed);
        },
        [options, container, output = entry.output, array = entry.array](const SatTable& table, int samples) {
            write_sat_file(output, container, table, io::SatInfo{options.depth_range, samples}, array);
        });
}

/// One file or a batch; returns the exit code (host/cli/batch.hpp).
int run_sat(const GlobalArguments& global, const SatArguments& arguments, const BatchArguments& batch) {
    MapCommand command;
    command.name = "sat";
    command.manifest_keys = {"max-kernel", "depth-range", "kernel", "out-container"};
    command.out_container = arguments.out_container;
    command.make_job = [&](const BatchEntry& entry) { return sat_job(arguments, entry); };
    return run_map_command(global, batch, command);
}

} // namespace

Subcommand add_sat_command(CLI::App& app) {
    // What the command line gives: the options below, and the files of one map or a batch.
    struct Parsed {
        SatArguments sat;
        BatchArguments batch;
    };
    const auto parsed = std::make_shared<Parsed>();
    SatArguments& sat = parsed->sat;
    // msmcl sat IN.exr OUT.exr [--max-kernel N] [--depth-range R] [--kernel K]
    CLI::App* sat_command = app.add_subcommand(
        "sat", "Depth map (EXR) -> integer modular summed-area table of its moments (EXR, KTX2 or DDS)");
    // IN OUT (depth map EXR, table .exr, .ktx2 or .dds), or a batch: IN... -o DIR, --list FILE.
    add_batch_options(*sat_command, parsed->batch);
    sat_command->add_option("--max-kernel", sat.max_kernel,
                            "N: texels of the largest rectangle ever queried (precision log2(2^32/N) bits)")
        ->capture_default_str()
        ->type_name("N");
    sat_command->add_option("--depth-range", sat.depth_range, "depth convention of the input: 0,1 or -1,1")
        ->capture_default_str()
        ->type_name("RANGE");
    sat_command->add_option("--kernel", sat.kernel,
                            "automatic (by the device's type), tiled_gpu (32x32 tiles in local memory), tiled_cpu "
                            "(bands of 32 rows, one work-item each) or row_per_thread (the papers' baseline); all "
                            "give the same table")
        ->capture_default_str()
        ->type_name("KERNEL");
    sat_command->add_option("--out-container", sat.out_container,
                            "exr, ktx2 or dds (default: from the output's extension)")
        ->type_name("CONTAINER");
    return {sat_command, [parsed](const GlobalArguments& global) { return run_sat(global, parsed->sat, parsed->batch); },
            true};
}

} // namespace msmcl::cli
