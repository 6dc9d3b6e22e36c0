// DDS (DX10 header) writer and reader (layout in dds.hpp).
#include "io/dds.hpp"

#include "io/atomic_file.hpp"
#include "io/image_limits.hpp"

#include <msmcl/errors.hpp>

namespace msmcl::io {

namespace {

constexpr std::uint32_t kMagic = 0x20534444u; // "DDS "
constexpr std::uint32_t kHeaderSize = 124;
constexpr std::uint32_t kPixelFormatSize = 32;
constexpr std::size_t kDataOffset = 4 + 124 + 20;
// dwFlags
constexpr std::uint32_t kDdsdCaps = 0x1, kDdsdHeight = 0x2, kDdsdWidth = 0x4, kDdsdPitch = 0x8;
constexpr std::uint32_t kDdsdPixelFormat = 0x1000, kDdsdMipMapCount = 0x20000, kDdsdDepth = 0x800000;
constexpr std::uint32_t kDdpfFourCC = 0x4;
constexpr std::uint32_t kFourCCDx10 = 0x30315844u; // "DX10"
constexpr std::uint32_t kDdsCapsTexture = 0x1000;
constexpr std::uint32_t kCaps2Cubemap = 0x200, kCaps2Volume = 0x200000;
constexpr std::uint32_t kResourceTexture2D = 3;
constexpr std::uint32_t kMiscTextureCube = 0x4;
constexpr std::uint32_t kAlphaModeUnknown = 0, kAlphaModeCustom = 4;

void put32(std::vector<std::uint8_t>& out, std::uint32_t value) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

std::uint32_t get32(const std::vector<std::uint8_t>& bytes, std::size_t at) {
    std::uint32_t value = 0;
    for (int i = 0; i < 4; ++i) value |= std::uint32_t(bytes[at + i]) << (8 * i);
    return value;
}

} // namespace

std::vector<std::uint8_t> encode_dds(const GpuImage& image) {
    const GpuFormatInfo& info = gpu_format_info(image.format);
    if (image.width <= 0 || image.height <= 0 || image.layers <= 0 || (!image.array && image.layers != 1))
        throw input_error("DDS: cannot store a " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                          " image of " + std::to_string(image.layers) + " layers");
    if (image.bytes.size() != image.expected_bytes())
        throw input_error("DDS: the image holds " + std::to_string(image.bytes.size()) + " bytes, expected " +
                          std::to_string(image.expected_bytes()));
    std::vector<std::uint8_t> out;
    out.reserve(kDataOffset + image.bytes.size());
    put32(out, kMagic);
    // DDS_HEADER
    put32(out, kHeaderSize);
    put32(out, kDdsdCaps | kDdsdHeight | kDdsdWidth | kDdsdPitch | kDdsdPixelFormat | kDdsdMipMapCount);
    put32(out, static_cast<std::uint32_t>(image.height));
    put32(out, static_cast<std::uint32_t>(image.width));
    put32(out, static_cast<std::uint32_t>(image.width) * info.texel_bytes); // row pitch
    put32(out, 0);                                                         // dwDepth
    put32(out, 1);                                                         // dwMipMapCount
    for (int i = 0; i < 11; ++i) put32(out, 0);                            // dwReserved1
    // DDS_PIXELFORMAT: the format is in the DX10 header.
    put32(out, kPixelFormatSize);
    put32(out, kDdpfFourCC);
    put32(out, kFourCCDx10);
    for (int i = 0; i < 5; ++i) put32(out, 0); // bit count, R, G, B, A masks
    put32(out, kDdsCapsTexture);
    for (int i = 0; i < 4; ++i) put32(out, 0); // dwCaps2, dwCaps3, dwCaps4, dwReserved2
    // DDS_HEADER_DXT10
    put32(out, info.dxgi_format);
    put32(out, kResourceTexture2D);
    put32(out, 0); // miscFlag
    put32(out, static_cast<std::uint32_t>(image.layers));
    put32(out, info.channels == 4 ? kAlphaModeCustom : kAlphaModeUnknown);
    out.insert(out.end(), image.bytes.begin(), image.bytes.end());
    return out;
}

GpuImage decode_dds(const std::vector<std::uint8_t>& bytes, const std::string& name) {
    if (bytes.size() < kDataOffset) throw input_error(name + ": truncated DDS file (" + std::to_string(bytes.size()) + " bytes)");
    if (get32(bytes, 0) != kMagic) throw input_error(name + ": not a DDS file (wrong magic)");
    if (get32(bytes, 4) != kHeaderSize || get32(bytes, 76) != kPixelFormatSize)
        throw input_error(name + ": corrupt DDS header (wrong structure sizes)");
    const std::uint32_t flags = get32(bytes, 8);
    const std::uint32_t height = get32(bytes, 12), width = get32(bytes, 16);
    const std::uint32_t mip_levels = (flags & kDdsdMipMapCount) ? get32(bytes, 28) : 1;
    if ((get32(bytes, 80) & kDdpfFourCC) == 0 || get32(bytes, 84) != kFourCCDx10)
        throw input_error(name + ": DDS file without a DX10 header (legacy pixel formats are not supported)");
    if ((flags & kDdsdDepth) || (get32(bytes, 112) & (kCaps2Cubemap | kCaps2Volume)))
        throw input_error(name + ": volume and cube DDS files are not supported");
    if (mip_levels > 1) throw input_error(name + ": expected one mip level, found " + std::to_string(mip_levels));
    if (width == 0 || height == 0 || width > 65536 || height > 65536)
        throw input_error(name + ": unsupported size " + std::to_string(width) + "x" + std::to_string(height));
    const std::uint32_t dxgi_format = get32(bytes, 128);
    const std::optional<GpuFormat> format = gpu_format_from_dxgi(dxgi_format);
    if (!format) throw input_error(name + ": unsupported DXGI format " + std::to_string(dxgi_format));
    if (get32(bytes, 132) != kResourceTexture2D || (get32(bytes, 136) & kMiscTextureCube))
        throw input_error(name + ": not a 2D texture");
    const std::uint32_t layers = get32(bytes, 140);
    if (layers == 0 || layers > 65536) throw input_error(name + ": array size " + std::to_string(layers));

    GpuImage image;
    image.format = *format;
    image.width = static_cast<int>(width);
    image.height = static_cast<int>(height);
    image.layers = static_cast<int>(layers);
    image.array = layers > 1;
    const std::size_t needed = image.expected_bytes();
    // Exactly the texels the header describes: more means the header is not the image's.
    if (bytes.size() - kDataOffset != needed)
        throw input_error(name + ": " + std::string(bytes.size() - kDataOffset < needed ? "truncated DDS file: " : "DDS file of the wrong size: ") + std::to_string(bytes.size() - kDataOffset) +
                          " bytes of texels, a " + std::to_string(width) + "x" + std::to_string(height) + " " +
                          gpu_format_info(*format).name + " image of " + std::to_string(layers) + " layers needs " +
                          std::to_string(needed));
    image.bytes.assign(bytes.begin() + kDataOffset, bytes.begin() + static_cast<std::ptrdiff_t>(kDataOffset + needed));
    return image;
}

void write_dds(const std::string& path, const GpuImage& image) {
    std::vector<std::uint8_t> bytes;
    try {
        bytes = encode_dds(image);
    } catch (const input_error& e) {
        throw input_error(path + ": " + e.what());
    }
    write_file_atomically(path, bytes.data(), bytes.size());
}

GpuImage read_dds(const std::string& path) {
    // The magic before the rest: a file of another kind is refused unread.
    const std::string content = read_input_file(path, {image_limits().max_bytes, "MSMCL_MAX_BYTES", "DDS ", "a DDS file"});
    return decode_dds(std::vector<std::uint8_t>(content.begin(), content.end()), path);
}

} // namespace msmcl::io
