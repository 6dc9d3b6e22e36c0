// filter on the OpenCL device (PoCL in CI) against the double-precision reference
// (host/reference/filter_reference.*): resolve + blur, every format, fused == three-pass,
// sizes, sample counts, depth ranges, sigmas, bad inputs, device path == host path.
#include "reference/filter_reference.hpp"

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

namespace ref = msmcl::reference;
using msmcl::DepthImage;
using msmcl::DepthRange;
using msmcl::FilterKernel;
using msmcl::Format;
using msmcl::Texture;

std::uint32_t test_seed() {
    const char* text = std::getenv("MSMCL_TEST_SEED");
    return text ? static_cast<std::uint32_t>(std::strtoul(text, nullptr, 10)) : 4096u;
}

// A smooth-ish depth map with occluders: a sloped, wavy receiver in [0.35, 0.95] and
// random disks and boxes in front of it (one at d = 0 exactly, one at d = 1), sampled at
// S sub-texel positions so that texels on occluder edges mix depths.
DepthImage make_depth(int width, int height, int samples, DepthRange range, std::uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double wave_x = 0.02 + 0.1 * unit(random), wave_y = 0.02 + 0.1 * unit(random);
    const double phase_x = 6.3 * unit(random), phase_y = 6.3 * unit(random);
    const double slope = 0.1 * unit(random);
    struct Occluder {
        bool disk;
        double cx, cy, rx, ry, depth;
    };
    std::vector<Occluder> occluders;
    const int count = 3 + static_cast<int>(random() % 6);
    const double extent = std::max(width, height);
    for (int i = 0; i < count; ++i) {
        Occluder o;
        o.disk = random() % 2 == 0;
        o.cx = unit(random) * width;
        o.cy = unit(random) * height;
        o.rx = 1.0 + unit(random) * extent / 4.0;
        o.ry = 1.0 + unit(random) * extent / 4.0;
        o.depth = i == 0 ? 0.0 : i == 1 ? 1.0 : 0.05 + 0.45 * unit(random);
        occluders.push_back(o);
    }
    DepthImage image;
    image.width = width;
    image.height = height;
    image.samples = samples;
    image.depth.resize(static_cast<std::size_t>(width) * height * samples);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            for (int s = 0; s < samples; ++s) {
                // Sample positions spread over the texel (centre for one sample).
                const double px = x + (samples == 1 ? 0.5 : std::fmod(0.25 + 0.618034 * s, 1.0));
                const double py = y + (samples == 1 ? 0.5 : std::fmod(0.5 + 0.381966 * s, 1.0));
                double d = 0.65 + 0.2 * std::sin(wave_x * px + phase_x) * std::cos(wave_y * py + phase_y) +
                           slope * (px / std::max(width, 1) - 0.5);
                // The nearest occluder that covers the sample wins (occluder 1 lies behind).
                for (const Occluder& o : occluders) {
                    const double u = (px - o.cx) / o.rx, v = (py - o.cy) / o.ry;
                    const bool inside = o.disk ? u * u + v * v <= 1.0 : std::fabs(u) <= 1.0 && std::fabs(v) <= 1.0;
                    if (inside && (o.depth < d || o.depth == 1.0)) d = o.depth;
                }
                const double rendered = range == DepthRange::zero_one ? d : 2.0 * d - 1.0;
                image.depth[(static_cast<std::size_t>(y) * width + x) * samples + s] = static_cast<float>(rendered);
            }
        }
    }
    return image;
}

ref::DepthMap to_reference(const DepthImage& image, DepthRange range) {
    return ref::DepthMap{image.width, image.height, image.samples, image.depth, range == DepthRange::zero_one};
}

std::string at(int x, int y) { return "texel (" + std::to_string(x) + ", " + std::to_string(y) + ")"; }

ref::Codes16 codes16(const Texture& t, int x, int y) {
    return {t.code16(x, y, 0), t.code16(x, y, 1), t.code16(x, y, 2), t.code16(x, y, 3)};
}

// Double Algorithm 2 as the kernel frames it: on biased moments of (z - c), c added back
// to the depths, everything clamped to its range.
ref::Nlq algorithm2_shifted(const ref::Moments& biased_shifted, double c) {
    ref::Nlq n = ref::nlq_from_moments(biased_shifted);
    n.y1 = std::clamp(n.y1 + c, -1.0, 1.0);
    n.y2 = std::clamp(n.y2 + c, -1.0, 1.0);
    n.v2 = std::clamp(n.v2, 0.0, 1.0);
    n.xi4 = std::clamp(n.xi4, 0.0, 0.25);
    return n;
}

