// The msmcl executable (docs/formats.md) and the sample-data tools, run as processes.
// Bad input: exit 2, one line "msmcl: <file>: <problem>" on stderr, no output file and
// no temporary file left. Device/runtime failure: exit 1. An unknown --device is a
// device_error (strict selection), so it exits 1, not 2.
#include "tools/triangle_rasterizer.hpp"
#include "io/atomic_file.hpp"
#include "io/exr_io.hpp"
#include "io/sat_exr.hpp"
#include "captured_process.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/formats.hpp>
#include <msmcl/sat.hpp>
#include <msmcl/version.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <spawn.h>
#include <string>
#include <sys/wait.h>
#include <vector>

extern char** environ;

#ifndef MSMCL_CLI_PATH // configured with MSMCL_BUILD_TOOLS=OFF: the Cli tests skip
#define MSMCL_CLI_PATH ""
#endif

namespace {

namespace fs = std::filesystem;
using msmcl::DepthImage;
using msmcl::DepthRange;
using msmcl::Format;
using msmcl::io::ExrChannel;
using msmcl::io::ExrImage;
using msmcl::io::SampleType;

const std::string cli_path = MSMCL_CLI_PATH;
const std::string scene_tool = std::string(MSMCL_TOOLS_BUILD_DIR) + "/msmcl-scene";
const std::string rasterize_tool = std::string(MSMCL_TOOLS_BUILD_DIR) + "/msmcl-rasterize";
const std::string preview_tool = std::string(MSMCL_TOOLS_BUILD_DIR) + "/msmcl-preview";

/// Fixed default seed, printed; MSMCL_TEST_SEED overrides.
std::uint32_t test_seed() {
    static const std::uint32_t seed = [] {
        const char* text = std::getenv("MSMCL_TEST_SEED");
        const std::uint32_t value = text ? static_cast<std::uint32_t>(std::strtoul(text, nullptr, 10)) : 20170730u;
        std::cout << "cli_test seed " << value << " (set MSMCL_TEST_SEED to change)" << std::endl;
        return value;
    }();
    return seed;
}

using msmcl::testing::ProcessResult;

bool have_device() {
    try {
        return !msmcl::list_devices().empty();
    } catch (const msmcl::error&) {
        return false;
    }
}

class Cli : public ::testing::Test {
protected:
    void SetUp() override {
        if (cli_path.empty()) GTEST_SKIP() << "built without the msmcl CLI and tools (MSMCL_BUILD_TOOLS=OFF)";
        std::string pattern = (fs::temp_directory_path() / "msmcl-cli-test-XXXXXX").string();
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        root_ = pattern;
        fs::create_directory(root_ / "in");
        fs::create_directory(root_ / "out");
        fs::create_directory(root_ / "log");
        random_.seed(test_seed());
        RecordProperty("seed", static_cast<int>(test_seed()));
    }
    void TearDown() override {
        if (!root_.empty()) fs::remove_all(root_);
    }

    std::string in(const std::string& name) const { return (root_ / "in" / name).string(); }
    std::string out(const std::string& name) const { return (root_ / "out" / name).string(); }
    std::vector<std::string> outputs() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(root_ / "out")) names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }

    /// Runs a program (no shell) with stdout and stderr captured.
    ProcessResult run(std::vector<std::string> arguments) {
        return msmcl::testing::run_captured(std::move(arguments), (root_ / "log" / "stdout").string(),
                                            (root_ / "log" / "stderr").string());
    }
    ProcessResult msmcl_cli(std::vector<std::string> arguments) {
        arguments.insert(arguments.begin(), cli_path);
        return run(std::move(arguments));
    }

    /// Expects exit 2, one stderr line "msmcl: [<file>: ]...<problem>...", and nothing in out/.
    void expect_bad_input(const std::vector<std::string>& arguments, const std::string& file,
                          const std::string& problem) {
        std::string command = "msmcl";
        for (const std::string& argument : arguments) command += " " + argument;
        SCOPED_TRACE(command);
        const ProcessResult result = msmcl_cli(arguments);
        EXPECT_EQ(result.exit_code, 2) << result.err;
        EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
        EXPECT_EQ(result.err.back(), '\n');
        const std::string prefix = "msmcl: " + (file.empty() ? std::string() : file + ": ");
        EXPECT_EQ(result.err.rfind(prefix, 0), 0u) << result.err << "  expected prefix: " << prefix;
        EXPECT_NE(result.err.find(problem), std::string::npos) << result.err << "  expected: " << problem;
        EXPECT_TRUE(outputs().empty()) << "left behind: " << (outputs().empty() ? "" : outputs()[0]);
    }

    /// A smooth depth map with small noise, values in the range.
    DepthImage make_depth(int width, int height, int samples, DepthRange range) {
        std::uniform_real_distribution<float> noise(-0.01f, 0.01f);
        DepthImage depth;
        depth.width = width;
        depth.height = height;
        depth.samples = samples;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                for (int s = 0; s < samples; ++s) {
                    const float d = 0.5f + 0.4f * std::sin(0.2f * x) * std::cos(0.15f * y) + noise(random_);
                    depth.depth.push_back(range == DepthRange::zero_one ? d : 2.0f * d - 1.0f);
                }
        return depth;
    }

    void write_receivers(const std::string& path, int width, int height, float u, float v, float z) {
        msmcl::io::ReceiverGrid grid;
        grid.width = width;
        grid.height = height;
        grid.points.u.assign(static_cast<std::size_t>(width) * height, u);
        grid.points.v.assign(grid.points.u.size(), v);
        grid.points.z.assign(grid.points.u.size(), z);
        msmcl::io::write_receivers_exr(path, grid);
    }

    fs::path root_;
    std::mt19937 random_;
};

