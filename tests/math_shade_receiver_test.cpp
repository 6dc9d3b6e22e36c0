// msmcl::shade_texel / shade_receiver (host/shading/shading.cpp): the lookup of
// docs/math.md (nearest, bilinear, clamp to the edge, depth convention and bias) on small
// hand-built textures, and per-texel shading against the double reference.
#include <msmcl/device_math.hpp>

#include "kernels/msm_shading.clh"
#include "reference/moment_math.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace ref = msmcl::reference;
using msmcl::Format;

#include "seeded_test.hpp"

namespace {


const Format all_formats[] = {Format::moments128, Format::msm64, Format::nlq64, Format::nlq32};

// Words of one texel holding the raw moments m of a depth distribution, in `format`.
void append_texel(std::vector<std::uint32_t>& words, Format format, const ref::Moments& exact) {
    msm_moments m;
    m.b1 = static_cast<float>(exact.b1);
    m.b2 = static_cast<float>(exact.b2);
    m.b3 = static_cast<float>(exact.b3);
    m.b4 = static_cast<float>(exact.b4);
    switch (format) {
    case Format::moments128:
        for (float b : {m.b1, m.b2, m.b3, m.b4}) words.push_back(as_uint(b));
        break;
    case Format::msm64: {
        msm_word2 w = msm_encode_msm64(m);
        words.push_back(w.w0);
        words.push_back(w.w1);
        break;
    }
    case Format::nlq64: {
        msm_word2 w = msm_encode_nlq64(msm_nlq_from_moments(msm_bias(m, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT)));
        words.push_back(w.w0);
        words.push_back(w.w1);
        break;
    }
    case Format::nlq32:
        words.push_back(msm_encode_nlq32(msm_nlq_from_moments(msm_bias(m, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT))));
        break;
    }
}

// A 3 x 2 map; texel (x, y) holds two depths -0.6 + 0.2 x and 0.1 + 0.3 y with weights
// 0.3 + 0.2 x (of the nearer) and the rest, so every texel differs.
ref::Distribution texel_distribution(int x, int y) {
    return {{-0.6 + 0.2 * x, 0.1 + 0.3 * y}, {0.3 + 0.2 * x, 0.7 - 0.2 * x}};
}

msmcl::Texture make_map(Format format) {
    msmcl::Texture map;
    map.format = format;
    map.width = 3;
    map.height = 2;
    for (int y = 0; y < map.height; ++y)
        for (int x = 0; x < map.width; ++x) append_texel(map.words, format, ref::moments_of(texel_distribution(x, y)));
    return map;
}

msmcl::ShadeOptions options(msmcl::Lookup lookup, msmcl::DepthRange range = msmcl::DepthRange::minus_one_one,
                            float bias = 0.0f) {
    msmcl::ShadeOptions o;
    o.lookup = lookup;
    o.depth_range = range;
    o.depth_bias = bias;
    return o;
}

} // namespace

TEST(MathShadeReceiver, NearestTakesTheTexelUnderTheReceiverClampedToTheEdge) {
    for (Format format : all_formats) {
        SCOPED_TRACE(msmcl::format_name(format));
        msmcl::Texture map = make_map(format);
        auto nearest = options(msmcl::Lookup::nearest);
        for (float z : {-0.7f, -0.45f, 0.0f, 0.3f, 0.95f}) {
            for (int y = 0; y < 2; ++y)
                for (int x = 0; x < 3; ++x)
                    for (float fraction : {0.0f, 0.3f, 0.99f})
                        EXPECT_EQ(msmcl::shade_receiver(map, x + fraction, y + fraction, z, nearest),
                                  msmcl::shade_texel(map, x, y, z));
            // Outside the map: the edge texel; NaN coordinates -> texel 0.
            EXPECT_EQ(msmcl::shade_receiver(map, -3.0f, -0.5f, z, nearest), msmcl::shade_texel(map, 0, 0, z));
            EXPECT_EQ(msmcl::shade_receiver(map, 1e30f, 7.0f, z, nearest), msmcl::shade_texel(map, 2, 1, z));
            EXPECT_EQ(msmcl::shade_receiver(map, std::numeric_limits<float>::quiet_NaN(), 1.5f, z, nearest),
                      msmcl::shade_texel(map, 0, 1, z));
        }
    }
}

