// The filter's VSM, EVSM and ESM formats (docs/formats.md, "Filterable representations") in
// every kernel distribution, against the double reference of tests/reference/
// (filterable_reference: warp, mean over the samples, 9x9 Gaussian, storage codes).
#include "filter_fixtures.hpp"
#include "reference/filterable_reference.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/formats.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace filter_fixtures;
using msmcl::WarpExponents;

struct FormatCase {
    Format format;
    ref::Warp warp;
    int channels;
    enum Storage { unorm16, half, float32 } storage;
};
const FormatCase kFormats[] = {
    {Format::vsm32, ref::Warp::vsm, 2, FormatCase::unorm16},   {Format::vsm64, ref::Warp::vsm, 2, FormatCase::float32},
    {Format::evsm2_32, ref::Warp::evsm2, 2, FormatCase::half}, {Format::evsm4_64, ref::Warp::evsm4, 4, FormatCase::half},
    {Format::evsm4_128, ref::Warp::evsm4, 4, FormatCase::float32}, {Format::esm32, ref::Warp::esm, 1, FormatCase::float32},
};

const double kFloatUlp = std::ldexp(1.0, -24); // the rounding of one float32 operation, relative

// Stored channel k of texel (x, y) as its value (unorm16 as the code, not divided).
double stored(const Texture& t, const FormatCase& f, int x, int y, int k) {
    if (f.storage == FormatCase::unorm16) return t.code16(x, y, k);
    if (f.storage == FormatCase::half) return ref::half_value(t.code16(x, y, k));
    float value;
    std::memcpy(&value, t.texel(x, y) + k, sizeof value);
    return value;
}

// How far the kernels' float32 value of lane k may be from the double one. Every lane's
// warped values have one sign (t, p, p^2, n^2 >= 0, n < 0), so the mean and the blur add
// magnitudes and their roundings are relative to the value: S - 1 additions and the
// 1/S scale (<= 17 for S <= 16), 2 x 9 fma steps and the taps rounded to float (9 halves
// of an ulp): < 48 ulps. The warp itself: x = 2d - 1 is within half an ulp, c x within
// an ulp of c, exp (msm_exp) within one ulp: p is off by at most (1.5 c + 2) ulps
// relatively, p^2 by twice that plus one; ESM's c (t - 1) by 2.5 c ulps. VSM's t carries an
// absolute 2^-24 from z, t^2 twice that: 2^-22 covers both. Values below the float32
// normal range (ESM's exp(-88)) may be stored as 0: 2^-125 absolute for every lane.
double float_tolerance(ref::Warp warp, int k, WarpExponents c, double value) {
    double warp_ulps = 0.0, absolute = std::ldexp(1.0, -125);
    switch (warp) {
    case ref::Warp::vsm: absolute = 4.0 * kFloatUlp; break;
    case ref::Warp::evsm2:
    case ref::Warp::evsm4: {
        const double exponent = k < 2 ? c.positive : c.negative;
        warp_ulps = (k % 2 == 0 ? 1.0 : 2.0) * (1.5 * exponent + 2.0) + 1.0;
        break;
    }
    case ref::Warp::esm: warp_ulps = 2.5 * c.positive + 2.0; break;
    }
    return (48.0 + warp_ulps) * kFloatUlp * std::fabs(value) + absolute;
}

// How far the stored channel may be from the double value: the float tolerance, then the
// storage's rounding of the kernel's value (half: half a spacing of halves around it;
// unorm16: half a code, in codes).
double stored_tolerance(const FormatCase& f, int k, WarpExponents c, double value) {
    const double tolerance = float_tolerance(f.warp, k, c, value);
    if (f.storage == FormatCase::unorm16) return 0.5 + 65535.0 * tolerance + 1e-3;
    if (f.storage == FormatCase::half) return tolerance + 0.5 * ref::half_spacing(std::fabs(value) + tolerance);
    return tolerance;
}

