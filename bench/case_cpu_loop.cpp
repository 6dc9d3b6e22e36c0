// Case cpu_loop: the filter as a careful C++ programmer writes it for the host in an
// afternoon, the fair plain-C++ peer of the fused kernels (cpu_loop_naive is the
// straightforward version). OpenMP, one band of output rows per thread; per band a
// resolved row (one plane per blurred lane, 4 edge-clamped guard texels each side) and a
// ring of 9 horizontally blurred rows that stays in L1/L2; per output row the vertical
// 9-tap over the ring, then a branch-free encoder over the row's planes. Every loop over
// texels is written for the compiler's vectorizer (__restrict planes, `omp simd`, inline
// math, selects instead of branches), Algorithm 2 of the nlq formats included
// (structure of arrays, as kernels/filter_fused_cpu.cl). Every filter format; the blur
// covers only the lanes the representation uses. The kernels' float operations in their
// order (first tap innermost, explicit fma, no contraction), unshifted as three_pass:
// moments128, msm64 and the VSM, EVSM and ESM formats equal three_pass bit for bit. The
// nlq formats take exp for Psi4's inverse from msm_exp (branch-free, vectorizes; std::exp
// does not), where the device's exp may round the other way: a few Psi4 codes may then
// differ from three_pass's by one step (on PoCL at 2048^2, S = 4: 69 of nlq64's 8.4M words,
// none of nlq32's; equal_to_three_pass says how many).
#include "harness.hpp"

#include <msmcl/filter.hpp>
#include <msmcl/formats.hpp>

#include "kernels/msm_formats.clh"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace msmcl::bench {

