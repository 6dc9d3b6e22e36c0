#include "io/exr_io.hpp"

#include "io/atomic_file.hpp"
#include "io/image_limits.hpp"
#include "io/texture_metadata.hpp"
#include "ops/range_scan.hpp"
#include "runtime/texture_kinds.hpp"

#include <msmcl/errors.hpp>

#include <ImfAttribute.h>
#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfFloatAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfOutputFile.h>
#include <ImfPartType.h>
#include <ImfStdIO.h>
#include <ImfStringAttribute.h>
#include <ImfThreading.h>
#include <ImfTileDescription.h>
#include <ImfTiledOutputFile.h>
#include <ImfVersion.h>
#include <Iex.h>
#include <half.h>

#include <algorithm>
#include <array>
#include <exception>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <thread>

namespace msmcl::io {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
    throw input_error(path + ": " + problem);
}

/// OpenEXR decodes and encodes the blocks of a file on its global thread pool: give it
/// one thread per hardware thread, once, unless the program has chosen a count itself.
int openexr_threads() {
    static std::once_flag started;
    std::call_once(started, [] {
        if (Imf::globalThreadCount() == 0)
            Imf::setGlobalThreadCount(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
    });
    return Imf::globalThreadCount();
}

/// OpenEXR's message without the quoted file name it repeats (ours leads the line).
std::string openexr_problem(const std::string& path, const std::exception& e) {
    std::string message = e.what();
    const std::string quoted = " \"" + path + "\"";
    for (std::size_t at = message.find(quoted); at != std::string::npos; at = message.find(quoted))
        message.erase(at, quoted.size());
    return "corrupt or truncated OpenEXR file (" + message + ")";
}

/// "1.5", "NaN", "+Inf": how a bad value appears in a message.
std::string describe_value(double value) {
    if (std::isnan(value)) return "NaN";
    if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", value);
    return text;
}

std::string texel_name(long long x, long long y) {
    return "texel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
}

const char* sample_type_name(Imf::PixelType type) {
    switch (type) {
    case Imf::UINT: return "UINT";
    case Imf::HALF: return "HALF";
    case Imf::FLOAT: return "FLOAT";
    default: return "unknown";
    }
}

Imf::PixelType to_pixel_type(SampleType type) {
    switch (type) {
    case SampleType::uint32: return Imf::UINT;
    case SampleType::half: return Imf::HALF;
    case SampleType::float32: return Imf::FLOAT;
    }
    return Imf::FLOAT;
}

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

/// An Imf input stream over bytes already in memory; reading past the end throws, which
/// OpenEXR reports as a truncated file.
class MemoryInputStream : public Imf::IStream {
public:
    MemoryInputStream(const std::string& name, std::string bytes)
        : Imf::IStream(name.c_str()), bytes_(std::move(bytes)) {}

    bool read(char c[], int n) override {
        if (n < 0 || position_ > bytes_.size() || bytes_.size() - position_ < static_cast<std::size_t>(n))
            throw Iex::InputExc("unexpected end of file");
        std::memcpy(c, bytes_.data() + position_, static_cast<std::size_t>(n));
        position_ += static_cast<std::size_t>(n);
        return position_ < bytes_.size();
    }
    uint64_t tellg() override { return position_; }
    void seekg(uint64_t position) override { position_ = static_cast<std::size_t>(position); }
    void clear() override {}

private:
    std::string bytes_;
    std::size_t position_ = 0;
};

/// An Imf output stream into an AtomicFile: the encoded bytes go to the disk as OpenEXR
/// produces them, never all in memory. The first failure is kept, since OpenEXR's
/// destructors swallow exceptions (the offset table is written by one).
class AtomicFileOutputStream : public Imf::OStream {
public:
    AtomicFileOutputStream(const std::string& name, AtomicFile& file) : Imf::OStream(name.c_str()), file_(file) {}

    void write(const char c[], int n) override { guarded([&] { file_.write(c, static_cast<std::size_t>(n)); }); }
    uint64_t tellp() override { return file_.position(); }
    void seekp(uint64_t position) override { guarded([&] { file_.seek(position); }); }

    /// Throws the first failure of a write or seek, if any.
    void rethrow_failure() const {
        if (failure_) std::rethrow_exception(failure_);
    }

private:
    template <typename Step>
    void guarded(const Step& step) {
        if (failure_) std::rethrow_exception(failure_);
        try {
            step();
        } catch (...) {
            failure_ = std::current_exception();
            throw;
        }
    }

    AtomicFile& file_;
    std::exception_ptr failure_;
};

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

/// Walks the attributes of the header after the magic number and version, as OpenEXR will
/// read them, and refuses a header on which OpenEXR's reader and the size fields disagree:
/// - a size field larger than what is left of the file (OpenEXR allocates an attribute of
///   unknown type by its size before reading it: a 500-byte file could ask for 2 GB);
/// - a fixed-size type, channel list or preview whose size field differs from what its
///   value takes: OpenEXR reads those by their own layout, so it would lose step with the
///   size fields and take later bytes for sizes that this walk never saw.
/// Multi-part and deep files are refused: msmcl reads single-part scanline and tiled images.
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

/// An opened EXR file whose header passed the checks every msmcl reader needs: a real
/// OpenEXR file, not deep, a data window that is neither empty nor absurd, and no
/// subsampled channels. OpenEXR's exceptions become input_error naming the file.
class ExrReader {
public:
    explicit ExrReader(const std::string& path) : path_(path) {
        // Load the bytes and look at the magic number before OpenEXR does.
        // (a file of another kind is refused after its first four bytes, not read whole).
        std::string bytes = read_input_file(path, {image_limits().max_bytes, "MSMCL_MAX_BYTES",
                                                   std::string("\x76\x2f\x31\x01", 4), "an OpenEXR file"});
        const std::uint64_t file_bytes = bytes.size();
        if (bytes.size() < 4 || !Imf::isImfMagic(bytes.data())) fail(path, "not an OpenEXR file");

        // Check the first header alone before OpenEXR sizes its tables by the data window.
        check_header_attributes(path, bytes);
        stream_ = std::make_unique<MemoryInputStream>(path, std::move(bytes));
        Imath::Box2i window;
        std::uint64_t stored_bytes_per_texel = 0, decoded_bytes_per_texel = 0;
        Imf::Compression compression = Imf::NO_COMPRESSION;
        std::uint64_t tile_width = 0, tile_height = 0;
        try {
            char magic_and_version[8];
            stream_->read(magic_and_version, 8);
            int version = static_cast<unsigned char>(magic_and_version[4]) |
                                static_cast<unsigned char>(magic_and_version[5]) << 8 |
                                static_cast<unsigned char>(magic_and_version[6]) << 16 |
                                static_cast<unsigned char>(magic_and_version[7]) << 24;
            Imf::Header first_header;
            first_header.readFrom(*stream_, version);
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
        width_ = static_cast<int>(width);
        height_ = static_cast<int>(height);

        // Open the file; any failure means it is damaged.
        try {
            stream_->seekg(0);
            file_ = std::make_unique<Imf::InputFile>(*stream_, openexr_threads());
        } catch (const std::exception& e) {
            fail(path, openexr_problem(path, e));
        }
        const Imf::Header& header = file_->header();
        if (header.hasType() && Imf::isDeepData(header.type()))
            fail(path, "deep OpenEXR images are not supported");
        if (header.dataWindow() != window) fail(path, "corrupt OpenEXR header");

        // msmcl works on full-resolution channels only.
        for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
            const Imf::Channel& channel = it.channel();
            if (channel.xSampling != 1 || channel.ySampling != 1)
                fail(path, std::string("channel ") + it.name() + " is subsampled (" +
                               std::to_string(channel.xSampling) + "x" + std::to_string(channel.ySampling) +
                               "); only full-resolution channels are supported");
        }
    }

    const std::string& path() const { return path_; }
    const Imf::Header& header() const { return file_->header(); }
    const Imath::Box2i data_window() const { return header().dataWindow(); }
    int width() const { return width_; }
    int height() const { return height_; }
    std::size_t texel_count() const { return static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_); }

    /// The channel of that name, or null.
    const Imf::Channel* find_channel(const std::string& name) const {
        return header().channels().findChannel(name);
    }
    std::vector<std::string> channel_names() const {
        std::vector<std::string> names;
        for (auto it = header().channels().begin(); it != header().channels().end(); ++it) names.push_back(it.name());
        return names;
    }

    /// Reads all rows into the slices of `frame_buffer`.
    void read(const Imf::FrameBuffer& frame_buffer) {
        try {
            file_->setFrameBuffer(frame_buffer);
            const Imath::Box2i window = data_window();
            file_->readPixels(window.min.y, window.max.y);
        } catch (const std::exception& e) {
            fail(path_, openexr_problem(path_, e));
        }
    }

    /// A FLOAT slice that writes channel values with the given strides into `base`
    /// (base = the value of the data window's first texel).
    Imf::Slice float_slice(float* base, std::size_t x_stride, std::size_t y_stride) const {
        return Imf::Slice::Make(Imf::FLOAT, base, data_window(), x_stride, y_stride);
    }

private:
    std::string path_;
    std::unique_ptr<MemoryInputStream> stream_;
    std::unique_ptr<Imf::InputFile> file_;
    int width_ = 0;
    int height_ = 0;
};

