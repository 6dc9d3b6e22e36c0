// msmcl: filter depth maps into moment shadow maps and shade receivers with them.
// Exit codes: 0 success, 2 bad input or usage, 1 device or runtime failure.
// Every failure prints exactly one line on stderr: "msmcl: [<file>: ]<problem>" (a batch and
// `info` one per bad file). A bare `msmcl` prints the usage and the commands (exit 2).
#include "cli/batch.hpp"
#include "cli/commands.hpp"
#include "cli/environment.hpp"
#include "cli/info_command.hpp"
#include "cli/progress.hpp"
#include "cli/sat_commands.hpp"
#include "cli/scatter_commands.hpp"
#include "cli/suggestions.hpp"
#include "io/atomic_file.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/version.hpp>

#include <CLI/CLI.hpp>

#include <csignal>
#include <iostream>
#include <new>
#include <string>

namespace {

constexpr int exit_bad_input = 2;
constexpr int exit_runtime_failure = 1;

/// One line: newlines (e.g. from a build log) become "; ".
std::string one_line(std::string text) {
    std::string line;
    for (char c : text) {
        if (c == '\r') continue;
        if (c == '\n') {
            if (!line.empty() && line.back() != ' ') line += "; ";
        } else {
            line += c;
        }
    }
    while (!line.empty() && (line.back() == ' ' || line.back() == ';')) line.pop_back();
    const std::size_t longest = 2000;
    if (line.size() > longest) line = line.substr(0, longest) + "...";
    return line;
}

int report(const std::string& problem, int exit_code) {
    std::cerr << "msmcl: " << one_line(msmcl::io::shorten_long_names(problem)) << std::endl;
    return exit_code;
}

/// No subcommand: the usage line and the subcommands on stderr (exit 2), as git and ktx do.
int usage(const CLI::App& app) {
    std::cerr << "usage: msmcl [OPTIONS] COMMAND [ARGUMENTS]\n\ncommands:\n";
    for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
        std::string name = "  " + command->get_name();
        name.resize(12, ' ');
        std::cerr << name << command->get_description() << '\n';
    }
    std::cerr << "\n'msmcl --help' lists the options and environment variables, 'msmcl COMMAND --help' a command's.\n";
    return exit_bad_input;
}

} // namespace

