// Algorithm 2 + Algorithm 3 (kernels/msm_moments.clh, msm_shading.clh through
// msmcl/device_math.hpp, float32) against the independent double-precision generic 4MSM of
// host/reference/moment_math.*, plus the shifted-frame variant of Algorithm 2.
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
#include <random>
#include <string>

#include "seeded_test.hpp"

namespace ref = msmcl::reference;

namespace {

class MathNlq : public msmcl::testing::SeededTest {
protected:
    // k depths uniform in [lo, hi], weights uniform in [0.05, 1].
    ref::Distribution random_distribution(int k, double lo = -1.0, double hi = 1.0) {
        ref::Distribution d;
        for (int i = 0; i < k; ++i) {
            d.depth.push_back(uniform(lo, hi));
            d.weight.push_back(uniform(0.05, 1.0));
        }
        return d;
    }
};

msmcl::Moments4 to_float(const ref::Moments& m) {
    return {static_cast<float>(m.b1), static_cast<float>(m.b2), static_cast<float>(m.b3),
            static_cast<float>(m.b4)};
}

ref::Nlq to_double(const msmcl::NlqTexel& t) { return {t.y1, t.y2, t.v2, t.xi4}; }

// The float32 pipeline: float moments, float bias, Algorithm 2.
msmcl::NlqTexel float_nlq(const ref::Moments& exact) {
    return msmcl::nlq_from_moments(msmcl::bias_moments(to_float(exact), MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT));
}

ref::Moments reference_biased(const ref::Moments& exact) {
    return ref::bias(exact, ref::alpha_float, ref::bstar_float);
}

double variance(const ref::Moments& m) { return m.b2 - m.b1 * m.b1; }

// Fragment depths on a grid slightly wider than [-1,1].
double grid_depth(int j, int count) { return -1.02 + 2.04 * j / (count - 1); }

} // namespace

// Distributions whose xi4 is far above float32 rounding: the float pipeline must match the
// double generic 4MSM closely. Tolerance 2e-3: float32 xi4 = b4 - b2^2 - L21^2 sigma2 cancels
// terms of size <= 1, an absolute error of a few 1e-7, i.e. a relative error <= ~1e-3 for
// xi4 >= 1e-4, and the bound changes by less than that relative change (measured max 5e-4).
TEST_F(MathNlq, Algorithm23MatchesGeneric4MsmWhenWellConditioned) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    int compared = 0;
    double worst = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        ref::Distribution d = random_distribution(3 + trial % 3);
        ref::Moments exact = ref::moments_of(d);
        ref::Nlq expected_nlq = ref::nlq_from_moments(reference_biased(exact));
        if (expected_nlq.xi4 < 1e-4 || expected_nlq.y2 - expected_nlq.y1 < 0.05) continue;
        msmcl::NlqTexel texel = float_nlq(exact);
        for (int j = 0; j < 61; ++j) {
            double zf = grid_depth(j, 61);
            double expected = ref::hamburger4(reference_biased(exact), zf).lower;
            double actual = msmcl::nlq_shadow(texel, static_cast<float>(zf));
            worst = std::max(worst, std::fabs(actual - expected));
            ASSERT_NEAR(actual, expected, 2e-3) << "trial " << trial << " zf " << zf;
            ++compared;
        }
    }
    std::printf("well-conditioned: %d comparisons, max |float - double| = %.3g\n", compared, worst);
    EXPECT_GT(compared, 10000);
}

