// host/io: EXR depth/receiver/texture/intensity files and PNG previews. No device needed.
#include "io/atomic_file.hpp"
#include "io/exr_io.hpp"
#include "io/png_io.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/formats.hpp>

#include <gtest/gtest.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <half.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using msmcl::DepthImage;
using msmcl::DepthRange;
using msmcl::Format;
using msmcl::Texture;
using msmcl::io::ExrChannel;
using msmcl::io::ExrImage;
using msmcl::io::SampleType;

/// Fixed default seed, printed; MSMCL_TEST_SEED overrides.
std::uint32_t test_seed() {
    static const std::uint32_t seed = [] {
        const char* text = std::getenv("MSMCL_TEST_SEED");
        const std::uint32_t value = text ? static_cast<std::uint32_t>(std::strtoul(text, nullptr, 10)) : 20170729u;
        std::cout << "io_test seed " << value << " (set MSMCL_TEST_SEED to change)" << std::endl;
        return value;
    }();
    return seed;
}

/// A fresh directory per test, removed afterwards.
class IoTest : public ::testing::Test {
protected:
    void SetUp() override {
        std::string pattern = (fs::temp_directory_path() / "msmcl-io-test-XXXXXX").string();
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        directory_ = pattern;
        random_.seed(test_seed());
        RecordProperty("seed", static_cast<int>(test_seed()));
    }
    void TearDown() override { fs::remove_all(directory_); }

    std::string path(const std::string& name) const { return (directory_ / name).string(); }
    /// Names of all entries in the directory (to find leftovers such as temp files).
    std::vector<std::string> entries() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(directory_)) names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }
    std::string bytes_of(const std::string& file) const { return msmcl::io::read_whole_file(file); }

    /// Where the value of the dataWindow attribute (a box2i: min x, min y, max x, max y)
    /// starts in the bytes of an EXR file.
    static std::size_t data_window_at(const std::string& bytes) {
        const std::string key("dataWindow\0box2i\0", 17);
        return bytes.find(key) + key.size() + 4; // after the size field
    }
    /// A real 4x3 depth file (written as small.exr): its bytes and its data_window_at.
    struct SmallExr {
        std::string bytes;
        std::size_t box_at = 0;
    };
    SmallExr small_exr() {
        msmcl::io::write_depth_exr(path("small.exr"), random_depth(4, 3, 1, DepthRange::zero_one));
        const std::string bytes = bytes_of(path("small.exr"));
        return {bytes, data_window_at(bytes)};
    }
    /// `small` with its data window's max corner patched to (max_x, max_y) (the offset table
    /// and data stay those of 4x3), written as `name`; its path.
    std::string with_data_window(const SmallExr& small, const std::string& name, std::int32_t max_x,
                                 std::int32_t max_y) const {
        std::string patched = small.bytes;
        std::memcpy(&patched[small.box_at + 8], &max_x, 4);
        std::memcpy(&patched[small.box_at + 12], &max_y, 4);
        std::ofstream(path(name), std::ios::binary) << patched;
        return path(name);
    }

    /// A depth map with values exactly representable in HALF (k/1024).
    DepthImage random_depth(int width, int height, int samples, DepthRange range) {
        DepthImage depth;
        depth.width = width;
        depth.height = height;
        depth.samples = samples;
        std::uniform_int_distribution<int> code(range == DepthRange::zero_one ? 0 : -1024, 1024);
        depth.depth.resize(static_cast<std::size_t>(width) * height * samples);
        for (float& d : depth.depth) d = static_cast<float>(code(random_)) / 1024.0f;
        return depth;
    }

    /// A texture of the format with random but valid words.
    Texture random_texture(Format format, int width, int height) {
        Texture texture;
        texture.format = format;
        texture.width = width;
        texture.height = height;
        texture.words.resize(static_cast<std::size_t>(width) * height * msmcl::texel_words(format));
        std::uniform_int_distribution<std::uint32_t> word;
        std::uniform_real_distribution<float> moment(-1.0f, 1.0f);
        for (std::uint32_t& w : texture.words) {
            if (format == Format::moments128) {
                const float value = moment(random_);
                std::memcpy(&w, &value, sizeof w);
            } else {
                w = word(random_);
            }
        }
        return texture;
    }

    /// Expects `call` to throw input_error whose message starts with `file` and contains `problem`.
    template <class Call>
    void expect_input_error(Call call, const std::string& file, const std::string& problem) {
        try {
            call();
            ADD_FAILURE() << "no input_error for " << file << " (expected '" << problem << "')";
        } catch (const msmcl::input_error& e) {
            const std::string message = e.what();
            EXPECT_EQ(message.rfind(file + ": ", 0), 0u) << message;
            EXPECT_NE(message.find(problem), std::string::npos) << message << "\n  expected: " << problem;
            EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        }
    }

    fs::path directory_;
    std::mt19937 random_;
};

ExrImage image_with(int width, int height, std::vector<ExrChannel> channels) {
    ExrImage image;
    image.width = width;
    image.height = height;
    image.channels = std::move(channels);
    return image;
}
ExrChannel float_channel(const std::string& name, std::size_t count, float value,
                         SampleType type = SampleType::float32) {
    return ExrChannel{name, type, std::vector<float>(count, value), {}};
}