namespace {

constexpr int kGuard = 4;
// Floats between the rows of the ring (one cache line, see filter_band).
constexpr int kRingPad = 16;

// ---- Per-texel math, inline and branch-free (each is used inside `omp simd` loops).

inline float select(bool c, float a, float b) { return c ? a : b; }
inline std::uint32_t select(bool c, std::uint32_t a, std::uint32_t b) { return c ? a : b; }

// msm's clamp (fmin(fmax(x, lo), hi), NaN -> lo) as selects.
inline float clamp_select(float x, float lo, float hi) {
    const float t = select(x > lo, x, lo);
    return select(t < hi, t, hi);
}

inline std::uint32_t bits_of(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}
inline float float_of(std::uint32_t u) {
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
}

// msm_internal_depth for the [0,1] range: 2d - 1 clamped to [-1,1], NaN -> -1 (the first
// select takes NaN to -1; both are one max and one min instruction).
inline float internal_depth(float d) {
    const float z = 2.0f * d - 1.0f;
    const float above = select(z > -1.0f, z, -1.0f);
    return select(above < 1.0f, above, 1.0f);
}

// msm_quantize_nearest: floor(x max + 0.5) clamped to [0, max], NaN -> 0.
inline std::uint32_t quantize_nearest(float x, float max_code) {
    float q = std::floor(x * max_code + 0.5f);
    q = select(q > 0.0f, q, 0.0f);
    q = select(q < max_code, q, max_code);
    return static_cast<std::uint32_t>(static_cast<std::int32_t>(q));
}

// msm_psi4 with its early return as a select.
inline float psi4(float xi4) {
    const float xi = msm_maxf(MSM_XI4_MIN, msm_minf(xi4, MSM_XI4_MAX));
    float psi = (msm_logf(msm_logf(xi * 1e7f)) - MSM_PSI4_L0) / (MSM_PSI4_L1 - MSM_PSI4_L0);
    psi = select(psi > 0.0f, psi, 0.0f);
    psi = select(psi < 1.0f, psi, 1.0f);
    return select(xi4 > MSM_XI4_MIN, psi, 0.0f);
}

// msm_quantize_psi4: Psi4 rounded up (msm_quantize_up: ceil, clamped to [0, max]), one
// more step where the inverse (exp by msm_exp) falls below xi4; the code kept as a float
// (exact) until the end. The inverse's case psi >= 1 (code = max) needs no select: no step
// is added there.
inline std::uint32_t quantize_psi4(float xi4, float max_code) {
    const float up = std::ceil(psi4(xi4) * max_code);
    const float code = select(up < max_code, select(up > 0.0f, up, 0.0f), max_code);
    const float inverse = msm_exp(msm_exp(code / max_code * (MSM_PSI4_L1 - MSM_PSI4_L0) + MSM_PSI4_L0)) / 1e7f;
    const float stepped = select((code < max_code) & (inverse < xi4), code + 1.0f, code);
    return static_cast<std::uint32_t>(static_cast<std::int32_t>(stepped));
}

// msm_half_bits with its three cases as selects.
inline std::uint32_t half_bits(float x) {
    const std::uint32_t bits = bits_of(x);
    const std::uint32_t sign = (bits >> 16) & 0x8000u;
    const std::uint32_t magnitude = bits & 0x7fffffffu;
    const std::uint32_t special = select(magnitude > 0x7f800000u, 0x7e00u, 0x7c00u);
    const std::uint32_t subnormal = bits_of(float_of(magnitude) + 0.5f) - 0x3f000000u;
    const std::uint32_t normal = (magnitude + 0xc8000fffu + ((magnitude >> 13) & 1u)) >> 13;
    const std::uint32_t code =
        select(magnitude >= 0x47800000u, special, select(magnitude < 0x38800000u, subnormal, normal));
    return code | sign;
}

// ---- The values blurred per sample (msm_filter_lanes), kLanes of them.

struct Lanes4 {
    float v0, v1, v2, v3;
};
struct MomentLanes { // b(z), unshifted as three_pass
    static constexpr int kLanes = 4;
    static Lanes4 of(float z, float, float) {
        const float z2 = z * z;
        return {z, z2, z2 * z, z2 * z2};
    }
};
struct VsmLanes { // (t, t^2)
    static constexpr int kLanes = 2;
    static Lanes4 of(float z, float, float) {
        const float t = msm_unit_depth(z);
        return {t, t * t, 0.0f, 0.0f};
    }
};
struct Evsm2Lanes { // (p, p^2)
    static constexpr int kLanes = 2;
    static Lanes4 of(float z, float positive, float) {
        const float p = msm_exp(positive * z);
        return {p, p * p, 0.0f, 0.0f};
    }
};
struct Evsm4Lanes { // (p, p^2, n, n^2)
    static constexpr int kLanes = 4;
    static Lanes4 of(float z, float positive, float negative) {
        const float p = msm_exp(positive * z);
        const float n = -msm_exp(-negative * z);
        return {p, p * p, n, n * n};
    }
};
struct EsmLanes { // exp(c (t - 1))
    static constexpr int kLanes = 1;
    static Lanes4 of(float z, float positive, float) {
        return {msm_exp(positive * (msm_unit_depth(z) - 1.0f)), 0.0f, 0.0f, 0.0f};
    }
};

// What one band works with: the map, the taps, the warp, the output.
struct Job {
    const float* depth;
    int width, height;
    Format format;
    std::array<float, 9> w;
    float positive, negative;
    std::uint32_t* texture;
};

// ---- Row steps.

// Lanes of input row `y` averaged over its S samples (sum from sample 0 up, times 1/S) into
// `planes` (L::kLanes planes of `stride` floats, texel x at kGuard + x), guard texels copied
// from the edges.
template <int S, class L>
void resolve_row(const Job& job, int y, float* planes, std::size_t stride) {
    const int width = job.width;
    const float* __restrict in = job.depth + static_cast<std::size_t>(y) * width * S;
    float* __restrict o0 = planes + kGuard;
    float* __restrict o1 = o0 + (L::kLanes > 1 ? stride : 0);
    float* __restrict o2 = o0 + (L::kLanes > 2 ? 2 * stride : 0);
    float* __restrict o3 = o0 + (L::kLanes > 3 ? 3 * stride : 0);
    const float positive = job.positive, negative = job.negative;
#pragma omp simd
    for (int x = 0; x < width; ++x) {
        Lanes4 sum = L::of(internal_depth(in[x * S]), positive, negative);
#pragma GCC unroll 16
        for (int s = 1; s < S; ++s) {
            const Lanes4 v = L::of(internal_depth(in[x * S + s]), positive, negative);
            sum.v0 = sum.v0 + v.v0;
            sum.v1 = sum.v1 + v.v1;
            sum.v2 = sum.v2 + v.v2;
            sum.v3 = sum.v3 + v.v3;
        }
        o0[x] = sum.v0 * (1.0f / float(S));
        if (L::kLanes > 1) o1[x] = sum.v1 * (1.0f / float(S));
        if (L::kLanes > 2) o2[x] = sum.v2 * (1.0f / float(S));
        if (L::kLanes > 3) o3[x] = sum.v3 * (1.0f / float(S));
    }
    // Guard texels: the edge texels repeated (clamp to edge).
    for (int j = 0; j < L::kLanes; ++j) {
        float* plane = planes + j * stride;
        for (int g = 0; g < kGuard; ++g) {
            plane[g] = plane[kGuard];
            plane[kGuard + width + g] = plane[kGuard + width - 1];
        }
    }
}

// 9-tap sum over one plane: out[x] = sum_i w[i] in[x + i], the first tap innermost.
inline void blur_horizontal(const float* __restrict in, float* __restrict out, int width, const float* w) {
    const float w0 = w[0], w1 = w[1], w2 = w[2], w3 = w[3], w4 = w[4], w5 = w[5], w6 = w[6], w7 = w[7], w8 = w[8];
#pragma omp simd
    for (int x = 0; x < width; ++x) {
        float sum = w0 * in[x];
        sum = std::fma(w1, in[x + 1], sum);
        sum = std::fma(w2, in[x + 2], sum);
        sum = std::fma(w3, in[x + 3], sum);
        sum = std::fma(w4, in[x + 4], sum);
        sum = std::fma(w5, in[x + 5], sum);
        sum = std::fma(w6, in[x + 6], sum);
        sum = std::fma(w7, in[x + 7], sum);
        sum = std::fma(w8, in[x + 8], sum);
        out[x] = sum;
    }
}

// 9-tap sum over nine rows (r[0] the oldest = topmost), the first tap innermost.
inline void blur_vertical(const float* const* r, float* __restrict out, int width, const float* w) {
    const float* __restrict r0 = r[0];
    const float* __restrict r1 = r[1];
    const float* __restrict r2 = r[2];
    const float* __restrict r3 = r[3];
    const float* __restrict r4 = r[4];
    const float* __restrict r5 = r[5];
    const float* __restrict r6 = r[6];
    const float* __restrict r7 = r[7];
    const float* __restrict r8 = r[8];
    const float w0 = w[0], w1 = w[1], w2 = w[2], w3 = w[3], w4 = w[4], w5 = w[5], w6 = w[6], w7 = w[7], w8 = w[8];
#pragma omp simd
    for (int x = 0; x < width; ++x) {
        float sum = w0 * r0[x];
        sum = std::fma(w1, r1[x], sum);
        sum = std::fma(w2, r2[x], sum);
        sum = std::fma(w3, r3[x], sum);
        sum = std::fma(w4, r4[x], sum);
        sum = std::fma(w5, r5[x], sum);
        sum = std::fma(w6, r6[x], sum);
        sum = std::fma(w7, r7[x], sum);
        sum = std::fma(w8, r8[x], sum);
        out[x] = sum;
    }
}

// Algorithm 2 over a row (msm_nlq_from_shifted_moments with c = 0: bias held as offsets,
// q2, q1 and xi4 in float-float), the same operations in the same order, the single-depth
// guard as selects. In: moment planes b[0..3]; out: planes y1, y2, v2, xi4.
inline void nlq_row(float* const* b, float* const* n, int width) {
    const float* __restrict b1p = b[0];
    const float* __restrict b2p = b[1];
    const float* __restrict b3p = b[2];
    const float* __restrict b4p = b[3];
    float* __restrict y1p = n[0];
    float* __restrict y2p = n[1];
    float* __restrict v2p = n[2];
    float* __restrict xi4p = n[3];
#pragma omp simd
    for (int x = 0; x < width; ++x) {
        const float bb1 = b1p[x], bb2 = b2p[x], bb3 = b3p[x], bb4 = b4p[x];
        // Bias offsets towards (0, 3/8, 0, 3/8) (msm_float_bias_target_shifted(0)).
        const float l1 = MSM_ALPHA_FLOAT * (0.0f - bb1);
        const float l2 = MSM_ALPHA_FLOAT * (MSM_BSTAR_FLOAT - bb2);
        const float l3 = MSM_ALPHA_FLOAT * (0.0f - bb3);
        const float l4 = MSM_ALPHA_FLOAT * (MSM_BSTAR_FLOAT - bb4);
        // q2 = b2 - b1^2 in float-float.
        const float square = bb1 * bb1;
        const float q2_sum = bb2 - square;
        const float q2_tail = msm_two_sum_error(bb2, -square, q2_sum) - msm_two_prod_error(bb1, bb1, square) +
                              (l2 - l1 * (2.0f * bb1 + l1));
        const float q2 = q2_sum + q2_tail;
        const float q2_lo = msm_two_sum_error(q2_sum, q2_tail, q2);
        // q1 = b1 b2 - b3 in float-float.
        const float product = bb1 * bb2;
        const float q1_sum = product - bb3;
        const float q1_tail = msm_two_sum_error(product, -bb3, q1_sum) + msm_two_prod_error(bb1, bb2, product) +
                              (bb1 * l2 + l1 * (bb2 + l2) - l3);
        const float q1 = q1_sum + q1_tail;
        const float q1_lo = msm_two_sum_error(q1_sum, q1_tail, q1);
        // The quadratic's roots y1 <= y2 (no cancellation), or a single depth.
        const float b1 = bb1 + l1;
        const float b2 = bb2 + l2;
        const float q0 = -b1 * q1 - b2 * q2;
        const float discriminant = q1 * q1 - 4.0f * q2 * q0;
        const bool single_depth = !(q2 > 0.0f) | !(discriminant > 0.0f);
        const float root_d = std::sqrt(discriminant);
        const float t = -0.5f * (q1 + select(q1 >= 0.0f, root_d, -root_d));
        const float root_a = t / q2;
        const float root_b = q0 / t;
        const float y1 = msm_minf(root_a, root_b);
        const float y2 = msm_maxf(root_a, root_b);
        // xi4 = (b4 - b2^2) - q1^2/q2 in float-float.
        const float square2 = bb2 * bb2;
        const float spread = bb4 - square2;
        const float spread_tail = msm_two_sum_error(bb4, -square2, spread) - msm_two_prod_error(bb2, bb2, square2) +
                                  (l4 - l2 * (2.0f * bb2 + l2));
        const float k = q1 / q2;
        const float residual = std::fma(-k, q2, q1) + (q1_lo - k * q2_lo);
        const float cross = k * q1;
        const float xi4 = (spread - cross) + (spread_tail - msm_two_prod_error(k, q1, cross) - k * (q1_lo + residual));
        // Outputs clamped, or the single depth b1.
        const float y = clamp_select(b1 + 0.0f, -1.0f, 1.0f);
        v2p[x] = select(single_depth, 0.5f, clamp_select((b1 - y1) / (y2 - y1), 0.0f, 1.0f));
        xi4p[x] = select(single_depth, 0.0f, clamp_select(xi4, 0.0f, MSM_XI4_MAX));
        y1p[x] = select(single_depth, y, clamp_select(y1 + 0.0f, -1.0f, 1.0f));
        y2p[x] = select(single_depth, y, clamp_select(y2 + 0.0f, -1.0f, 1.0f));
    }
}

// ---- Encoders: the planes of one filtered row into its texel words (msm_store_texel).

// Float texels (moments128, vsm64, evsm4_128, esm32): the planes' bits, interleaved.
template <int WORDS>
void encode_floats(float* const* p, std::uint32_t* __restrict out, int width) {
    const float* __restrict p0 = p[0];
    const float* __restrict p1 = p[WORDS > 1 ? 1 : 0];
    const float* __restrict p2 = p[WORDS > 2 ? 2 : 0];
    const float* __restrict p3 = p[WORDS > 3 ? 3 : 0];
#pragma omp simd
    for (int x = 0; x < width; ++x) {
        out[WORDS * x] = bits_of(p0[x]);
        if (WORDS > 1) out[WORDS * x + 1] = bits_of(p1[x]);
        if (WORDS > 2) out[WORDS * x + 2] = bits_of(p2[x]);
        if (WORDS > 3) out[WORDS * x + 3] = bits_of(p3[x]);
    }
}

// msm64: unorm16 of the affine basis (msm_encode_msm64).
void encode_msm64(float* const* p, std::uint32_t* __restrict out, int width) {
    const float* __restrict b1p = p[0];
    const float* __restrict b2p = p[1];
    const float* __restrict b3p = p[2];
    const float* __restrict b4p = p[3];
#pragma omp simd
    for (int x = 0; x < width; ++x) {
        const float b1 = b1p[x], b2 = b2p[x], b3 = b3p[x], b4 = b4p[x];
        const float r = 1.5f * b1 - 2.0f * b3 + 0.5f;
        const float g = 4.0f * b2 - 4.0f * b4;
        const float bl = MSM_SQRT3 * (0.5f * b1 - (2.0f / 9.0f) * b3) + 0.5f;
        const float a = 0.5f * b2 + 0.5f * b4;
        out[2 * x] = quantize_nearest(r, 65535.0f) | (quantize_nearest(g, 65535.0f) << 16);
        out[2 * x + 1] = quantize_nearest(bl, 65535.0f) | (quantize_nearest(a, 65535.0f) << 16);
    }
}

// nlq64 from the nlq planes (msm_encode_nlq64). Not inlined: inlined after nlq_row, GCC 12
// leaves a branch in this loop and does not vectorize it (called once per row).
__attribute__((noinline)) void encode_nlq64(float* const* n, std::uint32_t* __restrict out, int width) {
    const float* __restrict y1p = n[0];
    const float* __restrict y2p = n[1];
    const float* __restrict v2p = n[2];
    const float* __restrict xi4p = n[3];
#pragma omp simd
    for (int x = 0; x < width; ++x) {
        out[2 * x] = quantize_nearest(0.5f * (y1p[x] + 1.0f), 65535.0f) |
                     (quantize_nearest(0.5f * (y2p[x] + 1.0f), 65535.0f) << 16);
        out[2 * x + 1] = quantize_nearest(v2p[x], 65535.0f) | (quantize_psi4(xi4p[x], 65535.0f) << 16);
    }
}

// msm_nlq32_depth_code: floor(511.5 (y + 1)) clamped to [0, 1022].
inline std::uint32_t nlq32_depth_code(float y) {
    float q = std::floor(511.5f * (y + 1.0f));
    q = select(q > 0.0f, q, 0.0f);
    q = select(q < 1022.0f, q, 1022.0f);
    return static_cast<std::uint32_t>(static_cast<std::int32_t>(q));
}

// nlq32 from the nlq planes (msm_encode_nlq32), the fold as selects.
void encode_nlq32(float* const* n, std::uint32_t* __restrict out, int width) {
    const float* __restrict y1p = n[0];
    const float* __restrict y2p = n[1];
    const float* __restrict v2p = n[2];
    const float* __restrict xi4p = n[3];
#pragma omp simd
    for (int x = 0; x < width; ++x) {
        const std::uint32_t psi_code = quantize_psi4(xi4p[x], 63.0f);
        const std::uint32_t sqrt_v2_code = quantize_nearest(std::sqrt(msm_maxf(v2p[x], 0.0f)), 127.0f);
        const std::uint32_t yt1 = nlq32_depth_code(y1p[x]);
        const std::uint32_t yt2 = std::max(nlq32_depth_code(y2p[x]), yt1);
        const bool fold = yt1 >= 512u;
        const std::uint32_t t1 = select(fold, 1023u - yt1, yt1);
        const std::uint32_t t2 = select(fold, 1022u - yt2, yt2);
        out[x] = (psi_code << MSM_NLQ32_PSI_SHIFT) | (sqrt_v2_code << MSM_NLQ32_SQRTV2_SHIFT) |
                 (t1 << MSM_NLQ32_T1_SHIFT) | (t2 << MSM_NLQ32_T2_SHIFT);
    }
}

// vsm32 (unorm16) and evsm2_32 (half): two 16-bit codes in one word.
template <bool HALF>
void encode_codes16x2(float* const* p, std::uint32_t* __restrict out, int width) {
    const float* __restrict p0 = p[0];
    const float* __restrict p1 = p[1];
#pragma omp simd
    for (int x = 0; x < width; ++x) {
        const std::uint32_t c0 = HALF ? half_bits(p0[x]) : quantize_nearest(p0[x], 65535.0f);
        const std::uint32_t c1 = HALF ? half_bits(p1[x]) : quantize_nearest(p1[x], 65535.0f);
        out[x] = c0 | (c1 << 16);
    }
}

// evsm4_64: four half codes in two words.
void encode_evsm4_64(float* const* p, std::uint32_t* __restrict out, int width) {
    const float* __restrict p0 = p[0];
    const float* __restrict p1 = p[1];
    const float* __restrict p2 = p[2];
    const float* __restrict p3 = p[3];
#pragma omp simd
    for (int x = 0; x < width; ++x) {
        out[2 * x] = half_bits(p0[x]) | (half_bits(p1[x]) << 16);
        out[2 * x + 1] = half_bits(p2[x]) | (half_bits(p3[x]) << 16);
    }
}

// One filtered row into its texel words, by format (`nlq`: 4 planes of scratch).
void encode_row(Format format, float* const* planes, float* const* nlq, std::uint32_t* out, int width) {
    switch (format) {
    case Format::moments128:
    case Format::evsm4_128: encode_floats<4>(planes, out, width); break;
    case Format::vsm64: encode_floats<2>(planes, out, width); break;
    case Format::esm32: encode_floats<1>(planes, out, width); break;
    case Format::msm64: encode_msm64(planes, out, width); break;
    case Format::nlq64:
        nlq_row(planes, nlq, width);
        encode_nlq64(nlq, out, width);
        break;
    case Format::nlq32:
        nlq_row(planes, nlq, width);
        encode_nlq32(nlq, out, width);
        break;
    case Format::vsm32: encode_codes16x2<false>(planes, out, width); break;
    case Format::evsm2_32: encode_codes16x2<true>(planes, out, width); break;
    case Format::evsm4_64: encode_evsm4_64(planes, out, width); break;
    }
}

// ---- A band of output rows [y_begin, y_end).

template <int S, class L>
void filter_band(const Job& job, int y_begin, int y_end) {
    constexpr int kLanes = L::kLanes;
    const int width = job.width, height = job.height;
    const std::size_t padded = static_cast<std::size_t>(width) + 2 * kGuard;
    // The band's rows: one resolved row, the ring of 9 blurred rows, one filtered row.
    std::vector<float> resolved(kLanes * padded);
    // Ring rows a cache line more than a row apart: at power-of-two widths, rows 8 KiB apart
    // fell into the same L1 set and the vertical pass's nine rows evicted each other.
    const std::size_t ring_stride = static_cast<std::size_t>(width) + kRingPad;
    std::vector<float> ring(9 * kLanes * ring_stride);
    std::vector<float> filtered(4 * static_cast<std::size_t>(width)), nlq_values(4 * static_cast<std::size_t>(width));
    const auto ring_row = [&](int slot, int j) {
        return ring.data() + (static_cast<std::size_t>(slot) * kLanes + j) * ring_stride;
    };
    float* planes[4];
    float* nlq[4];
    for (int j = 0; j < 4; ++j) {
        planes[j] = filtered.data() + static_cast<std::size_t>(j) * width;
        nlq[j] = nlq_values.data() + static_cast<std::size_t>(j) * width;
    }
    const std::size_t words = texel_words(job.format);
    const int first = y_begin - kGuard;
    for (int iy = first; iy < y_end + kGuard; ++iy) {
        // Resolve input row iy (clamped into the map), blur it horizontally into its ring slot.
        resolve_row<S, L>(job, std::clamp(iy, 0, height - 1), resolved.data(), padded);
        const int slot = (iy - first) % 9;
        for (int j = 0; j < kLanes; ++j) blur_horizontal(resolved.data() + j * padded, ring_row(slot, j), width, job.w.data());
        if (iy < y_begin + kGuard) continue;
        // Output row iy - 4: the vertical blur over the ring (rows iy - 8 .. iy, oldest first).
        for (int j = 0; j < kLanes; ++j) {
            const float* rows[9];
            for (int i = 0; i < 9; ++i) rows[i] = ring_row((iy - 8 - first + i) % 9, j);
            blur_vertical(rows, planes[j], width, job.w.data());
        }
        // Encode and write the row.
        encode_row(job.format, planes, nlq, job.texture + static_cast<std::size_t>(iy - kGuard) * width * words, width);
    }
}

template <class L>
void filter_band_lanes(const Job& job, int samples, int y_begin, int y_end) {
    switch (samples) {
    case 1: filter_band<1, L>(job, y_begin, y_end); break;
    case 2: filter_band<2, L>(job, y_begin, y_end); break;
    case 4: filter_band<4, L>(job, y_begin, y_end); break;
    case 8: filter_band<8, L>(job, y_begin, y_end); break;
    default: filter_band<16, L>(job, y_begin, y_end); break;
    }
}

// The whole texture: one band of rows per OpenMP thread.
void filter_on_host(const DepthImage& depth, Format format, float sigma, std::uint32_t* texture) {
    const WarpExponents warp = effective_exponents(format, WarpExponents{});
    const Job job{depth.depth.data(), depth.width, depth.height, format, gaussian_taps(sigma),
                  warp.positive,      warp.negative, texture};
#pragma omp parallel
    {
        const int threads = omp_get_num_threads();
        const int band = (depth.height + threads - 1) / threads;
        const int y_begin = std::min(depth.height, omp_get_thread_num() * band);
        const int y_end = std::min(depth.height, y_begin + band);
        if (y_begin < y_end) {
            switch (format) {
            case Format::vsm32:
            case Format::vsm64: filter_band_lanes<VsmLanes>(job, depth.samples, y_begin, y_end); break;
            case Format::evsm2_32: filter_band_lanes<Evsm2Lanes>(job, depth.samples, y_begin, y_end); break;
            case Format::evsm4_64:
            case Format::evsm4_128: filter_band_lanes<Evsm4Lanes>(job, depth.samples, y_begin, y_end); break;
            case Format::esm32: filter_band_lanes<EsmLanes>(job, depth.samples, y_begin, y_end); break;
            default: filter_band_lanes<MomentLanes>(job, depth.samples, y_begin, y_end); break;
            }
        }
    }
}

std::vector<CaseResult> run_cpu_loop(BenchEnv& env, const Workload& work) {
    std::vector<std::uint32_t> texture(work.texels() * texel_words(work.format));
    CaseResult result;
    result.name = "cpu_loop";
    result.bytes = work.bytes();
    result.take(time_runs([&] { filter_on_host(*work.depth, work.format, work.sigma, texture.data()); },
                          env.warmups, env.reps));
    result.extra["threads"] = omp_get_max_threads();
    if (!env.three_pass_words.empty()) result.extra["equal_to_three_pass"] = equal_share(texture, env.three_pass_words);
    return {result};
}

MSMCL_BENCH_CASE({"cpu_loop", 40, run_cpu_loop});

} // namespace

} // namespace msmcl::bench