// At a texel centre bilinear is that texel; half-way between two centres it is the mean of
// the two moments (moments128: raw; msm64: decoded, then biased), checked against the double
// reconstruction of that mean, or of the two intensities (nlq64, nlq32); beyond the outer
// centres it clamps to the edge texel.
TEST(MathShadeReceiver, BilinearInterpolatesMomentsOrIntensities) {
    for (Format format : all_formats) {
        SCOPED_TRACE(msmcl::format_name(format));
        msmcl::Texture map = make_map(format);
        auto bilinear = options(msmcl::Lookup::bilinear);
        for (float z : {-0.7f, -0.45f, -0.05f, 0.3f, 0.95f}) {
            for (int y = 0; y < 2; ++y)
                for (int x = 0; x < 3; ++x)
                    EXPECT_EQ(msmcl::shade_receiver(map, x + 0.5f, y + 0.5f, z, bilinear), msmcl::shade_texel(map, x, y, z));
            // Clamped: the corner texel around the corner of the map.
            EXPECT_EQ(msmcl::shade_receiver(map, 0.1f, 0.2f, z, bilinear), msmcl::shade_texel(map, 0, 0, z));
            EXPECT_EQ(msmcl::shade_receiver(map, 2.9f, 1.7f, z, bilinear), msmcl::shade_texel(map, 2, 1, z));
            // Half-way between (0,1) and (1,1).
            float between = msmcl::shade_receiver(map, 1.0f, 1.5f, z, bilinear);
            if (format == Format::moments128 || format == Format::msm64) {
                // The double reconstruction of the mean of the two texels' moments (raw, or the
                // codes decoded in double): float32 rounding of the well-conditioned solve only
                // (two depths >= 0.5 apart per texel; measured < 1e-7).
                auto reference_moments = [&](int x, int y) {
                    const std::uint32_t* w = map.texel(x, y);
                    if (format == Format::msm64) return ref::decode_msm64(ref::unpack_codes16({w[0], w[1]}));
                    const msmcl::Moments4 m = msmcl::decode_moments128(w);
                    return ref::Moments{m.b1, m.b2, m.b3, m.b4};
                };
                const ref::Moments a = reference_moments(0, 1), b = reference_moments(1, 1);
                const ref::Moments mean{0.5 * (a.b1 + b.b1), 0.5 * (a.b2 + b.b2), 0.5 * (a.b3 + b.b3), 0.5 * (a.b4 + b.b4)};
                const double alpha = format == Format::moments128 ? ref::alpha_float : ref::alpha_msm64;
                const double bstar = format == Format::moments128 ? ref::bstar_float : ref::bstar_msm64;
                EXPECT_NEAR(between, ref::hamburger4(ref::bias(mean, alpha, bstar), z).lower, 1e-6) << z;
            } else {
                EXPECT_NEAR(between, 0.5f * (msmcl::shade_texel(map, 0, 1, z) + msmcl::shade_texel(map, 1, 1, z)), 1e-6)
                    << z;
            }
            // A quarter of the way: weights 3/4 and 1/4 along x (intensity formats).
            if (format == Format::nlq64 || format == Format::nlq32) {
                EXPECT_NEAR(msmcl::shade_receiver(map, 0.75f, 0.5f, z, bilinear),
                            0.75f * msmcl::shade_texel(map, 0, 0, z) + 0.25f * msmcl::shade_texel(map, 1, 0, z), 1e-6);
                EXPECT_NEAR(msmcl::shade_receiver(map, 2.5f, 0.75f, z, bilinear),
                            0.75f * msmcl::shade_texel(map, 2, 0, z) + 0.25f * msmcl::shade_texel(map, 2, 1, z), 1e-6);
            }
        }
    }
}