// ---- Textures ----------------------------------------------------------------------------

TEST_F(IoTest, EveryTextureFormatRoundTripsBitExactly) {
    for (Format format : {Format::moments128, Format::msm64, Format::nlq64, Format::nlq32}) {
        SCOPED_TRACE(msmcl::format_name(format));
        const Texture texture = random_texture(format, 37, 23);
        const msmcl::io::TextureInfo info{1.75f, 8, DepthRange::minus_one_one};
        const std::string file = path(std::string(msmcl::format_name(format)) + ".exr");
        msmcl::io::write_texture_exr(file, texture, info);

        const msmcl::io::TextureFile read = msmcl::io::read_texture_exr(file);
        EXPECT_EQ(read.texture.format, format);
        EXPECT_EQ(read.texture.width, 37);
        EXPECT_EQ(read.texture.height, 23);
        EXPECT_EQ(read.texture.words, texture.words);
        EXPECT_EQ(read.info.sigma, 1.75f);
        EXPECT_EQ(read.info.samples, 8);
        EXPECT_EQ(read.info.depth_range, DepthRange::minus_one_one);
    }
}

TEST_F(IoTest, TextureFilesFollowTheSpecLayout) {
    // docs/formats.md: channel names and types, codes in channels, attributes and their types.
    const Texture nlq64 = random_texture(Format::nlq64, 5, 4);
    msmcl::io::write_texture_exr(path("nlq64.exr"), nlq64, {2.4f, 4, DepthRange::zero_one});
    const ExrImage image = msmcl::io::read_exr(path("nlq64.exr"));
    for (int c = 0; c < 4; ++c) {
        const ExrChannel* channel = image.find_channel(std::string(1, "RGBA"[c]));
        ASSERT_NE(channel, nullptr);
        EXPECT_EQ(channel->type, SampleType::uint32);
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 5; ++x) EXPECT_EQ(channel->codes[y * 5 + x], nlq64.code16(x, y, c));
    }
    ASSERT_NE(image.find_attribute("msmcl:format"), nullptr);
    EXPECT_EQ(std::get<std::string>(image.find_attribute("msmcl:format")->value), "nlq64");
    EXPECT_EQ(std::get<float>(image.find_attribute("msmcl:sigma")->value), 2.4f);
    EXPECT_EQ(std::get<int>(image.find_attribute("msmcl:samples")->value), 4);
    EXPECT_EQ(std::get<std::string>(image.find_attribute("msmcl:depthRange")->value), "0,1");

    const Texture moments = random_texture(Format::moments128, 3, 2);
    msmcl::io::write_texture_exr(path("m128.exr"), moments, {0.0f, 1, DepthRange::zero_one});
    const ExrImage floats = msmcl::io::read_exr(path("m128.exr"));
    ASSERT_EQ(floats.channels.size(), 4u);
    EXPECT_EQ(floats.find_channel("B")->type, SampleType::float32);
    EXPECT_EQ(floats.find_channel("B")->values[4], moments.moment(1, 1, 3));

    const Texture nlq32 = random_texture(Format::nlq32, 3, 2);
    msmcl::io::write_texture_exr(path("n32.exr"), nlq32, {2.4f, 1, DepthRange::zero_one});
    const ExrImage packed = msmcl::io::read_exr(path("n32.exr"));
    ASSERT_EQ(packed.channels.size(), 1u);
    EXPECT_EQ(packed.channels[0].name, "R");
    EXPECT_EQ(packed.channels[0].codes[5], nlq32.code32(2, 1));
}

TEST_F(IoTest, TexturesAreEncodedStraightFromTheirWords) {
    // write_texture_exr encodes from the texture's words (16-bit codes widened in bands of
    // rows; 4096 texels a row makes 128-row bands, so 130 rows take two): the same bytes
    // as the generic writer given the channels as planes, and the same words back.
    for (Format format : {Format::moments128, Format::msm64, Format::nlq64, Format::nlq32}) {
        SCOPED_TRACE(msmcl::format_name(format));
        const bool banded = format == Format::msm64 || format == Format::nlq64;
        const int width = banded ? 4096 : 61, height = banded ? 130 : 37;
        const Texture texture = random_texture(format, width, height);
        const msmcl::io::TextureInfo info{2.4f, 4, DepthRange::zero_one};
        msmcl::io::write_texture_exr(path("direct.exr"), texture, info);

        ExrImage planes;
        planes.width = width;
        planes.height = height;
        const std::size_t texels = static_cast<std::size_t>(width) * height;
        const int channels = format == Format::nlq32 ? 1 : 4;
        for (int c = 0; c < channels; ++c) {
            ExrChannel channel{std::string(1, "RGBA"[c]), format == Format::moments128 ? SampleType::float32 : SampleType::uint32, {}, {}};
            for (int y = 0; y < height; ++y)
                for (int x = 0; x < width; ++x) {
                    if (format == Format::moments128) channel.values.push_back(texture.moment(x, y, c + 1));
                    else if (format == Format::nlq32) channel.codes.push_back(texture.code32(x, y));
                    else channel.codes.push_back(texture.code16(x, y, c));
                }
            ASSERT_EQ(channel.values.size() + channel.codes.size(), texels);
            planes.channels.push_back(std::move(channel));
        }
        planes.attributes = {{"msmcl:format", std::string(msmcl::format_name(format))},
                             {"msmcl:sigma", 2.4f},
                             {"msmcl:samples", 4},
                             {"msmcl:depthRange", std::string("0,1")}};
        msmcl::io::write_exr(path("planes.exr"), planes);
        EXPECT_EQ(bytes_of(path("direct.exr")), bytes_of(path("planes.exr")));
        EXPECT_EQ(msmcl::io::read_texture_exr(path("direct.exr")).texture.words, texture.words);
    }
    EXPECT_EQ(entries(), (std::vector<std::string>{"direct.exr", "planes.exr"}));
}

