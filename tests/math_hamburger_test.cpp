// Hamburger 4MSM (kernels/msm_shading.clh, float32: the GDC HLSL with the fixes of docs/math.md) against
// the independent double generic 4MSM (Algorithm 1 of Peters, HPG 2017) of host/reference, and
// checks of that reference itself against exact shares of discrete distributions.
#include <msmcl/device_math.hpp>

#include "kernels/msm_shading.clh"
#include "reference/moment_math.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <random>
#include <string>

#include "seeded_test.hpp"

namespace ref = msmcl::reference;

namespace {

class MathHamburger : public msmcl::testing::SeededTest {
protected:
    ref::Distribution random_distribution(int k) {
        ref::Distribution d;
        for (int i = 0; i < k; ++i) {
            d.depth.push_back(uniform(-1.0, 1.0));
            d.weight.push_back(uniform(0.05, 1.0));
        }
        return d;
    }
};

msm_moments to_float(const ref::Moments& m) {
    msm_moments r;
    r.b1 = static_cast<float>(m.b1);
    r.b2 = static_cast<float>(m.b2);
    r.b3 = static_cast<float>(m.b3);
    r.b4 = static_cast<float>(m.b4);
    return r;
}

msmcl::Moments4 to_api(const msm_moments& m) { return {m.b1, m.b2, m.b3, m.b4}; }

double variance(const ref::Moments& m) { return m.b2 - m.b1 * m.b1; }

double grid_depth(int j, int count) { return -1.02 + 2.04 * j / (count - 1); }

// Largest b4 change that keeps the moments valid (b4 >= the two-point limit).
ref::Moments with_b4_offset(ref::Moments m, double offset) {
    double floor_b4 = m.b4 - ref::nlq_from_moments(m).xi4;
    m.b4 = std::max(m.b4 + offset, floor_b4);
    return m;
}

} // namespace

// ---- The reference itself.

// Sharp bounds of exact moments of 3..5-point distributions: lower <= true share below zf,
// true share at or below zf <= upper. Tolerance 1e-6: the moments are doubles (1e-16) and
// the Hankel matrix of nearby depths has condition numbers up to ~1e10 (measured 5e-7).
TEST_F(MathHamburger, ReferenceBoundsEncloseTheTruth) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    for (int trial = 0; trial < 2000; ++trial) {
        ref::Distribution d = random_distribution(3 + trial % 3);
        ref::Moments exact = ref::moments_of(d);
        for (int j = 0; j < 41; ++j) {
            double zf = grid_depth(j, 41);
            ref::Bounds bounds = ref::hamburger4(exact, zf);
            double below = ref::exact_shadow(d, zf);
            double at_or_below = ref::exact_shadow(d, std::nextafter(zf, 2.0));
            ASSERT_LE(bounds.lower, below + 1e-6) << "trial " << trial << " zf " << zf;
            ASSERT_GE(bounds.upper, at_or_below - 1e-6) << "trial " << trial << " zf " << zf;
            ASSERT_LE(bounds.lower, bounds.upper + 1e-12);
        }
    }
}

// The bound is sharp: on the three-point distribution {zf, z1, z2} that the algorithm
// reconstructs, the lower bound is exactly the share below zf and the upper adds zf's weight.
TEST_F(MathHamburger, ReferenceBoundsAreAttainedByThreePointDistributions) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    for (int trial = 0; trial < 2000; ++trial) {
        ref::Distribution d = random_distribution(3);
        if (std::min({std::fabs(d.depth[0] - d.depth[1]), std::fabs(d.depth[0] - d.depth[2]),
                      std::fabs(d.depth[1] - d.depth[2])}) < 0.05)
            continue;
        // Evaluated at one of its own depths, the distribution is the minimizer.
        double zf = d.depth[trial % 3];
        ref::Bounds bounds = ref::hamburger4(ref::moments_of(d), zf);
        double total = d.weight[0] + d.weight[1] + d.weight[2];
        ASSERT_NEAR(bounds.lower, ref::exact_shadow(d, zf), 1e-9) << "trial " << trial;
        ASSERT_NEAR(bounds.upper - bounds.lower, d.weight[trial % 3] / total, 1e-9) << "trial " << trial;
    }
}

// Algorithm 2 in double and Eq. 4 are consistent: the texel of biased moments rebuilds
// those moments, so the texel's shadow is the moments' shadow.
TEST_F(MathHamburger, ReferenceNlqRebuildsItsMoments) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    for (int trial = 0; trial < 2000; ++trial) {
        ref::Moments biased = ref::bias(ref::moments_of(random_distribution(2 + trial % 4)), ref::alpha_float,
                                        ref::bstar_float);
        ref::Nlq texel = ref::nlq_from_moments(biased);
        ASSERT_LE(texel.y1, texel.y2);
        ASSERT_GE(texel.xi4, 0.0);
        ASSERT_LE(texel.xi4, 0.25);
        ref::Moments rebuilt = ref::moments_from_nlq(texel);
        ASSERT_NEAR(rebuilt.b1, biased.b1, 1e-12) << "trial " << trial;
        ASSERT_NEAR(rebuilt.b2, biased.b2, 1e-12) << "trial " << trial;
        ASSERT_NEAR(rebuilt.b3, biased.b3, 1e-12) << "trial " << trial;
        ASSERT_NEAR(rebuilt.b4, biased.b4, 1e-12) << "trial " << trial;
    }
}

