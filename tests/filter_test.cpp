// filter on the OpenCL device (PoCL in CI) against the double-precision reference
// (tests/reference/filter_reference.*), one suite run by every work distribution
// (FilterKernel: fused_paper, fused_cpu, three_pass): resolve + blur, every format, sizes
// around each kernel's output block (the CPU tile's borders included), sample counts, depth
// ranges, sigmas, bad inputs, device path == host path; the fused kernels against
// three-pass (bit for bit for moments128 and msm64, their per-block shift for nlq), the
// choice of `automatic`, other CPU tilings.
#include "filter_fixtures.hpp"
#include "ops/kernel_variants.hpp"
#include "runtime/context_impl.hpp"
#include "runtime/texture_kinds.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

// The fixtures' maps and checks, and their names for msmcl's types (ref, DepthImage, ...).
using namespace filter_fixtures;

using Size = std::array<int, 2>;

std::string size_name(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

// The maps each kernel's tests run on, shaped around its output block (fused_paper 32x24,
// fused_cpu its 128x64 tile, both with a guard band of 4; three_pass reads the paper's).
// Sizes around the block: a single texel, less than a block, exactly one, one more, more
// than the guard band past a block, tall and wide strips, and (CPU) maps with interior
// tiles between border tiles on both sides.
std::vector<Size> border_sizes(FilterKernel kernel) {
    if (kernel == FilterKernel::fused_cpu)
        return {{1, 1}, {7, 5}, {128, 64}, {129, 65}, {132, 68}, {1000, 1}, {1, 300}, {300, 200}, {397, 131}, {520, 70}, {264, 9}};
    return {{1, 1}, {31, 23}, {33, 25}, {32, 24}, {1000, 1}, {1, 1000}, {65, 49}, {7, 300}};
}

// A map of several blocks, for the sample counts, sigmas and depth ranges.
Size several_blocks(FilterKernel kernel) { return kernel == FilterKernel::fused_cpu ? Size{150, 80} : Size{70, 50}; }

// Maps (and seed offsets) of the nlq checks against the reference: for the CPU tile also
// one just past a tile, where the border tiles meet.
std::vector<std::array<int, 3>> nlq_maps(FilterKernel kernel) {
    if (kernel == FilterKernel::fused_cpu) return {{300, 200, 19 + 300}, {129, 65, 19 + 129}};
    return {{200, 150, 19}};
}

// Every test of the suite on one kernel (the parameter).
class FilterEveryKernel : public FilterTest, public ::testing::WithParamInterface<FilterKernel> {
protected:
    static FilterKernel kernel() { return GetParam(); }
    static std::string kernel_name() { return msmcl::filter_kernel_name(GetParam()); }
    static Texture with_kernel(const DepthImage& depth, Format format, float sigma = 2.4f,
                               DepthRange range = DepthRange::zero_one) {
        return run(depth, format, sigma, range, GetParam());
    }
    static Texture three_pass(const DepthImage& depth, Format format, float sigma = 2.4f,
                              DepthRange range = DepthRange::zero_one) {
        return run(depth, format, sigma, range, FilterKernel::three_pass);
    }
};

// The fused kernels against three-pass, the baseline without blocks.
class FilterFusedKernel : public FilterEveryKernel {};

std::string parameter_name(const ::testing::TestParamInfo<FilterKernel>& info) {
    return msmcl::filter_kernel_name(info.param);
}

INSTANTIATE_TEST_SUITE_P(Kernels, FilterEveryKernel,
                         ::testing::Values(FilterKernel::fused_paper, FilterKernel::fused_cpu, FilterKernel::three_pass),
                         parameter_name);
INSTANTIATE_TEST_SUITE_P(Kernels, FilterFusedKernel, ::testing::Values(FilterKernel::fused_paper, FilterKernel::fused_cpu),
                         parameter_name);

using Filter = FilterTest;

TEST(GaussianTaps, NormalizedSymmetricAndLikeTheReference) {
    for (float sigma : {0.0f, 0.5f, 1.0f, 2.4f, 4.0f, 100.0f}) {
        const std::array<float, 9> taps = msmcl::gaussian_taps(sigma);
        const std::array<double, 9> weights = ref::gaussian_weights(sigma);
        double total = 0.0;
        for (int i = 0; i < 9; ++i) {
            total += taps[i];
            EXPECT_EQ(taps[i], taps[8 - i]) << "sigma " << sigma;
            // Rounded once from double: half an ulp.
            EXPECT_NEAR(taps[i], weights[i], 0.5 * std::ldexp(1.0, -24) * 1.0001) << "sigma " << sigma << " tap " << i;
        }
        EXPECT_NEAR(total, 1.0, 1e-6) << "sigma " << sigma;
    }
    EXPECT_EQ(msmcl::gaussian_taps(0.0f)[4], 1.0f);
    EXPECT_THROW(msmcl::gaussian_taps(-1.0f), msmcl::input_error);
    EXPECT_THROW(msmcl::gaussian_taps(std::nanf("")), msmcl::input_error);
    EXPECT_THROW(msmcl::gaussian_taps(std::numeric_limits<float>::infinity()), msmcl::input_error);
}

TEST(SampleCounts, OnlyPowersOfTwoUpTo16) {
    for (int s = -1; s <= 32; ++s)
        EXPECT_EQ(msmcl::is_supported_sample_count(s), s == 1 || s == 2 || s == 4 || s == 8 || s == 16) << s;
}

TEST_P(FilterEveryKernel, Moments128MatchesReferenceAtEverySize) {
    for (const auto& [width, height] : border_sizes(kernel())) {
        const DepthImage depth = make_depth(width, height, 4, DepthRange::zero_one, test_seed() + width * 7 + height);
        expect_moments_close(with_kernel(depth, Format::moments128),
                             ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4), kMomentTolerance,
                             kernel_name() + " " + size_name(width, height));
    }
}