// Shift c of the fused kernel at texel (x, y): the internal depth (float32, as the kernel
// computes it) of sample 0 of its block's centre texel; 0 for three-pass.
double kernel_shift(const DepthImage& depth, DepthRange range, FilterKernel kernel, int x, int y) {
    if (kernel == FilterKernel::three_pass) return 0.0;
    const int cx = std::min(x / 32 * 32 + 16, depth.width - 1);
    const int cy = std::min(y / 24 * 24 + 12, depth.height - 1);
    const float d = depth.at(cx, cy, 0);
    return range == DepthRange::zero_one ? 2.0f * d - 1.0f : d;
}

// Unrounded codes of Algorithm 2's output: nlq64 channels, or the nlq32 fields yt1, yt2,
// sqrt(v2), Psi4.
std::array<double, 4> continuous_codes(const ref::Nlq& n, Format format) {
    if (format == Format::nlq64)
        return {65535.0 * (n.y1 + 1.0) / 2.0, 65535.0 * (n.y2 + 1.0) / 2.0, 65535.0 * n.v2, 65535.0 * ref::psi4(n.xi4)};
    return {511.5 * (n.y1 + 1.0), 511.5 * (n.y2 + 1.0), 127.0 * std::sqrt(n.v2), 63.0 * ref::psi4(n.xi4)};
}

// Largest change of the unrounded codes when the moments the kernel works on (those of
// z - c) move by their float32 error bound. A channel whose sensitivity stays below 0.4
// codes is well conditioned: the device's code lies within one of the reference's there.
// Error bound of moment j: 2e-6 (see kMomentTolerance) relative to the size sum w|z-c|^j
// (S_j: the even moment, or by Cauchy-Schwarz sqrt(S_{j-1} S_{j+1}) for odd j), plus
// j S_{j-1} 1e-7 for the rounding of z - c itself.
std::array<double, 4> code_sensitivity(const ref::Moments& exact, double c, Format format) {
    const ref::Moments biased = ref::shift(ref::bias(exact, 3e-7, 0.375), c);
    const ref::Moments shifted = ref::shift(exact, c);
    const double S[5] = {1.0, std::sqrt(std::max(0.0, shifted.b2)), std::max(0.0, shifted.b2),
                         std::sqrt(std::max(0.0, shifted.b2 * shifted.b4)), std::max(0.0, shifted.b4)};
    std::array<double, 4> bound{};
    for (int j = 1; j <= 4; ++j) bound[j - 1] = 2e-6 * S[j] + 1e-7 * j * S[j - 1];
    const std::array<double, 4> base = continuous_codes(algorithm2_shifted(biased, c), format);
    std::array<double, 4> sensitivity{};
    for (int signs = 0; signs < 16; ++signs) {
        const auto sign = [signs](int j) { return signs >> (j - 1) & 1 ? 1.0 : -1.0; };
        const ref::Moments moved{biased.b1 + sign(1) * bound[0], biased.b2 + sign(2) * bound[1],
                                 biased.b3 + sign(3) * bound[2], biased.b4 + sign(4) * bound[3]};
        const std::array<double, 4> codes = continuous_codes(algorithm2_shifted(moved, c), format);
        for (int k = 0; k < 4; ++k) sensitivity[k] = std::max(sensitivity[k], std::fabs(codes[k] - base[k]));
    }
    return sensitivity;
}
constexpr double kWellConditioned = 0.4;

// Fields of an nlq32 word, unfolded: yt1, yt2, sqrt(v2) code, Psi4 code.
std::array<int, 4> nlq32_fields(std::uint32_t word) {
    const int psi = word & 63u, sqrt_v2 = (word >> 6) & 127u, t1 = (word >> 13) & 511u, t2 = word >> 22;
    if (t2 < t1) return {1023 - t1, 1022 - t2, sqrt_v2, psi};
    return {t1, t2, sqrt_v2, psi};
}

