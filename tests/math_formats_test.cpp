// Texel formats of docs/formats.md (kernels/msm_formats.clh, float32) against hand-computed
// words and the independent double-precision encoders of host/reference/moment_math.*.
#include <msmcl/device_math.hpp>

#include "kernels/msm_formats.clh"
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

class MathFormats : public msmcl::testing::SeededTest {
protected:
    // A texel as Algorithm 2 produces it: y1 <= y2 in [-1,1], v2 in [0,1], xi4 over its range.
    msm_nlq random_texel() {
        float a = static_cast<float>(uniform(-1.0, 1.0)), b = static_cast<float>(uniform(-1.0, 1.0));
        msm_nlq n;
        n.y1 = std::min(a, b);
        n.y2 = std::max(a, b);
        n.v2 = static_cast<float>(uniform(0.0, 1.0));
        n.xi4 = static_cast<float>(std::pow(10.0, uniform(-8.0, std::log10(0.25))));
        return n;
    }
    // Moments of a random 1..4-point distribution on [-1,1].
    ref::Moments random_moments() {
        ref::Distribution d;
        int k = 1 + static_cast<int>(uniform(0.0, 4.0));
        for (int i = 0; i < k; ++i) {
            d.depth.push_back(uniform(-1.0, 1.0));
            d.weight.push_back(uniform(0.05, 1.0));
        }
        return ref::moments_of(d);
    }
};

msm_nlq texel(float y1, float y2, float v2, float xi4) {
    msm_nlq n;
    n.y1 = y1;
    n.y2 = y2;
    n.v2 = v2;
    n.xi4 = xi4;
    return n;
}

ref::Nlq to_double(const msm_nlq& n) { return {n.y1, n.y2, n.v2, n.xi4}; }

ref::Codes16 codes_of(const msm_word2& w) {
    return {static_cast<std::uint16_t>(w.w0 & 0xffffu), static_cast<std::uint16_t>(w.w0 >> 16),
            static_cast<std::uint16_t>(w.w1 & 0xffffu), static_cast<std::uint16_t>(w.w1 >> 16)};
}

// Field values of an nlq32 word, read with shifts and masks.
struct Fields32 {
    unsigned psi, sqrt_v2, t1, t2;
};
Fields32 fields_of(std::uint32_t w) { return {w & 63u, (w >> 6) & 127u, (w >> 13) & 511u, w >> 22}; }

int code_distance(int a, int b) { return std::abs(a - b); }

// The depth codes (yt1, yt2) of folded fields.
std::array<int, 2> unfolded(unsigned t1, unsigned t2) {
    if (t2 < t1) return {1023 - static_cast<int>(t1), 1022 - static_cast<int>(t2)};
    return {static_cast<int>(t1), static_cast<int>(t2)};
}

} // namespace

// ---- nlq32 bit layout, by hand.

// Unfolded branch: y1 = -0.5 -> floor(511.5 * 0.5) = 255, y2 = 0.25 -> floor(639.375) = 639
// (255 < 512: t1 = 255, t2 = 639); sqrt(0.25) * 127 = 63.5 -> 64 (half up); Psi4(0.25) = 1
// -> 63. Word = 63 | 64 << 6 | 255 << 13 | 639 << 22 = 0x9fdff03f.
TEST_F(MathFormats, Nlq32LayoutUnfoldedExample) {
    std::uint32_t w = msm_encode_nlq32(texel(-0.5f, 0.25f, 0.25f, 0.25f));
    Fields32 f = fields_of(w);
    EXPECT_EQ(f.psi, 63u);
    EXPECT_EQ(f.sqrt_v2, 64u);
    EXPECT_EQ(f.t1, 255u);
    EXPECT_EQ(f.t2, 639u);
    EXPECT_EQ(w, 0x9fdff03fu);
    EXPECT_EQ(w, ref::encode_nlq32(ref::Nlq{-0.5, 0.25, 0.25, 0.25}));
    msm_nlq d = msm_decode_nlq32(w);
    EXPECT_FLOAT_EQ(d.y1, 255.5f / 511.5f - 1.0f);
    EXPECT_FLOAT_EQ(d.y2, 639.5f / 511.5f - 1.0f);
    EXPECT_FLOAT_EQ(d.v2, (64.0f / 127.0f) * (64.0f / 127.0f));
    EXPECT_NEAR(d.xi4, 0.25f, 3e-6f);
}

