// Texture containers (host/io/ktx2.*, host/io/dds.*): the byte layouts of the KTX 2.0 and
// DDS (DX10) specifications, checked field by field against values written out here from
// the specs, bit-identical round trips of every format (plain and arrays, random texels),
// filtered textures through files, the CLI's --out-container, and the decoders' errors.
// The CLI's container rules: every command that reads a texture (shade, soft) reads all
// three containers with the same result, every command that writes one (filter, sat)
// writes all three, an unknown output extension is exit 2 with no output, and DDS files
// whose texels do not tell their format are refused unless --format / --max-kernel says.
// `msmcl info` on every kind of file, as text and JSON (nlohmann-json).
// Debian 12 packages no KTX2 tool (KTX-Software's `ktx` is not packaged) and no reader known
// to take these DX10 DDS formats (ImageMagick 6 and Pillow 9 target DXT/BC; not tried), so
// the layouts are pinned here instead. Seed: MSMCL_TEST_SEED (default 6).
#include "io/atomic_file.hpp"
#include "io/dds.hpp"
#include "io/exr_io.hpp"
#include "io/gpu_image.hpp"
#include "io/ktx2.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/formats.hpp>
#include <msmcl/sat.hpp>
#include <msmcl/version.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#ifndef MSMCL_CLI_PATH
#define MSMCL_CLI_PATH ""
#endif

