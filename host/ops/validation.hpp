// Validation the operations share: map sizes, depth values, receivers, buffer sizes. Every
// failure is an input_error whose message starts with the call ("filter: ...", "sat: ...").
#pragma once

#include "runtime/opencl.hpp"

#include <msmcl/types.hpp>

#include <cstddef>
#include <string>

namespace msmcl::detail {

/// Largest width or height of a map any operation accepts (OpenCL image limits are far
/// below this anyway).
inline constexpr int max_map_side = 65536;

/// width * height, as a size.
inline std::size_t texel_count(int width, int height) { return static_cast<std::size_t>(width) * height; }

/// "WxH".
std::string size_text(int width, int height);

/// input_error "<what> WxH is empty or negative" or "<what> WxH exceeds the limit of 65536
/// texels per side" (what: "filter: depth map size", "sat: depth map: size", ...).
void validate_map_size(const std::string& what, int width, int height);

/// Array layers of a texture array call: input_error "<call>: N array layers (1 to 2048)"
/// outside [1, max_array_layers].
void validate_array_layers(const std::string& call, int layers);

/// Calls that take one map: input_error "<call>: <what> is a texture array of N layers,
/// this call takes one (take a layer with layer(i))" for layers != 1.
void require_single_layer(const std::string& call, const char* what, int layers);

/// Where value i of a depth map's samples (or of a layer laid out like it) stands:
/// "texel (x, y) sample s", with " of array layer a" after the texel in a layered map.
std::string sample_position_text(const DepthImage& depth, std::size_t value_index);

/// The first NaN, Inf or out-of-range depth (row-major, samples in order): input_error
/// "<call>: depth at texel (x, y) sample s is d[, outside the depth range [r]]" (with
/// "of array layer a" after the texel in a layered map).
void validate_depth_values(const char* call, const DepthImage& depth, DepthRange range);

/// Receivers of a host call: u, v and z of one length, every value finite; input_error
/// "<call>: receiver arrays differ in length (...)" or "<call>: receiver i is not finite (...)".
void validate_receivers(const char* call, const Receivers& receivers);

/// Bytes of a cl_mem object (CL_MEM_SIZE).
cl_ulong buffer_size(cl_mem buffer);

} // namespace msmcl::detail
