// filter on the OpenCL device (PoCL in CI) against the double-precision reference
// (host/reference/filter_reference.*): resolve + blur, every format, fused == three-pass,
// sizes, sample counts, depth ranges, sigmas, bad inputs, device path == host path.
#include "filter_fixtures.hpp"

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

using namespace filter_fixtures;
namespace ref = msmcl::reference;
using msmcl::DepthImage;
using msmcl::DepthRange;
using msmcl::FilterKernel;
using msmcl::Format;
using msmcl::Texture;

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

TEST_F(Filter, Moments128MatchesReferenceAtEverySize) {
    const std::array<std::array<int, 2>, 8> sizes{{{1, 1}, {31, 23}, {33, 25}, {32, 24}, {1000, 1}, {1, 1000}, {65, 49}, {7, 300}}};
    for (const auto& [width, height] : sizes) {
        const DepthImage depth = make_depth(width, height, 4, DepthRange::zero_one, test_seed() + width * 7 + height);
        const Texture texture = run(depth, Format::moments128);
        expect_moments_close(texture, ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4),
                             kMomentTolerance, std::to_string(width) + "x" + std::to_string(height));
    }
}

TEST_F(Filter, Moments128MatchesReferenceForEverySampleCount) {
    for (int samples : {1, 2, 4, 8, 16}) {
        const DepthImage depth = make_depth(70, 50, samples, DepthRange::zero_one, test_seed() + samples);
        const Texture texture = run(depth, Format::moments128);
        expect_moments_close(texture, ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4),
                             kMomentTolerance, std::to_string(samples) + " samples");
    }
}

TEST_F(Filter, Moments128MatchesReferenceForEverySigma) {
    const DepthImage depth = make_depth(70, 50, 4, DepthRange::zero_one, test_seed() + 11);
    for (float sigma : {0.0f, 1.0f, 2.4f, 4.0f}) {
        const Texture texture = run(depth, Format::moments128, sigma);
        expect_moments_close(texture, ref::filter_moments(to_reference(depth, DepthRange::zero_one), sigma),
                             kMomentTolerance, "sigma " + std::to_string(sigma));
    }
    // sigma 0 is the plain resolve.
    const Texture unblurred = run(depth, Format::moments128, 0.0f);
    expect_moments_close(unblurred, ref::resolve(to_reference(depth, DepthRange::zero_one)), kMomentTolerance,
                         "resolve");
}

TEST_F(Filter, Moments128MatchesReferenceForTheMinusOneOneRange) {
    const DepthImage depth = make_depth(70, 50, 4, DepthRange::minus_one_one, test_seed() + 13);
    const Texture texture = run(depth, Format::moments128, 2.4f, DepthRange::minus_one_one);
    expect_moments_close(texture, ref::filter_moments(to_reference(depth, DepthRange::minus_one_one), 2.4),
                         kMomentTolerance, "depth range -1,1");
}

TEST_F(Filter, Msm64CodesMatchTheReferenceMomentsEncodedInDouble) {
    const DepthImage depth = make_depth(200, 150, 4, DepthRange::zero_one, test_seed() + 17);
    const Texture texture = run(depth, Format::msm64);
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
    std::cout << "msm64: " << exact_texels << " of " << texels << " texels exact, " << beyond_one
              << " off by more than one code, worst " << worst << "\n";
    // Within one code for at least 99.9% of the texels.
    EXPECT_LE(double(beyond_one), 0.001 * texels) << "seed " << test_seed();
}

TEST_F(Filter, NlqFormatsRebuildTheReferenceMoments) {
    const DepthImage depth = make_depth(200, 150, 4, DepthRange::zero_one, test_seed() + 19);
    const std::vector<ref::Moments> expected = ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4);
    for (FilterKernel kernel : {FilterKernel::fused_paper, FilterKernel::three_pass}) {
        const std::string name = kernel == FilterKernel::fused_paper ? "fused" : "three-pass";
        check_nlq_against_reference(run(depth, Format::nlq64, 2.4f, DepthRange::zero_one, kernel), depth, kernel,
                                    expected, "nlq64 " + name);
        check_nlq_against_reference(run(depth, Format::nlq32, 2.4f, DepthRange::zero_one, kernel), depth, kernel,
                                    expected, "nlq32 " + name);
    }
}