// All 2..5-point distributions (depth spread not below float32 resolution): the bound is
// ill-conditioned near the steps when xi4 is at the bias level (~1e-7), so the float result
// is compared with the double bound's envelope under the float32 errors: b4 changed by
// +-1e-6 (8 ulps of 1: rounding of b1..b4 and of the ~10 operations of xi4, all on terms
// <= 1; the bound falls as b4 grows), zf shifted by +-(1e-4 + 2e-6/sigma2) (depth error of
// y1, y2, see TwoPointDistributionsReconstructThroughAlgorithm2; the bound rises with zf),
// plus 1e-5. Measured excess: ~1e-6.
TEST_F(MathNlq, Algorithm23WithinFloatEnvelopeOfGeneric4Msm) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    const double db4 = 1e-6, eps = 1e-5;
    int compared = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        int k = 2 + trial % 4;
        ref::Distribution d = random_distribution(k);
        ref::Moments exact = ref::moments_of(d);
        if (variance(exact) < 1e-5) continue;
        double dz = 1e-4 + 2e-6 / variance(exact);
        ref::Moments biased = reference_biased(exact);
        ref::Moments more_b4 = biased, less_b4 = biased;
        more_b4.b4 += db4;
        // Not below the two-point limit, where b4 stops being a valid moment.
        less_b4.b4 = std::max(biased.b4 - db4, biased.b4 - ref::nlq_from_moments(biased).xi4);
        msmcl::NlqTexel texel = float_nlq(exact);
        for (int j = 0; j < 81; ++j) {
            double zf = grid_depth(j, 81);
            double low = ref::hamburger4(more_b4, zf - dz).lower;
            double high = ref::hamburger4(less_b4, zf + dz).lower;
            double actual = msmcl::nlq_shadow(texel, static_cast<float>(zf));
            ASSERT_GE(actual, low - eps) << "k " << k << " trial " << trial << " zf " << zf;
            ASSERT_LE(actual, high + eps) << "k " << k << " trial " << trial << " zf " << zf;
            ++compared;
        }
    }
    EXPECT_GT(compared, 100000);
}

// Algorithm 3 alone: float on a texel vs the double generic 4MSM on the moments rebuilt
// from the same texel (Eq. 4; both with Algorithm 3's clamps). Envelope: zf +-1e-6 (a few ulps of (zf - y1)/(y2 - y1) near
// the steps, which are ~sqrt(xi4) wide) plus 2e-5 (float32 evaluation of the weight).
TEST_F(MathNlq, Algorithm3MatchesGenericOnTheSameTexel) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    const double dz = 1e-6, eps = 2e-5;
    for (int trial = 0; trial < 2000; ++trial) {
        msmcl::NlqTexel texel;
        texel.y1 = static_cast<float>(uniform(-1.0, 0.9));
        texel.y2 = static_cast<float>(std::min(1.0, texel.y1 + std::pow(10.0, uniform(-3.0, 0.3))));
        texel.v2 = static_cast<float>(uniform(0.01, 0.99));
        // Every fifth texel degenerate: one depth, v2 = 0 or 1 (Algorithm 3's clamps apply).
        if (trial % 5 == 0) texel.y2 = trial % 10 == 0 ? texel.y1 : texel.y2;
        if (trial % 5 == 1) texel.v2 = static_cast<float>(trial % 2);
        texel.xi4 = msmcl::psi4_inverse(static_cast<float>(uniform(0.0, 1.0)));
        ref::Nlq exact = to_double(texel);
        for (int j = 0; j < 81; ++j) {
            double zf = grid_depth(j, 81);
            float actual = msmcl::nlq_shadow(texel, static_cast<float>(zf));
            double low = ref::nlq_shadow(exact, zf - dz);
            double high = ref::nlq_shadow(exact, zf + dz);
            ASSERT_GE(actual, low - eps) << "trial " << trial << " zf " << zf;
            ASSERT_LE(actual, high + eps) << "trial " << trial << " zf " << zf;
        }
    }
}

// Exact two-point texels (xi4 = 0) give the exact step function (the xi floor 1e-12 of
// Algorithm 3 softens the steps within ~1e-5 of each depth only).
TEST_F(MathNlq, TwoPointTexelsReconstructExactly) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    for (int trial = 0; trial < 2000; ++trial) {
        ref::Distribution d = random_distribution(2);
        if (std::fabs(d.depth[0] - d.depth[1]) < 1e-3) continue;
        ref::Nlq exact = ref::nlq_from_moments(ref::moments_of(d));
        msmcl::NlqTexel texel{static_cast<float>(exact.y1), static_cast<float>(exact.y2),
                              static_cast<float>(exact.v2), 0.0f};
        for (int j = 0; j < 101; ++j) {
            double zf = grid_depth(j, 101);
            if (std::fabs(zf - d.depth[0]) < 1e-4 || std::fabs(zf - d.depth[1]) < 1e-4) continue;
            // Tolerance: v2 and the depths rounded to float32 (1e-7) plus the softening.
            EXPECT_NEAR(msmcl::nlq_shadow(texel, static_cast<float>(zf)), ref::exact_shadow(d, zf), 1e-5)
                << "trial " << trial << " zf " << zf;
        }
    }
}