// ---- float32 Hamburger vs the reference.

// xi4 far above float32 rounding: lower and upper within 2e-3 (xi4 >= 1e-4 known to relative
// ~1e-3 in float32, see math_nlq_test; measured max ~5e-4).
TEST_F(MathHamburger, LowerAndUpperMatchReferenceWhenWellConditioned) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    int compared = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        ref::Moments exact = ref::moments_of(random_distribution(3 + trial % 3));
        ref::Moments biased = ref::bias(exact, ref::alpha_float, ref::bstar_float);
        ref::Nlq texel = ref::nlq_from_moments(biased);
        if (texel.xi4 < 1e-4 || texel.y2 - texel.y1 < 0.05) continue;
        msmcl::Moments4 biased_float =
            msmcl::bias_moments(to_api(to_float(exact)), MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT);
        for (int j = 0; j < 61; ++j) {
            double zf = grid_depth(j, 61);
            ref::Bounds expected = ref::hamburger4(biased, zf);
            ASSERT_NEAR(msmcl::hamburger4_lower(biased_float, static_cast<float>(zf)), expected.lower, 2e-3)
                << "trial " << trial << " zf " << zf;
            ASSERT_NEAR(msmcl::hamburger4_upper(biased_float, static_cast<float>(zf)), expected.upper, 2e-3)
                << "trial " << trial << " zf " << zf;
            ++compared;
        }
    }
    EXPECT_GT(compared, 10000);
}

// All 2..5-point distributions: within the double bounds' envelope under float32 errors
// (b4 +-1e-6, zf +-(1e-4 + 2e-6/sigma2), 1e-5; as in math_nlq_test). Lower falls and upper
// rises as b4 grows; both rise with zf. The last step of the GDC code divides by
// (zf - z1)(z2 - z1) and loses ~3e-8/distance next to a depth: allowed 1e-7/distance. The
// upper bound's w0 = 1/(1 + f1^2/D22 + f2^2/D33) inherits float32 noise of the pivots where
// D33 = xi4 is at its floor: 2e-4 more for it (measured 7.3e-5 over 100 seeds).
TEST_F(MathHamburger, LowerAndUpperWithinFloatEnvelopeOfReference) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    const double db4 = 1e-6, eps = 1e-5;
    for (int trial = 0; trial < 2000; ++trial) {
        ref::Distribution d = random_distribution(2 + trial % 4);
        ref::Moments exact = ref::moments_of(d);
        if (variance(exact) < 1e-5) continue;
        double dz = 1e-4 + 2e-6 / variance(exact);
        ref::Moments biased = ref::bias(exact, ref::alpha_float, ref::bstar_float);
        ref::Moments more_b4 = with_b4_offset(biased, db4), less_b4 = with_b4_offset(biased, -db4);
        msmcl::Moments4 biased_float =
            msmcl::bias_moments(to_api(to_float(exact)), MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT);
        for (int j = 0; j < 81; ++j) {
            double zf = grid_depth(j, 81);
            double nearest = 2;
            for (double depth : d.depth) nearest = std::min(nearest, std::fabs(zf - depth));
            double slack = eps + 1e-7 / nearest;
            float lower = msmcl::hamburger4_lower(biased_float, static_cast<float>(zf));
            float upper = msmcl::hamburger4_upper(biased_float, static_cast<float>(zf));
            ASSERT_GE(lower, ref::hamburger4(more_b4, zf - dz).lower - slack) << "trial " << trial << " zf " << zf;
            ASSERT_LE(lower, ref::hamburger4(less_b4, zf + dz).lower + slack) << "trial " << trial << " zf " << zf;
            ASSERT_GE(upper, ref::hamburger4(less_b4, zf - dz).upper - slack - 2e-4) << "trial " << trial << " zf " << zf;
            ASSERT_LE(upper, ref::hamburger4(more_b4, zf + dz).upper + slack + 2e-4) << "trial " << trial << " zf " << zf;
        }
    }
}

