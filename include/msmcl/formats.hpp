// Texture formats, depth conventions and the host-side image containers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace msmcl {

/// Storage formats of a filtered shadow map: the moment formats (docs/math.md) and the
/// other filterable representations engines ship (docs/formats.md, "Filterable
/// representations"). t is the depth mapped to [0,1] (t = (z + 1)/2), x = 2t - 1 = z.
enum class Format {
    moments128, ///< 4 x float32: b1..b4 of z in [-1,1]
    msm64,      ///< 4 x unorm16 of the optimized affine basis (R,G,B,A)
    nlq64,      ///< 4 x unorm16: (y1+1)/2, (y2+1)/2, v2, Psi4(xi4) (rounded up)
    nlq32,      ///< 1 x uint32: Psi4 (6 bits), sqrt(v2) (7), folded y1 (9), y2 (10)
    vsm32,      ///< 2 x unorm16: (t, t^2) (variance shadow map)
    vsm64,      ///< 2 x float32: (t, t^2)
    evsm2_32,   ///< 2 x half: (p, p^2), p = exp(c+ x) (exponential variance shadow map)
    evsm4_64,   ///< 4 x half: (p, p^2, n, n^2), n = -exp(-c- x)
    evsm4_128,  ///< 4 x float32: as evsm4_64
    esm32,      ///< 1 x float32: exp(c (t - 1)) (exponential shadow map)
};

/// The exponents of the exponential warps (docs/formats.md, "Filterable representations"):
/// EVSM's c+ and c-, ESM's c in `positive`. 0 means the format's default
/// (default_exponents); formats without a warp take none.
struct WarpExponents {
    float positive = 0.f;
    float negative = 0.f;
};
inline bool operator==(WarpExponents a, WarpExponents b) noexcept {
    return a.positive == b.positive && a.negative == b.negative;
}
inline bool operator!=(WarpExponents a, WarpExponents b) noexcept { return !(a == b); }

/// Convention of the depth values as rendered.
enum class DepthRange {
    zero_one,      ///< d in [0,1] (D3D, Vulkan): z = 2d - 1
    minus_one_one, ///< d in [-1,1] (OpenGL): z = d
};

/// "moments128", "msm64", "nlq64", "nlq32", "vsm32", "vsm64", "evsm2_32", "evsm4_64",
/// "evsm4_128", "esm32".
const char* format_name(Format format) noexcept;
/// Inverse of format_name; std::nullopt for an unknown name.
std::optional<Format> parse_format(std::string_view name) noexcept;
/// "0,1" or "-1,1" (the EXR attribute and CLI spelling).
const char* depth_range_name(DepthRange range) noexcept;
std::optional<DepthRange> parse_depth_range(std::string_view name) noexcept;

/// The exponents a format warps with when its filter options give 0: 5.54 for half storage
/// (evsm2_32, evsm4_64: c+ and c-), 40 and 5 for evsm4_128, 80 for esm32 (in `positive`);
/// 0 for the lanes a format has no warp for (the moment formats and VSM have none).
WarpExponents default_exponents(Format format) noexcept;
/// The largest exponents a format stores without Inf: the warp squared fits the storage
/// (half: ln(65504)/2 = 5.545; float32 EVSM: 42, leaving room for the resolve's sum of 16
/// samples; esm32: 88 < ln(FLT_MAX), so that shading's exp(c (1 - t)) stays finite); 0
/// for the lanes without a warp. docs/formats.md derives them.
WarpExponents max_exponents(Format format) noexcept;
/// The exponents a filter of `format` uses for `requested`: 0 replaced by the default.
/// Throws input_error naming the limit for a value that is negative, not finite, beyond
/// max_exponents, or given for a lane the format has no warp for (`what` leads the message).
WarpExponents effective_exponents(Format format, WarpExponents requested, const char* what = "filter");

