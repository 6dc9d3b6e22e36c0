// Float-float toolkit (kernels/msm_df.clh) against long double, and the accurate shading of
// the linear formats (kernels/msm_shading.clh: moments about their mean in float-float)
// against the independent double reconstruction of host/reference. u = 2^-24 below.
#include <msmcl/device_math.hpp>

#include "kernels/msm_shading.clh"
#include "reference/moment_math.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>

namespace ref = msmcl::reference;

#include "seeded_test.hpp"

namespace {

using Long = long double;

const Long u = std::ldexp(1.0L, -24);
const Long u2 = u * u;

Long value(msm_df a) { return static_cast<Long>(a.hi) + static_cast<Long>(a.lo); }

// hi is the float nearest to hi + lo.
bool normalized(msm_df a) { return static_cast<float>(value(a)) == a.hi; }

class MathDf : public msmcl::testing::SeededTest {
protected:
    // A float of either sign with a binary exponent in [-e, e].
    float random_float(int e) {
        float f = static_cast<float>(std::ldexp(uniform(1.0, 2.0), static_cast<int>(uniform(-e, e + 1))));
        return uniform(0.0, 1.0) < 0.5 ? -f : f;
    }
    // A normalized pair: lo within 0.99 ulp(hi)/2.
    msm_df random_df(int e) {
        float hi = random_float(e);
        float lo = static_cast<float>(uniform(-0.99, 0.99) * 0.5 * std::ldexp(1.0, std::ilogb(hi) - 23));
        return msm_df_make(hi, lo);
    }
    // b near -a (cancellation of 1..20 bits) or unrelated.
    msm_df partner(msm_df a) {
        if (uniform(0.0, 1.0) < 0.5) return random_df(8);
        msm_df b = msm_df_make(-a.hi * static_cast<float>(1.0 + std::ldexp(uniform(-1.0, 1.0), -static_cast<int>(uniform(1, 21)))),
                               0.0f);
        b.lo = static_cast<float>(uniform(-0.99, 0.99) * 0.5 * std::ldexp(1.0, std::ilogb(b.hi) - 23));
        return b;
    }
};

} // namespace

// ---- The toolkit.

// TwoSum, FastTwoSum, TwoProd: the pair is the exact result (|a|, |b| within 2^+-16, so the
// exact sum fits the 64-bit long double mantissa).
TEST_F(MathDf, ErrorFreeTransformationsAreExact) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    for (int trial = 0; trial < 200000; ++trial) {
        float a = random_float(16), b = random_float(16);
        msm_df s = msm_two_sum(a, b);
        ASSERT_EQ(value(s), static_cast<Long>(a) + static_cast<Long>(b)) << a << " + " << b;
        ASSERT_EQ(s.hi, a + b);
        float big = std::fabs(a) >= std::fabs(b) ? a : b, small = std::fabs(a) >= std::fabs(b) ? b : a;
        ASSERT_EQ(value(msm_fast_two_sum(big, small)), static_cast<Long>(a) + static_cast<Long>(b));
        msm_df p = msm_two_prod(a, b);
        ASSERT_EQ(value(p), static_cast<Long>(a) * static_cast<Long>(b)) << a << " * " << b;
        ASSERT_EQ(p.hi, a * b);
    }
}

