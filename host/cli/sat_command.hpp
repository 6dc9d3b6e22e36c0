// The summed-area table subcommand of msmcl (docs/math.md), for one map or a batch
// (host/cli/batch.cpp):
//   msmcl sat IN.exr OUT.exr|OUT.ktx2|OUT.dds [--max-kernel N] [--depth-range 0,1|-1,1]
//             [--out-container C] [--kernel K]
// As the other subcommands: options are checked before any file is touched, inputs are
// read and outputs written through msmcl::io (atomic writes), errors map to exit codes 2/1.
#pragma once

#include "cli/commands.hpp"

#include <string>

namespace msmcl::cli {

/// The options of `msmcl sat` (its files: BatchArguments, host/cli/batch.hpp).
struct SatArguments {
    std::string max_kernel = "729";
    std::string depth_range = "0,1";
    std::string kernel = "automatic"; ///< automatic, tiled_gpu, tiled_cpu or row_per_thread
    std::string out_container; ///< exr, ktx2 or dds; empty: from the output's extension
};

/// Adds `sat` to the application.
Subcommand add_sat_command(CLI::App& app);

} // namespace msmcl::cli