// Folded branch: y1 = 0.2 -> floor(613.8) = 613 >= 512, so t1 = 1023 - 613 = 410;
// y2 = 0.9 -> floor(971.85) = 971, t2 = 1022 - 971 = 51 (< t1); sqrt(0.81) * 127 = 114.3
// -> 114; xi4 = 0 -> Psi4 = 0 -> 0. Word = 114 << 6 | 410 << 13 | 51 << 22 = 0x0cf35c80.
TEST_F(MathFormats, Nlq32LayoutFoldedExample) {
    std::uint32_t w = msm_encode_nlq32(texel(0.2f, 0.9f, 0.81f, 0.0f));
    Fields32 f = fields_of(w);
    EXPECT_EQ(f.psi, 0u);
    EXPECT_EQ(f.sqrt_v2, 114u);
    EXPECT_EQ(f.t1, 410u);
    EXPECT_EQ(f.t2, 51u);
    EXPECT_EQ(w, 0x0cf35c80u);
    EXPECT_EQ(w, ref::encode_nlq32(ref::Nlq{0.2, 0.9, 0.81, 0.0}));
    msm_nlq d = msm_decode_nlq32(w);
    EXPECT_FLOAT_EQ(d.y1, 613.5f / 511.5f - 1.0f);
    EXPECT_FLOAT_EQ(d.y2, 971.5f / 511.5f - 1.0f);
    EXPECT_FLOAT_EQ(d.v2, (114.0f / 127.0f) * (114.0f / 127.0f));
    EXPECT_FLOAT_EQ(d.xi4, 1.2e-7f);
}

// The fold boundary and the clamps: yt = 511 stays, 512 folds; y = 1 clamps to 1022;
// codes outside their fields clamp.
TEST_F(MathFormats, Nlq32FoldBoundaryAndClamps) {
    // y = 0 -> 511 (unfolded), y = 0.001 -> floor(512.01) = 512 (folded to 511, 510).
    Fields32 below = fields_of(msm_encode_nlq32(texel(0.0f, 0.0f, 0.5f, 0.0f)));
    EXPECT_EQ(below.t1, 511u);
    EXPECT_EQ(below.t2, 511u);
    Fields32 above = fields_of(msm_encode_nlq32(texel(0.001f, 0.001f, 0.5f, 0.0f)));
    EXPECT_EQ(above.t1, 511u);
    EXPECT_EQ(above.t2, 510u);
    EXPECT_NEAR(msm_decode_nlq32(msm_encode_nlq32(texel(0.001f, 0.001f, 0.5f, 0.0f))).y1, 512.5 / 511.5 - 1, 1e-7);
    // y = 1: min(1022, 1023) = 1022, folded to t1 = 1, t2 = 0.
    EXPECT_EQ(msm_encode_nlq32(texel(1.0f, 1.0f, 0.0f, 0.0f)), 1u << 13);
    // y = -1, v2 = 1: all zero but sqrt(v2) = 127.
    EXPECT_EQ(msm_encode_nlq32(texel(-1.0f, -1.0f, 1.0f, 0.0f)), 127u << 6);
    // Out of range inputs clamp to the field: y beyond [-1,1], v2 beyond [0,1], xi4 > 0.25.
    Fields32 clamped = fields_of(msm_encode_nlq32(texel(-1.5f, 1.5f, 1.5f, 3.0f)));
    EXPECT_EQ(clamped.psi, 63u);
    EXPECT_EQ(clamped.sqrt_v2, 127u);
    EXPECT_EQ(clamped.t1, 0u);
    EXPECT_EQ(clamped.t2, 1022u);
    EXPECT_EQ(fields_of(msm_encode_nlq32(texel(0.0f, 0.0f, -0.5f, 0.0f))).sqrt_v2, 0u);
}

