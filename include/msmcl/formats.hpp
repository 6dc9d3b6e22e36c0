// Texture formats, depth conventions and the host-side image containers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace msmcl {

/// Storage formats of a filtered moment shadow map (docs/math.md).
enum class Format {
    moments128, ///< 4 x float32: b1..b4 of z in [-1,1]
    msm64,      ///< 4 x unorm16 of the optimized affine basis (R,G,B,A)
    nlq64,      ///< 4 x unorm16: (y1+1)/2, (y2+1)/2, v2, Psi4(xi4) (rounded up)
    nlq32,      ///< 1 x uint32: Psi4 (6 bits), sqrt(v2) (7), folded y1 (9), y2 (10)
};

/// Convention of the depth values as rendered.
enum class DepthRange {
    zero_one,      ///< d in [0,1] (D3D, Vulkan): z = 2d - 1
    minus_one_one, ///< d in [-1,1] (OpenGL): z = d
};

/// "moments128", "msm64", "nlq64", "nlq32".
const char* format_name(Format format) noexcept;
/// Inverse of format_name; std::nullopt for an unknown name.
std::optional<Format> parse_format(std::string_view name) noexcept;
/// "0,1" or "-1,1" (the EXR attribute and CLI spelling).
const char* depth_range_name(DepthRange range) noexcept;
std::optional<DepthRange> parse_depth_range(std::string_view name) noexcept;

/// Bytes per texel of a format: 16, 8, 8, 4.
std::size_t texel_bytes(Format format) noexcept;
/// 32-bit words per texel: 4, 2, 2, 1.
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
///  - nlq32: one word per texel.
struct Texture {
    Format format = Format::moments128;
    int width = 0;
    int height = 0;
    std::vector<std::uint32_t> words;
    int layers = 1; ///< array layers in `words`

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