// Whether the stored channel is a finite number (a half code with exponent bits 31 is Inf
// or NaN; unorm codes always are).
bool stored_finite(const Texture& t, const FormatCase& f, int x, int y, int k) {
    if (f.storage == FormatCase::half) return ((t.code16(x, y, k) >> 10) & 0x1f) != 0x1f;
    return std::isfinite(stored(t, f, x, y, k));
}

// Every stored channel against the reference; reports the worst channel in tolerances.
void expect_matches_reference(const Texture& texture, const FormatCase& f, const DepthImage& depth, DepthRange range,
                              WarpExponents c, const std::string& what) {
    ASSERT_EQ(texture.format, f.format) << what;
    EXPECT_EQ(texture.exponents, c) << what;
    const std::vector<ref::Channels> expected =
        ref::filter_warped(to_reference(depth, range), 2.4, f.warp, c.positive, c.negative);
    double worst = 0.0;
    std::string worst_at;
    for (int y = 0; y < texture.height; ++y)
        for (int x = 0; x < texture.width; ++x)
            for (int k = 0; k < f.channels; ++k) {
                const double value = expected[std::size_t(y) * texture.width + x][k];
                const double target = f.storage == FormatCase::unorm16 ? 65535.0 * value : value;
                const double ratio = std::fabs(stored(texture, f, x, y, k) - target) / stored_tolerance(f, k, c, value);
                if (!(ratio <= worst)) { // NaN fails too
                    worst = std::isnan(ratio) ? std::numeric_limits<double>::infinity() : ratio;
                    worst_at = at(x, y) + " channel " + std::to_string(k) + ": stored " +
                               std::to_string(stored(texture, f, x, y, k)) + ", reference " + std::to_string(target);
                }
            }
    EXPECT_LE(worst, 1.0) << what << ": worst " << worst_at << ", seed " << test_seed();
}

// The exponents a format's filter uses by default.
WarpExponents defaults(Format format) { return msmcl::effective_exponents(format, {}); }

class FilterableEveryKernel : public FilterTest, public ::testing::WithParamInterface<FilterKernel> {
protected:
    static Texture run_with(const DepthImage& depth, Format format, DepthRange range, WarpExponents exponents,
                            FilterKernel kernel = GetParam()) {
        msmcl::FilterOptions options;
        options.format = format;
        options.depth_range = range;
        options.kernel = kernel;
        options.exponents = exponents;
        return msmcl::filter(*context_, depth, options);
    }
    static std::string name(const FormatCase& f, int samples, DepthRange range) {
        return std::string(msmcl::filter_kernel_name(GetParam())) + " " + msmcl::format_name(f.format) + " S=" +
               std::to_string(samples) + " range " + msmcl::depth_range_name(range);
    }
};

INSTANTIATE_TEST_SUITE_P(Kernels, FilterableEveryKernel,
                         ::testing::Values(FilterKernel::fused_paper, FilterKernel::fused_cpu, FilterKernel::three_pass),
                         [](const ::testing::TestParamInfo<FilterKernel>& info) {
                             return std::string(msmcl::filter_kernel_name(info.param));
                         });

// Random maps with occluders at d = 0 and d = 1 exactly, S = 1, 4, 8, both depth ranges,
// over several blocks of the kernel, at the default exponents.
TEST_P(FilterableEveryKernel, EveryFormatMatchesTheDoubleReference) {
    const int width = GetParam() == FilterKernel::fused_cpu ? 150 : 70;
    const int height = GetParam() == FilterKernel::fused_cpu ? 80 : 50;
    for (int samples : {1, 4, 8})
        for (DepthRange range : {DepthRange::zero_one, DepthRange::minus_one_one}) {
            const DepthImage depth = make_depth(width, height, samples, range, test_seed() + 31 * samples);
            for (const FormatCase& f : kFormats)
                expect_matches_reference(run_with(depth, f.format, range, {}), f, depth, range, defaults(f.format),
                                         name(f, samples, range));
        }
}