/// "A, B, G, R" (at most 8 names) for messages.
std::string list_names(const std::vector<std::string>& names) {
    if (names.empty()) return "none";
    std::string text;
    for (std::size_t i = 0; i < names.size() && i < 8; ++i) text += (i ? ", " : "") + names[i];
    if (names.size() > 8) text += ", ...";
    return text;
}

/// Requires a HALF or FLOAT channel `name`; `purpose` says what it is for in messages.
void require_float_channel(const ExrReader& reader, const std::string& name, const std::string& purpose) {
    const Imf::Channel* channel = reader.find_channel(name);
    if (!channel)
        fail(reader.path(), "missing channel " + name + " (" + purpose + "; channels: " +
                                list_names(reader.channel_names()) + ")");
    if (channel->type != Imf::HALF && channel->type != Imf::FLOAT)
        fail(reader.path(), "channel " + name + " has type " + sample_type_name(channel->type) +
                                "; it must be HALF or FLOAT");
}

/// The header msmcl writes for `image`: display window = data window, ZIP, the image's
/// channels and attributes and nothing else (the channels' data is not looked at).
Imf::Header exr_header(const ExrImage& image) {
    const Imath::Box2i window(Imath::V2i(image.x_origin, image.y_origin),
                              Imath::V2i(image.x_origin + image.width - 1, image.y_origin + image.height - 1));
    Imf::Header header(window, window, 1.0f, Imath::V2f(0.0f, 0.0f), 1.0f, Imf::INCREASING_Y,
                       Imf::ZIP_COMPRESSION);
    for (const ExrChannel& channel : image.channels)
        header.channels().insert(channel.name,
                                 Imf::Channel(to_pixel_type(channel.type), channel.x_sampling, channel.y_sampling));
    for (const ExrAttribute& attribute : image.attributes) {
        if (const auto* text = std::get_if<std::string>(&attribute.value))
            header.insert(attribute.name, Imf::StringAttribute(*text));
        else if (const auto* number = std::get_if<float>(&attribute.value))
            header.insert(attribute.name, Imf::FloatAttribute(*number));
        else
            header.insert(attribute.name, Imf::IntAttribute(std::get<int>(attribute.value)));
    }
    return header;
}

