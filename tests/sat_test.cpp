// Integer modular summed-area tables on the OpenCL device (PoCL in CI) against the
// independent 64-bit references of host/reference/sat_reference.*: whole tables, every
// rectangle of at most N texels on small maps, sampled rectangles on 2048^2, tables that wrap
// many times, quantization of depth maps, interpolated queries against area-weighted
// integrals, the tiled scan == the one-thread-per-row baseline, EXR round trip, bad input.
#include "reference/sat_reference.hpp"

#include "io/exr_io.hpp"
#include "io/sat_exr.hpp"
#include "kernels/msm_sat.clh"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/sat.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "seeded_test.hpp"

namespace {

namespace ref = msmcl::reference;
using msmcl::DepthImage;
using msmcl::DepthRange;
using msmcl::SatKernel;
using msmcl::SatTable;

class SatTest : public msmcl::testing::DeviceSuite<SatTest> {};

// Random integer texels in [0, max_value].
ref::SatTexels random_texels(int width, int height, std::uint32_t max_value, std::mt19937& rng) {
    ref::SatTexels t;
    t.width = width;
    t.height = height;
    std::uniform_int_distribution<std::uint32_t> value(0, max_value);
    t.values.resize(4 * static_cast<std::size_t>(width) * height);
    for (std::uint32_t& v : t.values) v = value(rng);
    return t;
}

SatTable table_of(const std::vector<std::uint32_t>& words, int width, int height, std::uint32_t n) {
    SatTable table;
    table.width = width;
    table.height = height;
    table.max_kernel_texels = n;
    table.scale = ref::sat_scale(n);
    table.words = words;
    return table;
}

// Index of the first differing word, or -1.
long long first_difference(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
    if (a.size() != b.size()) return 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i] != b[i]) return static_cast<long long>(i);
    return -1;
}

// Every rectangle of at most N texels: the table query equals the direct 64-bit sum. Sums
// grow one row at a time per (x0, y0, width), so the direct sums cost O(texels * N).
// Returns the number of rectangles checked.
long long check_all_rectangles(const SatTable& table, const ref::SatTexels& texels, std::uint32_t n) {
    long long checked = 0;
    for (int y0 = 0; y0 < texels.height; ++y0)
        for (int x0 = 0; x0 < texels.width; ++x0)
            for (int w = 1; x0 + w <= texels.width && static_cast<std::uint32_t>(w) <= n; ++w) {
                std::array<std::uint64_t, 4> direct{0, 0, 0, 0};
                for (int h = 1; y0 + h <= texels.height && static_cast<std::uint64_t>(w) * h <= n; ++h) {
                    for (int x = x0; x < x0 + w; ++x)
                        for (int c = 0; c < 4; ++c) direct[c] += texels.at(x, y0 + h - 1, c);
                    const auto sum = msmcl::sat_rectangle_sum(table, x0, y0, x0 + w - 1, y0 + h - 1);
                    for (int c = 0; c < 4; ++c)
                        if (sum[c] != direct[c]) {
                            ADD_FAILURE() << "rectangle x " << x0 << ".." << x0 + w - 1 << " y " << y0 << ".."
                                          << y0 + h - 1 << " channel " << c << ": table " << sum[c] << ", direct "
                                          << direct[c];
                            return checked;
                        }
                    ++checked;
                }
            }
    return checked;
}

TEST(SatMath, ScaleIsFloorOfMaxOverN) {
    for (std::uint32_t n : {2u, 3u, 16u, 256u, 729u, 1000u, 65536u, 0x7fffffffu}) {
        EXPECT_EQ(msmcl::sat_scale(n), ref::sat_scale(n)) << "N " << n;
        // N texels of the largest value still fit 32 bits; one more texel would not.
        EXPECT_LE(static_cast<std::uint64_t>(n) * msmcl::sat_scale(n), 0xffffffffull);
        EXPECT_GT(static_cast<std::uint64_t>(n) * (msmcl::sat_scale(n) + 1ull), 0xffffffffull);
    }
    // 27^2 keeps log2(scale) = 22.5 bits (docs/math.md).
    EXPECT_NEAR(std::log2(double(msmcl::sat_scale(729))), 22.49, 0.01);
}

