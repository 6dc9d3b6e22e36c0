// sat: integer modular summed-area tables of moments (docs/math.md) and moment soft
// shadow mapping for a directional light (Peters et al., i3D 2016, section 3).
//
// A table holds, per texel (x, y), four uint32 channels: the prefix sums over all texels
// i <= x, j <= y of round(c * scale), where c are the channels R, G, B, A of the msm64
// affine basis (docs/math.md) of the texel's resolved moments (mean of b(z) over its
// MSAA samples, no blur) and scale = floor((2^32 - 1) / N) for the largest kernel of N
// texels the caller will query. The sums wrap mod 2^32; any rectangle of at most N texels
// comes out exact. Precision: log2(scale) bits per channel (N = 27^2: 22.5 bits).
//
// Queries that would exceed N texels: the host query functions throw input_error; the
// device query kernel writes NaN moments; soft shadows never issue one (the blocker
// search square must satisfy K^2 <= N, checked up front, and the filter side is clamped
// to floor(sqrt(N)) texels, see SoftShadowOptions).
//
// The device functions a renderer includes are in kernels/msm_sat.clh.
#pragma once

#include <msmcl/context.hpp>
#include <msmcl/enqueue.hpp>
#include <msmcl/types.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace msmcl {

/// Smallest and largest N (texels of the largest kernel) a table may declare. N = 1 would
/// need a scale of 2^32 - 1, more than a file's int attribute holds, and allows no filtering.
inline constexpr std::uint32_t sat_min_kernel_texels = 2;
inline constexpr std::uint32_t sat_max_kernel_texels = 0x7fffffffu;

/// floor((2^32 - 1) / N). Throws input_error for N outside
/// [sat_min_kernel_texels, sat_max_kernel_texels].
std::uint32_t sat_scale(std::uint32_t max_kernel_texels);

/// "automatic", "tiled_gpu", "tiled_cpu", "row_per_thread".
const char* sat_kernel_name(SatKernel kernel) noexcept;
std::optional<SatKernel> parse_sat_kernel(std::string_view name) noexcept;
/// The kernel a table build with `requested` runs on the context's device (`automatic`
/// resolved).
SatKernel sat_kernel_for(const Context& context, SatKernel requested);

/// Builds the table of a host depth map. Validates like filter(): size, sample count (1, 2,
/// 4, 8, 16), every depth finite and inside the range (input_error names the first bad
/// texel), and N.
SatTable build_sat(Context& context, const DepthImage& depth, const SatOptions& options);

/// Device version: `depth` as for filter(); `table` a buffer of at least
/// 16 * width * height bytes. Depth values are not validated (out-of-range values clamp to
/// the range, NaN counts as the near plane), like filter().
void build_sat(Context& context, const DeviceDepth& depth, cl_mem table, const SatOptions& options,
               const Enqueue& enqueue = {});

/// Tables of translucent shadow maps (docs/math.md): each sample's surfaces composited as
/// filter() composites them (TranslucentLayer), the texel the mean of the composited
/// moments over its samples. Validates the layers like filter(). No layers: exactly
/// build_sat(context, depth, options); layers of opacity 0 give the same bits as none.
SatTable build_sat(Context& context, const DepthImage& depth, const std::vector<TranslucentLayer>& layers,
                   const SatOptions& options);
/// Device version (DeviceLayers as for filter()); one more pass over the texels than an
/// opaque table (composite and quantize, then the same prefix sums).
void build_sat(Context& context, const DeviceDepth& depth, const DeviceLayers& layers, cl_mem table,
               const SatOptions& options, const Enqueue& enqueue = {});

/// The prefix sums alone, for callers that quantize their own texels: `texels` holds 4
/// uint32 per texel (row-major), the result the wrapping 2D prefix sums.
std::vector<std::uint32_t> sat_prefix_sums(Context& context, const std::vector<std::uint32_t>& texels, int width,
                                           int height, SatKernel kernel = SatKernel::automatic);
/// Device version: `texels` and `table` buffers of at least 16 * width * height bytes each,
/// distinct.
void sat_prefix_sums(Context& context, cl_mem texels, cl_mem table, int width, int height,
                     SatKernel kernel = SatKernel::automatic, const Enqueue& enqueue = {});

// ---- Queries on the host (the functions of kernels/msm_sat.clh compiled as C++).

/// Exact channel sums over the texels [x0, x1] x [y0, y1] (inclusive). Throws input_error
/// when the rectangle is empty, leaves the table or holds more than N texels.
std::array<std::uint32_t, 4> sat_rectangle_sum(const SatTable& table, int x0, int y0, int x1, int y1);