// Relative error bounds of Joldes, Muller, Popescu 2017 (AccurateDWPlusDW 3u^2, DWPlusFP 2u^2,
// DWTimesFP3 2u^2, DWTimesDW3 <= 5u^2; SloppyDWPlusDW 3u^2 for one sign, else absolute
// 3u^2 (|a| + |b|)), on operands with and without cancellation; results normalized. The long
// double references round at 2^-64 of the result (1e-5 of these bounds).
TEST_F(MathDf, ArithmeticMeetsItsErrorBounds) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    Long worst_add = 0, worst_add_f = 0, worst_mul_f = 0, worst_mul = 0, worst_sloppy = 0;
    for (int trial = 0; trial < 200000; ++trial) {
        msm_df a = random_df(8), b = partner(a);
        float f = uniform(0.0, 1.0) < 0.5 ? b.hi : random_float(8);
        // hi + hi and lo + lo are exact in long double; value(a) + value(b) is not (a pair can
        // span more than 64 bits) and would show its rounding through the cancellation.
        const Long exact_add = (static_cast<Long>(a.hi) + b.hi) + (static_cast<Long>(a.lo) + b.lo);
        const Long exact_add_f = (static_cast<Long>(a.hi) + f) + a.lo;
        auto relative = [](Long got, Long exact) { return exact == 0 ? std::fabs(got) : std::fabs(got - exact) / std::fabs(exact); };

        msm_df add = msm_df_add(a, b);
        ASSERT_TRUE(normalized(add));
        worst_add = std::max(worst_add, relative(value(add), exact_add) / u2);
        msm_df add_f = msm_df_add_f(a, f);
        ASSERT_TRUE(normalized(add_f));
        worst_add_f = std::max(worst_add_f, relative(value(add_f), exact_add_f) / u2);
        msm_df mul_f = msm_df_mul_f(a, f);
        ASSERT_TRUE(normalized(mul_f));
        worst_mul_f = std::max(worst_mul_f, relative(value(mul_f), value(a) * f) / u2);
        msm_df mul = msm_df_mul(a, b);
        ASSERT_TRUE(normalized(mul));
        worst_mul = std::max(worst_mul, relative(value(mul), value(a) * value(b)) / u2);
        msm_df sloppy = msm_df_add_sloppy(a, b);
        const bool one_sign = (a.hi > 0) == (b.hi > 0);
        const Long sloppy_error = one_sign ? relative(value(sloppy), exact_add)
                                           : std::fabs(value(sloppy) - exact_add) / (std::fabs(value(a)) + std::fabs(value(b)));
        worst_sloppy = std::max(worst_sloppy, sloppy_error / u2);
        ASSERT_EQ(msm_df_sub(a, b).hi, msm_df_add(a, msm_df_neg(b)).hi);
    }
    std::printf("worst errors / u^2: add %.3Lf, add float %.3Lf, times float %.3Lf, times df %.3Lf, sloppy add %.3Lf\n",
                worst_add, worst_add_f, worst_mul_f, worst_mul, worst_sloppy);
    EXPECT_LE(worst_add, 3.0L);
    EXPECT_LE(worst_add_f, 2.0L);
    EXPECT_LE(worst_mul_f, 2.0L);
    EXPECT_LE(worst_mul, 5.0L);
    EXPECT_LE(worst_sloppy, 3.0L);
}

// lerp(a, b, 0) is a bit for bit (the texel itself at a texel centre); in between within
// ~5u^2 (|a| + |b|) (sloppy additions and one product).
TEST_F(MathDf, LerpIsExactAtZeroAndAccurateBetween) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    for (int trial = 0; trial < 100000; ++trial) {
        msm_df a = random_df(2), b = uniform(0.0, 1.0) < 0.5 ? random_df(2) : partner(a);
        float t = trial % 10 == 0 ? 0.0f : static_cast<float>(uniform(0.0, 1.0));
        msm_df blend = msm_df_lerp(a, b, t);
        msm_df blend_f = msm_df_lerp_f(a.hi, b.hi, t);
        if (t == 0.0f) {
            ASSERT_EQ(blend.hi, a.hi);
            ASSERT_EQ(blend.lo, a.lo);
            ASSERT_EQ(blend_f.hi, a.hi);
            ASSERT_EQ(blend_f.lo, 0.0f);
        }
        const Long scale = std::fabs(value(a)) + std::fabs(value(b));
        ASSERT_LE(std::fabs(value(blend) - (value(a) + t * (value(b) - value(a)))), 5 * u2 * scale) << trial;
        const Long exact_f = static_cast<Long>(a.hi) + t * (static_cast<Long>(b.hi) - a.hi);
        ASSERT_LE(std::fabs(value(blend_f) - exact_f), 5 * u2 * scale) << trial;
    }
}

