// Names and sizes of formats and depth conventions.
#include "runtime/texture_kinds.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/formats.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace msmcl {

const char* format_name(Format format) noexcept {
    return detail::is_known(format) ? detail::texture_kind(format).name : "unknown";
}

std::optional<Format> parse_format(std::string_view name) noexcept {
    const detail::TextureKind* kind = detail::find_texture_kind(name);
    return kind ? kind->format : std::nullopt;
}

const char* depth_range_name(DepthRange range) noexcept {
    return range == DepthRange::zero_one ? "0,1" : "-1,1";
}

std::optional<DepthRange> parse_depth_range(std::string_view name) noexcept {
    if (name == "0,1") return DepthRange::zero_one;
    if (name == "-1,1") return DepthRange::minus_one_one;
    return std::nullopt;
}

std::size_t texel_bytes(Format format) noexcept {
    return detail::is_known(format) ? detail::gpu_format_info(detail::texture_kind(format)).texel_bytes : 0;
}

WarpExponents default_exponents(Format format) noexcept {
    return detail::is_known(format) ? detail::texture_kind(format).warp.defaults : WarpExponents{};
}

WarpExponents max_exponents(Format format) noexcept {
    return detail::is_known(format) ? detail::texture_kind(format).warp.largest : WarpExponents{};
}

std::string detail::shortest_text(float value) {
    char text[32];
    for (int digits = 1; digits <= 9; ++digits) {
        std::snprintf(text, sizeof text, "%.*g", digits, double(value));
        if (std::strtof(text, nullptr) == value) break;
    }
    return text;
}

namespace {

using detail::shortest_text;

// One exponent of `requested`: 0 -> the default; else within (0, largest].
float effective_exponent(Format format, float requested, float fallback, float largest, const char* lane,
                         const char* what) {
    const std::string prefix = std::string(what) + ": exponent " + lane + " " + shortest_text(requested) + " of " +
                               format_name(format);
    if (largest == 0.0f) {
        if (requested != 0.0f) throw input_error(prefix + ": the format has no such warp");
        return 0.0f;
    }
    if (!std::isfinite(requested) || requested < 0.0f)
        throw input_error(prefix + ": exponents are finite and > 0 (0 = the default " + shortest_text(fallback) + ")");
    if (requested > largest)
        throw input_error(prefix + " is beyond its safe limit " + shortest_text(largest) +
                          " (the stored warp would overflow; docs/formats.md)");
    return requested == 0.0f ? fallback : requested;
}

} // namespace

WarpExponents effective_exponents(Format format, WarpExponents requested, const char* what) {
    if (!detail::is_known(format)) throw input_error(std::string(what) + ": unknown format");
    const detail::WarpLimits& warp = detail::texture_kind(format).warp;
    return {effective_exponent(format, requested.positive, warp.defaults.positive, warp.largest.positive, "c+", what),
            effective_exponent(format, requested.negative, warp.defaults.negative, warp.largest.negative, "c-", what)};
}

namespace detail {

namespace {
// A float as an OpenCL C literal that reads back exactly: "0x1.628f5cp+2f".
std::string float_literal(float value) {
    char text[48];
    std::snprintf(text, sizeof text, "%af", double(value));
    return text;
}
} // namespace

std::vector<std::string> texture_kind_defines(Format format, WarpExponents exponents) {
    std::vector<std::string> defines;
    for (const TextureKind& kind : kTextureKinds)
        if (kind.format)
            defines.push_back(std::string(kind.kernel_constant) + "=" + std::to_string(static_cast<int>(*kind.format)));
    for (const RepresentationInfo& representation : kRepresentations)
        defines.push_back(std::string(representation.kernel_constant) + "=" +
                          std::to_string(static_cast<int>(representation.representation)));
    const TextureKind& kind = texture_kind(format);
    defines.push_back(std::string("MSM_FORMAT=") + kind.kernel_constant);
    defines.push_back(std::string("MSM_REPRESENTATION=") + representation_info(kind.representation).kernel_constant);
    defines.push_back("MSM_TEXEL_WORDS=" + std::to_string(gpu_format_info(kind).texel_bytes / 4));
    defines.push_back(std::string("MSM_FORMAT_SHIFTED=") + (kind.shifted ? "1" : "0"));
    defines.push_back(std::string("MSM_BLENDS_MOMENTS=") + (kind.blends_moments ? "1" : "0"));
    defines.push_back(std::string("MSM_FLOAT_TEXELS=") + (float_texels(kind) ? "1" : "0"));
    defines.push_back(std::string("MSM_HALF_TEXELS=") + (half_texels(kind) ? "1" : "0"));
    const WarpExponents warp = effective_exponents(format, exponents, "filter");
    defines.push_back("MSM_WARP_POSITIVE=" + float_literal(warp.positive));
    defines.push_back("MSM_WARP_NEGATIVE=" + float_literal(warp.negative));
    return defines;
}

} // namespace detail

float Texture::moment(int x, int y, int j) const {
    float value;
    std::memcpy(&value, texel(x, y) + (j - 1), sizeof value);
    return value;
}

Texture Texture::layer(int index) const {
    if (index < 0 || index >= layers)
        throw input_error("texture: array layer " + std::to_string(index) + " of a texture of " +
                          std::to_string(layers) + " layers");
    const std::size_t layer_words = static_cast<std::size_t>(width) * height * texel_words(format);
    if (words.size() != layer_words * static_cast<std::size_t>(layers))
        throw input_error("texture: holds " + std::to_string(words.size()) + " words, " + std::to_string(layers) +
                          " layers need " + std::to_string(layer_words * static_cast<std::size_t>(layers)));
    const auto first = words.begin() + static_cast<std::ptrdiff_t>(layer_words * static_cast<std::size_t>(index));
    return Texture{format, width, height, std::vector<std::uint32_t>(first, first + static_cast<std::ptrdiff_t>(layer_words)),
                   1, exponents};
}

std::uint16_t Texture::code16(int x, int y, int c) const {
    const std::uint32_t word = texel(x, y)[c / 2];
    return static_cast<std::uint16_t>(c % 2 == 0 ? word & 0xffffu : word >> 16);
}

} // namespace msmcl