TEST_P(FilterEveryKernel, Moments128MatchesReferenceForEverySampleCount) {
    const auto [width, height] = several_blocks(kernel());
    for (int samples : {1, 2, 4, 8, 16}) {
        const DepthImage depth = make_depth(width, height, samples, DepthRange::zero_one, test_seed() + samples);
        expect_moments_close(with_kernel(depth, Format::moments128),
                             ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4), kMomentTolerance,
                             kernel_name() + " " + std::to_string(samples) + " samples");
    }
}

TEST_P(FilterEveryKernel, Moments128MatchesReferenceForEverySigma) {
    const auto [width, height] = several_blocks(kernel());
    const DepthImage depth = make_depth(width, height, 4, DepthRange::zero_one, test_seed() + 11);
    for (float sigma : {0.0f, 1.0f, 2.4f, 4.0f}) {
        expect_moments_close(with_kernel(depth, Format::moments128, sigma),
                             ref::filter_moments(to_reference(depth, DepthRange::zero_one), sigma), kMomentTolerance,
                             kernel_name() + " sigma " + std::to_string(sigma));
    }
    // sigma 0 is the plain resolve.
    expect_moments_close(with_kernel(depth, Format::moments128, 0.0f), ref::resolve(to_reference(depth, DepthRange::zero_one)),
                         kMomentTolerance, kernel_name() + " resolve");
}

TEST_P(FilterEveryKernel, Moments128MatchesReferenceForTheMinusOneOneRange) {
    const auto [width, height] = several_blocks(kernel());
    const DepthImage depth = make_depth(width, height, 4, DepthRange::minus_one_one, test_seed() + 13);
    expect_moments_close(with_kernel(depth, Format::moments128, 2.4f, DepthRange::minus_one_one),
                         ref::filter_moments(to_reference(depth, DepthRange::minus_one_one), 2.4), kMomentTolerance,
                         kernel_name() + " depth range -1,1");
}

