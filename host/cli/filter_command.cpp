#include "cli/filter_command.hpp"
#include "cli/batch.hpp"
#include "cli/option_values.hpp"
#include "cli/texture_files.hpp"

#include "io/exr_io.hpp"

#include <msmcl/filter.hpp>

#include <memory>
#include <optional>

namespace msmcl::cli {
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

/// One file or a batch; returns the exit code (host/cli/batch.hpp).
int run_filter(const GlobalArguments& global, const FilterArguments& arguments, const BatchArguments& batch) {
    MapCommand command;
    command.name = "filter";
    command.manifest_keys = {"format", "sigma", "depth-range", "kernel", "out-container", "exponents", "exponent"};
    command.out_container = arguments.out_container;
    command.make_job = [&](const BatchEntry& entry) { return filter_job(arguments, entry); };
    return run_map_command(global, batch, command);
}

} // namespace

Subcommand add_filter_command(CLI::App& app) {
    // What the command line gives: the options below, and the files of one map or a batch.
    struct Parsed {
        FilterArguments filter;
        BatchArguments batch;
    };
    const auto parsed = std::make_shared<Parsed>();
    FilterArguments& filter = parsed->filter;
    CLI::App* filter_command =
        app.add_subcommand("filter", "Depth map (EXR, Z or sample<N>.Z) -> filtered moment shadow map (EXR, KTX2 or DDS)");
    // IN OUT: a depth map EXR (optional translucent layers layer<k>.Z, layer<k>.A) and the
    // texture to write (EXR; .ktx2 or .dds: KTX2 or DDS); or a batch: IN... -o DIR, --list FILE.
    BatchArguments& filter_batch = parsed->batch;
    msmcl::cli::add_batch_options(*filter_command, filter_batch);
    filter_command->add_option("--format", filter.format,
                               "moments128, msm64, nlq64, nlq32, vsm32, vsm64, evsm2_32, evsm4_64, evsm4_128 or "
                               "esm32 (required; docs/formats.md)")
        ->type_name("FORMAT");
    filter_command->add_option("--exponents", filter.exponents,
                               "EVSM formats: the warp exponents c+ or c+,c- (default: the largest safe for the "
                               "storage, docs/formats.md)")
        ->type_name("C+,C-");
    filter_command->add_option("--exponent", filter.exponent,
                               "esm32: the warp exponent c (default 80, at most 88)")
        ->type_name("C");
    filter_command->add_option("--sigma", filter.sigma, "Gaussian sigma in texels, >= 0 (0 = no blur)")
        ->capture_default_str()
        ->type_name("FLOAT");
    filter_command->add_option("--depth-range", filter.depth_range, "depth convention of the input: 0,1 or -1,1")
        ->capture_default_str()
        ->type_name("RANGE");
    filter_command->add_option("--kernel", filter.kernel,
                               "automatic (by the device's type), fused_paper (the paper's GPU kernel), "
                               "fused_cpu (the CPU distribution) or three_pass (the baseline); all give the same "
                               "texture up to the nlq formats' per-block shift")
        ->capture_default_str()
        ->type_name("KERNEL");
    filter_command->add_option("--out-container", filter.out_container,
                               "exr, ktx2 or dds (default: from the output's extension, else exr)")
        ->type_name("CONTAINER");
    return {filter_command,
            [parsed](const GlobalArguments& global) { return run_filter(global, parsed->filter, parsed->batch); },
            true};
}

} // namespace msmcl::cli