// The constants carry 48 bits; code/65535 within 3u^2 (product 2u^2, constant 1e-19) for
// every code.
TEST(MathDfConstants, ConstantsAndUnormCodes) {
    auto relative = [](msm_df a, Long exact) { return std::fabs(value(a) - exact) / exact; };
    EXPECT_LE(relative(msm_df_make(MSM_DF_THIRD_HI, MSM_DF_THIRD_LO), 1.0L / 3), u2);
    EXPECT_LE(relative(msm_df_make(MSM_DF_SQRT3_HI, MSM_DF_SQRT3_LO), std::sqrt(3.0L)), u2);
    EXPECT_LE(relative(msm_df_make(MSM_DF_SQRT3_3_4_HI, MSM_DF_SQRT3_3_4_LO), 0.75L * std::sqrt(3.0L)), u2);
    EXPECT_LE(relative(msm_df_make(MSM_DF_INV_65535_HI, MSM_DF_INV_65535_LO), 1.0L / 65535), u2);
    for (int code = 1; code <= 65535; ++code)
        ASSERT_LE(relative(msm_df_unorm16(static_cast<float>(code)), code / 65535.0L), 3 * u2) << code;
    EXPECT_EQ(value(msm_df_unorm16(0.0f)), 0.0L);
}

// ---- Decoding, blending and moments about the mean.

namespace {

ref::Moments to_ref(const msm_moments_df& m) {
    return {static_cast<double>(value(m.b1)), static_cast<double>(value(m.b2)), static_cast<double>(value(m.b3)),
            static_cast<double>(value(m.b4))};
}

double max_difference(const msm_moments_df& m, const ref::Moments& r) {
    return static_cast<double>(std::max({std::fabs(value(m.b1) - r.b1), std::fabs(value(m.b2) - r.b2),
                                         std::fabs(value(m.b3) - r.b3), std::fabs(value(m.b4) - r.b4)}));
}

msm_word2 random_word2(std::mt19937_64& rng) {
    msm_word2 w;
    w.w0 = static_cast<std::uint32_t>(rng());
    w.w1 = static_cast<std::uint32_t>(rng());
    return w;
}

ref::Moments reference_decode(msm_word2 w) {
    return ref::decode_msm64({static_cast<std::uint16_t>(w.w0 & 0xffffu), static_cast<std::uint16_t>(w.w0 >> 16),
                              static_cast<std::uint16_t>(w.w1 & 0xffffu), static_cast<std::uint16_t>(w.w1 >> 16)});
}

// Moments of a random 1..4-point distribution on [-1,1] with an occasional tight cluster.
ref::Moments random_moments(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    ref::Distribution d;
    const int k = 1 + static_cast<int>(4 * unit(rng));
    const double spread = unit(rng) < 0.5 ? 2.0 : 1e-3;
    const double centre = 2 * unit(rng) - 1;
    for (int i = 0; i < k; ++i) {
        d.depth.push_back(std::clamp(centre + spread * (unit(rng) - 0.5), -1.0, 1.0));
        d.weight.push_back(0.05 + unit(rng));
    }
    return ref::moments_of(d);
}

msm_moments to_float(const ref::Moments& m) {
    msm_moments r;
    r.b1 = static_cast<float>(m.b1);
    r.b2 = static_cast<float>(m.b2);
    r.b3 = static_cast<float>(m.b3);
    r.b4 = static_cast<float>(m.b4);
    return r;
}

ref::Moments to_ref(const msm_moments& m) { return {m.b1, m.b2, m.b3, m.b4}; }

} // namespace

// msm64 decode in float-float vs the double reference (1e-16): every product and sum is
// within ~5u^2 = 2e-14 of values <= 1.4; the float32 decode is printed for contrast (~1e-7).
TEST_F(MathDf, Msm64DecodeMatchesReference) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    double worst = 0, worst_float = 0;
    for (int trial = 0; trial < 100000; ++trial) {
        msm_word2 w = random_word2(rng_);
        const ref::Moments expected = reference_decode(w);
        worst = std::max(worst, max_difference(msm_decode_msm64_df(w), expected));
        worst_float = std::max(worst_float, max_difference(msm_moments_df_from_float(msm_decode_msm64(w)), expected));
    }
    std::printf("msm64 decode: float-float max error %.3g, float32 %.3g\n", worst, worst_float);
    EXPECT_LE(worst, 5e-14);
}