TEST(SatMath, QuantizeRoundsWithinHalfAUnitAndNeverExceedsScale) {
    // msm_sat_quantize(m, scale): one float32 fma, so |q - m scale| <= 1/2 + 2^-24 m scale
    // (exact arithmetic in long double), q <= scale, monotonic in m; NaN and m <= 0 give 0.
    std::mt19937 rng(static_cast<std::uint32_t>(msmcl::testing::run_seed(20160227u)));
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const std::uint32_t scales[] = {2u, 5891588u, 65535u, 0x7fffffffu, 1u << 24, 3u};
    std::vector<float> values = {0.0f, 1.0f, 0.5f, 1e-30f, 1e-45f, std::nextafter(1.0f, 0.0f), 0.25f, 0.75f};
    for (int i = 0; i < 100000; ++i) values.push_back(unit(rng));
    std::sort(values.begin(), values.end());
    for (std::uint32_t scale : scales) {
        std::uint32_t previous = 0;
        for (float m : values) {
            const std::uint32_t q = msm_sat_quantize(m, scale);
            const long double exact = static_cast<long double>(m) * scale;
            ASSERT_LE(std::fabs(static_cast<long double>(q) - exact), 0.5L + exact * 0x1p-24L) << "m " << m << " scale " << scale;
            ASSERT_LE(q, scale);
            ASSERT_GE(q, previous) << "not monotonic at m " << m;
            previous = q;
        }
        EXPECT_EQ(msm_sat_quantize(1.0f, scale), scale);
        EXPECT_EQ(msm_sat_quantize(0.0f, scale), 0u);
    }
    // Clamped outside [0, 1], NaN -> 0; 0.5 * 3 = 1.5 rounds up.
    EXPECT_EQ(msm_sat_quantize(-0.5f, 1000u), 0u);
    EXPECT_EQ(msm_sat_quantize(1.5f, 1000u), 1000u);
    EXPECT_EQ(msm_sat_quantize(std::numeric_limits<float>::quiet_NaN(), 1000u), 0u);
    EXPECT_EQ(msm_sat_quantize(0.5f, 3u), 2u);
}

TEST(SatMath, AffineBasisRoundTripsAndMatchesReference) {
    // msm_sat_basis_of / msm_sat_moments_of_basis against the reference msm64 affine map.
    std::mt19937 rng(static_cast<std::uint32_t>(msmcl::testing::run_seed(20160227u)));
    std::uniform_real_distribution<double> depth(-1.0, 1.0);
    for (int i = 0; i < 1000; ++i) {
        const double z = depth(rng);
        const ref::Moments b = ref::moments_of(z);
        const msm_moments m = {float(b.b1), float(b.b2), float(b.b3), float(b.b4)};
        const msm_sat_basis c = msm_sat_basis_of(m);
        const std::array<double, 4> expected = ref::msm64_affine(b);
        // float32 channels of |coefficient| <= 4 combinations: a few 1e-7.
        EXPECT_NEAR(c.c0, expected[0], 1e-6);
        EXPECT_NEAR(c.c1, expected[1], 1e-6);
        EXPECT_NEAR(c.c2, expected[2], 1e-6);
        EXPECT_NEAR(c.c3, expected[3], 1e-6);
        for (double channel : expected) {
            EXPECT_GE(channel, -1e-12);
            EXPECT_LE(channel, 1 + 1e-12);
        }
        const msm_moments back = msm_sat_moments_of_basis(c);
        EXPECT_NEAR(back.b1, b.b1, 2e-6);
        EXPECT_NEAR(back.b2, b.b2, 2e-6);
        EXPECT_NEAR(back.b3, b.b3, 2e-6);
        EXPECT_NEAR(back.b4, b.b4, 2e-6);
    }
}

TEST_F(SatTest, EveryRectangleUpToNIsExactOnSmallMaps) {
    std::mt19937 rng(seed_);
    struct Case {
        int width, height;
        std::uint32_t n;
    };
    // Sizes below, at and across the 32x32 tiles; N from tiny to larger than the map.
    const Case cases[] = {{1, 1, 2}, {7, 5, 6}, {32, 32, 64}, {33, 31, 49}, {40, 70, 100}, {97, 3, 300},
                          {65, 66, 20}, {5, 129, 2000}};
    for (const Case& c : cases) {
        const std::uint32_t scale = ref::sat_scale(c.n);
        const ref::SatTexels texels = random_texels(c.width, c.height, scale, rng);
        const std::vector<std::uint32_t> expected = ref::prefix_sums(texels);
        for (SatKernel kernel : {SatKernel::tiled_gpu, SatKernel::tiled_cpu, SatKernel::row_per_thread}) {
            const std::vector<std::uint32_t> words =
                msmcl::sat_prefix_sums(context(), texels.values, c.width, c.height, kernel);
            ASSERT_EQ(first_difference(words, expected), -1)
                << c.width << "x" << c.height << " kernel " << static_cast<int>(kernel);
        }
        const SatTable table = table_of(expected, c.width, c.height, c.n);
        const long long checked = check_all_rectangles(table, texels, c.n);
        std::printf("  %dx%d N=%u: %lld rectangles exact\n", c.width, c.height, c.n, checked);
        EXPECT_GT(checked, 0);
    }
}