ExrImage depth_image(int width, int height, std::vector<ExrChannel> channels) {
    ExrImage image;
    image.width = width;
    image.height = height;
    image.channels = std::move(channels);
    return image;
}
ExrChannel depth_channel(const std::string& name, std::size_t count, float value,
                         SampleType type = SampleType::float32) {
    return ExrChannel{name, type, std::vector<float>(count, value), {}};
}

// ---- Help, version, devices ------------------------------------------------------------

TEST_F(Cli, HelpAndVersion) {
    const ProcessResult help = msmcl_cli({"--help"});
    EXPECT_EQ(help.exit_code, 0);
    for (const char* word : {"filter", "shade", "devices", "--device", "--version"})
        EXPECT_NE(help.out.find(word), std::string::npos) << word;
    const ProcessResult filter_help = msmcl_cli({"filter", "--help"});
    EXPECT_EQ(filter_help.exit_code, 0);
    EXPECT_NE(filter_help.out.find("--format"), std::string::npos);
    EXPECT_NE(filter_help.out.find("--sigma"), std::string::npos);
    const ProcessResult version = msmcl_cli({"--version"});
    EXPECT_EQ(version.exit_code, 0);
    EXPECT_EQ(version.out, std::string("msmcl ") + msmcl::version_string + "\n");
    // Usage errors are one line too (a bare `msmcl` prints the usage: cli_conventions_test.cpp).
    expect_bad_input({"filter", in("a.exr")}, "", "");
}

TEST_F(Cli, DevicesListsEveryDeviceAndMarksTheDefault) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    const ProcessResult result = msmcl_cli({"devices"});
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const auto lines = std::count(result.out.begin(), result.out.end(), '\n');
    EXPECT_EQ(static_cast<std::size_t>(lines), msmcl::list_devices().size());
    EXPECT_NE(result.out.find("0:0  "), std::string::npos) << result.out;
    std::size_t marks = 0;
    for (std::size_t at = result.out.find("[default]"); at != std::string::npos; at = result.out.find("[default]", at + 1))
        ++marks;
    EXPECT_EQ(marks, 1u) << result.out;
}

// devices --verbose adds what the automatic choice runs on the picked device, and why
// (the filter's choice in two formats, found by filtering a small map; the SAT's kernel).
TEST_F(Cli, DevicesVerboseSaysWhatTheAutomaticChoiceRuns) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    const ProcessResult result = msmcl_cli({"--verbose", "devices"});
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const std::string expected_filter = msmcl::filter_kernel_name(msmcl::filter_kernel_for(
        msmcl::Context(), msmcl::FilterKernel::automatic));
    EXPECT_NE(result.out.find("automatic choices on "), std::string::npos) << result.out;
    for (const char* format : {"msm64", "nlq32"})
        EXPECT_NE(result.out.find(std::string("  ") + format + " filter: " + expected_filter), std::string::npos)
            << result.out;
    EXPECT_NE(result.out.find("  sat: "), std::string::npos) << result.out;
    EXPECT_TRUE(outputs().empty());
}

TEST_F(Cli, UnknownDeviceIsADeviceErrorWithExitCodeOne) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    msmcl::io::write_depth_exr(in("d.exr"), make_depth(16, 16, 1, DepthRange::zero_one));
    for (std::vector<std::string> arguments :
         {std::vector<std::string>{"--device", "no-such-device-anywhere", "filter", in("d.exr"), out("t.exr"), "--format", "nlq64"},
          std::vector<std::string>{"filter", in("d.exr"), out("t.exr"), "--format", "nlq64", "--device", "no-such-device-anywhere"},
          std::vector<std::string>{"--device", "no-such-device-anywhere", "devices"}}) {
        const ProcessResult result = msmcl_cli(arguments);
        EXPECT_EQ(result.exit_code, 1) << result.err;
        EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
        EXPECT_EQ(result.err.rfind("msmcl: ", 0), 0u) << result.err;
        EXPECT_NE(result.err.find("no-such-device-anywhere"), std::string::npos) << result.err;
        EXPECT_TRUE(outputs().empty());
    }
}

