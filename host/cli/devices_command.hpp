// The devices subcommand of msmcl: `msmcl devices` prints one line per OpenCL device to
// stdout and marks the one a Context would pick with the global options and the environment.
#pragma once

#include "cli/commands.hpp"

namespace msmcl::cli {

/// Adds `devices` to the application.
Subcommand add_devices_command(CLI::App& app);

} // namespace msmcl::cli