TEST_F(SatTest, TablesThatWrapManyTimesStayExactModulo2To32) {
    // Full-range texels: every prefix sum wraps thousands of times; the table still equals the
    // 64-bit sums mod 2^32, so every rectangle difference equals its direct sum mod 2^32.
    std::mt19937 rng(seed_ + 1);
    const int width = 150, height = 97;
    const ref::SatTexels texels = random_texels(width, height, 0xffffffffu, rng);
    const std::vector<std::uint32_t> expected = ref::prefix_sums(texels);
    const auto whole = ref::direct_sum(texels, 0, 0, width - 1, height - 1);
    std::printf("  the last table entry wrapped %llu times\n",
                static_cast<unsigned long long>(whole[0] >> 32));
    EXPECT_GT(whole[0] >> 32, 1000u);
    for (SatKernel kernel : {SatKernel::tiled_gpu, SatKernel::tiled_cpu, SatKernel::row_per_thread})
        ASSERT_EQ(first_difference(msmcl::sat_prefix_sums(context(), texels.values, width, height, kernel), expected),
                  -1);
    std::uniform_int_distribution<int> x(0, width - 1), y(0, height - 1);
    for (int i = 0; i < 2000; ++i) {
        int x0 = x(rng), x1 = x(rng), y0 = y(rng), y1 = y(rng);
        if (x0 > x1) std::swap(x0, x1);
        if (y0 > y1) std::swap(y0, y1);
        const msm_sat_sum s = msm_sat_rectangle_sum(expected.data(), width, x0, y0, x1, y1);
        const auto direct = ref::direct_sum(texels, x0, y0, x1, y1);
        ASSERT_EQ(s.c0, static_cast<std::uint32_t>(direct[0]));
        ASSERT_EQ(s.c3, static_cast<std::uint32_t>(direct[3]));
    }
}

TEST_F(SatTest, SampledRectanglesOn2048SquaredAreExact) {
    // The one large table of the suite: 2048^2, N = 27^2, tiled scan.
    std::mt19937 rng(seed_ + 2);
    const int side = 2048;
    const std::uint32_t n = 27 * 27;
    const ref::SatTexels texels = random_texels(side, side, ref::sat_scale(n), rng);
    const std::vector<std::uint32_t> words = msmcl::sat_prefix_sums(context(), texels.values, side, side);
    ASSERT_EQ(first_difference(words, ref::prefix_sums(texels)), -1);
    const SatTable table = table_of(words, side, side, n);
    std::uniform_int_distribution<int> position(0, side - 1), extent(1, 27 * 27);
    int checked = 0;
    for (int i = 0; i < 20000; ++i) {
        // Any shape of at most N texels, including 1 x 729 and 729 x 1.
        const int w = extent(rng);
        const int h = std::max(1, extent(rng) / w);
        const int x0 = std::min(position(rng), side - w), y0 = std::min(position(rng), side - h);
        const auto sum = msmcl::sat_rectangle_sum(table, x0, y0, x0 + w - 1, y0 + h - 1);
        const auto direct = ref::direct_sum(texels, x0, y0, x0 + w - 1, y0 + h - 1);
        for (int c = 0; c < 4; ++c) ASSERT_EQ(sum[c], direct[c]) << "rectangle " << x0 << "," << y0 << " " << w << "x" << h;
        ++checked;
    }
    std::printf("  2048^2, N = 729: %d sampled rectangles exact\n", checked);
}

// A depth map with occluders over a sloped receiver, S samples per texel (a blend of
// smooth regions and depth discontinuities).
DepthImage make_depth(int width, int height, int samples, DepthRange range, std::mt19937& rng) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    DepthImage depth;
    depth.width = width;
    depth.height = height;
    depth.samples = samples;
    const double slope = 0.3 * unit(rng);
    struct Disk {
        double x, y, r, d;
    };
    std::vector<Disk> disks;
    for (int i = 0; i < 6; ++i)
        disks.push_back({unit(rng) * width, unit(rng) * height, 1 + unit(rng) * width / 4.0, unit(rng) * 0.5});
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int s = 0; s < samples; ++s) {
                const double px = x + unit(rng), py = y + unit(rng);
                double d = 0.6 + slope * (px / width - 0.5);
                for (const Disk& disk : disks)
                    if ((px - disk.x) * (px - disk.x) + (py - disk.y) * (py - disk.y) < disk.r * disk.r)
                        d = std::min(d, disk.d);
                depth.depth.push_back(static_cast<float>(range == DepthRange::zero_one ? d : 2 * d - 1));
            }
    return depth;
}

ref::DepthMap reference_map(const DepthImage& depth, DepthRange range) {
    ref::DepthMap map;
    map.width = depth.width;
    map.height = depth.height;
    map.samples = depth.samples;
    map.depth = depth.depth;
    map.zero_one = range == DepthRange::zero_one;
    return map;
}

