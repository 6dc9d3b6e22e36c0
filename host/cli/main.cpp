// msmcl: filter depth maps into moment shadow maps and shade receivers with them.
// Exit codes: 0 success, 2 bad input or usage, 1 device or runtime failure.
// Every failure prints exactly one line on stderr: "msmcl: [<file>: ]<problem>" (a batch and
// `info` one per bad file). A bare `msmcl` prints the usage and the commands (exit 2).
#include "cli/commands.hpp"
#include "cli/devices_command.hpp"
#include "cli/environment.hpp"
#include "cli/filter_command.hpp"
#include "cli/info_command.hpp"
#include "cli/progress.hpp"
#include "cli/sat_command.hpp"
#include "cli/scatter_command.hpp"
#include "cli/shade_command.hpp"
#include "cli/soft_command.hpp"
#include "cli/suggestions.hpp"
#include "io/atomic_file.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/version.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <csignal>
#include <iostream>
#include <new>
#include <string>
#include <vector>

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

    // The subcommands, each from its own file (host/cli/<name>_command.cpp), in the order of
    // the help.
    const std::vector<msmcl::cli::Subcommand> commands = {
        msmcl::cli::add_filter_command(app),  msmcl::cli::add_shade_command(app),
        msmcl::cli::add_sat_command(app),     msmcl::cli::add_soft_command(app),
        msmcl::cli::add_scatter_command(app), msmcl::cli::add_devices_command(app),
        msmcl::cli::add_info_command(app)};

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
    const auto chosen = std::find_if(commands.begin(), commands.end(),
                                     [](const msmcl::cli::Subcommand& command) { return command.command->parsed(); });
    if (chosen == commands.end()) return usage(app);
    try {
        if (global.quiet && global.verbose) throw msmcl::cli::usage_error("-q/--quiet and -v/--verbose exclude each other");
        // --device all spreads a batch's files: the other commands have one device.
        if (global.device == "all" && !chosen->spreads_over_devices)
            throw msmcl::cli::usage_error("--device all spreads the files of a batch: only filter and sat take it");
        // filter, sat and info return the exit code of their files; the others 0.
        return chosen->run(global);
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