TEST_F(IoTest, WritesAreByteDeterministic) {
    const Texture texture = random_texture(Format::msm64, 64, 48);
    msmcl::io::write_texture_exr(path("a.exr"), texture, {2.4f, 4, DepthRange::zero_one});
    msmcl::io::write_texture_exr(path("b.exr"), texture, {2.4f, 4, DepthRange::zero_one});
    EXPECT_EQ(bytes_of(path("a.exr")), bytes_of(path("b.exr")));

    const DepthImage depth = random_depth(33, 17, 4, DepthRange::zero_one);
    msmcl::io::write_depth_exr(path("d1.exr"), depth);
    msmcl::io::write_depth_exr(path("d2.exr"), depth);
    EXPECT_EQ(bytes_of(path("d1.exr")), bytes_of(path("d2.exr")));

    const std::vector<float> gray(20 * 10, 0.25f);
    msmcl::io::write_png_preview(path("p1.png"), 20, 10, 1, gray);
    msmcl::io::write_png_preview(path("p2.png"), 20, 10, 1, gray);
    EXPECT_EQ(bytes_of(path("p1.png")), bytes_of(path("p2.png")));
}

TEST_F(IoTest, TextureReaderRejectsWhatItCannotUse) {
    const std::size_t n = 6;
    auto codes = [n](std::uint32_t value) { return std::vector<std::uint32_t>(n, value); };
    auto uint_channel = [&](const std::string& name, std::uint32_t value) {
        return ExrChannel{name, SampleType::uint32, {}, codes(value)};
    };
    auto with_attributes = [](ExrImage image, const std::string& format) {
        image.attributes = {{"msmcl:format", format}, {"msmcl:sigma", 2.4f}, {"msmcl:samples", 1},
                            {"msmcl:depthRange", std::string("0,1")}};
        return image;
    };
    const std::vector<ExrChannel> rgba = {uint_channel("A", 1), uint_channel("B", 2), uint_channel("G", 3),
                                          uint_channel("R", 4)};
    msmcl::io::write_exr(path("ok.exr"), with_attributes(image_with(3, 2, rgba), "msm64"));
    EXPECT_EQ(msmcl::io::read_texture_exr(path("ok.exr")).texture.code16(2, 1, 0), 4);

    msmcl::io::write_exr(path("plain.exr"), image_with(3, 2, rgba));
    expect_input_error([&] { msmcl::io::read_texture_exr(path("plain.exr")); }, path("plain.exr"),
                       "msmcl:format is missing");
    msmcl::io::write_exr(path("unknown.exr"), with_attributes(image_with(3, 2, rgba), "msm128"));
    expect_input_error([&] { msmcl::io::read_texture_exr(path("unknown.exr")); }, path("unknown.exr"),
                       "unknown texture format 'msm128'");
    msmcl::io::write_exr(path("float.exr"), with_attributes(image_with(3, 2, rgba), "moments128"));
    expect_input_error([&] { msmcl::io::read_texture_exr(path("float.exr")); }, path("float.exr"),
                       "channel R has type UINT; format moments128 needs FLOAT");
    msmcl::io::write_exr(path("extra.exr"), with_attributes(image_with(3, 2, rgba), "nlq32"));
    expect_input_error([&] { msmcl::io::read_texture_exr(path("extra.exr")); }, path("extra.exr"),
                       "unexpected channel A for format nlq32");
    std::vector<ExrChannel> three = {uint_channel("B", 2), uint_channel("G", 3), uint_channel("R", 4)};
    msmcl::io::write_exr(path("three.exr"), with_attributes(image_with(3, 2, three), "nlq64"));
    expect_input_error([&] { msmcl::io::read_texture_exr(path("three.exr")); }, path("three.exr"),
                       "missing channel A for format nlq64");
    std::vector<ExrChannel> wide = rgba;
    wide[3].codes[4] = 70000;
    msmcl::io::write_exr(path("wide.exr"), with_attributes(image_with(3, 2, wide), "nlq64"));
    expect_input_error([&] { msmcl::io::read_texture_exr(path("wide.exr")); }, path("wide.exr"),
                       "texel (1, 1) channel R: code 70000 does not fit 16 bits");
    ExrImage bad_range = with_attributes(image_with(3, 2, rgba), "msm64");
    bad_range.attributes[3].value = std::string("0,2");
    msmcl::io::write_exr(path("range.exr"), bad_range);
    expect_input_error([&] { msmcl::io::read_texture_exr(path("range.exr")); }, path("range.exr"),
                       "msmcl:depthRange is '0,2'");
    ExrImage int_sigma = with_attributes(image_with(3, 2, rgba), "msm64");
    int_sigma.attributes[1].value = 2;
    msmcl::io::write_exr(path("sigma.exr"), int_sigma);
    expect_input_error([&] { msmcl::io::read_texture_exr(path("sigma.exr")); }, path("sigma.exr"),
                       "msmcl:sigma (float) is missing or not a float");
}

