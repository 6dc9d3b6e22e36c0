// Textures as a GPU takes them, for the texture containers (ktx2.hpp, dds.hpp): the exact
// Vulkan / DXGI pixel format and the packed texel bytes, rows top to bottom.
#pragma once

#include "runtime/texture_kinds.hpp"

#include <msmcl/types.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace msmcl::io {

/// The pixel formats msmcl writes and their facts: rows of the format table.
using detail::GpuFormat;
using detail::GpuFormatInfo;
using detail::gpu_format_info;
/// The format with this VkFormat or DXGI_FORMAT value, if msmcl writes it.
std::optional<GpuFormat> gpu_format_from_vk(std::uint32_t vk_format) noexcept;
std::optional<GpuFormat> gpu_format_from_dxgi(std::uint32_t dxgi_format) noexcept;

/// A 2D texture or 2D texture array of one mip level: `layers` images of width x height
/// texels (layer after layer, rows top to bottom, texels packed, little-endian).
struct GpuImage {
    GpuFormat format = GpuFormat::r32_uint;
    int width = 0;
    int height = 0;
    int layers = 1;      ///< images in `bytes`
    bool array = false;  ///< a texture array (also with one layer) rather than a plain 2D texture
    std::vector<std::uint8_t> bytes;
    /// Key/value pairs written into KTX2 files (sorted on write; DDS has no place for them).
    std::vector<std::pair<std::string, std::string>> metadata;

    std::size_t expected_bytes() const {
        return static_cast<std::size_t>(width) * height * layers * gpu_format_info(format).texel_bytes;
    }
    /// The value of metadata key `key`, if present.
    std::optional<std::string> find_metadata(const std::string& key) const;
};

/// The GPU format of a texture: r32g32b32a32_sfloat, r16g16b16a16_unorm (msm64, nlq64), r32_uint.
GpuFormat gpu_format_of(Format format) noexcept;

/// A texture with the bytes of Texture::words (a texture array for Texture::layers > 1);
/// metadata msmcl:format plus `metadata`.
GpuImage gpu_image_of(const Texture& texture, std::vector<std::pair<std::string, std::string>> metadata = {});
/// A summed-area table (r32g32b32a32_uint, an array for SatTable::layers > 1); metadata msmcl:format "sat", msmcl:maxKernelTexels, msmcl:scale.
GpuImage gpu_image_of(const SatTable& table);

/// The texture of `format` held by `image` (of the matching GPU format; a texture array
/// gives a Texture of as many layers). Throws input_error naming `name` on a mismatch.
Texture texture_of(const GpuImage& image, Format format, const std::string& name);

} // namespace msmcl::io
