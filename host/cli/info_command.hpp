// msmcl info FILE... [--json] [--depth-range R]: what a file holds, for every kind of file
// msmcl reads or writes (depth maps, receivers, filtered maps, summed-area tables, results,
// scattering scenes and maps, previews) in every container (EXR, KTX2, DDS, JSON, PNG).
// Per file: kind, container, size, format, samples, layers, attributes, and per channel
// (decoded quantities for textures) the value range and the counts of NaN, Inf and values
// outside the range the kind allows. Files are read leniently (a depth map with NaNs is
// described, not refused); a file that cannot be parsed at all is named on stderr, the
// others are still described, and the exit code is 2.
#pragma once

#include "cli/commands.hpp"

#include <msmcl/formats.hpp>

#include <string>
#include <vector>

namespace msmcl::cli {

struct InfoArguments {
    std::vector<std::string> files;
    bool json = false;
    std::string depth_range = "0,1"; ///< convention of depth maps and receivers (they record none)
};

/// Adds `info` to the application: it prints the description of every readable file to
/// stdout (text, or one JSON array with --json) and names each unreadable one on stderr;
/// its exit code is 2 when one was bad.
Subcommand add_info_command(CLI::App& app);

/// The description of one file as `msmcl info --json` prints it (one object of its array),
/// as JSON text (the Python module's msmcl.info).
std::string describe_json(const std::string& path, DepthRange depth_range);

} // namespace msmcl::cli