// ---- Depth maps ----------------------------------------------------------------------------

TEST_F(IoTest, DepthRoundTripsForEverySampleCountInTexelMajorOrder) {
    for (int samples : {1, 2, 4, 8, 16}) {
        SCOPED_TRACE(samples);
        const DepthImage depth = random_depth(19, 7, samples, DepthRange::zero_one);
        msmcl::io::write_depth_exr(path("depth.exr"), depth);
        const ExrImage raw = msmcl::io::read_exr(path("depth.exr"));
        ASSERT_EQ(raw.channels.size(), static_cast<std::size_t>(samples));
        EXPECT_NE(raw.find_channel(samples == 1 ? "Z" : "sample" + std::to_string(samples - 1) + ".Z"), nullptr);

        const DepthImage read = msmcl::io::read_depth_exr(path("depth.exr"), DepthRange::zero_one);
        EXPECT_EQ(read.width, 19);
        EXPECT_EQ(read.height, 7);
        EXPECT_EQ(read.samples, samples);
        EXPECT_EQ(read.depth, depth.depth);
        EXPECT_EQ(read.at(18, 6, samples - 1), depth.at(18, 6, samples - 1));
    }
}

TEST_F(IoTest, DepthReadsHalfTiledAndOffsetDataWindows) {
    // HALF: the k/1024 values survive exactly; also [-1,1] content.
    const DepthImage depth = random_depth(40, 36, 4, DepthRange::minus_one_one);
    msmcl::io::write_depth_exr(path("half.exr"), depth, SampleType::half);
    EXPECT_EQ(msmcl::io::read_depth_exr(path("half.exr"), DepthRange::minus_one_one).depth, depth.depth);

    // Tiled file with a data window that does not start at (0, 0).
    ExrImage tiled = image_with(40, 36, {});
    tiled.tiled = true;
    tiled.x_origin = -7;
    tiled.y_origin = 12;
    for (int s = 0; s < 2; ++s) {
        ExrChannel channel = float_channel("sample" + std::to_string(s) + ".Z", 40 * 36, 0.0f);
        for (std::size_t t = 0; t < channel.values.size(); ++t) channel.values[t] = static_cast<float>(t % 97) / 97.0f + s * 0.001f;
        tiled.channels.push_back(channel);
    }
    tiled.channels.push_back(float_channel("R", 40 * 36, 7.0f)); // unrelated channels are ignored
    msmcl::io::write_exr(path("tiled.exr"), tiled);
    const DepthImage read = msmcl::io::read_depth_exr(path("tiled.exr"), DepthRange::zero_one);
    ASSERT_EQ(read.samples, 2);
    EXPECT_EQ(read.width, 40);
    EXPECT_EQ(read.height, 36);
    EXPECT_EQ(read.at(5, 3, 0), tiled.channels[0].values[3 * 40 + 5]);
    EXPECT_EQ(read.at(39, 35, 1), tiled.channels[1].values[35 * 40 + 39]);
}