TEST_F(SatTest, DepthMapsQuantizeLikeTheReference) {
    // Texels recovered from the table by exact 1x1 queries against round(c * scale) of the
    // double-precision channels. Tolerance: the device resolves and transforms in float32
    // (|c_float - c_double| <= 2e-6 for S <= 16: S + 4 roundings of values <= 1 scaled by
    // affine coefficients <= 4), times scale, plus the rounding step itself.
    std::mt19937 rng(seed_ + 3);
    struct Case {
        int width, height, samples;
        DepthRange range;
        std::uint32_t n;
    };
    const Case cases[] = {{45, 37, 1, DepthRange::zero_one, 729},
                          {64, 64, 4, DepthRange::minus_one_one, 2},
                          {70, 33, 16, DepthRange::zero_one, 81},
                          {31, 90, 8, DepthRange::minus_one_one, 10000},
                          {96, 40, 2, DepthRange::zero_one, 65536}};
    for (const Case& c : cases) {
        const DepthImage depth = make_depth(c.width, c.height, c.samples, c.range, rng);
        msmcl::SatOptions options;
        options.max_kernel_texels = c.n;
        options.depth_range = c.range;
        options.kernel = SatKernel::tiled_gpu;
        const SatTable tiled = msmcl::build_sat(context(), depth, options);
        options.kernel = SatKernel::tiled_cpu;
        const SatTable vectors = msmcl::build_sat(context(), depth, options);
        options.kernel = SatKernel::row_per_thread;
        const SatTable rows = msmcl::build_sat(context(), depth, options);
        ASSERT_EQ(first_difference(tiled.words, rows.words), -1) << "tiled_gpu != one thread per row";
        ASSERT_EQ(first_difference(vectors.words, rows.words), -1) << "tiled_cpu != one thread per row";
        ASSERT_EQ(tiled.scale, ref::sat_scale(c.n));

        const std::vector<double> channels = ref::affine_channels(reference_map(depth, c.range));
        const double tolerance = 2e-6 * tiled.scale + 1.0;
        double worst = 0;
        for (int y = 0; y < c.height; ++y)
            for (int x = 0; x < c.width; ++x) {
                const auto texel = msmcl::sat_rectangle_sum(tiled, x, y, x, y);
                for (int ch = 0; ch < 4; ++ch) {
                    const double expected = channels[4 * (static_cast<std::size_t>(y) * c.width + x) + ch] * tiled.scale;
                    worst = std::max(worst, std::fabs(texel[ch] - expected));
                }
            }
        std::printf("  %dx%d S=%d N=%u: worst texel error %.3f units (tolerance %.1f)\n", c.width, c.height, c.samples,
                    c.n, worst, tolerance);
        EXPECT_LE(worst, tolerance);
    }
}

