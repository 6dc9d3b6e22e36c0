// Probe mode of msmcl-bench: one fresh process times its first filter() call (program
// build or cache load, first-launch JIT, the run) and a few steady calls after it.
#pragma once

#include <msmcl/formats.hpp>

#include <string>

namespace msmcl::bench {

/// The hidden command-line flag that selects probe mode.
inline constexpr const char* kProbeFlag = "--probe-first-call";

/// Runs the probe for the automatic kernel and writes {first_ms, steady_ms, context_ms,
/// programs_built} to `json_path`. Returns the exit code.
int run_first_call_probe(int size, int samples, Format format, const std::string& device,
                         const std::string& json_path);

} // namespace msmcl::bench