TEST_F(IoTest, DepthReadsEveryCompressionOfScanlineFiles) {
    // Files written by OpenEXR itself: FLOAT samples in every compression (OpenEXRCore decodes
    // those, blocks of 1 to 32 rows, a last block cut short), a HALF and a UINT channel that
    // the depth reader skips, and a data window that does not start at (0, 0).
    const int width = 45, height = 37, samples = 4;
    std::vector<std::vector<float>> values(samples, std::vector<float>(width * height));
    for (int s = 0; s < samples; ++s)
        for (int t = 0; t < width * height; ++t) values[s][t] = static_cast<float>((t * 7919 + s * 104729) % 65536) / 65536.0f;
    std::vector<half> other_half(width * height, half(0.25f));
    std::vector<std::uint32_t> other_uint(width * height, 7u);
    const Imath::Box2i window(Imath::V2i(-3, 5), Imath::V2i(-3 + width - 1, 5 + height - 1));
    for (const Imf::Compression compression : {Imf::NO_COMPRESSION, Imf::RLE_COMPRESSION, Imf::ZIPS_COMPRESSION,
                                               Imf::ZIP_COMPRESSION, Imf::PIZ_COMPRESSION, Imf::PXR24_COMPRESSION}) {
        const std::string file = path("compression" + std::to_string(compression) + ".exr");
        {
            Imf::Header header(window, window, 1.0f, Imath::V2f(0, 0), 1.0f, Imf::INCREASING_Y, compression);
            Imf::FrameBuffer frame;
            const auto at = [&](auto* data) {
                return reinterpret_cast<char*>(data) - (static_cast<std::ptrdiff_t>(window.min.y) * width + window.min.x) *
                                                           static_cast<std::ptrdiff_t>(sizeof(*data));
            };
            for (int s = 0; s < samples; ++s) {
                const std::string name = "sample" + std::to_string(s) + ".Z";
                header.channels().insert(name, Imf::Channel(Imf::FLOAT));
                frame.insert(name, Imf::Slice(Imf::FLOAT, at(values[s].data()), sizeof(float), sizeof(float) * width));
            }
            header.channels().insert("A", Imf::Channel(Imf::HALF));
            frame.insert("A", Imf::Slice(Imf::HALF, at(other_half.data()), sizeof(half), sizeof(half) * width));
            header.channels().insert("id", Imf::Channel(Imf::UINT));
            frame.insert("id", Imf::Slice(Imf::UINT, at(other_uint.data()), 4, 4 * width));
            Imf::OutputFile output(file.c_str(), header);
            output.setFrameBuffer(frame);
            output.writePixels(height);
        }
        const DepthImage read = msmcl::io::read_depth_exr(file, DepthRange::zero_one);
        ASSERT_EQ(read.width, width);
        ASSERT_EQ(read.height, height);
        ASSERT_EQ(read.samples, samples);
        // PXR24 keeps 24 of a float's 32 bits; the others give the values back exactly.
        for (int s = 0; s < samples; ++s)
            for (int t = 0; t < width * height; t += 1) {
                const float expected = values[s][t];
                if (compression == Imf::PXR24_COMPRESSION)
                    ASSERT_NEAR(read.at(t % width, t / width, s), expected, 1.0f / 32768.0f) << file << " texel " << t;
                else
                    ASSERT_EQ(read.at(t % width, t / width, s), expected) << file << " texel " << t << " sample " << s;
            }
    }
}

TEST_F(IoTest, DepthBlocksThatDoNotDecodeAreNamed) {
    // ZIPS and ZIP files of equal depths (each block deflates to a few bytes) whose last
    // byte, the zlib checksum of the last block, is changed: refused with the file's name,
    // whichever decoder meets it first.
    for (const Imf::Compression compression : {Imf::ZIPS_COMPRESSION, Imf::ZIP_COMPRESSION}) {
        const int width = 16, height = 20;
        std::vector<float> depth(width * height, 0.5f);
        {
            const Imath::Box2i window(Imath::V2i(0, 0), Imath::V2i(width - 1, height - 1));
            Imf::Header header(window, window, 1.0f, Imath::V2f(0, 0), 1.0f, Imf::INCREASING_Y, compression);
            header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
            Imf::FrameBuffer frame;
            frame.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(depth.data()), sizeof(float), sizeof(float) * width));
            Imf::OutputFile output(path("depth.exr").c_str(), header);
            output.setFrameBuffer(frame);
            output.writePixels(height);
        }
        ASSERT_EQ(msmcl::io::read_depth_exr(path("depth.exr"), DepthRange::zero_one).depth, depth);
        std::string bytes = bytes_of(path("depth.exr"));
        bytes.back() = static_cast<char>(bytes.back() ^ 0x5A);
        std::ofstream(path("bad.exr"), std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        expect_input_error([&] { msmcl::io::read_depth_exr(path("bad.exr"), DepthRange::zero_one); }, path("bad.exr"),
                           "corrupt or truncated OpenEXR file (Error reading pixel data from image file. Data "
                           "decompression (zlib) failed.)");
    }
}

