// Helpers of the filter suite (tests/filter_test.cpp): synthetic depth maps, the
// double-precision reference in each kernel's frame, code sensitivity, nlq checks, the
// shared Context fixture.
#pragma once

#include "reference/filter_reference.hpp"
#include "ops/kernel_variants.hpp"
#include "runtime/tuning.hpp"

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
#include <sstream>
#include <string>
#include <vector>

namespace filter_fixtures {


namespace ref = msmcl::reference;
using msmcl::DepthImage;
using msmcl::DepthRange;
using msmcl::FilterKernel;
using msmcl::Format;
using msmcl::Texture;

// Sets an environment variable for one scope and puts back what was there before (a
// tuning variable the test run itself was started with, such as the rusticl label's
// MSMCL_CPU_TILE, must outlive the test that overrides it).
class ScopedEnvironment {
public:
    ScopedEnvironment(const char* name, const char* value) : name_(name) {
        if (const char* previous = std::getenv(name)) previous_ = previous, had_previous_ = true;
        ::setenv(name, value, 1);
    }
    ~ScopedEnvironment() {
        if (had_previous_) ::setenv(name_.c_str(), previous_.c_str(), 1);
        else ::unsetenv(name_.c_str());
    }
    ScopedEnvironment(const ScopedEnvironment&) = delete;
    ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

private:
    std::string name_;
    std::string previous_;
    bool had_previous_ = false;
};

inline std::uint32_t test_seed() {
    const char* text = std::getenv("MSMCL_TEST_SEED");
    return text ? static_cast<std::uint32_t>(std::strtoul(text, nullptr, 10)) : 4096u;
}

// A smooth-ish depth map with occluders: a sloped, wavy receiver in [0.35, 0.95] and
// random disks and boxes in front of it (one at d = 0 exactly, one at d = 1), sampled at
// S sub-texel positions so that texels on occluder edges mix depths.
inline DepthImage make_depth(int width, int height, int samples, DepthRange range, std::uint32_t seed) {
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

inline ref::DepthMap to_reference(const DepthImage& image, DepthRange range) {
    return ref::DepthMap{image.width, image.height, image.samples, image.depth, range == DepthRange::zero_one};
}

inline std::string at(int x, int y) { return "texel (" + std::to_string(x) + ", " + std::to_string(y) + ")"; }

inline ref::Codes16 codes16(const Texture& t, int x, int y) {
    return {t.code16(x, y, 0), t.code16(x, y, 1), t.code16(x, y, 2), t.code16(x, y, 3)};
}

// Double Algorithm 2 as the kernel frames it: on biased moments of (z - c), c added back
// to the depths, everything clamped to its range.
inline ref::Nlq algorithm2_shifted(const ref::Moments& biased_shifted, double c) {
    ref::Nlq n = ref::nlq_from_moments(biased_shifted);
    n.y1 = std::clamp(n.y1 + c, -1.0, 1.0);
    n.y2 = std::clamp(n.y2 + c, -1.0, 1.0);
    n.v2 = std::clamp(n.v2, 0.0, 1.0);
    n.xi4 = std::clamp(n.xi4, 0.0, 0.25);
    return n;
}

// Tile of the CPU distribution (kernels/filter_fused_cpu.cl) on the device the test
// program's Contexts pick: the library's own answer (MSMCL_CPU_TILE or the default, cut
// where the device limits loops), read anew at each call since tests override the variable.
inline std::array<int, 2> cpu_tile() {
    static const msmcl::DeviceInfo device = msmcl::Context().device();
    const msmcl::detail::TileSize tile = msmcl::detail::filter_cpu_tile(device);
    return {tile.width, tile.height};
}

// Output block of a fused kernel: the paper's 32x24 (kernels/filter_fused_gpu.cl) or the CPU
// tile; three_pass has none (its blocks are single texels, it reads the paper's size here).
inline std::array<int, 2> output_block(FilterKernel kernel) {
    return kernel == FilterKernel::fused_cpu ? cpu_tile() : std::array<int, 2>{32, 24};
}

// Shift c of a kernel per texel, in float32 as the kernel computes it from the internal
// depths z = 2d - 1 (or d) of sample 0: (min z + max z) * 0.5f over the input texels of the
// texel's output block (fused_paper: 32x24, fused_cpu: its tile) and their guard band of 4
// (coordinates clamped into the image) whose z < 1 (the far plane takes no part; 1 if all
// are there); three_pass, 0. Computed once per block.
class KernelShift {
public:
    KernelShift(const DepthImage& depth, DepthRange range, FilterKernel kernel)
        : kernel_(kernel), block_(output_block(kernel)) {
        if (kernel == FilterKernel::three_pass) return;
        columns_ = (depth.width + block_[0] - 1) / block_[0];
        const int rows = (depth.height + block_[1] - 1) / block_[1];
        // msm_internal_depth: NaN -> -1, clamped into [-1, 1].
        const auto internal = [&](int tx, int ty) {
            const float d = depth.at(tx, ty, 0);
            const float z = range == DepthRange::zero_one ? 2.0f * d - 1.0f : d;
            return std::isnan(z) ? -1.0f : std::clamp(z, -1.0f, 1.0f);
        };
        for (int row = 0; row < rows; ++row)
            for (int column = 0; column < columns_; ++column) {
                const int x0 = column * block_[0] - 4, y0 = row * block_[1] - 4;
                float lowest = 1.0f, highest = -1.0f;
                bool any = false;
                for (int by = 0; by < block_[1] + 8; ++by)
                    for (int bx = 0; bx < block_[0] + 8; ++bx) {
                        const float z = internal(std::clamp(x0 + bx, 0, depth.width - 1),
                                                 std::clamp(y0 + by, 0, depth.height - 1));
                        if (z == 1.0f) continue;
                        lowest = any ? std::min(lowest, z) : z;
                        highest = any ? std::max(highest, z) : z;
                        any = true;
                    }
                shifts_.push_back(any ? (lowest + highest) * 0.5f : 1.0f);
            }
    }
    double at(int x, int y) const {
        if (kernel_ == FilterKernel::three_pass) return 0.0;
        return shifts_[std::size_t(y / block_[1]) * columns_ + x / block_[0]];
    }

private:
    FilterKernel kernel_;
    std::array<int, 2> block_;
    int columns_ = 0;
    std::vector<float> shifts_;
};

// Unrounded codes of Algorithm 2's output: nlq64 channels, or the nlq32 fields yt1, yt2,
// sqrt(v2), Psi4.
inline std::array<double, 4> continuous_codes(const ref::Nlq& n, Format format) {
    if (format == Format::nlq64)
        return {65535.0 * (n.y1 + 1.0) / 2.0, 65535.0 * (n.y2 + 1.0) / 2.0, 65535.0 * n.v2, 65535.0 * ref::psi4(n.xi4)};
    return {511.5 * (n.y1 + 1.0), 511.5 * (n.y2 + 1.0), 127.0 * std::sqrt(n.v2), 63.0 * ref::psi4(n.xi4)};
}

// The float32 sums of the moments of z - c: (40 + S) roundings (the shift, the powers, the
// S-sample mean, 2 x 9 taps), each <= 2^-24 of the running size, for S <= 8: 48 x 6e-8. The
// tolerance of rebuilt moments uses it; the choice of well-conditioned codes keeps 2e-6 (a
// tighter bound admits more codes to the one-step comparison).
inline constexpr double kShiftedMomentTolerance = 3e-6;

// Largest change of the unrounded codes when the moments the kernel works on (those of
// z - c) move by their float32 error bound. A channel whose sensitivity stays below 0.4
// codes is well conditioned: the device's code lies within one of the reference's there.
// Error bound of moment j: `relative` to the size sum w|z-c|^j
// (S_j: the even moment, or by Cauchy-Schwarz sqrt(S_{j-1} S_{j+1}) for odd j), plus
// j S_{j-1} 1e-7 for the rounding of z - c itself.
inline std::array<double, 4> float32_moment_bound(const ref::Moments& exact, double c, double relative) {
    const ref::Moments shifted = ref::shift(exact, c);
    const double S[5] = {1.0, std::sqrt(std::max(0.0, shifted.b2)), std::max(0.0, shifted.b2),
                         std::sqrt(std::max(0.0, shifted.b2 * shifted.b4)), std::max(0.0, shifted.b4)};
    std::array<double, 4> bound{};
    for (int j = 1; j <= 4; ++j) bound[j - 1] = relative * S[j] + 1e-7 * j * S[j - 1];
    return bound;
}

// The biased moments of (z - c) moved by +-bound (sign pattern `signs`, bit j-1 for b_j).
inline ref::Moments moved_moments(const ref::Moments& biased, const std::array<double, 4>& bound, int signs) {
    const auto sign = [signs](int j) { return signs >> (j - 1) & 1 ? 1.0 : -1.0; };
    return {biased.b1 + sign(1) * bound[0], biased.b2 + sign(2) * bound[1], biased.b3 + sign(3) * bound[2],
            biased.b4 + sign(4) * bound[3]};
}

inline std::array<double, 4> code_sensitivity(const ref::Moments& exact, double c, Format format) {
    const ref::Moments biased = ref::shift(ref::bias(exact, 3e-7, 0.375), c);
    const std::array<double, 4> bound = float32_moment_bound(exact, c, 2e-6);
    const std::array<double, 4> base = continuous_codes(algorithm2_shifted(biased, c), format);
    std::array<double, 4> sensitivity{};
    for (int signs = 0; signs < 16; ++signs) {
        const std::array<double, 4> codes =
            continuous_codes(algorithm2_shifted(moved_moments(biased, bound, signs), c), format);
        for (int k = 0; k < 4; ++k) sensitivity[k] = std::max(sensitivity[k], std::fabs(codes[k] - base[k]));
    }
    return sensitivity;
}

// How far the float32 noise of the kernel's moments (the bound above, in the frame of c) can
// move the moments rebuilt from Algorithm 2's output: double Algorithm 2 on the moved
// moments, rebuilt with Eq. 4, against the same on the exact ones. Where nothing clamps this
// is the noise itself, moved to the unshifted frame; where a root leaves [-1, 1] or a weight
// [0, 1], Algorithm 2 no longer reproduces its input and the noise shows through the roots'
// sensitivity (e.g. a root of weight 0.04 at the near plane, 0.12 from the other).
inline std::array<double, 4> rebuilt_noise(const ref::Moments& exact, double c) {
    const ref::Moments biased = ref::shift(ref::bias(exact, 3e-7, 0.375), c);
    const std::array<double, 4> bound = float32_moment_bound(exact, c, kShiftedMomentTolerance);
    const ref::Moments base = ref::moments_from_nlq(algorithm2_shifted(biased, c));
    std::array<double, 4> noise{};
    for (int signs = 0; signs < 16; ++signs) {
        const ref::Moments moved = ref::moments_from_nlq(algorithm2_shifted(moved_moments(biased, bound, signs), c));
        for (int j = 1; j <= 4; ++j)
            noise[j - 1] = std::max(noise[j - 1], std::fabs(ref::moment(moved, j) - ref::moment(base, j)));
    }
    return noise;
}
inline constexpr double kWellConditioned = 0.4;

// Fields of an nlq32 word, unfolded: yt1, yt2, sqrt(v2) code, Psi4 code.
inline std::array<int, 4> nlq32_fields(std::uint32_t word) {
    const int psi = word & 63u, sqrt_v2 = (word >> 6) & 127u, t1 = (word >> 13) & 511u, t2 = word >> 22;
    if (t2 < t1) return {1023 - t1, 1022 - t2, sqrt_v2, psi};
    return {t1, t2, sqrt_v2, psi};
}

// The four codes (nlq64) or fields yt1, yt2, sqrt(v2) code, Psi4 code (nlq32) of a texel.
inline std::array<int, 4> nlq_fields(const Texture& t, int x, int y) {
    if (t.format == Format::nlq64)
        return {t.code16(x, y, 0), t.code16(x, y, 1), t.code16(x, y, 2), t.code16(x, y, 3)};
    return nlq32_fields(t.code32(x, y));
}

// Shared fixture: one Context (its device, PoCL in CI) for the whole test program; skips
// every test when there is no OpenCL device.
class FilterTest : public ::testing::Test {
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

    static inline std::unique_ptr<msmcl::Context> context_;
    static inline std::string skip_reason_;
};

// float32 accumulation: ~20 roundings (z = 2d - 1, the powers, S-sample mean, 2 x 9 fma
// steps, taps rounded to float) of values |b| <= 1, each <= 2^-24 ~ 6e-8: < 1.5e-6.
inline constexpr double kMomentTolerance = 2e-6;

// Largest |device - reference| over all texels and moments; reports the worst texel.
inline void expect_moments_close(const Texture& texture, const std::vector<ref::Moments>& expected, double tolerance,
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

// Bound on |moments rebuilt from a decoded nlq texel - exact biased moments| for moment
// j (1..4): half a quantization step of each depth (dy) and of v2 (dv2) moved through
// b_j = (1 - v2) y1^j + v2 y2^j, the decoded xi4 minus the one a code lower (Psi4 rounds up),
// the float32 noise of the kernel's moments as it reaches the rebuilt ones (`noise`,
// rebuilt_noise), and 1e-5 for float32 Algorithm 2 and the xi4 floor 1.2e-7.
inline double rebuilt_tolerance(int j, const ref::Nlq& decoded, double dy, double dv2, double dxi4, double noise) {
    const double y_max = std::max(std::fabs(decoded.y1), std::fabs(decoded.y2)) + dy;
    double tolerance = j * std::pow(y_max, j - 1) * dy +
                       dv2 * std::fabs(std::pow(decoded.y2, j) - std::pow(decoded.y1, j)) + 1e-5 + noise;
    if (j == 4) tolerance += dxi4;
    return tolerance;
}

inline void check_nlq_against_reference(const Texture& texture, const DepthImage& depth, FilterKernel kernel,
                                 const std::vector<ref::Moments>& expected, const std::string& what) {
    const bool is64 = texture.format == Format::nlq64;
    std::size_t compared = 0, off_by_one = 0;
    double worst_ratio = 0.0;
    int worst_x = 0, worst_y = 0, worst_j = 0;
    const KernelShift shift(depth, DepthRange::zero_one, kernel);
    for (int y = 0; y < texture.height; ++y) {
        for (int x = 0; x < texture.width; ++x) {
            const ref::Moments& exact = expected[std::size_t(y) * texture.width + x];
            const ref::Moments biased = ref::bias(exact, 3e-7, 0.375);
            // Decode the texel (docs/math.md), rebuild its moments with Eq. 4.
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
            const double c = shift.at(x, y);
            const std::array<double, 4> noise = rebuilt_noise(exact, c);
            for (int j = 1; j <= 4; ++j) {
                const double ratio = std::fabs(ref::moment(rebuilt, j) - ref::moment(biased, j)) /
                                     rebuilt_tolerance(j, decoded, dy, dv2, dxi4, noise[j - 1]);
                if (!(ratio <= worst_ratio)) {
                    worst_ratio = std::isnan(ratio) ? 1e30 : ratio;
                    worst_x = x, worst_y = y, worst_j = j;
                }
            }
            // Codes against double Algorithm 2 (in the kernel's frame) where well conditioned.
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

} // namespace filter_fixtures
