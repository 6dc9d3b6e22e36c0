// Case cpu_loop_naive: the same work as a plain multi-threaded C++ loop on the host, written
// the straightforward way (case cpu_loop is the tuned peer): per band of output rows and
// thread, resolve a row, blur it horizontally into a ring of 9 rows, blur vertically,
// quantize one texel at a time (the kernels' math headers compiled as C++), write.
// Compiled with -O3 (and -march=native where the bench is built with MSMCL_BENCH_NATIVE),
// no OpenMP; std::thread, one band per hardware thread. Same float operation order as the
// kernels: moments128/msm64 equal three_pass bit for bit.
#include "harness.hpp"

#include <msmcl/filter.hpp>

#include "kernels/msm_formats.clh"

#include <algorithm>
#include <cmath>
#include <thread>

namespace msmcl::bench {

namespace {

constexpr int kGuard = 4;

// Internal depth z in [-1,1] of depth d in [0,1] (NaN -> -1), as msm_internal_depth,
// written so that GCC vectorizes it.
inline float internal_depth(float d) {
    float z = 2.0f * d - 1.0f;
    z = z > 1.0f ? 1.0f : z;
    z = z < -1.0f ? -1.0f : z;
    return z != z ? -1.0f : z;
}

// Moments of texel row `y` (mean over S samples, as the kernels' resolve_texel) into four
// planes of width + 8 floats, the 4 guard texels each side copies of the edge.
template <int S>
void resolve_row(const float* depth_row, int width, float* planes) {
    const std::size_t stride = static_cast<std::size_t>(width) + 2 * kGuard;
    float* b1 = planes + kGuard;
    float* b2 = b1 + stride;
    float* b3 = b2 + stride;
    float* b4 = b3 + stride;
    for (int x = 0; x < width; ++x) {
        msm_moments sum = msm_moments_of(internal_depth(depth_row[x * S]));
#pragma GCC unroll 16
        for (int s = 1; s < S; ++s) sum = msm_moments_add(sum, msm_moments_of(internal_depth(depth_row[x * S + s])));
        const msm_moments m = msm_moments_scale(sum, 1.0f / float(S));
        b1[x] = m.b1;
        b2[x] = m.b2;
        b3[x] = m.b3;
        b4[x] = m.b4;
    }
    for (int j = 0; j < 4; ++j) {
        float* plane = planes + j * stride;
        for (int g = 0; g < kGuard; ++g) {
            plane[g] = plane[kGuard];
            plane[kGuard + width + g] = plane[kGuard + width - 1];
        }
    }
}

// 9-tap sum of v[0], v[step], ... v[8 step] in the kernels' order (first tap innermost).
inline float taps9(const float* w, const float* v, std::size_t step) {
    float sum = w[0] * v[0];
    for (int i = 1; i < 9; ++i) sum = std::fma(w[i], v[i * step], sum);
    return sum;
}

// Output rows [y_begin, y_end) of the texture.
template <int S>
void filter_band(const DepthImage& depth, Format format, const std::array<float, 9>& taps,
                 std::uint32_t* texture, int y_begin, int y_end) {
    const int width = depth.width, height = depth.height;
    const std::size_t padded = static_cast<std::size_t>(width) + 2 * kGuard;
    std::vector<float> resolved(4 * padded);
    std::vector<float> ring(9 * 4 * static_cast<std::size_t>(width)); // 9 rows x 4 planes
    std::vector<float> blurred(4 * static_cast<std::size_t>(width));
    const float* w = taps.data();
    const auto ring_row = [&](int slot, int j) { return ring.data() + (static_cast<std::size_t>(slot) * 4 + j) * width; };
    const int first = y_begin - kGuard;
    for (int iy = first; iy < y_end + kGuard; ++iy) {
        // Resolve input row iy (clamped), blur it horizontally into its ring slot.
        const int y = std::clamp(iy, 0, height - 1);
        resolve_row<S>(depth.depth.data() + static_cast<std::size_t>(y) * width * S, width, resolved.data());
        const int slot = (iy - first) % 9;
        for (int j = 0; j < 4; ++j) {
            const float* in = resolved.data() + j * padded;
            float* out = ring_row(slot, j);
            for (int x = 0; x < width; ++x) out[x] = taps9(w, in + x, 1);
        }
        if (iy < y_begin + kGuard) continue;
        // Output row iy - 4: vertical blur over the ring (rows iy-8 .. iy, oldest first).
        const int out_y = iy - kGuard;
        for (int j = 0; j < 4; ++j) {
            const float* rows[9];
            for (int i = 0; i < 9; ++i) rows[i] = ring_row((iy - 8 - first + i) % 9, j);
            float* out = blurred.data() + j * width;
            for (int x = 0; x < width; ++x) {
                float sum = w[0] * rows[0][x];
                for (int i = 1; i < 9; ++i) sum = std::fma(w[i], rows[i][x], sum);
                out[x] = sum;
            }
        }
        // Quantize and write the row.
        const std::size_t words = texel_words(format);
        std::uint32_t* row_out = texture + static_cast<std::size_t>(out_y) * width * words;
        for (int x = 0; x < width; ++x) {
            msm_moments m;
            m.b1 = blurred[x];
            m.b2 = blurred[width + x];
            m.b3 = blurred[2 * width + x];
            m.b4 = blurred[3 * width + x];
            if (format == Format::moments128) {
                row_out[4 * x] = as_uint(m.b1);
                row_out[4 * x + 1] = as_uint(m.b2);
                row_out[4 * x + 2] = as_uint(m.b3);
                row_out[4 * x + 3] = as_uint(m.b4);
            } else if (format == Format::msm64) {
                const msm_word2 code = msm_encode_msm64(m);
                row_out[2 * x] = code.w0;
                row_out[2 * x + 1] = code.w1;
            } else if (format == Format::nlq64) {
                const msm_word2 code = msm_encode_nlq64(msm_nlq_from_moments(msm_bias(m, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT)));
                row_out[2 * x] = code.w0;
                row_out[2 * x + 1] = code.w1;
            } else {
                row_out[x] = msm_encode_nlq32(msm_nlq_from_moments(msm_bias(m, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT)));
            }
        }
    }
}

// The whole texture, one band of rows per hardware thread.
void filter_on_host(const DepthImage& depth, Format format, float sigma, std::uint32_t* texture) {
    const std::array<float, 9> taps = gaussian_taps(sigma);
    const int threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    const int band = (depth.height + threads - 1) / threads;
    const auto work = [&](int y_begin, int y_end) {
        switch (depth.samples) {
        case 1: filter_band<1>(depth, format, taps, texture, y_begin, y_end); break;
        case 2: filter_band<2>(depth, format, taps, texture, y_begin, y_end); break;
        case 4: filter_band<4>(depth, format, taps, texture, y_begin, y_end); break;
        case 8: filter_band<8>(depth, format, taps, texture, y_begin, y_end); break;
        default: filter_band<16>(depth, format, taps, texture, y_begin, y_end); break;
        }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads && t * band < depth.height; ++t)
        pool.emplace_back(work, t * band, std::min(depth.height, (t + 1) * band));
    work(0, std::min(depth.height, band));
    for (std::thread& thread : pool) thread.join();
}

std::vector<CaseResult> run_cpu_loop_naive(BenchEnv& env, const Workload& work) {
    std::vector<std::uint32_t> texture(work.texels() * texel_words(work.format));
    CaseResult result;
    result.name = "cpu_loop_naive";
    result.bytes = work.bytes();
    result.take(time_runs([&] { filter_on_host(*work.depth, work.format, work.sigma, texture.data()); },
                          env.warmups, env.reps));
    result.extra["threads"] = std::max(1u, std::thread::hardware_concurrency());
    if (!env.three_pass_words.empty()) result.extra["equal_to_three_pass"] = equal_share(texture, env.three_pass_words);
    return {result};
}

MSMCL_BENCH_CASE({"cpu_loop_naive", 41, run_cpu_loop_naive});

} // namespace

} // namespace msmcl::bench