// Decoding the blended codes is blending the decoded moments (the decode is affine).
TEST_F(MathDf, Msm64CodeBlendDecodesLikeBlendedMoments) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    for (int trial = 0; trial < 20000; ++trial) {
        msm_word2 w[4] = {random_word2(rng_), random_word2(rng_), random_word2(rng_), random_word2(rng_)};
        const float tx = static_cast<float>(uniform(0.0, 1.0)), ty = static_cast<float>(uniform(0.0, 1.0));
        const msm_moments_df got = msm_decode_msm64_codes_df(msm_codes16_df_bilinear(w[0], w[1], w[2], w[3], tx, ty));
        const double weights[4] = {(1.0 - tx) * (1.0 - ty), tx * (1.0 - ty), (1.0 - tx) * ty, double(tx) * ty};
        ref::Moments expected;
        for (int k = 0; k < 4; ++k) {
            const ref::Moments m = reference_decode(w[k]);
            expected.b1 += weights[k] * m.b1;
            expected.b2 += weights[k] * m.b2;
            expected.b3 += weights[k] * m.b3;
            expected.b4 += weights[k] * m.b4;
        }
        ASSERT_LE(max_difference(got, expected), 5e-14) << "trial " << trial;
    }
}

// Moments about c = b1 by float-float Horner vs ref::shift (long double) of the same float
// moments: absolute errors ~u^2 times the Horner terms (<= ~6): bound 1e-13.
TEST_F(MathDf, MomentsAboutTheMeanMatchReference) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    double worst = 0;
    for (int trial = 0; trial < 100000; ++trial) {
        const msm_moments raw = to_float(random_moments(rng_));
        const float c = trial % 3 == 0 ? static_cast<float>(uniform(-1.0, 1.0)) : raw.b1;
        worst = std::max(worst, max_difference(msm_moments_df_about(msm_moments_df_from_float(raw), c),
                                               ref::shift(to_ref(raw), c)));
    }
    std::printf("moments about c: max error %.3g\n", worst);
    EXPECT_LE(worst, 1e-13);
}

// The bias applied about c equals the bias of docs/math.md applied first (double) and then shifted. The
// correction alpha (t - m) is float32: t up to 5.4 (c = +-1) carries ~2 ulps (1e-6), times
// alpha: 3e-13 for moments128, 6e-11 for msm64; against biased central moments >= ~alpha/10.
TEST_F(MathDf, BiasAboutTheMeanMatchesReference) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    double worst[2] = {0, 0};
    for (int trial = 0; trial < 100000; ++trial) {
        const msm_moments raw = to_float(random_moments(rng_));
        const int msm64 = trial % 2;
        const float alpha = msm64 ? MSM_ALPHA_MSM64 : MSM_ALPHA_FLOAT, bstar = msm64 ? MSM_BSTAR_MSM64 : MSM_BSTAR_FLOAT;
        const float c = raw.b1;
        const msm_moments_df got = msm_bias_about_df(msm_moments_df_about(msm_moments_df_from_float(raw), c), c, alpha, bstar);
        worst[msm64] = std::max(worst[msm64], max_difference(got, ref::shift(ref::bias(to_ref(raw), alpha, bstar), c)));
    }
    std::printf("biased moments about c: max error moments128 %.3g, msm64 %.3g\n", worst[0], worst[1]);
    EXPECT_LE(worst[0], 1e-12);
    EXPECT_LE(worst[1], 2e-10);
}

// ---- Accurate shading of the linear formats.

namespace {

// What the double reconstruction gives for UNBIASED moments b.
double reference_lower(const ref::Moments& b, double alpha, double bstar, double zf) {
    return ref::hamburger4(ref::bias(b, alpha, bstar), zf).lower;
}

} // namespace

