// Host copies of the device math: the consumer-side shading of kernels/msm_shading.clh,
// the blue noise of kernels/msm_bluenoise.clh and the moment math of msm_moments.clh (the
// very same sources compiled as C++, float32), for tools and tests that need the device's
// results without a device.
#pragma once

#include <msmcl/types.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace msmcl {

/// b' = (1 - alpha) b + alpha (0, bstar, 0, bstar).
Moments4 bias_moments(const Moments4& b, float alpha, float bstar);
/// Algorithm 2 (with the float32 guard) on biased single-precision moments.
NlqTexel nlq_from_moments(const Moments4& biased);
float psi4(float xi4);
float psi4_inverse(float psi);

/// Decoders of one texel, given its words as stored in a Texture.
Moments4 decode_moments128(const std::uint32_t* words);
Moments4 decode_msm64(const std::uint32_t* words);
NlqTexel decode_nlq64(const std::uint32_t* words);
NlqTexel decode_nlq32(std::uint32_t word);

/// Hamburger 4MSM lower bound on the share of depth below zf (Algorithm 1), from biased
/// moments; the upper bound adds the weight w0 at zf.
float hamburger4_lower(const Moments4& biased, float zf);
float hamburger4_upper(const Moments4& biased, float zf);
/// Accurate lower bound for the linear formats from UNBIASED moments (raw moments128, or
/// decoded msm64) and their bias (alpha, bstar): moments about their mean in float-float,
/// biased there, then the 4MSM; what shade_texel runs for moments128. hamburger4_lower on
/// bias_moments(...) is the fast float32 path: where alpha is small (moments128, 3e-7) it
/// keeps one or two digits of the biased variance in flat regions.
float linear_shadow(const Moments4& unbiased, float alpha, float bstar, float zf);
/// Algorithm 3 (lower bound) from a decoded nlq texel.
float nlq_shadow(const NlqTexel& texel, float zf);

/// Shadow intensity of one texel of `map` at internal depth zf (bias of the format
/// applied), the device's per-texel shading, with the format's default minimum variance
/// (VSM, EVSM) and no light-bleed reduction.
float shade_texel(const Texture& map, int x, int y, float zf);
/// The same with the minimum variance and light-bleed reduction of `options` (VSM, EVSM).
float shade_texel(const Texture& map, int x, int y, float zf, const ShadeOptions& options);

/// One quantity a texel holds, decoded (what `msmcl info` counts): its name ("b1", "y1",
/// "t", "p", ...) and the range its meaning allows.
struct DecodedQuantity {
    std::string name;
    double min = 0;
    double max = 0;
};
/// The quantities of a texel of `texture`'s format (1 to 4; the ranges of warps from the
/// texture's exponents).
std::vector<DecodedQuantity> decoded_quantities(const Texture& texture);
/// Decodes texel `index` of `texture.words` (every layer, row-major: index < width * height
/// * layers) into decoded_quantities(texture).size() values.
void decode_texel(const Texture& texture, std::size_t index, float values[4]);
/// The whole lookup of the `shade` kernel for one receiver (u, v in texels, z as
/// rendered), on the host. A dithered lookup counts the receiver as screen pixel (0, 0).
float shade_receiver(const Texture& map, float u, float v, float z, const ShadeOptions& options);
/// The same for a receiver at screen pixel (px, py) (what dither indexes the blue noise by).
float shade_receiver(const Texture& map, float u, float v, float z, std::uint32_t px, std::uint32_t py,
                     const ShadeOptions& options);

/// The blue noise of the dithered lookup: void-and-cluster (Ulichney 1993,
/// Gaussian sigma 1.9), generated at build time from a fixed seed: 64 tileable textures of
/// 64x64 texels, 2 channels of 8 bits, each channel a permutation of the levels 0..255 (16
/// texels each). blue_noise_bytes() bytes, byte ((texture * 64 + y) * 64 + x) * 2 + channel;
/// level l stands for the offset (l + 0.5) / 256. kernels/msm_bluenoise.clh indexes it.
const std::uint8_t* blue_noise_textures() noexcept;
std::size_t blue_noise_bytes() noexcept;

/// The blue-noise texture and shift of a frame (kernels/msm_bluenoise.clh).
struct BlueNoiseFrame {
    std::uint32_t texture = 0;  ///< 0..63
    std::uint32_t offset_x = 0; ///< 0..63
    std::uint32_t offset_y = 0; ///< 0..63
};
BlueNoiseFrame blue_noise_frame(std::uint32_t frame);
/// Dither offsets in (0, 1) of screen pixel (px, py) in `frame` (from blue_noise_textures()).
struct DitherNoise {
    float x = 0.5f;
    float y = 0.5f;
};
DitherNoise blue_noise_at(std::uint32_t frame, std::uint32_t px, std::uint32_t py);

} // namespace msmcl