TEST_F(SatTest, DevicePathEqualsHostPath) {
    std::mt19937 rng(seed_ + 4);
    const DepthImage depth = make_depth(77, 50, 4, DepthRange::zero_one, rng);
    msmcl::SatOptions options;
    options.max_kernel_texels = 400;
    const SatTable host = msmcl::build_sat(context(), depth, options);

    cl_int status = CL_SUCCESS;
    cl_context cl = context().cl_context_handle();
    cl_mem depth_buffer = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, depth.depth.size() * 4,
                                         const_cast<float*>(depth.depth.data()), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_mem table_buffer = clCreateBuffer(cl, CL_MEM_READ_WRITE, host.words.size() * 4, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_event done = nullptr;
    msmcl::Enqueue enqueue;
    enqueue.done = &done;
    msmcl::build_sat(context(), msmcl::DeviceDepth{depth_buffer, depth.width, depth.height, depth.samples},
                     table_buffer, options, enqueue);
    ASSERT_NE(done, nullptr);
    std::vector<std::uint32_t> words(host.words.size());
    ASSERT_EQ(clEnqueueReadBuffer(context().cl_queue_handle(), table_buffer, CL_TRUE, 0, words.size() * 4,
                                  words.data(), 1, &done, nullptr),
              CL_SUCCESS);
    clReleaseEvent(done);
    EXPECT_EQ(first_difference(words, host.words), -1);

    // A device table is also what sat_prefix_sums makes of the same texels.
    cl_mem texels_buffer = clCreateBuffer(cl, CL_MEM_READ_WRITE, host.words.size() * 4, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    std::vector<std::uint32_t> texels(host.words.size());
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x) {
            const auto t = msmcl::sat_rectangle_sum(host, x, y, x, y);
            std::copy(t.begin(), t.end(), texels.begin() + 4 * (static_cast<std::size_t>(y) * depth.width + x));
        }
    ASSERT_EQ(clEnqueueWriteBuffer(context().cl_queue_handle(), texels_buffer, CL_TRUE, 0, texels.size() * 4,
                                   texels.data(), 0, nullptr, nullptr),
              CL_SUCCESS);
    msmcl::Enqueue blocking;
    blocking.blocking = true;
    msmcl::sat_prefix_sums(context(), texels_buffer, table_buffer, depth.width, depth.height,
                           SatKernel::automatic, blocking);
    ASSERT_EQ(clEnqueueReadBuffer(context().cl_queue_handle(), table_buffer, CL_TRUE, 0, words.size() * 4,
                                  words.data(), 0, nullptr, nullptr),
              CL_SUCCESS);
    EXPECT_EQ(first_difference(words, host.words), -1);
    clReleaseMemObject(texels_buffer);
    clReleaseMemObject(table_buffer);
    clReleaseMemObject(depth_buffer);
}

TEST_F(SatTest, DeviceDepthsOutsideTheRangeResolveAsClamped) {
    // A device buffer is not validated: NaN must resolve as the near plane and anything
    // outside the range as its end, in every build (odd sizes: partial chunks of 16 columns,
    // a last band with an odd number of rows). Expected: the host path on the clamped map.
    std::mt19937 rng(seed_ + 5);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    for (DepthRange range : {DepthRange::zero_one, DepthRange::minus_one_one}) {
        const float lowest = range == DepthRange::zero_one ? 0.0f : -1.0f;
        const float specials[] = {nan, -nan, inf, -inf, 1.5f, lowest - 0.25f, 1e30f, -1e30f, -0.0f, 1.0f, lowest,
                                  std::nextafter(1.0f, 2.0f), std::nextafter(lowest, -2.0f)};
        for (int samples : {1, 2, 8}) {
            DepthImage raw = make_depth(37, 35, samples, range, rng);
            DepthImage clamped = raw;
            std::uniform_int_distribution<int> pick(0, 2 * static_cast<int>(std::size(specials)) - 1);
            for (std::size_t i = 0; i < raw.depth.size(); ++i) {
                const int k = pick(rng);
                if (k >= static_cast<int>(std::size(specials))) continue; // half the samples stay
                const float d = specials[k];
                raw.depth[i] = d;
                clamped.depth[i] = std::isnan(d) ? lowest : std::clamp(d, lowest, 1.0f);
            }
            msmcl::SatOptions options;
            options.max_kernel_texels = 200;
            options.depth_range = range;
            const SatTable expected = msmcl::build_sat(context(), clamped, options);

            cl_int status = CL_SUCCESS;
            cl_context cl = context().cl_context_handle();
            cl_mem depth_buffer = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, raw.depth.size() * 4,
                                                 raw.depth.data(), &status);
            ASSERT_EQ(status, CL_SUCCESS);
            cl_mem table_buffer = clCreateBuffer(cl, CL_MEM_READ_WRITE, expected.words.size() * 4, nullptr, &status);
            ASSERT_EQ(status, CL_SUCCESS);
            for (SatKernel kernel : {SatKernel::tiled_gpu, SatKernel::tiled_cpu, SatKernel::row_per_thread}) {
                options.kernel = kernel;
                msmcl::Enqueue blocking;
                blocking.blocking = true;
                msmcl::build_sat(context(), msmcl::DeviceDepth{depth_buffer, raw.width, raw.height, samples},
                                 table_buffer, options, blocking);
                std::vector<std::uint32_t> words(expected.words.size());
                ASSERT_EQ(clEnqueueReadBuffer(context().cl_queue_handle(), table_buffer, CL_TRUE, 0, words.size() * 4,
                                              words.data(), 0, nullptr, nullptr),
                          CL_SUCCESS);
                EXPECT_EQ(first_difference(words, expected.words), -1)
                    << "kernel " << static_cast<int>(kernel) << ", S=" << samples << ", range "
                    << msmcl::depth_range_name(range);
            }
            clReleaseMemObject(table_buffer);
            clReleaseMemObject(depth_buffer);
        }
    }
}

