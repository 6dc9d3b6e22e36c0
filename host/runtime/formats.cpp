// Names and sizes of formats and depth conventions.
#include "runtime/texture_kinds.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/formats.hpp>

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

namespace detail {

std::vector<std::string> texture_kind_defines(Format format) {
    std::vector<std::string> defines;
    for (const TextureKind& kind : kTextureKinds)
        if (kind.format)
            defines.push_back(std::string(kind.kernel_constant) + "=" + std::to_string(static_cast<int>(*kind.format)));
    const TextureKind& kind = texture_kind(format);
    defines.push_back(std::string("MSM_FORMAT=") + kind.kernel_constant);
    defines.push_back("MSM_TEXEL_WORDS=" + std::to_string(gpu_format_info(kind).texel_bytes / 4));
    defines.push_back(std::string("MSM_FORMAT_SHIFTED=") + (kind.shifted ? "1" : "0"));
    defines.push_back(std::string("MSM_BLENDS_MOMENTS=") + (kind.blends_moments ? "1" : "0"));
    defines.push_back(std::string("MSM_FLOAT_TEXELS=") + (float_texels(kind) ? "1" : "0"));
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
    return Texture{format, width, height, std::vector<std::uint32_t>(first, first + static_cast<std::ptrdiff_t>(layer_words))};
}

std::uint16_t Texture::code16(int x, int y, int c) const {
    const std::uint32_t word = texel(x, y)[c / 2];
    return static_cast<std::uint16_t>(c % 2 == 0 ? word & 0xffffu : word >> 16);
}

} // namespace msmcl
