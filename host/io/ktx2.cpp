// KTX 2.0 writer and reader (layout in ktx2.hpp).
#include "io/ktx2.hpp"

#include "io/atomic_file.hpp"
#include "io/image_limits.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/version.hpp>

#include <algorithm>
#include <cstring>
#include <numeric>

namespace msmcl::io {

namespace {

constexpr std::uint8_t kIdentifier[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
constexpr std::size_t kHeaderBytes = 80;     // identifier, header, index
constexpr std::size_t kLevelIndexBytes = 24; // one level

// Khronos Data Format 1.3 constants.
constexpr std::uint32_t kDfVersion13 = 2;
constexpr std::uint32_t kDfModelRgbsda = 1;
constexpr std::uint32_t kDfPrimariesBt709 = 1;
constexpr std::uint32_t kDfTransferLinear = 1;
constexpr std::uint32_t kDfChannelAlpha = 15;
constexpr std::uint32_t kDfQualifierFloat = 0x80;
constexpr std::uint32_t kDfQualifierSigned = 0x40;
constexpr std::uint32_t kFloatOne = 0x3F800000u;      // 1.0f
constexpr std::uint32_t kFloatMinusOne = 0xBF800000u; // -1.0f

// One sample of the descriptor: channel (0 R, 1 G, 2 B, 3 A), bits at offset.
struct Sample {
    std::uint32_t channel, offset, bits;
};

void put32(std::vector<std::uint8_t>& out, std::uint32_t value) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}
void set32(std::vector<std::uint8_t>& out, std::size_t at, std::uint32_t value) {
    for (int i = 0; i < 4; ++i) out[at + i] = static_cast<std::uint8_t>(value >> (8 * i));
}
void set64(std::vector<std::uint8_t>& out, std::size_t at, std::uint64_t value) {
    for (int i = 0; i < 8; ++i) out[at + i] = static_cast<std::uint8_t>(value >> (8 * i));
}
void pad_to(std::vector<std::uint8_t>& out, std::size_t alignment) {
    while (out.size() % alignment != 0) out.push_back(0);
}

// Bounds-checked little-endian reads.
struct Reader {
    const std::vector<std::uint8_t>& bytes;
    const std::string& name;

