// The msmcl subcommands: each parses nothing itself, reads its inputs through msmcl::io,
// calls the public API and writes its output through msmcl::io.
#pragma once

#include <msmcl/context.hpp>

#include <stdexcept>
#include <string>

namespace msmcl::cli {

/// A bad command line that CLI11 cannot see (bad option values): exit code 2.
class usage_error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

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

/// Global options shared by every subcommand.
struct GlobalArguments {
    std::string device; ///< empty: default selection (MSMCL_DEVICE, else first GPU, ...)
    bool verbose = false; ///< -v, --verbose: a timing line per stage on stderr
    bool quiet = false;   ///< -q, --quiet: nothing on stderr but errors (no progress, no summary)
    DeviceSelection selection() const;
};

struct BatchArguments;
/// One file or a batch; returns the exit code (host/cli/batch.hpp).
int run_filter(const GlobalArguments& global, const FilterArguments& arguments, const BatchArguments& batch);
void run_shade(const GlobalArguments& global, const ShadeArguments& arguments);
/// Prints one line per device to stdout and marks the one a Context would pick.
void run_devices(const GlobalArguments& global);

} // namespace msmcl::cli