// Both branches round trip: for every pair yt1 <= yt2 the fields are the fold of docs/formats.md and
// the decoded depths are the centres of yt1, yt2 again.
TEST_F(MathFormats, Nlq32FoldIsABijectionOnTheTriangle) {
    for (unsigned yt1 = 0; yt1 <= 1022; ++yt1) {
        for (unsigned yt2 = yt1; yt2 <= 1022; ++yt2) {
            float y1 = msm_nlq32_depth_decode(yt1), y2 = msm_nlq32_depth_decode(yt2);
            std::uint32_t w = msm_encode_nlq32(texel(y1, y2, 0.5f, 0.0f));
            Fields32 f = fields_of(w);
            bool fold = yt1 >= 512;
            ASSERT_EQ(f.t1, fold ? 1023 - yt1 : yt1) << yt1 << " " << yt2;
            ASSERT_EQ(f.t2, fold ? 1022 - yt2 : yt2) << yt1 << " " << yt2;
            msm_nlq d = msm_decode_nlq32(w);
            ASSERT_EQ(d.y1, y1) << yt1 << " " << yt2;
            ASSERT_EQ(d.y2, y2) << yt1 << " " << yt2;
        }
    }
}

// ---- nlq64 and msm64 words, by hand.

// y1 = -1 -> 0, y2 = 1 -> 65535, v2 = 0.5 -> 32767.5 -> 32768 (half up), Psi4(0.25) -> 65535.
TEST_F(MathFormats, Nlq64WordExample) {
    msm_word2 w = msm_encode_nlq64(texel(-1.0f, 1.0f, 0.5f, 0.25f));
    EXPECT_EQ(w.w0, 0xffff0000u);
    EXPECT_EQ(w.w1, 0xffff8000u);
    std::array<std::uint32_t, 2> words = ref::pack_codes16(ref::encode_nlq64(ref::Nlq{-1, 1, 0.5, 0.25}));
    EXPECT_EQ(w.w0, words[0]);
    EXPECT_EQ(w.w1, words[1]);
    // device_math.hpp decodes the same words.
    msmcl::NlqTexel t = msmcl::decode_nlq64(words.data());
    EXPECT_EQ(t.y1, -1.0f);
    EXPECT_EQ(t.y2, 1.0f);
    EXPECT_FLOAT_EQ(t.v2, 32768.0f / 65535.0f);
}

// z = 0: b = 0, R = B = 0.5 -> 32768, G = A = 0. z = 1: b = 1, R = 0, G = 0,
// B = sqrt(3)(1/2 - 2/9) + 1/2 = 0.981127 -> 64298, A = 1 -> 65535.
TEST_F(MathFormats, Msm64WordExamples) {
    msm_word2 zero = msm_encode_msm64(msm_moments_of(0.0f));
    EXPECT_EQ(zero.w0, 0x00008000u);
    EXPECT_EQ(zero.w1, 0x00008000u);
    msm_word2 one = msm_encode_msm64(msm_moments_of(1.0f));
    EXPECT_EQ(one.w0, 0u);
    EXPECT_EQ(one.w1, (65535u << 16) | 64298u);
    EXPECT_EQ(codes_of(one), ref::encode_msm64(ref::moments_of(1.0)));
}

// ---- The affine pair of docs/math.md.