// msm64 texels: decode, bias 6e-5 / 0.628, lower bound; against the reference on the same
// codes (decoded and biased in double). The bigger bias keeps xi4 >= ~1e-5, so float32
// (b4 +-1e-6) matters less; the same envelope applies.
TEST_F(MathHamburger, Msm64TexelsMatchReference) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    const double db4 = 1e-6, dz = 1e-4, eps = 1e-5;
    for (int trial = 0; trial < 1500; ++trial) {
        ref::Distribution d = random_distribution(1 + trial % 5);
        msm_word2 w = msm_encode_msm64(to_float(ref::moments_of(d)));
        ref::Codes16 codes = {static_cast<std::uint16_t>(w.w0 & 0xffffu), static_cast<std::uint16_t>(w.w0 >> 16),
                              static_cast<std::uint16_t>(w.w1 & 0xffffu), static_cast<std::uint16_t>(w.w1 >> 16)};
        ref::Moments biased = ref::bias(ref::decode_msm64(codes), ref::alpha_msm64, ref::bstar_msm64);
        ref::Moments more_b4 = with_b4_offset(biased, db4), less_b4 = with_b4_offset(biased, -db4);
        for (int j = 0; j < 61; ++j) {
            double zf = grid_depth(j, 61);
            float actual = msm_shadow_msm64(w, static_cast<float>(zf));
            ASSERT_GE(actual, ref::hamburger4(more_b4, zf - dz).lower - eps) << "trial " << trial << " zf " << zf;
            ASSERT_LE(actual, ref::hamburger4(less_b4, zf + dz).lower + eps) << "trial " << trial << " zf " << zf;
        }
    }
}

// A single depth (zero variance in float32) is a step at that depth.
TEST_F(MathHamburger, SingleDepthIsAStep) {
    for (float z : {-1.0f, -0.3f, 0.0f, 0.7f, 1.0f}) {
        msm_moments m = msm_moments_of(z);
        EXPECT_EQ(msm_hamburger4_lower(m, z - 0.01f), 0.0f);
        EXPECT_EQ(msm_hamburger4_lower(m, z), 0.0f);
        EXPECT_EQ(msm_hamburger4_upper(m, z), 1.0f);
        EXPECT_EQ(msm_hamburger4_lower(m, z + 0.01f), 1.0f);
        // With the float32 bias: a soft step around z, still 0 well below and 1 well above.
        msm_moments biased = msm_bias(m, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT);
        EXPECT_NEAR(msm_hamburger4_lower(biased, z - 0.1f), 0.0f, 1e-4);
        if (z < 0.9f) {
            EXPECT_NEAR(msm_hamburger4_lower(biased, z + 0.1f), 1.0f, 1e-4);
        }
    }
}

// Whatever the input (invalid moments, degenerate texels, far-away fragments), results are
// finite and in [0,1]: the shading functions never hand a renderer NaN.
TEST_F(MathHamburger, AnyInputGivesAnIntensityInZeroOne) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    auto check = [](float value, const char* what, int trial) {
        ASSERT_TRUE(value >= 0.0f && value <= 1.0f) << what << " " << value << " trial " << trial;
    };
    for (int trial = 0; trial < 20000; ++trial) {
        msm_moments m;
        m.b1 = static_cast<float>(uniform(-1.0, 1.0));
        m.b2 = static_cast<float>(uniform(0.0, 1.0));
        m.b3 = static_cast<float>(uniform(-1.0, 1.0));
        m.b4 = static_cast<float>(uniform(0.0, 1.0));
        msm_nlq t;
        t.y1 = static_cast<float>(uniform(-1.0, 1.0));
        t.y2 = trial % 3 == 0 ? t.y1 : static_cast<float>(uniform(t.y1, 1.0));
        t.v2 = trial % 5 == 0 ? static_cast<float>(trial % 2) : static_cast<float>(uniform(0.0, 1.0));
        t.xi4 = trial % 7 == 0 ? 0.0f : static_cast<float>(std::pow(10.0, uniform(-30.0, std::log10(0.25))));
        float zf = trial % 11 == 0 ? (trial % 2 ? 1e30f : -1e30f) : static_cast<float>(uniform(-1.1, 1.1));
        check(msm_hamburger4_lower(m, zf), "lower", trial);
        check(msm_hamburger4_upper(m, zf), "upper", trial);
        check(msm_shadow_moments128(m, zf), "moments128", trial);
        check(msm_nlq_shadow(t, zf), "nlq", trial);
        check(msm_nlq_shadow(t, t.y1 + 1e-7f), "nlq at y1", trial);
        check(msm_nlq_shadow(t, t.y2), "nlq at y2", trial);
        check(msm_nlq_shadow(msm_nlq_from_moments(msm_bias(m, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT)), zf), "alg2+3", trial);
        msm_word2 w;
        w.w0 = static_cast<std::uint32_t>(rng_());
        w.w1 = static_cast<std::uint32_t>(rng_());
        check(msm_shadow_msm64(w, zf), "msm64", trial);
        check(msm_shadow_nlq64(w, zf), "nlq64", trial);
        check(msm_shadow_nlq32(w.w0, zf), "nlq32", trial);
    }
}