TEST_F(SatTest, BuildsOnTwoQueuesShareTheScratchInTurns) {
    // The Context keeps the builds' scratch buffers; builds enqueued on two queues without
    // waiting for each other must still take turns with them (and a larger map grows them).
    std::mt19937 rng(seed_ + 6);
    cl_int status = CL_SUCCESS;
    cl_context cl = context().cl_context_handle();
    cl_command_queue other = clCreateCommandQueue(cl, context().cl_device_handle(), 0, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    for (SatKernel kernel : {SatKernel::tiled_cpu, SatKernel::tiled_gpu}) {
        const DepthImage maps[] = {make_depth(150, 70, 2, DepthRange::zero_one, rng),
                                   make_depth(300, 140, 2, DepthRange::zero_one, rng),
                                   make_depth(90, 40, 2, DepthRange::zero_one, rng)};
        msmcl::SatOptions options;
        options.max_kernel_texels = 500;
        options.kernel = kernel;
        std::vector<cl_mem> depths, tables;
        std::vector<cl_event> done(std::size(maps), nullptr);
        for (std::size_t i = 0; i < std::size(maps); ++i) {
            const DepthImage& map = maps[i];
            depths.push_back(clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, map.depth.size() * 4,
                                            const_cast<float*>(map.depth.data()), &status));
            ASSERT_EQ(status, CL_SUCCESS);
            tables.push_back(clCreateBuffer(cl, CL_MEM_READ_WRITE, 16 * map.depth.size() / map.samples, nullptr,
                                            &status));
            ASSERT_EQ(status, CL_SUCCESS);
            msmcl::Enqueue enqueue;
            enqueue.queue = i % 2 ? other : nullptr; // alternate: the Context's queue, the other
            enqueue.done = &done[i];
            msmcl::build_sat(context(), msmcl::DeviceDepth{depths[i], map.width, map.height, map.samples},
                             tables[i], options, enqueue);
        }
        ASSERT_EQ(clFlush(other), CL_SUCCESS);
        for (std::size_t i = 0; i < std::size(maps); ++i) {
            const SatTable expected = msmcl::build_sat(context(), maps[i], options);
            std::vector<std::uint32_t> words(expected.words.size());
            ASSERT_EQ(clEnqueueReadBuffer(context().cl_queue_handle(), tables[i], CL_TRUE, 0, words.size() * 4,
                                          words.data(), 1, &done[i], nullptr),
                      CL_SUCCESS);
            EXPECT_EQ(first_difference(words, expected.words), -1)
                << "map " << i << ", kernel " << static_cast<int>(kernel);
            clReleaseEvent(done[i]);
            clReleaseMemObject(tables[i]);
            clReleaseMemObject(depths[i]);
        }
    }
    clReleaseCommandQueue(other);
}

// Reference moments of a query: area-weighted mean of the texel integers, inverse affine.
ref::Moments reference_query(const ref::SatTexels& texels, std::uint32_t scale, const msmcl::SatRectangle& r) {
    return ref::moments_of_channel_mean(ref::area_weighted_mean(texels, r.left, r.top, r.right, r.bottom), scale);
}

