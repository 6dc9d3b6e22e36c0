// Names and sizes of formats and depth conventions.
#include "runtime/enum_names.hpp"

#include <msmcl/formats.hpp>

#include <cstring>

namespace msmcl {

// The names of Format values, both ways (format_name, parse_format).
constexpr detail::EnumNames<Format> format_names[] = {
    {Format::moments128, "moments128"},
    {Format::msm64, "msm64"},
    {Format::nlq64, "nlq64"},
    {Format::nlq32, "nlq32"},
};

const char* format_name(Format format) noexcept { return detail::name_in(format_names, format); }

std::optional<Format> parse_format(std::string_view name) noexcept { return detail::parse_in(format_names, name); }

const char* depth_range_name(DepthRange range) noexcept {
    return range == DepthRange::zero_one ? "0,1" : "-1,1";
}

std::optional<DepthRange> parse_depth_range(std::string_view name) noexcept {
    if (name == "0,1") return DepthRange::zero_one;
    if (name == "-1,1") return DepthRange::minus_one_one;
    return std::nullopt;
}

std::size_t texel_bytes(Format format) noexcept {
    switch (format) {
        case Format::moments128: return 16;
        case Format::msm64:
        case Format::nlq64: return 8;
        case Format::nlq32: return 4;
    }
    return 0;
}

float Texture::moment(int x, int y, int j) const {
    float value;
    std::memcpy(&value, texel(x, y) + (j - 1), sizeof value);
    return value;
}

std::uint16_t Texture::code16(int x, int y, int c) const {
    const std::uint32_t word = texel(x, y)[c / 2];
    return static_cast<std::uint16_t>(c % 2 == 0 ? word & 0xffffu : word >> 16);
}

} // namespace msmcl