// In double the two maps are exact inverses: the linear parts multiply to the identity.
TEST_F(MathFormats, Msm64AffinePairInvertsExactly) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    const std::array<double, 4> offset = ref::msm64_affine(ref::Moments{});
    EXPECT_EQ(offset[0], 0.5);
    EXPECT_EQ(offset[1], 0.0);
    EXPECT_EQ(offset[2], 0.5);
    EXPECT_EQ(offset[3], 0.0);
    // Columns of the forward matrix M (affine image of unit vectors minus the offset).
    double forward[4][4], inverse[4][4];
    for (int j = 0; j < 4; ++j) {
        ref::Moments unit;
        double* slots[4] = {&unit.b1, &unit.b2, &unit.b3, &unit.b4};
        *slots[j] = 1.0;
        std::array<double, 4> image = ref::msm64_affine(unit);
        for (int i = 0; i < 4; ++i) forward[i][j] = image[i] - offset[i];
        std::array<double, 4> rgba = offset;
        rgba[j] += 1.0;
        ref::Moments back = ref::msm64_affine_inverse(rgba);
        double values[4] = {back.b1, back.b2, back.b3, back.b4};
        for (int i = 0; i < 4; ++i) inverse[i][j] = values[i];
    }
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
            double product = 0;
            for (int k = 0; k < 4; ++k) product += inverse[i][k] * forward[k][j];
            EXPECT_NEAR(product, i == j ? 1.0 : 0.0, 1e-15) << i << " " << j;
        }
    }
    // And on random moments, each channel of a valid vector lies in [0,1].
    for (int trial = 0; trial < 1000; ++trial) {
        ref::Moments b = random_moments();
        std::array<double, 4> rgba = ref::msm64_affine(b);
        for (double channel : rgba) {
            EXPECT_GE(channel, -1e-12);
            EXPECT_LE(channel, 1 + 1e-12);
        }
        ref::Moments back = ref::msm64_affine_inverse(rgba);
        EXPECT_NEAR(back.b1, b.b1, 1e-15);
        EXPECT_NEAR(back.b2, b.b2, 1e-15);
        EXPECT_NEAR(back.b3, b.b3, 1e-15);
        EXPECT_NEAR(back.b4, b.b4, 1e-15);
    }
}

// float32 msm64: codes as the double encoder's (or one off, where float32 rounding of a
// channel lands on the other side of a half step); decode(encode(b)) within half a code per
// channel mapped through the inverse matrix (row sums of |inverse|: 1/3 + sqrt 3, 1.125,
// 0.75 + 0.75 sqrt 3, 1.125 times 0.5/65535), plus 1e-6 for float32.
TEST_F(MathFormats, Msm64FloatMatchesReferenceAndRoundTrips) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    const double half = 0.5 / 65535;
    const double bound[4] = {(1.0 / 3 + std::sqrt(3.0)) * half + 1e-6, 1.125 * half + 1e-6,
                             (0.75 + 0.75 * std::sqrt(3.0)) * half + 1e-6, 1.125 * half + 1e-6};
    int off_by_one = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        ref::Moments exact = random_moments();
        msm_moments m{static_cast<float>(exact.b1), static_cast<float>(exact.b2), static_cast<float>(exact.b3),
                      static_cast<float>(exact.b4)};
        msm_word2 w = msm_encode_msm64(m);
        ref::Codes16 expected = ref::encode_msm64(ref::Moments{m.b1, m.b2, m.b3, m.b4});
        ref::Codes16 actual = codes_of(w);
        for (int c = 0; c < 4; ++c) {
            ASSERT_LE(code_distance(actual[c], expected[c]), 1) << "trial " << trial << " channel " << c;
            off_by_one += actual[c] != expected[c];
        }
        msm_moments d = msm_decode_msm64(w);
        ASSERT_NEAR(d.b1, m.b1, bound[0]) << "trial " << trial;
        ASSERT_NEAR(d.b2, m.b2, bound[1]) << "trial " << trial;
        ASSERT_NEAR(d.b3, m.b3, bound[2]) << "trial " << trial;
        ASSERT_NEAR(d.b4, m.b4, bound[3]) << "trial " << trial;
        // The float decoder is the double one, to float32 precision.
        ref::Moments reference = ref::decode_msm64(actual);
        ASSERT_NEAR(d.b1, reference.b1, 1e-6);
        ASSERT_NEAR(d.b2, reference.b2, 1e-6);
        ASSERT_NEAR(d.b3, reference.b3, 1e-6);
        ASSERT_NEAR(d.b4, reference.b4, 1e-6);
        // device_math.hpp reads the same two words.
        const std::uint32_t words[2] = {w.w0, w.w1};
        msmcl::Moments4 via_api = msmcl::decode_msm64(words);
        ASSERT_EQ(via_api.b1, d.b1);
        ASSERT_EQ(via_api.b4, d.b4);
    }
    std::printf("msm64: %d of 80000 float codes one off the double ones\n", off_by_one);
}