namespace {

namespace fs = std::filesystem;
using msmcl::io::GpuFormat;
using msmcl::io::GpuImage;

unsigned test_seed() {
    static const unsigned seed = [] {
        const char* text = std::getenv("MSMCL_TEST_SEED");
        const unsigned value = text ? static_cast<unsigned>(std::strtoul(text, nullptr, 10)) : 6u;
        std::printf("containers_test: seed %u (MSMCL_TEST_SEED overrides)\n", value);
        return value;
    }();
    return seed;
}

std::uint32_t u32_at(const std::vector<std::uint8_t>& bytes, std::size_t at) {
    std::uint32_t value = 0;
    for (int i = 0; i < 4; ++i) value |= std::uint32_t(bytes.at(at + i)) << (8 * i);
    return value;
}
std::uint64_t u64_at(const std::vector<std::uint8_t>& bytes, std::size_t at) {
    return std::uint64_t(u32_at(bytes, at)) | (std::uint64_t(u32_at(bytes, at + 4)) << 32);
}

GpuImage random_image(GpuFormat format, int width, int height, int layers, std::mt19937& random) {
    GpuImage image;
    image.format = format;
    image.width = width;
    image.height = height;
    image.layers = layers;
    image.array = layers > 1;
    image.bytes.resize(image.expected_bytes());
    for (std::uint8_t& byte : image.bytes) byte = static_cast<std::uint8_t>(random());
    return image;
}

constexpr GpuFormat kFormats[] = {GpuFormat::r16g16b16a16_unorm, GpuFormat::r32_uint, GpuFormat::r32g32b32a32_sfloat,
                                  GpuFormat::r32g32b32a32_uint, GpuFormat::a2b10g10r10_unorm_pack32};

TEST(GpuFormats, VulkanAndDxgiValues) {
    // VkFormat (vulkan_core.h) and DXGI_FORMAT (dxgiformat.h) enumerators.
    EXPECT_EQ(msmcl::io::gpu_format_info(GpuFormat::r16g16b16a16_unorm).vk_format, 91u);
    EXPECT_EQ(msmcl::io::gpu_format_info(GpuFormat::r16g16b16a16_unorm).dxgi_format, 11u);
    EXPECT_EQ(msmcl::io::gpu_format_info(GpuFormat::r32_uint).vk_format, 98u);
    EXPECT_EQ(msmcl::io::gpu_format_info(GpuFormat::r32_uint).dxgi_format, 42u);
    EXPECT_EQ(msmcl::io::gpu_format_info(GpuFormat::r32g32b32a32_sfloat).vk_format, 109u);
    EXPECT_EQ(msmcl::io::gpu_format_info(GpuFormat::r32g32b32a32_sfloat).dxgi_format, 2u);
    EXPECT_EQ(msmcl::io::gpu_format_info(GpuFormat::r32g32b32a32_uint).vk_format, 107u);
    EXPECT_EQ(msmcl::io::gpu_format_info(GpuFormat::r32g32b32a32_uint).dxgi_format, 3u);
    EXPECT_EQ(msmcl::io::gpu_format_info(GpuFormat::a2b10g10r10_unorm_pack32).vk_format, 64u);
    EXPECT_EQ(msmcl::io::gpu_format_info(GpuFormat::a2b10g10r10_unorm_pack32).dxgi_format, 24u);
    EXPECT_EQ(msmcl::io::gpu_format_of(msmcl::Format::msm64), GpuFormat::r16g16b16a16_unorm);
    EXPECT_EQ(msmcl::io::gpu_format_of(msmcl::Format::nlq64), GpuFormat::r16g16b16a16_unorm);
    EXPECT_EQ(msmcl::io::gpu_format_of(msmcl::Format::nlq32), GpuFormat::r32_uint);
    EXPECT_EQ(msmcl::io::gpu_format_of(msmcl::Format::moments128), GpuFormat::r32g32b32a32_sfloat);
}

// The data format descriptors, word by word, as the Khronos Data Format Specification 1.3
// (and libktx's vk2dfd) spell them for these Vulkan formats.
TEST(Ktx2, DataFormatDescriptors) {
    const auto header = [](std::uint32_t samples, std::uint32_t bytes) {
        const std::uint32_t block = 24 + 16 * samples;
        return std::vector<std::uint32_t>{4 + block, 0, 2 | (block << 16), 0x00010101u, 0, bytes, 0};
    };
    const auto sample = [](std::uint32_t offset, std::uint32_t bits, std::uint32_t channel, std::uint32_t lower,
                           std::uint32_t upper) {
        return std::array<std::uint32_t, 4>{offset | ((bits - 1) << 16) | (channel << 24), 0, lower, upper};
    };
    const auto descriptor = [](std::vector<std::uint32_t> words, std::initializer_list<std::array<std::uint32_t, 4>> samples) {
        for (const auto& s : samples) words.insert(words.end(), s.begin(), s.end());
        return words;
    };
    EXPECT_EQ(msmcl::io::ktx2_data_format_descriptor(GpuFormat::r16g16b16a16_unorm),
              descriptor(header(4, 8), {sample(0, 16, 0, 0, 0xFFFF), sample(16, 16, 1, 0, 0xFFFF),
                                        sample(32, 16, 2, 0, 0xFFFF), sample(48, 16, 15, 0, 0xFFFF)}));
    EXPECT_EQ(msmcl::io::ktx2_data_format_descriptor(GpuFormat::r32_uint),
              descriptor(header(1, 4), {sample(0, 32, 0, 0, 1)}));
    EXPECT_EQ(msmcl::io::ktx2_data_format_descriptor(GpuFormat::r32g32b32a32_uint),
              descriptor(header(4, 16), {sample(0, 32, 0, 0, 1), sample(32, 32, 1, 0, 1), sample(64, 32, 2, 0, 1),
                                         sample(96, 32, 15, 0, 1)}));
    // Float samples: qualifiers FLOAT | SIGNED, lower -1.0f, upper 1.0f.
    EXPECT_EQ(msmcl::io::ktx2_data_format_descriptor(GpuFormat::r32g32b32a32_sfloat),
              descriptor(header(4, 16), {sample(0, 32, 0xC0, 0xBF800000u, 0x3F800000u),
                                         sample(32, 32, 0xC1, 0xBF800000u, 0x3F800000u),
                                         sample(64, 32, 0xC2, 0xBF800000u, 0x3F800000u),
                                         sample(96, 32, 0xCF, 0xBF800000u, 0x3F800000u)}));
    EXPECT_EQ(msmcl::io::ktx2_data_format_descriptor(GpuFormat::a2b10g10r10_unorm_pack32),
              descriptor(header(4, 4), {sample(0, 10, 0, 0, 1023), sample(10, 10, 1, 0, 1023),
                                        sample(20, 10, 2, 0, 1023), sample(30, 2, 15, 0, 3)}));
}

TEST(Ktx2, ByteLayoutOfTheHeaderIndexAndLevel) {
    std::mt19937 random(test_seed());
    GpuImage image = random_image(GpuFormat::r16g16b16a16_unorm, 5, 3, 1, random);
    image.metadata = {{"msmcl:format", "nlq64"}, {"msmcl:depthRange", "0,1"}};
    const std::vector<std::uint8_t> file = msmcl::io::encode_ktx2(image);

    const std::uint8_t identifier[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
    EXPECT_EQ(std::memcmp(file.data(), identifier, 12), 0);
    EXPECT_EQ(u32_at(file, 12), 91u); // vkFormat
    EXPECT_EQ(u32_at(file, 16), 2u);  // typeSize
    EXPECT_EQ(u32_at(file, 20), 5u);  // pixelWidth
    EXPECT_EQ(u32_at(file, 24), 3u);  // pixelHeight
    EXPECT_EQ(u32_at(file, 28), 0u);  // pixelDepth
    EXPECT_EQ(u32_at(file, 32), 0u);  // layerCount: not an array
    EXPECT_EQ(u32_at(file, 36), 1u);  // faceCount
    EXPECT_EQ(u32_at(file, 40), 1u);  // levelCount
    EXPECT_EQ(u32_at(file, 44), 0u);  // supercompressionScheme
    // Index: the DFD right after the one-level index, key/value data right after the DFD.
    const std::uint32_t dfd_offset = u32_at(file, 48), dfd_length = u32_at(file, 52);
    EXPECT_EQ(dfd_offset, 104u);
    EXPECT_EQ(dfd_length, 4u + 24u + 4u * 16u);
    EXPECT_EQ(u32_at(file, dfd_offset), dfd_length); // dfdTotalSize
    const std::uint32_t kvd_offset = u32_at(file, 56), kvd_length = u32_at(file, 60);
    EXPECT_EQ(kvd_offset, dfd_offset + dfd_length);
    EXPECT_EQ(kvd_length % 4, 0u);
    EXPECT_EQ(u64_at(file, 64), 0u); // sgdByteOffset
    EXPECT_EQ(u64_at(file, 72), 0u); // sgdByteLength
    // Level 0: aligned to lcm(8, 4) after the key/value data, then the texels, then nothing.
    const std::uint64_t level_offset = u64_at(file, 80);
    EXPECT_EQ(level_offset % 8, 0u);
    EXPECT_GE(level_offset, kvd_offset + kvd_length);
    EXPECT_LT(level_offset, kvd_offset + kvd_length + 8u);
    EXPECT_EQ(u64_at(file, 88), image.bytes.size());
    EXPECT_EQ(u64_at(file, 96), image.bytes.size());
    EXPECT_EQ(file.size(), level_offset + image.bytes.size());
    EXPECT_EQ(std::memcmp(file.data() + level_offset, image.bytes.data(), image.bytes.size()), 0);

    // Key/value pairs: sorted by key, NUL after key and value, each padded to 4 bytes.
    std::vector<std::string> keys;
    for (std::size_t at = kvd_offset; at < kvd_offset + kvd_length;) {
        const std::uint32_t length = u32_at(file, at);
        const std::string pair(reinterpret_cast<const char*>(file.data() + at + 4), length);
        ASSERT_EQ(pair.back(), '\0');
        keys.push_back(pair.substr(0, pair.find('\0')));
        if (keys.back() == "KTXorientation") EXPECT_EQ(pair, std::string("KTXorientation\0rd\0", 18));
        if (keys.back() == "KTXwriter")
            EXPECT_EQ(pair, std::string("KTXwriter\0msmcl ", 16) + msmcl::version_string + std::string(1, '\0'));
        at += 4 + (length + 3) / 4 * 4;
    }
    EXPECT_EQ(keys, (std::vector<std::string>{"KTXorientation", "KTXwriter", "msmcl:depthRange", "msmcl:format"}));
}

TEST(Dds, ByteLayoutOfTheHeaders) {
    std::mt19937 random(test_seed() + 1);
    const GpuImage image = random_image(GpuFormat::r32_uint, 7, 2, 1, random);
    const std::vector<std::uint8_t> file = msmcl::io::encode_dds(image);
    ASSERT_EQ(file.size(), 148u + image.bytes.size());
    EXPECT_EQ(u32_at(file, 0), 0x20534444u);  // "DDS "
    EXPECT_EQ(u32_at(file, 4), 124u);         // dwSize
    EXPECT_EQ(u32_at(file, 8), 0x2100Fu);     // CAPS | HEIGHT | WIDTH | PITCH | PIXELFORMAT | MIPMAPCOUNT
    EXPECT_EQ(u32_at(file, 12), 2u);          // dwHeight
    EXPECT_EQ(u32_at(file, 16), 7u);          // dwWidth
    EXPECT_EQ(u32_at(file, 20), 28u);         // dwPitchOrLinearSize: row bytes
    EXPECT_EQ(u32_at(file, 24), 0u);          // dwDepth
    EXPECT_EQ(u32_at(file, 28), 1u);          // dwMipMapCount
    for (std::size_t at = 32; at < 76; at += 4) EXPECT_EQ(u32_at(file, at), 0u) << "dwReserved1 at " << at;
    EXPECT_EQ(u32_at(file, 76), 32u);         // ddspf.dwSize
    EXPECT_EQ(u32_at(file, 80), 4u);          // DDPF_FOURCC
    EXPECT_EQ(u32_at(file, 84), 0x30315844u); // "DX10"
    for (std::size_t at = 88; at < 108; at += 4) EXPECT_EQ(u32_at(file, at), 0u);
    EXPECT_EQ(u32_at(file, 108), 0x1000u);    // DDSCAPS_TEXTURE
    for (std::size_t at = 112; at < 128; at += 4) EXPECT_EQ(u32_at(file, at), 0u);
    EXPECT_EQ(u32_at(file, 128), 42u);        // DXGI_FORMAT_R32_UINT
    EXPECT_EQ(u32_at(file, 132), 3u);         // D3D10_RESOURCE_DIMENSION_TEXTURE2D
    EXPECT_EQ(u32_at(file, 136), 0u);         // miscFlag
    EXPECT_EQ(u32_at(file, 140), 1u);         // arraySize
    EXPECT_EQ(u32_at(file, 144), 0u);         // alpha mode unknown: one channel
    EXPECT_EQ(std::memcmp(file.data() + 148, image.bytes.data(), image.bytes.size()), 0);

    const GpuImage rgba = random_image(GpuFormat::r32g32b32a32_sfloat, 3, 3, 2, random);
    const std::vector<std::uint8_t> array_file = msmcl::io::encode_dds(rgba);
    EXPECT_EQ(u32_at(array_file, 128), 2u);   // DXGI_FORMAT_R32G32B32A32_FLOAT
    EXPECT_EQ(u32_at(array_file, 140), 2u);   // arraySize
    EXPECT_EQ(u32_at(array_file, 144), 4u);   // DDS_ALPHA_MODE_CUSTOM: A is data
    EXPECT_EQ(array_file.size(), 148u + rgba.bytes.size());
}

// Random texels of every format, plain and as 2-layer arrays, through both containers.
TEST(Containers, EveryFormatRoundTripsBitIdentically) {
    std::mt19937 random(test_seed() + 2);
    for (GpuFormat format : kFormats) {
        for (int layers : {1, 2}) {
            SCOPED_TRACE(std::string(msmcl::io::gpu_format_info(format).name) + " layers " + std::to_string(layers));
            GpuImage image = random_image(format, 1 + random() % 40, 1 + random() % 30, layers, random);
            image.metadata = {{"msmcl:format", "test"}, {"zeta", "last"}, {"alpha", std::string("with\tbytes\x7f")}};

            const GpuImage from_ktx2 = msmcl::io::decode_ktx2(msmcl::io::encode_ktx2(image), "memory.ktx2");
            EXPECT_EQ(from_ktx2.format, format);
            EXPECT_EQ(from_ktx2.width, image.width);
            EXPECT_EQ(from_ktx2.height, image.height);
            EXPECT_EQ(from_ktx2.layers, layers);
            EXPECT_EQ(from_ktx2.array, image.array);
            EXPECT_EQ(from_ktx2.bytes, image.bytes);
            for (const auto& [key, value] : image.metadata) EXPECT_EQ(from_ktx2.find_metadata(key), value) << key;
            EXPECT_EQ(from_ktx2.find_metadata("KTXorientation"), std::string("rd"));

            const GpuImage from_dds = msmcl::io::decode_dds(msmcl::io::encode_dds(image), "memory.dds");
            EXPECT_EQ(from_dds.format, format);
            EXPECT_EQ(from_dds.width, image.width);
            EXPECT_EQ(from_dds.height, image.height);
            EXPECT_EQ(from_dds.layers, layers);
            EXPECT_EQ(from_dds.bytes, image.bytes);
        }
    }
}

TEST(Containers, DecodersRefuseBrokenFiles) {
    std::mt19937 random(test_seed() + 3);
    const GpuImage image = random_image(GpuFormat::r32_uint, 4, 4, 1, random);
    const auto message_of = [](auto decode) -> std::string {
        try {
            decode();
        } catch (const msmcl::input_error& e) {
            return e.what();
        }
        return "no input_error";
    };
    const std::vector<std::uint8_t> ktx2 = msmcl::io::encode_ktx2(image);
    std::vector<std::uint8_t> broken = ktx2;
    broken[3] = 'Y';
    EXPECT_NE(message_of([&] { msmcl::io::decode_ktx2(broken, "a.ktx2"); }).find("a.ktx2: not a KTX2 file"),
              std::string::npos);
    broken = ktx2;
    broken.resize(broken.size() - 1);
    EXPECT_NE(message_of([&] { msmcl::io::decode_ktx2(broken, "a.ktx2"); }).find("truncated"), std::string::npos);
    broken = ktx2;
    broken[12] = 37; // VK_FORMAT_R8G8B8A8_UNORM
    EXPECT_NE(message_of([&] { msmcl::io::decode_ktx2(broken, "a.ktx2"); }).find("unsupported vkFormat 37"),
              std::string::npos);
    broken = ktx2;
    broken[104 + 12] ^= 0x02; // colour primaries in the DFD
    EXPECT_NE(message_of([&] { msmcl::io::decode_ktx2(broken, "a.ktx2"); }).find("data format descriptor"),
              std::string::npos);

    const std::vector<std::uint8_t> dds = msmcl::io::encode_dds(image);
    broken = dds;
    broken.resize(100);
    EXPECT_NE(message_of([&] { msmcl::io::decode_dds(broken, "a.dds"); }).find("a.dds: truncated"), std::string::npos);
    broken = dds;
    broken.pop_back();
    EXPECT_NE(message_of([&] { msmcl::io::decode_dds(broken, "a.dds"); }).find("bytes of texels"), std::string::npos);
    broken = dds;
    broken[86] = 'T'; // FourCC "DXT1": a legacy file
    broken[87] = '1';
    EXPECT_NE(message_of([&] { msmcl::io::decode_dds(broken, "a.dds"); }).find("DX10"), std::string::npos);
    broken = dds;
    broken[128] = 28; // DXGI_FORMAT_R8G8B8A8_UNORM
    EXPECT_NE(message_of([&] { msmcl::io::decode_dds(broken, "a.dds"); }).find("unsupported DXGI format 28"),
              std::string::npos);
    EXPECT_NE(message_of([&] { msmcl::io::read_ktx2("/nonexistent/x.ktx2"); }).find("/nonexistent/x.ktx2"),
              std::string::npos);
}

class ContainerFiles : public ::testing::Test {
protected:
    void SetUp() override {
        directory_ = fs::temp_directory_path() / ("msmcl-containers-" + std::to_string(::getpid()));
        fs::create_directories(directory_);
    }
    void TearDown() override { fs::remove_all(directory_); }

    static msmcl::DepthImage random_depth(int width, int height, int samples, unsigned seed) {
        std::mt19937 random(seed);
        std::uniform_real_distribution<float> unit(0.0f, 1.0f);
        msmcl::DepthImage depth;
        depth.width = width;
        depth.height = height;
        depth.samples = samples;
        for (int i = 0; i < width * height * samples; ++i) depth.depth.push_back(0.1f + 0.8f * unit(random));
        return depth;
    }
    std::string path(const std::string& name) const { return (directory_ / name).string(); }

    fs::path directory_;
};

// Filtered textures and a summed-area table through files, reloaded bit-identically.
TEST_F(ContainerFiles, FilteredTexturesReloadBitIdentically) {
    msmcl::Context context;
    const msmcl::DepthImage depth = random_depth(29, 23, 2, test_seed() + 4);
    for (msmcl::Format format : {msmcl::Format::moments128, msmcl::Format::msm64, msmcl::Format::nlq64,
                                 msmcl::Format::nlq32}) {
        SCOPED_TRACE(msmcl::format_name(format));
        msmcl::FilterOptions options;
        options.format = format;
        const msmcl::Texture texture = msmcl::filter(context, depth, options);
        msmcl::io::write_ktx2(path("map.ktx2"), msmcl::io::gpu_image_of(texture));
        msmcl::io::write_dds(path("map.dds"), msmcl::io::gpu_image_of(texture));
        const GpuImage from_ktx2 = msmcl::io::read_ktx2(path("map.ktx2"));
        EXPECT_EQ(from_ktx2.find_metadata("msmcl:format"), std::string(msmcl::format_name(format)));
        EXPECT_EQ(msmcl::io::texture_of(from_ktx2, format, "map.ktx2").words, texture.words);
        EXPECT_EQ(msmcl::io::texture_of(msmcl::io::read_dds(path("map.dds")), format, "map.dds").words, texture.words);
    }
    msmcl::SatOptions sat_options;
    const msmcl::SatTable table = msmcl::build_sat(context, depth, sat_options);
    msmcl::io::write_ktx2(path("sat.ktx2"), msmcl::io::gpu_image_of(table));
    const GpuImage sat = msmcl::io::read_ktx2(path("sat.ktx2"));
    EXPECT_EQ(sat.format, GpuFormat::r32g32b32a32_uint);
    EXPECT_EQ(sat.find_metadata("msmcl:scale"), std::to_string(table.scale));
    ASSERT_EQ(sat.bytes.size(), table.words.size() * 4);
    EXPECT_EQ(std::memcmp(sat.bytes.data(), table.words.data(), sat.bytes.size()), 0);
    EXPECT_THROW(msmcl::io::texture_of(sat, msmcl::Format::nlq32, "sat.ktx2"), msmcl::input_error);
}

// msmcl filter --out-container: the same texels as the EXR output, the record in KTX2.
TEST_F(ContainerFiles, CliWritesKtx2AndDds) {
    const std::string cli = MSMCL_CLI_PATH;
    if (cli.empty()) GTEST_SKIP() << "built without the msmcl CLI";
    const msmcl::DepthImage depth = random_depth(40, 24, 4, test_seed() + 5);
    msmcl::io::write_depth_exr(path("depth.exr"), depth);
    const auto run = [&](const std::string& arguments) {
        return std::system(("'" + cli + "' filter '" + path("depth.exr") + "' " + arguments + " 2>'" +
                            path("stderr.txt") + "'")
                               .c_str());
    };
    ASSERT_EQ(run("'" + path("map.exr") + "' --format nlq64 --sigma 1.5"), 0);
    ASSERT_EQ(run("'" + path("map.ktx2") + "' --format nlq64 --sigma 1.5"), 0);
    ASSERT_EQ(run("'" + path("map.bin") + "' --format nlq64 --sigma 1.5 --out-container dds"), 0);
    const msmcl::io::TextureFile exr = msmcl::io::read_texture_exr(path("map.exr"));
    const GpuImage ktx2 = msmcl::io::read_ktx2(path("map.ktx2"));
    EXPECT_EQ(msmcl::io::texture_of(ktx2, msmcl::Format::nlq64, "map.ktx2").words, exr.texture.words);
    EXPECT_EQ(ktx2.find_metadata("msmcl:format"), std::string("nlq64"));
    EXPECT_EQ(ktx2.find_metadata("msmcl:sigma"), std::string("1.5"));
    EXPECT_EQ(ktx2.find_metadata("msmcl:samples"), std::string("4"));
    EXPECT_EQ(ktx2.find_metadata("msmcl:depthRange"), std::string("0,1"));
    EXPECT_EQ(msmcl::io::texture_of(msmcl::io::read_dds(path("map.bin")), msmcl::Format::nlq64, "map.bin").words,
              exr.texture.words);

    // A bad container is a usage error: exit 2, one line, no output.
    const int status = run("'" + path("map.png") + "' --format nlq64 --out-container png");
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 2);
    EXPECT_FALSE(fs::exists(path("map.png")));
    const std::string message = msmcl::io::read_whole_file(path("stderr.txt"));
    EXPECT_NE(message.find("--out-container 'png'"), std::string::npos) << message;
    EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 1) << message;
}