TEST_P(FilterEveryKernel, Msm64CodesMatchTheReferenceMomentsEncodedInDouble) {
    const DepthImage depth = make_depth(200, 150, 4, DepthRange::zero_one, test_seed() + 17);
    const Texture texture = with_kernel(depth, Format::msm64);
    const std::vector<ref::Moments> expected = ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4);
    std::size_t exact_texels = 0, beyond_one = 0, texels = 0;
    unsigned worst = 0;
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x) {
            const ref::Codes16 codes = ref::encode_msm64(expected[std::size_t(y) * depth.width + x]);
            unsigned texel_worst = 0;
            for (int c = 0; c < 4; ++c) {
                const unsigned want = codes[c];
                const unsigned got = texture.code16(x, y, c);
                texel_worst = std::max(texel_worst, got > want ? got - want : want - got);
            }
            // Float moments differ from double by < 2e-6; G = 4 b2 - 4 b4 scales that by 8:
            // 65535 * 1.6e-5 ~ 1 code, so never more than 2 codes.
            EXPECT_LE(texel_worst, 2u) << at(x, y) << ", seed " << test_seed();
            worst = std::max(worst, texel_worst);
            exact_texels += texel_worst == 0;
            beyond_one += texel_worst > 1;
            ++texels;
        }
    std::cout << "msm64 " << kernel_name() << ": " << exact_texels << " of " << texels << " texels exact, "
              << beyond_one << " off by more than one code, worst " << worst << "\n";
    // Within one code for at least 99.9% of the texels.
    EXPECT_LE(double(beyond_one), 0.001 * texels) << "seed " << test_seed();
}

// The nlq formats: moments rebuilt from the decoded texels within the quantization of the
// reference, codes within one of double Algorithm 2 in the kernel's (block-shifted) frame.
TEST_P(FilterEveryKernel, NlqFormatsRebuildTheReferenceMoments) {
    for (const auto& [width, height, seed_offset] : nlq_maps(kernel())) {
        const DepthImage depth = make_depth(width, height, 4, DepthRange::zero_one, test_seed() + seed_offset);
        const std::vector<ref::Moments> expected = ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4);
        const std::string name = kernel_name() + " " + size_name(width, height);
        check_nlq_against_reference(with_kernel(depth, Format::nlq64), depth, kernel(), expected, "nlq64 " + name);
        check_nlq_against_reference(with_kernel(depth, Format::nlq32), depth, kernel(), expected, "nlq32 " + name);
    }
}

// moments128 and msm64 (no shift): bit for bit at every size around the block.
TEST_P(FilterFusedKernel, Moments128AndMsm64EqualThreePassBitForBit) {
    for (const auto& [width, height] : border_sizes(kernel())) {
        const DepthImage depth = make_depth(width, height, 4, DepthRange::zero_one, test_seed() + 3 + width + height);
        for (Format format : {Format::moments128, Format::msm64})
            EXPECT_EQ(with_kernel(depth, format).words, three_pass(depth, format).words)
                << kernel_name() << " " << size_name(width, height) << " " << msmcl::format_name(format);
    }
}