TEST_F(SatTest, InterpolatedQueriesEqualTheAreaWeightedIntegral) {
    // Host and device interpolated queries against the area-weighted mean in double.
    // Tolerance: each of the 9 exact sub-sums is rounded once to float (relative 2^-24),
    // weighted and accumulated in float (another ~9 roundings of the mean), then the inverse
    // affine (coefficients <= 1.8): < 1e-5 on moments in [-1, 1] ... [0, 1].
    std::mt19937 rng(seed_ + 5);
    const int width = 83, height = 61;
    const std::uint32_t n = 27 * 27;
    const std::uint32_t scale = ref::sat_scale(n);
    // Smooth-ish texels from a depth map so that the moments are meaningful.
    const DepthImage depth = make_depth(width, height, 4, DepthRange::zero_one, rng);
    msmcl::SatOptions options;
    options.max_kernel_texels = n;
    const SatTable table = msmcl::build_sat(context(), depth, options);
    ref::SatTexels texels;
    texels.width = width;
    texels.height = height;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (std::uint32_t v : msmcl::sat_rectangle_sum(table, x, y, x, y)) texels.values.push_back(v);

    // Rectangles: random fractional corners, inside one texel, thin strips, integer corners,
    // touching the map's edges, up to the largest that fits (27 + fraction).
    std::vector<msmcl::SatRectangle> rectangles;
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int i = 0; i < 3000; ++i) {
        const int kind = i % 5;
        float w = 0.05f + unit(rng) * 27.0f, h = 0.05f + unit(rng) * 27.0f;
        if (kind == 1) w = h = 0.01f + 0.9f * unit(rng);
        if (kind == 2) h = 0.2f;
        float left = unit(rng) * (width - w), top = unit(rng) * (height - h);
        if (kind == 3) {
            left = std::floor(left);
            top = std::floor(top);
            w = std::ceil(w);
            h = std::ceil(h);
        }
        if (kind == 4) {
            left = 0.0f;
            top = height - h;
        }
        rectangles.push_back({left, top, std::min(left + w, float(width)), std::min(top + h, float(height))});
    }

    // Device queries.
    std::vector<float> flat;
    for (const auto& r : rectangles) flat.insert(flat.end(), {r.left, r.top, r.right, r.bottom});
    cl_int status = CL_SUCCESS;
    cl_context cl = context().cl_context_handle();
    cl_mem table_buffer = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, table.words.size() * 4,
                                         const_cast<std::uint32_t*>(table.words.data()), &status);
    cl_mem rect_buffer = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, flat.size() * 4, flat.data(), &status);
    cl_mem out_buffer = clCreateBuffer(cl, CL_MEM_WRITE_ONLY, flat.size() * 4, nullptr, &status);
    msmcl::Enqueue blocking;
    blocking.blocking = true;
    msmcl::sat_query_moments(context(), msmcl::DeviceSat{table_buffer, width, height, n}, rect_buffer,
                             rectangles.size(), out_buffer, blocking);
    std::vector<float> device(flat.size());
    ASSERT_EQ(clEnqueueReadBuffer(context().cl_queue_handle(), out_buffer, CL_TRUE, 0, device.size() * 4,
                                  device.data(), 0, nullptr, nullptr),
              CL_SUCCESS);

    double worst_host = 0, worst_device = 0;
    for (std::size_t i = 0; i < rectangles.size(); ++i) {
        const ref::Moments expected = reference_query(texels, scale, rectangles[i]);
        const msmcl::Moments4 host = msmcl::sat_interpolated_moments(table, rectangles[i]);
        const double e[4] = {expected.b1, expected.b2, expected.b3, expected.b4};
        const float h[4] = {host.b1, host.b2, host.b3, host.b4};
        for (int j = 0; j < 4; ++j) {
            worst_host = std::max(worst_host, std::fabs(h[j] - e[j]));
            worst_device = std::max(worst_device, std::fabs(device[4 * i + j] - e[j]));
        }
    }
    std::printf("  %zu interpolated queries: worst moment error host %.2e, device %.2e\n", rectangles.size(),
                worst_host, worst_device);
    EXPECT_LT(worst_host, 1e-5);
    EXPECT_LT(worst_device, 1e-5);

    // Integer corners through the exact path agree with the direct sums to float rounding.
    for (int i = 0; i < 500; ++i) {
        const int x0 = static_cast<int>(unit(rng) * (width - 27)), y0 = static_cast<int>(unit(rng) * (height - 27));
        const int x1 = x0 + static_cast<int>(unit(rng) * 26), y1 = y0 + static_cast<int>(unit(rng) * 26);
        const msmcl::Moments4 m = msmcl::sat_rectangle_moments(table, x0, y0, x1, y1);
        const ref::Moments expected = reference_query(texels, scale, {float(x0), float(y0), float(x1 + 1), float(y1 + 1)});
        EXPECT_NEAR(m.b1, expected.b1, 1e-5);
        EXPECT_NEAR(m.b2, expected.b2, 1e-5);
        EXPECT_NEAR(m.b3, expected.b3, 1e-5);
        EXPECT_NEAR(m.b4, expected.b4, 1e-5);
    }

    // Queries that do not fit give NaN on the device, never a wrapped result.
    const std::vector<float> bad = {0.5f, 0.5f, 40.0f, 40.0f,   // 38^2 texels > N
                                    -1.0f, 0.0f, 2.0f, 2.0f,    // leaves the map
                                    3.0f, 3.0f, 3.0f, 4.0f,     // empty
                                    std::nanf(""), 0.0f, 1.0f, 1.0f};
    cl_mem bad_buffer = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bad.size() * 4,
                                       const_cast<float*>(bad.data()), &status);
    msmcl::sat_query_moments(context(), msmcl::DeviceSat{table_buffer, width, height, n}, bad_buffer, 4, out_buffer,
                             blocking);
    std::vector<float> bad_out(16);
    ASSERT_EQ(clEnqueueReadBuffer(context().cl_queue_handle(), out_buffer, CL_TRUE, 0, 64, bad_out.data(), 0, nullptr,
                                  nullptr),
              CL_SUCCESS);
    for (float v : bad_out) EXPECT_TRUE(std::isnan(v));
    clReleaseMemObject(bad_buffer);
    clReleaseMemObject(out_buffer);
    clReleaseMemObject(rect_buffer);
    clReleaseMemObject(table_buffer);
}

TEST_F(SatTest, ExrRoundTripIsBitExact) {
    std::mt19937 rng(seed_ + 6);
    const DepthImage depth = make_depth(40, 23, 2, DepthRange::minus_one_one, rng);
    msmcl::SatOptions options;
    options.max_kernel_texels = 225;
    options.depth_range = DepthRange::minus_one_one;
    const SatTable table = msmcl::build_sat(context(), depth, options);
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("msmcl_sat_test_" + std::to_string(seed_) + ".exr")).string();
    msmcl::io::write_sat_exr(path, table, msmcl::io::SatInfo{DepthRange::minus_one_one, 2});
    const msmcl::io::SatFile read = msmcl::io::read_sat_exr(path);
    EXPECT_EQ(read.table.width, table.width);
    EXPECT_EQ(read.table.height, table.height);
    EXPECT_EQ(read.table.max_kernel_texels, 225u);
    EXPECT_EQ(read.table.scale, table.scale);
    EXPECT_EQ(first_difference(read.table.words, table.words), -1);
    EXPECT_EQ(read.info.depth_range, DepthRange::minus_one_one);
    EXPECT_EQ(read.info.samples, 2);

    // A file whose scale attribute contradicts N is refused.
    msmcl::io::ExrImage image = msmcl::io::read_exr(path);
    for (auto& a : image.attributes)
        if (a.name == "msmcl:satScale") a.value = 12345;
    msmcl::io::write_exr(path, image);
    EXPECT_THROW(msmcl::io::read_sat_exr(path), msmcl::input_error);
    // A texture file is not a table.
    msmcl::io::write_intensity_exr(path, 2, 2, {0, 0, 0, 0});
    EXPECT_THROW(msmcl::io::read_sat_exr(path), msmcl::input_error);
    std::filesystem::remove(path);
}

