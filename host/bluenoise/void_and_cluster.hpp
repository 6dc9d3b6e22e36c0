// Blue noise by the void-and-cluster method (Ulichney 1993, "Void-and-cluster method for
// dither array generation"), as Peters, HPG 2017, section 4.2 uses it: Gaussian energy filter with
// sigma 1.9 on a torus (so every texture tiles), 64 textures of 64x64 texels, 2 channels,
// 8 bits per channel, every channel a permutation of the 256 equally spaced levels.
//
// Header-only: the build-time generator (generate_table.cpp), the library's fallback
// (host/shading/blue_noise.cpp) and the tests include it. Energies are integers (a Gaussian
// quantized to 2^24) and ties are broken by a seeded per-texel key, so the result depends on
// the seed alone, bit for bit, on every compiler and platform.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <thread>
#include <vector>

namespace msmcl::bluenoise {

inline constexpr int texture_side = 64;
inline constexpr int texture_count = 64;
inline constexpr int channel_count = 2;
inline constexpr double gaussian_sigma = 1.9;
/// Share of minority texels in the initial binary pattern (Ulichney's usual 10%).
inline constexpr double initial_fill = 0.1;
/// Seed of the table the library embeds.
inline constexpr std::uint64_t library_seed = 0x6d736d636c424e31ull; // "msmclBN1"
/// Bytes of the whole table: byte ((t * 64 + y) * 64 + x) * 2 + c.
inline constexpr std::size_t table_bytes =
    std::size_t(texture_count) * texture_side * texture_side * channel_count;

/// SplitMix64 (Steele, Lea, Flood 2014): a small, fully specified generator, so the seed
/// alone fixes the output (std:: distributions are implementation-defined).
class SplitMix64 {
public:
    explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, bound) (bound <= 2^32; the modulo bias is below 2^-32).
    std::uint32_t below(std::uint32_t bound) { return static_cast<std::uint32_t>((next() >> 32) % bound); }

private:
    std::uint64_t state_;
};

/// The Gaussian energy filter exp(-r^2 / (2 sigma^2)) scaled by 2^24 and rounded, on the
/// offsets where it is not 0 (|dx|, |dy| <= 12 for sigma 1.9).
struct EnergyFilter {
    struct Tap {
        int dx, dy;
        std::int64_t weight;
    };
    std::vector<Tap> taps;

    explicit EnergyFilter(double sigma, int side) {
        const double scale = 16777216.0;
        const int reach = static_cast<int>(std::ceil(sigma * std::sqrt(2.0 * std::log(2.0 * scale))));
        if (2 * reach + 1 > side) throw std::invalid_argument("void-and-cluster: filter wider than the texture");
        for (int dy = -reach; dy <= reach; ++dy)
            for (int dx = -reach; dx <= reach; ++dx) {
                const double weight = std::floor(scale * std::exp(-(dx * dx + dy * dy) / (2.0 * sigma * sigma)) + 0.5);
                if (weight > 0) taps.push_back({dx, dy, static_cast<std::int64_t>(weight)});
            }
    }
};

/// A binary pattern on a side x side torus and the energy of its ones at every texel.
/// Energies carry a unique tie-break key in their low 12+ bits (a seeded permutation of the
/// texels), so every argmin/argmax is unique and independent of the scan order.
class BinaryPattern {
public:
    BinaryPattern(int side, const EnergyFilter& filter, const std::vector<std::int64_t>& tie_keys)
        : side_(side), filter_(&filter), ones_(std::size_t(side) * side, 0), energy_(tie_keys) {}

    bool is_one(int texel) const { return ones_[texel] != 0; }
    std::size_t texels() const { return ones_.size(); }

    void set(int texel, bool one) {
        if (is_one(texel) == one) return;
        ones_[texel] = one ? 1 : 0;
        // Add or remove this texel's share of the energy around it (wrapping around).
        const int x = texel % side_, y = texel / side_;
        const std::int64_t sign = one ? 1 : -1;
        for (const EnergyFilter::Tap& tap : filter_->taps) {
            const int tx = (x + tap.dx + side_) % side_, ty = (y + tap.dy + side_) % side_;
            energy_[std::size_t(ty) * side_ + tx] += sign * (tap.weight << tie_bits);
        }
    }

    /// The tightest cluster: the one with the highest energy.
    int tightest_cluster() const { return extreme(true); }
    /// The largest void: the zero with the lowest energy.
    int largest_void() const { return extreme(false); }

    static constexpr int tie_bits = 13; // > log2(64 * 64) texels

private:
    int extreme(bool among_ones) const {
        int best = -1;
        for (std::size_t i = 0; i < ones_.size(); ++i) {
            if ((ones_[i] != 0) != among_ones) continue;
            if (best < 0 || (among_ones ? energy_[i] > energy_[best] : energy_[i] < energy_[best]))
                best = static_cast<int>(i);
        }
        if (best < 0) throw std::logic_error("void-and-cluster: no texel of the requested kind");
        return best;
    }