/// Serializes `image` to EXR bytes in memory (validated, ZIP, deterministic).
std::string encode_exr(const std::string& path, const ExrImage& image) {
    // Validate sizes and channel data before OpenEXR sees them.
    // (Sizes beyond max_image_side are allowed here, so tests can make files the readers refuse.)
    if (image.width <= 0 || image.height <= 0)
        fail(path, "cannot write an image of " + std::to_string(image.width) + " x " +
                       std::to_string(image.height) + " texels");
    if (image.channels.empty()) fail(path, "cannot write an image without channels");
    std::set<std::string> names;
    for (const ExrChannel& channel : image.channels) {
        if (channel.name.empty() || !names.insert(channel.name).second)
            fail(path, "empty or repeated channel name '" + channel.name + "'");
        if (channel.x_sampling < 1 || channel.y_sampling < 1 || image.width % channel.x_sampling != 0 ||
            image.height % channel.y_sampling != 0 || image.x_origin % channel.x_sampling != 0 ||
            image.y_origin % channel.y_sampling != 0)
            fail(path, "channel " + channel.name + ": sampling does not divide the data window");
        const std::size_t expected = static_cast<std::size_t>(image.width / channel.x_sampling) *
                                     static_cast<std::size_t>(image.height / channel.y_sampling);
        const std::size_t given = channel.type == SampleType::uint32 ? channel.codes.size() : channel.values.size();
        if (given != expected)
            fail(path, "channel " + channel.name + " holds " + std::to_string(given) + " values, expected " +
                           std::to_string(expected));
    }

    // Header: display window = data window, ZIP, the caller's attributes and nothing else.
    Imf::Header header = exr_header(image);
    const Imath::Box2i window = header.dataWindow();

    // Frame buffer in the channels' own types (OpenEXR does not convert on output):
    // HALF channels get rounded copies (round to nearest even).
    Imf::FrameBuffer frame_buffer;
    std::vector<std::vector<half>> half_copies;
    half_copies.reserve(image.channels.size());
    for (const ExrChannel& channel : image.channels) {
        const void* data = channel.values.data();
        std::size_t value_bytes = sizeof(float);
        if (channel.type == SampleType::uint32) {
            data = channel.codes.data();
        } else if (channel.type == SampleType::half) {
            half_copies.emplace_back(channel.values.begin(), channel.values.end());
            data = half_copies.back().data();
            value_bytes = sizeof(half);
        }
        frame_buffer.insert(channel.name,
                            Imf::Slice::Make(to_pixel_type(channel.type), data, window, value_bytes,
                                             value_bytes * static_cast<std::size_t>(image.width / channel.x_sampling),
                                             channel.x_sampling, channel.y_sampling));
    }

    // Encode into memory; the file object must be gone (offset table written) before reading the bytes.
    Imf::StdOSStream stream;
    try {
        if (image.tiled) {
            header.setTileDescription(Imf::TileDescription(32, 32, Imf::ONE_LEVEL));
            Imf::TiledOutputFile file(stream, header, openexr_threads());
            file.setFrameBuffer(frame_buffer);
            file.writeTiles(0, file.numXTiles() - 1, 0, file.numYTiles() - 1);
        } else {
            Imf::OutputFile file(stream, header, openexr_threads());
            file.setFrameBuffer(frame_buffer);
            file.writePixels(image.height);
        }
    } catch (const std::exception& e) {
        throw error(path + ": cannot encode OpenEXR data (" + e.what() + ")");
    }
    return stream.str();
}

void write_exr_atomically(const std::string& path, const ExrImage& image) {
    const std::string bytes = encode_exr(path, image);
    write_file_atomically(path, bytes.data(), bytes.size());
}

/// "sample<k>.Z" -> k; -1 for other names; throws for a malformed sample layer name.
int sample_layer_index(const std::string& path, const std::string& name) {
    static const std::string prefix = "sample";
    static const std::string suffix = ".Z";
    if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
        return -1;
    const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    const bool all_digits = std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (!all_digits) return -1; // another layer, e.g. "sampleA.Z": not a depth sample
    if (digits.size() > 4 || (digits.size() > 1 && digits[0] == '0'))
        fail(path, "bad sample layer name '" + name + "' (expected sample0.Z, sample1.Z, ...)");
    return std::stoi(digits);
}

bool is_supported_samples(int samples) {
    return samples == 1 || samples == 2 || samples == 4 || samples == 8 || samples == 16;
}

/// The channels of a texture format (its row of the format table): names in texel order,
/// one type (FLOAT for float32 texels, HALF for half texels, else UINT holding the codes),
/// the bits of each in the texel's words (32: a whole word; fewer: packed from bit 0 up, as
/// the codes of msm64). HALF channels go through 32-bit slots whose low half is the code
/// (little-endian, as the texture's words).
struct TextureLayout {
    std::vector<std::string> channels;
    SampleType type;
    std::uint32_t bits;
};
TextureLayout texture_layout(Format format) {
    const detail::GpuFormatInfo& pixels = detail::gpu_format_info(detail::texture_kind(format));
    const SampleType type = pixels.kind != detail::ChannelKind::sfloat ? SampleType::uint32
                            : pixels.channel_bits[0] == 16            ? SampleType::half
                                                                      : SampleType::float32;
    TextureLayout layout{{}, type, pixels.channel_bits[0]};
    for (std::uint32_t c = 0; c < pixels.channels; ++c) layout.channels.push_back(std::string(1, "RGBA"[c]));
    return layout;
}

// Channel c of a texel whose channels are `bits` (< 32) wide, packed from bit 0 of its first word up.
std::uint32_t packed_channel(const std::uint32_t* words, std::size_t c, std::uint32_t bits) {
    return (words[c * bits / 32] >> (c * bits % 32)) & ((1u << bits) - 1u);
}


} // namespace

const ExrChannel* ExrImage::find_channel(const std::string& name) const {
    for (const ExrChannel& channel : channels)
        if (channel.name == name) return &channel;
    return nullptr;
}

const ExrAttribute* ExrImage::find_attribute(const std::string& name) const {
    for (const ExrAttribute& attribute : attributes)
        if (attribute.name == name) return &attribute;
    return nullptr;
}

void write_exr(const std::string& path, const ExrImage& image) { write_exr_atomically(path, image); }