// Exponents other than the defaults reach the warp and the texture's record.
TEST_P(FilterableEveryKernel, GivenExponentsMatchTheDoubleReference) {
    const DepthImage depth = make_depth(45, 37, 4, DepthRange::zero_one, test_seed() + 5);
    const struct {
        Format format;
        WarpExponents exponents;
    } cases[] = {{Format::evsm2_32, {3.0f, 0.0f}}, {Format::evsm4_64, {2.5f, 4.0f}},
                 {Format::evsm4_128, {20.0f, 10.0f}}, {Format::esm32, {30.0f, 0.0f}}};
    for (const auto& c : cases)
        for (const FormatCase& f : kFormats)
            if (f.format == c.format)
                expect_matches_reference(run_with(depth, f.format, DepthRange::zero_one, c.exponents), f, depth,
                                         DepthRange::zero_one, c.exponents, name(f, 4, DepthRange::zero_one));
}

// Depth exactly at both ends of each range (texels all near, all far, and samples mixing
// both), every sample count, the largest exponents: every stored channel is finite. The
// paper's kernel runs every sample count; the others the largest, whose resolve sums most.
TEST_P(FilterableEveryKernel, NoInfOrNanAtTheEndsOfTheDepthRange) {
    const std::vector<int> sample_counts =
        GetParam() == FilterKernel::fused_paper ? std::vector<int>{1, 2, 4, 8, 16} : std::vector<int>{16};
    for (int samples : sample_counts)
        for (DepthRange range : {DepthRange::zero_one, DepthRange::minus_one_one}) {
            const float near = range == DepthRange::zero_one ? 0.0f : -1.0f, far = 1.0f;
            DepthImage depth;
            depth.width = 40;
            depth.height = 30;
            depth.samples = samples;
            for (int y = 0; y < depth.height; ++y)
                for (int x = 0; x < depth.width; ++x)
                    for (int s = 0; s < samples; ++s) {
                        // Left third near, middle third far, right third alternating samples.
                        const int band = 3 * x / depth.width;
                        depth.depth.push_back(band == 0 ? near : band == 1 ? far : (s + y) % 2 ? near : far);
                    }
            for (const FormatCase& f : kFormats) {
                const WarpExponents largest = msmcl::max_exponents(f.format);
                const Texture texture = run_with(depth, f.format, range, largest);
                for (int y = 0; y < texture.height; ++y)
                    for (int x = 0; x < texture.width; ++x)
                        for (int k = 0; k < f.channels; ++k)
                            ASSERT_TRUE(stored_finite(texture, f, x, y, k))
                                << name(f, samples, range) << " " << at(x, y) << " channel " << k;
                expect_matches_reference(texture, f, depth, range, msmcl::effective_exponents(f.format, largest),
                                         name(f, samples, range) + " at the largest exponents");
            }
        }
}

// A translucent layer of opacity 1 in front of every sample takes all the weight: the same
// texels as an opaque map at the layer's depths (the composite weights the warped values
// as it weights moments, docs/math.md).
TEST_P(FilterableEveryKernel, OpaqueLayerInFrontEqualsTheOpaqueMapAtItsDepth) {
    const DepthImage depth = make_depth(45, 37, 4, DepthRange::zero_one, test_seed() + 11);
    msmcl::TranslucentLayer layer;
    DepthImage front = depth;
    for (float& d : front.depth) d *= 0.5f;
    layer.depth = front.depth;
    layer.opacity.assign(depth.depth.size(), 1.0f);
    for (const FormatCase& f : kFormats) {
        msmcl::FilterOptions options;
        options.format = f.format;
        options.kernel = GetParam();
        const Texture layered = msmcl::filter(*context_, depth, {layer}, options);
        EXPECT_EQ(layered.words, msmcl::filter(*context_, front, options).words)
            << msmcl::format_name(f.format) << " " << msmcl::filter_kernel_name(GetParam());
    }
}

using Filterable = FilterTest;

