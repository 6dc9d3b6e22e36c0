// Dithered lookup (docs/math.md) of the shade kernel on PoCL: against a double
// reference that picks the texel from the embedded blue noise on its own (floor(u - 0.5 + n)
// with the frame's texture and shift), against the host twin, with explicit or row-major
// screen pixels, and averaged over frames against the bilinear blend of the shaded texels.
#include "io/exr_io.hpp"
#include "reference/moment_math.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/shade.hpp>
#include <msmcl/device_math.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <spawn.h>
#include <sstream>
#include <sys/wait.h>

extern char** environ;

#ifndef MSMCL_CLI_PATH // configured with MSMCL_BUILD_TOOLS=OFF: the CLI test skips
#define MSMCL_CLI_PATH ""
#endif

namespace ref = msmcl::reference;

#include "random_textures.hpp"
#include "seeded_test.hpp"

namespace {

using msmcl::testing::random_texture;

std::uint32_t test_seed() { return static_cast<std::uint32_t>(msmcl::testing::run_seed(20170728u)); }

class DitherTest : public msmcl::testing::DeviceSuite<DitherTest, 20170728u> {};


// Double-precision shadow of one stored texel at internal depth zf: decode, bias, generic
// 4MSM (linear formats) or the 4MSM of the moments Eq. 4 rebuilds (nlq formats).
double reference_texel_shadow(const msmcl::Texture& t, int x, int y, double zf) {
    const std::uint32_t* w = t.texel(x, y);
    switch (t.format) {
        case msmcl::Format::moments128: {
            const ref::Moments b{t.moment(x, y, 1), t.moment(x, y, 2), t.moment(x, y, 3), t.moment(x, y, 4)};
            return ref::hamburger4(ref::bias(b, ref::alpha_float, ref::bstar_float), zf).lower;
        }
        case msmcl::Format::msm64:
            return ref::hamburger4(ref::bias(ref::decode_msm64(ref::unpack_codes16({w[0], w[1]})), ref::alpha_msm64,
                                             ref::bstar_msm64),
                                   zf)
                .lower;
        case msmcl::Format::nlq64: return ref::nlq_shadow(ref::decode_nlq64(ref::unpack_codes16({w[0], w[1]})), zf);
        case msmcl::Format::nlq32: return ref::nlq_shadow(ref::decode_nlq32(w[0]), zf);
    }
    return 0;
}

// The frame convention of kernels/msm_bluenoise.clh written out again: lowbias32 of
// frame + 0x9e3779b9; texture bits 0-5, shift x bits 6-11, shift y bits 12-17.
double reference_noise(std::uint32_t frame, std::uint32_t px, std::uint32_t py, int channel) {
    std::uint32_t h = frame + 0x9e3779b9u;
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
    const std::uint32_t texture = h % 64, sx = (h / 64) % 64, sy = (h / 4096) % 64;
    const std::size_t texel = (std::size_t(texture) * 64 + (py + sy) % 64) * 64 + (px + sx) % 64;
    return (msmcl::blue_noise_textures()[texel * 2 + channel] + 0.5) / 256.0;
}

// docs/math.md, Lookups: the texel floor(c - 0.5 + n), clamped; where float32 could round the sum
// across an integer (within 1e-5 of it), both neighbours are candidates.
std::vector<int> reference_dither_candidates(double c, double n, int size) {
    const double s = std::clamp(c - 0.5 + n, -1.0, double(size));
    std::vector<int> candidates{std::clamp(static_cast<int>(std::floor(s)), 0, size - 1)};
    const double nearest_integer = std::round(s);
    if (std::abs(s - nearest_integer) < 1e-5) {
        candidates.push_back(std::clamp(static_cast<int>(nearest_integer) - 1, 0, size - 1));
        candidates.push_back(std::clamp(static_cast<int>(nearest_integer), 0, size - 1));
    }
    return candidates;
}

// Smallest |device - reference| over the candidate texels of a dithered receiver.
double reference_dither_error(const msmcl::Texture& t, float u, float v, float z, std::uint32_t px, std::uint32_t py,
                              const msmcl::ShadeOptions& o, float device) {
    const double zf = ref::internal_depth(z, o.depth_range == msmcl::DepthRange::zero_one) - o.depth_bias;
    double best = 1e300;
    for (int x : reference_dither_candidates(u, reference_noise(o.frame, px, py, 0), t.width))
        for (int y : reference_dither_candidates(v, reference_noise(o.frame, px, py, 1), t.height))
            best = std::min(best, std::abs(device - reference_texel_shadow(t, x, y, zf)));
    return best;
}

struct Scatter {
    msmcl::Receivers receivers;
    msmcl::ReceiverPixels pixels;
};

// Receivers over the map and a margin around it (clamp to the edge), depths through the
// range, screen pixels anywhere on a 4K screen (the noise tiles every 64 pixels).
Scatter random_receivers(int width, int height, std::size_t count, std::mt19937& rng) {
    Scatter s;
    std::uniform_real_distribution<float> u(-3.0f, width + 3.0f), v(-3.0f, height + 3.0f), z(0.0f, 1.0f);
    std::uniform_int_distribution<std::uint32_t> px(0, 3839), py(0, 2159);
    for (std::size_t i = 0; i < count; ++i) {
        s.receivers.u.push_back(u(rng));
        s.receivers.v.push_back(v(rng));
        s.receivers.z.push_back(z(rng));
        s.pixels.x.push_back(px(rng));
        s.pixels.y.push_back(py(rng));
    }
    return s;
}

class DitherAgainstReference : public DitherTest, public ::testing::WithParamInterface<msmcl::Format> {};

TEST_P(DitherAgainstReference, PicksTheTexelOfTheBlueNoiseAndShadesItLikeNearest) {
    const msmcl::Format format = GetParam();
    std::mt19937 rng(test_seed() + 31 * static_cast<unsigned>(format));
    const int width = 37, height = 29;
    const msmcl::Texture map = random_texture(format, width, height, rng);
    const Scatter scatter = random_receivers(width, height, 8000, rng);

    for (std::uint32_t frame : {0u, 1u, 4711u, 0xffffffffu}) {
        msmcl::ShadeOptions options;
        options.lookup = msmcl::Lookup::dither;
        options.frame = frame;
        const std::vector<float> device = msmcl::shade(*context_, map, scatter.receivers, scatter.pixels, options);
        ASSERT_EQ(device.size(), scatter.receivers.size());
        double max_vs_reference = 0, max_vs_host = 0;
        std::size_t above_1e4 = 0;
        for (std::size_t i = 0; i < device.size(); ++i) {
            const float u = scatter.receivers.u[i], v = scatter.receivers.v[i], z = scatter.receivers.z[i];
            const std::uint32_t px = scatter.pixels.x[i], py = scatter.pixels.y[i];
            ASSERT_TRUE(device[i] >= 0.0f && device[i] <= 1.0f) << "receiver " << i << " gave " << device[i];
            const double error = reference_dither_error(map, u, v, z, px, py, options, device[i]);
            max_vs_reference = std::max(max_vs_reference, error);
            above_1e4 += error > 1e-4;
            max_vs_host = std::max(max_vs_host, double(std::abs(device[i] - msmcl::shade_receiver(map, u, v, z, px, py, options))));
        }
        const double share = double(above_1e4) / device.size();
        std::printf("%s dither frame %u: vs double reference max %.3g, share > 1e-4 %.4f%%; vs host twin max %.3g\n",
                    msmcl::format_name(format), frame, max_vs_reference, 100 * share, max_vs_host);
        // The texel is the reference's; its shading has the nearest lookup's accuracy
        // (tests/shade_test.cpp: within 1e-4 for 99.9% of receivers, 1e-2 for all).
        EXPECT_LE(share, 0.001);
        EXPECT_LE(max_vs_reference, 1e-2);
        // Same source on host and device: only libm ulps differ.
        EXPECT_LE(max_vs_host, 1e-2);
    }
}

INSTANTIATE_TEST_SUITE_P(AllFormats, DitherAgainstReference,
                         ::testing::Values(msmcl::Format::moments128, msmcl::Format::msm64, msmcl::Format::nlq64,
                                           msmcl::Format::nlq32),
                         [](const auto& info) { return std::string(msmcl::format_name(info.param)); });

TEST_F(DitherTest, RowMajorPixelsEqualExplicitPixels) {
    std::mt19937 rng(test_seed() + 5);
    const msmcl::Texture map = random_texture(msmcl::Format::nlq32, 20, 20, rng);
    const std::uint32_t screen_width = 97;
    Scatter scatter = random_receivers(20, 20, 97 * 23 + 11, rng);
    for (std::size_t i = 0; i < scatter.receivers.size(); ++i) {
        scatter.pixels.x[i] = static_cast<std::uint32_t>(i % screen_width);
        scatter.pixels.y[i] = static_cast<std::uint32_t>(i / screen_width);
    }
    msmcl::ShadeOptions options;
    options.lookup = msmcl::Lookup::dither;
    options.frame = 99;
    const std::vector<float> explicit_pixels = msmcl::shade(*context_, map, scatter.receivers, scatter.pixels, options);
    options.screen_width = screen_width;
    EXPECT_EQ(msmcl::shade(*context_, map, scatter.receivers, options), explicit_pixels);
    // screen_width 0: one row, pixel (i, 0).
    for (std::size_t i = 0; i < scatter.receivers.size(); ++i) {
        scatter.pixels.x[i] = static_cast<std::uint32_t>(i);
        scatter.pixels.y[i] = 0;
    }
    options.screen_width = 0;
    EXPECT_EQ(msmcl::shade(*context_, map, scatter.receivers, options),
              msmcl::shade(*context_, map, scatter.receivers, scatter.pixels, options));
    // The other lookups ignore pixels and frame.
    options.lookup = msmcl::Lookup::bilinear;
    const std::vector<float> bilinear = msmcl::shade(*context_, map, scatter.receivers, options);
    options.frame = 3;
    EXPECT_EQ(msmcl::shade(*context_, map, scatter.receivers, scatter.pixels, options), bilinear);
}

TEST_F(DitherTest, DevicePathWithPixelBufferEqualsHostPath) {
    std::mt19937 rng(test_seed() + 6);
    const msmcl::Texture map = random_texture(msmcl::Format::nlq64, 16, 8, rng);
    const Scatter scatter = random_receivers(16, 8, 300, rng);
    msmcl::ShadeOptions o;
    o.lookup = msmcl::Lookup::dither;
    o.frame = 12;
    const std::vector<float> host = msmcl::shade(*context_, map, scatter.receivers, scatter.pixels, o);

    // Caller-owned buffers: map, planar u v z, planar pixels x y, result.
    const std::size_t n = scatter.receivers.size();
    cl_int status = CL_SUCCESS;
    cl_context ctx = context_->cl_context_handle();
    std::vector<float> uvz(scatter.receivers.u);
    uvz.insert(uvz.end(), scatter.receivers.v.begin(), scatter.receivers.v.end());
    uvz.insert(uvz.end(), scatter.receivers.z.begin(), scatter.receivers.z.end());
    std::vector<std::uint32_t> xy(scatter.pixels.x);
    xy.insert(xy.end(), scatter.pixels.y.begin(), scatter.pixels.y.end());
    cl_mem map_buffer = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, map.words.size() * 4,
                                       const_cast<std::uint32_t*>(map.words.data()), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_mem uvz_buffer = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, uvz.size() * 4, uvz.data(), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_mem xy_buffer = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, xy.size() * 4, xy.data(), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_mem out = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, n * 4, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    msmcl::Enqueue e;
    e.blocking = true;
    msmcl::shade(*context_, msmcl::DeviceTexture{map_buffer, map.format, map.width, map.height}, uvz_buffer, xy_buffer,
                 n, out, o, e);
    std::vector<float> device(n);
    ASSERT_EQ(clEnqueueReadBuffer(context_->cl_queue_handle(), out, CL_TRUE, 0, n * 4, device.data(), 0, nullptr, nullptr),
              CL_SUCCESS);
    EXPECT_EQ(device, host);
    for (cl_mem m : {map_buffer, uvz_buffer, xy_buffer, out}) clReleaseMemObject(m);
}

// Per receiver: the bilinear taps' shaded texels (host twin) and their weights.
struct BilinearExpectation {
    double mean = 0;     // sum_k w_k s_k: the bilinear blend of the shaded texels
    double variance = 0; // of one dithered lookup if it picks texel k with probability w_k
};

BilinearExpectation bilinear_expectation(const msmcl::Texture& map, float u, float v, float z,
                                         const msmcl::ShadeOptions& o) {
    const double zf = ref::internal_depth(z, o.depth_range == msmcl::DepthRange::zero_one) - o.depth_bias;
    const double fx = std::clamp(double(u) - 0.5, -1.0, double(map.width));
    const double fy = std::clamp(double(v) - 0.5, -1.0, double(map.height));
    const double tx = fx - std::floor(fx), ty = fy - std::floor(fy);
    const int x0 = std::clamp(static_cast<int>(std::floor(fx)), 0, map.width - 1);
    const int x1 = std::clamp(static_cast<int>(std::floor(fx)) + 1, 0, map.width - 1);
    const int y0 = std::clamp(static_cast<int>(std::floor(fy)), 0, map.height - 1);
    const int y1 = std::clamp(static_cast<int>(std::floor(fy)) + 1, 0, map.height - 1);
    const double w[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
    const double s[4] = {reference_texel_shadow(map, x0, y0, zf), reference_texel_shadow(map, x1, y0, zf),
                         reference_texel_shadow(map, x0, y1, zf), reference_texel_shadow(map, x1, y1, zf)};
    BilinearExpectation e;
    for (int k = 0; k < 4; ++k) e.mean += w[k] * s[k];
    for (int k = 0; k < 4; ++k) e.variance += w[k] * (s[k] - e.mean) * (s[k] - e.mean);
    return e;
}

class DitherConvergence : public DitherTest, public ::testing::WithParamInterface<msmcl::Format> {};

TEST_P(DitherConvergence, AveragedOverFramesIsTheBilinearBlendOfTheShadedTexels) {
    const msmcl::Format format = GetParam();
    std::mt19937 rng(test_seed() + 77 + static_cast<unsigned>(format));
    const int width = 12, height = 10;
    const msmcl::Texture map = random_texture(format, width, height, rng);
    const Scatter scatter = random_receivers(width, height, 2000, rng);
    const std::size_t n = scatter.receivers.size();

    // The mean of F frames per receiver.
    const int frames = 256;
    std::vector<double> mean(n, 0.0), mean64(n, 0.0);
    msmcl::ShadeOptions options;
    options.lookup = msmcl::Lookup::dither;
    for (int f = 0; f < frames; ++f) {
        options.frame = static_cast<std::uint32_t>(f);
        const std::vector<float> y = msmcl::shade(*context_, map, scatter.receivers, scatter.pixels, options);
        for (std::size_t i = 0; i < n; ++i) {
            mean[i] += y[i] / double(frames);
            if (f < 64) mean64[i] += y[i] / 64.0;
        }
    }

    // Each frame picks texel x0 + 1 with probability P(n >= 1 - tx) (blue noise of a random
    // texture at a random shift: a uniform level), so the F-frame mean is the bilinear blend
    // sum_k w_k s_k plus sampling noise of variance sum_k w_k (s_k - mean)^2 / F (plus a bias
    // of at most 1/512 per axis from the 256 levels, and the two channels' correlation).
    // Standardized errors z = (mean_F - blend) / sd must have mean ~0 and mean square ~1.
    double z_sum = 0, z2_sum = 0, rms = 0, rms64 = 0, max_error = 0;
    std::size_t spread = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const BilinearExpectation e = bilinear_expectation(map, scatter.receivers.u[i], scatter.receivers.v[i],
                                                           scatter.receivers.z[i], options);
        const double error = mean[i] - e.mean;
        rms += error * error / n;
        rms64 += (mean64[i] - e.mean) * (mean64[i] - e.mean) / n;
        max_error = std::max(max_error, std::abs(error));
        if (e.variance < 1e-6) continue; // all four texels (nearly) alike: nothing to average
        const double z = error / std::sqrt(e.variance / frames);
        z_sum += z;
        z2_sum += z * z;
        ++spread;
    }
    const double z_mean = z_sum / spread, z2_mean = z2_sum / spread;
    std::printf("%s: %d frames, %zu receivers (%zu with spread): error vs bilinear blend rms %.4f, max %.4f; "
                "64 frames rms %.4f; standardized mean %.3f, mean square %.3f\n",
                msmcl::format_name(format), frames, n, spread, std::sqrt(rms), max_error, std::sqrt(rms64), z_mean, z2_mean);
    ASSERT_GT(spread, n / 4);
    // Over ~1000 receivers the mean of z has sd ~0.03 and the mean of z^2 ~1 +- 0.05 if the
    // frames sample the weights without bias; 0.2 and [0.6, 1.5] leave room for the level
    // quantization and the channel correlation, and fail for a biased pick (floor(u + n)
    // instead of floor(u - 0.5 + n) moves every weight by 1/2) or frames that repeat the noise.
    EXPECT_LT(std::abs(z_mean), 0.2);
    EXPECT_GT(z2_mean, 0.6);
    EXPECT_LT(z2_mean, 1.5);
}

INSTANTIATE_TEST_SUITE_P(AllFormats, DitherConvergence,
                         ::testing::Values(msmcl::Format::moments128, msmcl::Format::msm64, msmcl::Format::nlq64,
                                           msmcl::Format::nlq32),
                         [](const auto& info) { return std::string(msmcl::format_name(info.param)); });

TEST_F(DitherTest, SampleSceneNlq64Over64FramesApproachesBilinear) {
    // The shipped railing scene (filtered nlq64, the view's receivers): the error of one
    // dithered frame and of the mean of 64 frames against the bilinear lookup (for nlq64 the
    // bilinear blend of the shaded texels).
    const msmcl::DepthImage depth =
        msmcl::io::read_depth_exr(MSMCL_SOURCE_DIR "/data/railing_256x256_4x.exr", msmcl::DepthRange::zero_one);
    const msmcl::io::ReceiverGrid view = msmcl::io::read_receivers_exr(MSMCL_SOURCE_DIR "/data/railing_view_160x120.exr");
    msmcl::FilterOptions filter_options;
    filter_options.format = msmcl::Format::nlq64;
    const msmcl::Texture map = msmcl::filter(*context_, depth, filter_options);
    msmcl::ShadeOptions options;
    options.lookup = msmcl::Lookup::bilinear;
    const std::vector<float> bilinear = msmcl::shade(*context_, map, view.points, options);
    options.lookup = msmcl::Lookup::nearest;
    const std::vector<float> nearest = msmcl::shade(*context_, map, view.points, options);
    options.lookup = msmcl::Lookup::dither;
    options.screen_width = static_cast<std::uint32_t>(view.width);
    const std::size_t n = bilinear.size();
    std::vector<double> mean(n, 0.0);
    double rms_one = 0, rms_nearest = 0;
    for (std::uint32_t frame = 0; frame < 64; ++frame) {
        options.frame = frame;
        const std::vector<float> y = msmcl::shade(*context_, map, view.points, options);
        for (std::size_t i = 0; i < n; ++i) {
            mean[i] += y[i] / 64.0;
            if (frame == 0) rms_one += (y[i] - bilinear[i]) * (y[i] - bilinear[i]) / double(n);
        }
    }
    double rms64 = 0, max64 = 0;
    for (std::size_t i = 0; i < n; ++i) {
        rms64 += (mean[i] - bilinear[i]) * (mean[i] - bilinear[i]) / double(n);
        max64 = std::max(max64, std::abs(mean[i] - bilinear[i]));
        rms_nearest += (nearest[i] - bilinear[i]) * (nearest[i] - bilinear[i]) / double(n);
    }
    std::printf("railing nlq64 %dx%d view vs bilinear: nearest rms %.4f; dither one frame rms %.4f; "
                "mean of 64 frames rms %.4f, max %.4f\n",
                view.width, view.height, std::sqrt(rms_nearest), std::sqrt(rms_one), std::sqrt(rms64), max64);
    // The 64-frame mean is much closer to bilinear than one frame (noise / sqrt(64) = 1/8).
    EXPECT_LT(std::sqrt(rms64), 0.25 * std::sqrt(rms_one));
}

TEST_F(DitherTest, RejectsMismatchedPixels) {
    std::mt19937 rng(test_seed());
    const msmcl::Texture map = random_texture(msmcl::Format::nlq64, 4, 4, rng);
    msmcl::Receivers r{{1.0f, 2.0f}, {1.0f, 2.0f}, {0.5f, 0.5f}};
    msmcl::ShadeOptions o;
    o.lookup = msmcl::Lookup::dither;
    EXPECT_NO_THROW(msmcl::shade(*context_, map, r, msmcl::ReceiverPixels{{0, 1}, {0, 0}}, o));
    EXPECT_THROW(msmcl::shade(*context_, map, r, msmcl::ReceiverPixels{{0}, {0}}, o), msmcl::input_error);
    EXPECT_THROW(msmcl::shade(*context_, map, r, msmcl::ReceiverPixels{{0, 1}, {}}, o), msmcl::input_error);
    o.lookup = static_cast<msmcl::Lookup>(7);
    EXPECT_THROW(msmcl::shade(*context_, map, r, o), msmcl::input_error);
}

// ---- msmcl shade --lookup dither [--frame N], receivers with and without PX, PY.

struct CliRun {
    int exit_code = -1;
    std::string err;
};

// Runs the msmcl executable (no shell), stderr captured.
CliRun run_cli(std::vector<std::string> arguments, const std::filesystem::path& directory) {
    arguments.insert(arguments.begin(), MSMCL_CLI_PATH);
    const std::string err_log = (directory / "stderr").string();
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, err_log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<char*> argv;
    for (std::string& argument : arguments) argv.push_back(argument.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    CliRun run;
    if (posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ) == 0) {
        int status = 0;
        waitpid(pid, &status, 0);
        run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    posix_spawn_file_actions_destroy(&actions);
    std::ifstream err(err_log);
    std::stringstream text;
    text << err.rdbuf();
    run.err = text.str();
    return run;
}

TEST_F(DitherTest, CliShadesWithDitherFrameAndScreenPixels) {
    if (std::string(MSMCL_CLI_PATH).empty()) GTEST_SKIP() << "built without the msmcl CLI";
    namespace fs = std::filesystem;
    std::string pattern = (fs::temp_directory_path() / "msmcl-dither-test-XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    const fs::path root = pattern;
    const auto path = [&](const char* name) { return (root / name).string(); };

    // A map and a 23x7 receiver grid, once with PX, PY and once without.
    std::mt19937 rng(test_seed() + 8);
    const msmcl::Texture map = random_texture(msmcl::Format::nlq64, 12, 9, rng);
    msmcl::io::write_texture_exr(path("map.exr"), map, {2.4f, 1, msmcl::DepthRange::zero_one});
    msmcl::io::ReceiverGrid grid;
    grid.width = 23;
    grid.height = 7;
    const Scatter scatter = random_receivers(12, 9, 23 * 7, rng);
    grid.points = scatter.receivers;
    msmcl::io::write_receivers_exr(path("plain.exr"), grid);
    grid.pixels = scatter.pixels;
    msmcl::io::write_receivers_exr(path("pixels.exr"), grid);
    ASSERT_EQ(msmcl::io::read_receivers_exr(path("pixels.exr")).pixels.x, scatter.pixels.x);
    ASSERT_TRUE(msmcl::io::read_receivers_exr(path("plain.exr")).pixels.x.empty());

    // The CLI's results are the library's: explicit pixels, else the grid's row-major pixels.
    msmcl::ShadeOptions options;
    options.lookup = msmcl::Lookup::dither;
    options.frame = 5;
    const auto shaded = [&](const char* file) { return msmcl::io::read_exr(path(file)).find_channel("Y")->values; };
    ASSERT_EQ(run_cli({"shade", path("map.exr"), path("pixels.exr"), path("y1.exr"), "--lookup", "dither", "--frame", "5"}, root)
                  .exit_code,
              0);
    EXPECT_EQ(shaded("y1.exr"), msmcl::shade(*context_, map, scatter.receivers, scatter.pixels, options));
    ASSERT_EQ(run_cli({"shade", path("map.exr"), path("plain.exr"), path("y2.exr"), "--lookup", "dither", "--frame", "5"}, root)
                  .exit_code,
              0);
    options.screen_width = 23;
    EXPECT_EQ(shaded("y2.exr"), msmcl::shade(*context_, map, scatter.receivers, options));
    // Frame 0 by default.
    ASSERT_EQ(run_cli({"shade", path("map.exr"), path("plain.exr"), path("y3.exr"), "--lookup", "dither"}, root).exit_code, 0);
    options.frame = 0;
    EXPECT_EQ(shaded("y3.exr"), msmcl::shade(*context_, map, scatter.receivers, options));

    // Bad frames and a lone PX: exit 2, a message, no output.
    for (const char* frame : {"-1", "4294967296", "1.5", "x", ""}) {
        const CliRun run = run_cli({"shade", path("map.exr"), path("plain.exr"), path("bad.exr"), "--lookup", "dither",
                                    "--frame", frame},
                                   root);
        EXPECT_EQ(run.exit_code, 2) << frame;
        EXPECT_NE(run.err.find("--frame must be a whole number"), std::string::npos) << run.err;
        EXPECT_FALSE(fs::exists(path("bad.exr")));
    }
    msmcl::io::ExrImage lone = msmcl::io::read_exr(path("pixels.exr"));
    lone.channels.erase(std::remove_if(lone.channels.begin(), lone.channels.end(),
                                       [](const msmcl::io::ExrChannel& c) { return c.name == "PY"; }),
                        lone.channels.end());
    msmcl::io::write_exr(path("lone.exr"), lone);
    const CliRun run = run_cli({"shade", path("map.exr"), path("lone.exr"), path("bad.exr"), "--lookup", "dither"}, root);
    EXPECT_EQ(run.exit_code, 2);
    EXPECT_NE(run.err.find("has channel PX without PY"), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(path("bad.exr")));
    fs::remove_all(root);
}

} // namespace
