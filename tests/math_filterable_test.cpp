// The shading of the filterable formats (kernels/msm_filterable_shading.clh compiled as C++, the very
// code the kernels and shaders run) against the double reference of
// tests/reference/filterable_reference.hpp: the decoders bit for bit, the shading within the
// effect of float32 rounding on its inputs.
#include "kernels/msm_filterable_shading.clh"
#include "reference/filterable_reference.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace ref = msmcl::reference;

#include "seeded_test.hpp"

namespace {

using MathFilterableTest = msmcl::testing::SeededTest;

int warp_constant(ref::Warp warp) {
    return warp == ref::Warp::vsm ? MSM_WARP_VSM : warp == ref::Warp::evsm2 ? MSM_WARP_EVSM2
                                                  : warp == ref::Warp::evsm4 ? MSM_WARP_EVSM4 : MSM_WARP_ESM;
}

msm_warp_shading device_shading(const ref::WarpShading& s) {
    return msm_warp_shading_make(warp_constant(s.warp), float(s.positive), float(s.negative), float(s.min_variance),
                                 float(s.light_bleed_reduction));
}

msm_moments as_moments(const ref::Channels& c) {
    msm_moments m;
    m.b1 = float(c[0]), m.b2 = float(c[1]), m.b3 = float(c[2]), m.b4 = float(c[3]);
    return m;
}

ref::Channels as_channels(const msm_moments& m) { return {m.b1, m.b2, m.b3, m.b4}; }

std::uint16_t float_to_half_bits(float value) {
    // Exact for the values the test uses (halves read back from the reference).
    for (std::uint32_t code = 0; code < 0x10000u; ++code)
        if (ref::half_value(std::uint16_t(code)) == double(value)) return std::uint16_t(code);
    return 0x7e00u;
}

} // namespace

// Every binary16 code, subnormals, infinities and NaNs included, decodes exactly.
TEST(MathFilterable, HalfDecodeIsExactForEveryCode) {
    for (std::uint32_t code = 0; code < 0x10000u; ++code) {
        const double expected = ref::half_value(std::uint16_t(code));
        const float got = msm_half_value(code);
        if (std::isnan(expected)) {
            EXPECT_TRUE(std::isnan(got)) << "code " << code;
        } else {
            ASSERT_EQ(double(got), expected) << "code " << code;
            ASSERT_EQ(std::signbit(got), bool(code & 0x8000u)) << "code " << code;
        }
    }
}

// Each decoder reads the channels in the order of docs/formats.md (R in the low bits).
TEST(MathFilterable, DecodersReadTheChannelsInOrder) {
    // vsm32: unorm16 codes 1000 (R) and 50000 (G).
    const msm_moments vsm32 = msm_decode_vsm32(1000u | (50000u << 16));
    EXPECT_EQ(vsm32.b1, 1000.0f / 65535.0f);
    EXPECT_EQ(vsm32.b2, 50000.0f / 65535.0f);
    EXPECT_EQ(vsm32.b3, 0.0f);
    // vsm64 and esm32: float bits.
    msm_word2 w;
    w.w0 = as_uint(0.25f), w.w1 = as_uint(0.0625f);
    const msm_moments vsm64 = msm_decode_vsm64(w);
    EXPECT_EQ(vsm64.b1, 0.25f);
    EXPECT_EQ(vsm64.b2, 0.0625f);
    EXPECT_EQ(msm_decode_esm32(as_uint(0.75f)).b1, 0.75f);
    // evsm2_32 and evsm4_64: halves 1.5 (0x3e00), 2.25 (0x4080), -0.5 (0xb800), 0.25 (0x3400).
    const msm_moments evsm2 = msm_decode_evsm2_32(0x3e00u | (0x4080u << 16));
    EXPECT_EQ(evsm2.b1, 1.5f);
    EXPECT_EQ(evsm2.b2, 2.25f);
    w.w0 = 0x3e00u | (0x4080u << 16), w.w1 = 0xb800u | (0x3400u << 16);
    const msm_moments evsm4 = msm_decode_evsm4_64(w);
    EXPECT_EQ(evsm4.b1, 1.5f);
    EXPECT_EQ(evsm4.b2, 2.25f);
    EXPECT_EQ(evsm4.b3, -0.5f);
    EXPECT_EQ(evsm4.b4, 0.25f);
    EXPECT_EQ(float_to_half_bits(-0.5f), 0xb800u);
}

// Closed forms: a single occluder depth, no minimum variance, no light-bleed reduction.
TEST(MathFilterable, SingleDepthGivesAStep) {
    for (ref::Warp warp : {ref::Warp::vsm, ref::Warp::evsm2, ref::Warp::evsm4}) {
        const ref::Channels c = ref::warp_channels(warp, 0.5, 5.54, 5.54);
        const msm_warp_shading s = msm_warp_shading_make(warp_constant(warp), 5.54f, 5.54f, 0.0f, 0.0f);
        // In front of the occluder (t_r < 0.5): lit; behind it: shadowed.
        EXPECT_EQ(msm_shadow_warped(as_moments(c), 2.0f * 0.4f - 1.0f, s), 0.0f);
        EXPECT_NEAR(msm_shadow_warped(as_moments(c), 2.0f * 0.6f - 1.0f, s), 1.0f, 1e-3);
    }
    // ESM: visibility exp(c (t_o - t_r)), clamped to 1 in front of the occluder.
    const msm_warp_shading esm = msm_warp_shading_make(MSM_WARP_ESM, 80.0f, 0.0f, 0.0f, 0.0f);
    const msm_moments stored = as_moments(ref::warp_channels(ref::Warp::esm, 0.5, 80.0, 0.0));
    EXPECT_EQ(msm_shadow_warped(stored, 2.0f * 0.45f - 1.0f, esm), 0.0f);
    EXPECT_NEAR(msm_shadow_warped(stored, 2.0f * 0.51f - 1.0f, esm), 1.0 - std::exp(-0.8), 1e-5);
}