// Runs the CLI through the shell; stderr goes to a file. Returns the exit code (-1 on a signal).
class CliContainers : public ContainerFiles {
protected:
    void SetUp() override {
        ContainerFiles::SetUp();
        if (std::string(MSMCL_CLI_PATH).empty()) GTEST_SKIP() << "built without the msmcl CLI";
        msmcl::io::write_depth_exr(path("depth.exr"), random_depth(37, 29, 2, test_seed() + 7));
        msmcl::io::ReceiverGrid receivers;
        receivers.width = 13;
        receivers.height = 11;
        std::mt19937 random(test_seed() + 8);
        std::uniform_real_distribution<float> u(0.0f, 37.0f), v(0.0f, 29.0f), z(0.0f, 1.0f);
        for (int i = 0; i < receivers.width * receivers.height; ++i) {
            receivers.points.u.push_back(u(random));
            receivers.points.v.push_back(v(random));
            receivers.points.z.push_back(z(random));
        }
        msmcl::io::write_receivers_exr(path("receivers.exr"), receivers);
    }
    int cli(const std::string& arguments) {
        const int status = std::system(("'" + std::string(MSMCL_CLI_PATH) + "' " + arguments + " 2>'" +
                                        path("stderr.txt") + "'").c_str());
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    std::string err() const { return msmcl::io::read_whole_file(path("stderr.txt")); }
    std::string q(const std::string& name) const { return "'" + path(name) + "'"; }
    std::string bytes(const std::string& name) const { return msmcl::io::read_whole_file(path(name)); }
    // Exit 2, one line naming `file` and containing `words`, and `output` not written.
    void expect_refused(const std::string& arguments, const std::string& file, const std::string& words,
                        const std::string& output) {
        SCOPED_TRACE(arguments);
        EXPECT_EQ(cli(arguments), 2);
        const std::string message = err();
        EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 1) << message;
        EXPECT_NE(message.find(file), std::string::npos) << message;
        EXPECT_NE(message.find(words), std::string::npos) << message;
        EXPECT_FALSE(fs::exists(path(output))) << output;
    }
};