// ---- filter ------------------------------------------------------------------------------

TEST_F(Cli, FilterWritesEveryFormatWithItsAttributesLikeTheApi) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    const DepthImage depth = make_depth(45, 31, 4, DepthRange::minus_one_one);
    msmcl::io::write_depth_exr(in("depth.exr"), depth);
    msmcl::Context context;
    for (Format format : {Format::moments128, Format::msm64, Format::nlq64, Format::nlq32}) {
        SCOPED_TRACE(msmcl::format_name(format));
        const std::string file = out(std::string(msmcl::format_name(format)) + ".exr");
        const ProcessResult result = msmcl_cli({"filter", in("depth.exr"), file, "--format", msmcl::format_name(format),
                                                "--sigma", "1.5", "--depth-range", "-1,1"});
        ASSERT_EQ(result.exit_code, 0) << result.err;
        EXPECT_TRUE(result.err.empty()) << result.err;

        const msmcl::io::TextureFile texture = msmcl::io::read_texture_exr(file);
        EXPECT_EQ(texture.texture.format, format);
        EXPECT_EQ(texture.texture.width, 45);
        EXPECT_EQ(texture.texture.height, 31);
        EXPECT_EQ(texture.info.sigma, 1.5f);
        EXPECT_EQ(texture.info.samples, 4);
        EXPECT_EQ(texture.info.depth_range, DepthRange::minus_one_one);

        // The CLI is a thin shell: same texels as the API on the same data and device.
        msmcl::FilterOptions options;
        options.format = format;
        options.sigma = 1.5f;
        options.depth_range = DepthRange::minus_one_one;
        EXPECT_EQ(texture.texture.words, msmcl::filter(context, depth, options).words);
    }
    // Deterministic: the same command twice gives the same bytes.
    ASSERT_EQ(msmcl_cli({"filter", in("depth.exr"), out("again.exr"), "--format", "nlq64", "--sigma", "1.5",
                         "--depth-range=-1,1"}).exit_code, 0);
    EXPECT_EQ(msmcl::io::read_whole_file(out("again.exr")), msmcl::io::read_whole_file(out("nlq64.exr")));
    std::vector<std::string> expected = {"again.exr", "moments128.exr", "msm64.exr", "nlq32.exr", "nlq64.exr"};
    EXPECT_EQ(outputs(), expected); // no temporary files
}

// --kernel reaches every work distribution of filter and sat; each gives the library's
// result with the same choice (nlq64 tells the filter kernels apart: each shifts the moments
// by the depth midrange of its own blocks), `automatic` the one the library picks.
TEST_F(Cli, KernelOptionPicksTheDistribution) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    const DepthImage depth = make_depth(70, 50, 4, DepthRange::zero_one);
    msmcl::io::write_depth_exr(in("depth.exr"), depth);
    msmcl::Context context;
    for (const char* name : {"automatic", "fused_paper", "fused_cpu", "three_pass"}) {
        SCOPED_TRACE(name);
        const std::string file = out(std::string("filter_") + name + ".exr");
        const ProcessResult result =
            msmcl_cli({"filter", in("depth.exr"), file, "--format", "nlq64", "--kernel", name});
        ASSERT_EQ(result.exit_code, 0) << result.err;
        msmcl::FilterOptions options;
        options.format = Format::nlq64;
        options.kernel = *msmcl::parse_filter_kernel(name);
        EXPECT_EQ(msmcl::io::read_texture_exr(file).texture.words, msmcl::filter(context, depth, options).words);
    }
    const msmcl::FilterKernel automatic = msmcl::filter_kernel_for(context, msmcl::FilterKernel::automatic);
    EXPECT_NE(automatic, msmcl::FilterKernel::automatic);
    EXPECT_EQ(msmcl::io::read_whole_file(out("filter_automatic.exr")),
              msmcl::io::read_whole_file(out(std::string("filter_") + msmcl::filter_kernel_name(automatic) + ".exr")));
    // Every table build gives the same table.
    const std::vector<std::uint32_t> table = msmcl::build_sat(context, depth, msmcl::SatOptions{}).words;
    for (const char* name : {"automatic", "tiled_gpu", "tiled_cpu", "row_per_thread"}) {
        SCOPED_TRACE(name);
        const std::string file = out(std::string("sat_") + name + ".exr");
        const ProcessResult result = msmcl_cli({"sat", in("depth.exr"), file, "--kernel", name});
        ASSERT_EQ(result.exit_code, 0) << result.err;
        EXPECT_EQ(msmcl::io::read_sat_exr(file).table.words, table);
    }
    // An unknown kernel: usage error, nothing written.
    for (const std::string& name : outputs()) fs::remove(out(name));
    expect_bad_input({"filter", in("depth.exr"), out("t.exr"), "--format", "nlq64", "--kernel", "fused"}, "",
                     "unknown --kernel 'fused' (expected automatic, fused_paper, fused_cpu or three_pass)");
    expect_bad_input({"sat", in("depth.exr"), out("t.exr"), "--kernel", "tiled"}, "",
                     "unknown --kernel 'tiled' (expected automatic, tiled_gpu, tiled_cpu or row_per_thread)");
}

