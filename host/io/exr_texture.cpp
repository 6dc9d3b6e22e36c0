// Filtered textures in EXR files (exr_io.hpp, docs/formats.md): one channel per texel
// channel of the format's row in the format table, and the msmcl:* attributes that say
// how the texels were made; written straight from the texture's words, streamed to disk.
#include "io/texture_metadata.hpp"
#include "io/exr_file.hpp"

#include "io/atomic_file.hpp"
#include "runtime/texture_kinds.hpp"

#include <msmcl/errors.hpp>

#include <ImfFloatAttribute.h>
#include <ImfIntAttribute.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include <algorithm>
#include <cmath>
#include <exception>

namespace msmcl::io {
using namespace exr;
namespace {

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

} // namespace msmcl::io