TEST_F(IoTest, DepthReaderNamesTheFileAndTheProblem) {
    const std::size_t n = 8 * 4;
    auto write = [&](const std::string& name, std::vector<ExrChannel> channels, int width = 8, int height = 4) {
        msmcl::io::write_exr(path(name), image_with(width, height, std::move(channels)));
        return path(name);
    };
    auto read = [](const std::string& file, DepthRange range = DepthRange::zero_one) {
        return [file, range] { msmcl::io::read_depth_exr(file, range); };
    };

    expect_input_error(read(path("absent.exr")), path("absent.exr"), "cannot open: No such file or directory");
    std::ofstream(path("text.exr")) << "this is not an image\n";
    expect_input_error(read(path("text.exr")), path("text.exr"), "not an OpenEXR file");

    // Truncated: a valid file cut in half.
    msmcl::io::write_depth_exr(path("whole.exr"), random_depth(64, 64, 4, DepthRange::zero_one));
    const std::string whole = bytes_of(path("whole.exr"));
    std::ofstream(path("half.exr"), std::ios::binary).write(whole.data(), static_cast<std::streamsize>(whole.size() / 2));
    expect_input_error(read(path("half.exr")), path("half.exr"), "corrupt or truncated OpenEXR file");
    // Header only (cut inside the header).
    std::ofstream(path("stub.exr"), std::ios::binary).write(whole.data(), 40);
    expect_input_error(read(path("stub.exr")), path("stub.exr"), "corrupt or truncated OpenEXR file");

    expect_input_error(read(write("rgb.exr", {float_channel("R", n, 0), float_channel("G", n, 0)})), path("rgb.exr"),
                       "missing depth channel: expected Z or sample0.Z .. sample<S-1>.Z (channels: G, R)");
    expect_input_error(read(write("gap.exr", {float_channel("sample0.Z", n, 0), float_channel("sample2.Z", n, 0)})),
                       path("gap.exr"), "sample1.Z is missing");
    expect_input_error(read(write("three.exr", {float_channel("sample0.Z", n, 0), float_channel("sample1.Z", n, 0),
                                                float_channel("sample2.Z", n, 0)})),
                       path("three.exr"), "unsupported sample count 3");
    expect_input_error(read(write("mixed.exr", {float_channel("Z", n, 0), float_channel("sample0.Z", n, 0)})),
                       path("mixed.exr"), "both a Z channel and sample<N>.Z layers");
    expect_input_error(read(write("zero.exr", {float_channel("sample00.Z", n, 0)})), path("zero.exr"),
                       "bad sample layer name 'sample00.Z'");
    expect_input_error(read(write("uint.exr", {ExrChannel{"Z", SampleType::uint32, {}, std::vector<std::uint32_t>(n, 0)}})),
                       path("uint.exr"), "channel Z has type UINT; it must be HALF or FLOAT");
    ExrChannel subsampled = float_channel("Z", n / 4, 0.5f);
    subsampled.x_sampling = 2;
    subsampled.y_sampling = 2;
    expect_input_error(read(write("sub.exr", {subsampled})), path("sub.exr"), "channel Z is subsampled (2x2)");
    expect_input_error(read(write("wide.exr", {float_channel("Z", 65537, 0.5f)}, 65537, 1)), path("wide.exr"),
                       "data window 65537 x 1 is too large");

    // Data windows patched in the header: empty (OpenEXR refuses it) and absurd (we do).
    const SmallExr small = small_exr();
    ASSERT_LT(small.box_at, small.bytes.size());
    expect_input_error(read(with_data_window(small, "empty.exr", -1, 2)), path("empty.exr"), "empty data window");
    expect_input_error(read(with_data_window(small, "absurd.exr", 3, 99999)), path("absurd.exr"),
                       "data window 4 x 100000 is too large (at most 65536 per side)");

    // Bad values: the first bad texel and its value are named.
    ExrChannel values = float_channel("sample1.Z", n, 0.5f);
    values.values[2 * 8 + 3] = std::numeric_limits<float>::quiet_NaN();
    expect_input_error(read(write("nan.exr", {float_channel("sample0.Z", n, 0.5f), values})), path("nan.exr"),
                       "texel (3, 2) sample1.Z: depth is NaN");
    values.values[2 * 8 + 3] = -std::numeric_limits<float>::infinity();
    expect_input_error(read(write("inf.exr", {float_channel("sample0.Z", n, 0.5f), values})), path("inf.exr"),
                       "texel (3, 2) sample1.Z: depth is -Inf");
    values.values[2 * 8 + 3] = 1.5f;
    expect_input_error(read(write("high.exr", {float_channel("sample0.Z", n, 0.5f), values})), path("high.exr"),
                       "texel (3, 2) sample1.Z: depth 1.5 is outside the depth range [0,1]");
    ExrChannel negative = float_channel("Z", n, -0.25f);
    expect_input_error(read(write("neg.exr", {negative})), path("neg.exr"), "texel (0, 0) Z: depth -0.25 is outside");
    EXPECT_NO_THROW(msmcl::io::read_depth_exr(path("neg.exr"), DepthRange::minus_one_one));
    negative.values[n - 1] = -1.5f;
    expect_input_error(read(write("neg2.exr", {negative}), DepthRange::minus_one_one), path("neg2.exr"),
                       "texel (7, 3) Z: depth -1.5 is outside the depth range [-1,1]");
}