// The three distributions run the same operations in the same order: the same bits.
TEST_F(Filterable, EveryDistributionGivesTheSameTexels) {
    const DepthImage depth = make_depth(150, 90, 4, DepthRange::minus_one_one, test_seed() + 3);
    for (const FormatCase& f : kFormats) {
        msmcl::FilterOptions options;
        options.format = f.format;
        options.depth_range = DepthRange::minus_one_one;
        options.kernel = FilterKernel::three_pass;
        const Texture baseline = msmcl::filter(*context_, depth, options);
        for (FilterKernel kernel : {FilterKernel::fused_paper, FilterKernel::fused_cpu}) {
            options.kernel = kernel;
            EXPECT_EQ(msmcl::filter(*context_, depth, options).words, baseline.words)
                << msmcl::format_name(f.format) << " " << msmcl::filter_kernel_name(kernel);
        }
    }
}

// The defaults and limits of the derivation (docs/formats.md, "Exponents"), and the
// refusals: beyond the limit (naming it), negative, not finite, a lane the format lacks.
TEST_F(Filterable, ExponentsHaveTheirDefaultsAndLimits) {
    EXPECT_EQ(msmcl::default_exponents(Format::evsm2_32), (WarpExponents{5.54f, 0.0f}));
    EXPECT_EQ(msmcl::default_exponents(Format::evsm4_64), (WarpExponents{5.54f, 5.54f}));
    EXPECT_EQ(msmcl::default_exponents(Format::evsm4_128), (WarpExponents{40.0f, 5.0f}));
    EXPECT_EQ(msmcl::default_exponents(Format::esm32), (WarpExponents{80.0f, 0.0f}));
    for (Format format : {Format::moments128, Format::nlq32, Format::vsm32, Format::vsm64})
        EXPECT_EQ(msmcl::default_exponents(format), WarpExponents{}) << msmcl::format_name(format);
    // Half: exp(2c) below the largest half; float32: 16 samples of exp(2c) below FLT_MAX.
    EXPECT_LT(std::exp(2.0 * msmcl::max_exponents(Format::evsm4_64).positive), 65504.0);
    EXPECT_LT(16.0 * std::exp(2.0 * msmcl::max_exponents(Format::evsm4_128).positive),
              double(std::numeric_limits<float>::max()));
    EXPECT_LT(std::exp(double(msmcl::max_exponents(Format::esm32).positive)),
              double(std::numeric_limits<float>::max()));

    const auto message = [](Format format, WarpExponents exponents) -> std::string {
        try {
            msmcl::effective_exponents(format, exponents);
        } catch (const msmcl::input_error& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_NE(message(Format::evsm2_32, {5.6f, 0.0f}).find("safe limit 5.54"), std::string::npos);
    EXPECT_NE(message(Format::evsm4_128, {40.0f, 43.0f}).find("safe limit 42"), std::string::npos);
    EXPECT_NE(message(Format::esm32, {89.0f, 0.0f}).find("safe limit 88"), std::string::npos);
    EXPECT_NE(message(Format::esm32, {-1.0f, 0.0f}).find("> 0"), std::string::npos);
    EXPECT_NE(message(Format::evsm4_64, {std::nanf(""), 1.0f}).find("> 0"), std::string::npos);
    EXPECT_NE(message(Format::evsm2_32, {1.0f, 1.0f}).find("no such warp"), std::string::npos);
    EXPECT_NE(message(Format::msm64, {1.0f, 0.0f}).find("no such warp"), std::string::npos);
    EXPECT_EQ(msmcl::effective_exponents(Format::evsm4_64, {0.0f, 2.0f}), (WarpExponents{5.54f, 2.0f}));

    // filter refuses them before it touches the device.
    const DepthImage depth = make_depth(8, 8, 1, DepthRange::zero_one, test_seed());
    msmcl::FilterOptions options;
    options.format = Format::evsm4_64;
    options.exponents = {6.0f, 1.0f};
    EXPECT_THROW(msmcl::filter(*context_, depth, options), msmcl::input_error);
}

} // namespace