// Flat regions: texels of one surface with a spread of 0..3e-4 (the filter's float32 moments
// of it), receivers up to 5e-3 in front of and behind it. The biased variance there is ~1e-7:
// the fast float32 path keeps one or two digits of it (printed), the accurate path must agree
// with the double reconstruction of the same stored texel within 1e-4.
TEST_F(MathDf, FlatTexelsMatchTheDoubleReconstruction) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    double worst[2] = {0, 0}, worst_fast[2] = {0, 0};
    for (int trial = 0; trial < 3000; ++trial) {
        const double z = uniform(-0.99, 0.99), spread = uniform(0.0, 3e-4);
        ref::Distribution d;
        for (int k = 0; k < 4; ++k) {
            d.depth.push_back(z + spread * uniform(-0.5, 0.5));
            d.weight.push_back(uniform(0.1, 1.0));
        }
        const msm_moments stored = to_float(ref::moments_of(d));
        const msm_word2 word = msm_encode_msm64(stored);
        for (int j = 0; j < 41; ++j) {
            const float zf = static_cast<float>(z + 5e-3 * (j - 20) / 20.0);
            // moments128: the stored floats are the texel.
            const double expected128 = reference_lower(to_ref(stored), ref::alpha_float, ref::bstar_float, zf);
            worst[0] = std::max(worst[0], std::fabs(msm_shadow_moments128(stored, zf) - expected128));
            worst_fast[0] = std::max(worst_fast[0], std::fabs(msm_shadow_moments128_fast(stored, zf) - expected128));
            // msm64: the codes are the texel.
            const double expected64 = reference_lower(reference_decode(word), ref::alpha_msm64, ref::bstar_msm64, zf);
            worst[1] = std::max(worst[1], std::fabs(msm_shadow_msm64(word, zf) - expected64));
            worst_fast[1] = std::max(worst_fast[1], std::fabs(msm_shadow_msm64_fast(word, zf) - expected64));
        }
    }
    std::printf("flat texels, max error vs double: moments128 accurate %.3g (fast %.3g), msm64 accurate %.3g (fast %.3g)\n",
                worst[0], worst_fast[0], worst[1], worst_fast[1]);
    EXPECT_LE(worst[0], 1e-4);
    EXPECT_LE(worst[1], 1e-4);
}

// Any texel: 1..4 depths, spread or clustered, receivers on a grid but not within 1e-3 of a
// depth of the texel (there the bound is a step and float32 zf itself decides). Within 1e-4
// of the double reconstruction (the remaining error is the float32 solve, measured ~1e-5).
TEST_F(MathDf, AnyTexelMatchesTheDoubleReconstructionAwayFromItsDepths) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    double worst[2] = {0, 0};
    for (int trial = 0; trial < 3000; ++trial) {
        ref::Distribution d;
        const int k = 1 + trial % 4;
        const double centre = uniform(-0.9, 0.9), spread = trial % 3 == 0 ? 2e-2 : 1.0;
        for (int i = 0; i < k; ++i) {
            d.depth.push_back(std::clamp(centre + spread * uniform(-0.5, 0.5), -1.0, 1.0));
            d.weight.push_back(uniform(0.05, 1.0));
        }
        const msm_moments stored = to_float(ref::moments_of(d));
        const msm_word2 word = msm_encode_msm64(stored);
        for (int j = 0; j < 81; ++j) {
            const float zf = static_cast<float>(-1.0 + 2.0 * j / 80);
            double nearest = 2;
            for (double depth : d.depth) nearest = std::min(nearest, std::fabs(zf - depth));
            if (nearest < 1e-3) continue;
            worst[0] = std::max(worst[0], std::fabs(msm_shadow_moments128(stored, zf) -
                                                    reference_lower(to_ref(stored), ref::alpha_float, ref::bstar_float, zf)));
            worst[1] = std::max(worst[1], std::fabs(msm_shadow_msm64(word, zf) - reference_lower(reference_decode(word), ref::alpha_msm64,
                                                                                                  ref::bstar_msm64, zf)));
        }
    }
    std::printf("any texel, max error vs double: moments128 %.3g, msm64 %.3g\n", worst[0], worst[1]);
    EXPECT_LE(worst[0], 1e-4);
    EXPECT_LE(worst[1], 1e-4);
}

