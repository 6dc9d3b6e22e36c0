// filter: depth map (MSAA) -> resolved, Gaussian-blurred, quantized moment shadow map.
#pragma once

#include <msmcl/context.hpp>
#include <msmcl/enqueue.hpp>
#include <msmcl/formats.hpp>

#include <array>
#include <optional>
#include <string_view>
#include <vector>

namespace msmcl {

/// Which kernel does the work. All produce the same texture (SPEC section 4; the
/// fused kernel shifts moments per block before Algorithm 2, which makes nlq codes
/// more accurate than three_pass in flat regions).
enum class FilterKernel {
    automatic,   ///< the best one for the device
    fused_paper, ///< the paper's 40x32 local-memory kernel (256 work-items, GPU layout)
    three_pass,  ///< resolve -> global, horizontal blur -> global, vertical blur + quantize
    fused_cpu,   ///< the same fused filter distributed for CPU devices: scalar code that the
                 ///< OpenCL compiler vectorizes across work-items, one work-item per texel
                 ///< column of a 128x64 tile whose rows are streamed; nlq formats shift per
                 ///< tile (environment MSMCL_CPU_TILE="WxH" changes the tile). `automatic`
                 ///< picks it on devices that report CPU and not GPU, fused_paper on the
                 ///< others (docs/devices.md)
};
/// "automatic", "fused_paper", "three_pass", "fused_cpu".
const char* filter_kernel_name(FilterKernel kernel) noexcept;
std::optional<FilterKernel> parse_filter_kernel(std::string_view name) noexcept;
/// The kernel a filter call with `requested` runs on the context's device: `automatic`
/// resolved, an explicit choice returned as is. Throws device_error when the device
/// cannot run the choice (too few work-items per group or too little local memory).
FilterKernel filter_kernel_for(const Context& context, FilterKernel requested);

struct FilterOptions {
    Format format = Format::nlq64;
    float sigma = 2.4f; ///< Gaussian standard deviation in texels; 0 = no blur
    DepthRange depth_range = DepthRange::zero_one;
    FilterKernel kernel = FilterKernel::automatic;
};

/// The 9 normalized taps w_{-4..4} of the blur as float32 (symmetric; sigma 0 gives
/// a unit impulse). Throws input_error for a negative or non-finite sigma.
std::array<float, 9> gaussian_taps(float sigma);

/// Sample counts the filter accepts: 1, 2, 4, 8, 16.
bool is_supported_sample_count(int samples) noexcept;

/// Filters a host depth map. Validates everything (size, sample count, depth range,
/// NaN/Inf) and throws input_error naming the first bad texel.
Texture filter(Context& context, const DepthImage& depth, const FilterOptions& options);

/// A depth map already on the device: a buffer of float, layout as DepthImage.
struct DeviceDepth {
    cl_mem buffer = nullptr;
    int width = 0;
    int height = 0;
    int samples = 1;
};

/// Filters device data into `texture` (a buffer of at least width*height*texel_bytes
/// bytes, layout as Texture). No host copies. Depth values are not validated on the
/// device: out-of-range values are clamped to the range, NaN counts as the near plane.
void filter(Context& context, const DeviceDepth& depth, cl_mem texture,
            const FilterOptions& options, const Enqueue& enqueue = {});

// ---- Translucent occluders (SPEC section 7, seed 001 section 4).

/// Most translucent layers one call composites.
inline constexpr int max_translucent_layers = 8;

/// A translucent layer over a depth map: for every sample of every texel a depth (as
/// rendered, in the map's range) and an opacity in [0, 1], each laid out as
/// DepthImage::depth (same width, height and samples). Opacity 0 where the layer has no
/// surface. Per sample, the opaque surface (opacity 1) and the layers are alpha-blended
/// nearest first, whatever the order of the layers: the texel stores the moments of
/// sum_i prod_{j<i} (1 - a_j) a_i b(z_i) instead of b(z).
struct TranslucentLayer {
    std::vector<float> depth;
    std::vector<float> opacity;
};

/// Filters a depth map with translucent layers (at most max_translucent_layers). Validates
/// like filter() and also every layer's size, depths and opacities (input_error names the
/// first bad one). No layers: exactly filter(context, depth, options); layers of opacity 0
/// give the same bits as none.
Texture filter(Context& context, const DepthImage& depth, const std::vector<TranslucentLayer>& layers,
               const FilterOptions& options);

/// Translucent layers already on the device: `depth` and `opacity` each hold
/// count * width * height * samples floats, layer after layer, each layer laid out as
/// DeviceDepth. count 0: no layers (the buffers may be null).
struct DeviceLayers {
    cl_mem depth = nullptr;
    cl_mem opacity = nullptr;
    int count = 0;
};

/// Device version. Values are not validated on the device: depths clamp to the range (NaN
/// counts as the near plane), opacities clamp to [0, 1] (NaN counts as 0).
void filter(Context& context, const DeviceDepth& depth, const DeviceLayers& layers, cl_mem texture,
            const FilterOptions& options, const Enqueue& enqueue = {});

} // namespace msmcl
