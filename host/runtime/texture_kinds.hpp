// The one table of the textures msmcl writes (docs/formats.md, "The format table"): one row
// per kind of texture (the filter formats: the four moment formats and the VSM, EVSM and
// ESM formats; summed-area tables, scattering maps) with
// every fact that the library, the file writers and the kernels need about it, and one row
// per GPU pixel format (several kinds share one: msm64 and nlq64 are both 4 x unorm16).
// The kernels see the rows as defines (texture_kind_defines), never as bare numbers.
// Adding a format: a Format value, a row here (and a pixel-format row if its texels are
// new), and its kernel code (warp, encoder, decoder, shading).
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
    r16g16_unorm,             ///< vsm32: t, t^2
    r32g32_sfloat,            ///< vsm64: t, t^2
    r16g16_sfloat,            ///< evsm2_32: p, p^2 (half)
    r16g16b16a16_sfloat,      ///< evsm4_64: p, p^2, n, n^2 (half)
    r32_sfloat,               ///< esm32
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
    std::uint32_t channels;    ///< components (1, 2 or 4)
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
    // VK_FORMAT_R16G16_UNORM, DXGI_FORMAT_R16G16_UNORM
    {GpuFormat::r16g16_unorm, "r16g16_unorm", 77, 35, 4, 2, 2, {16, 16}, ChannelKind::unorm},
    // VK_FORMAT_R32G32_SFLOAT, DXGI_FORMAT_R32G32_FLOAT
    {GpuFormat::r32g32_sfloat, "r32g32_sfloat", 103, 16, 8, 4, 2, {32, 32}, ChannelKind::sfloat},
    // VK_FORMAT_R16G16_SFLOAT, DXGI_FORMAT_R16G16_FLOAT
    {GpuFormat::r16g16_sfloat, "r16g16_sfloat", 83, 34, 4, 2, 2, {16, 16}, ChannelKind::sfloat},
    // VK_FORMAT_R16G16B16A16_SFLOAT, DXGI_FORMAT_R16G16B16A16_FLOAT
    {GpuFormat::r16g16b16a16_sfloat, "r16g16b16a16_sfloat", 97, 10, 8, 2, 4, {16, 16, 16, 16}, ChannelKind::sfloat},
    // VK_FORMAT_R32_SFLOAT, DXGI_FORMAT_R32_FLOAT
    {GpuFormat::r32_sfloat, "r32_sfloat", 100, 41, 4, 4, 1, {32}, ChannelKind::sfloat},
};

/// What a filter format's texels hold, each with its kernel constant (MSM_REPRESENTATION ==
/// MSM_REPRESENTATION_VSM, ...) and its shading (docs/formats.md, "Filterable
/// representations"): power moments (Hamburger 4MSM), (t, t^2) (Chebyshev), the EVSM warps
/// (p, p^2) and (p, p^2, n, n^2) (Chebyshev, the lesser bound), ESM's exp(c (t - 1)).
enum class Representation { moments, vsm, evsm2, evsm4, esm };
struct RepresentationInfo {
    Representation representation;
    const char* name;            ///< "moments", "vsm", ...
    const char* kernel_constant; ///< MSM_REPRESENTATION_MOMENTS, ...
    std::uint32_t lanes;         ///< values per sample the filter averages and blurs (of its 4 lanes)
    const char* map_kind;        ///< what `msmcl info` calls a map of it: "moment shadow map", ...
};
inline constexpr RepresentationInfo kRepresentations[] = {
    {Representation::moments, "moments", "MSM_REPRESENTATION_MOMENTS", 4, "moment shadow map"},
    {Representation::vsm, "vsm", "MSM_REPRESENTATION_VSM", 2, "variance shadow map"},
    {Representation::evsm2, "evsm2", "MSM_REPRESENTATION_EVSM2", 2, "exponential variance shadow map"},
    {Representation::evsm4, "evsm4", "MSM_REPRESENTATION_EVSM4", 4, "exponential variance shadow map"},
    {Representation::esm, "esm", "MSM_REPRESENTATION_ESM", 1, "exponential shadow map"},
};
inline const RepresentationInfo& representation_info(Representation representation) noexcept {
    return kRepresentations[static_cast<std::size_t>(representation)];
}