TEST_F(SatTest, BadInputIsRejected) {
    std::mt19937 rng(seed_ + 7);
    DepthImage depth = make_depth(8, 8, 1, DepthRange::zero_one, rng);
    msmcl::SatOptions options;
    options.max_kernel_texels = 16;
    // N outside [2, 2^31 - 1].
    for (std::uint32_t n : {0u, 1u, 0x80000000u}) {
        options.max_kernel_texels = n;
        EXPECT_THROW(msmcl::build_sat(context(), depth, options), msmcl::input_error) << "N " << n;
    }
    options.max_kernel_texels = 16;
    // NaN, Inf and out-of-range depths, named by texel.
    for (float bad : {std::nanf(""), std::numeric_limits<float>::infinity(), 1.5f, -0.25f}) {
        DepthImage broken = depth;
        broken.depth[3 * 8 + 5] = bad;
        try {
            msmcl::build_sat(context(), broken, options);
            ADD_FAILURE() << "no error for depth " << bad;
        } catch (const msmcl::input_error& e) {
            EXPECT_NE(std::string(e.what()).find("(5, 3)"), std::string::npos) << e.what();
        }
    }
    // Sizes and sample counts.
    DepthImage wrong = depth;
    wrong.depth.pop_back();
    EXPECT_THROW(msmcl::build_sat(context(), wrong, options), msmcl::input_error);
    wrong = depth;
    wrong.samples = 3;
    EXPECT_THROW(msmcl::build_sat(context(), wrong, options), msmcl::input_error);
    wrong = depth;
    wrong.width = 0;
    EXPECT_THROW(msmcl::build_sat(context(), wrong, options), msmcl::input_error);
    EXPECT_THROW(msmcl::sat_prefix_sums(context(), std::vector<std::uint32_t>(10), 2, 2), msmcl::input_error);
    // Device buffers: null or too small.
    cl_int status = CL_SUCCESS;
    cl_mem small = clCreateBuffer(context().cl_context_handle(), CL_MEM_READ_WRITE, 64, nullptr, &status);
    EXPECT_THROW(msmcl::build_sat(context(), msmcl::DeviceDepth{nullptr, 8, 8, 1}, small, options), msmcl::input_error);
    EXPECT_THROW(msmcl::build_sat(context(), msmcl::DeviceDepth{small, 8, 8, 1}, small, options), msmcl::input_error);
    EXPECT_THROW(msmcl::sat_prefix_sums(context(), small, small, 2, 2), msmcl::input_error);
    clReleaseMemObject(small);

    // Queries beyond N texels or the map, and inconsistent tables.
    const SatTable table = msmcl::build_sat(context(), depth, options);
    EXPECT_THROW(msmcl::sat_rectangle_sum(table, 0, 0, 4, 3), msmcl::input_error); // 20 > 16 texels
    EXPECT_NO_THROW(msmcl::sat_rectangle_sum(table, 0, 0, 3, 3));
    EXPECT_THROW(msmcl::sat_rectangle_sum(table, -1, 0, 1, 1), msmcl::input_error);
    EXPECT_THROW(msmcl::sat_rectangle_sum(table, 6, 6, 8, 7), msmcl::input_error);
    EXPECT_THROW(msmcl::sat_rectangle_sum(table, 3, 3, 2, 3), msmcl::input_error);
    EXPECT_THROW(msmcl::sat_interpolated_moments(table, {0.5f, 0.5f, 6.5f, 6.5f}), msmcl::input_error);
    EXPECT_NO_THROW(msmcl::sat_interpolated_moments(table, {0.5f, 0.5f, 5.5f, 5.5f}));
    EXPECT_THROW(msmcl::sat_interpolated_moments(table, {1.0f, 1.0f, 1.0f, 2.0f}), msmcl::input_error);
    EXPECT_THROW(msmcl::sat_interpolated_moments(table, {0.0f, 0.0f, 9.0f, 1.0f}), msmcl::input_error);
    SatTable inconsistent = table;
    inconsistent.scale += 1;
    EXPECT_THROW(msmcl::sat_rectangle_sum(inconsistent, 0, 0, 0, 0), msmcl::input_error);
    inconsistent = table;
    inconsistent.words.pop_back();
    EXPECT_THROW(msmcl::sat_rectangle_sum(inconsistent, 0, 0, 0, 0), msmcl::input_error);
}

} // namespace
