// The CPU work distribution of the fused filter (kernels/filter_fused_cpu.cl,
// FilterKernel::fused_cpu) against the same double-precision reference as the paper's
// kernel (tests/filter_test.cpp), bit for bit equal to three-pass for moments128 and
// msm64, the nlq formats within their quantization of the reference, tile borders and
// odd sizes, other tilings, the choice of `automatic` on a CPU device, the device path.
#include "filter_fixtures.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

using namespace filter_fixtures;
using msmcl::DepthImage;
using msmcl::DepthRange;
using msmcl::FilterKernel;
using msmcl::Format;
using msmcl::Texture;

class FilterCpu : public FilterTest {
protected:
    static Texture cpu(const DepthImage& depth, Format format, float sigma = 2.4f,
                       DepthRange range = DepthRange::zero_one) {
        return run(depth, format, sigma, range, FilterKernel::fused_cpu);
    }
    static Texture three_pass(const DepthImage& depth, Format format, float sigma = 2.4f,
                              DepthRange range = DepthRange::zero_one) {
        return run(depth, format, sigma, range, FilterKernel::three_pass);
    }
};

std::string size_name(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

// Sizes around the default 128x64 tile and its 4-texel guard band: a single texel, less
// than a tile, exactly one tile, one more, more than the guard band past a tile, tall and
// wide strips, and maps with interior tiles (guard band inside the image) between border
// tiles on both sides.
const std::vector<std::array<int, 2>>& odd_sizes() {
    static const std::vector<std::array<int, 2>> sizes{{1, 1},     {7, 5},    {128, 64},  {129, 65},  {132, 68},
                                                        {1000, 1}, {1, 300},  {300, 200}, {397, 131}, {520, 70},
                                                        {264, 9}};
    return sizes;
}

TEST_F(FilterCpu, Moments128MatchesReferenceAtEverySize) {
    for (const auto& [width, height] : odd_sizes()) {
        const DepthImage depth = make_depth(width, height, 4, DepthRange::zero_one, test_seed() + width * 7 + height);
        expect_moments_close(cpu(depth, Format::moments128),
                             ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4), kMomentTolerance,
                             size_name(width, height));
    }
}

TEST_F(FilterCpu, Moments128AndMsm64EqualThreePassBitForBit) {
    for (const auto& [width, height] : odd_sizes()) {
        const DepthImage depth = make_depth(width, height, 4, DepthRange::zero_one, test_seed() + 3 + width + height);
        for (Format format : {Format::moments128, Format::msm64})
            EXPECT_EQ(cpu(depth, format).words, three_pass(depth, format).words)
                << size_name(width, height) << " " << msmcl::format_name(format);
    }
}

TEST_F(FilterCpu, EverySampleCountSigmaAndDepthRange) {
    for (int samples : {1, 2, 4, 8, 16}) {
        const DepthImage depth = make_depth(150, 80, samples, DepthRange::zero_one, test_seed() + samples);
        expect_moments_close(cpu(depth, Format::moments128),
                             ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4), kMomentTolerance,
                             std::to_string(samples) + " samples");
    }
    const DepthImage depth = make_depth(150, 80, 4, DepthRange::zero_one, test_seed() + 11);
    for (float sigma : {0.0f, 1.0f, 4.0f}) {
        expect_moments_close(cpu(depth, Format::moments128, sigma),
                             ref::filter_moments(to_reference(depth, DepthRange::zero_one), sigma), kMomentTolerance,
                             "sigma " + std::to_string(sigma));
    }
    const DepthImage gl = make_depth(150, 80, 4, DepthRange::minus_one_one, test_seed() + 13);
    expect_moments_close(cpu(gl, Format::moments128, 2.4f, DepthRange::minus_one_one),
                         ref::filter_moments(to_reference(gl, DepthRange::minus_one_one), 2.4), kMomentTolerance,
                         "depth range -1,1");
}

// The nlq formats: moments rebuilt from the decoded texels within the quantization of the
// reference, codes within one of double Algorithm 2 in the kernel's (tile-shifted) frame.
TEST_F(FilterCpu, NlqFormatsRebuildTheReferenceMoments) {
    for (const auto& [width, height] : std::vector<std::array<int, 2>>{{300, 200}, {129, 65}}) {
        const DepthImage depth = make_depth(width, height, 4, DepthRange::zero_one, test_seed() + 19 + width);
        const std::vector<ref::Moments> expected = ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4);
        check_nlq_against_reference(cpu(depth, Format::nlq64), depth, FilterKernel::fused_cpu, expected,
                                    "nlq64 fused_cpu " + size_name(width, height));
        check_nlq_against_reference(cpu(depth, Format::nlq32), depth, FilterKernel::fused_cpu, expected,
                                    "nlq32 fused_cpu " + size_name(width, height));
    }
}