/// The exponents of a warp: its default and its largest safe value (formats.hpp,
/// default_exponents and max_exponents; docs/formats.md derives them). All 0: no warp.
struct WarpLimits {
    WarpExponents defaults;
    WarpExponents largest;
};
// Half storage: p^2 <= 65504 (largest half) for c <= ln(65504)/2 = 5.545. float32 EVSM:
// the resolve sums up to 16 squared warps before it divides, 16 exp(2c) < FLT_MAX for
// c < 42.9. esm32: exp(c (t - 1)) <= 1 always; shading multiplies by exp(c (1 - t_r)),
// finite for c < ln(FLT_MAX) = 88.72.
inline constexpr WarpLimits kNoWarp{{0.f, 0.f}, {0.f, 0.f}};
inline constexpr WarpLimits kEvsmHalf{{5.54f, 5.54f}, {5.54f, 5.54f}};
inline constexpr WarpLimits kEvsm2Half{{5.54f, 0.f}, {5.54f, 0.f}};
inline constexpr WarpLimits kEvsmFloat{{40.f, 5.f}, {42.f, 42.f}};
inline constexpr WarpLimits kEsmFloat{{80.f, 0.f}, {88.f, 0.f}};

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
inline constexpr ShadingDefaults kMomentDefaults{1e-3f, Lookup::bilinear, 0.0f};
// VSM and EVSM: the same bias and lookup, a minimum variance above what the storage's rounding
// does to the variance m2 - m1^2 (docs/formats.md, "Shading defaults"): unorm16 (t, t^2) up to
// 2.3e-5; half EVSM 3 * 2^-11 w^2, i.e. V = 1.2e-5 through the slope 2 c w at c = 5.54; float
// (t, t^2) ~1e-7 after the blur; float EVSM 3 * 2^-24 w^2, V = 1.8e-9 at c- = 5.
inline constexpr ShadingDefaults kVsm32Defaults{1e-3f, Lookup::bilinear, 3e-5f};
inline constexpr ShadingDefaults kVsm64Defaults{1e-3f, Lookup::bilinear, 1e-6f};
inline constexpr ShadingDefaults kEvsmHalfDefaults{1e-3f, Lookup::bilinear, 2e-5f};
inline constexpr ShadingDefaults kEvsmFloatDefaults{1e-3f, Lookup::bilinear, 2e-8f};
// ESM: the same bias and lookup (no variance).
inline constexpr ShadingDefaults kEsmDefaults{1e-3f, Lookup::bilinear, 0.0f};

/// One kind of texture msmcl writes.
struct TextureKind {
    const char* name;             ///< format_name, the msmcl:format value of EXR and KTX2 files
    std::optional<Format> format; ///< the filter formats; none for tables and scattering maps
    const char* kernel_constant;  ///< the kernels' name of the format (MSM_FORMAT == ...); filter formats only
    GpuFormat gpu_format;         ///< texel bytes, channels, Vulkan/DXGI, KTX2/DDS fields, EXR channels
    cl_channel_order cl_order;    ///< the OpenCL image format of filter_to_image / build_sat_to_image
    cl_channel_type cl_type;
    cl_channel_type cl_type_also; ///< a second channel type the image may have (0: none)
    /// The filter blurs the moments of z - c, c the block's midrange (docs/math.md): the
    /// non-linear formats, whose Algorithm 2 needs moments near 0.
    bool shifted;
    /// Shading: a bilinear lookup blends the moments and shades once (linear formats), else
    /// it shades four texels and blends the intensities. The VSM, EVSM and ESM formats blend
    /// their stored values, as hardware filtering does.
    bool blends_moments;
    /// What the texels hold (moments for the four moment formats and for the other kinds).
    Representation representation;
    /// The warp's exponents (kNoWarp: none).
    WarpLimits warp;
    /// The host copy of the format's decoding and shading (host/shading/shading.cpp); null
    /// for the kinds `shade` does not read.
    const TexelShading* host_shading;
    /// The shading options of the format where the caller leaves them.
    ShadingDefaults shading_defaults;
};