// The whole float pipeline on two-point distributions: Algorithm 2 recovers both depths
// and the weight, and away from the steps the bound is the exact share. Depths and weight:
// float32 rounding (~1e-7) and the bias (3e-7) perturb sigma2, q1, q0; the roots amplify
// that by 1/sigma2, the weight by 1/(sigma2 (y2 - y1)): tolerances 2e-6/sigma2 and
// 1.5e-6/(sigma2 (y2 - y1)) (measured constants 6.7e-7 and 4.4e-7). Bound: the bias leaves xi4 ~1e-7 whose
// Chebyshev-like tails decay as ~xi4 / distance^2: at 0.05 from a step that is < 1e-3.
TEST_F(MathNlq, TwoPointDistributionsReconstructThroughAlgorithm2) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    double worst = 0;
    for (int trial = 0; trial < 1000; ++trial) {
        ref::Distribution d = random_distribution(2);
        if (std::fabs(d.depth[0] - d.depth[1]) < 0.1) continue;
        ref::Moments exact = ref::moments_of(d);
        msmcl::NlqTexel texel = float_nlq(exact);
        double lo = std::min(d.depth[0], d.depth[1]), hi = std::max(d.depth[0], d.depth[1]);
        double weight_hi = (d.depth[0] > d.depth[1] ? d.weight[0] : d.weight[1]) / (d.weight[0] + d.weight[1]);
        double depth_tolerance = 2e-6 / variance(exact);
        double weight_tolerance = 1.5e-6 / (variance(exact) * (hi - lo));
        ASSERT_NEAR(texel.y1, lo, depth_tolerance) << "trial " << trial;
        ASSERT_NEAR(texel.y2, hi, depth_tolerance) << "trial " << trial;
        ASSERT_NEAR(texel.v2, weight_hi, weight_tolerance) << "trial " << trial;
        ASSERT_LT(texel.xi4, 2e-6) << "trial " << trial;
        for (int j = 0; j < 101; ++j) {
            double zf = grid_depth(j, 101);
            if (std::fabs(zf - lo) < 0.05 || std::fabs(zf - hi) < 0.05) continue;
            double truth = ref::exact_shadow(d, zf);
            double error = std::fabs(msmcl::nlq_shadow(texel, static_cast<float>(zf)) - truth);
            ref::Moments softer = reference_biased(exact);
            softer.b4 += 1e-6;
            double bias_error = std::fabs(ref::hamburger4(softer, zf).lower - truth);
            worst = std::max(worst, error - bias_error);
            ASSERT_LT(error, bias_error + 1e-4) << "trial " << trial << " zf " << zf;
        }
    }
    std::printf("two-point pipeline: max error beyond the bias's away from the steps %.3g\n", worst);
}

// A lower bound: never above the true share below zf. float32 moments resolve depths only
// to ~1e-4 + 2e-6/sigma2 (see TwoPointDistributionsReconstructThroughAlgorithm2), and for
// wide distributions float32 xi4 (terms ~1, error ~1e-7) can fall below the bias's
// contribution, making steps sharper than the truth right at the support points (seen: 8.6e-4
// at 3.5e-5 above a depth). So: bound(zf) <= share below zf + that depth allowance, plus 1e-5
// (alpha = 3e-7 of the b* distribution's mass, float noise; measured max excess 1e-6).
// The Hamburger code's last step divides float32 differences by (zf - z1)(z2 - z1), so it
// may also lose ~3e-8 / distance to the nearest depth (measured; allowed 1e-7 / distance).
TEST_F(MathNlq, LowerBoundNeverExceedsTrueShare) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    double worst = -1;
    for (int trial = 0; trial < 3000; ++trial) {
        ref::Distribution d = random_distribution(2 + trial % 4);
        ref::Moments exact = ref::moments_of(d);
        msmcl::NlqTexel texel = float_nlq(exact);
        msmcl::Moments4 biased = msmcl::bias_moments(to_float(exact), MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT);
        double dz = 1e-4 + 2e-6 / variance(exact);
        for (int j = 0; j < 101; ++j) {
            double zf = grid_depth(j, 101);
            double truth = ref::exact_shadow(d, zf + dz);
            float nlq = msmcl::nlq_shadow(texel, static_cast<float>(zf));
            float hamburger = msmcl::hamburger4_lower(biased, static_cast<float>(zf));
            double nearest = 2;
            for (double depth : d.depth) nearest = std::min(nearest, std::fabs(zf - depth));
            worst = std::max(worst, nlq - truth);
            ASSERT_LE(nlq, truth + 1e-5) << "trial " << trial << " zf " << zf;
            ASSERT_LE(hamburger, truth + 1e-5 + 1e-7 / nearest) << "trial " << trial << " zf " << zf;
        }
    }
    std::printf("Algorithm 3: max excess over the true share: %.3g\n", worst);
}

