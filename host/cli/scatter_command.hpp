// The single-scattering subcommand of msmcl (docs/math.md):
//   msmcl scatter SCENE.json SHADOWMAP.exr CAMERA_DEPTH.exr OUT.exr [--moments 4|6]
//                 [--no-filter] [--sigma S] [--beta adaptive|B] [--ray-march N [--jitter SEED]]
//                 [--rectified FILE] [--prefix-sums FILE]
// As the other subcommands: options are checked before any file is touched, inputs are
// read and outputs written through msmcl::io (atomic writes), errors map to exit codes 2/1.
#pragma once

#include "cli/commands.hpp"

#include <string>

namespace msmcl::cli {

struct ScatterArguments {
    std::string scene;
    std::string shadow_map;
    std::string camera_depth;
    std::string output;
    std::string moments = "6";
    bool no_filter = false;
    std::string sigma = "1";
    std::string beta = "adaptive";
    std::string ray_march;   ///< empty: prefiltered; else the number of ray-marching steps
    std::string jitter = "0";
    std::string rectified;   ///< optional EXR of the resampled moments
    std::string prefix_sums; ///< optional EXR of the stored (quantized) prefix sums
    std::string kernel = "automatic";        ///< the prefilter's rows: automatic, rows_gpu or rows_cpu
    std::string filter_kernel = "automatic"; ///< the moment map's filter kernel (as msmcl filter --kernel)
    std::string map;         ///< optional KTX2 of the prefiltered map, as a renderer uploads it
};

/// Adds `scatter` to the application.
Subcommand add_scatter_command(CLI::App& app);

} // namespace msmcl::cli