ExrImage read_exr(const std::string& path) {
    ExrReader reader(path);
    ExrImage image;
    image.width = reader.width();
    image.height = reader.height();
    image.x_origin = reader.data_window().min.x;
    image.y_origin = reader.data_window().min.y;
    image.tiled = reader.header().hasTileDescription();

    // One buffer per channel, in the file's (alphabetical) channel order.
    Imf::FrameBuffer frame_buffer;
    const std::size_t row_bytes = sizeof(float) * static_cast<std::size_t>(reader.width());
    for (auto it = reader.header().channels().begin(); it != reader.header().channels().end(); ++it) {
        ExrChannel channel;
        channel.name = it.name();
        channel.type = it.channel().type == Imf::UINT   ? SampleType::uint32
                       : it.channel().type == Imf::HALF ? SampleType::half
                                                        : SampleType::float32;
        if (channel.type == SampleType::uint32)
            channel.codes.resize(reader.texel_count());
        else
            channel.values.resize(reader.texel_count());
        image.channels.push_back(std::move(channel));
    }
    for (ExrChannel& channel : image.channels) {
        const bool is_uint = channel.type == SampleType::uint32;
        void* data = is_uint ? static_cast<void*>(channel.codes.data()) : static_cast<void*>(channel.values.data());
        frame_buffer.insert(channel.name, Imf::Slice::Make(is_uint ? Imf::UINT : Imf::FLOAT, data,
                                                           reader.data_window(), 4, row_bytes));
    }
    reader.read(frame_buffer);

    // The attributes of the kinds msmcl uses.
    for (auto it = reader.header().begin(); it != reader.header().end(); ++it) {
        const Imf::Attribute& attribute = it.attribute();
        if (const auto* text = dynamic_cast<const Imf::StringAttribute*>(&attribute))
            image.attributes.push_back({it.name(), text->value()});
        else if (const auto* number = dynamic_cast<const Imf::FloatAttribute*>(&attribute))
            image.attributes.push_back({it.name(), number->value()});
        else if (const auto* integer = dynamic_cast<const Imf::IntAttribute*>(&attribute))
            image.attributes.push_back({it.name(), integer->value()});
    }
    return image;
}

namespace {

/// read_depth_exr on an opened file (read_translucent_depth_exr reads its layers from the
/// same one).
DepthImage read_depth(ExrReader& reader, DepthRange range) {
    const std::string& path = reader.path();

    // Find the sample layout: Z alone, or sample0.Z .. sample<S-1>.Z.
    const std::vector<std::string> names = reader.channel_names();
    bool has_plain_z = false;
    std::map<int, std::string> layers;
    for (const std::string& name : names) {
        if (name == "Z") has_plain_z = true;
        else if (const int index = sample_layer_index(path, name); index >= 0) layers[index] = name;
    }
    if (has_plain_z && !layers.empty())
        fail(path, "has both a Z channel and sample<N>.Z layers; use one layout");
    if (!has_plain_z && layers.empty())
        fail(path, "missing depth channel: expected Z or sample0.Z .. sample<S-1>.Z (channels: " +
                       list_names(names) + ")");
    std::vector<std::string> depth_channels;
    if (has_plain_z) {
        depth_channels.push_back("Z");
    } else {
        for (int index = 0; index < static_cast<int>(layers.size()); ++index) {
            if (!layers.count(index))
                fail(path, "sample layers must be contiguous from sample0.Z: sample" + std::to_string(index) +
                               ".Z is missing (found " + std::to_string(layers.size()) + " layers up to " +
                               layers.rbegin()->second + ")");
            depth_channels.push_back(layers[index]);
        }
    }
    const int samples = static_cast<int>(depth_channels.size());
    if (!is_supported_samples(samples))
        fail(path, "unsupported sample count " + std::to_string(samples) + " (must be 1, 2, 4, 8 or 16)");
    for (const std::string& name : depth_channels) require_float_channel(reader, name, "depth");

    // Read all samples of a texel next to each other (texel-major).
    DepthImage depth;
    depth.width = reader.width();
    depth.height = reader.height();
    depth.samples = samples;
    depth.depth.resize(reader.texel_count() * static_cast<std::size_t>(samples));
    Imf::FrameBuffer frame_buffer;
    const std::size_t texel_bytes = sizeof(float) * static_cast<std::size_t>(samples);
    for (int s = 0; s < samples; ++s)
        frame_buffer.insert(depth_channels[static_cast<std::size_t>(s)],
                            reader.float_slice(depth.depth.data() + s, texel_bytes,
                                               texel_bytes * static_cast<std::size_t>(depth.width)));
    reader.read(frame_buffer);

    // Every depth must be finite and inside the declared range.
    const float low = range == DepthRange::zero_one ? 0.0f : -1.0f;
    const float high = 1.0f;
    const std::size_t count = depth.depth.size();
    if (const std::size_t i = detail::first_outside(depth.depth.data(), count, low, high); i < count) {
        const float value = depth.depth[i];
        const std::size_t texel = i / static_cast<std::size_t>(samples);
        const long long x = static_cast<long long>(texel % static_cast<std::size_t>(depth.width));
        const long long y = static_cast<long long>(texel / static_cast<std::size_t>(depth.width));
        const std::string where = texel_name(x, y) + " " + depth_channels[i % static_cast<std::size_t>(samples)];
        if (!std::isfinite(value)) fail(path, where + ": depth is " + describe_value(value));
        fail(path, where + ": depth " + describe_value(value) + " is outside the depth range [" +
                       depth_range_name(range) + "]");
    }
    return depth;
}

} // namespace

DepthImage read_depth_exr(const std::string& path, DepthRange range) {
    ExrReader reader(path);
    return read_depth(reader, range);
}

void write_depth_exr(const std::string& path, const DepthImage& depth, SampleType type) {
    if (type == SampleType::uint32) fail(path, "depth must be written as HALF or FLOAT");
    if (depth.samples < 1 || depth.width <= 0 || depth.height <= 0 ||
        depth.depth.size() != static_cast<std::size_t>(depth.width) * depth.height * depth.samples)
        fail(path, "depth image size does not match its data");

    // One channel per sample: Z, or sample<s>.Z.
    ExrImage image;
    image.width = depth.width;
    image.height = depth.height;
    const std::size_t texels = static_cast<std::size_t>(depth.width) * depth.height;
    for (int s = 0; s < depth.samples; ++s) {
        ExrChannel channel;
        channel.name = depth.samples == 1 ? "Z" : "sample" + std::to_string(s) + ".Z";
        channel.type = type;
        channel.values.resize(texels);
        for (std::size_t t = 0; t < texels; ++t)
            channel.values[t] = depth.depth[t * static_cast<std::size_t>(depth.samples) + static_cast<std::size_t>(s)];
        image.channels.push_back(std::move(channel));
    }
    write_exr_atomically(path, image);
}

