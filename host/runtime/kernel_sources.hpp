// Access to the kernels/ files embedded at build time.
#pragma once

#include <cstdint>
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

/// A program's whole source and its 64-bit FNV-1a hash (the program cache's key).
struct KernelSource {
    std::string text;
    std::uint64_t hash = 0;
};

/// The embedded program `name` with `defines` ("MSM_FORMAT=2" or "NAME") as `#define`
/// lines in front, assembled and hashed once per (name, defines) for the whole process
/// and kept (embedded files never change), so launches do not redo either. Thread-safe;
/// the reference stays valid until the process ends.
const KernelSource& kernel_source(std::string_view name, const std::vector<std::string>& defines);

/// Build options of every program, before a device's own (quirks.hpp) and the caller's.
inline constexpr const char* base_build_options = "-cl-std=CL1.2";

} // namespace msmcl::detail
