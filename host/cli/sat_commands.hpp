// The summed-area table subcommands of msmcl (docs/math.md):
//   msmcl sat IN.exr OUT.exr|OUT.ktx2|OUT.dds [--max-kernel N] [--depth-range 0,1|-1,1]
//             [--out-container C] [--kernel K]
//   msmcl soft SAT.exr|SAT.ktx2|SAT.dds RECEIVERS.exr OUT.exr --light-size L [--search-size K]
//              [--min-filter F] [--depth-bias B] [--depth-range R] [--max-kernel N]
// As the other subcommands: options are checked before any file is touched, inputs are
// read and outputs written through msmcl::io (atomic writes), errors map to exit codes 2/1.
#pragma once

#include "cli/batch.hpp"
#include "cli/commands.hpp"

#include <CLI/CLI.hpp>

#include <string>

namespace msmcl::cli {

/// The options of `msmcl sat` (its files: BatchArguments, host/cli/batch.hpp).
struct SatArguments {
    std::string max_kernel = "729";
    std::string depth_range = "0,1";
    std::string kernel = "automatic"; ///< automatic, tiled_gpu, tiled_cpu or row_per_thread
    std::string out_container; ///< exr, ktx2 or dds; empty: from the output's extension
};

struct SoftArguments {
    std::string table;
    std::string receivers;
    std::string output;
    std::string light_size;
    std::string search_size = "0";
    std::string min_filter = "1";
    std::string depth_bias = "1e-3";
    std::string depth_range; ///< empty: the table's msmcl:depthRange
    std::string max_kernel;  ///< empty: the table's; required for DDS tables
    std::string receiver_weight = "0.1";
    std::string filter_parts = "2";
    bool published = false; ///< the method as published: receiver weight 0, one filter part
};

/// The two subcommands and what they parsed.
struct SatCommands {
    SatArguments sat;
    BatchArguments sat_batch;
    SoftArguments soft;
    CLI::App* sat_command = nullptr;
    CLI::App* soft_command = nullptr;
};

/// Adds `sat` and `soft` to the application.
void add_sat_commands(CLI::App& app, SatCommands& commands);

/// Runs whichever of the two was parsed; returns the exit code.
int run_sat_commands(const GlobalArguments& global, const SatCommands& commands);

/// One file or a batch; returns the exit code (host/cli/batch.hpp).
int run_sat(const GlobalArguments& global, const SatArguments& arguments, const BatchArguments& batch);
void run_soft(const GlobalArguments& global, const SoftArguments& arguments);

} // namespace msmcl::cli
