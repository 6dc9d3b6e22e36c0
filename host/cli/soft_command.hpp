// The soft shadow subcommand of msmcl (docs/math.md): a summed-area table written by
// `msmcl sat` queried at receivers:
//   msmcl soft SAT.exr|SAT.ktx2|SAT.dds RECEIVERS.exr OUT.exr --light-size L [--search-size K]
//              [--min-filter F] [--depth-bias B] [--depth-range R] [--max-kernel N]
// As the other subcommands: options are checked before any file is touched, inputs are
// read and outputs written through msmcl::io (atomic writes), errors map to exit codes 2/1.
#pragma once

#include "cli/commands.hpp"

#include <string>

namespace msmcl::cli {

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

/// Adds `soft` to the application.
Subcommand add_soft_command(CLI::App& app);

} // namespace msmcl::cli
