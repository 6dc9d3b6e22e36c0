// The plain data of the API: what the operations take and return, and their options.
// Structs and enums with accessors at most, no operations: every public header that
// needs one of these includes this header, never another operation's header. The
// formats, depth conventions and host images (DepthImage, Texture, Receivers) are in
// formats.hpp, which this header includes.
#pragma once

#include <msmcl/formats.hpp>
#include <msmcl/vector3.hpp>

#include <CL/cl.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace msmcl {

// ---- Stage timings of the host calls

/// One stage of a host call (filter, build_sat, shade, soft_shade on host arrays), timed:
/// "upload", "program" (building its programs, or finding them in the Context's caches),
/// "kernel", "download".
struct StageTime {
    const char* stage = "";
    double milliseconds = 0;
    std::string note; ///< "4194304 bytes, 4194304 in place", "1 program built", "cache hit"
};
/// Called on the calling thread as each stage of a host call ends (`on_stage` of its
/// options). A call given one waits for the device at the end of every stage, so that each
/// time is the stage's own; device calls (cl_mem in and out) ignore it.
using StageObserver = std::function<void(const StageTime&)>;

// ---- Depth maps (filter, build_sat)

/// A depth map already on the device: a buffer of float, layout as DepthImage (`layers`
/// array layers, one after the other).
struct DeviceDepth {
    cl_mem buffer = nullptr;
    int width = 0;
    int height = 0;
    int samples = 1;
    int layers = 1; ///< array layers (texture arrays), 1 .. max_array_layers
};

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

/// Translucent layers already on the device: `depth` and `opacity` each hold
/// count * width * height * samples floats, layer after layer, each layer laid out as
/// DeviceDepth. count 0: no layers (the buffers may be null). A layered DeviceDepth (texture
/// arrays): count translucent layers per array layer, array layer after array layer
/// (array layer a, translucent layer k at a * count + k).
struct DeviceLayers {
    cl_mem depth = nullptr;
    cl_mem opacity = nullptr;
    int count = 0;
};

// ---- Filtering

/// Which kernel filters. All produce the same texture (the fused kernels shift moments
/// per block before Algorithm 2, which makes nlq codes more accurate than three_pass in
/// flat regions).
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

struct FilterOptions {
    Format format = Format::nlq64;
    float sigma = 2.4f; ///< Gaussian standard deviation in texels; 0 = no blur
    DepthRange depth_range = DepthRange::zero_one;
    FilterKernel kernel = FilterKernel::automatic;
    StageObserver on_stage; ///< the host call's stage timings (none: not timed)
    /// EVSM's c+ and c-, ESM's c (in `positive`); 0 = the format's default. Only for the
    /// formats with a warp (effective_exponents, include/msmcl/formats.hpp).
    WarpExponents exponents;
};

// ---- Filtered maps and their shading (shade)

/// A filtered map already on the device (a buffer, layout as Texture).
struct DeviceTexture {
    cl_mem buffer = nullptr;
    Format format = Format::nlq64;
    int width = 0;
    int height = 0;
    WarpExponents exponents; ///< as Texture::exponents: what the filter used
};

/// How shade() reads the map at a receiver.
enum class Lookup {
    nearest,  ///< texel floor(u), floor(v)
    bilinear, ///< between texel centres around (u-0.5, v-0.5): moments for moments128/msm64,
              ///< the four shadow intensities for nlq64/nlq32
    dither,   ///< one texel floor(u - 0.5 + nx), floor(v - 0.5 + ny) with blue noise (nx, ny) in
              ///< [0,1) of the receiver's screen pixel and the frame;
              ///< averaged over frames, the bilinear blend of the shaded texels
};

/// The defaults below are the moment formats'; shade_defaults(format) (shade.hpp) gives any
/// format's, from the format table (docs/formats.md).
struct ShadeOptions {
    Lookup lookup = Lookup::bilinear;
    /// Subtracted from the receiver's internal depth z (2d - 1 or d, see DepthRange) before shading.
    float depth_bias = 1e-3f;
    /// Convention of the receivers' z (normally the map's).
    DepthRange depth_range = DepthRange::zero_one;
    /// dither: the frame number; its hash picks the blue-noise texture and its shift.
    std::uint32_t frame = 0;
    /// dither, receivers without explicit pixels: receiver i is pixel (i % screen_width,
    /// i / screen_width) of a row-major image; 0 = one row (pixel (i, 0)).
    std::uint32_t screen_width = 0;
    StageObserver on_stage; ///< the host call's stage timings (none: not timed)
    /// VSM and EVSM: the least variance of the depth t in [0, 1] that Chebyshev's bound assumes,
    /// in [0, 0.25] (docs/math.md, "Shading VSM, EVSM and ESM"); none: the format's default
    /// (docs/formats.md, the format table). Refused for the other formats.
    std::optional<float> min_variance;
    /// VSM and EVSM: light-bleed reduction R in [0, 1), the bound rescaled from [R, 1] to
    /// [0, 1]; 0 is the method as published. A nonzero R is refused for the other formats.
    float light_bleed_reduction = 0.0f;
};

