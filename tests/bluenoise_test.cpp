// The blue-noise textures of the dithered lookup (docs/math.md): the table the library
// embeds (msmcl::blue_noise_textures(), generated at build time by host/bluenoise/) is what
// void-and-cluster makes from the library's seed; every channel is a permutation of equally
// spaced levels; the textures tile seamlessly; their spectrum has far less low-frequency
// energy than white noise and is radially symmetric. Plus the per-frame choice of
// kernels/msm_bluenoise.clh.
#include "bluenoise/void_and_cluster.hpp"

#include <msmcl/shade.hpp>
#include <msmcl/device_math.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

namespace bn = msmcl::bluenoise;

namespace {

constexpr int kSide = 64;
constexpr int kTexels = kSide * kSide;
constexpr int kTextures = 64;

std::uint32_t test_seed() {
    static const std::uint32_t seed = [] {
        const char* env = std::getenv("MSMCL_TEST_SEED");
        const std::uint32_t value = env ? static_cast<std::uint32_t>(std::strtoul(env, nullptr, 10)) : 1993u;
        std::printf("bluenoise_test seed %u (set MSMCL_TEST_SEED to change)\n", value);
        return value;
    }();
    return seed;
}

// Channel c of texture t of the embedded table, row-major levels.
std::vector<double> embedded_channel(int t, int c) {
    const std::uint8_t* table = msmcl::blue_noise_textures();
    std::vector<double> values(kTexels);
    for (int i = 0; i < kTexels; ++i) values[i] = table[(std::size_t(t) * kTexels + i) * 2 + c];
    return values;
}

// Power spectrum |DFT|^2 of a 64x64 signal minus its mean (separable DFT in double).
std::vector<double> power_spectrum(const std::vector<double>& signal) {
    const double pi = 3.14159265358979323846;
    std::vector<std::complex<double>> twiddle(kSide);
    for (int k = 0; k < kSide; ++k) twiddle[k] = std::polar(1.0, -2 * pi * k / kSide);
    double mean = 0;
    for (double v : signal) mean += v;
    mean /= kTexels;
    // Rows, then columns.
    std::vector<std::complex<double>> rows(kTexels), full(kTexels);
    for (int y = 0; y < kSide; ++y)
        for (int fx = 0; fx < kSide; ++fx) {
            std::complex<double> sum = 0;
            for (int x = 0; x < kSide; ++x) sum += (signal[y * kSide + x] - mean) * twiddle[(fx * x) % kSide];
            rows[y * kSide + fx] = sum;
        }
    for (int fx = 0; fx < kSide; ++fx)
        for (int fy = 0; fy < kSide; ++fy) {
            std::complex<double> sum = 0;
            for (int y = 0; y < kSide; ++y) sum += rows[y * kSide + fx] * twiddle[(fy * y) % kSide];
            full[fy * kSide + fx] = sum;
        }
    std::vector<double> power(kTexels);
    for (int i = 0; i < kTexels; ++i) power[i] = std::norm(full[i]);
    return power;
}

// Signed frequency of DFT index k (cycles per 64 texels).
int signed_frequency(int k) { return k < kSide / 2 ? k : k - kSide; }

// Mean power in the ring lo < |f| <= hi.
double ring_power(const std::vector<double>& power, double lo, double hi) {
    double sum = 0;
    int bins = 0;
    for (int fy = 0; fy < kSide; ++fy)
        for (int fx = 0; fx < kSide; ++fx) {
            const double r = std::hypot(signed_frequency(fx), signed_frequency(fy));
            if (r > lo && r <= hi) {
                sum += power[fy * kSide + fx];
                ++bins;
            }
        }
    return sum / bins;
}

TEST(BlueNoise, TableIsThe64TexturesOfTwoChannels) {
    EXPECT_EQ(msmcl::blue_noise_bytes(), std::size_t(64) * 64 * 64 * 2);
    EXPECT_EQ(msmcl::blue_noise_bytes(), bn::table_bytes);
    ASSERT_NE(msmcl::blue_noise_textures(), nullptr);
}

TEST(BlueNoise, EveryChannelIsAPermutationOfEquallySpacedLevels) {
    // 4096 texels, 256 levels: each level exactly 16 times (rank * 256 / 4096).
    for (int t = 0; t < kTextures; ++t)
        for (int c = 0; c < 2; ++c) {
            std::array<int, 256> count{};
            for (double v : embedded_channel(t, c)) ++count[static_cast<int>(v)];
            for (int level = 0; level < 256; ++level)
                ASSERT_EQ(count[level], 16) << "texture " << t << " channel " << c << " level " << level;
        }
}

TEST(BlueNoise, EmbeddedTableIsWhatTheGeneratorMakesFromTheSeed) {
    // Two textures regenerated here (a full table takes seconds): the first, and one the
    // test seed picks. A different seed gives a different texture.
    const int picked = 1 + static_cast<int>(test_seed() % (kTextures - 1));
    for (int t : {0, picked}) {
        const std::vector<std::uint8_t> texture = bn::generate_texture(bn::library_seed, t);
        ASSERT_EQ(texture.size(), std::size_t(kTexels) * 2);
        EXPECT_TRUE(std::equal(texture.begin(), texture.end(), msmcl::blue_noise_textures() + std::size_t(t) * texture.size()))
            << "texture " << t;
    }
    const std::vector<std::uint8_t> other = bn::generate_texture(bn::library_seed + 1, 0);
    EXPECT_FALSE(std::equal(other.begin(), other.end(), msmcl::blue_noise_textures()));
    // Deterministic: the same seed twice, the same bytes.
    EXPECT_EQ(bn::generate_texture(12345, 3), bn::generate_texture(12345, 3));
}

TEST(BlueNoise, TexturesTileSeamlessly) {
    // Mean |difference| of neighbours across each of the 64 vertical cuts (and horizontal
    // cuts), over all channels: the wrap-around cut (63 | 0) must look like the 63 inner cuts.
    // Each cut averages 64 rows x 128 channels = 8192 pairs.
    for (int vertical = 0; vertical < 2; ++vertical) {
        std::vector<double> cut_mean(kSide, 0.0);
        for (int t = 0; t < kTextures; ++t)
            for (int c = 0; c < 2; ++c) {
                const std::vector<double> v = embedded_channel(t, c);
                for (int cut = 0; cut < kSide; ++cut)
                    for (int k = 0; k < kSide; ++k) {
                        const int a = (cut + kSide - 1) % kSide, b = cut;
                        const double d = vertical ? v[k * kSide + a] - v[k * kSide + b] : v[a * kSide + k] - v[b * kSide + k];
                        cut_mean[cut] += std::abs(d) / (kSide * kTextures * 2);
                    }
            }
        double mean = 0, variance = 0;
        for (int cut = 1; cut < kSide; ++cut) mean += cut_mean[cut] / (kSide - 1);
        for (int cut = 1; cut < kSide; ++cut) variance += (cut_mean[cut] - mean) * (cut_mean[cut] - mean) / (kSide - 2);
        const double z = (cut_mean[0] - mean) / std::sqrt(variance);
        std::printf("%s cuts: mean |neighbour difference| %.3f (sd %.3f over inner cuts), wrap-around cut %.3f (z %.2f)\n",
                    vertical ? "vertical" : "horizontal", mean, std::sqrt(variance), cut_mean[0], z);
        // The wrap-around cut is one sample of the same distribution: within 4 sd.
        EXPECT_LT(std::abs(z), 4.0);
    }
}

TEST(BlueNoise, SpectrumHasWeakLowFrequenciesAndIsRadiallySymmetric) {
    // Mean power spectrum of the 128 channels, and of white noise with the same values
    // (each channel randomly permuted).
    std::mt19937 random(test_seed());
    std::vector<double> blue(kTexels, 0.0), white(kTexels, 0.0);
    for (int t = 0; t < kTextures; ++t)
        for (int c = 0; c < 2; ++c) {
            std::vector<double> v = embedded_channel(t, c);
            const std::vector<double> pb = power_spectrum(v);
            std::shuffle(v.begin(), v.end(), random);
            const std::vector<double> pw = power_spectrum(v);
            for (int i = 0; i < kTexels; ++i) {
                blue[i] += pb[i] / (2 * kTextures);
                white[i] += pw[i] / (2 * kTextures);
            }
        }

    // Radial profile against white noise (Nyquist at |f| = 32).
    for (double r = 0; r < 32; r += 4)
        std::printf("|f| in (%2.0f, %2.0f]: blue / white power %.3f\n", r, r + 4, ring_power(blue, r, r + 4) / ring_power(white, r, r + 4));
    const double low = ring_power(blue, 0, 8) / ring_power(white, 0, 8);
    const double high = ring_power(blue, 16, 32) / ring_power(white, 16, 32);
    std::printf("low band (0, 8]: %.4f of white noise's power; high band (16, 32]: %.3f\n", low, high);
    // Blue noise: the low band (a quarter of the Nyquist radius) holds almost none of white
    // noise's power (measured 3e-4; asserted 1e-2), the high band more than white noise (the
    // total is the same).
    EXPECT_LT(low, 0.01);
    EXPECT_GT(high, 1.2);

    // Radial symmetry: in the band 10 < |f| <= 30, each bin's power relative to the mean of
    // its ring (|f| rounded), averaged over 8 angular sectors (angle folded to [0, pi): the
    // spectrum of a real signal is symmetric): the sectors agree within 10%. Sampling noise
    // of one sector: ~130 bins x 128 spectra of exponential variates, ~0.3%.
    const double pi = 3.14159265358979323846;
    std::array<double, 64> ring_sum{};
    std::array<int, 64> ring_bins{};
    for (int fy = 0; fy < kSide; ++fy)
        for (int fx = 0; fx < kSide; ++fx) {
            const int ring = static_cast<int>(std::lround(std::hypot(signed_frequency(fx), signed_frequency(fy))));
            ring_sum[ring] += blue[fy * kSide + fx];
            ++ring_bins[ring];
        }
    std::array<double, 8> sector_sum{};
    std::array<int, 8> sector_bins{};
    for (int fy = 0; fy < kSide; ++fy)
        for (int fx = 0; fx < kSide; ++fx) {
            const int sx = signed_frequency(fx), sy = signed_frequency(fy);
            const double r = std::hypot(sx, sy);
            if (r <= 10 || r > 30) continue;
            const int ring = static_cast<int>(std::lround(r));
            double angle = std::atan2(double(sy), double(sx));
            if (angle < 0) angle += pi;
            const int sector = std::min(7, static_cast<int>(angle / pi * 8));
            sector_sum[sector] += blue[fy * kSide + fx] / (ring_sum[ring] / ring_bins[ring]);
            ++sector_bins[sector];
        }
    double lo = 1e300, hi = 0;
    for (int s = 0; s < 8; ++s) {
        const double mean = sector_sum[s] / sector_bins[s];
        lo = std::min(lo, mean);
        hi = std::max(hi, mean);
    }
    std::printf("band (10, 30], 8 angular sectors: max / min mean power %.4f\n", hi / lo);
    EXPECT_LT(hi / lo, 1.1);
}

TEST(BlueNoise, FramesPickEveryTextureAndShift) {
    // The per-frame constant (a hash of the frame number): over 4096 frames every texture and
    // every shift occurs, each about 64 times.
    std::array<int, 64> textures{}, shifts_x{}, shifts_y{};
    for (std::uint32_t frame = 0; frame < 4096; ++frame) {
        const msmcl::BlueNoiseFrame f = msmcl::blue_noise_frame(frame);
        ASSERT_LT(f.texture, 64u);
        ASSERT_LT(f.offset_x, 64u);
        ASSERT_LT(f.offset_y, 64u);
        ++textures[f.texture];
        ++shifts_x[f.offset_x];
        ++shifts_y[f.offset_y];
    }
    for (const auto* counts : {&textures, &shifts_x, &shifts_y}) {
        const auto [lo, hi] = std::minmax_element(counts->begin(), counts->end());
        // Binomial(4096, 1/64): mean 64, sd 7.9; 6 sd either side.
        EXPECT_GE(*lo, 64 - 48);
        EXPECT_LE(*hi, 64 + 48);
    }
    // The noise of a pixel is the shifted texture's texel, offset (level + 0.5) / 256.
    const msmcl::BlueNoiseFrame f = msmcl::blue_noise_frame(7);
    const std::uint8_t* texel = msmcl::blue_noise_textures() +
                                ((std::size_t(f.texture) * 64 + (5 + f.offset_y) % 64) * 64 + (70 + f.offset_x) % 64) * 2;
    const msmcl::DitherNoise n = msmcl::blue_noise_at(7, 70, 5);
    EXPECT_EQ(n.x, (texel[0] + 0.5f) / 256.0f);
    EXPECT_EQ(n.y, (texel[1] + 0.5f) / 256.0f);
}

} // namespace