/// Bytes per texel of a format: 16, 8, 8, 4 (moment formats), 4, 8, 4, 8, 16, 4.
std::size_t texel_bytes(Format format) noexcept;
/// 32-bit words per texel: texel_bytes / 4.
inline std::size_t texel_words(Format format) noexcept { return texel_bytes(format) / 4; }

/// Internal depth z in [-1,1] of a rendered depth value.
inline double to_internal_depth(double d, DepthRange range) noexcept {
    return range == DepthRange::zero_one ? 2.0 * d - 1.0 : d;
}

/// Most layers of a texture array (filter and build_sat of a layered depth map): the least
/// any OpenCL 1.2 device supports for image arrays (CL_DEVICE_IMAGE_MAX_ARRAY_SIZE).
inline constexpr int max_array_layers = 2048;

/// A (multisampled) depth map in host memory, or `layers` of them of one size: the layers
/// of a texture array (the cascades of a cascaded shadow map, the maps of several lights;
/// docs/formats.md, "Texture arrays"). These are array layers, not the translucent layers
/// of TranslucentLayer.
/// Layout: layer after layer; in each, texel-major, the S samples of a texel contiguous:
/// `depth[((layer * height + y) * width + x) * samples + s]`, rows top to bottom.
struct DepthImage {
    int width = 0;
    int height = 0;
    int samples = 1; ///< 1, 2, 4, 8 or 16
    std::vector<float> depth;
    int layers = 1; ///< array layers in `depth`, 1 .. max_array_layers

    float at(int x, int y, int s = 0, int layer = 0) const {
        // Each index converted on its own: the headers compile clean under -Wsign-conversion.
        using std::size_t;
        return depth[((size_t(layer) * size_t(height) + size_t(y)) * size_t(width) + size_t(x)) * size_t(samples) +
                     size_t(s)];
    }
};

/// A filtered moment shadow map in host memory, exactly the bytes of the device texture,
/// or a texture array of `layers` such maps (filter of a layered DepthImage).
/// Layout: layer after layer; in each, row-major, texel_words(format) little-endian 32-bit
/// words per texel.
///  - moments128: words are the float32 bits of b1, b2, b3, b4;
///  - msm64/nlq64: four uint16 codes, channel 0 in the low half of word 0,
///    channel 1 in its high half, channels 2 and 3 likewise in word 1;
///  - nlq32, esm32: one word per texel;
///  - vsm32, evsm2_32: two 16-bit codes (unorm16, half) in one word, channel 0 low;
///  - vsm64: the float32 bits of t, t^2; evsm4_128: of p, p^2, n, n^2;
///  - evsm4_64: four half codes laid out as msm64's.
struct Texture {
    Format format = Format::moments128;
    int width = 0;
    int height = 0;
    std::vector<std::uint32_t> words;
    int layers = 1; ///< array layers in `words`
    /// The warp's exponents the texels were made with (filter writes them, the file readers
    /// and writers keep them, shading reads them); 0 for the lanes without a warp.
    WarpExponents exponents;

    const std::uint32_t* texel(int x, int y, int layer = 0) const {
        using std::size_t;
        return words.data() +
               ((size_t(layer) * size_t(height) + size_t(y)) * size_t(width) + size_t(x)) * texel_words(format);
    }
    /// Array layer `index` (0 .. layers - 1) as a texture of its own.
    Texture layer(int index) const;
    /// moments128 only: moment b_j, j in 1..4.
    float moment(int x, int y, int j) const;
    /// msm64/nlq64 only: the 16-bit code of channel c in 0..3.
    std::uint16_t code16(int x, int y, int c) const;
    /// nlq32 only: the packed word.
    std::uint32_t code32(int x, int y) const { return *texel(x, y); }
};

/// Points at which a shadow map is evaluated (`shade`).
/// u, v: texel units in the map (texel centres at i + 0.5); z: receiver depth in the
/// same convention as the map's depth input. All three vectors have the same length.
struct Receivers {
    std::vector<float> u;
    std::vector<float> v;
    std::vector<float> z;
    std::size_t size() const noexcept { return z.size(); }
};

} // namespace msmcl