TEST_F(IoTest, ImageSizesAreCappedAndCheckedAgainstTheFile) {
    // A real 4x3 file whose header is patched to claim a larger data window (the offset
    // table and data stay those of 4x3): refused from the header alone, before anything
    // of the claimed size is allocated.
    const SmallExr small = small_exr();
    ASSERT_LT(small.box_at, small.bytes.size());
    const auto depth_of = [](const std::string& file) {
        return [file] { msmcl::io::read_depth_exr(file, DepthRange::zero_one); };
    };
    // 60000^2 texels: over the texel limit (2^28).
    expect_input_error(depth_of(with_data_window(small, "huge.exr", 59999, 59999)), path("huge.exr"),
                       "60000 x 60000 texels exceed the limit of 268435456 (MSMCL_MAX_TEXELS)");
    // 16000^2 FLOAT texels fit the limits (1.02e9 bytes), but not the few hundred bytes of
    // the file even at zlib's largest expansion.
    const std::string claims = with_data_window(small, "claims.exr", 15999, 15999);
    expect_input_error(depth_of(claims), claims, "the header claims 16000 x 16000 texels (1024000000 bytes of data)");
    expect_input_error([&] { msmcl::io::read_exr(claims); }, claims, "more than the");
    // An attribute whose size field claims 2 GB: refused before OpenEXR would allocate it.
    std::string claims_size = small.bytes;
    const std::int32_t huge_size = 0x7fffffff;
    std::memcpy(&claims_size[small.box_at - 4], &huge_size, 4);
    std::ofstream(path("attribute.exr"), std::ios::binary) << claims_size;
    expect_input_error(depth_of(path("attribute.exr")), path("attribute.exr"),
                       "attribute dataWindow (box2i) claims 2147483647 bytes");
    // A size field that disagrees with the value OpenEXR reads by the type's own layout
    // (here the data window's box2i, 16 bytes): refused, since OpenEXR would lose step
    // with the size fields and take later bytes for sizes.
    std::string box_size = small.bytes;
    const std::int32_t box_plus_one = 17;
    std::memcpy(&box_size[small.box_at - 4], &box_plus_one, 4);
    std::ofstream(path("box_size.exr"), std::ios::binary) << box_size;
    expect_input_error(depth_of(path("box_size.exr")), path("box_size.exr"),
                       "attribute dataWindow (box2i) has a size field of 17 bytes but a value of 16");
    // A string vector whose string claims 2 GB inside an 8-byte value: OpenEXR would size
    // the string by that length before reading it.
    const std::string strings("names\0stringvector\0\x08\0\0\0\xff\xff\xff\x7f" "abcd", 31);
    std::ofstream(path("strings.exr"), std::ios::binary) << small.bytes.substr(0, 8) + strings + small.bytes.substr(8);
    expect_input_error(depth_of(path("strings.exr")), path("strings.exr"),
                       "attribute names (stringvector) has a size field of 8 bytes");
    // Tiles of 1 x 1 over 8192 x 8192: refused before OpenEXR sizes its tile tables.
    ExrImage tiled = image_with(64, 64, {float_channel("Z", 64 * 64, 0.5f)});
    tiled.tiled = true;
    msmcl::io::write_exr(path("tiled.exr"), tiled);
    std::string tiles = bytes_of(path("tiled.exr"));
    const std::string tiles_key("tiles\0tiledesc\0", 15);
    const std::size_t tiles_at = tiles.find(tiles_key) + tiles_key.size() + 4;
    const std::size_t window_at = data_window_at(tiles);
    ASSERT_LT(tiles_at, tiles.size());
    const std::uint32_t one = 1;
    const std::int32_t last = 8191;
    std::memcpy(&tiles[tiles_at], &one, 4);
    std::memcpy(&tiles[tiles_at + 4], &one, 4);
    std::memcpy(&tiles[window_at + 8], &last, 4);
    std::memcpy(&tiles[window_at + 12], &last, 4);
    std::ofstream(path("tiles.exr"), std::ios::binary) << tiles;
    expect_input_error(depth_of(path("tiles.exr")), path("tiles.exr"), "the header claims 8192 x 8192 texels");
    // The limits are the environment's when set.
    msmcl::io::write_depth_exr(path("four.exr"), random_depth(16, 16, 4, DepthRange::zero_one));
    ASSERT_EQ(::setenv("MSMCL_MAX_TEXELS", "255", 1), 0);
    expect_input_error(depth_of(path("four.exr")), path("four.exr"), "16 x 16 texels exceed the limit of 255");
    ASSERT_EQ(::setenv("MSMCL_MAX_TEXELS", "256", 1), 0);
    EXPECT_NO_THROW(msmcl::io::read_depth_exr(path("four.exr"), DepthRange::zero_one));
    ASSERT_EQ(::setenv("MSMCL_MAX_BYTES", "4095", 1), 0); // 16 bytes per texel (4 FLOAT samples)
    expect_input_error(depth_of(path("four.exr")), path("four.exr"), "exceed the limit of 4095 bytes (MSMCL_MAX_BYTES)");
    ASSERT_EQ(::setenv("MSMCL_MAX_BYTES", "100", 1), 0); // smaller than the file itself
    expect_input_error(depth_of(path("four.exr")), path("four.exr"), "bytes exceed the limit of 100 bytes");
    ASSERT_EQ(::setenv("MSMCL_MAX_BYTES", "lots", 1), 0);
    EXPECT_THROW(msmcl::io::read_depth_exr(path("four.exr"), DepthRange::zero_one), msmcl::input_error);
    ::unsetenv("MSMCL_MAX_TEXELS");
    ::unsetenv("MSMCL_MAX_BYTES");
    EXPECT_NO_THROW(msmcl::io::read_depth_exr(path("four.exr"), DepthRange::zero_one));
}

// ---- Receivers, intensity, PNG ---------------------------------------------------------