// filter writes every container; shade reads each of them and gives the same bytes.
TEST_F(CliContainers, ShadeReadsMapsFromEveryContainer) {
    for (const char* format : {"moments128", "msm64", "nlq64", "nlq32"}) {
        SCOPED_TRACE(format);
        for (const char* extension : {"exr", "ktx2", "dds"})
            ASSERT_EQ(cli("filter " + q("depth.exr") + " " + q(std::string("map.") + extension) + " --format " + format),
                      0) << err();
        // DDS maps of 16-bit texels need --format; it is harmless (and checked) elsewhere.
        const std::string dds_format = " --format " + std::string(format);
        ASSERT_EQ(cli("shade " + q("map.exr") + " " + q("receivers.exr") + " " + q("y_exr.exr")), 0) << err();
        ASSERT_EQ(cli("shade " + q("map.ktx2") + " " + q("receivers.exr") + " " + q("y_ktx2.exr")), 0) << err();
        ASSERT_EQ(cli("shade " + q("map.dds") + " " + q("receivers.exr") + " " + q("y_dds.exr") + dds_format), 0)
            << err();
        EXPECT_EQ(bytes("y_ktx2.exr"), bytes("y_exr.exr"));
        EXPECT_EQ(bytes("y_dds.exr"), bytes("y_exr.exr"));
    }
    // The container is recognized by its bytes, not its name.
    fs::copy_file(path("map.ktx2"), path("ktx2_named.exr"));
    ASSERT_EQ(cli("shade " + q("ktx2_named.exr") + " " + q("receivers.exr") + " " + q("y_named.exr")), 0) << err();
    EXPECT_EQ(bytes("y_named.exr"), bytes("y_exr.exr"));
}