TEST_F(Cli, FilterWithoutBlurGivesThePowersOfEachDepth) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    // Equal samples per texel, sigma 0: b_j = z^j (float32 powers and mean: 1e-6 is a few
    // ulp). Same program variant as above (4 samples, [-1,1]) to keep cold runs short.
    DepthImage depth = make_depth(20, 10, 4, DepthRange::minus_one_one);
    for (std::size_t i = 0; i < depth.depth.size(); ++i) depth.depth[i] = depth.depth[i - i % 4];
    msmcl::io::write_depth_exr(in("d.exr"), depth);
    const ProcessResult result = msmcl_cli(
        {"filter", in("d.exr"), out("m.exr"), "--format", "moments128", "--sigma", "0", "--depth-range", "-1,1"});
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const msmcl::io::TextureFile texture = msmcl::io::read_texture_exr(out("m.exr"));
    EXPECT_EQ(texture.info.sigma, 0.0f);
    for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 20; ++x) {
            const double z = depth.at(x, y);
            for (int j = 1; j <= 4; ++j)
                EXPECT_NEAR(texture.texture.moment(x, y, j), std::pow(z, j), 1e-6) << x << "," << y << " b" << j;
        }
}

TEST_F(Cli, FilterAcceptsHalfDepth) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    msmcl::io::write_depth_exr(in("half.exr"), make_depth(24, 24, 4, DepthRange::zero_one), SampleType::half);
    const ProcessResult result = msmcl_cli({"filter", in("half.exr"), out("t.exr"), "--format", "nlq32"});
    EXPECT_EQ(result.exit_code, 0) << result.err;
    const msmcl::io::TextureFile texture = msmcl::io::read_texture_exr(out("t.exr"));
    EXPECT_EQ(texture.info.samples, 4);
    EXPECT_EQ(texture.info.depth_range, DepthRange::zero_one); // the default
}