// Where both frames are well conditioned, the CPU distribution's codes equal three-pass's
// or are one step away (the shifts differ).
TEST_F(FilterCpu, NlqCodesAgreeWithThreePass) {
    const DepthImage depth = make_depth(300, 200, 4, DepthRange::zero_one, test_seed() + 23);
    const std::vector<ref::Moments> expected = ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4);
    const KernelShift shift(depth, DepthRange::zero_one, FilterKernel::fused_cpu);
    for (Format format : {Format::nlq64, Format::nlq32}) {
        const Texture fused = cpu(depth, format);
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
        std::cout << msmcl::format_name(format) << " fused_cpu vs three-pass: " << equal << " of " << compared
                  << " well-conditioned codes equal\n";
        // Something to compare (nlq64's unshifted three-pass frame is ill-conditioned in
        // most texels of this map).
        EXPECT_GT(compared, std::size_t(depth.width) * depth.height / 8);
    }
}

// Far from z = 0 the unshifted Algorithm 2 loses its precision to cancellation
// (docs/math.md, the float32 guard); the per-tile shift keeps the CPU distribution as accurate as the paper's
// kernel with its per-block shift.
TEST_F(FilterCpu, TileShiftKeepsFlatFarRegionsAccurate) {
    DepthImage depth;
    depth.width = 300, depth.height = 140, depth.samples = 4;
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x)
            for (int s = 0; s < 4; ++s)
                depth.depth.push_back(0.93f + 0.004f * std::sin(0.3f * (x + 0.25f * s) + float(test_seed() % 7)) *
                                                  std::cos(0.2f * y));
    const std::vector<ref::Moments> expected = ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4);
    const Texture fused = cpu(depth, Format::nlq64);
    std::size_t texels = 0, close = 0;
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x) {
            const ref::Moments biased = ref::bias(expected[std::size_t(y) * depth.width + x], 3e-7, 0.375);
            const ref::Codes16 want = ref::encode_nlq64(algorithm2_shifted(biased, 0.0));
            bool within_one = true;
            for (int c = 0; c < 4; ++c) within_one &= std::abs(int(fused.code16(x, y, c)) - int(want[c])) <= 1;
            ++texels;
            close += within_one;
        }
    std::cout << "flat far region, nlq64 codes within one of double Algorithm 2: " << close << " of " << texels << "\n";
    EXPECT_GE(close, texels * 99 / 100) << "seed " << test_seed();
}

// The tile size is a tuning parameter (MSMCL_CPU_TILE): other tilings, one of them as
// narrow as the guard band and one row high, give the same texture.
TEST_F(FilterCpu, OtherTilingsGiveTheSameTexture) {
    const DepthImage depth = make_depth(203, 77, 4, DepthRange::zero_one, test_seed() + 29);
    const Texture standard = cpu(depth, Format::msm64);
    for (const char* tiling : {"8x1", "40x7"}) {
        setenv("MSMCL_CPU_TILE", tiling, 1);
        const Texture other = cpu(depth, Format::msm64);
        unsetenv("MSMCL_CPU_TILE");
        EXPECT_EQ(other.words, standard.words) << "tiling " << tiling;
    }
    EXPECT_EQ(standard.words, three_pass(depth, Format::msm64).words);
}

// `automatic` picks the CPU distribution on a device that is a CPU and not a GPU (the nlq
// codes tell the kernels apart: each shifts by the depth midrange of its own blocks) and the
// paper's kernel elsewhere (docs/oclgrind.md).
TEST_F(FilterCpu, AutomaticPicksTheDistributionOfTheDeviceType) {
    const DepthImage depth = make_depth(300, 200, 4, DepthRange::zero_one, test_seed() + 31);
    const Texture automatic = run(depth, Format::nlq64, 2.4f, DepthRange::zero_one, FilterKernel::automatic);
    const bool cpu_only = context_->device().is_cpu && !context_->device().is_gpu;
    const FilterKernel expected = cpu_only ? FilterKernel::fused_cpu : FilterKernel::fused_paper;
    EXPECT_EQ(msmcl::filter_kernel_for(*context_, FilterKernel::automatic), expected);
    EXPECT_EQ(automatic.words, run(depth, Format::nlq64, 2.4f, DepthRange::zero_one, expected).words);
    if (cpu_only)
        EXPECT_NE(automatic.words, run(depth, Format::nlq64, 2.4f, DepthRange::zero_one, FilterKernel::fused_paper).words);
}

