// `msmcl filter|sat IN... --array OUT` (docs/cli.md, *Texture arrays*), run as processes:
//  - layer i of the array file holds the texel bytes of the single-file output of input i,
//    byte for byte, with the same key/value record, in KTX2 (layerCount; DDS arraySize: the
//    same texels),
//    for every format, for tables, and with translucent layers in some inputs only;
//  - one input gives an array of one layer (KTX2 layerCount 1), not a plain 2D texture;
//  - `msmcl info` reports the layers;
//  - inputs of another size or sample count, an EXR output and the batch options are refused
//    with one line naming the file, exit 2 and no output file (nor a temporary one).
#include "io/atomic_file.hpp"
#include "io/dds.hpp"
#include "io/exr_io.hpp"
#include "io/ktx2.hpp"
#include "cli_folder_test.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using msmcl::testing::CliRun;

class ArrayCli : public msmcl::testing::CliFolderTest {
protected:
    /// A map with `count` translucent layers (layer<k>.Z, layer<k>.A) in front of its depth.
    std::string write_translucent(const std::string& name, int width, int height, int samples, int count) {
        msmcl::io::TranslucentDepth translucent;
        translucent.depth = random_depth(width, height, samples);
        std::uniform_real_distribution<float> opacity(0.0f, 1.0f);
        for (int k = 0; k < count; ++k) {
            msmcl::TranslucentLayer layer;
            for (float depth : translucent.depth.depth) {
                layer.depth.push_back(depth * (0.3f + 0.2f * float(k)));
                layer.opacity.push_back(opacity(rng_));
            }
            translucent.layers.push_back(std::move(layer));
        }
        msmcl::io::write_translucent_depth_exr(path(name), translucent);
        return name;
    }

    /// The GPU image of a KTX2 or DDS file of the test's folder.
    msmcl::io::GpuImage image(const std::string& name) const {
        return name.size() > 4 && name.substr(name.size() - 4) == ".dds" ? msmcl::io::read_dds(path(name))
                                                                          : msmcl::io::read_ktx2(path(name));
    }

    /// Asserts that `array` holds the images of `singles` as its layers, bytes and record.
    void expect_layers_are(const std::string& array, const std::vector<std::string>& singles) {
        SCOPED_TRACE(array);
        const msmcl::io::GpuImage stacked = image(array);
        ASSERT_EQ(stacked.layers, static_cast<int>(singles.size()));
        EXPECT_TRUE(stacked.array);
        for (std::size_t i = 0; i < singles.size(); ++i) {
            SCOPED_TRACE(singles[i]);
            const msmcl::io::GpuImage one = image(singles[i]);
            ASSERT_EQ(one.layers, 1);
            EXPECT_EQ(stacked.format, one.format);
            EXPECT_EQ(stacked.width, one.width);
            EXPECT_EQ(stacked.height, one.height);
            EXPECT_EQ(stacked.metadata, one.metadata);
            ASSERT_EQ(stacked.bytes.size(), singles.size() * one.bytes.size());
            const std::vector<std::uint8_t> layer(stacked.bytes.begin() + std::ptrdiff_t(i * one.bytes.size()),
                                                  stacked.bytes.begin() + std::ptrdiff_t((i + 1) * one.bytes.size()));
            EXPECT_TRUE(layer == one.bytes) << "layer " << i << " differs from the single-file output";
        }
    }

    /// The names in the test's folder, sorted.
    std::vector<std::string> files() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(root_)) names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }
};