TEST_F(IoTest, ReceiversRoundTripAndAreValidated) {
    msmcl::io::ReceiverGrid grid;
    grid.width = 6;
    grid.height = 5;
    for (int i = 0; i < 30; ++i) {
        grid.points.u.push_back(-3.0f + i);
        grid.points.v.push_back(100.5f - i);
        grid.points.z.push_back(i / 30.0f);
    }
    msmcl::io::write_receivers_exr(path("r.exr"), grid);
    const msmcl::io::ReceiverGrid read = msmcl::io::read_receivers_exr(path("r.exr"));
    EXPECT_EQ(read.width, 6);
    EXPECT_EQ(read.height, 5);
    EXPECT_EQ(read.points.u, grid.points.u);
    EXPECT_EQ(read.points.v, grid.points.v);
    EXPECT_EQ(read.points.z, grid.points.z);

    msmcl::io::write_exr(path("nov.exr"), image_with(2, 2, {float_channel("U", 4, 0), float_channel("Z", 4, 0)}));
    expect_input_error([&] { msmcl::io::read_receivers_exr(path("nov.exr")); }, path("nov.exr"), "missing channel V");
    msmcl::io::write_exr(path("nan.exr"), image_with(2, 2, {float_channel("U", 4, 0), float_channel("V", 4, NAN),
                                                            float_channel("Z", 4, 0)}));
    expect_input_error([&] { msmcl::io::read_receivers_exr(path("nan.exr")); }, path("nan.exr"),
                       "texel (0, 0): V is NaN");
}

TEST_F(IoTest, IntensityIsOneFloatChannelY) {
    const std::vector<float> intensity = {0.0f, 0.25f, 1.0f, 0.5f, 0.125f, 0.75f};
    msmcl::io::write_intensity_exr(path("y.exr"), 3, 2, intensity);
    const ExrImage image = msmcl::io::read_exr(path("y.exr"));
    ASSERT_EQ(image.channels.size(), 1u);
    EXPECT_EQ(image.channels[0].name, "Y");
    EXPECT_EQ(image.channels[0].type, SampleType::float32);
    EXPECT_EQ(image.channels[0].values, intensity);
    EXPECT_EQ(image.width, 3);
    EXPECT_EQ(image.height, 2);
}

TEST_F(IoTest, PngPreviewDecodesToTheMappedLevels) {
    // Gray: linear map of [black, white] to [0, 255], clamped, NaN -> 0.
    const std::vector<float> gray = {-1.0f, 0.0f, 0.5f, 1.0f, 2.0f, NAN};
    msmcl::io::write_png_preview(path("g.png"), 3, 2, 1, gray);
    png_image decoded{};
    decoded.version = PNG_IMAGE_VERSION;
    ASSERT_TRUE(png_image_begin_read_from_file(&decoded, path("g.png").c_str()));
    EXPECT_EQ(decoded.width, 3u);
    EXPECT_EQ(decoded.height, 2u);
    decoded.format = PNG_FORMAT_GRAY;
    std::vector<unsigned char> pixels(PNG_IMAGE_SIZE(decoded));
    ASSERT_TRUE(png_image_finish_read(&decoded, nullptr, pixels.data(), 0, nullptr));
    EXPECT_EQ(pixels, (std::vector<unsigned char>{0, 0, 128, 255, 255, 0}));

    // RGB with a custom range.
    msmcl::io::write_png_preview(path("c.png"), 1, 1, 3, {10.0f, 15.0f, 20.0f}, 10.0f, 20.0f);
    png_image colour{};
    colour.version = PNG_IMAGE_VERSION;
    ASSERT_TRUE(png_image_begin_read_from_file(&colour, path("c.png").c_str()));
    colour.format = PNG_FORMAT_RGB;
    std::vector<unsigned char> rgb(PNG_IMAGE_SIZE(colour));
    ASSERT_TRUE(png_image_finish_read(&colour, nullptr, rgb.data(), 0, nullptr));
    EXPECT_EQ(rgb, (std::vector<unsigned char>{0, 128, 255}));
}

// ---- Atomic writes -----------------------------------------------------------------------

TEST_F(IoTest, WritesAreAtomicAndLeaveNoTemporaryFiles) {
    // Replacing an existing file works and leaves only the final name.
    std::ofstream(path("out.exr")) << "old content";
    msmcl::io::write_intensity_exr(path("out.exr"), 1, 1, {0.5f});
    EXPECT_EQ(entries(), std::vector<std::string>{"out.exr"});
    EXPECT_EQ(msmcl::io::read_exr(path("out.exr")).channels[0].values[0], 0.5f);

    // A failure before writing (bad data) leaves the old file untouched.
    const std::string before = bytes_of(path("out.exr"));
    EXPECT_THROW(msmcl::io::write_intensity_exr(path("out.exr"), 2, 2, {0.5f}), msmcl::input_error);
    EXPECT_EQ(bytes_of(path("out.exr")), before);

    // Missing directory: input_error naming the file, nothing created.
    expect_input_error([&] { msmcl::io::write_intensity_exr(path("no/such/dir.exr"), 1, 1, {0.0f}); },
                       path("no/such/dir.exr"), "cannot write: No such file or directory");
    // A directory under the final name.
    fs::create_directory(path("sub"));
    expect_input_error([&] { msmcl::io::write_intensity_exr(path("sub"), 1, 1, {0.0f}); }, path("sub"),
                       "is a directory");
    EXPECT_EQ(entries(), (std::vector<std::string>{"out.exr", "sub"}));
    EXPECT_TRUE(fs::is_empty(path("sub")));
}

} // namespace