// Quantized texels never raise the bound by more than their rounding allows. Depths move
// by at most half a step (nlq64 1/65535, nlq32 0.5/511.5): covered by evaluating the
// unquantized bound at zf + that shift. Psi4 rounds up, so xi4 never shrinks (which would
// raise the bound). v2 rounds to nearest: nlq64 by <= 7.6e-6, nlq32 (7 bits of sqrt(v2)) by
// <= 0.008, and where min(v1, v2) is not much larger than that error the shape of the bound
// changes (nlq32 stores v1 = 1 - v2 < 0.008 as 0, and v1 = 0.02 to +-22%). So: texels with
// min(v1, v2) >= 0.01 (nlq64) / 0.02 (nlq32), tolerances 1e-3 / 0.05 (measured max 3.8e-4 /
// 0.036 over 200 seeds x 3000 distributions). Distributions wider than float32 resolution
// (sigma2 >= 1e-5); flat regions are the shifted path's business.
TEST_F(MathNlq, QuantizedBoundsStayBelowUnquantized) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    const float shift64 = 1.0f / 65535.0f + 1e-6f, shift32 = 0.5f / 511.5f + 1e-6f;
    double worst64 = -1, worst32 = -1;
    int texels64 = 0, texels32 = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        ref::Distribution d = random_distribution(2 + trial % 4);
        ref::Moments exact = ref::moments_of(d);
        if (variance(exact) < 1e-5) continue;
        msmcl::NlqTexel texel = float_nlq(exact);
        msm_nlq raw{texel.y1, texel.y2, texel.v2, texel.xi4};
        msm_word2 word64 = msm_encode_nlq64(raw);
        const std::uint32_t words64[2] = {word64.w0, word64.w1};
        msmcl::NlqTexel q64 = msmcl::decode_nlq64(words64);
        msmcl::NlqTexel q32 = msmcl::decode_nlq32(msm_encode_nlq32(raw));
        ASSERT_GE(q64.xi4, texel.xi4) << "trial " << trial;
        ASSERT_GE(q32.xi4, texel.xi4) << "trial " << trial;
        float min_weight = std::min(texel.v2, 1.0f - texel.v2);
        texels64 += min_weight >= 0.01f;
        texels32 += min_weight >= 0.02f;
        for (int j = 0; j < 101; ++j) {
            float zf = static_cast<float>(grid_depth(j, 101));
            if (min_weight >= 0.01f) {
                double excess = msmcl::nlq_shadow(q64, zf) - msmcl::nlq_shadow(texel, zf + shift64);
                worst64 = std::max(worst64, excess);
                ASSERT_LE(excess, 1e-3) << "nlq64 trial " << trial << " zf " << zf;
            }
            if (min_weight >= 0.02f) {
                double excess = msmcl::nlq_shadow(q32, zf) - msmcl::nlq_shadow(texel, zf + shift32);
                worst32 = std::max(worst32, excess);
                ASSERT_LE(excess, 0.05) << "nlq32 trial " << trial << " zf " << zf;
            }
        }
    }
    std::printf("quantized over unquantized: nlq64 %.3g (%d texels), nlq32 %.3g (%d texels)\n", worst64,
                texels64, worst32, texels32);
    EXPECT_GT(texels32, 1000);
}