    void need(std::uint64_t at, std::uint64_t size, const char* what) const {
        if (at > bytes.size() || size > bytes.size() - at)
            throw input_error(name + ": truncated KTX2 file (" + what + " at byte " + std::to_string(at) + ")");
    }
    std::uint32_t u32(std::uint64_t at, const char* what) const {
        need(at, 4, what);
        std::uint32_t value = 0;
        for (int i = 0; i < 4; ++i) value |= std::uint32_t(bytes[at + i]) << (8 * i);
        return value;
    }
    std::uint64_t u64(std::uint64_t at, const char* what) const {
        return std::uint64_t(u32(at, what)) | (std::uint64_t(u32(at + 4, what)) << 32);
    }
};

// The channels of the format's texel, packed from bit 0 up.
std::vector<Sample> samples_of(GpuFormat format) {
    const GpuFormatInfo& info = gpu_format_info(format);
    std::vector<Sample> samples;
    std::uint32_t offset = 0;
    for (std::uint32_t c = 0; c < info.channels; ++c) {
        samples.push_back({c, offset, info.channel_bits[c]});
        offset += info.channel_bits[c];
    }
    return samples;
}

// The key/value data block: sorted by key (byte-wise), each entry padded to 4 bytes.
std::vector<std::uint8_t> key_value_data(const GpuImage& image) {
    std::vector<std::pair<std::string, std::string>> entries = image.metadata;
    entries.emplace_back("KTXorientation", "rd");
    entries.emplace_back("KTXwriter", std::string("msmcl ") + version_string);
    std::sort(entries.begin(), entries.end());
    for (std::size_t i = 1; i < entries.size(); ++i)
        if (entries[i].first == entries[i - 1].first)
            throw input_error("KTX2: metadata key '" + entries[i].first + "' appears twice");
    std::vector<std::uint8_t> out;
    for (const auto& [key, value] : entries) {
        if (key.empty() || key.find('\0') != std::string::npos)
            throw input_error("KTX2: metadata keys must be non-empty and free of NUL bytes");
        // Values are UTF-8 strings with their terminating NUL, as the KTX keys use them.
        put32(out, static_cast<std::uint32_t>(key.size() + 1 + value.size() + 1));
        out.insert(out.end(), key.begin(), key.end());
        out.push_back(0);
        out.insert(out.end(), value.begin(), value.end());
        out.push_back(0);
        pad_to(out, 4);
    }
    return out;
}

} // namespace

std::vector<std::uint32_t> ktx2_data_format_descriptor(GpuFormat format) {
    const GpuFormatInfo& info = gpu_format_info(format);
    const std::vector<Sample> samples = samples_of(format);
    const std::uint32_t block_bytes = 24 + 16 * static_cast<std::uint32_t>(samples.size());
    std::vector<std::uint32_t> words;
    words.push_back(4 + block_bytes);                       // dfdTotalSize
    words.push_back(0);                                     // vendorId KHR, descriptorType basic
    words.push_back(kDfVersion13 | (block_bytes << 16));    // versionNumber, descriptorBlockSize
    words.push_back(kDfModelRgbsda | (kDfPrimariesBt709 << 8) | (kDfTransferLinear << 16)); // flags 0: straight alpha
    words.push_back(0);                                     // texel block 1x1x1x1
    words.push_back(info.texel_bytes);                      // bytesPlane0
    words.push_back(0);                                     // bytesPlane4..7
    for (const Sample& sample : samples) {
        std::uint32_t channel = sample.channel == 3 ? kDfChannelAlpha : sample.channel;
        std::uint32_t lower = 0, upper = 0;
        switch (info.kind) {
        case detail::ChannelKind::unorm: upper = (1u << sample.bits) - 1u; break; // normalized: max code
        case detail::ChannelKind::uint: upper = 1u; break;                        // integers: 1 stands for 1
        case detail::ChannelKind::sfloat:
            channel |= kDfQualifierFloat | kDfQualifierSigned;
            lower = kFloatMinusOne;
            upper = kFloatOne;
            break;
        }
        words.push_back(sample.offset | ((sample.bits - 1) << 16) | (channel << 24));
        words.push_back(0); // sample position
        words.push_back(lower);
        words.push_back(upper);
    }
    return words;
}

std::vector<std::uint8_t> encode_ktx2(const GpuImage& image) {
    const GpuFormatInfo& info = gpu_format_info(image.format);
    if (image.width <= 0 || image.height <= 0 || image.layers <= 0 || (!image.array && image.layers != 1))
        throw input_error("KTX2: cannot store a " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                          " image of " + std::to_string(image.layers) + " layers");
    if (image.bytes.size() != image.expected_bytes())
        throw input_error("KTX2: the image holds " + std::to_string(image.bytes.size()) + " bytes, expected " +
                          std::to_string(image.expected_bytes()));

    std::vector<std::uint8_t> out(kIdentifier, kIdentifier + sizeof kIdentifier);
    // Header.
    put32(out, info.vk_format);
    put32(out, info.type_size);
    put32(out, static_cast<std::uint32_t>(image.width));
    put32(out, static_cast<std::uint32_t>(image.height));
    put32(out, 0); // pixelDepth: 2D
    put32(out, image.array ? static_cast<std::uint32_t>(image.layers) : 0u);
    put32(out, 1); // faceCount
    put32(out, 1); // levelCount
    put32(out, 0); // supercompressionScheme: none
    // Index and level index, filled in below.
    out.resize(kHeaderBytes + kLevelIndexBytes, 0);

    // Data format descriptor.
    const std::size_t dfd_offset = out.size();
    for (std::uint32_t word : ktx2_data_format_descriptor(image.format)) put32(out, word);
    const std::size_t dfd_length = out.size() - dfd_offset;
    // Key/value data.
    const std::size_t kvd_offset = out.size();
    const std::vector<std::uint8_t> kvd = key_value_data(image);
    out.insert(out.end(), kvd.begin(), kvd.end());
    // Level 0, aligned to lcm(texel bytes, 4).
    pad_to(out, std::lcm<std::size_t>(info.texel_bytes, 4));
    const std::size_t level_offset = out.size();
    out.insert(out.end(), image.bytes.begin(), image.bytes.end());

    set32(out, 48, static_cast<std::uint32_t>(dfd_offset));
    set32(out, 52, static_cast<std::uint32_t>(dfd_length));
    set32(out, 56, kvd.empty() ? 0u : static_cast<std::uint32_t>(kvd_offset));
    set32(out, 60, static_cast<std::uint32_t>(kvd.size()));
    set64(out, 64, 0); // sgdByteOffset
    set64(out, 72, 0); // sgdByteLength
    set64(out, 80, level_offset);
    set64(out, 88, image.bytes.size());
    set64(out, 96, image.bytes.size()); // uncompressedByteLength
    return out;
}

GpuImage decode_ktx2(const std::vector<std::uint8_t>& bytes, const std::string& name) {
    const Reader in{bytes, name};
    in.need(0, kHeaderBytes + kLevelIndexBytes, "header");
    if (!std::equal(kIdentifier, kIdentifier + sizeof kIdentifier, bytes.begin()))
        throw input_error(name + ": not a KTX2 file (wrong identifier)");
    const std::uint32_t vk_format = in.u32(12, "vkFormat");
    const std::optional<GpuFormat> format = gpu_format_from_vk(vk_format);
    if (!format) throw input_error(name + ": unsupported vkFormat " + std::to_string(vk_format));
    const GpuFormatInfo& info = gpu_format_info(*format);
    GpuImage image;
    image.format = *format;
    if (in.u32(16, "typeSize") != info.type_size)
        throw input_error(name + ": typeSize " + std::to_string(in.u32(16, "typeSize")) + " does not match vkFormat");
    const std::uint32_t width = in.u32(20, "pixelWidth"), height = in.u32(24, "pixelHeight");
    const std::uint32_t depth = in.u32(28, "pixelDepth"), layers = in.u32(32, "layerCount");
    const std::uint32_t faces = in.u32(36, "faceCount"), levels = in.u32(40, "levelCount");
    if (width == 0 || height == 0 || width > 65536 || height > 65536 || depth != 0 || layers > 65536)
        throw input_error(name + ": not a 2D texture or array of a supported size");
    if (faces != 1) throw input_error(name + ": cube maps are not supported");
    if (levels != 1) throw input_error(name + ": expected one mip level, found levelCount " + std::to_string(levels));
    if (in.u32(44, "supercompressionScheme") != 0) throw input_error(name + ": supercompressed files are not supported");
    image.width = static_cast<int>(width);
    image.height = static_cast<int>(height);
    image.array = layers > 0;
    image.layers = layers > 0 ? static_cast<int>(layers) : 1;

    // The descriptor must be the one of the format.
    const std::uint32_t dfd_offset = in.u32(48, "dfdByteOffset"), dfd_length = in.u32(52, "dfdByteLength");
    const std::vector<std::uint32_t> expected = ktx2_data_format_descriptor(*format);
    if (dfd_length != expected.size() * 4)
        throw input_error(name + ": data format descriptor of " + std::to_string(dfd_length) + " bytes, expected " +
                          std::to_string(expected.size() * 4) + " for " + info.name);
    for (std::size_t i = 0; i < expected.size(); ++i)
        if (in.u32(dfd_offset + 4 * i, "data format descriptor") != expected[i])
            throw input_error(name + ": data format descriptor word " + std::to_string(i) + " does not describe " +
                              info.name);

    // Key/value pairs.
    const std::uint32_t kvd_offset = in.u32(56, "kvdByteOffset"), kvd_length = in.u32(60, "kvdByteLength");
    in.need(kvd_offset, kvd_length, "key/value data");
    for (std::uint64_t at = kvd_offset; at < std::uint64_t(kvd_offset) + kvd_length;) {
        const std::uint32_t length = in.u32(at, "key/value length");
        in.need(at + 4, length, "key/value pair");
        const char* text = reinterpret_cast<const char*>(bytes.data() + at + 4);
        const std::size_t key_length = strnlen(text, length);
        if (key_length == length) throw input_error(name + ": key/value pair without a NUL after its key");
        std::string value(text + key_length + 1, length - key_length - 1);
        if (!value.empty() && value.back() == '\0') value.pop_back();
        image.metadata.emplace_back(std::string(text, key_length), value);
        at += 4 + (std::uint64_t(length) + 3) / 4 * 4;
    }
    if (in.u64(72, "sgdByteLength") != 0) throw input_error(name + ": unexpected supercompression global data");

    // The one level.
    const std::uint64_t level_offset = in.u64(80, "level byteOffset"), level_length = in.u64(88, "level byteLength");
    if (in.u64(96, "level uncompressedByteLength") != level_length || level_length != image.expected_bytes())
        throw input_error(name + ": level 0 holds " + std::to_string(level_length) + " bytes, a " +
                          std::to_string(width) + "x" + std::to_string(height) + " " + info.name + " image of " +
                          std::to_string(image.layers) + " layers needs " + std::to_string(image.expected_bytes()));
    if (level_offset % std::lcm<std::uint64_t>(info.texel_bytes, 4) != 0)
        throw input_error(name + ": level 0 is not aligned");
    // The texels follow the header, the level index, the descriptor and the key/value data
    // (KTX 2.0 section 3: file structure); data overlapping them is no image.
    const std::uint64_t indexes_end = std::max({std::uint64_t(kHeaderBytes + kLevelIndexBytes),
                                                std::uint64_t(dfd_offset) + dfd_length,
                                                std::uint64_t(kvd_offset) + kvd_length});
    if (level_offset < indexes_end)
        throw input_error(name + ": level 0 starts at byte " + std::to_string(level_offset) +
                          ", inside the header and its indexes (which end at byte " + std::to_string(indexes_end) + ")");
    in.need(level_offset, level_length, "level 0");
    image.bytes.assign(bytes.begin() + static_cast<std::ptrdiff_t>(level_offset),
                       bytes.begin() + static_cast<std::ptrdiff_t>(level_offset + level_length));
    return image;
}

void write_ktx2(const std::string& path, const GpuImage& image) {
    std::vector<std::uint8_t> bytes;
    try {
        bytes = encode_ktx2(image);
    } catch (const input_error& e) {
        throw input_error(path + ": " + e.what());
    }
    write_file_atomically(path, bytes.data(), bytes.size());
}

GpuImage read_ktx2(const std::string& path) {
    // The identifier before the rest: a file of another kind is refused unread.
    const std::string content =
        read_input_file(path, {image_limits().max_bytes, "MSMCL_MAX_BYTES",
                               std::string(reinterpret_cast<const char*>(kIdentifier), sizeof kIdentifier), "a KTX2 file"});
    return decode_ktx2(std::vector<std::uint8_t>(content.begin(), content.end()), path);
}

} // namespace msmcl::io