// moments128 and msm64 bit for bit; nlq: the fused kernel shifts by its block's depth
// midrange, so its codes equal three-pass's or are one step away where both kernels' frames
// are well conditioned.
TEST_P(FilterFusedKernel, EqualsThreePass) {
    const bool cpu = kernel() == FilterKernel::fused_cpu;
    const DepthImage depth = cpu ? make_depth(300, 200, 4, DepthRange::zero_one, test_seed() + 23)
                                 : make_depth(200, 150, 4, DepthRange::zero_one, test_seed() + 23);
    for (Format format : {Format::moments128, Format::msm64})
        EXPECT_EQ(with_kernel(depth, format).words, three_pass(depth, format).words) << msmcl::format_name(format);
    const std::vector<ref::Moments> expected = ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4);
    const KernelShift shift(depth, DepthRange::zero_one, kernel());
    for (Format format : {Format::nlq64, Format::nlq32}) {
        const Texture fused = with_kernel(depth, format);
        const Texture three = three_pass(depth, format);
        std::size_t compared = 0, equal = 0;
        for (int y = 0; y < depth.height; ++y)
            for (int x = 0; x < depth.width; ++x) {
                const ref::Moments& exact = expected[std::size_t(y) * depth.width + x];
                const double c = shift.at(x, y);
                const std::array<double, 4> fused_sensitivity = code_sensitivity(exact, c, format);
                const std::array<double, 4> three_sensitivity = code_sensitivity(exact, 0.0, format);
                const std::array<int, 4> a = nlq_fields(fused, x, y), b = nlq_fields(three, x, y);
                for (int k = 0; k < 4; ++k) {
                    if (std::max(fused_sensitivity[k], three_sensitivity[k]) > kWellConditioned) continue;
                    ++compared;
                    equal += a[k] == b[k];
                    EXPECT_LE(std::abs(a[k] - b[k]), 1) << msmcl::format_name(format) << " " << at(x, y) << " field "
                                                        << k << ", seed " << test_seed();
                }
            }
        std::cout << msmcl::format_name(format) << " " << kernel_name() << " vs three-pass: " << equal << " of "
                  << compared << " well-conditioned codes equal\n";
        // Something to compare: a quarter of the paper's map; an eighth of the CPU's, whose
        // unshifted three-pass frame is ill-conditioned for nlq64 in most texels.
        EXPECT_GT(compared, std::size_t(depth.width) * depth.height / (cpu ? 8 : 4));
    }
}

// Far from z = 0, b2 - b1^2 cancels in float32 (docs/math.md, Float32 guard); the fused
// kernels' per-block (per-tile) shift keeps Algorithm 2 accurate there.
TEST_P(FilterFusedKernel, ShiftKeepsFlatFarRegionsAccurate) {
    DepthImage depth;
    const auto [width, height] = kernel() == FilterKernel::fused_cpu ? Size{300, 140} : Size{96, 72};
    depth.width = width, depth.height = height, depth.samples = 4;
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x)
            for (int s = 0; s < 4; ++s)
                depth.depth.push_back(0.93f + 0.004f * std::sin(0.3f * (x + 0.25f * s) + float(test_seed() % 7)) *
                                                  std::cos(0.2f * y));
    const std::vector<ref::Moments> expected = ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4);
    std::size_t texels = 0, fused_close = 0, three_close = 0;
    const Texture fused = with_kernel(depth, Format::nlq64);
    const Texture three = three_pass(depth, Format::nlq64);
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x) {
            const ref::Moments biased = ref::bias(expected[std::size_t(y) * depth.width + x], 3e-7, 0.375);
            const ref::Codes16 want = ref::encode_nlq64(algorithm2_shifted(biased, 0.0));
            const auto close = [&](const Texture& t) {
                for (int c = 0; c < 4; ++c)
                    if (std::abs(int(t.code16(x, y, c)) - int(want[c])) > 1) return false;
                return true;
            };
            ++texels;
            fused_close += close(fused);
            three_close += close(three);
        }
    std::cout << "flat far region, nlq64 codes within one of double Algorithm 2: " << kernel_name() << " "
              << fused_close << ", three-pass " << three_close << " of " << texels << "\n";
    // The unshifted three-pass baseline gets few or none of these right; the fused kernels
    // practically all.
    EXPECT_GE(fused_close, texels * 99 / 100) << "seed " << test_seed();
    EXPECT_GE(fused_close, three_close);
}