// Random filtered texels (1 to 4 depths with random weights, the storage's exponents) and
// receivers at random depths, minimum variances and light-bleed reductions: the float32
// shading of the stored values against the double reference on the same stored values. The
// tolerance is what the reference itself moves when its inputs move by their float32
// rounding (each channel by 2^-21 relative: the rounding of the blend and of m2 - m1^2; the
// receiver's depth by 2^-21: the rounding of t and of the exponential's argument), plus 1e-6.
TEST_F(MathFilterableTest, ShadingMatchesTheDoubleReference) {
    struct Case {
        ref::Warp warp;
        double positive, negative;
    };
    const Case cases[] = {{ref::Warp::vsm, 0, 0},        {ref::Warp::evsm2, 5.54, 0}, {ref::Warp::evsm4, 5.54, 5.54},
                          {ref::Warp::evsm4, 40.0, 5.0}, {ref::Warp::esm, 80.0, 0},   {ref::Warp::esm, 10.0, 0}};
    const double min_variances[] = {0.0, 1e-6, 1e-4, 1e-2};
    const double reductions[] = {0.0, 0.15, 0.5};
    const double eps = std::ldexp(1.0, -21);
    double worst = 0;
    for (const Case& c : cases)
        for (double v : min_variances)
            for (double r : reductions)
                for (int trial = 0; trial < 200; ++trial) {
                    const int depths = 1 + int(uniform(0, 4));
                    std::vector<double> t, weight;
                    for (int k = 0; k < depths; ++k) t.push_back(uniform(0, 1)), weight.push_back(uniform(0.05, 1));
                    const ref::WarpShading s{c.warp, c.positive, c.negative, v, r};
                    // The texel as float32 channels, the reference on those very values.
                    const msm_moments stored = as_moments(ref::warp_channels(c.warp, t, weight, c.positive, c.negative));
                    const ref::Channels exact = as_channels(stored);
                    const float zf = float(uniform(-1.1, 1.1));
                    const double receiver = 0.5 * double(zf) + 0.5;
                    const double expected = ref::warp_shadow(exact, receiver, s);
                    double tolerance = 0;
                    for (int signs = 0; signs < 16; ++signs)
                        for (double dt : {-eps, 0.0, eps}) {
                            ref::Channels moved = exact;
                            for (int k = 0; k < 4; ++k) moved[k] *= 1.0 + ((signs >> k) & 1 ? eps : -eps);
                            tolerance = std::max(tolerance, std::fabs(ref::warp_shadow(moved, receiver + dt, s) - expected));
                        }
                    tolerance += 1e-6;
                    const float got = msm_shadow_warped(stored, zf, device_shading(s));
                    ASSERT_TRUE(got >= 0.0f && got <= 1.0f) << got;
                    ASSERT_NEAR(got, expected, tolerance)
                        << "warp " << int(c.warp) << " c " << c.positive << "," << c.negative << " V " << v << " R "
                        << r << " zf " << zf << " depths " << depths;
                    worst = std::max(worst, std::fabs(got - expected));
                }
    std::printf("largest difference from the double reference: %.3g\n", worst);
}

// No depth in [0, 1] and no receiver gives Inf or NaN at the storage's largest exponents,
// and V up to 0.25 (the largest variance of a depth in [0, 1]).
TEST(MathFilterable, ExtremesStayFinite) {
    const msm_warp_shading shadings[] = {
        msm_warp_shading_make(MSM_WARP_VSM, 0.0f, 0.0f, 0.25f, 0.99f),
        msm_warp_shading_make(MSM_WARP_EVSM4, 5.54f, 5.54f, 0.25f, 0.0f),
        msm_warp_shading_make(MSM_WARP_EVSM4, 44.0f, 44.0f, 0.25f, 0.5f),
        msm_warp_shading_make(MSM_WARP_ESM, 88.0f, 0.0f, 0.0f, 0.0f)};
    const ref::Warp warps[] = {ref::Warp::vsm, ref::Warp::evsm4, ref::Warp::evsm4, ref::Warp::esm};
    for (int k = 0; k < 4; ++k)
        for (double t : {0.0, 1e-7, 0.5, 1.0 - 1e-7, 1.0})
            for (float zf : {-2.0f, -1.0f, 0.0f, 1.0f, 2.0f}) {
                const msm_moments m = as_moments(
                    ref::warp_channels(warps[k], t, shadings[k].positive, shadings[k].negative));
                const float shadow = msm_shadow_warped(m, zf, shadings[k]);
                EXPECT_TRUE(shadow >= 0.0f && shadow <= 1.0f) << k << " t " << t << " zf " << zf << ": " << shadow;
            }
}