// The four codes (nlq64) or fields yt1, yt2, sqrt(v2) code, Psi4 code (nlq32) of a texel.
std::array<int, 4> nlq_fields(const Texture& t, int x, int y) {
    if (t.format == Format::nlq64)
        return {t.code16(x, y, 0), t.code16(x, y, 1), t.code16(x, y, 2), t.code16(x, y, 3)};
    return nlq32_fields(t.code32(x, y));
}

class Filter : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        try {
            context_ = std::make_unique<msmcl::Context>();
        } catch (const msmcl::error& e) {
            skip_reason_ = e.what();
        }
        std::cout << "seed " << test_seed() << " (set MSMCL_TEST_SEED to change)\n";
    }
    static void TearDownTestSuite() { context_.reset(); }
    void SetUp() override {
        if (!context_) GTEST_SKIP() << "no OpenCL device: " << skip_reason_;
        RecordProperty("seed", std::to_string(test_seed()));
    }

    static Texture run(const DepthImage& depth, Format format, float sigma = 2.4f,
                       DepthRange range = DepthRange::zero_one, FilterKernel kernel = FilterKernel::fused_paper) {
        msmcl::FilterOptions options;
        options.format = format;
        options.sigma = sigma;
        options.depth_range = range;
        options.kernel = kernel;
        Texture texture = msmcl::filter(*context_, depth, options);
        EXPECT_EQ(texture.format, format);
        EXPECT_EQ(texture.width, depth.width);
        EXPECT_EQ(texture.height, depth.height);
        EXPECT_EQ(texture.words.size(), std::size_t(depth.width) * depth.height * msmcl::texel_words(format));
        return texture;
    }

    static std::unique_ptr<msmcl::Context> context_;
    static std::string skip_reason_;
};
std::unique_ptr<msmcl::Context> Filter::context_;
std::string Filter::skip_reason_;

// float32 accumulation: ~20 roundings (z = 2d - 1, the powers, S-sample mean, 2 x 9 fma
// steps, taps rounded to float) of values |b| <= 1, each <= 2^-24 ~ 6e-8: < 1.5e-6.
constexpr double kMomentTolerance = 2e-6;

// Largest |device - reference| over all texels and moments; reports the worst texel.
void expect_moments_close(const Texture& texture, const std::vector<ref::Moments>& expected, double tolerance,
                          const std::string& what) {
    ASSERT_EQ(texture.format, Format::moments128);
    double worst = 0.0;
    int worst_x = 0, worst_y = 0;
    for (int y = 0; y < texture.height; ++y)
        for (int x = 0; x < texture.width; ++x)
            for (int j = 1; j <= 4; ++j) {
                const double error =
                    std::fabs(texture.moment(x, y, j) - ref::moment(expected[std::size_t(y) * texture.width + x], j));
                // NaN must fail too.
                if (!(error <= worst)) {
                    worst = std::isnan(error) ? std::numeric_limits<double>::infinity() : error;
                    worst_x = x;
                    worst_y = y;
                }
            }
    EXPECT_LE(worst, tolerance) << what << ": worst at " << at(worst_x, worst_y) << ", seed " << test_seed();
}

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

// Bound on |moments rebuilt from a decoded nlq texel - exact biased moments| for moment
// j (1..4): half a quantization step of each depth (dy) and of v2 (dv2) moved through
// b_j = (1 - v2) y1^j + v2 y2^j, the decoded xi4 minus the one a code lower (Psi4 rounds up),
// and 1e-5 for float32 Algorithm 2 and the xi4 floor 1.2e-7.
double rebuilt_tolerance(int j, const ref::Nlq& decoded, double dy, double dv2, double dxi4) {
    const double y_max = std::max(std::fabs(decoded.y1), std::fabs(decoded.y2)) + dy;
    double tolerance = j * std::pow(y_max, j - 1) * dy +
                       dv2 * std::fabs(std::pow(decoded.y2, j) - std::pow(decoded.y1, j)) + 1e-5;
    if (j == 4) tolerance += dxi4;
    return tolerance;
}