TEST_F(Filter, FusedEqualsThreePass) {
    const DepthImage depth = make_depth(200, 150, 4, DepthRange::zero_one, test_seed() + 23);
    // moments128 and msm64 (no shift): bit for bit.
    for (Format format : {Format::moments128, Format::msm64}) {
        const Texture fused = run(depth, format);
        const Texture three = run(depth, format, 2.4f, DepthRange::zero_one, FilterKernel::three_pass);
        EXPECT_EQ(fused.words, three.words) << msmcl::format_name(format);
    }
    // nlq: the fused kernel shifts by the block's depth midrange; codes equal or off by one
    // where both kernels' frames are well conditioned.
    const std::vector<ref::Moments> expected = ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4);
    const KernelShift shift(depth, DepthRange::zero_one, FilterKernel::fused_paper);
    for (Format format : {Format::nlq64, Format::nlq32}) {
        const Texture fused = run(depth, format);
        const Texture three = run(depth, format, 2.4f, DepthRange::zero_one, FilterKernel::three_pass);
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
                    EXPECT_LE(std::abs(a[k] - b[k]), 1) << msmcl::format_name(format) << " " << at(x, y) << " field " << k;
                }
            }
        std::cout << msmcl::format_name(format) << " fused vs three-pass: " << equal << " of " << compared
                  << " well-conditioned codes equal\n";
        EXPECT_GT(compared, std::size_t(depth.width) * depth.height / 4);
    }
}

// Far from z = 0, b2 - b1^2 cancels in float32 (docs/math.md, Float32 guard); the
// fused kernel's per-block shift keeps Algorithm 2 accurate there.
TEST_F(Filter, FusedShiftKeepsFlatFarRegionsAccurate) {
    DepthImage depth;
    depth.width = 96, depth.height = 72, depth.samples = 4;
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x)
            for (int s = 0; s < 4; ++s)
                depth.depth.push_back(0.93f + 0.004f * std::sin(0.3f * (x + 0.25f * s) + float(test_seed() % 7)) *
                                                  std::cos(0.2f * y));
    const std::vector<ref::Moments> expected = ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4);
    std::size_t texels = 0, fused_close = 0, three_close = 0;
    const Texture fused = run(depth, Format::nlq64);
    const Texture three = run(depth, Format::nlq64, 2.4f, DepthRange::zero_one, FilterKernel::three_pass);
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
    std::cout << "flat far region, nlq64 codes within one of double Algorithm 2: fused " << fused_close << ", three-pass "
              << three_close << " of " << texels << "\n";
    // The unshifted three-pass baseline gets few or none of these right; the fused kernel
    // practically all.
    EXPECT_GE(fused_close, texels * 99 / 100) << "seed " << test_seed();
    EXPECT_GE(fused_close, three_close);
}

TEST_F(Filter, FusedEqualsThreePassAtOddSizes) {
    const std::array<std::array<int, 2>, 5> sizes{{{1, 1}, {31, 23}, {33, 25}, {1000, 1}, {1, 1000}}};
    for (const auto& [width, height] : sizes) {
        const DepthImage depth = make_depth(width, height, 4, DepthRange::zero_one, test_seed() + 29 + width);
        EXPECT_EQ(run(depth, Format::moments128).words,
                  run(depth, Format::moments128, 2.4f, DepthRange::zero_one, FilterKernel::three_pass).words)
            << width << "x" << height;
    }
}

TEST_F(Filter, AutomaticPicksAKernelThatGivesTheSameTexture) {
    const DepthImage depth = make_depth(70, 50, 4, DepthRange::zero_one, test_seed() + 31);
    EXPECT_EQ(run(depth, Format::msm64, 2.4f, DepthRange::zero_one, FilterKernel::automatic).words,
              run(depth, Format::msm64).words);
}

TEST_F(Filter, LargeMap2048) {
    const DepthImage depth = make_depth(2048, 2048, 4, DepthRange::zero_one, test_seed() + 37);
    const Texture fused = run(depth, Format::moments128);
    const Texture three = run(depth, Format::moments128, 2.4f, DepthRange::zero_one, FilterKernel::three_pass);
    EXPECT_EQ(fused.words, three.words);
    // Spot checks against the direct 9x9 reference: block corners, image borders, random texels.
    const ref::DepthMap map = to_reference(depth, DepthRange::zero_one);
    std::mt19937 random(test_seed());
    std::vector<std::array<int, 2>> texels{{0, 0}, {2047, 2047}, {0, 2047}, {2047, 0}, {31, 23}, {32, 24}, {2047, 1000}};
    for (int i = 0; i < 400; ++i) texels.push_back({int(random() % 2048), int(random() % 2048)});
    for (const auto& [x, y] : texels) {
        const ref::Moments expected = ref::filter_moments_at(map, 2.4, x, y);
        for (int j = 1; j <= 4; ++j)
            EXPECT_NEAR(fused.moment(x, y, j), ref::moment(expected, j), kMomentTolerance) << at(x, y) << " b" << j;
    }
}