// sat writes every container; soft reads each of them and gives the same bytes.
// The VSM, EVSM and ESM formats: the same texels in EXR, KTX2 and DDS, each container's pixel
// format the table's (docs/formats.md), and the exponents recorded in EXR and KTX2.
TEST_F(CliContainers, FilterableFormatsInEveryContainer) {
    const struct {
        const char* format;
        std::uint32_t vk_format, dxgi_format;
        msmcl::WarpExponents exponents;
    } cases[] = {{"vsm32", 77, 35, {}},           {"vsm64", 103, 16, {}},
                 {"evsm2_32", 83, 34, {5.54f, 0}}, {"evsm4_64", 97, 10, {5.54f, 5.54f}},
                 {"evsm4_128", 109, 2, {40, 5}},   {"esm32", 100, 41, {80, 0}}};
    for (const auto& c : cases) {
        SCOPED_TRACE(c.format);
        const msmcl::Format format = *msmcl::parse_format(c.format);
        for (const char* extension : {"exr", "ktx2", "dds"})
            ASSERT_EQ(cli("filter " + q("depth.exr") + " " + q(std::string("map.") + extension) + " --format " + c.format),
                      0) << err();
        const msmcl::io::TextureFile exr = msmcl::io::read_texture_exr(path("map.exr"));
        const GpuImage ktx2 = msmcl::io::read_ktx2(path("map.ktx2")), dds = msmcl::io::read_dds(path("map.dds"));
        EXPECT_EQ(msmcl::io::gpu_format_info(ktx2.format).vk_format, c.vk_format);
        EXPECT_EQ(msmcl::io::gpu_format_info(dds.format).dxgi_format, c.dxgi_format);
        const msmcl::Texture from_ktx2 = msmcl::io::texture_of(ktx2, format, "map.ktx2");
        EXPECT_EQ(from_ktx2.words, exr.texture.words);
        EXPECT_EQ(msmcl::io::texture_of(dds, format, "map.dds").words, exr.texture.words);
        EXPECT_EQ(exr.texture.exponents, c.exponents);
        EXPECT_EQ(from_ktx2.exponents, c.exponents);
    }
    // Given exponents are recorded and read back; DDS, which keeps no record, refuses them.
    ASSERT_EQ(cli("filter " + q("depth.exr") + " " + q("e.ktx2") + " --format evsm4_64 --exponents 3,2.5"), 0) << err();
    const GpuImage ktx2 = msmcl::io::read_ktx2(path("e.ktx2"));
    EXPECT_EQ(ktx2.find_metadata("msmcl:exponents"), std::string("3,2.5"));
    EXPECT_EQ(msmcl::io::texture_of(ktx2, msmcl::Format::evsm4_64, "e.ktx2").exponents, (msmcl::WarpExponents{3, 2.5f}));
    expect_refused("filter " + q("depth.exr") + " " + q("e.dds") + " --format evsm4_64 --exponents 3,2.5", "e.dds",
                   "keeps no record of the exponents", "e.dds");
    // Options of another representation and exponents beyond the storage's limit: exit 2.
    expect_refused("filter " + q("depth.exr") + " " + q("m.ktx2") + " --format msm64 --exponents 3,2", "--exponents",
                   "not msm64", "m.ktx2");
    expect_refused("filter " + q("depth.exr") + " " + q("m.ktx2") + " --format evsm4_64 --exponent 3", "--exponent",
                   "not evsm4_64", "m.ktx2");
    expect_refused("filter " + q("depth.exr") + " " + q("m.ktx2") + " --format esm32 --exponent 89", "esm32",
                   "safe limit 88", "m.ktx2");
    expect_refused("filter " + q("depth.exr") + " " + q("m.ktx2") + " --format evsm2_32 --exponents 6", "evsm2_32",
                   "safe limit 5.54", "m.ktx2");
}