// The lower-bound property survives quantization: the decoded bound stays below the true
// share at zf + half a depth step, plus the weight v2 may gain by rounding to nearest
// (nlq64 7.6e-6; nlq32 0.008, for texels with min(v1, v2) >= 0.01) plus the bias's 3e-7
// and float32 noise: 1e-5 and 0.008 + 1e-5 (measured 7.5e-6 / 0.0075).
TEST_F(MathNlq, QuantizedBoundsStayBelowTrueShare) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    for (int trial = 0; trial < 3000; ++trial) {
        ref::Distribution d = random_distribution(2 + trial % 4);
        ref::Moments exact = ref::moments_of(d);
        if (variance(exact) < 1e-5) continue;
        msmcl::NlqTexel texel = float_nlq(exact);
        msm_nlq raw{texel.y1, texel.y2, texel.v2, texel.xi4};
        msm_word2 word64 = msm_encode_nlq64(raw);
        uint word32 = msm_encode_nlq32(raw);
        bool weights_resolved = std::min(texel.v2, 1.0f - texel.v2) >= 0.01f;
        for (int j = 0; j < 101; ++j) {
            double zf = grid_depth(j, 101);
            float zf32 = static_cast<float>(zf);
            ASSERT_LE(msm_shadow_nlq64(word64, zf32), ref::exact_shadow(d, zf + 1.0 / 65535 + 1e-6) + 1e-5)
                << "nlq64 trial " << trial << " zf " << zf;
            if (weights_resolved) {
                ASSERT_LE(msm_shadow_nlq32(word32, zf32), ref::exact_shadow(d, zf + 0.5 / 511.5 + 1e-6) + 0.00801)
                    << "nlq32 trial " << trial << " zf " << zf;
            }
        }
    }
}

// c = 0: the shifted path is the plain path, bit for bit: the shifted bias target is
// exactly (0, 3/8, 0, 3/8) and adding c = 0 back changes nothing. Both hold the bias as
// offsets apart from the moments (msm_bias_offsets), so the plain path is fed those, not
// msm_bias's moments rounded to float32.
TEST_F(MathNlq, ShiftedMomentsWithZeroShiftAreThePlainPath) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    const msm_moments target{0.0f, MSM_BSTAR_FLOAT, 0.0f, MSM_BSTAR_FLOAT};
    for (int trial = 0; trial < 1000; ++trial) {
        msmcl::Moments4 m = to_float(ref::moments_of(random_distribution(1 + trial % 5)));
        msm_moments raw{m.b1, m.b2, m.b3, m.b4};
        msm_nlq shifted = msm_nlq_from_shifted_moments(raw, 0.0f);
        msm_nlq plain = msm_nlq_from_split_moments(raw, msm_bias_offsets(raw, MSM_ALPHA_FLOAT, target), 0.0f);
        ASSERT_EQ(as_uint(shifted.y1), as_uint(plain.y1));
        ASSERT_EQ(as_uint(shifted.y2), as_uint(plain.y2));
        ASSERT_EQ(as_uint(shifted.v2), as_uint(plain.v2));
        ASSERT_EQ(as_uint(shifted.xi4), as_uint(plain.xi4));
    }
}

