// shade: evaluate a filtered moment shadow map at receiver points.
#pragma once

#include <msmcl/context.hpp>
#include <msmcl/enqueue.hpp>
#include <msmcl/formats.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace msmcl {

enum class Lookup {
    nearest,  ///< texel floor(u), floor(v)
    bilinear, ///< between texel centres around (u-0.5, v-0.5): moments for moments128/msm64,
              ///< the four shadow intensities for nlq64/nlq32
    dither,   ///< one texel floor(u - 0.5 + nx), floor(v - 0.5 + ny) with blue noise (nx, ny) in
              ///< [0,1) of the receiver's screen pixel and the frame (docs/math.md);
              ///< averaged over frames, the bilinear blend of the shaded texels
};
const char* lookup_name(Lookup lookup) noexcept;
std::optional<Lookup> parse_lookup(std::string_view name) noexcept;

struct ShadeOptions {
    Lookup lookup = Lookup::bilinear;
    /// Subtracted from the receiver's internal depth z (docs/math.md) before shading.
    float depth_bias = 1e-3f;
    /// Convention of the receivers' z (normally the map's).
    DepthRange depth_range = DepthRange::zero_one;
    /// dither: the frame number; its hash picks the blue-noise texture and its shift.
    std::uint32_t frame = 0;
    /// dither, receivers without explicit pixels: receiver i is pixel (i % screen_width,
    /// i / screen_width) of a row-major image; 0 = one row (pixel (i, 0)).
    std::uint32_t screen_width = 0;
};

/// Screen pixel of each receiver (dither indexes the blue noise by it; the other lookups
/// ignore it). Both vectors as long as the receivers'.
struct ReceiverPixels {
    std::vector<std::uint32_t> x;
    std::vector<std::uint32_t> y;
    std::size_t size() const noexcept { return x.size(); }
};

/// Shadow intensity (0 lit, 1 shadowed) for each receiver. Throws input_error for an
/// empty map, mismatched receiver arrays, or non-finite receiver values.
std::vector<float> shade(Context& context, const Texture& map, const Receivers& receivers,
                         const ShadeOptions& options);
/// The same with the receivers' screen pixels (for dither); also throws input_error when
/// `pixels` differs in length from the receivers.
std::vector<float> shade(Context& context, const Texture& map, const Receivers& receivers,
                         const ReceiverPixels& pixels, const ShadeOptions& options);

/// A filtered map already on the device (a buffer, layout as Texture).
struct DeviceTexture {
    cl_mem buffer = nullptr;
    Format format = Format::nlq64;
    int width = 0;
    int height = 0;
};

/// Device-side shade: `receivers_uvz` holds 3*count floats, planar (all u, then all v,
/// then all z); `intensity` receives count floats.
void shade(Context& context, const DeviceTexture& map, cl_mem receivers_uvz, std::size_t count,
           cl_mem intensity, const ShadeOptions& options, const Enqueue& enqueue = {});
/// The same with the receivers' screen pixels: `receiver_pixels` holds 2*count uints, planar
/// (all x, then all y), or is null (row-major, ShadeOptions::screen_width).
void shade(Context& context, const DeviceTexture& map, cl_mem receivers_uvz, cl_mem receiver_pixels,
           std::size_t count, cl_mem intensity, const ShadeOptions& options, const Enqueue& enqueue = {});

/// The blue noise of the dithered lookup (docs/math.md): void-and-cluster (Ulichney 1993,
/// Gaussian sigma 1.9), generated at build time from a fixed seed: 64 tileable textures of
/// 64x64 texels, 2 channels of 8 bits, each channel a permutation of the levels 0..255 (16
/// texels each). blue_noise_bytes() bytes, byte ((texture * 64 + y) * 64 + x) * 2 + channel;
/// level l stands for the offset (l + 0.5) / 256. kernels/msm_bluenoise.clh indexes it.
const std::uint8_t* blue_noise_textures() noexcept;
std::size_t blue_noise_bytes() noexcept;

} // namespace msmcl
