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

} // namespace msmcl::detail