// ---- nlq64 / nlq32 round trips and float vs double encoders.

// nlq64 round trip: depths within half a step (1/65535 in [-1,1]), v2 within 0.5/65535,
// both plus float32 rounding (1e-7); decoded xi4 never below the original, at most one code
// of Psi4 above it. Codes equal to the double encoder's or one off.
TEST_F(MathFormats, Nlq64RoundTripAndReference) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    int off_by_one = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        msm_nlq n = random_texel();
        msm_word2 w = msm_encode_nlq64(n);
        msm_nlq d = msm_decode_nlq64(w);
        ASSERT_NEAR(d.y1, n.y1, 1.0 / 65535 + 1e-7) << "trial " << trial;
        ASSERT_NEAR(d.y2, n.y2, 1.0 / 65535 + 1e-7) << "trial " << trial;
        ASSERT_NEAR(d.v2, n.v2, 0.5 / 65535 + 1e-7) << "trial " << trial;
        ASSERT_GE(d.xi4, n.xi4) << "trial " << trial;
        ASSERT_LE(ref::psi4(d.xi4) - ref::psi4(n.xi4), 1.0 / 65535 + 1e-6) << "trial " << trial;
        ref::Codes16 expected = ref::encode_nlq64(to_double(n));
        ref::Codes16 actual = codes_of(w);
        for (int c = 0; c < 4; ++c) {
            ASSERT_LE(code_distance(actual[c], expected[c]), 1) << "trial " << trial << " channel " << c;
            off_by_one += actual[c] != expected[c];
        }
        ref::Nlq reference = ref::decode_nlq64(actual);
        ASSERT_NEAR(d.y1, reference.y1, 1e-7);
        ASSERT_NEAR(d.v2, reference.v2, 1e-7);
        // float32 exp(exp(a)), a <= 2.69: a's rounding (2.4e-7) grows by exp(a) <= 14.7 to a
        // relative error of ~4e-6 of xi4, plus the exps' own: 2e-5.
        ASSERT_NEAR(d.xi4 / reference.xi4, 1.0, 2e-5);
    }
    std::printf("nlq64: %d of 80000 float codes one off the double ones\n", off_by_one);
}

