// The one table of the textures msmcl writes (docs/formats.md, "The format table"): one row
// per kind of texture (the four moment formats, summed-area tables, scattering maps) with
// every fact that the library, the file writers and the kernels need about it, and one row
// per GPU pixel format (several kinds share one: msm64 and nlq64 are both 4 x unorm16).
// The kernels see the rows as defines (texture_kind_defines), never as bare numbers.
// Adding a format: a Format value, a row here (and a pixel-format row if its texels are
// new), and its kernel code (encoder, decoder, shading).
#pragma once

#include "shading/texel_shading.hpp"

#include <msmcl/formats.hpp>
#include <msmcl/types.hpp>

#include <CL/cl.h>

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace msmcl::detail {

/// The pixel formats of the GPU containers (KTX2, DDS): the texel bytes as a GPU samples them.
enum class GpuFormat {
    r16g16b16a16_unorm,       ///< msm64, nlq64: 4 x unorm16 (the codes, R first)
    r32_uint,                 ///< nlq32
    r32g32b32a32_sfloat,      ///< moments128: b1..b4
    r32g32b32a32_uint,        ///< summed-area tables: channels R, G, B, A
    a2b10g10r10_unorm_pack32, ///< six-moment single scattering: R bits 0-9, G 10-19, B 20-29, A 30-31
};

/// How a channel's bits read (KTX2 sample qualifiers and range, EXR sample type).
enum class ChannelKind { unorm, uint, sfloat };

struct GpuFormatInfo {
    GpuFormat format;
    const char* name;          ///< "r16g16b16a16_unorm", ...
    std::uint32_t vk_format;   ///< VkFormat (KTX2 vkFormat)
    std::uint32_t dxgi_format; ///< DXGI_FORMAT (DDS DX10 header)
    std::uint32_t texel_bytes; ///< bytes per texel
    std::uint32_t type_size;   ///< KTX2 typeSize: bytes of the component or packed type
    std::uint32_t channels;    ///< components (1 or 4)
    std::uint8_t channel_bits[4]; ///< bits of channel c (R, G, B, A), packed from bit 0 up
    ChannelKind kind;
};

// VkFormat and DXGI_FORMAT values from the Vulkan and DXGI headers; in GpuFormat order.
inline constexpr GpuFormatInfo kGpuFormats[] = {
    // VK_FORMAT_R16G16B16A16_UNORM, DXGI_FORMAT_R16G16B16A16_UNORM
    {GpuFormat::r16g16b16a16_unorm, "r16g16b16a16_unorm", 91, 11, 8, 2, 4, {16, 16, 16, 16}, ChannelKind::unorm},
    // VK_FORMAT_R32_UINT, DXGI_FORMAT_R32_UINT
    {GpuFormat::r32_uint, "r32_uint", 98, 42, 4, 4, 1, {32}, ChannelKind::uint},
    // VK_FORMAT_R32G32B32A32_SFLOAT, DXGI_FORMAT_R32G32B32A32_FLOAT
    {GpuFormat::r32g32b32a32_sfloat, "r32g32b32a32_sfloat", 109, 2, 16, 4, 4, {32, 32, 32, 32}, ChannelKind::sfloat},
    // VK_FORMAT_R32G32B32A32_UINT, DXGI_FORMAT_R32G32B32A32_UINT
    {GpuFormat::r32g32b32a32_uint, "r32g32b32a32_uint", 107, 3, 16, 4, 4, {32, 32, 32, 32}, ChannelKind::uint},
    // VK_FORMAT_A2B10G10R10_UNORM_PACK32, DXGI_FORMAT_R10G10B10A2_UNORM
    {GpuFormat::a2b10g10r10_unorm_pack32, "a2b10g10r10_unorm_pack32", 64, 24, 4, 4, 4, {10, 10, 10, 2},
     ChannelKind::unorm},
};

/// The shading options a format gets where the caller leaves them (shade_defaults,
/// msmcl shade): the depth bias, the lookup and, for VSM and EVSM, the minimum variance.
struct ShadingDefaults {
    float depth_bias;   ///< internal depth units (ShadeOptions::depth_bias)
    Lookup lookup;
    float min_variance; ///< depth units t^2 (docs/math.md); 0 where the format has no variance bound
};
/// Kinds that are not shaded by `shade` (tables, scattering maps).
inline constexpr ShadingDefaults kNotShaded{0.0f, Lookup::nearest, 0.0f};
/// The moment formats: docs/math.md's bias of the receiver, bilinear.
inline constexpr ShadingDefaults kMomentShading{1e-3f, Lookup::bilinear, 0.0f};

/// One kind of texture msmcl writes.
struct TextureKind {
    const char* name;             ///< format_name, the msmcl:format value of EXR and KTX2 files
    std::optional<Format> format; ///< the moment formats; none for tables and scattering maps
    const char* kernel_constant;  ///< the kernels' name of the format (MSM_FORMAT == ...); moment formats only
    GpuFormat gpu_format;         ///< texel bytes, channels, Vulkan/DXGI, KTX2/DDS fields, EXR channels
    cl_channel_order cl_order;    ///< the OpenCL image format of filter_to_image / build_sat_to_image
    cl_channel_type cl_type;
    cl_channel_type cl_type_also; ///< a second channel type the image may have (0: none)
    /// The filter blurs the moments of z - c, c the block's midrange (docs/math.md): the
    /// non-linear formats, whose Algorithm 2 needs moments near 0.
    bool shifted;
    /// Shading: a bilinear lookup blends the moments and shades once (linear formats), else
    /// it shades four texels and blends the intensities.
    bool blends_moments;
    /// The host copy of the format's decoding and shading (host/shading/shading.cpp); null
    /// for the kinds `shade` does not read.
    const TexelShading* host_shading;
    /// The shading options of the format where the caller leaves them.
    ShadingDefaults shading_defaults;
};

// The moment formats first, in Format order (checked below), then the other kinds.
inline constexpr TextureKind kTextureKinds[] = {
    {"moments128", Format::moments128, "MSM_FORMAT_MOMENTS128", GpuFormat::r32g32b32a32_sfloat, CL_RGBA, CL_FLOAT, 0,
     false, true, &kMoments128Shading, kMomentShading},
    {"msm64", Format::msm64, "MSM_FORMAT_MSM64", GpuFormat::r16g16b16a16_unorm, CL_RGBA, CL_UNORM_INT16,
     CL_UNSIGNED_INT16, false, true, &kMsm64Shading, kMomentShading},
    {"nlq64", Format::nlq64, "MSM_FORMAT_NLQ64", GpuFormat::r16g16b16a16_unorm, CL_RGBA, CL_UNORM_INT16,
     CL_UNSIGNED_INT16, true, false, &kNlq64Shading, kMomentShading},
    {"nlq32", Format::nlq32, "MSM_FORMAT_NLQ32", GpuFormat::r32_uint, CL_R, CL_UNSIGNED_INT32, 0, true, false,
     &kNlq32Shading, kMomentShading},
    // Summed-area tables (build_sat): four uint32 sums of a texel's moments.
    {"sat", std::nullopt, nullptr, GpuFormat::r32g32b32a32_uint, CL_RGBA, CL_UNSIGNED_INT32, 0, false, false, nullptr,
     kNotShaded},
    // Prefiltered scattering maps as a renderer uploads them: 6 moments as a 2-layer array
    // (odd powers, even powers), 4 moments in the msm64 layout.
    {"scatter6", std::nullopt, nullptr, GpuFormat::a2b10g10r10_unorm_pack32, 0, 0, 0, false, false, nullptr,
     kNotShaded},
    {"scatter4", std::nullopt, nullptr, GpuFormat::r16g16b16a16_unorm, 0, 0, 0, false, false, nullptr, kNotShaded},
};

inline constexpr bool moment_formats_in_order() {
    std::size_t i = 0;
    for (const TextureKind& kind : kTextureKinds) {
        if (!kind.format) break;
        if (static_cast<std::size_t>(*kind.format) != i++) return false;
    }
    return true;
}
static_assert(moment_formats_in_order(), "the moment formats lead kTextureKinds in Format order");

inline constexpr bool gpu_formats_in_order() {
    for (std::size_t i = 0; i < std::size(kGpuFormats); ++i)
        if (static_cast<std::size_t>(kGpuFormats[i].format) != i) return false;
    return true;
}
static_assert(gpu_formats_in_order(), "kGpuFormats in GpuFormat order");

inline constexpr std::size_t count_moment_formats() {
    std::size_t count = 0;
    for (const TextureKind& kind : kTextureKinds) count += kind.format ? 1 : 0;
    return count;
}
/// Moment formats: Format values 0 .. kMomentFormats - 1.
inline constexpr std::size_t kMomentFormats = count_moment_formats();
/// Whether `format` is one of the table's (a value cast from outside may not be).
inline constexpr bool is_known(Format format) noexcept { return static_cast<std::size_t>(format) < kMomentFormats; }

/// The row of a moment format.
inline const TextureKind& texture_kind(Format format) noexcept { return kTextureKinds[static_cast<std::size_t>(format)]; }
/// The row named `name` ("sat", "scatter6"), if any.
inline constexpr const TextureKind* find_texture_kind(std::string_view name) noexcept {
    for (const TextureKind& kind : kTextureKinds)
        if (name == kind.name) return &kind;
    return nullptr;
}
/// The rows of the kinds that are no moment format.
inline constexpr const TextureKind& kSatKind = *find_texture_kind("sat");
inline constexpr const TextureKind& kScatter6Kind = *find_texture_kind("scatter6");
inline constexpr const TextureKind& kScatter4Kind = *find_texture_kind("scatter4");
/// Every moment format, in Format order.
inline std::vector<Format> moment_formats() {
    std::vector<Format> formats;
    for (std::size_t i = 0; i < kMomentFormats; ++i) formats.push_back(static_cast<Format>(i));
    return formats;
}

/// The moment formats whose texels are `gpu_format` (a DDS file names no format: its texels
/// tell it where one format alone has them).
inline std::vector<Format> formats_with(GpuFormat gpu_format) {
    std::vector<Format> formats;
    for (std::size_t i = 0; i < kMomentFormats; ++i)
        if (kTextureKinds[i].gpu_format == gpu_format) formats.push_back(static_cast<Format>(i));
    return formats;
}

inline const GpuFormatInfo& gpu_format_info(GpuFormat format) noexcept {
    return kGpuFormats[static_cast<std::size_t>(format)];
}
inline const GpuFormatInfo& gpu_format_info(const TextureKind& kind) noexcept { return gpu_format_info(kind.gpu_format); }
/// Whether the texel words of `kind` are the bits of float values (moments128).
inline bool float_texels(const TextureKind& kind) noexcept { return gpu_format_info(kind).kind == ChannelKind::sfloat; }

/// The defines a kernel of moment format `format` compiles with: the names of every
/// format (MSM_FORMAT_MSM64=1, ...), MSM_FORMAT as one of them, and the row's facts
/// (MSM_TEXEL_WORDS, MSM_FORMAT_SHIFTED, MSM_BLENDS_MOMENTS, MSM_FLOAT_TEXELS).
std::vector<std::string> texture_kind_defines(Format format);

} // namespace msmcl::detail