// The bilinear functions at weights (0, 0) are the texel (bit for bit), and their blend is
// the blend of the moments.
TEST_F(MathDf, BilinearAtATexelCentreIsTheTexel) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    for (int trial = 0; trial < 2000; ++trial) {
        msm_moments m[4];
        msm_word2 w[4];
        for (int k = 0; k < 4; ++k) {
            m[k] = to_float(random_moments(rng_));
            w[k] = msm_encode_msm64(m[k]);
        }
        const float zf = static_cast<float>(uniform(-1.0, 1.0));
        ASSERT_EQ(msm_shadow_moments128_bilinear(m[0], m[1], m[2], m[3], 0.0f, 0.0f, zf), msm_shadow_moments128(m[0], zf));
        ASSERT_EQ(msm_shadow_msm64_bilinear(w[0], w[1], w[2], w[3], 0.0f, 0.0f, zf), msm_shadow_msm64(w[0], zf));
        // Between texels: the double reconstruction of the blended moments. Receivers are not
        // kept away from the texels' depths here, hence 1e-3 (errors measured ~1e-5).
        const float tx = static_cast<float>(uniform(0.0, 1.0)), ty = static_cast<float>(uniform(0.0, 1.0));
        const double weights[4] = {(1.0 - tx) * (1.0 - ty), tx * (1.0 - ty), (1.0 - tx) * ty, double(tx) * ty};
        ref::Moments blend;
        for (int k = 0; k < 4; ++k) {
            blend.b1 += weights[k] * m[k].b1;
            blend.b2 += weights[k] * m[k].b2;
            blend.b3 += weights[k] * m[k].b3;
            blend.b4 += weights[k] * m[k].b4;
        }
        EXPECT_NEAR(msm_shadow_moments128_bilinear(m[0], m[1], m[2], m[3], tx, ty, zf),
                    reference_lower(blend, ref::alpha_float, ref::bstar_float, zf), 1e-3)
            << "trial " << trial;
    }
}

// The host API's linear_shadow is the per-texel shading of moments128 (and of msm64 moments).
TEST_F(MathDf, HostLinearShadowIsTheTexelShading) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    for (int trial = 0; trial < 2000; ++trial) {
        const msm_moments m = to_float(random_moments(rng_));
        const float zf = static_cast<float>(uniform(-1.0, 1.0));
        ASSERT_EQ(msmcl::linear_shadow({m.b1, m.b2, m.b3, m.b4}, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT, zf),
                  msm_shadow_moments128(m, zf));
        ASSERT_EQ(msmcl::linear_shadow({m.b1, m.b2, m.b3, m.b4}, MSM_ALPHA_MSM64, MSM_BSTAR_MSM64, zf),
                  msm_shadow_msm64_decoded(m, zf));
    }
}

// Whatever the input (invalid moments, random words, far-away fragments): finite, in [0,1].
TEST_F(MathDf, AnyInputGivesAnIntensityInZeroOne) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    for (int trial = 0; trial < 20000; ++trial) {
        msm_moments m[4];
        msm_word2 w[4];
        for (int k = 0; k < 4; ++k) {
            m[k].b1 = static_cast<float>(uniform(-1.0, 1.0));
            m[k].b2 = static_cast<float>(uniform(0.0, 1.0));
            m[k].b3 = static_cast<float>(uniform(-1.0, 1.0));
            m[k].b4 = static_cast<float>(uniform(0.0, 1.0));
            w[k] = random_word2(rng_);
        }
        const float zf = trial % 11 == 0 ? (trial % 2 ? 1e30f : -1e30f) : static_cast<float>(uniform(-1.1, 1.1));
        const float tx = static_cast<float>(uniform(0.0, 1.0)), ty = static_cast<float>(uniform(0.0, 1.0));
        for (float intensity : {msm_shadow_moments128(m[0], zf), msm_shadow_msm64(w[0], zf),
                            msm_shadow_moments128_bilinear(m[0], m[1], m[2], m[3], tx, ty, zf),
                            msm_shadow_msm64_bilinear(w[0], w[1], w[2], w[3], tx, ty, zf)})
            ASSERT_TRUE(intensity >= 0.0f && intensity <= 1.0f) << intensity << " trial " << trial;
    }
}
