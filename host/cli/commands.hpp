// What every msmcl subcommand shares, and the one way each joins the application: the file
// of a subcommand (host/cli/<name>_command.cpp) defines `Subcommand add_<name>_command(CLI::App&)`,
// which adds the subcommand with its options and says how to run it; main.cpp calls them in
// the order of the help and runs the one that was parsed. A subcommand parses nothing itself,
// reads its inputs through msmcl::io, calls the public API and writes its output through msmcl::io.
#pragma once

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>

#include <CLI/CLI.hpp>

#include <functional>
#include <stdexcept>
#include <string>

namespace msmcl::cli {

/// A bad command line that CLI11 cannot see (bad option values): exit code 2.
class usage_error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Global options shared by every subcommand.
struct GlobalArguments {
    std::string device; ///< empty: default selection (MSMCL_DEVICE, else first GPU, ...)
    bool verbose = false; ///< -v, --verbose: a timing line per stage on stderr
    bool quiet = false;   ///< -q, --quiet: nothing on stderr but errors (no progress, no summary)
    DeviceSelection selection() const;
};

/// A subcommand as its file added it to the application.
struct Subcommand {
    CLI::App* command = nullptr; ///< CLI11's subcommand, holding its options
    /// Runs the subcommand once CLI11 parsed it (its options are filled); returns the exit code.
    std::function<int(const GlobalArguments& global)> run;
    /// Takes `--device all` (a batch spread over every device): filter and sat.
    bool spreads_over_devices = false;
};

/// Library input errors do not know the file; put it in front.
[[noreturn]] void rethrow_with_file(const std::string& path, const input_error& e);

} // namespace msmcl::cli