namespace {

/// "layer<k>.<rest>" -> k (and rest); -1 for other names. A malformed index is an error.
int translucent_layer_index(const std::string& path, const std::string& name, std::string& rest) {
    static const std::string prefix = "layer";
    if (name.compare(0, prefix.size(), prefix) != 0) return -1;
    const std::size_t dot = name.find('.', prefix.size());
    if (dot == std::string::npos || dot == prefix.size()) return -1;
    const std::string digits = name.substr(prefix.size(), dot - prefix.size());
    if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) return -1;
    if (digits.size() > 4 || (digits.size() > 1 && digits[0] == '0'))
        fail(path, "bad translucent layer name '" + name + "' (expected layer0.Z, layer0.A, layer1.Z, ...)");
    rest = name.substr(dot + 1);
    return std::stoi(digits);
}

/// Inserts the slices that read the channels `names` (one per sample, or a single one for
/// sample 0 of every texel) into a texel-major array of `samples` values per texel.
void insert_per_sample(const ExrReader& reader, Imf::FrameBuffer& frame_buffer, const std::vector<std::string>& names,
                       std::vector<float>& values, int samples) {
    values.resize(reader.texel_count() * static_cast<std::size_t>(samples));
    const std::size_t texel_bytes = sizeof(float) * static_cast<std::size_t>(samples);
    for (std::size_t s = 0; s < names.size(); ++s)
        frame_buffer.insert(names[s], reader.float_slice(values.data() + s, texel_bytes,
                                                         texel_bytes * static_cast<std::size_t>(reader.width())));
}

/// After the read: a single channel's value (in sample 0) copied to the other samples.
void broadcast_sample0(std::vector<float>& values, std::size_t channels, int samples) {
    if (channels != 1) return;
    for (std::size_t t = 0; t < values.size(); t += static_cast<std::size_t>(samples))
        for (int s = 1; s < samples; ++s) values[t + static_cast<std::size_t>(s)] = values[t];
}

} // namespace