TEST_F(Cli, FilterRejectsEveryBadInputWithExitTwoAndNoOutput) {
    const std::size_t n = 16 * 8;
    auto write = [&](const std::string& name, std::vector<ExrChannel> channels, int width = 16, int height = 8) {
        msmcl::io::write_exr(in(name), depth_image(width, height, std::move(channels)));
        return in(name);
    };
    auto filter = [&](const std::string& input, std::vector<std::string> extra = {}) {
        std::vector<std::string> arguments = {"filter", input, out("t.exr"), "--format", "nlq64"};
        arguments.insert(arguments.end(), extra.begin(), extra.end());
        return arguments;
    };
    msmcl::io::write_depth_exr(in("good.exr"), make_depth(64, 48, 4, DepthRange::zero_one));
    const std::string good = in("good.exr");

    // Files that are not usable EXRs.
    expect_bad_input(filter(in("missing.exr")), in("missing.exr"), "cannot open: No such file or directory");
    const std::string bytes = msmcl::io::read_whole_file(good);
    std::ofstream(in("truncated.exr"), std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
    expect_bad_input(filter(in("truncated.exr")), in("truncated.exr"), "corrupt or truncated OpenEXR file");
    std::ofstream(in("text.exr")) << "P3 1 1 255 0 0 0\n";
    expect_bad_input(filter(in("text.exr")), in("text.exr"), "not an OpenEXR file");

    // Channels and sample layers.
    expect_bad_input(filter(write("rgb.exr", {depth_channel("R", n, 0.5f), depth_channel("G", n, 0.5f)})),
                     in("rgb.exr"), "missing depth channel");
    expect_bad_input(filter(write("gap.exr", {depth_channel("sample0.Z", n, 0.5f), depth_channel("sample1.Z", n, 0.5f),
                                              depth_channel("sample3.Z", n, 0.5f)})),
                     in("gap.exr"), "sample2.Z is missing");
    expect_bad_input(filter(write("three.exr", {depth_channel("sample0.Z", n, 0.5f), depth_channel("sample1.Z", n, 0.5f),
                                                depth_channel("sample2.Z", n, 0.5f)})),
                     in("three.exr"), "unsupported sample count 3");
    expect_bad_input(filter(write("uint.exr", {ExrChannel{"Z", SampleType::uint32, {}, std::vector<std::uint32_t>(n, 1)}})),
                     in("uint.exr"), "channel Z has type UINT");

    // Values: NaN, Inf, outside the declared range.
    ExrChannel bad = depth_channel("Z", n, 0.5f);
    bad.values[5 * 16 + 9] = std::numeric_limits<float>::quiet_NaN();
    expect_bad_input(filter(write("nan.exr", {bad})), in("nan.exr"), "texel (9, 5) Z: depth is NaN");
    bad.values[5 * 16 + 9] = std::numeric_limits<float>::infinity();
    expect_bad_input(filter(write("inf.exr", {bad})), in("inf.exr"), "texel (9, 5) Z: depth is +Inf");
    bad.values[5 * 16 + 9] = 1.5f;
    expect_bad_input(filter(write("high.exr", {bad})), in("high.exr"), "texel (9, 5) Z: depth 1.5 is outside the depth range [0,1]");
    bad.values[5 * 16 + 9] = -1.5f;
    expect_bad_input(filter(write("low.exr", {bad}), {"--depth-range", "-1,1"}), in("low.exr"),
                     "texel (9, 5) Z: depth -1.5 is outside the depth range [-1,1]");
    expect_bad_input(filter(write("huge.exr", {depth_channel("Z", 65537, 0.5f)}, 65537, 1)), in("huge.exr"),
                     "data window 65537 x 1 is too large");

    // Option values (checked before any file is read).
    expect_bad_input({"filter", good, out("t.exr"), "--format", "nlq16"}, "", "unknown --format 'nlq16'");
    expect_bad_input({"filter", good, out("t.exr")}, "", "--format is required");
    expect_bad_input(filter(good, {"--sigma", "-1"}), "", "--sigma must be >= 0");
    expect_bad_input(filter(good, {"--sigma", "nan"}), "", "--sigma must be a finite number, got 'nan'");
    expect_bad_input(filter(good, {"--sigma", "2.4x"}), "", "--sigma must be a finite number");
    expect_bad_input(filter(good, {"--depth-range", "0,2"}), "", "--depth-range must be 0,1 or -1,1, got '0,2'");
    expect_bad_input(filter(good, {"--bogus"}), "", "--bogus");
}

// ---- shade -------------------------------------------------------------------------------

TEST_F(Cli, ShadeWritesOneIntensityPerReceiverOnTheReceiversGrid) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    // A flat occluder at d = 0.5 over a 32x32 map; receivers on a 7x5 grid, partly outside.
    DepthImage flat;
    flat.width = flat.height = 32;
    flat.samples = 4;
    flat.depth.assign(32 * 32 * 4, 0.5f);
    msmcl::io::write_depth_exr(in("flat.exr"), flat);
    ASSERT_EQ(msmcl_cli({"filter", in("flat.exr"), out("map.exr"), "--format", "nlq32"}).exit_code, 0);

    msmcl::io::ReceiverGrid grid;
    grid.width = 7;
    grid.height = 5;
    for (int i = 0; i < 35; ++i) {
        grid.points.u.push_back(-10.0f + 9.0f * (i % 7)); // -10 .. 44: some outside the map
        grid.points.v.push_back(3.5f + 5.0f * (i / 7));
        grid.points.z.push_back(i % 2 ? 0.9f : 0.2f); // behind or in front of the occluder
    }
    msmcl::io::write_receivers_exr(in("receivers.exr"), grid);
    for (const char* lookup : {"nearest", "bilinear"}) {
        SCOPED_TRACE(lookup);
        const std::string file = out(std::string("y_") + lookup + ".exr");
        const ProcessResult result = msmcl_cli({"shade", out("map.exr"), in("receivers.exr"), file, "--lookup", lookup});
        ASSERT_EQ(result.exit_code, 0) << result.err;
        const ExrImage image = msmcl::io::read_exr(file);
        EXPECT_EQ(image.width, 7);
        EXPECT_EQ(image.height, 5);
        ASSERT_EQ(image.channels.size(), 1u);
        EXPECT_EQ(image.channels[0].name, "Y");
        EXPECT_EQ(image.channels[0].type, SampleType::float32);
        // One depth everywhere: lit in front (lower bound 0), shadowed behind (nlq32
        // quantization and the moment bias leak a few percent at most).
        for (int i = 0; i < 35; ++i) {
            if (i % 2) EXPECT_GT(image.channels[0].values[i], 0.9f) << i;
            else EXPECT_LT(image.channels[0].values[i], 0.02f) << i;
        }
    }
}

