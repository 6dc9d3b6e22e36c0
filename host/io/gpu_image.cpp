// Pixel format table and conversions of host/io/gpu_image.hpp.
#include "io/gpu_image.hpp"

#include <msmcl/errors.hpp>

#include <cstring>

namespace msmcl::io {

namespace {

// VkFormat and DXGI_FORMAT values from the Vulkan and DXGI headers.
constexpr GpuFormatInfo kFormats[] = {
    {"r16g16b16a16_unorm", 91, 11, 8, 2, 4},       // VK_FORMAT_R16G16B16A16_UNORM, DXGI_FORMAT_R16G16B16A16_UNORM
    {"r32_uint", 98, 42, 4, 4, 1},                 // VK_FORMAT_R32_UINT, DXGI_FORMAT_R32_UINT
    {"r32g32b32a32_sfloat", 109, 2, 16, 4, 4},     // VK_FORMAT_R32G32B32A32_SFLOAT, DXGI_FORMAT_R32G32B32A32_FLOAT
    {"r32g32b32a32_uint", 107, 3, 16, 4, 4},       // VK_FORMAT_R32G32B32A32_UINT, DXGI_FORMAT_R32G32B32A32_UINT
    {"a2b10g10r10_unorm_pack32", 64, 24, 4, 4, 4}, // VK_FORMAT_A2B10G10R10_UNORM_PACK32, DXGI_FORMAT_R10G10B10A2_UNORM
};
constexpr GpuFormat kAllFormats[] = {GpuFormat::r16g16b16a16_unorm, GpuFormat::r32_uint, GpuFormat::r32g32b32a32_sfloat,
                                     GpuFormat::r32g32b32a32_uint, GpuFormat::a2b10g10r10_unorm_pack32};

// `layers` > 1: a texture array (KTX2 layerCount, DDS arraySize); one layer: a 2D texture.
GpuImage image_of_words(GpuFormat format, int width, int height, int layers, const std::vector<std::uint32_t>& words) {
    GpuImage image;
    image.format = format;
    image.width = width;
    image.height = height;
    image.layers = layers;
    image.array = layers > 1;
    // Little-endian words, as the device wrote them (x86 and ARM hosts are little-endian).
    image.bytes.resize(words.size() * sizeof(std::uint32_t));
    if (!words.empty()) std::memcpy(image.bytes.data(), words.data(), image.bytes.size());
    return image;
}

} // namespace

const GpuFormatInfo& gpu_format_info(GpuFormat format) noexcept { return kFormats[static_cast<int>(format)]; }

std::optional<GpuFormat> gpu_format_from_vk(std::uint32_t vk_format) noexcept {
    for (GpuFormat format : kAllFormats)
        if (gpu_format_info(format).vk_format == vk_format) return format;
    return std::nullopt;
}

std::optional<GpuFormat> gpu_format_from_dxgi(std::uint32_t dxgi_format) noexcept {
    for (GpuFormat format : kAllFormats)
        if (gpu_format_info(format).dxgi_format == dxgi_format) return format;
    return std::nullopt;
}

std::optional<std::string> GpuImage::find_metadata(const std::string& key) const {
    for (const auto& entry : metadata)
        if (entry.first == key) return entry.second;
    return std::nullopt;
}

GpuFormat gpu_format_of(Format format) noexcept {
    switch (format) {
    case Format::moments128: return GpuFormat::r32g32b32a32_sfloat;
    case Format::msm64:
    case Format::nlq64: return GpuFormat::r16g16b16a16_unorm;
    case Format::nlq32: return GpuFormat::r32_uint;
    }
    return GpuFormat::r32_uint;
}

GpuImage gpu_image_of(const Texture& texture, std::vector<std::pair<std::string, std::string>> metadata) {
    GpuImage image =
        image_of_words(gpu_format_of(texture.format), texture.width, texture.height, texture.layers, texture.words);
    image.metadata.emplace_back("msmcl:format", format_name(texture.format));
    for (auto& entry : metadata) image.metadata.push_back(std::move(entry));
    return image;
}

GpuImage gpu_image_of(const SatTable& table) {
    GpuImage image = image_of_words(GpuFormat::r32g32b32a32_uint, table.width, table.height, table.layers, table.words);
    image.metadata = {{"msmcl:format", "sat"},
                      {"msmcl:maxKernelTexels", std::to_string(table.max_kernel_texels)},
                      {"msmcl:scale", std::to_string(table.scale)}};
    return image;
}

Texture texture_of(const GpuImage& image, Format format, const std::string& name) {
    if (image.format != gpu_format_of(format))
        throw input_error(name + ": holds " + gpu_format_info(image.format).name + " texels, a " + format_name(format) +
                          " texture is " + gpu_format_info(gpu_format_of(format)).name);
    if (image.bytes.size() != image.expected_bytes())
        throw input_error(name + ": holds " + std::to_string(image.bytes.size()) + " bytes of texels, expected " +
                          std::to_string(image.expected_bytes()));
    Texture texture;
    texture.format = format;
    texture.width = image.width;
    texture.height = image.height;
    texture.layers = image.layers;
    texture.words.resize(image.bytes.size() / sizeof(std::uint32_t));
    if (!image.bytes.empty()) std::memcpy(texture.words.data(), image.bytes.data(), image.bytes.size());
    return texture;
}

} // namespace msmcl::io