TEST_P(FilterFusedKernel, LargeMapEqualsThreePass) {
    // The paper's kernel on a 2048^2 map; the CPU tiles over one of 9 x 11 tiles.
    const auto [width, height] = kernel() == FilterKernel::fused_cpu ? Size{1100, 700} : Size{2048, 2048};
    const DepthImage depth = make_depth(width, height, 4, DepthRange::zero_one, test_seed() + 37);
    const Texture fused = with_kernel(depth, Format::moments128);
    EXPECT_EQ(fused.words, three_pass(depth, Format::moments128).words);
    // Spot checks against the direct 9x9 reference: block corners, image borders, random texels.
    const ref::DepthMap map = to_reference(depth, DepthRange::zero_one);
    const auto [block_width, block_height] = output_block(kernel());
    std::mt19937 random(test_seed());
    std::vector<std::array<int, 2>> texels{{0, 0},
                                           {width - 1, height - 1},
                                           {0, height - 1},
                                           {width - 1, 0},
                                           {block_width - 1, block_height - 1},
                                           {block_width, block_height},
                                           {width - 1, height / 2}};
    for (int i = 0; i < 400; ++i) texels.push_back({int(random() % width), int(random() % height)});
    for (const auto& [x, y] : texels) {
        const ref::Moments expected = ref::filter_moments_at(map, 2.4, x, y);
        for (int j = 1; j <= 4; ++j)
            EXPECT_NEAR(fused.moment(x, y, j), ref::moment(expected, j), kMomentTolerance) << at(x, y) << " b" << j;
    }
}