TEST_F(Cli, ShadeTakesTheDepthRangeFromTheMap) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    // Occluder at z = 0 in [-1,1]. A receiver at 0.3 is behind it in [-1,1]; read as [0,1]
    // it would be at z = -0.4, in front.
    DepthImage flat;
    flat.width = flat.height = 16;
    flat.samples = 4;
    flat.depth.assign(16 * 16 * 4, 0.0f);
    msmcl::io::write_depth_exr(in("flat.exr"), flat);
    ASSERT_EQ(msmcl_cli({"filter", in("flat.exr"), out("map.exr"), "--format", "moments128", "--depth-range=-1,1"}).exit_code, 0);
    write_receivers(in("r.exr"), 2, 2, 8.0f, 8.0f, 0.3f);
    const ProcessResult shaded = msmcl_cli({"shade", out("map.exr"), in("r.exr"), out("y.exr")});
    ASSERT_EQ(shaded.exit_code, 0) << shaded.err;
    EXPECT_GT(msmcl::io::read_exr(out("y.exr")).channels[0].values[0], 0.9f);
    // An explicit --depth-range overrides it.
    ASSERT_EQ(msmcl_cli({"shade", out("map.exr"), in("r.exr"), out("y01.exr"), "--depth-range", "0,1"}).exit_code, 0);
    EXPECT_LT(msmcl::io::read_exr(out("y01.exr")).channels[0].values[0], 0.02f);
}

TEST_F(Cli, ShadeRejectsEveryBadInputWithExitTwoAndNoOutput) {
    // A valid map written through the library's own writer (no device needed here).
    msmcl::Texture map;
    map.format = Format::nlq64;
    map.width = map.height = 4;
    map.words.assign(4 * 4 * 2, 0x80008000u);
    msmcl::io::write_texture_exr(in("map.exr"), map, {2.4f, 1, DepthRange::zero_one});
    write_receivers(in("r.exr"), 3, 2, 1.0f, 1.0f, 0.5f);
    msmcl::io::write_depth_exr(in("depth.exr"), make_depth(8, 8, 1, DepthRange::zero_one));

    expect_bad_input({"shade", in("map.exr"), in("r.exr"), out("y.exr"), "--lookup", "dither", "--frame", "-1"}, "",
                     "--frame must be a whole number");
    expect_bad_input({"shade", in("map.exr"), in("r.exr"), out("y.exr"), "--lookup", "cubic"}, "",
                     "unknown --lookup 'cubic'");
    expect_bad_input({"shade", in("map.exr"), in("r.exr"), out("y.exr"), "--depth-bias", "inf"}, "",
                     "--depth-bias must be a finite number");
    expect_bad_input({"shade", in("map.exr"), in("r.exr"), out("y.exr"), "--depth-range", "1,0"}, "",
                     "--depth-range must be 0,1 or -1,1");
    expect_bad_input({"shade", in("map.exr"), in("r.exr")}, "", "output is required");

    msmcl::io::write_exr(in("no_v.exr"), depth_image(3, 2, {depth_channel("U", 6, 1.0f), depth_channel("Z", 6, 0.5f)}));
    expect_bad_input({"shade", in("map.exr"), in("no_v.exr"), out("y.exr")}, in("no_v.exr"), "missing channel V");
    ExrChannel u = depth_channel("U", 6, 1.0f);
    u.values[4] = std::numeric_limits<float>::quiet_NaN();
    msmcl::io::write_exr(in("nan_u.exr"), depth_image(3, 2, {u, depth_channel("V", 6, 1.0f), depth_channel("Z", 6, 0.5f)}));
    expect_bad_input({"shade", in("map.exr"), in("nan_u.exr"), out("y.exr")}, in("nan_u.exr"), "texel (1, 1): U is NaN");
    expect_bad_input({"shade", in("depth.exr"), in("r.exr"), out("y.exr")}, in("depth.exr"),
                     "not an msmcl texture (attribute msmcl:format is missing)");
    expect_bad_input({"shade", in("missing.exr"), in("r.exr"), out("y.exr")}, in("missing.exr"), "cannot open");
}

// ---- Sample-data tools ---------------------------------------------------------------------
// (Device runs here reuse the program variants above: 4 samples, nlq32, so that a cold
// PoCL cache builds few programs.)

