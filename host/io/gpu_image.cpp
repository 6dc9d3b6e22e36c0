// Pixel format table and conversions of host/io/gpu_image.hpp.
#include "io/gpu_image.hpp"

#include "io/texture_metadata.hpp"

#include <msmcl/errors.hpp>

#include <cstring>

namespace msmcl::io {

namespace {

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

std::optional<GpuFormat> gpu_format_from_vk(std::uint32_t vk_format) noexcept {
    for (const GpuFormatInfo& info : detail::kGpuFormats)
        if (info.vk_format == vk_format) return info.format;
    return std::nullopt;
}

std::optional<GpuFormat> gpu_format_from_dxgi(std::uint32_t dxgi_format) noexcept {
    for (const GpuFormatInfo& info : detail::kGpuFormats)
        if (info.dxgi_format == dxgi_format) return info.format;
    return std::nullopt;
}

std::optional<std::string> GpuImage::find_metadata(const std::string& key) const {
    for (const auto& entry : metadata)
        if (entry.first == key) return entry.second;
    return std::nullopt;
}

GpuFormat gpu_format_of(Format format) noexcept { return detail::texture_kind(format).gpu_format; }

GpuImage gpu_image_of(const Texture& texture, std::vector<std::pair<std::string, std::string>> metadata) {
    GpuImage image =
        image_of_words(gpu_format_of(texture.format), texture.width, texture.height, texture.layers, texture.words);
    image.metadata.emplace_back("msmcl:format", format_name(texture.format));
    if (const std::optional<std::string> record = exponents_record(texture))
        image.metadata.emplace_back("msmcl:exponents", *record);
    for (auto& entry : metadata) image.metadata.push_back(std::move(entry));
    return image;
}

GpuImage gpu_image_of(const SatTable& table) {
    GpuImage image = image_of_words(detail::kSatKind.gpu_format, table.width, table.height, table.layers, table.words);
    image.metadata = {{"msmcl:format", detail::kSatKind.name},
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
    texture.exponents = exponents_of_record(image.find_metadata("msmcl:exponents"), format, name);
    texture.words.resize(image.bytes.size() / sizeof(std::uint32_t));
    if (!image.bytes.empty()) std::memcpy(texture.words.data(), image.bytes.data(), image.bytes.size());
    return texture;
}

} // namespace msmcl::io
