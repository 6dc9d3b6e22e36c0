// filter: depth map (MSAA) -> resolved, Gaussian-blurred, quantized moment shadow map.
#pragma once

#include <msmcl/context.hpp>
#include <msmcl/enqueue.hpp>
#include <msmcl/types.hpp>

#include <array>
#include <optional>
#include <string_view>
#include <vector>

namespace msmcl {

/// "automatic", "fused_paper", "three_pass", "fused_cpu".
const char* filter_kernel_name(FilterKernel kernel) noexcept;
std::optional<FilterKernel> parse_filter_kernel(std::string_view name) noexcept;
/// The kernel a filter call with `requested` runs on the context's device: `automatic`
/// resolved, an explicit choice returned as is. Throws device_error when the device
/// cannot run the choice (too few work-items per group or too little local memory).
FilterKernel filter_kernel_for(const Context& context, FilterKernel requested);

/// The 9 normalized taps w_{-4..4} of the blur as float32 (symmetric; sigma 0 gives
/// a unit impulse). Throws input_error for a negative or non-finite sigma.
std::array<float, 9> gaussian_taps(float sigma);

/// Sample counts the filter accepts: 1, 2, 4, 8, 16.
bool is_supported_sample_count(int samples) noexcept;

/// Filters a host depth map. Validates everything (size, sample count, depth range,
/// NaN/Inf) and throws input_error naming the first bad texel.
Texture filter(Context& context, const DepthImage& depth, const FilterOptions& options);

/// Filters device data into `texture` (a buffer of at least width*height*texel_bytes
/// bytes, layout as Texture). No host copies. Depth values are not validated on the
/// device: out-of-range values are clamped to the range, NaN counts as the near plane.
void filter(Context& context, const DeviceDepth& depth, cl_mem texture,
            const FilterOptions& options, const Enqueue& enqueue = {});

// ---- Translucent occluders (docs/math.md, Peters et al., i3D 2016, section 4).

/// Filters a depth map with translucent layers (at most max_translucent_layers). Validates
/// like filter() and also every layer's size, depths and opacities (input_error names the
/// first bad one). No layers: exactly filter(context, depth, options); layers of opacity 0
/// give the same bits as none.
Texture filter(Context& context, const DepthImage& depth, const std::vector<TranslucentLayer>& layers,
               const FilterOptions& options);

/// Device version. Values are not validated on the device: depths clamp to the range (NaN
/// counts as the near plane), opacities clamp to [0, 1] (NaN counts as 0).
void filter(Context& context, const DeviceDepth& depth, const DeviceLayers& layers, cl_mem texture,
            const FilterOptions& options, const Enqueue& enqueue = {});

} // namespace msmcl