/// Mean power moments b1..b4 (unbiased) over the texels [x0, x1] x [y0, y1]: the exact
/// sum converted to float, divided by scale and area, affine basis inverted.
Moments4 sat_rectangle_moments(const SatTable& table, int x0, int y0, int x1, int y1);

/// A rectangle in texel units with arbitrary corners: [left, right) x [top, bottom), texel
/// i covering [i, i + 1).
struct SatRectangle {
    float left = 0, top = 0, right = 0, bottom = 0;
};

/// Mean power moments over the rectangle, each texel weighted by its covered area (the
/// interpolated query: 4x4 table entries, 3x3 exact sums converted to float one by one).
/// Throws input_error when the rectangle is empty, not finite, leaves [0, width] x
/// [0, height], or one of its 3x3 sub-rectangles holds more than N texels.
Moments4 sat_interpolated_moments(const SatTable& table, const SatRectangle& rectangle);

/// Device queries: `rectangles` holds 4 floats per query (left, top, right, bottom);
/// `moments` receives 4 floats per query (b1..b4, as sat_interpolated_moments). A
/// rectangle that is empty, not finite, leaves the map or exceeds N texels gives NaN.
void sat_query_moments(Context& context, const DeviceSat& table, cl_mem rectangles, std::size_t count,
                       cl_mem moments, const Enqueue& enqueue = {});

// ---- Moment soft shadows (directional light).

struct SoftShadowOptions {
    /// Penumbra width in texels per unit of internal depth z (in [-1,1]) between receiver
    /// and average blocker: filter side = light_size * (zf - z_blocker). For a light of
    /// angular diameter theta, a light frustum depth of D world units (z spans 2) and
    /// texels of t world units: light_size = tan(theta) * D / (2 t). Finite, >= 0.
    float light_size = 64.0f;
    /// Side K of the texel-aligned blocker search square (texels); 0 = floor(sqrt(N)).
    /// K^2 must not exceed N.
    int search_size = 0;
    /// Smallest filter side in texels (the fully lit and contact case), in (0, floor(sqrt(N))].
    float min_filter_size = 1.0f;
    /// Subtracted from the receiver's internal depth before shading.
    float depth_bias = 1e-3f;
    /// Convention of the receivers' z.
    DepthRange depth_range = DepthRange::zero_one;
    /// Refinements of the published method that leak less light than it against brute-force
    /// PCSS (docs/soft_shadows.md); receiver_blocker_weight = 0 and filter_parts = 1 give
    /// the method of Peters et al., i3D 2016, section 3.
    /// Share k of the receiver's own reconstructed point (weight w0 at zf) that the average
    /// blocker depth counts as blockers at zf: ((eps + k w0) zf + sum w_i z_i) / (eps + k w0
    /// + sum w_i). In [0, 1]; free.
    float receiver_blocker_weight = 0.1f;
    /// The filter square split into filter_parts x filter_parts equal parts, each with its
    /// own 4MSM bound, averaged by area. In [1, 4]; costs a query and a 4MSM bound per part.
    int filter_parts = 2;
    StageObserver on_stage; ///< the host call's stage timings (none: not timed)
};

/// The blocker search side and the largest filter side (floor(sqrt(N))) the options give
/// for a table of N texels; throws input_error for invalid options.
struct SoftShadowLimits {
    int search_size = 0;
    float max_filter_size = 0;
};
SoftShadowLimits soft_shadow_limits(std::uint32_t max_kernel_texels, const SoftShadowOptions& options);

/// Shadow intensity (0 lit, 1 shadowed) per receiver (u, v in texels, z as rendered).
/// Receivers outside the map clamp to its edge. Throws input_error for an invalid table,
/// options, mismatched receiver arrays or non-finite receiver values.
std::vector<float> soft_shade(Context& context, const SatTable& table, const Receivers& receivers,
                              const SoftShadowOptions& options);

/// Device version: `receivers_uvz` holds 3 * count floats, planar (all u, then all v,
/// then all z); `intensity` receives count floats.
void soft_shade(Context& context, const DeviceSat& table, cl_mem receivers_uvz, std::size_t count,
                cl_mem intensity, const SoftShadowOptions& options, const Enqueue& enqueue = {});
/// The same from a table image: one device copy of the table into a staging buffer, then
/// the buffer call. Throws input_error for a wrong object, format or size before anything
/// is enqueued.
void soft_shade(Context& context, const DeviceSatImage& table, cl_mem receivers_uvz, std::size_t count,
                cl_mem intensity, const SoftShadowOptions& options, const Enqueue& enqueue = {});

/// The same soft shadow of one receiver computed on the host (float32, the code of
/// kernels/msm_sat.clh), for tools and tests without a device.
float soft_shadow_at(const SatTable& table, float u, float v, float z, const SoftShadowOptions& options);

} // namespace msmcl
