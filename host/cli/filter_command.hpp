// The filter subcommand of msmcl, for one map or a batch (host/cli/batch.cpp):
// msmcl filter IN.exr OUT.exr|OUT.ktx2|OUT.dds --format F [--sigma S] [--depth-range R] [--kernel K]
//              [--out-container C]
// msmcl filter IN.exr... -o DIR | --list FILE [--shard I/N] [--json FILE|-] (same options)
// msmcl filter IN.exr... --array OUT.ktx2|OUT.dds (same options): one texture array
// As the other subcommands: options are checked before any file is touched, inputs are
// read and outputs written through msmcl::io (atomic writes), errors map to exit codes 2/1.
#pragma once

#include "cli/commands.hpp"

#include <string>

namespace msmcl::cli {

/// The options of `msmcl filter` (its files: BatchArguments, host/cli/batch.hpp).
struct FilterArguments {
    std::string format; ///< required (on the command line, or per file in a manifest)
    std::string sigma = "2.4";
    std::string depth_range = "0,1";
    std::string out_container; ///< exr, ktx2 or dds; empty: from the output's extension (.ktx2, .dds, else exr)
    std::string kernel = "automatic"; ///< automatic, fused_paper, fused_cpu or three_pass
    std::string exponents; ///< EVSM: "C+" or "C+,C-"; empty: the format's defaults
    std::string exponent;  ///< ESM: "C"; empty: the default
};

/// Adds `filter` to the application.
Subcommand add_filter_command(CLI::App& app);

} // namespace msmcl::cli