TEST_F(CliContainers, SoftReadsTablesFromEveryContainer) {
    for (const char* extension : {"exr", "ktx2", "dds"})
        ASSERT_EQ(cli("sat " + q("depth.exr") + " " + q(std::string("sat.") + extension) + " --max-kernel 100"), 0)
            << err();
    const std::string options = " --light-size 8 --search-size 6";
    ASSERT_EQ(cli("soft " + q("sat.exr") + " " + q("receivers.exr") + " " + q("s_exr.exr") + options), 0) << err();
    ASSERT_EQ(cli("soft " + q("sat.ktx2") + " " + q("receivers.exr") + " " + q("s_ktx2.exr") + options), 0) << err();
    ASSERT_EQ(cli("soft " + q("sat.dds") + " " + q("receivers.exr") + " " + q("s_dds.exr") + options +
                  " --max-kernel 100"), 0) << err();
    EXPECT_EQ(bytes("s_ktx2.exr"), bytes("s_exr.exr"));
    EXPECT_EQ(bytes("s_dds.exr"), bytes("s_exr.exr"));
    // The table words themselves are the same in every container.
    const GpuImage ktx2 = msmcl::io::read_ktx2(path("sat.ktx2"));
    EXPECT_EQ(ktx2.find_metadata("msmcl:maxKernelTexels"), std::string("100"));
    EXPECT_EQ(ktx2.bytes, msmcl::io::read_dds(path("sat.dds")).bytes);
}