// The float32 arithmetic of Algorithm 2 alone: msm_nlq_from_shifted_moments against double
// Algorithm 2 on the very same float32 moments of z - c, biased exactly, so that only the
// rounding inside Algorithm 2 differs. Ordinary distributions and near-two-point ones
// (xi4 down to 1e-6). The cancelling terms (sigma2, q1, xi4) are float-float: xi4 within a
// few float32 roundings of itself (tolerance 2e-5 relative, measured max 1.4e-6; the
// plain float32 formulas are off by more than 100% on these inputs), the depths within
// float32 rounding amplified by 1/(y2 - y1) (tolerance 1e-5 / (y2 - y1), measured max
// 7e-7 / (y2 - y1)), v2 = (b1 - y1)/(y2 - y1) once more (1e-4 / (y2 - y1), measured
// 1.1e-5 / (y2 - y1)).
TEST_F(MathNlq, Algorithm2ArithmeticMatchesDoubleOnTheSameMoments) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    const double alpha = MSM_ALPHA_FLOAT;
    int compared = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        ref::Distribution d;
        if (trial % 2) {
            d = random_distribution(3 + trial % 3);
        } else {
            const double a = uniform(-1.0, 1.0), b = uniform(-1.0, 1.0), e = std::pow(10.0, uniform(-4.0, -2.0));
            d.depth = {a, b, a + e};
            d.weight = {uniform(0.1, 1.0), uniform(0.1, 1.0), uniform(0.01, 0.1)};
        }
        const float c = static_cast<float>(uniform(-1.0, 1.0));
        const msmcl::Moments4 m = to_float(ref::shift(ref::moments_of(d), c));
        // The exact bias of these float32 moments in the shifted frame.
        const ref::Moments target = ref::shift({0.0, ref::bstar_float, 0.0, ref::bstar_float}, c);
        const ref::Moments biased{(1 - alpha) * m.b1 + alpha * target.b1, (1 - alpha) * m.b2 + alpha * target.b2,
                                  (1 - alpha) * m.b3 + alpha * target.b3, (1 - alpha) * m.b4 + alpha * target.b4};
        const ref::Nlq expected = ref::nlq_from_moments(biased);
        const double gap = expected.y2 - expected.y1;
        // Away from the clamps and from one-depth texels.
        if (!(expected.xi4 > 1e-6 && expected.xi4 < 0.25) || gap < 1e-3 || expected.v2 < 1e-3 ||
            expected.v2 > 1.0 - 1e-3 || std::fabs(expected.y1 + c) > 1.0 || std::fabs(expected.y2 + c) > 1.0)
            continue;
        const msm_nlq actual = msm_nlq_from_shifted_moments(msm_moments{m.b1, m.b2, m.b3, m.b4}, c);
        ASSERT_NEAR(actual.xi4, expected.xi4, 2e-5 * expected.xi4) << "trial " << trial;
        ASSERT_NEAR(actual.y1, expected.y1 + c, 1e-5 / gap) << "trial " << trial;
        ASSERT_NEAR(actual.y2, expected.y2 + c, 1e-5 / gap) << "trial " << trial;
        ASSERT_NEAR(actual.v2, expected.v2, 1e-4 / gap) << "trial " << trial;
        ++compared;
    }
    EXPECT_GT(compared, 1000);
}

// c != 0 on ordinary distributions: the same representation as the double reference of
// the unshifted biased moments. Tolerances: depths and weight as in the well-conditioned
// test; xi4 1e-5 (moments of z - c reach (|z| + |c|)^4 <= 16, so their float32 rounding
// is up to 16 times that of moments of z).
TEST_F(MathNlq, ShiftedMomentsMatchReferenceOnOrdinaryDistributions) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    int compared = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        ref::Distribution d = random_distribution(3 + trial % 3);
        ref::Moments exact = ref::moments_of(d);
        ref::Nlq expected = ref::nlq_from_moments(reference_biased(exact));
        if (expected.xi4 < 1e-4 || expected.y2 - expected.y1 < 0.05) continue;
        float c = static_cast<float>(uniform(-1.0, 1.0));
        msmcl::Moments4 shifted = to_float(ref::shift(exact, c));
        msm_nlq actual = msm_nlq_from_shifted_moments(msm_moments{shifted.b1, shifted.b2, shifted.b3, shifted.b4}, c);
        ASSERT_NEAR(actual.y1, expected.y1, 1e-3) << "trial " << trial;
        ASSERT_NEAR(actual.y2, expected.y2, 1e-3) << "trial " << trial;
        ASSERT_NEAR(actual.v2, expected.v2, 1e-3) << "trial " << trial;
        ASSERT_NEAR(actual.xi4, expected.xi4, 1e-5) << "trial " << trial;
        ++compared;
    }
    EXPECT_GT(compared, 300);
}