TranslucentDepth read_translucent_depth_exr(const std::string& path, DepthRange range) {
    TranslucentDepth result;
    ExrReader reader(path);
    result.depth = read_depth(reader, range);
    const int samples = result.depth.samples;

    // Collect the layer channels: layer<k>.Z / .A, or layer<k>.sample<s>.Z / .A.
    struct LayerChannels {
        std::map<int, std::string> z, a; // per sample; key -1: one channel for every sample
    };
    std::map<int, LayerChannels> found;
    for (const std::string& name : reader.channel_names()) {
        std::string rest;
        const int k = translucent_layer_index(path, name, rest);
        if (k < 0) continue;
        int sample = -1;
        std::string kind = rest;
        if (rest.compare(0, 6, "sample") == 0 && rest.size() > 8) {
            const std::string tail = rest.substr(6);
            const std::size_t dot = tail.find('.');
            const std::string digits = tail.substr(0, dot);
            if (dot == std::string::npos || digits.empty() || digits.size() > 4 || (digits.size() > 1 && digits[0] == '0') ||
                !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
                fail(path, "bad translucent layer channel '" + name + "' (expected layer<k>.sample<s>.Z or .A)");
            sample = std::stoi(digits);
            kind = tail.substr(dot + 1);
        }
        if (kind != "Z" && kind != "A")
            fail(path, "bad translucent layer channel '" + name + "' (expected a depth .Z or an opacity .A)");
        if (sample >= samples)
            fail(path, "translucent layer channel " + name + " names a sample the depth map (" + std::to_string(samples) +
                           " samples) does not have");
        (kind == "Z" ? found[k].z : found[k].a)[sample] = name;
        require_float_channel(reader, name, "translucent layer");
    }
    if (found.empty()) return result;
    if (static_cast<int>(found.size()) > max_translucent_layers)
        fail(path, std::to_string(found.size()) + " translucent layers (at most " +
                       std::to_string(max_translucent_layers) + ")");

    // Every layer 0 .. K-1 complete: both channels, one for every sample or one per sample.
    const int count = static_cast<int>(found.size());
    std::vector<std::array<std::vector<std::string>, 2>> names(static_cast<std::size_t>(count));
    for (int k = 0; k < count; ++k) {
        if (!found.count(k))
            fail(path, "translucent layers must be numbered from layer0 without gaps: layer" + std::to_string(k) +
                           " is missing");
        const LayerChannels& channels = found[k];
        for (int c = 0; c < 2; ++c) {
            const std::map<int, std::string>& by_sample = c == 0 ? channels.z : channels.a;
            const char* kind = c == 0 ? "Z" : "A";
            const std::string base = "layer" + std::to_string(k) + ".";
            std::vector<std::string>& list = names[static_cast<std::size_t>(k)][static_cast<std::size_t>(c)];
            if (by_sample.count(-1) && by_sample.size() == 1) {
                list = {by_sample.at(-1)};
            } else if (!by_sample.count(-1) && static_cast<int>(by_sample.size()) == samples && samples > 1) {
                for (int s = 0; s < samples; ++s) list.push_back(by_sample.at(s));
            } else {
                fail(path, "translucent layer " + std::to_string(k) + " needs " + base + kind +
                               (samples > 1 ? " or " + base + "sample0." + kind + " .. " + base + "sample" +
                                                  std::to_string(samples - 1) + "." + kind
                                            : std::string()) +
                               ", and not both");
            }
        }
    }

    // One read for all layers (each read decompresses every channel of the file).
    result.layers.resize(static_cast<std::size_t>(count));
    Imf::FrameBuffer frame_buffer;
    for (int k = 0; k < count; ++k) {
        TranslucentLayer& layer = result.layers[static_cast<std::size_t>(k)];
        insert_per_sample(reader, frame_buffer, names[static_cast<std::size_t>(k)][0], layer.depth, samples);
        insert_per_sample(reader, frame_buffer, names[static_cast<std::size_t>(k)][1], layer.opacity, samples);
    }
    reader.read(frame_buffer);

    for (int k = 0; k < count; ++k) {
        TranslucentLayer& layer = result.layers[static_cast<std::size_t>(k)];
        const std::array<std::vector<std::string>, 2>& layer_names = names[static_cast<std::size_t>(k)];
        broadcast_sample0(layer.depth, layer_names[0].size(), samples);
        broadcast_sample0(layer.opacity, layer_names[1].size(), samples);

        // Depths finite and in the range, opacities in [0, 1].
        const float low = range == DepthRange::zero_one ? 0.0f : -1.0f;
        for (std::size_t i = 0; i < layer.depth.size(); ++i) {
            const float d = layer.depth[i], a = layer.opacity[i];
            const bool depth_ok = std::isfinite(d) && d >= low && d <= 1.0f;
            if (depth_ok && a >= 0.0f && a <= 1.0f) continue;
            const std::size_t texel = i / static_cast<std::size_t>(samples);
            const std::size_t s = i % static_cast<std::size_t>(samples);
            const std::vector<std::string>& bad = layer_names[depth_ok ? 1 : 0];
            const std::string where =
                texel_name(static_cast<long long>(texel % static_cast<std::size_t>(result.depth.width)),
                           static_cast<long long>(texel / static_cast<std::size_t>(result.depth.width))) +
                " " + bad[bad.size() == 1 ? 0 : s];
            if (!depth_ok && !std::isfinite(d)) fail(path, where + ": depth is " + describe_value(d));
            if (!depth_ok)
                fail(path, where + ": depth " + describe_value(d) + " is outside the depth range [" +
                               depth_range_name(range) + "]");
            fail(path, where + ": opacity " + describe_value(a) + " is outside [0, 1]");
        }
    }
    return result;
}

void write_translucent_depth_exr(const std::string& path, const TranslucentDepth& depth, SampleType type) {
    const DepthImage& opaque = depth.depth;
    if (type == SampleType::uint32) fail(path, "depth must be written as HALF or FLOAT");
    if (opaque.samples < 1 || opaque.width <= 0 || opaque.height <= 0 ||
        opaque.depth.size() != static_cast<std::size_t>(opaque.width) * opaque.height * opaque.samples)
        fail(path, "depth image size does not match its data");
    for (const TranslucentLayer& layer : depth.layers)
        if (layer.depth.size() != opaque.depth.size() || layer.opacity.size() != opaque.depth.size())
            fail(path, "translucent layer size does not match the depth map");

    // Per sample: the opaque channel, then every layer's depth and opacity.
    ExrImage image;
    image.width = opaque.width;
    image.height = opaque.height;
    const std::size_t texels = static_cast<std::size_t>(opaque.width) * opaque.height;
    const auto add = [&](const std::string& name, const std::vector<float>& all, int s) {
        ExrChannel channel;
        channel.name = name;
        channel.type = type;
        channel.values.resize(texels);
        for (std::size_t t = 0; t < texels; ++t)
            channel.values[t] = all[t * static_cast<std::size_t>(opaque.samples) + static_cast<std::size_t>(s)];
        image.channels.push_back(std::move(channel));
    };
    for (int s = 0; s < opaque.samples; ++s) {
        const std::string sample = opaque.samples == 1 ? "" : "sample" + std::to_string(s) + ".";
        add(sample + "Z", opaque.depth, s);
        for (std::size_t k = 0; k < depth.layers.size(); ++k) {
            const std::string layer = "layer" + std::to_string(k) + "." + sample;
            add(layer + "Z", depth.layers[k].depth, s);
            add(layer + "A", depth.layers[k].opacity, s);
        }
    }
    write_exr_atomically(path, image);
}

ReceiverGrid read_receivers_exr(const std::string& path) {
    ExrReader reader(path);
    for (const char* name : {"U", "V", "Z"})
        require_float_channel(reader, name, "receivers need channels U, V, Z");

    // Read the three planes.
    ReceiverGrid grid;
    grid.width = reader.width();
    grid.height = reader.height();
    std::vector<float> planes[3];
    Imf::FrameBuffer frame_buffer;
    const char* names[3] = {"U", "V", "Z"};
    for (int c = 0; c < 3; ++c) {
        planes[c].resize(reader.texel_count());
        frame_buffer.insert(names[c], reader.float_slice(planes[c].data(), sizeof(float),
                                                         sizeof(float) * static_cast<std::size_t>(grid.width)));
    }
    reader.read(frame_buffer);

    // Every coordinate must be finite (points outside the map are fine: lookups clamp).
    for (int c = 0; c < 3; ++c)
        for (std::size_t i = 0; i < planes[c].size(); ++i)
            if (!std::isfinite(planes[c][i]))
                fail(path, texel_name(static_cast<long long>(i % static_cast<std::size_t>(grid.width)),
                                      static_cast<long long>(i / static_cast<std::size_t>(grid.width))) +
                               ": " + names[c] + " is " + describe_value(planes[c][i]));
    grid.points.u = std::move(planes[0]);
    grid.points.v = std::move(planes[1]);
    grid.points.z = std::move(planes[2]);

    // Optional screen pixels: PX and PY together, whole numbers.
    const bool has_px = reader.find_channel("PX") != nullptr, has_py = reader.find_channel("PY") != nullptr;
    if (has_px != has_py) fail(path, std::string("has channel ") + (has_px ? "PX" : "PY") + " without " + (has_px ? "PY" : "PX"));
    if (has_px) {
        std::vector<std::uint32_t>* targets[2] = {&grid.pixels.x, &grid.pixels.y};
        const char* pixel_names[2] = {"PX", "PY"};
        for (int c = 0; c < 2; ++c) {
            std::vector<std::uint32_t>& target = *targets[c];
            target.resize(reader.texel_count());
            Imf::FrameBuffer pixel_buffer;
            if (reader.find_channel(pixel_names[c])->type == Imf::UINT) {
                pixel_buffer.insert(pixel_names[c], Imf::Slice::Make(Imf::UINT, target.data(), reader.data_window(),
                                                                     sizeof(std::uint32_t),
                                                                     sizeof(std::uint32_t) * static_cast<std::size_t>(grid.width)));
                reader.read(pixel_buffer);
                continue;
            }
            // HALF or FLOAT: every value a whole number in [0, 2^24] (exact in float).
            std::vector<float> values(reader.texel_count());
            pixel_buffer.insert(pixel_names[c], reader.float_slice(values.data(), sizeof(float),
                                                                   sizeof(float) * static_cast<std::size_t>(grid.width)));
            reader.read(pixel_buffer);
            for (std::size_t i = 0; i < values.size(); ++i) {
                const float value = values[i];
                if (!(value >= 0.0f && value <= 16777216.0f && std::floor(value) == value))
                    fail(path, texel_name(static_cast<long long>(i % static_cast<std::size_t>(grid.width)),
                                          static_cast<long long>(i / static_cast<std::size_t>(grid.width))) +
                                   ": " + pixel_names[c] + " is " + describe_value(value) +
                                   "; screen pixels must be whole numbers in [0, 16777216]");
                target[i] = static_cast<std::uint32_t>(value);
            }
        }
    }
    return grid;
}

void write_receivers_exr(const std::string& path, const ReceiverGrid& receivers) {
    const std::size_t count = static_cast<std::size_t>(std::max(receivers.width, 0)) * std::max(receivers.height, 0);
    if (receivers.points.u.size() != count || receivers.points.v.size() != count || receivers.points.z.size() != count)
        fail(path, "receiver grid size does not match its data");
    ExrImage image;
    image.width = receivers.width;
    image.height = receivers.height;
    image.channels = {{"U", SampleType::float32, receivers.points.u, {}},
                      {"V", SampleType::float32, receivers.points.v, {}},
                      {"Z", SampleType::float32, receivers.points.z, {}}};
    if (!receivers.pixels.x.empty() || !receivers.pixels.y.empty()) {
        if (receivers.pixels.x.size() != count || receivers.pixels.y.size() != count)
            fail(path, "receiver pixels do not match the grid size");
        image.channels.push_back({"PX", SampleType::uint32, {}, receivers.pixels.x});
        image.channels.push_back({"PY", SampleType::uint32, {}, receivers.pixels.y});
    }
    write_exr_atomically(path, image);
}

void write_texture_exr(const std::string& path, const Texture& texture, const TextureInfo& info) {
    const std::size_t words_per_texel = texel_words(texture.format);
    const std::size_t texels = static_cast<std::size_t>(std::max(texture.width, 0)) * std::max(texture.height, 0);
    if (texture.words.size() != texels * words_per_texel) fail(path, "texture size does not match its data");
    if (texels == 0)
        fail(path, "cannot write an image of " + std::to_string(texture.width) + " x " +
                       std::to_string(texture.height) + " texels");
    if (!std::isfinite(info.sigma) || info.sigma < 0.0f) fail(path, "sigma must be finite and >= 0");

    // The channels as docs/formats.md lays them out, and the attributes that tell a reader
    // how to use the texels.
    const TextureLayout layout = texture_layout(texture.format);
    ExrImage image;
    image.width = texture.width;
    image.height = texture.height;
    for (const std::string& name : layout.channels) image.channels.push_back({name, layout.type, {}, {}});
    image.attributes = {{"msmcl:format", std::string(format_name(texture.format))},
                        {"msmcl:sigma", info.sigma},
                        {"msmcl:samples", info.samples},
                        {"msmcl:depthRange", std::string(depth_range_name(info.depth_range))}};
    if (const std::optional<std::string> record = exponents_record(texture))
        image.attributes.push_back({"msmcl:exponents", *record});

    // Encode straight from the texture's words into the file. Whole-word channels (the float
    // bits of moments128, the word of nlq32) are read in place with a texel stride; the
    // 16-bit codes of msm64 and nlq64 are widened to 32-bit channels one band of rows at a time.
    const std::size_t texel_stride = words_per_texel * sizeof(std::uint32_t);
    const std::size_t row_texels = static_cast<std::size_t>(texture.width);
    AtomicFile file(path);
    AtomicFileOutputStream stream(path, file);
    try {
        Imf::OutputFile output(stream, exr_header(image), openexr_threads());
        const Imf::PixelType type = to_pixel_type(layout.type);
        if (layout.bits == 32) {
            Imf::FrameBuffer frame_buffer;
            // (OpenEXR only reads through a slice's base when it writes.)
            char* const texels_base = const_cast<char*>(reinterpret_cast<const char*>(texture.words.data()));
            for (std::size_t c = 0; c < layout.channels.size(); ++c)
                frame_buffer.insert(layout.channels[c], Imf::Slice(type, texels_base + c * sizeof(std::uint32_t),
                                                                   texel_stride, texel_stride * row_texels));
            output.setFrameBuffer(frame_buffer);
            output.writePixels(texture.height);
        } else {
            // Bands of whole ZIP blocks (16 rows) of about 8 MiB of channel values.
            const std::size_t channels = layout.channels.size();
            const std::size_t row_bytes = channels * sizeof(std::uint32_t) * row_texels;
            const int band_rows = static_cast<int>(std::max<std::size_t>(1, (8u << 20) / (16 * row_bytes)) * 16);
            std::vector<std::uint32_t> band(channels * row_texels *
                                            static_cast<std::size_t>(std::min(band_rows, texture.height)));
            for (int first = 0; first < texture.height; first += band_rows) {
                const int rows = std::min(band_rows, texture.height - first);
                const std::size_t band_texels = row_texels * static_cast<std::size_t>(rows);
                const std::uint32_t* words =
                    texture.words.data() + row_texels * static_cast<std::size_t>(first) * words_per_texel;
                for (std::size_t t = 0; t < band_texels; ++t)
                    for (std::size_t c = 0; c < channels; ++c)
                        band[c * band_texels + t] = packed_channel(words + words_per_texel * t, c, layout.bits);
                const Imath::Box2i rows_window(Imath::V2i(0, first), Imath::V2i(texture.width - 1, first + rows - 1));
                Imf::FrameBuffer frame_buffer;
                for (std::size_t c = 0; c < channels; ++c)
                    frame_buffer.insert(layout.channels[c],
                                        Imf::Slice::Make(type, band.data() + c * band_texels, rows_window,
                                                         sizeof(std::uint32_t), sizeof(std::uint32_t) * row_texels));
                output.setFrameBuffer(frame_buffer);
                output.writePixels(rows);
            }
        }
    } catch (const msmcl::error&) {
        throw;
    } catch (const std::exception& e) {
        stream.rethrow_failure();
        throw error(path + ": cannot encode OpenEXR data (" + e.what() + ")");
    }
    // The offset table, written when the OpenEXR file closed, may have failed silently.
    stream.rethrow_failure();
    file.commit();
}

TextureFile read_texture_exr(const std::string& path) {
    ExrReader reader(path);
    const Imf::Header& header = reader.header();

    // The format attribute says which channels to expect.
    if (header.find("msmcl:format") == header.end())
        fail(path, "not an msmcl texture (attribute msmcl:format is missing)");
    const auto* format_attribute = header.findTypedAttribute<Imf::StringAttribute>("msmcl:format");
    if (!format_attribute) fail(path, "attribute msmcl:format is not a string");
    const std::optional<Format> format = parse_format(format_attribute->value());
    if (!format) fail(path, "unknown texture format '" + format_attribute->value() + "' in msmcl:format");

    // The other attributes, each present, of its type, with a usable value.
    TextureFile result;
    const auto* sigma = header.findTypedAttribute<Imf::FloatAttribute>("msmcl:sigma");
    if (!sigma) fail(path, "attribute msmcl:sigma (float) is missing or not a float");
    if (!std::isfinite(sigma->value()) || sigma->value() < 0.0f)
        fail(path, "attribute msmcl:sigma is " + describe_value(sigma->value()) + "; it must be finite and >= 0");
    const auto* samples = header.findTypedAttribute<Imf::IntAttribute>("msmcl:samples");
    if (!samples) fail(path, "attribute msmcl:samples (int) is missing or not an int");
    if (!is_supported_samples(samples->value()))
        fail(path, "attribute msmcl:samples is " + std::to_string(samples->value()) + "; it must be 1, 2, 4, 8 or 16");
    const auto* range = header.findTypedAttribute<Imf::StringAttribute>("msmcl:depthRange");
    if (!range) fail(path, "attribute msmcl:depthRange (string) is missing or not a string");
    const std::optional<DepthRange> depth_range = parse_depth_range(range->value());
    if (!depth_range) fail(path, "attribute msmcl:depthRange is '" + range->value() + "'; it must be 0,1 or -1,1");
    result.info = {sigma->value(), samples->value(), *depth_range};
    std::optional<std::string> exponents;
    if (header.find("msmcl:exponents") != header.end()) {
        const auto* record = header.findTypedAttribute<Imf::StringAttribute>("msmcl:exponents");
        if (!record) fail(path, "attribute msmcl:exponents is not a string");
        exponents = record->value();
    }
    const WarpExponents warp = exponents_of_record(exponents, *format, path);

    // Exactly the channels of the format, of its type.
    const TextureLayout layout = texture_layout(*format);
    const Imf::PixelType wanted_type = to_pixel_type(layout.type);
    for (const std::string& name : layout.channels) {
        const Imf::Channel* channel = reader.find_channel(name);
        if (!channel) fail(path, "missing channel " + name + " for format " + format_name(*format));
        if (channel->type != wanted_type)
            fail(path, "channel " + name + " has type " + sample_type_name(channel->type) + "; format " +
                           format_name(*format) + " needs " + sample_type_name(wanted_type));
    }
    for (const std::string& name : reader.channel_names())
        if (std::find(layout.channels.begin(), layout.channels.end(), name) == layout.channels.end())
            fail(path, "unexpected channel " + name + " for format " + format_name(*format));

    // Read the channels as 32-bit words (float bits for moments128).
    const std::size_t texels = reader.texel_count();
    std::vector<std::vector<std::uint32_t>> planes(layout.channels.size(), std::vector<std::uint32_t>(texels));
    Imf::FrameBuffer frame_buffer;
    for (std::size_t c = 0; c < layout.channels.size(); ++c)
        frame_buffer.insert(layout.channels[c],
                            Imf::Slice::Make(wanted_type, planes[c].data(), reader.data_window(), 4,
                                             4 * static_cast<std::size_t>(reader.width())));
    reader.read(frame_buffer);

    // Pack the channels into the texture's words.
    Texture& texture = result.texture;
    texture.format = *format;
    texture.width = reader.width();
    texture.height = reader.height();
    texture.exponents = warp;
    const std::size_t words_per_texel = texel_words(*format);
    texture.words.assign(texels * words_per_texel, 0u);
    for (std::size_t t = 0; t < texels; ++t) {
        std::uint32_t* words = texture.words.data() + t * words_per_texel;
        for (std::size_t c = 0; c < planes.size(); ++c) {
            if (layout.bits < 32 && planes[c][t] >> layout.bits != 0)
                fail(path, texel_name(static_cast<long long>(t % static_cast<std::size_t>(texture.width)),
                                      static_cast<long long>(t / static_cast<std::size_t>(texture.width))) +
                               " channel " + layout.channels[c] + ": code " + std::to_string(planes[c][t]) +
                               " does not fit " + std::to_string(layout.bits) + " bits");
            words[c * layout.bits / 32] |= planes[c][t] << (c * layout.bits % 32);
        }
    }
    return result;
}

void write_intensity_exr(const std::string& path, int width, int height, const std::vector<float>& intensity) {
    if (width <= 0 || height <= 0 || intensity.size() != static_cast<std::size_t>(width) * height)
        fail(path, "intensity image size does not match its data");
    ExrImage image;
    image.width = width;
    image.height = height;
    image.channels = {{"Y", SampleType::float32, intensity, {}}};
    write_exr_atomically(path, image);
}

} // namespace msmcl::io