/// Screen pixel of each receiver (dither indexes the blue noise by it; the other lookups
/// ignore it). Both vectors as long as the receivers'.
struct ReceiverPixels {
    std::vector<std::uint32_t> x;
    std::vector<std::uint32_t> y;
    std::size_t size() const noexcept { return x.size(); }
};

// ---- Moments (the host copies of the device math, sat queries)

/// Power moments b1..b4 of z in [-1,1] (b0 = 1 implied).
struct Moments4 {
    float b1 = 0, b2 = 0, b3 = 0, b4 = 0;
};

/// Output of Algorithm 2: two depths y1 <= y2 in [-1,1], weight v2 of y2, offset xi4.
struct NlqTexel {
    float y1 = 0, y2 = 0, v2 = 0, xi4 = 0;
};

// ---- Summed-area tables (build_sat, soft_shade)

/// Which kernels build the table. All give the same bits. The tiled scans read the input
/// twice (totals, then the scan) and write the table once; the carries in between are
/// prefix sums over 1/16 to 1/32 of the texels.
enum class SatKernel {
    automatic,      ///< tiled_cpu on devices that report CPU and not GPU, tiled_gpu on the
                    ///< others (docs/devices.md)
    tiled_gpu,      ///< 32x32 tiles, 32 work-items each, through 4 KiB of local memory one strip of
                    ///< 8 rows at a time: work-items walk the strip's columns, then one row and
                    ///< channel each (one add per texel and direction, conflict-free rotated rows)
    tiled_cpu,      ///< bands of 32 full rows, one work-item each, 16 columns at a time in 16-lane
                    ///< vectors: column walks, then four shuffle-and-add steps across the lanes
                    ///< (what PoCL's CPU device runs well)
    row_per_thread, ///< the papers' baseline: one work-item per row, then one per column
};

struct SatOptions {
    /// N: texels of the largest rectangle that will ever be queried (27 x 27 = 729 by default).
    std::uint32_t max_kernel_texels = 27 * 27;
    DepthRange depth_range = DepthRange::zero_one;
    SatKernel kernel = SatKernel::automatic;
    StageObserver on_stage; ///< the host call's stage timings (none: not timed)
};

/// A table in host memory, or a texture array of `layers` tables (build_sat of a layered
/// DepthImage), layer after layer.
struct SatTable {
    int width = 0;
    int height = 0;
    std::uint32_t max_kernel_texels = 0; ///< N
    std::uint32_t scale = 0;             ///< sat_scale(N)
    /// 4 words per texel (channels R, G, B, A), row-major, rows top to bottom.
    std::vector<std::uint32_t> words;
    int layers = 1; ///< array layers in `words`

    const std::uint32_t* texel(int x, int y, int layer = 0) const {
        using std::size_t;
        return words.data() + 4 * ((size_t(layer) * size_t(height) + size_t(y)) * size_t(width) + size_t(x));
    }
    /// Array layer `index` (0 .. layers - 1) as a table of its own.
    SatTable layer(int index) const;
};

/// A table already on the device: a buffer with 4 uint32 per texel, layout as SatTable.
struct DeviceSat {
    cl_mem buffer = nullptr;
    int width = 0;
    int height = 0;
    std::uint32_t max_kernel_texels = 0; ///< N the table was built for
};

/// A table in a 2D image of CL_RGBA / CL_UNSIGNED_INT32 (interop.hpp, sat_image_format()):
/// its top-left width x height texels, as build_sat_to_image writes them.
struct DeviceSatImage {
    cl_mem image = nullptr;
    int width = 0;
    int height = 0;
    std::uint32_t max_kernel_texels = 0; ///< N the table was built for
};

} // namespace msmcl