// nlq32 round trip: depths within half a step (0.5/511.5, floor then centre), sqrt(v2)
// within 0.5/127, order kept, decoded xi4 never below the original (at most one Psi4 code of
// 1/63 above it). Fields equal to the double encoder's or one off (depth codes compared
// unfolded: one code across yt1 = 511|512 flips the fold).
TEST_F(MathFormats, Nlq32RoundTripAndReference) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    int off_by_one = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        msm_nlq n = random_texel();
        std::uint32_t w = msm_encode_nlq32(n);
        msm_nlq d = msm_decode_nlq32(w);
        ASSERT_NEAR(d.y1, n.y1, 0.5 / 511.5 + 1e-6) << "trial " << trial;
        ASSERT_NEAR(d.y2, n.y2, 0.5 / 511.5 + 1e-6) << "trial " << trial;
        ASSERT_LE(d.y1, d.y2) << "trial " << trial;
        ASSERT_NEAR(std::sqrt(d.v2), std::sqrt(n.v2), 0.5 / 127 + 1e-6) << "trial " << trial;
        ASSERT_GE(d.xi4, n.xi4) << "trial " << trial;
        ASSERT_LE(ref::psi4(d.xi4) - ref::psi4(n.xi4), 1.0 / 63 + 1e-6) << "trial " << trial;
        ref::Nlq32Fields expected = ref::nlq32_fields(to_double(n));
        ref::Nlq32Fields actual = ref::unpack_nlq32(w);
        Fields32 shifted = fields_of(w);
        ASSERT_EQ(actual.psi, shifted.psi);
        ASSERT_EQ(actual.sqrt_v2, shifted.sqrt_v2);
        ASSERT_EQ(actual.t1, shifted.t1);
        ASSERT_EQ(actual.t2, shifted.t2);
        ASSERT_LE(code_distance(actual.psi, expected.psi), 1) << "trial " << trial;
        ASSERT_LE(code_distance(actual.sqrt_v2, expected.sqrt_v2), 1) << "trial " << trial;
        std::array<int, 2> actual_depths = unfolded(actual.t1, actual.t2);
        std::array<int, 2> expected_depths = unfolded(expected.t1, expected.t2);
        ASSERT_LE(code_distance(actual_depths[0], expected_depths[0]), 1) << "trial " << trial;
        ASSERT_LE(code_distance(actual_depths[1], expected_depths[1]), 1) << "trial " << trial;
        off_by_one += (actual.psi != expected.psi) + (actual.sqrt_v2 != expected.sqrt_v2) +
                      (actual_depths[0] != expected_depths[0]) + (actual_depths[1] != expected_depths[1]);
        ref::Nlq reference = ref::decode_nlq32(w);
        ASSERT_NEAR(d.y1, reference.y1, 1e-7);
        ASSERT_NEAR(d.y2, reference.y2, 1e-7);
        ASSERT_NEAR(d.v2, reference.v2, 1e-7);
        ASSERT_NEAR(d.xi4 / reference.xi4, 1.0, 2e-5);
        ASSERT_EQ(msmcl::decode_nlq32(w).y1, d.y1);
    }
    std::printf("nlq32: %d of 80000 float fields one off the double ones\n", off_by_one);
}

// Reference packing is its own independent arithmetic: check it against shifts too.
TEST_F(MathFormats, ReferencePackingMatchesShifts) {
    SCOPED_TRACE("seed " + std::to_string(seed_));
    for (int trial = 0; trial < 1000; ++trial) {
        ref::Nlq32Fields f;
        f.psi = static_cast<std::uint32_t>(uniform(0, 64));
        f.sqrt_v2 = static_cast<std::uint32_t>(uniform(0, 128));
        f.t1 = static_cast<std::uint32_t>(uniform(0, 512));
        f.t2 = static_cast<std::uint32_t>(uniform(0, 1024));
        std::uint32_t w = ref::pack_nlq32(f);
        EXPECT_EQ(w, f.psi | (f.sqrt_v2 << 6) | (f.t1 << 13) | (f.t2 << 22));
        ref::Codes16 codes = {static_cast<std::uint16_t>(uniform(0, 65536)), static_cast<std::uint16_t>(uniform(0, 65536)),
                              static_cast<std::uint16_t>(uniform(0, 65536)), static_cast<std::uint16_t>(uniform(0, 65536))};
        msm_word2 packed = msm_pack_codes16(codes[0], codes[1], codes[2], codes[3]);
        std::array<std::uint32_t, 2> words = ref::pack_codes16(codes);
        EXPECT_EQ(packed.w0, words[0]);
        EXPECT_EQ(packed.w1, words[1]);
        EXPECT_EQ(ref::unpack_codes16(words), codes);
    }
}