// Unknown output extensions and contradicting --out-container: exit 2, nothing written.
TEST_F(CliContainers, UnknownOutputExtensionsAreRefused) {
    ASSERT_EQ(cli("filter " + q("depth.exr") + " " + q("map.exr") + " --format nlq64"), 0) << err();
    ASSERT_EQ(cli("sat " + q("depth.exr") + " " + q("sat.exr")), 0) << err();
    expect_refused("filter " + q("depth.exr") + " " + q("out.png") + " --format nlq64", "out.png",
                   "unknown output extension '.png'", "out.png");
    expect_refused("filter " + q("depth.exr") + " " + q("noextension") + " --format nlq64", "noextension",
                   "unknown output extension", "noextension");
    expect_refused("filter " + q("depth.exr") + " " + q("t.ktx2") + " --format nlq64 --out-container dds", "t.ktx2",
                   "--out-container says dds", "t.ktx2");
    expect_refused("sat " + q("depth.exr") + " " + q("t.png"), "t.png", "unknown output extension '.png'", "t.png");
    expect_refused("shade " + q("map.exr") + " " + q("receivers.exr") + " " + q("y.ktx2"), "y.ktx2",
                   "name it .exr", "y.ktx2");
    expect_refused("soft " + q("sat.exr") + " " + q("receivers.exr") + " " + q("y.png") + " --light-size 4", "y.png",
                   "name it .exr", "y.png");
    // An input that is no container at all.
    std::system(("echo hello > " + q("text.exr")).c_str());
    expect_refused("shade " + q("text.exr") + " " + q("receivers.exr") + " " + q("y.exr"), "text.exr",
                   "not an OpenEXR, KTX2 or DDS file", "y.exr");
}

// DDS records no format and no N: msm64/nlq64 and moments128/evsm4_128 maps and tables are
// refused unless the user says, and the error names the option; a --format that contradicts
// the file is refused.
TEST_F(CliContainers, AmbiguousDdsNeedsTheUserToSay) {
    ASSERT_EQ(cli("filter " + q("depth.exr") + " " + q("msm.dds") + " --format msm64"), 0) << err();
    ASSERT_EQ(cli("filter " + q("depth.exr") + " " + q("m128.dds") + " --format moments128"), 0) << err();
    ASSERT_EQ(cli("filter " + q("depth.exr") + " " + q("nlq.ktx2") + " --format nlq64"), 0) << err();
    ASSERT_EQ(cli("sat " + q("depth.exr") + " " + q("sat.dds")), 0) << err();
    expect_refused("shade " + q("msm.dds") + " " + q("receivers.exr") + " " + q("y.exr"), "msm.dds", "--format", "y.exr");
    expect_refused("shade " + q("m128.dds") + " " + q("receivers.exr") + " " + q("y.exr") + " --format nlq32",
                   "m128.dds", "--format says nlq32", "y.exr");
    // R32G32B32A32_FLOAT texels are moments128 or evsm4_128.
    expect_refused("shade " + q("m128.dds") + " " + q("receivers.exr") + " " + q("y.exr"), "m128.dds",
                   "--format moments128 or --format evsm4_128", "y.exr");
    expect_refused("shade " + q("nlq.ktx2") + " " + q("receivers.exr") + " " + q("y.exr") + " --format msm64",
                   "nlq.ktx2", "holds a nlq64 texture", "y.exr");
    expect_refused("soft " + q("sat.dds") + " " + q("receivers.exr") + " " + q("y.exr") + " --light-size 4", "sat.dds",
                   "--max-kernel", "y.exr");
    // Said, they are read.
    EXPECT_EQ(cli("shade " + q("msm.dds") + " " + q("receivers.exr") + " " + q("y1.exr") + " --format msm64"), 0) << err();
    EXPECT_EQ(cli("shade " + q("m128.dds") + " " + q("receivers.exr") + " " + q("y2.exr") + " --format moments128"), 0)
        << err();
    EXPECT_EQ(cli("soft " + q("sat.dds") + " " + q("receivers.exr") + " " + q("y3.exr") + " --light-size 4 --max-kernel 729"),
              0) << err();
}