void check_nlq_against_reference(const Texture& texture, const DepthImage& depth, FilterKernel kernel,
                                 const std::vector<ref::Moments>& expected, const std::string& what) {
    const bool is64 = texture.format == Format::nlq64;
    std::size_t compared = 0, off_by_one = 0;
    double worst_ratio = 0.0;
    int worst_x = 0, worst_y = 0, worst_j = 0;
    for (int y = 0; y < texture.height; ++y) {
        for (int x = 0; x < texture.width; ++x) {
            const ref::Moments& exact = expected[std::size_t(y) * texture.width + x];
            const ref::Moments biased = ref::bias(exact, 3e-7, 0.375);
            // Decode the texel (SPEC section 3), rebuild its moments with Eq. 4.
            ref::Nlq decoded;
            double dy, dv2, dxi4;
            if (is64) {
                const ref::Codes16 codes = codes16(texture, x, y);
                decoded = ref::decode_nlq64(codes);
                dy = 1.0 / 65535.0;
                dv2 = 0.5 / 65535.0;
                dxi4 = decoded.xi4 - ref::psi4_inverse(std::max(0.0, (codes[3] - 1.0) / 65535.0));
            } else {
                const std::uint32_t word = texture.code32(x, y);
                decoded = ref::decode_nlq32(word);
                dy = 1.0 / 1023.0;
                dv2 = 2.0 * std::sqrt(decoded.v2) * (0.5 / 127.0) + (0.5 / 127.0) * (0.5 / 127.0);
                dxi4 = decoded.xi4 - ref::psi4_inverse(std::max(0.0, ((word & 63u) - 1.0) / 63.0));
            }
            dxi4 = std::max(dxi4, 1.2e-7);
            const ref::Moments rebuilt = ref::moments_from_nlq(decoded);
            for (int j = 1; j <= 4; ++j) {
                const double ratio = std::fabs(ref::moment(rebuilt, j) - ref::moment(biased, j)) /
                                     rebuilt_tolerance(j, decoded, dy, dv2, dxi4);
                if (!(ratio <= worst_ratio)) {
                    worst_ratio = std::isnan(ratio) ? 1e30 : ratio;
                    worst_x = x, worst_y = y, worst_j = j;
                }
            }
            // Codes against double Algorithm 2 (in the kernel's frame) where well conditioned.
            const double c = kernel_shift(depth, DepthRange::zero_one, kernel, x, y);
            const ref::Nlq reference = algorithm2_shifted(ref::shift(biased, c), c);
            const std::array<double, 4> sensitivity = code_sensitivity(exact, c, texture.format);
            const std::array<int, 4> got = nlq_fields(texture, x, y);
            std::array<int, 4> want;
            if (is64) {
                const ref::Codes16 codes = ref::encode_nlq64(reference);
                want = {codes[0], codes[1], codes[2], codes[3]};
            } else {
                want = nlq32_fields(ref::encode_nlq32(reference));
            }
            for (int k = 0; k < 4; ++k) {
                if (sensitivity[k] > kWellConditioned) continue;
                ++compared;
                off_by_one += got[k] != want[k];
                EXPECT_LE(std::abs(got[k] - want[k]), 1) << what << " " << at(x, y) << " field " << k
                                                         << ", seed " << test_seed();
            }
        }
    }
    EXPECT_LE(worst_ratio, 1.0) << what << ": rebuilt moments off, worst b" << worst_j << " at "
                                << at(worst_x, worst_y) << " (error / tolerance), seed " << test_seed();
    std::cout << what << ": " << compared << " well-conditioned codes compared, " << off_by_one
              << " off by one; worst rebuilt moment error " << worst_ratio << " of its tolerance (b" << worst_j
              << ")\n";
    // The check must have had something to compare.
    EXPECT_GT(compared, std::size_t(texture.width) * texture.height / 4) << what;
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
    // nlq: the fused kernel shifts by the block's centre depth; codes equal or off by one
    // where both kernels' frames are well conditioned.
    const std::vector<ref::Moments> expected = ref::filter_moments(to_reference(depth, DepthRange::zero_one), 2.4);
    for (Format format : {Format::nlq64, Format::nlq32}) {
        const Texture fused = run(depth, format);
        const Texture three = run(depth, format, 2.4f, DepthRange::zero_one, FilterKernel::three_pass);
        std::size_t compared = 0, equal = 0;
        for (int y = 0; y < depth.height; ++y)
            for (int x = 0; x < depth.width; ++x) {
                const ref::Moments& exact = expected[std::size_t(y) * depth.width + x];
                const double c = kernel_shift(depth, DepthRange::zero_one, FilterKernel::fused_paper, x, y);
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

// Far from z = 0, b2 - b1^2 cancels in float32 (SPEC section 3, Float32 guard); the
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