TEST_F(Cli, SceneToolFeedsFilterAndShadeIntoAViewSizedImage) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    const ProcessResult scene = run({scene_tool, "--width", "96", "--samples", "4", "--depth", in("scene.exr"),
                                     "--receivers", in("view.exr"), "--view-width", "64", "--view-height", "48",
                                     "--lighting", in("lighting.exr")});
    ASSERT_EQ(scene.exit_code, 0) << scene.err;
    const DepthImage depth = msmcl::io::read_depth_exr(in("scene.exr"), DepthRange::zero_one);
    EXPECT_EQ(depth.samples, 4);
    EXPECT_EQ(depth.width, 96);

    // Deterministic: the same arguments give the same bytes.
    ASSERT_EQ(run({scene_tool, "--width", "96", "--samples", "4", "--depth", in("scene2.exr")}).exit_code, 0);
    EXPECT_EQ(msmcl::io::read_whole_file(in("scene.exr")), msmcl::io::read_whole_file(in("scene2.exr")));

    ASSERT_EQ(msmcl_cli({"filter", in("scene.exr"), out("map.exr"), "--format", "nlq32"}).exit_code, 0);
    const ProcessResult shade = msmcl_cli({"shade", out("map.exr"), in("view.exr"), out("y.exr")});
    ASSERT_EQ(shade.exit_code, 0) << shade.err;
    const ExrImage y = msmcl::io::read_exr(out("y.exr"));
    EXPECT_EQ(y.width, 64);
    EXPECT_EQ(y.height, 48);
    // The view shows both lit and shadowed surfaces.
    const auto& values = y.channels[0].values;
    EXPECT_GT(std::count_if(values.begin(), values.end(), [](float v) { return v > 0.5f; }), 50);
    EXPECT_GT(std::count_if(values.begin(), values.end(), [](float v) { return v < 0.1f; }), 500);

    const ProcessResult preview =
        run({preview_tool, out("y.exr"), out("y.png"), "--lighting", in("lighting.exr")});
    EXPECT_EQ(preview.exit_code, 0) << preview.err;
    EXPECT_TRUE(fs::file_size(out("y.png")) > 100);
}

TEST_F(Cli, RasterizeToolFeedsFilterAndShade) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    const ProcessResult mesh = run({rasterize_tool, "--width", "128", "--samples", "4", "--depth", in("wuson.exr"),
                                    "--receivers", in("view.exr"), "--view-width", "40", "--view-height", "30"});
    ASSERT_EQ(mesh.exit_code, 0) << mesh.err;
    const DepthImage depth = msmcl::io::read_depth_exr(in("wuson.exr"), DepthRange::zero_one);
    EXPECT_EQ(depth.samples, 4);
    EXPECT_EQ(depth.width, 128);
    ASSERT_EQ(msmcl_cli({"filter", in("wuson.exr"), out("map.exr"), "--format", "nlq32"}).exit_code, 0);
    ASSERT_EQ(msmcl_cli({"shade", out("map.exr"), in("view.exr"), out("y.exr"), "--lookup", "nearest"}).exit_code, 0);
    const ExrImage y = msmcl::io::read_exr(out("y.exr"));
    EXPECT_EQ(y.width, 40);
    EXPECT_EQ(y.height, 30);
    const auto& values = y.channels[0].values;
    // Lit and shadowed parts. Lit ground reads up to ~0.3, not 0: at 128^2 the blur spans
    // ~0.03 of depth on the sloped ground, far more than the 1e-3 bias, and the moment
    // lower bound of a receiver inside that spread is above 0 (moments128 does the same).
    EXPECT_GT(std::count_if(values.begin(), values.end(), [](float v) { return v > 0.5f; }), 20);
    EXPECT_GT(std::count_if(values.begin(), values.end(), [](float v) { return v < 0.35f; }), 600);
}