// The filter formats first, in Format order (checked below), then the other kinds.
inline constexpr TextureKind kTextureKinds[] = {
    {"moments128", Format::moments128, "MSM_FORMAT_MOMENTS128", GpuFormat::r32g32b32a32_sfloat, CL_RGBA, CL_FLOAT, 0,
     false, true, Representation::moments, kNoWarp, &kMoments128Shading, kMomentDefaults},
    {"msm64", Format::msm64, "MSM_FORMAT_MSM64", GpuFormat::r16g16b16a16_unorm, CL_RGBA, CL_UNORM_INT16,
     CL_UNSIGNED_INT16, false, true, Representation::moments, kNoWarp, &kMsm64Shading, kMomentDefaults},
    {"nlq64", Format::nlq64, "MSM_FORMAT_NLQ64", GpuFormat::r16g16b16a16_unorm, CL_RGBA, CL_UNORM_INT16,
     CL_UNSIGNED_INT16, true, false, Representation::moments, kNoWarp, &kNlq64Shading, kMomentDefaults},
    {"nlq32", Format::nlq32, "MSM_FORMAT_NLQ32", GpuFormat::r32_uint, CL_R, CL_UNSIGNED_INT32, 0, true, false,
     Representation::moments, kNoWarp, &kNlq32Shading, kMomentDefaults},
    {"vsm32", Format::vsm32, "MSM_FORMAT_VSM32", GpuFormat::r16g16_unorm, CL_RG, CL_UNORM_INT16, CL_UNSIGNED_INT16,
     false, true, Representation::vsm, kNoWarp, &kVsm32Shading, kVsm32Defaults},
    {"vsm64", Format::vsm64, "MSM_FORMAT_VSM64", GpuFormat::r32g32_sfloat, CL_RG, CL_FLOAT, 0, false, true,
     Representation::vsm, kNoWarp, &kVsm64Shading, kVsm64Defaults},
    {"evsm2_32", Format::evsm2_32, "MSM_FORMAT_EVSM2_32", GpuFormat::r16g16_sfloat, CL_RG, CL_HALF_FLOAT, 0, false,
     true, Representation::evsm2, kEvsm2Half, &kEvsm2_32Shading, kEvsmHalfDefaults},
    {"evsm4_64", Format::evsm4_64, "MSM_FORMAT_EVSM4_64", GpuFormat::r16g16b16a16_sfloat, CL_RGBA, CL_HALF_FLOAT, 0,
     false, true, Representation::evsm4, kEvsmHalf, &kEvsm4_64Shading, kEvsmHalfDefaults},
    {"evsm4_128", Format::evsm4_128, "MSM_FORMAT_EVSM4_128", GpuFormat::r32g32b32a32_sfloat, CL_RGBA, CL_FLOAT, 0,
     false, true, Representation::evsm4, kEvsmFloat, &kEvsm4_128Shading, kEvsmFloatDefaults},
    {"esm32", Format::esm32, "MSM_FORMAT_ESM32", GpuFormat::r32_sfloat, CL_R, CL_FLOAT, 0, false, true,
     Representation::esm, kEsmFloat, &kEsm32Shading, kEsmDefaults},
    // Summed-area tables (build_sat): four uint32 sums of a texel's moments.
    {"sat", std::nullopt, nullptr, GpuFormat::r32g32b32a32_uint, CL_RGBA, CL_UNSIGNED_INT32, 0, false, false,
     Representation::moments, kNoWarp, nullptr, kNotShaded},
    // Prefiltered scattering maps as a renderer uploads them: 6 moments as a 2-layer array
    // (odd powers, even powers), 4 moments in the msm64 layout.
    {"scatter6", std::nullopt, nullptr, GpuFormat::a2b10g10r10_unorm_pack32, 0, 0, 0, false, false,
     Representation::moments, kNoWarp, nullptr, kNotShaded},
    {"scatter4", std::nullopt, nullptr, GpuFormat::r16g16b16a16_unorm, 0, 0, 0, false, false, Representation::moments,
     kNoWarp, nullptr, kNotShaded},
};

inline constexpr bool filter_formats_in_order() {
    std::size_t i = 0;
    for (const TextureKind& kind : kTextureKinds) {
        if (!kind.format) break;
        if (static_cast<std::size_t>(*kind.format) != i++) return false;
    }
    return true;
}
static_assert(filter_formats_in_order(), "the filter formats lead kTextureKinds in Format order");

inline constexpr bool representations_in_order() {
    for (std::size_t i = 0; i < std::size(kRepresentations); ++i)
        if (static_cast<std::size_t>(kRepresentations[i].representation) != i) return false;
    return true;
}
static_assert(representations_in_order(), "kRepresentations in Representation order");

inline constexpr bool gpu_formats_in_order() {
    for (std::size_t i = 0; i < std::size(kGpuFormats); ++i)
        if (static_cast<std::size_t>(kGpuFormats[i].format) != i) return false;
    return true;
}
static_assert(gpu_formats_in_order(), "kGpuFormats in GpuFormat order");