TEST_F(ArrayCli, FilterArrayLayersAreTheSingleFileOutputsInEveryFormat) {
    // Four cascades; the third has translucent layers, the others none.
    const std::vector<std::string> inputs = {write_depth("c0.exr", 53, 37, 4), write_depth("c1.exr", 53, 37, 4),
                                             write_translucent("c2.exr", 53, 37, 4, 2),
                                             write_depth("c3.exr", 53, 37, 4)};
    for (const char* format : {"moments128", "msm64", "nlq64", "nlq32"}) {
        SCOPED_TRACE(format);
        const std::string array = std::string("array_") + format;
        for (const char* extension : {".ktx2", ".dds"}) {
            std::vector<std::string> arguments = {"filter"};
            arguments.insert(arguments.end(), inputs.begin(), inputs.end());
            arguments.insert(arguments.end(), {"--array", array + extension, "--format", format, "--sigma", "1.7"});
            const CliRun run = cli(arguments);
            ASSERT_EQ(run.exit_code, 0) << run.err;
            EXPECT_EQ(run.err, "");
        }
        std::vector<std::string> singles;
        for (const std::string& input : inputs) {
            singles.push_back("single_" + std::string(format) + "_" + input.substr(0, 2) + ".ktx2");
            const CliRun one = cli({"filter", input, singles.back(), "--format", format, "--sigma", "1.7"});
            ASSERT_EQ(one.exit_code, 0) << one.err;
        }
        expect_layers_are(array + ".ktx2", singles);
        // The DDS array holds the same texels (DDS keeps no record).
        const msmcl::io::GpuImage dds = image(array + ".dds"), ktx2 = image(array + ".ktx2");
        EXPECT_EQ(dds.layers, 4);
        EXPECT_TRUE(dds.array);
        EXPECT_TRUE(dds.bytes == ktx2.bytes);
    }
    // msmcl info reports the layers.
    const CliRun info = cli({"info", "array_nlq64.ktx2"});
    ASSERT_EQ(info.exit_code, 0) << info.err;
    EXPECT_NE(info.out.find("layers 4 (texture array)"), std::string::npos) << info.out;
    const CliRun json = cli({"info", "array_nlq32.dds", "--json"});
    ASSERT_EQ(json.exit_code, 0) << json.err;
    EXPECT_NE(json.out.find("\"texture_array\": true"), std::string::npos) << json.out;
}

TEST_F(ArrayCli, SatArrayLayersAreTheSingleFileTables) {
    const std::vector<std::string> inputs = {write_translucent("t0.exr", 40, 26, 2, 1), write_depth("t1.exr", 40, 26, 2),
                                             write_depth("t2.exr", 40, 26, 2)};
    for (const char* extension : {".ktx2", ".dds"}) {
        std::vector<std::string> arguments = {"sat"};
        arguments.insert(arguments.end(), inputs.begin(), inputs.end());
        arguments.insert(arguments.end(), {"--array", std::string("tables") + extension, "--max-kernel", "400"});
        const CliRun run = cli(arguments);
        ASSERT_EQ(run.exit_code, 0) << run.err;
    }
    std::vector<std::string> singles;
    for (const std::string& input : inputs) {
        singles.push_back("one_" + input.substr(0, 2) + ".ktx2");
        ASSERT_EQ(cli({"sat", input, singles.back(), "--max-kernel", "400"}).exit_code, 0);
    }
    expect_layers_are("tables.ktx2", singles);
    EXPECT_TRUE(image("tables.dds").bytes == image("tables.ktx2").bytes);
    EXPECT_EQ(image("tables.dds").layers, 3);
    // --verbose drives the library stage by stage: the same bytes.
    const CliRun verbose = cli({"--verbose", "sat", inputs[0], inputs[1], inputs[2], "--array", "verbose.ktx2",
                                "--max-kernel", "400"});
    ASSERT_EQ(verbose.exit_code, 0) << verbose.err;
    EXPECT_NE(verbose.err.find("msmcl: kernel:"), std::string::npos) << verbose.err;
    EXPECT_TRUE(msmcl::io::read_whole_file(path("verbose.ktx2")) == msmcl::io::read_whole_file(path("tables.ktx2")));
}

