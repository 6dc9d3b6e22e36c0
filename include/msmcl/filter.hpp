// filter: depth map (MSAA) -> resolved, Gaussian-blurred, quantized moment shadow map.
#pragma once

#include <msmcl/context.hpp>
#include <msmcl/enqueue.hpp>
#include <msmcl/formats.hpp>

#include <array>

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
                 ///< picks it on CPU devices, fused_paper on the others
};

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

} // namespace msmcl