// Flat regions: all depths within 1e-5..1e-4 of a centre c with 0.5 <= |c| <= 0.95 (a
// plane seen by the light, where docs/math.md saw float32 NaNs). Unshifted float32 moments
// cancel sigma2 (~1e-7, mostly the bias's) against b1^2 ~ 0.5; the shifted path does not.
// Two measures against the double reference of the exact biased moments:
//  - xi4, relative (independent of how well float32 v2 ~ 1 - 1e-6 holds v1);
//  - the bound over zf in [c - 3 spread, c + 3 spread], with the double generic 4MSM on
//    the moments the texel implies (Eq. 4), so that Algorithm 3's clamps do not enter.
TEST_F(MathNlq, ShiftedPathIsMuchCloserOnFlatRegions) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    double bound_plain = 0, bound_shifted = 0, xi_plain = 0, xi_shifted = 0;
    const int trials = 400;
    for (int trial = 0; trial < trials; ++trial) {
        double centre = (trial % 2 ? 1 : -1) * uniform(0.5, 0.95);
        double spread = std::pow(10.0, uniform(-5.0, -4.0));
        ref::Distribution d = random_distribution(2 + trial % 4, centre - spread, centre + spread);
        ref::Moments exact = ref::moments_of(d);
        ref::Moments biased = reference_biased(exact);
        ref::Nlq expected_texel = ref::nlq_from_moments(biased);
        float c = static_cast<float>(centre);
        msmcl::Moments4 shifted = to_float(ref::shift(exact, c));
        msm_nlq via_shift =
            msm_nlq_from_shifted_moments(msm_moments{shifted.b1, shifted.b2, shifted.b3, shifted.b4}, c);
        ref::Nlq shifted_texel{via_shift.y1, via_shift.y2, via_shift.v2, via_shift.xi4};
        ref::Nlq plain_texel = to_double(float_nlq(exact));
        double err_plain = 0, err_shifted = 0;
        for (int j = 0; j < 201; ++j) {
            double zf = centre - 3 * spread + 6 * spread * j / 200.0;
            double expected = ref::hamburger4(biased, zf).lower;
            err_plain = std::max(err_plain, std::fabs(ref::nlq_shadow(plain_texel, zf, false) - expected));
            err_shifted = std::max(err_shifted, std::fabs(ref::nlq_shadow(shifted_texel, zf, false) - expected));
        }
        double xi_err_shifted = std::fabs(shifted_texel.xi4 - expected_texel.xi4) / expected_texel.xi4;
        double xi_err_plain = std::fabs(plain_texel.xi4 - expected_texel.xi4) / expected_texel.xi4;
        // xi4 of the shifted path: float32 roundings of moments of z - c, no large
        // cancellation (measured max 5e-6).
        ASSERT_LT(xi_err_shifted, 1e-4) << "trial " << trial << " spread " << spread;
        // Bound: the bias's far point has v1 = 1 - v2 ~ 1e-6, held by float32 v2 only to
        // +-6e-8 (~5%), which moves the bound by a few 1e-2 (measured max 0.05).
        ASSERT_LT(err_shifted, 0.1) << "trial " << trial << " spread " << spread;
        bound_plain += err_plain;
        bound_shifted += err_shifted;
        xi_plain += xi_err_plain;
        xi_shifted += xi_err_shifted;
    }
    std::printf("flat regions, mean errors: bound plain %.3g shifted %.3g; xi4 plain %.3g shifted %.3g\n",
                bound_plain / trials, bound_shifted / trials, xi_plain / trials, xi_shifted / trials);
    EXPECT_LT(bound_shifted, 0.1 * bound_plain);
    EXPECT_LT(xi_shifted, 0.001 * xi_plain);
}

TEST_F(MathNlq, Psi4MatchesReferenceAndInverts) {
    EXPECT_EQ(msmcl::psi4(0.0f), 0.0f);
    EXPECT_EQ(msmcl::psi4(1.2e-7f), 0.0f);
    EXPECT_NEAR(msmcl::psi4(0.25f), 1.0f, 1e-6);
    EXPECT_EQ(msmcl::psi4(1.0f), 1.0f);
    EXPECT_NEAR(msmcl::psi4_inverse(0.0f), 1.2e-7, 1e-13);
    EXPECT_EQ(msmcl::psi4_inverse(1.0f), 0.25f);
    for (int i = 0; i <= 1000; ++i) {
        double psi = i / 1000.0;
        double xi = ref::psi4_inverse(psi);
        // float32 ln ln and exp exp: relative error of a few ulps on each step.
        EXPECT_NEAR(msmcl::psi4(static_cast<float>(xi)), ref::psi4(static_cast<float>(xi)), 2e-6) << psi;
        // float32 exp(exp(a)), a <= 2.69: a's rounding (2.4e-7) grows by exp(a) <= 14.7 to
        // ~4e-6 relative, plus the exps' own: 2e-5.
        EXPECT_NEAR(msmcl::psi4_inverse(static_cast<float>(psi)) / xi, 1.0, 2e-5) << psi;
        EXPECT_NEAR(ref::psi4(xi), psi, 1e-12);
    }
}