TEST_F(Filter, BadInputsThrowInputError) {
    const DepthImage good = make_depth(8, 6, 2, DepthRange::zero_one, test_seed());
    msmcl::FilterOptions options;
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

// Device path with caller-owned buffers, a wait list and a done event, vs the host path.
TEST_F(Filter, DevicePathEqualsHostPath) {
    const DepthImage depth = make_depth(100, 70, 4, DepthRange::zero_one, test_seed() + 41);
    cl_context cl_ctx = context_->cl_context_handle();
    cl_int status = CL_SUCCESS;
    // The caller's own queue, distinct from the Context's.
    cl_command_queue queue = clCreateCommandQueue(cl_ctx, context_->cl_device_handle(), 0, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    const std::size_t depth_bytes = depth.depth.size() * sizeof(float);
    cl_mem depth_buffer = clCreateBuffer(cl_ctx, CL_MEM_READ_ONLY, depth_bytes, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    for (Format format : {Format::nlq64, Format::moments128}) {
        for (FilterKernel kernel : {FilterKernel::fused_paper, FilterKernel::three_pass}) {
            const std::size_t texture_bytes = std::size_t(depth.width) * depth.height * msmcl::texel_bytes(format);
            cl_mem texture_buffer = clCreateBuffer(cl_ctx, CL_MEM_WRITE_ONLY, texture_bytes, nullptr, &status);
            ASSERT_EQ(status, CL_SUCCESS);
            cl_event uploaded = nullptr, filtered = nullptr;
            ASSERT_EQ(clEnqueueWriteBuffer(queue, depth_buffer, CL_FALSE, 0, depth_bytes, depth.depth.data(), 0,
                                           nullptr, &uploaded),
                      CL_SUCCESS);
            msmcl::FilterOptions options;
            options.format = format;
            options.kernel = kernel;
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
            EXPECT_EQ(words, run(depth, format, 2.4f, DepthRange::zero_one, kernel).words)
                << msmcl::format_name(format);
            clReleaseEvent(uploaded);
            clReleaseEvent(filtered);
            clReleaseMemObject(texture_buffer);
        }
    }
    // The Context's own queue, blocking, no events.
    const std::size_t texture_bytes = std::size_t(depth.width) * depth.height * 8;
    cl_mem texture_buffer = clCreateBuffer(cl_ctx, CL_MEM_READ_WRITE, texture_bytes, nullptr, &status);
    ASSERT_EQ(clEnqueueWriteBuffer(queue, depth_buffer, CL_TRUE, 0, depth_bytes, depth.depth.data(), 0, nullptr, nullptr),
              CL_SUCCESS);
    msmcl::FilterOptions options;
    options.format = Format::msm64;
    msmcl::Enqueue blocking;
    blocking.blocking = true;
    msmcl::filter(*context_, msmcl::DeviceDepth{depth_buffer, depth.width, depth.height, depth.samples}, texture_buffer,
                  options, blocking);
    std::vector<std::uint32_t> words(texture_bytes / 4);
    ASSERT_EQ(clEnqueueReadBuffer(queue, texture_buffer, CL_TRUE, 0, texture_bytes, words.data(), 0, nullptr, nullptr),
              CL_SUCCESS);
    EXPECT_EQ(words, run(depth, Format::msm64).words);
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

// Device depth is not validated: out-of-range values clamp to the range, NaN is the near plane.
TEST_F(Filter, DevicePathClampsOutOfRangeDepth) {
    DepthImage wild = make_depth(40, 30, 1, DepthRange::zero_one, test_seed() + 43);
    DepthImage tame = wild;
    wild.depth[10] = 7.0f, tame.depth[10] = 1.0f;
    wild.depth[100] = -3.0f, tame.depth[100] = 0.0f;
    wild.depth[500] = std::nanf(""), tame.depth[500] = 0.0f;
    wild.depth[700] = -std::numeric_limits<float>::infinity(), tame.depth[700] = 0.0f;
    cl_int status = CL_SUCCESS;
    cl_mem depth_buffer = clCreateBuffer(context_->cl_context_handle(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                         wild.depth.size() * 4, wild.depth.data(), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    const std::size_t texture_bytes = 40 * 30 * 16;
    cl_mem texture_buffer = clCreateBuffer(context_->cl_context_handle(), CL_MEM_WRITE_ONLY, texture_bytes, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    msmcl::FilterOptions options;
    options.format = Format::moments128;
    msmcl::Enqueue blocking;
    blocking.blocking = true;
    msmcl::filter(*context_, msmcl::DeviceDepth{depth_buffer, 40, 30, 1}, texture_buffer, options, blocking);
    std::vector<std::uint32_t> words(texture_bytes / 4);
    ASSERT_EQ(clEnqueueReadBuffer(context_->cl_queue_handle(), texture_buffer, CL_TRUE, 0, texture_bytes, words.data(),
                                  0, nullptr, nullptr),
              CL_SUCCESS);
    EXPECT_EQ(words, run(tame, Format::moments128).words);
    clReleaseMemObject(texture_buffer);
    clReleaseMemObject(depth_buffer);
}

} // namespace