inline constexpr std::size_t count_filter_formats() {
    std::size_t count = 0;
    for (const TextureKind& kind : kTextureKinds) count += kind.format ? 1 : 0;
    return count;
}
/// Filter formats: Format values 0 .. kFilterFormats - 1.
inline constexpr std::size_t kFilterFormats = count_filter_formats();
/// Whether `format` is one of the table's (a value cast from outside may not be).
inline constexpr bool is_known(Format format) noexcept { return static_cast<std::size_t>(format) < kFilterFormats; }

/// The row of a filter format.
inline const TextureKind& texture_kind(Format format) noexcept { return kTextureKinds[static_cast<std::size_t>(format)]; }
/// The row named `name` ("sat", "scatter6"), if any.
inline constexpr const TextureKind* find_texture_kind(std::string_view name) noexcept {
    for (const TextureKind& kind : kTextureKinds)
        if (name == kind.name) return &kind;
    return nullptr;
}
/// The rows of the kinds that are no filter format.
inline constexpr const TextureKind& kSatKind = *find_texture_kind("sat");
inline constexpr const TextureKind& kScatter6Kind = *find_texture_kind("scatter6");
inline constexpr const TextureKind& kScatter4Kind = *find_texture_kind("scatter4");
/// Every filter format, in Format order.
inline std::vector<Format> filter_formats() {
    std::vector<Format> formats;
    for (std::size_t i = 0; i < kFilterFormats; ++i) formats.push_back(static_cast<Format>(i));
    return formats;
}
/// The representation of a filter format, and whether it is one of the moment formats.
inline Representation representation_of(Format format) noexcept { return texture_kind(format).representation; }
inline bool is_moment_format(Format format) noexcept { return representation_of(format) == Representation::moments; }
/// The filter formats of one representation, in Format order.
inline std::vector<Format> formats_of(Representation representation) {
    std::vector<Format> formats;
    for (Format format : filter_formats())
        if (representation_of(format) == representation) formats.push_back(format);
    return formats;
}

/// The filter formats whose texels are `gpu_format` (a DDS file names no format: its texels
/// tell it where one format alone has them).
inline std::vector<Format> formats_with(GpuFormat gpu_format) {
    std::vector<Format> formats;
    for (std::size_t i = 0; i < kFilterFormats; ++i)
        if (kTextureKinds[i].gpu_format == gpu_format) formats.push_back(static_cast<Format>(i));
    return formats;
}

inline const GpuFormatInfo& gpu_format_info(GpuFormat format) noexcept {
    return kGpuFormats[static_cast<std::size_t>(format)];
}
inline const GpuFormatInfo& gpu_format_info(const TextureKind& kind) noexcept { return gpu_format_info(kind.gpu_format); }
/// Whether the texel words of `kind` are the bits of float32 values (moments128, vsm64,
/// evsm4_128, esm32; the half formats pack two codes a word and are not).
inline bool float_texels(const TextureKind& kind) noexcept {
    return gpu_format_info(kind).kind == ChannelKind::sfloat && gpu_format_info(kind).channel_bits[0] == 32;
}

/// The defines a kernel of filter format `format` compiles with: the names of every
/// format (MSM_FORMAT_MSM64=1, ...) and representation (MSM_REPRESENTATION_VSM=1, ...),
/// MSM_FORMAT and MSM_REPRESENTATION as one of them, the row's facts (MSM_TEXEL_WORDS,
/// MSM_FORMAT_SHIFTED, MSM_BLENDS_MOMENTS, MSM_FLOAT_TEXELS, MSM_HALF_TEXELS) and the warp's
/// exponents MSM_WARP_POSITIVE, MSM_WARP_NEGATIVE (effective_exponents of `exponents`, as
/// float literals; 0 without a warp).
std::vector<std::string> texture_kind_defines(Format format, WarpExponents exponents = {});
/// A float as short as reads back exactly ("5.54"): the exponents in messages and records.
std::string shortest_text(float value);
/// Whether the texels of `kind` are half floats (evsm2_32, evsm4_64).
inline bool half_texels(const TextureKind& kind) noexcept {
    return gpu_format_info(kind).kind == ChannelKind::sfloat && gpu_format_info(kind).channel_bits[0] == 16;
}

} // namespace msmcl::detail
