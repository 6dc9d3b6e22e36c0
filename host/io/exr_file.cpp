// An EXR file in general (exr_file.hpp): opening and checking a file for every layout's
// reader, the generic reader and writer of any image (read_exr, write_exr), the header
// msmcl writes and the words of its messages.
#include "io/exr_file.hpp"

#include "io/atomic_file.hpp"
#include "io/exr_header_check.hpp"
#include "io/image_limits.hpp"

#include <msmcl/errors.hpp>

#include <ImfAttribute.h>
#include <ImfFloatAttribute.h>
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
#include <cmath>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <set>
#include <thread>

namespace msmcl::io {
namespace exr {
namespace {

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

} // namespace

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
    throw input_error(path + ": " + problem);
}

int openexr_threads() {
    static std::once_flag started;
    std::call_once(started, [] {
        if (Imf::globalThreadCount() == 0)
            Imf::setGlobalThreadCount(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
    });
    return Imf::globalThreadCount();
}

std::string openexr_problem(const std::string& path, const std::exception& e) {
    std::string message = e.what();
    const std::string quoted = " \"" + path + "\"";
    for (std::size_t at = message.find(quoted); at != std::string::npos; at = message.find(quoted))
        message.erase(at, quoted.size());
    return "corrupt or truncated OpenEXR file (" + message + ")";
}

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

ExrReader::ExrReader(const std::string& path) : path_(path) {
    // Load the bytes and look at the magic number before OpenEXR does.
    // (a file of another kind is refused after its first four bytes, not read whole).
    std::string bytes = read_input_file(path, {image_limits().max_bytes, "MSMCL_MAX_BYTES",
                                               std::string("\x76\x2f\x31\x01", 4), "an OpenEXR file"});
    const std::uint64_t file_bytes = bytes.size();
    if (bytes.size() < 4 || !Imf::isImfMagic(bytes.data())) fail(path, "not an OpenEXR file");

    // Check the first header alone before OpenEXR sizes its tables by the data window.
    check_header_attributes(path, bytes);
    stream_ = std::make_unique<MemoryInputStream>(path, std::move(bytes));
    const Imath::Box2i window = check_first_header(path, *stream_, file_bytes);
    width_ = window.max.x - window.min.x + 1;
    height_ = window.max.y - window.min.y + 1;

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

std::string list_names(const std::vector<std::string>& names) {
    if (names.empty()) return "none";
    std::string text;
    for (std::size_t i = 0; i < names.size() && i < 8; ++i) text += (i ? ", " : "") + names[i];
    if (names.size() > 8) text += ", ...";
    return text;
}

void require_float_channel(const ExrReader& reader, const std::string& name, const std::string& purpose) {
    const Imf::Channel* channel = reader.find_channel(name);
    if (!channel)
        fail(reader.path(), "missing channel " + name + " (" + purpose + "; channels: " +
                                list_names(reader.channel_names()) + ")");
    if (channel->type != Imf::HALF && channel->type != Imf::FLOAT)
        fail(reader.path(), "channel " + name + " has type " + sample_type_name(channel->type) +
                                "; it must be HALF or FLOAT");
}

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

void write_exr_atomically(const std::string& path, const ExrImage& image) {
    const std::string bytes = encode_exr(path, image);
    write_file_atomically(path, bytes.data(), bytes.size());
}

} // namespace exr

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

void write_exr(const std::string& path, const ExrImage& image) { exr::write_exr_atomically(path, image); }

ExrImage read_exr(const std::string& path) {
    exr::ExrReader reader(path);
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

} // namespace msmcl::io