// msmcl info: kind, size, format, samples, layers, attributes, ranges and counts of
// NaN/Inf/out-of-range values for every kind of file, in text and in JSON.
TEST_F(CliContainers, InfoDescribesEveryKindOfFile) {
    // A broken depth map (which filter refuses) is described, with its bad values counted.
    msmcl::io::ExrImage broken;
    broken.width = 4;
    broken.height = 2;
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    broken.channels = {{"Z", msmcl::io::SampleType::float32, {0.5f, nan, inf, 1.5f, -0.25f, 0.0f, 1.0f, nan}, {}},
                       {"layer0.Z", msmcl::io::SampleType::float32, std::vector<float>(8, 0.25f), {}},
                       {"layer0.A", msmcl::io::SampleType::float32, std::vector<float>(8, 2.0f), {}}};
    msmcl::io::write_exr(path("broken.exr"), broken);
    ASSERT_EQ(cli("filter " + q("depth.exr") + " " + q("map.ktx2") + " --format nlq32 --sigma 1.5"), 0) << err();
    ASSERT_EQ(cli("filter " + q("depth.exr") + " " + q("map.exr") + " --format msm64"), 0) << err();
    ASSERT_EQ(cli("filter " + q("depth.exr") + " " + q("map.dds") + " --format nlq64"), 0) << err();
    ASSERT_EQ(cli("sat " + q("depth.exr") + " " + q("sat.exr") + " --max-kernel 100"), 0) << err();
    ASSERT_EQ(cli("shade " + q("map.exr") + " " + q("receivers.exr") + " " + q("y.exr")), 0) << err();

    const std::string files = q("broken.exr") + " " + q("depth.exr") + " " + q("receivers.exr") + " " + q("map.exr") +
                              " " + q("map.ktx2") + " " + q("map.dds") + " " + q("sat.exr") + " " + q("y.exr");
    ASSERT_EQ(cli("info --json " + files + " > " + q("info.json")), 0) << err();
    const nlohmann::json all = nlohmann::json::parse(bytes("info.json"));
    ASSERT_EQ(all.size(), 8u);
    const auto channel = [](const nlohmann::json& info, const std::string& name) {
        for (const nlohmann::json& c : info.at("channels"))
            if (c.at("name") == name) return c;
        ADD_FAILURE() << "no channel " << name << " in " << info.dump();
        return nlohmann::json::object();
    };
    // Broken depth map: 2 NaN, 1 Inf, 2 finite values outside [0, 1]; opacities 2.0 outside [0, 1].
    const nlohmann::json& depth_info = all[0];
    EXPECT_EQ(depth_info.at("kind"), "depth map");
    EXPECT_EQ(depth_info.at("width"), 4);
    EXPECT_EQ(depth_info.at("samples"), 1);
    EXPECT_EQ(depth_info.at("translucent_layers"), 1);
    EXPECT_EQ(depth_info.at("layers"), 1); // an EXR holds one array layer
    const nlohmann::json z = channel(depth_info, "Z");
    EXPECT_EQ(z.at("nan"), 2);
    EXPECT_EQ(z.at("inf"), 1);
    EXPECT_EQ(z.at("out_of_range"), 2);
    EXPECT_EQ(z.at("min"), -0.25);
    EXPECT_EQ(z.at("max"), 1.5);
    EXPECT_EQ(channel(depth_info, "layer0.A").at("out_of_range"), 8);
    // The good depth map: 2 samples, nothing bad.
    EXPECT_EQ(all[1].at("samples"), 2);
    EXPECT_EQ(channel(all[1], "sample1.Z").at("out_of_range"), 0);
    EXPECT_EQ(all[2].at("kind"), "receivers");
    // Maps in every container: format, record and decoded quantities.
    EXPECT_EQ(all[3].at("kind"), "moment shadow map");
    EXPECT_EQ(all[3].at("format"), "msm64");
    EXPECT_EQ(all[3].at("attributes").at("msmcl:format"), "msm64");
    EXPECT_EQ(channel(all[3], "b2").at("count"), 37 * 29);
    EXPECT_EQ(all[4].at("container"), "ktx2");
    EXPECT_EQ(all[4].at("format"), "nlq32");
    EXPECT_EQ(all[4].at("attributes").at("msmcl:sigma"), 1.5); // a number, as in EXR
    EXPECT_EQ(all[4].at("samples"), all[1].at("samples"));
    EXPECT_EQ(channel(all[4], "xi4").at("out_of_range"), 0);
    EXPECT_EQ(all[5].at("container"), "dds");
    EXPECT_TRUE(all[5].at("format").is_null());
    EXPECT_EQ(all[5].at("candidates"), nlohmann::json::array({"msm64", "nlq64"}));
    EXPECT_TRUE(all[5].at("samples").is_null()); // DDS keeps no record
    // Every description has the same keys, and says its layout's version.
    for (const nlohmann::json& info : all) {
        EXPECT_EQ(info.at("schema"), "msmcl-info/1");
        EXPECT_EQ(info.size(), all[0].size()) << info.dump();
    }
    EXPECT_EQ(all[6].at("kind"), "summed-area table");
    EXPECT_EQ(all[6].at("max_kernel_texels"), 100);
    EXPECT_EQ(all[7].at("kind"), "shadow intensity");
    EXPECT_EQ(channel(all[7], "Y").at("out_of_range"), 0);

    // Text: one headline per file, a line per channel with the same counts.
    ASSERT_EQ(cli("info " + files + " > " + q("info.txt")), 0) << err();
    const std::string text = bytes("info.txt");
    EXPECT_NE(text.find(path("broken.exr") + ": depth map, 4x2, exr, samples 1, translucent_layers 1"), std::string::npos) << text;
    EXPECT_NE(text.find("  Z (float32): min -0.25, max 1.5, NaN 2, Inf 1, outside [0, 1] 2"), std::string::npos) << text;
    EXPECT_NE(text.find(path("map.ktx2") + ": moment shadow map, 37x29, ktx2, format nlq32"), std::string::npos) << text;

    // Files that cannot be parsed or opened: each named in one line on stderr, every readable
    // file still described on stdout, exit 2 at the end.
    std::system(("echo hello > " + q("text.exr")).c_str());
    EXPECT_EQ(cli("info " + q("text.exr") + " " + q("map.exr") + " " + q("missing.exr") + " " + q("map.ktx2") + " > " +
                  q("bad.txt")),
              2);
    const std::string errors = err();
    EXPECT_NE(errors.find("msmcl: " + path("text.exr") + ": not an OpenEXR, KTX2 or DDS file\n"), std::string::npos) << errors;
    EXPECT_NE(errors.find("msmcl: " + path("missing.exr") + ": cannot open"), std::string::npos) << errors;
    EXPECT_EQ(std::count(errors.begin(), errors.end(), '\n'), 2) << errors;
    const std::string described = bytes("bad.txt");
    EXPECT_NE(described.find(path("map.exr") + ": moment shadow map"), std::string::npos) << described;
    EXPECT_NE(described.find(path("map.ktx2") + ": moment shadow map"), std::string::npos) << described;
}

} // namespace