TEST_F(Cli, RasterizeToolReadsAsciiAndBinaryPly) {
    // assimp's unit cube as ascii quads and as binary triangles: the same shadow map.
    const std::string models = "/usr/share/assimp/models/PLY/";
    if (!fs::exists(models + "cube.ply") || !fs::exists(models + "cube_binary.ply"))
        GTEST_SKIP() << "assimp-testmodels not installed";
    for (const char* model : {"cube.ply", "cube_binary.ply"}) {
        const ProcessResult result = run({rasterize_tool, "--model", models + model, "--width", "64", "--samples", "4",
                                          "--depth", in(std::string(model) + ".exr")});
        ASSERT_EQ(result.exit_code, 0) << result.err;
    }
    const DepthImage ascii = msmcl::io::read_depth_exr(in("cube.ply.exr"), DepthRange::zero_one);
    const DepthImage binary = msmcl::io::read_depth_exr(in("cube_binary.ply.exr"), DepthRange::zero_one);
    ASSERT_EQ(ascii.depth.size(), binary.depth.size());
    for (std::size_t i = 0; i < ascii.depth.size(); ++i) ASSERT_NEAR(ascii.depth[i], binary.depth[i], 1e-6) << i;
    // A broken file is an error naming it.
    std::ofstream(in("broken.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1 2\n";
    const ProcessResult broken = run({rasterize_tool, "--model", in("broken.ply"), "--depth", out("x.exr")});
    EXPECT_NE(broken.exit_code, 0);
    EXPECT_NE(broken.err.find(in("broken.ply")), std::string::npos) << broken.err;
    EXPECT_TRUE(outputs().empty());
}

TEST(Rasterizer, TrianglesSharingEdgesCoverEverySampleExactlyOnce) {
    // A jittered 6x6 grid of quads, each split along a random diagonal with a random
    // winding, over a 48x48 target: every sample inside the grid's outline is covered
    // exactly once (top-left rule), whatever lands exactly on an edge or vertex.
    std::mt19937 random(test_seed());
    const int cells = 6, size = 48;
    std::vector<msmcl::data::ScreenPoint> grid;
    std::uniform_int_distribution<int> jitter(-3, 3); // multiples of 1/2 px: many samples on edges
    for (int j = 0; j <= cells; ++j)
        for (int i = 0; i <= cells; ++i) {
            const bool border = i == 0 || j == 0 || i == cells || j == cells;
            grid.push_back({8.0 * i + (border ? 0 : 0.5 * jitter(random)), 8.0 * j + (border ? 0 : 0.5 * jitter(random))});
        }
    for (int samples : {1, 4, 16}) {
        const auto pattern = msmcl::data::standard_sample_pattern(samples);
        std::vector<int> coverage(static_cast<std::size_t>(size) * size * samples, 0);
        auto count = [&](int x, int y, int s, double w0, double w1, double w2) {
            EXPECT_NEAR(w0 + w1 + w2, 1.0, 1e-12);
            ++coverage[(static_cast<std::size_t>(y) * size + x) * samples + s];
        };
        for (int j = 0; j < cells; ++j)
            for (int i = 0; i < cells; ++i) {
                const auto& a = grid[j * (cells + 1) + i];
                const auto& b = grid[j * (cells + 1) + i + 1];
                const auto& c = grid[(j + 1) * (cells + 1) + i + 1];
                const auto& d = grid[(j + 1) * (cells + 1) + i];
                const bool flip = random() & 1, diagonal = random() & 1;
                if (diagonal) {
                    msmcl::data::rasterize_triangle(a, flip ? c : b, flip ? b : c, size, size, pattern, count);
                    msmcl::data::rasterize_triangle(a, flip ? d : c, flip ? c : d, size, size, pattern, count);
                } else {
                    msmcl::data::rasterize_triangle(a, flip ? d : b, flip ? b : d, size, size, pattern, count);
                    msmcl::data::rasterize_triangle(b, flip ? d : c, flip ? c : d, size, size, pattern, count);
                }
            }
        // The grid's outline is the square [0, 48]^2: samples on its right and bottom
        // borders belong to the neighbours that are not drawn; none lie there here.
        for (std::size_t k = 0; k < coverage.size(); ++k)
            ASSERT_EQ(coverage[k], 1) << "sample " << k % samples << " of texel " << k / samples << ", "
                                      << samples << " samples, seed " << test_seed();
    }
}

TEST_F(Cli, CommittedSampleDataMatchesItsTools) {
    // data/*.exr are made by scripts/make_sample_data.sh; regenerating must give the same
    // values (up to 1e-6: libm may differ in the last bit between machines).
    struct Sample {
        std::string tool, depth, view;
    };
    const std::string data = MSMCL_SOURCE_DIR "/data/";
    for (const Sample& sample : {Sample{scene_tool, "railing_256x256_4x.exr", "railing_view_160x120.exr"},
                                 Sample{rasterize_tool, "wuson_256x256_4x.exr", "wuson_view_160x120.exr"}}) {
        SCOPED_TRACE(sample.depth);
        ASSERT_TRUE(fs::exists(data + sample.depth));
        const ProcessResult result = run({sample.tool, "--width", "256", "--samples", "4", "--depth", in(sample.depth),
                                          "--receivers", in(sample.view), "--view-width", "160", "--view-height", "120"});
        ASSERT_EQ(result.exit_code, 0) << result.err;
        for (const std::string& name : {sample.depth, sample.view}) {
            const ExrImage committed = msmcl::io::read_exr(data + name);
            const ExrImage fresh = msmcl::io::read_exr(in(name));
            ASSERT_EQ(committed.channels.size(), fresh.channels.size()) << name;
            for (std::size_t c = 0; c < fresh.channels.size(); ++c) {
                ASSERT_EQ(committed.channels[c].values.size(), fresh.channels[c].values.size());
                double worst = 0;
                for (std::size_t i = 0; i < fresh.channels[c].values.size(); ++i)
                    worst = std::max(worst, std::fabs(static_cast<double>(committed.channels[c].values[i]) -
                                                      fresh.channels[c].values[i]) /
                                                std::max(1.0, std::fabs(static_cast<double>(fresh.channels[c].values[i]))));
                EXPECT_LE(worst, 1e-6) << name << " channel " << fresh.channels[c].name;
            }
        }
    }
}

} // namespace