TEST_F(FilterCpu, LargeMapEqualsThreePass) {
    const DepthImage depth = make_depth(1100, 700, 4, DepthRange::zero_one, test_seed() + 37);
    EXPECT_EQ(cpu(depth, Format::moments128).words, three_pass(depth, Format::moments128).words);
}

// Caller-owned buffers, the caller's queue, a wait list and a done event.
TEST_F(FilterCpu, DevicePathEqualsHostPath) {
    const DepthImage depth = make_depth(260, 90, 4, DepthRange::zero_one, test_seed() + 41);
    cl_context cl_ctx = context_->cl_context_handle();
    cl_int status = CL_SUCCESS;
    cl_command_queue queue = clCreateCommandQueue(cl_ctx, context_->cl_device_handle(), 0, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    const std::size_t depth_bytes = depth.depth.size() * sizeof(float);
    cl_mem depth_buffer = clCreateBuffer(cl_ctx, CL_MEM_READ_ONLY, depth_bytes, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    for (Format format : {Format::nlq32, Format::moments128}) {
        const std::size_t texture_bytes = std::size_t(depth.width) * depth.height * msmcl::texel_bytes(format);
        cl_mem texture_buffer = clCreateBuffer(cl_ctx, CL_MEM_WRITE_ONLY, texture_bytes, nullptr, &status);
        ASSERT_EQ(status, CL_SUCCESS);
        cl_event uploaded = nullptr, filtered = nullptr;
        ASSERT_EQ(clEnqueueWriteBuffer(queue, depth_buffer, CL_FALSE, 0, depth_bytes, depth.depth.data(), 0, nullptr,
                                       &uploaded),
                  CL_SUCCESS);
        msmcl::FilterOptions options;
        options.format = format;
        options.kernel = FilterKernel::fused_cpu;
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
        EXPECT_EQ(words, cpu(depth, format).words) << msmcl::format_name(format);
        clReleaseEvent(uploaded);
        clReleaseEvent(filtered);
        clReleaseMemObject(texture_buffer);
    }
    clReleaseMemObject(depth_buffer);
    clReleaseCommandQueue(queue);
}

// Device depth is not validated: out-of-range values clamp to the range, NaN is the near
// plane, in the interior and the border tiles alike.
TEST_F(FilterCpu, DevicePathClampsOutOfRangeDepth) {
    DepthImage wild = make_depth(300, 70, 1, DepthRange::zero_one, test_seed() + 43);
    DepthImage tame = wild;
    for (std::size_t i : {std::size_t(0), std::size_t(150 * 70 + 35), std::size_t(299 + 300 * 69), std::size_t(4000)}) {
        wild.depth[i] = i % 2 ? 7.0f : std::nanf("");
        tame.depth[i] = i % 2 ? 1.0f : 0.0f;
    }
    wild.depth[5000] = -std::numeric_limits<float>::infinity(), tame.depth[5000] = 0.0f;
    cl_int status = CL_SUCCESS;
    cl_mem depth_buffer = clCreateBuffer(context_->cl_context_handle(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                         wild.depth.size() * 4, wild.depth.data(), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    const std::size_t texture_bytes = std::size_t(300) * 70 * 16;
    cl_mem texture_buffer =
        clCreateBuffer(context_->cl_context_handle(), CL_MEM_WRITE_ONLY, texture_bytes, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    msmcl::FilterOptions options;
    options.format = Format::moments128;
    options.kernel = FilterKernel::fused_cpu;
    msmcl::Enqueue blocking;
    blocking.blocking = true;
    msmcl::filter(*context_, msmcl::DeviceDepth{depth_buffer, 300, 70, 1}, texture_buffer, options, blocking);
    std::vector<std::uint32_t> words(texture_bytes / 4);
    ASSERT_EQ(clEnqueueReadBuffer(context_->cl_queue_handle(), texture_buffer, CL_TRUE, 0, texture_bytes, words.data(),
                                  0, nullptr, nullptr),
              CL_SUCCESS);
    EXPECT_EQ(words, cpu(tame, Format::moments128).words);
    clReleaseMemObject(texture_buffer);
    clReleaseMemObject(depth_buffer);
}

} // namespace
