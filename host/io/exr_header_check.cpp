// The header safety walk (exr_header_check.hpp): everything checked in an untrusted EXR
// file before OpenEXR sizes a table or a buffer by what its header claims.
#include "io/exr_header_check.hpp"

#include "io/exr_file.hpp"
#include "io/image_limits.hpp"

#include <ImfCompression.h>
#include <ImfHeader.h>
#include <ImfTileDescription.h>

#include <cstring>
#include <exception>
#include <utility>

namespace msmcl::io::exr {
namespace {

/// The largest ratio of decoded to stored bytes a compression method can reach (rounded
/// up): RLE stores a run of up to 128 bytes in 2; zlib (ZIP, ZIPS, and PXR24 after its
/// 24-bit rounding) expands at most 1032-fold; PIZ's Huffman coder spends at least 10 bits
/// on a run of 256 values of 2 bytes; B44 stores 4x4 HALF blocks in 3 bytes at least; DWA
/// chains run-length coding and zlib, and unknown methods get the same generous bound.
std::uint64_t max_expansion(Imf::Compression compression) {
    switch (compression) {
    case Imf::NO_COMPRESSION: return 1;
    case Imf::RLE_COMPRESSION: return 64;
    case Imf::ZIPS_COMPRESSION:
    case Imf::ZIP_COMPRESSION: return 1032;
    case Imf::PXR24_COMPRESSION: return 1376;
    case Imf::PIZ_COMPRESSION: return 410;
    case Imf::B44_COMPRESSION:
    case Imf::B44A_COMPRESSION: return 11;
    default: return 64 * 1032;
    }
}

/// The value size OpenEXR's C++ reader takes for an attribute of a fixed-size type, which
/// it reads without looking at the size field; 0 for a type whose size the field gives.
/// Sizes from the OpenEXR file layout (a box2i is four int32, a tiledesc two uint32 and a
/// mode byte, ...).
std::uint32_t fixed_attribute_size(const std::string& type) {
    static const std::pair<const char*, std::uint32_t> sizes[] = {
        {"box2i", 16},    {"box2f", 16},   {"chromaticities", 32}, {"compression", 1}, {"deepImageState", 1},
        {"double", 8},    {"envmap", 1},   {"float", 4},           {"int", 4},         {"keycode", 28},
        {"lineOrder", 1}, {"m33f", 36},    {"m33d", 72},           {"m44f", 64},       {"m44d", 128},
        {"rational", 8},  {"tiledesc", 9}, {"timecode", 8},        {"v2i", 8},         {"v2f", 8},
        {"v2d", 16},      {"v3i", 12},     {"v3f", 12},            {"v3d", 24}};
    for (const auto& [name, size] : sizes)
        if (type == name) return size;
    return 0;
}

/// How many bytes OpenEXR's reader takes for the value of a `type` attribute that starts
/// at `at`, looking no further than `end` (the size field's end): fixed sizes, the entries
/// of a channel list up to its empty name, the strings of a string vector, a preview's
/// 8-byte size and RGBA8 texels; the size field itself for the types read by it. A value that runs past `end` gives more
/// than the size field.
std::uint64_t attribute_value_size(const std::string& type, const std::string& bytes, std::size_t at, std::size_t end) {
    const std::uint64_t size = end - at;
    if (const std::uint32_t fixed = fixed_attribute_size(type)) return fixed;
    if (type == "chlist") {
        // Entries of a name, then pixel type, linear flag, 3 reserved bytes and x, y sampling
        // (16 bytes); an empty name ends the list.
        std::size_t entry = at;
        for (;;) {
            const std::size_t name_end = bytes.find('\0', entry);
            if (name_end == std::string::npos || name_end >= end) return size + 1;
            if (name_end == entry) return name_end + 1 - at;
            entry = name_end + 1 + 16;
            if (entry > end) return size + 1;
        }
    }
    if (type == "stringvector") {
        // Strings of an int32 length and as many bytes, until the size field is used up;
        // OpenEXR sizes each string by its length field before reading it.
        std::size_t element = at;
        while (element < end) {
            std::int32_t length = 0;
            if (end - element < 4) return size + 1;
            std::memcpy(&length, bytes.data() + element, 4);
            element += 4;
            if (length < 0 || static_cast<std::uint64_t>(length) > end - element) return size + 1;
            element += static_cast<std::size_t>(length);
        }
        return size;
    }
    if (type == "preview") {
        if (size < 8) return 8;
        std::uint32_t width = 0, height = 0;
        std::memcpy(&width, bytes.data() + at, 4);
        std::memcpy(&height, bytes.data() + at + 4, 4);
        return 8 + 4 * static_cast<std::uint64_t>(width) * height;
    }
    return size;
}

} // namespace

void check_header_attributes(const std::string& path, const std::string& bytes) {
    if (bytes.size() < 8) fail(path, "corrupt or truncated OpenEXR file: no version field");
    const unsigned flags = static_cast<unsigned char>(bytes[5]);
    if (flags & 0x10) fail(path, "multi-part OpenEXR files are not supported");
    if (flags & 0x08) fail(path, "deep OpenEXR images are not supported");
    std::size_t at = 8;
    const auto text = [&](const char* what) {
        const std::size_t end = bytes.find('\0', at);
        if (end == std::string::npos || end - at > 255)
            fail(path, std::string("corrupt or truncated OpenEXR file: unterminated attribute ") + what);
        std::string value = bytes.substr(at, end - at);
        at = end + 1;
        return value;
    };
    for (;;) {
        const std::string name = text("name");
        if (name.empty()) return; // the end of the header
        const std::string type = text("type");
        if (bytes.size() - at < 4) fail(path, "corrupt or truncated OpenEXR file: attribute " + name + " is cut short");
        std::int32_t size = 0;
        std::memcpy(&size, bytes.data() + at, 4);
        at += 4;
        if (size < 0 || static_cast<std::uint64_t>(size) > bytes.size() - at)
            fail(path, "corrupt or truncated OpenEXR file: attribute " + name + " (" + type + ") claims " + std::to_string(size) +
                           " bytes, " + std::to_string(bytes.size() - at) + " are left in the file");
        const std::size_t value_end = at + static_cast<std::size_t>(size);
        const std::uint64_t taken = attribute_value_size(type, bytes, at, value_end);
        if (taken != static_cast<std::uint64_t>(size))
            fail(path, "corrupt OpenEXR header: attribute " + name + " (" + type + ") has a size field of " +
                           std::to_string(size) + " bytes but a value of " + std::to_string(taken));
        at = value_end;
    }
}

Imath::Box2i check_first_header(const std::string& path, Imf::IStream& stream, std::uint64_t file_bytes) {
    Imath::Box2i window;
    std::uint64_t stored_bytes_per_texel = 0, decoded_bytes_per_texel = 0;
    Imf::Compression compression = Imf::NO_COMPRESSION;
    std::uint64_t tile_width = 0, tile_height = 0;
    try {
        char magic_and_version[8];
        stream.read(magic_and_version, 8);
        int version = static_cast<unsigned char>(magic_and_version[4]) |
                            static_cast<unsigned char>(magic_and_version[5]) << 8 |
                            static_cast<unsigned char>(magic_and_version[6]) << 16 |
                            static_cast<unsigned char>(magic_and_version[7]) << 24;
        Imf::Header first_header;
        first_header.readFrom(stream, version);
        window = first_header.dataWindow();
        // What the channels take per texel: in the file, and as msmcl holds them (4 bytes).
        for (auto it = first_header.channels().begin(); it != first_header.channels().end(); ++it) {
            stored_bytes_per_texel += it.channel().type == Imf::HALF ? 2 : 4;
            decoded_bytes_per_texel += 4;
        }
        compression = first_header.compression();
        if (first_header.hasTileDescription()) {
            const Imf::TileDescription& tiles = first_header.tileDescription();
            tile_width = tiles.xSize;
            tile_height = tiles.ySize;
        }
    } catch (const std::exception& e) {
        fail(path, openexr_problem(path, e));
    }
    // The data window decides the image size: refuse empty and absurd ones.
    const long long width = static_cast<long long>(window.max.x) - window.min.x + 1;
    const long long height = static_cast<long long>(window.max.y) - window.min.y + 1;
    if (width <= 0 || height <= 0) fail(path, "empty data window");
    if (width > max_image_side || height > max_image_side)
        fail(path, "data window " + std::to_string(width) + " x " + std::to_string(height) +
                       " is too large (at most " + std::to_string(max_image_side) + " per side)");
    // Limits, and the claimed size against what the file can hold, before OpenEXR
    // allocates its line buffers or msmcl its channels.
    check_image_size(path, static_cast<std::uint64_t>(width), static_cast<std::uint64_t>(height),
                     stored_bytes_per_texel, decoded_bytes_per_texel, file_bytes, max_expansion(compression));
    // Tiles: OpenEXR allocates a buffer per tile and an offset per tile. A tile larger
    // than the image, or more tiles than the file has room for offsets (8 bytes each),
    // is a damaged header.
    if (tile_width != 0 || tile_height != 0) {
        if (tile_width == 0 || tile_height == 0 || tile_width > static_cast<std::uint64_t>(width) + 64 ||
            tile_height > static_cast<std::uint64_t>(height) + 64)
            fail(path, "tiles of " + std::to_string(tile_width) + " x " + std::to_string(tile_height) +
                           " do not fit a data window of " + std::to_string(width) + " x " + std::to_string(height));
        const std::uint64_t tiles = ((static_cast<std::uint64_t>(width) + tile_width - 1) / tile_width) *
                                    ((static_cast<std::uint64_t>(height) + tile_height - 1) / tile_height);
        if (tiles > file_bytes / 8)
            fail(path, "the header claims " + std::to_string(tiles) + " tiles, more than the " +
                           std::to_string(file_bytes) + " bytes of the file can hold offsets for");
    }
    return window;
}

} // namespace msmcl::io::exr