int main(int argc, char** argv) {
    // Ctrl-C or a kill while an output is written leaves no temporary file behind.
    msmcl::io::remove_temporary_files_on_signals();
    // Past the file size limit (ulimit -f) a write fails with EFBIG, reported like a full
    // disk, instead of SIGXFSZ ending the process with its temporary file left behind.
    std::signal(SIGXFSZ, SIG_IGN);
    CLI::App app{"msmcl: moment shadow maps on OpenCL (filter depth maps, shade receivers)", "msmcl"};
    app.set_version_flag("--version", std::string("msmcl ") + msmcl::version_string);
    app.require_subcommand(1);
    // Each subcommand's help inherits this footer; the environment table is the top level's alone (below).
    app.footer("Exit codes: 0 success, 2 bad input or usage, 1 device or runtime failure.");
    // Global options may also follow the subcommand.
    app.fallthrough();

    msmcl::cli::GlobalArguments global;
    app.add_option("--device", global.device,
                   "OpenCL device: gpu, cpu, an index, P:D (platform:device) or a name substring; "
                   "default MSMCL_DEVICE, else the first GPU, else the first CPU; an unknown device is an error; "
                   "all: a batch of filter or sat spreads its files over every device")
        ->type_name("DEVICE");
    app.add_flag("-v,--verbose", global.verbose,
                 "print a timing line per stage on stderr (read, device setup, program build or cache hit, "
                 "upload, kernel, download, write)");
    app.add_flag("-q,--quiet", global.quiet, "nothing on stderr but errors: no progress line, no batch summary");

    // msmcl filter IN.exr OUT.exr|OUT.ktx2|OUT.dds --format F [--sigma S] [--depth-range R] [--kernel K]
    //              [--out-container C]
    // msmcl filter IN.exr... -o DIR | --list FILE [--shard I/N] [--json FILE|-] (same options)
    // msmcl filter IN.exr... --array OUT.ktx2|OUT.dds (same options): one texture array
    msmcl::cli::FilterArguments filter;
    CLI::App* filter_command =
        app.add_subcommand("filter", "Depth map (EXR, Z or sample<N>.Z) -> filtered moment shadow map (EXR, KTX2 or DDS)");
    // IN OUT: a depth map EXR (optional translucent layers layer<k>.Z, layer<k>.A) and the
    // texture to write (EXR; .ktx2 or .dds: KTX2 or DDS); or a batch: IN... -o DIR, --list FILE.
    msmcl::cli::BatchArguments filter_batch;
    msmcl::cli::add_batch_options(*filter_command, filter_batch);
    filter_command->add_option("--format", filter.format, "moments128, msm64, nlq64 or nlq32 (required)")
        ->type_name("FORMAT");
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

    // msmcl shade MAP.exr RECEIVERS.exr OUT.exr [--lookup L] [--frame N] [--depth-bias B] [--depth-range R]
    msmcl::cli::ShadeArguments shade;
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

    // msmcl sat ... and msmcl soft ... (host/cli/sat_commands.cpp)
    msmcl::cli::SatCommands sat_commands;
    msmcl::cli::add_sat_commands(app, sat_commands);

    // msmcl scatter ... (host/cli/scatter_commands.cpp)
    msmcl::cli::ScatterArguments scatter;
    msmcl::cli::add_scatter_command(app, scatter);

    CLI::App* devices_command = app.add_subcommand("devices", "List OpenCL devices; marks the one msmcl picks");

    // msmcl info FILE... [--json] (host/cli/info_command.cpp)
    msmcl::cli::InfoArguments info;
    msmcl::cli::add_info_command(app, info);

    // `msmcl --help` (and so the man page) ends with every environment variable msmcl reads.
    app.footer(app.get_footer() + "\n\n" + msmcl::cli::environment_help());

    // A bare `msmcl`: what it can do, not only that a subcommand is missing.
    if (argc <= 1) return usage(app);

    // Parse: help and version go to stdout with exit 0, every other parse error is usage.
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // A typo reads as a missing word to CLI11: name the unknown word instead.
        const std::vector<std::string> arguments(argv + 1, argv + argc);
        const std::optional<std::string> unknown = msmcl::cli::unknown_word_message(app, arguments);
        // Global options but no command: the same usage as a bare `msmcl`.
        if (!unknown && app.get_subcommands().empty() && std::string(e.what()).find("subcommand") != std::string::npos)
            return usage(app);
        return report(unknown ? *unknown : std::string(e.what()), exit_bad_input);
    }
    msmcl::cli::set_quiet(global.quiet);

    // Run the chosen subcommand and map failures to exit codes.
    try {
        if (global.quiet && global.verbose) throw msmcl::cli::usage_error("-q/--quiet and -v/--verbose exclude each other");
        // --device all spreads a batch's files: the other commands have one device.
        if (global.device == "all" && !filter_command->parsed() && !sat_commands.sat_command->parsed())
            throw msmcl::cli::usage_error("--device all spreads the files of a batch: only filter and sat take it");
        // filter and sat report a batch's failures per file and return its exit code.
        if (filter_command->parsed()) return msmcl::cli::run_filter(global, filter, filter_batch);
        else if (shade_command->parsed()) msmcl::cli::run_shade(global, shade);
        else if (devices_command->parsed()) msmcl::cli::run_devices(global);
        else if (info.command->parsed()) return msmcl::cli::run_info(info);
        else if (scatter.command->parsed()) msmcl::cli::run_scatter(global, scatter);
        else return msmcl::cli::run_sat_commands(global, sat_commands);
        return 0;
    } catch (const msmcl::cli::usage_error& e) {
        return report(e.what(), exit_bad_input);
    } catch (const msmcl::input_error& e) {
        return report(e.what(), exit_bad_input);
    } catch (const msmcl::unfit_kernel_error& e) { // an explicit --kernel the device cannot run: a usage choice
        return report(e.what(), exit_bad_input);
    } catch (const msmcl::error& e) { // opencl_error, build_error, device_error, I/O failures
        return report(e.what(), exit_runtime_failure);
    } catch (const std::bad_alloc&) {
        return report("out of memory", exit_runtime_failure);
    } catch (const std::exception& e) {
        return report(e.what(), exit_runtime_failure);
    }
}
