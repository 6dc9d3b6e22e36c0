// Access to the kernels/ files embedded at build time.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace msmcl::detail {

/// The embedded file `name` ("msm_shading.clh"); throws msmcl::error if absent.
std::string_view embedded_kernel_file(std::string_view name);

/// Names of all embedded files.
std::vector<std::string> embedded_kernel_names();

/// The source of `name` with every `#include "x"` line replaced by the embedded file x
/// (recursively, each file once), ready for clCreateProgramWithSource.
std::string assemble_kernel_source(std::string_view name);

/// The program text the host builds for `name` with `defines` ("MSM_FORMAT=2"; each becomes
/// a `#define NAME VALUE` line in front of the assembled source, then `#line 1`).
std::string assemble_variant_source(std::string_view name, const std::vector<std::string>& defines);

/// Build options of every program, before a device's own (quirks.hpp) and the caller's.
inline constexpr const char* base_build_options = "-cl-std=CL1.2";

} // namespace msmcl::detail