TEST_P(FilterEveryKernel, BadInputsThrowInputError) {
    const DepthImage good = make_depth(8, 6, 2, DepthRange::zero_one, test_seed());
    msmcl::FilterOptions options;
    options.kernel = kernel();
    const auto expect_input_error = [&](DepthImage depth, const msmcl::FilterOptions& o, const std::string& needle) {
        try {
            msmcl::filter(*context_, depth, o);
            ADD_FAILURE() << "no input_error for: " << needle;
        } catch (const msmcl::input_error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    DepthImage bad = good;
    bad.depth[(2 * 8 + 3) * 2 + 1] = std::nanf("");
    expect_input_error(bad, options, "texel (3, 2) sample 1 is nan");
    bad = good;
    bad.depth[(5 * 8 + 7) * 2] = std::numeric_limits<float>::infinity();
    expect_input_error(bad, options, "texel (7, 5) sample 0 is inf");
    bad = good;
    bad.depth[0] = 1.5f;
    expect_input_error(bad, options, "texel (0, 0) sample 0 is 1.5, outside the depth range [0,1]");
    bad = good;
    bad.depth[3] = -0.25f;
    expect_input_error(bad, options, "texel (1, 0) sample 1 is -0.25");
    // -0.25 is fine in [-1,1], -1.5 is not.
    msmcl::FilterOptions gl = options;
    gl.depth_range = DepthRange::minus_one_one;
    EXPECT_NO_THROW(msmcl::filter(*context_, bad, gl));
    bad.depth[3] = -1.5f;
    expect_input_error(bad, gl, "outside the depth range [-1,1]");
    bad = good;
    bad.samples = 3;
    bad.depth.resize(8 * 6 * 3, 0.5f);
    expect_input_error(bad, options, "unsupported sample count 3");
    bad = good;
    bad.depth.pop_back();
    expect_input_error(bad, options, "needs 96 values, got 95");
    bad = good;
    bad.width = 0;
    expect_input_error(bad, options, "empty");
    bad = good;
    bad.height = -2;
    expect_input_error(bad, options, "empty");
    bad = good;
    bad.width = 70000;
    expect_input_error(bad, options, "exceeds");
    msmcl::FilterOptions negative = options;
    negative.sigma = -1.0f;
    expect_input_error(good, negative, "sigma");
}

// Device path with caller-owned buffers, the caller's queue, a wait list and a done event,
// vs the host path.
TEST_P(FilterEveryKernel, DevicePathEqualsHostPath) {
    const auto [width, height] = kernel() == FilterKernel::fused_cpu ? Size{260, 90} : Size{100, 70};
    const DepthImage depth = make_depth(width, height, 4, DepthRange::zero_one, test_seed() + 41);
    cl_context cl_ctx = context_->cl_context_handle();
    cl_int status = CL_SUCCESS;
    // The caller's own queue, distinct from the Context's.
    cl_command_queue queue = clCreateCommandQueue(cl_ctx, context_->cl_device_handle(), 0, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    const std::size_t depth_bytes = depth.depth.size() * sizeof(float);
    cl_mem depth_buffer = clCreateBuffer(cl_ctx, CL_MEM_READ_ONLY, depth_bytes, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    for (Format format : {Format::nlq64, Format::nlq32, Format::moments128}) {
        const std::size_t texture_bytes = std::size_t(depth.width) * depth.height * msmcl::texel_bytes(format);
        cl_mem texture_buffer = clCreateBuffer(cl_ctx, CL_MEM_WRITE_ONLY, texture_bytes, nullptr, &status);
        ASSERT_EQ(status, CL_SUCCESS);
        cl_event uploaded = nullptr, filtered = nullptr;
        ASSERT_EQ(clEnqueueWriteBuffer(queue, depth_buffer, CL_FALSE, 0, depth_bytes, depth.depth.data(), 0, nullptr,
                                       &uploaded),
                  CL_SUCCESS);
        msmcl::FilterOptions options;
        options.format = format;
        options.kernel = kernel();
        msmcl::Enqueue enqueue;
        enqueue.queue = queue;
        enqueue.wait_for = {uploaded};
        enqueue.done = &filtered;
        msmcl::filter(*context_, msmcl::DeviceDepth{depth_buffer, depth.width, depth.height, depth.samples},
                      texture_buffer, options, enqueue);
        ASSERT_NE(filtered, nullptr);
        std::vector<std::uint32_t> words(texture_bytes / 4);
        ASSERT_EQ(clEnqueueReadBuffer(queue, texture_buffer, CL_TRUE, 0, texture_bytes, words.data(), 1, &filtered,
                                      nullptr),
                  CL_SUCCESS);
        cl_int execution = 1;
        ASSERT_EQ(clGetEventInfo(filtered, CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof execution, &execution, nullptr),
                  CL_SUCCESS);
        EXPECT_EQ(execution, CL_COMPLETE);
        EXPECT_EQ(words, with_kernel(depth, format).words) << msmcl::format_name(format);
        clReleaseEvent(uploaded);
        clReleaseEvent(filtered);
        clReleaseMemObject(texture_buffer);
    }
    // The Context's own queue, blocking, no events.
    const std::size_t texture_bytes = std::size_t(depth.width) * depth.height * 8;
    cl_mem texture_buffer = clCreateBuffer(cl_ctx, CL_MEM_READ_WRITE, texture_bytes, nullptr, &status);
    ASSERT_EQ(clEnqueueWriteBuffer(queue, depth_buffer, CL_TRUE, 0, depth_bytes, depth.depth.data(), 0, nullptr, nullptr),
              CL_SUCCESS);
    msmcl::FilterOptions options;
    options.format = Format::msm64;
    options.kernel = kernel();
    msmcl::Enqueue blocking;
    blocking.blocking = true;
    msmcl::filter(*context_, msmcl::DeviceDepth{depth_buffer, depth.width, depth.height, depth.samples}, texture_buffer,
                  options, blocking);
    std::vector<std::uint32_t> words(texture_bytes / 4);
    ASSERT_EQ(clEnqueueReadBuffer(queue, texture_buffer, CL_TRUE, 0, texture_bytes, words.data(), 0, nullptr, nullptr),
              CL_SUCCESS);
    EXPECT_EQ(words, with_kernel(depth, Format::msm64).words);
    // Buffers too small and bad shapes are input errors.
    const msmcl::DeviceDepth too_big{depth_buffer, depth.width, depth.height + 1, depth.samples};
    EXPECT_THROW(msmcl::filter(*context_, too_big, texture_buffer, options), msmcl::input_error);
    options.format = Format::moments128;
    const msmcl::DeviceDepth shape{depth_buffer, depth.width, depth.height, depth.samples};
    EXPECT_THROW(msmcl::filter(*context_, shape, texture_buffer, options), msmcl::input_error);
    EXPECT_THROW(msmcl::filter(*context_, msmcl::DeviceDepth{depth_buffer, 10, 10, 3}, texture_buffer, options),
                 msmcl::input_error);
    EXPECT_THROW(msmcl::filter(*context_, msmcl::DeviceDepth{nullptr, 10, 10, 1}, texture_buffer, options),
                 msmcl::input_error);
    clReleaseMemObject(texture_buffer);
    clReleaseMemObject(depth_buffer);
    clReleaseCommandQueue(queue);
}

// Device depth is not validated: out-of-range values clamp to the range, NaN is the near
// plane, in the interior and the border blocks (tiles) alike.
TEST_P(FilterEveryKernel, DevicePathClampsOutOfRangeDepth) {
    constexpr int width = 300, height = 70;
    DepthImage wild = make_depth(width, height, 1, DepthRange::zero_one, test_seed() + 43);
    DepthImage tame = wild;
    for (std::size_t i : {std::size_t(0), std::size_t(10), std::size_t(500), std::size_t(4000),
                          std::size_t(150 * 70 + 35), std::size_t(299 + 300 * 69)}) {
        wild.depth[i] = i % 2 ? 7.0f : std::nanf("");
        tame.depth[i] = i % 2 ? 1.0f : 0.0f;
    }
    wild.depth[100] = -3.0f, tame.depth[100] = 0.0f;
    wild.depth[700] = -std::numeric_limits<float>::infinity(), tame.depth[700] = 0.0f;
    wild.depth[5000] = -std::numeric_limits<float>::infinity(), tame.depth[5000] = 0.0f;
    cl_int status = CL_SUCCESS;
    cl_mem depth_buffer = clCreateBuffer(context_->cl_context_handle(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                         wild.depth.size() * 4, wild.depth.data(), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    const std::size_t texture_bytes = std::size_t(width) * height * 16;
    cl_mem texture_buffer =
        clCreateBuffer(context_->cl_context_handle(), CL_MEM_WRITE_ONLY, texture_bytes, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    msmcl::FilterOptions options;
    options.format = Format::moments128;
    options.kernel = kernel();
    msmcl::Enqueue blocking;
    blocking.blocking = true;
    msmcl::filter(*context_, msmcl::DeviceDepth{depth_buffer, width, height, 1}, texture_buffer, options, blocking);
    std::vector<std::uint32_t> words(texture_bytes / 4);
    ASSERT_EQ(clEnqueueReadBuffer(context_->cl_queue_handle(), texture_buffer, CL_TRUE, 0, texture_bytes, words.data(),
                                  0, nullptr, nullptr),
              CL_SUCCESS);
    EXPECT_EQ(words, with_kernel(tame, Format::moments128).words);
    clReleaseMemObject(texture_buffer);
    clReleaseMemObject(depth_buffer);
}

// `automatic` picks the CPU distribution on a device that is a CPU and not a GPU (the nlq
// codes tell the kernels apart: each shifts by the depth midrange of its own blocks) and the
// paper's kernel elsewhere (docs/oclgrind.md); msm64 has no shift, so any choice gives the
// paper kernel's texture.
TEST_F(Filter, AutomaticPicksTheDistributionOfTheDeviceType) {
    const DepthImage small = make_depth(70, 50, 4, DepthRange::zero_one, test_seed() + 31);
    EXPECT_EQ(run(small, Format::msm64, 2.4f, DepthRange::zero_one, FilterKernel::automatic).words,
              run(small, Format::msm64).words);
    const DepthImage depth = make_depth(300, 200, 4, DepthRange::zero_one, test_seed() + 31);
    const Texture automatic = run(depth, Format::nlq64, 2.4f, DepthRange::zero_one, FilterKernel::automatic);
    const bool cpu_only = context_->device().is_cpu && !context_->device().is_gpu;
    const FilterKernel expected = cpu_only ? FilterKernel::fused_cpu : FilterKernel::fused_paper;
    EXPECT_EQ(msmcl::filter_kernel_for(*context_, FilterKernel::automatic), expected);
    EXPECT_EQ(automatic.words, run(depth, Format::nlq64, 2.4f, DepthRange::zero_one, expected).words);
    if (cpu_only)
        EXPECT_NE(automatic.words, run(depth, Format::nlq64, 2.4f, DepthRange::zero_one, FilterKernel::fused_paper).words);
}

// The CPU tile size is a tuning parameter (MSMCL_CPU_TILE): other tilings, one of them as
// narrow as the guard band and one row high, give the same texture.
TEST_F(Filter, OtherCpuTilingsGiveTheSameTexture) {
    const DepthImage depth = make_depth(203, 77, 4, DepthRange::zero_one, test_seed() + 29);
    const Texture standard = run(depth, Format::msm64, 2.4f, DepthRange::zero_one, FilterKernel::fused_cpu);
    for (const char* tiling : {"8x1", "40x7"}) {
        const Texture other = [&] {
            const ScopedEnvironment tile("MSMCL_CPU_TILE", tiling);
            return run(depth, Format::msm64, 2.4f, DepthRange::zero_one, FilterKernel::fused_cpu);
        }();
        EXPECT_EQ(other.words, standard.words) << "tiling " << tiling;
    }
    EXPECT_EQ(standard.words, run(depth, Format::msm64, 2.4f, DepthRange::zero_one, FilterKernel::three_pass).words);
}

// A host call given a StageObserver reports its stages in order (what the CLI's --verbose
// prints) and returns the texels it returns untimed.
TEST_F(Filter, StageObserverSeesEachStageAndChangesNoTexel) {
    const DepthImage depth = make_depth(70, 50, 4, DepthRange::zero_one, test_seed() + 37);
    msmcl::FilterOptions options;
    options.format = Format::nlq64;
    std::vector<std::string> stages;
    options.on_stage = [&](const msmcl::StageTime& time) { stages.push_back(time.stage); };
    const Texture timed = msmcl::filter(*context_, depth, options);
    EXPECT_EQ(stages, (std::vector<std::string>{"upload", "program", "kernel", "download"}));
    options.on_stage = nullptr;
    EXPECT_EQ(timed.words, msmcl::filter(*context_, depth, options).words);
}

// The host checks devices against the local memory the fused kernels allocate: for every
// program variant of the covering set, the host's figure (kernels/fused_layout.clh,
// fused_cpu_layout.clh) equals what the built kernel reports.
TEST_F(Filter, HostLocalMemoryFigureIsTheKernels) {
    std::size_t checked = 0;
    for (const msmcl::detail::KernelVariant& variant : msmcl::detail::kernel_variants()) {
        if (variant.local_bytes == 0) continue;
        for (const msmcl::detail::KernelVariant::Kernel& kernel : variant.kernels) {
            cl::Kernel& built = context_->impl().kernel(variant.file, variant.defines, kernel.name);
            EXPECT_EQ(built.getWorkGroupInfo<CL_KERNEL_LOCAL_MEM_SIZE>(context_->impl().device), variant.local_bytes)
                << kernel.name << " " << variant.note;
            ++checked;
        }
    }
    EXPECT_GT(checked, 0u);
}

// The paper's kernel in smaller groups (MSMCL_FUSED_WORK_ITEMS: each work-item plays 2, 4 or
// 8 of the 256 roles, what a device allowing fewer work-items gets) gives the same texels.
TEST_F(Filter, SmallerFusedGroupsGiveTheSameTexture) {
    const DepthImage depth = make_depth(75, 53, 4, DepthRange::zero_one, test_seed() + 37);
    for (Format format : msmcl::detail::filter_formats()) {
        const Texture standard = run(depth, format, 2.4f, DepthRange::zero_one, FilterKernel::fused_paper);
        for (const char* work_items : {"128", "64", "32"}) {
            const Texture smaller = [&] {
                const ScopedEnvironment group("MSMCL_FUSED_WORK_ITEMS", work_items);
                return run(depth, format, 2.4f, DepthRange::zero_one, FilterKernel::fused_paper);
            }();
            EXPECT_EQ(smaller.words, standard.words) << msmcl::format_name(format) << ", " << work_items << " work-items";
        }
    }
}

} // namespace