// The receiver's z is converted with its depth range, then the depth bias is subtracted.
TEST(MathShadeReceiver, DepthRangeAndBias) {
    for (Format format : all_formats) {
        SCOPED_TRACE(msmcl::format_name(format));
        msmcl::Texture map = make_map(format);
        for (float d : {0.1f, 0.3f, 0.52f, 0.7f}) {
            float z = 2.0f * d - 1.0f;
            EXPECT_EQ(msmcl::shade_receiver(map, 1.2f, 0.4f, d, options(msmcl::Lookup::nearest, msmcl::DepthRange::zero_one, 1e-3f)),
                      msmcl::shade_texel(map, 1, 0, z - 1e-3f));
            EXPECT_EQ(msmcl::shade_receiver(map, 1.2f, 0.4f, z, options(msmcl::Lookup::nearest, msmcl::DepthRange::minus_one_one, 0.05f)),
                      msmcl::shade_texel(map, 1, 0, z - 0.05f));
        }
        // Depths outside the range clamp to it: behind everything -> shadowed by all of the
        // texel's mass, in front -> lit.
        EXPECT_GT(msmcl::shade_receiver(map, 0.5f, 0.5f, 5.0f, options(msmcl::Lookup::nearest)), 0.95f);
        EXPECT_EQ(msmcl::shade_receiver(map, 0.5f, 0.5f, -5.0f, options(msmcl::Lookup::nearest)), 0.0f);
    }
}

// Per texel, each format against the double reference of what the texel stores (same
// envelope reasoning as math_nlq_test / math_hamburger_test: zf +-1e-4, b4 +-1e-6, 1e-4).
TEST(MathShadeReceiver, TexelShadingMatchesReference) {
    const std::uint64_t seed = msmcl::testing::run_seed();
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (int trial = 0; trial < 300; ++trial) {
        ref::Distribution d{{uniform(rng), uniform(rng), uniform(rng)}, {1.0, 0.5 + 0.5 * uniform(rng), 0.6}};
        ref::Moments exact = ref::moments_of(d);
        if (exact.b2 - exact.b1 * exact.b1 < 1e-3) continue;
        for (Format format : all_formats) {
            msmcl::Texture map;
            map.format = format;
            map.width = map.height = 1;
            append_texel(map.words, format, exact);
            for (int j = 0; j < 41; ++j) {
                double zf = -1.0 + 2.0 * j / 40;
                double low, high;
                const double dz = 1e-4, db4 = 1e-6, eps = 1e-4;
                if (format == Format::nlq64 || format == Format::nlq32) {
                    // Algorithm 3 vs the generic 4MSM on the decoded texel (Eq. 4, clamped as
                    // Algorithm 3 clamps: nlq32 often decodes v2 = 1).
                    msmcl::NlqTexel t = format == Format::nlq64 ? msmcl::decode_nlq64(map.texel(0, 0))
                                                                : msmcl::decode_nlq32(map.words[0]);
                    ref::Nlq texel{t.y1, t.y2, t.v2, t.xi4};
                    low = ref::nlq_shadow(texel, zf - dz);
                    high = ref::nlq_shadow(texel, zf + dz);
                } else {
                    msmcl::Moments4 m = format == Format::moments128 ? msmcl::decode_moments128(map.texel(0, 0))
                                                                     : msmcl::decode_msm64(map.texel(0, 0));
                    double alpha = format == Format::moments128 ? ref::alpha_float : ref::alpha_msm64;
                    double bstar = format == Format::moments128 ? ref::bstar_float : ref::bstar_msm64;
                    ref::Moments biased = ref::bias(ref::Moments{m.b1, m.b2, m.b3, m.b4}, alpha, bstar);
                    ref::Moments more = biased, less = biased;
                    more.b4 += db4;
                    less.b4 = std::max(biased.b4 - db4, biased.b4 - ref::nlq_from_moments(biased).xi4);
                    low = ref::hamburger4(more, zf - dz).lower;
                    high = ref::hamburger4(less, zf + dz).lower;
                }
                float actual = msmcl::shade_texel(map, 0, 0, static_cast<float>(zf));
                ASSERT_GE(actual, low - eps) << msmcl::format_name(format) << " trial " << trial << " zf " << zf;
                ASSERT_LE(actual, high + eps) << msmcl::format_name(format) << " trial " << trial << " zf " << zf;
            }
        }
    }
}