TEST_F(ArrayCli, VerboseFilterWritesTheSameArray) {
    const std::vector<std::string> inputs = {write_depth("a.exr", 45, 31, 1), write_translucent("b.exr", 45, 31, 1, 3)};
    const CliRun quiet = cli({"filter", inputs[0], inputs[1], "--array", "quiet.ktx2", "--format", "nlq32"});
    ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
    const CliRun verbose =
        cli({"--verbose", "filter", inputs[0], inputs[1], "--array", "verbose.ktx2", "--format", "nlq32"});
    ASSERT_EQ(verbose.exit_code, 0) << verbose.err;
    EXPECT_NE(verbose.err.find("msmcl: program:"), std::string::npos) << verbose.err;
    EXPECT_TRUE(msmcl::io::read_whole_file(path("verbose.ktx2")) == msmcl::io::read_whole_file(path("quiet.ktx2")));
}

TEST_F(ArrayCli, OneInputIsAnArrayOfOneLayer) {
    const std::string input = write_depth("only.exr", 30, 20, 2);
    ASSERT_EQ(cli({"filter", input, "--array", "one.ktx2", "--format", "msm64"}).exit_code, 0);
    ASSERT_EQ(cli({"filter", input, "plain.ktx2", "--format", "msm64"}).exit_code, 0);
    const msmcl::io::GpuImage array = image("one.ktx2"), plain = image("plain.ktx2");
    EXPECT_TRUE(array.array);
    EXPECT_FALSE(plain.array);
    EXPECT_EQ(array.layers, 1);
    EXPECT_TRUE(array.bytes == plain.bytes);
    // KTX2 layerCount (bytes 32..35 of the header): 1 for the array, 0 for a 2D texture.
    const std::string array_bytes = msmcl::io::read_whole_file(path("one.ktx2"));
    const std::string plain_bytes = msmcl::io::read_whole_file(path("plain.ktx2"));
    EXPECT_EQ(array_bytes[32], 1);
    EXPECT_EQ(plain_bytes[32], 0);
    const CliRun info = cli({"info", "one.ktx2"});
    ASSERT_EQ(info.exit_code, 0) << info.err;
    EXPECT_NE(info.out.find("layers 1 (texture array)"), std::string::npos) << info.out;
}

TEST_F(ArrayCli, MismatchedInputsAndBadFormsAreRefusedWithoutOutput) {
    const std::string a = write_depth("a.exr", 32, 24, 4), b = write_depth("b.exr", 32, 24, 4);
    const std::string wide = write_depth("wide.exr", 33, 24, 4), fewer = write_depth("fewer.exr", 32, 24, 2);
    const std::vector<std::string> before = files();
    struct Case {
        std::vector<std::string> arguments;
        std::string named; ///< what the one error line must name
    };
    const std::vector<Case> cases = {
        {{"filter", a, b, wide, "--array", "out.ktx2", "--format", "nlq64"}, "wide.exr: 33x24, 4 samples per texel"},
        {{"filter", a, fewer, "--array", "out.ktx2", "--format", "nlq64"}, "fewer.exr: 32x24, 2 samples per texel"},
        {{"sat", a, wide, "--array", "out.dds", "--max-kernel", "400"}, "wide.exr"},
        {{"filter", a, b, "--array", "out.exr", "--format", "msm64"}, "out.exr: an OpenEXR texture holds one map"},
        {{"filter", a, b, "--array", "out.ktx2", "--out-container", "exr", "--format", "msm64"}, "out.ktx2"},
        {{"filter", a, b, "--array", "out.ktx2", "-o", "dir", "--format", "msm64"}, "--array"},
        {{"filter", "--array", "out.ktx2", "--format", "msm64"}, "needs inputs"},
        {{"filter", a, "missing.exr", "--array", "out.ktx2", "--format", "msm64"}, "missing.exr"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.arguments[2] + " " + c.named);
        const CliRun run = cli(c.arguments);
        EXPECT_EQ(run.exit_code, 2) << run.err;
        EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
        EXPECT_EQ(run.err.rfind("msmcl: ", 0), 0u) << run.err;
        EXPECT_NE(run.err.find(c.named), std::string::npos) << run.err;
        EXPECT_EQ(run.out, "");
        EXPECT_EQ(files(), before) << "an output or temporary file was left";
    }
}

} // namespace