    int side_;
    const EnergyFilter* filter_;
    std::vector<std::uint8_t> ones_;
    std::vector<std::int64_t> energy_;
};

/// Ulichney's dither array: the rank (0 .. side^2 - 1) of every texel, row-major.
inline std::vector<int> void_and_cluster_ranks(int side, double sigma, std::uint64_t seed) {
    const int texels = side * side;
    const EnergyFilter filter(sigma, side);
    SplitMix64 random(seed);

    // Tie-break keys: a random permutation of 0 .. texels - 1.
    std::vector<std::int64_t> keys(texels);
    for (int i = 0; i < texels; ++i) keys[i] = i;
    for (int i = texels - 1; i > 0; --i) std::swap(keys[i], keys[random.below(static_cast<std::uint32_t>(i + 1))]);

    // Initial binary pattern: 10% ones at random texels (white noise).
    BinaryPattern prototype(side, filter, keys);
    const int initial_ones = static_cast<int>(initial_fill * texels);
    std::vector<int> order(texels);
    for (int i = 0; i < texels; ++i) order[i] = i;
    for (int i = 0; i < initial_ones; ++i) {
        std::swap(order[i], order[i + random.below(static_cast<std::uint32_t>(texels - i))]);
        prototype.set(order[i], true);
    }

    // Move the tightest cluster into the largest void until they coincide.
    for (int swaps = 0;; ++swaps) {
        if (swaps > 100 * texels) throw std::logic_error("void-and-cluster: the initial pattern does not converge");
        const int cluster = prototype.tightest_cluster();
        prototype.set(cluster, false);
        const int void_texel = prototype.largest_void();
        prototype.set(void_texel, true);
        if (void_texel == cluster) break;
    }

    std::vector<int> rank(texels, -1);
    // Phase 1: remove the tightest clusters of the prototype, ranks initial_ones - 1 .. 0.
    {
        BinaryPattern pattern = prototype;
        for (int r = initial_ones - 1; r >= 0; --r) {
            const int cluster = pattern.tightest_cluster();
            pattern.set(cluster, false);
            rank[cluster] = r;
        }
    }
    // Phases 2 and 3: fill the largest voids, ranks initial_ones .. texels - 1. (Past half
    // full, Ulichney's tightest cluster of the zeros is the largest void of the ones: the two
    // energies add up to the same constant everywhere.)
    {
        BinaryPattern pattern = prototype;
        for (int r = initial_ones; r < texels; ++r) {
            const int void_texel = pattern.largest_void();
            pattern.set(void_texel, true);
            rank[void_texel] = r;
        }
    }
    return rank;
}

/// Seed of one channel of one texture of the table made from `seed`.
inline std::uint64_t channel_seed(std::uint64_t seed, int texture, int channel) {
    SplitMix64 mix(seed ^ (0x632be59bd9b4e019ull * static_cast<std::uint64_t>(texture * channel_count + channel + 1)));
    return mix.next();
}

/// One texture: side x side texels, 2 interleaved 8-bit channels, level = rank * 256 / side^2.
inline std::vector<std::uint8_t> generate_texture(std::uint64_t seed, int texture) {
    const int texels = texture_side * texture_side;
    std::vector<std::uint8_t> bytes(std::size_t(texels) * channel_count);
    for (int c = 0; c < channel_count; ++c) {
        const std::vector<int> rank = void_and_cluster_ranks(texture_side, gaussian_sigma, channel_seed(seed, texture, c));
        for (int i = 0; i < texels; ++i)
            bytes[std::size_t(i) * channel_count + c] = static_cast<std::uint8_t>(rank[i] * 256 / texels);
    }
    return bytes;
}

/// The whole table from `seed` (table_bytes, layout above), textures spread over the
/// hardware threads.
inline std::vector<std::uint8_t> generate_table(std::uint64_t seed) {
    std::vector<std::uint8_t> table(table_bytes);
    const std::size_t texture_bytes = table_bytes / texture_count;
    const int workers = std::max(1, std::min<int>(texture_count, static_cast<int>(std::thread::hardware_concurrency())));
    std::vector<std::thread> threads;
    for (int w = 0; w < workers; ++w)
        threads.emplace_back([&table, texture_bytes, seed, w, workers] {
            for (int t = w; t < texture_count; t += workers) {
                const std::vector<std::uint8_t> texture = generate_texture(seed, t);
                std::copy(texture.begin(), texture.end(), table.begin() + static_cast<std::ptrdiff_t>(t * texture_bytes));
            }
        });
    for (std::thread& thread : threads) thread.join();
    return table;
}

} // namespace msmcl::bluenoise
