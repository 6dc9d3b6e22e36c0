// The shade subcommand of msmcl: a filtered moment shadow map queried at receivers:
// msmcl shade MAP.exr RECEIVERS.exr OUT.exr [--lookup L] [--frame N] [--depth-bias B] [--depth-range R]
//             [--format F]
// As the other subcommands: options are checked before any file is touched, inputs are
// read and outputs written through msmcl::io (atomic writes), errors map to exit codes 2/1.
#pragma once

#include "cli/commands.hpp"

#include <string>

namespace msmcl::cli {

/// The options of `msmcl shade`.
struct ShadeArguments {
    std::string map;
    std::string receivers;
    std::string output;
    std::string lookup;      ///< empty: the format's (the format table, shade_defaults)
    std::string depth_bias;  ///< empty: the format's
    std::string depth_range; ///< empty: the map's msmcl:depthRange
    std::string frame = "0"; ///< dither: the frame number (blue-noise texture and shift)
    std::string format;      ///< empty: the map's; required for DDS maps of msm64/nlq64 texels
    std::string min_variance;          ///< VSM, EVSM; empty: the format's
    std::string light_bleed_reduction; ///< VSM, EVSM; empty: 0
};

/// Adds `shade` to the application.
Subcommand add_shade_command(CLI::App& app);

} // namespace msmcl::cli
