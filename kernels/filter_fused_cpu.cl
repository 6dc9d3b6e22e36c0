// The fused filter (resolve -> 9x9 Gaussian -> quantize, one global write) distributed
// for CPU devices: one work-item per group filters a whole CPU_TILE_W x CPU_TILE_H output
// tile, streaming its CPU_TILE_H + 8 input rows (docs/kernels.md). Per input row r:
//   resolve:  the moments of the S samples of each input column (the tile and its guard
//             band), averaged, into the `resolved` row;
//   blur:     horizontal 9-tap of that row into slot r % 9 of a ring of the last 9
//             blurred rows; from the ninth row on, the vertical 9-tap over the ring into
//             the `filtered` row;
//   quantize: each filtered texel into the format's words, stored to output row r - 8.
// Each step is a loop along the row with no branch in its body, which the compiler
// vectorizes (SIMD lanes along x); nothing waits at a barrier and no work-item loop is
// built around the code. Interior and border tile columns are separate kernels: only the
// border one clamps columns, by copying the edge texel's moments into the guard band.
// Same math headers, taps and float operation order as filter_fused_gpu.cl and
// filter_three_pass.cl: moments128 and msm64 equal them bit for bit; the nlq formats shift
// the moments by the midrange c of the tile's input depths (docs/math.md, see tile_shift).
// Compile-time: MSM_SAMPLES, MSM_FORMAT, MSM_DEPTH_ZERO_ONE, MSM_LAYERS as for
// filter_fused_gpu.cl; CPU_TILE_W, CPU_TILE_H: tuning parameters (host/ops/filter.cpp).

// Math functions for the quantizers of msm_formats.clh that vectorize (in this kernel
// only). PoCL's floor() and ceil() are library code with branches: clang's builtins become
// single instructions with the same IEEE results. PoCL's exp() is branchy: Psi4's inverse
// takes msm_exp (msm_filterable.clh), inline and branch-free, the algorithm the warps use in
// every kernel (FreeBSD's e_expf.c). Psi4's logarithm is msm_logf of msm_moments.clh in
// every kernel.
#define floor(x) __builtin_floorf(x)
#define ceil(x) __builtin_ceilf(x)
#define exp(x) msm_exp(x)
#include "msm_formats.clh"
#include "msm_translucent.clh"
#include "msm_array.clh"
#include "fused_cpu_layout.clh"

// Translucent layers (MSM_LAYERS > 0, docs/math.md): the resolve composites each sample's
// surfaces (msm_translucent.clh) instead of taking b(z), and the kernels take the layers'
// depths and opacities as two more arguments; 0 compiles the opaque code alone.
#ifndef MSM_LAYERS
#define MSM_LAYERS 0
#endif
#if MSM_LAYERS
#define CPU_LAYER_PARAMS , __global const float *restrict layer_depth, __global const float *restrict layer_opacity
#define CPU_LAYER_ARGS , layer_depth, layer_opacity
#else
#define CPU_LAYER_PARAMS
#define CPU_LAYER_ARGS
#endif

#define CPU_IN_W CPU_IN_W_OF(CPU_TILE_W)
// Rows the prefetch (prefetch_part) runs ahead, a build option for experiments, and the
// parts a row's prefetches are split into.
#ifndef CPU_PREFETCH_AHEAD
#define CPU_PREFETCH_AHEAD 4
#endif
#define CPU_PREFETCH_PARTS 4

// Origin of this group's output tile. Interior groups: tile column ix0 + group x; border
// groups: the tile columns left of ix0, then those from ix1 on. Tile row = group y.
static inline int tile_x0(int border, int ix0, int ix1) {
    const int g = (int)get_group_id(0);
    const int column = border ? (g < ix0 ? g : ix1 + (g - ix0)) : ix0 + g;
    return column * CPU_TILE_W;
}
static inline int tile_y0(void) { return (int)get_group_id(1) * CPU_TILE_H; }

// Asks the caches for memory a few rows before the loops touch it (CPU_PREFETCH_AHEAD
// rows, into the second-level cache; msm_prefetch of msm_portable.clh, where the kernel
// compiles to a CPU's instructions): each tile row is a stretch of its own, too short for
// the hardware prefetcher to ramp up, so without it the resolve (or the nlq formats' shift)
// waited for the depth samples and each store for its cache line (docs/kernels.md). A row's
// lines are asked for in CPU_PREFETCH_PARTS parts, one before each step: all at once, they
// filled the core's queue of outstanding misses and the prefetches themselves waited.
// Part `part` of the cache lines of [begin, end).
static inline void prefetch_part(__global const char* begin, __global const char* end, int part, int for_write) {
    const size_t lines = ((size_t)(end - begin) + 63) / 64;
    const size_t first = lines * part / CPU_PREFETCH_PARTS, last = lines * (part + 1) / CPU_PREFETCH_PARTS;
    for (size_t line = first; line < last; ++line) {
        if (for_write)
            msm_prefetch(begin + 64 * line, 1, 2);
        else
            msm_prefetch(begin + 64 * line, 0, 2);
    }
}

// The depth samples of input columns [first, last) of image row y (clamped into the image).
static inline void prefetch_depth_row(__global const float* depth, int width, int height, int x0, int first,
                                      int last, int y, int part) {
    if (!MSM_CAN_PREFETCH) return;
    const size_t texel0 = (size_t)clamp(y, 0, height - 1) * width + (size_t)(x0 - CPU_GUARD);
    prefetch_part((__global const char*)(depth + (texel0 + first) * MSM_SAMPLES),
                  (__global const char*)(depth + (texel0 + last) * MSM_SAMPLES), part, 0);
}

// What input row r + CPU_PREFETCH_AHEAD of the tile touches: its depth samples (the nlq
// formats' shift has read them all before), and its output row's texels, to write.
static inline void prefetch_rows(__global const float* depth, __global const uint* texture, int width, int height,
                                 int x0, int y0, int first, int last, int columns, int r, int rows_in, int part) {
    const int ahead = r + CPU_PREFETCH_AHEAD;
    if (!MSM_CAN_PREFETCH || ahead >= rows_in) return;
    if (!MSM_FORMAT_SHIFTED) prefetch_depth_row(depth, width, height, x0, first, last, y0 - CPU_GUARD + ahead, part);
    if (ahead < 2 * CPU_GUARD) return;
    __global const char* begin =
        (__global const char*)(texture + ((size_t)(y0 + ahead - 2 * CPU_GUARD) * width + x0) * MSM_TEXEL_WORDS);
    prefetch_part(begin, begin + (size_t)columns * MSM_TEXEL_WORDS * 4, part, 1);
}

// The shift c of the nlq formats (docs/math.md), as in filter_fused_gpu.cl: the midrange
// (min + max) / 2 of the internal depths z < 1 of sample 0 of the tile's input texels
// (input columns [first, last) inside the image, rows y0 - 4 .. clamped into it, which is
// the set of texels the resolve reads); 1 if all are on the far plane, which takes no part
// (it would pull c halfway away from the geometry). min and max are exact in any order:
// first per column down the rows (a loop along x that vectorizes) into `scratch` (2 *
// CPU_IN_W floats), then over the columns. 0 for the other formats.
static inline float tile_shift(__global const float* depth, int width, int height, int x0, int y0, int first,
                               int last, int rows_in, __local float* restrict scratch) {
#if MSM_FORMAT_SHIFTED
    __local float* restrict lowest = scratch;
    __local float* restrict highest = scratch + CPU_IN_W;
    for (int x = first; x < last; ++x) {
        lowest[x] = 1.0f;
        highest[x] = -1.0f;
    }
    for (int k = 0; k < rows_in; ++k) {
        if (k + CPU_PREFETCH_AHEAD < rows_in)
            for (int part = 0; part < CPU_PREFETCH_PARTS; ++part)
                prefetch_depth_row(depth, width, height, x0, first, last, y0 - CPU_GUARD + k + CPU_PREFETCH_AHEAD,
                                   part);
        const size_t row = (size_t)clamp(y0 - CPU_GUARD + k, 0, height - 1) * width;
        __global const float* texels = depth + (row + (size_t)(x0 - CPU_GUARD)) * MSM_SAMPLES;
        for (int x = first; x < last; ++x) {
            const float z = msm_internal_depth(texels[x * MSM_SAMPLES], MSM_DEPTH_ZERO_ONE);
            const int rendered = z < 1.0f;
            lowest[x] = rendered ? msm_minf(lowest[x], z) : lowest[x];
            highest[x] = rendered ? msm_maxf(highest[x], z) : highest[x];
        }
    }
    float low = 1.0f, high = -1.0f;
    for (int x = first; x < last; ++x) {
        low = msm_minf(low, lowest[x]);
        high = msm_maxf(high, highest[x]);
    }
    return low <= high ? (low + high) * 0.5f : 1.0f;
#else
    return 0.0f;
#endif
}

// Step "resolve" of one input row: input column x (image column x0 - 4 + x) averages the
// lanes of (z - shift) of its S samples into the `resolved` planes, in the order of
// msm_resolve_texel (msm_moments.clh): sum from sample 0 up, times 1/S. Columns [first,
// last) lie inside the image; the guard columns outside it take the edge texel's moments
// (the clamp of the other kernels: the same texel, the same bits).
static inline void resolve_row(__global const float* depth, int width, int height, int x0, int first, int last,
                               size_t row, float shift, __local float* restrict resolved CPU_LAYER_PARAMS) {
    __local float* restrict b1 = resolved;
    __local float* restrict b2 = resolved + CPU_IN_W;
    __local float* restrict b3 = resolved + 2 * CPU_IN_W;
    __local float* restrict b4 = resolved + 3 * CPU_IN_W;
    const size_t texel0 = row + (size_t)(x0 - CPU_GUARD); // image texel of input column 0
    for (int x = first; x < last; ++x) {
#if MSM_LAYERS
        const msm_moments m = msm_resolve_translucent_texel(depth, layer_depth, layer_opacity,
                                                            (size_t)width * height * MSM_SAMPLES, texel0 + x,
                                                            MSM_SAMPLES, MSM_LAYERS, MSM_DEPTH_ZERO_ONE, shift);
#else
        // msm_resolve_texel's loop, unrolled: a loop left inside stops the vectorization along x.
        __global const float* samples = depth + (texel0 + x) * MSM_SAMPLES;
        msm_moments sum = msm_filter_lanes(msm_internal_depth(samples[0], MSM_DEPTH_ZERO_ONE), shift);
#pragma unroll
        for (int s = 1; s < MSM_SAMPLES; ++s)
            sum = msm_moments_add(sum, msm_filter_lanes(msm_internal_depth(samples[s], MSM_DEPTH_ZERO_ONE), shift));
        const msm_moments m = msm_moments_scale(sum, 1.0f / (float)MSM_SAMPLES);
#endif
        b1[x] = m.b1;
        b2[x] = m.b2;
        b3[x] = m.b3;
        b4[x] = m.b4;
    }
    // The guard columns outside the image: copies of the edge column.
    for (int x = 0; x < first; ++x) {
        b1[x] = b1[first];
        b2[x] = b2[first];
        b3[x] = b3[first];
        b4[x] = b4[first];
    }
    for (int x = last; x < CPU_IN_W; ++x) {
        b1[x] = b1[last - 1];
        b2[x] = b2[last - 1];
        b3[x] = b3[last - 1];
        b4[x] = b4[last - 1];
    }
}

// 9-tap sum of v(0..8) with weights w4 w3 w2 w1 w0 w1 w2 w3 w4, the first tap innermost
// (the order of the other kernels).
#define CPU_TAPS9(v)                                                                          \
    fma(w4, v(8), fma(w3, v(7), fma(w2, v(6), fma(w1, v(5),                                   \
    fma(w0, v(4), fma(w1, v(3), fma(w2, v(2), fma(w3, v(1), w4 * v(0)))))))))

// Step "blur", first half: horizontal 9-tap of the resolved row into ring slot `slot`
// (output column x reads input columns x .. x + 8). The four planes in one loop body: four
// independent chains of nine dependent FMAs, which the core overlaps (a loop per plane
// waited for each chain at its end).
#define CPU_AT_H(j, i) resolved[(j) * CPU_IN_W + x + (i)]
#define CPU_AT_H0(i) CPU_AT_H(0, i)
#define CPU_AT_H1(i) CPU_AT_H(1, i)
#define CPU_AT_H2(i) CPU_AT_H(2, i)
#define CPU_AT_H3(i) CPU_AT_H(3, i)
static inline void blur_row(float w0, float w1, float w2, float w3, float w4, __local const float* restrict resolved,
                            __local float* restrict slot) {
    for (int x = 0; x < CPU_TILE_W; ++x) {
        slot[x] = CPU_TAPS9(CPU_AT_H0);
        slot[CPU_TILE_W + x] = CPU_TAPS9(CPU_AT_H1);
        slot[2 * CPU_TILE_W + x] = CPU_TAPS9(CPU_AT_H2);
        slot[3 * CPU_TILE_W + x] = CPU_TAPS9(CPU_AT_H3);
    }
}

// Step "blur", second half: vertical 9-tap over the ring, oldest row first (ring slot of
// input row r - 8 + i is (r + 1 + i) % 9), into the `filtered` planes, the four planes in
// one loop body as above.
#define CPU_AT_V(j, i) rows[i][(j) * CPU_TILE_W + x]
#define CPU_AT_V0(i) CPU_AT_V(0, i)
#define CPU_AT_V1(i) CPU_AT_V(1, i)
#define CPU_AT_V2(i) CPU_AT_V(2, i)
#define CPU_AT_V3(i) CPU_AT_V(3, i)
static inline void blur_column(float w0, float w1, float w2, float w3, float w4, int r,
                               __local const float* restrict ring, __local float* restrict filtered) {
    __local const float* rows[9];
#pragma unroll
    for (int i = 0; i < 9; ++i) rows[i] = ring + ((r + 1 + i) % 9) * 4 * CPU_TILE_W;
    for (int x = 0; x < CPU_TILE_W; ++x) {
        filtered[x] = CPU_TAPS9(CPU_AT_V0);
        filtered[CPU_TILE_W + x] = CPU_TAPS9(CPU_AT_V1);
        filtered[2 * CPU_TILE_W + x] = CPU_TAPS9(CPU_AT_V2);
        filtered[3 * CPU_TILE_W + x] = CPU_TAPS9(CPU_AT_V3);
    }
}

// Algorithm 2 exactly as msm_nlq_from_shifted_moments (msm_moments.clh) computes it (bias
// held as offsets, q2, q1 and xi4 in float-float), the same operations in the same order,
// with a single return: the header's early return merges two 16-byte structs, which the
// x86-64 calling convention passes as pairs of float2, and that vector-typed merge stays
// after inlining and stops the loop vectorizer. Tested against the same double reference
// as every kernel, and bit for bit against the other kernels.
static inline __attribute__((always_inline)) msm_nlq cpu_nlq_from_shifted_moments(msm_moments b, float c) {
    MSM_NO_CONTRACT
    const msm_moments target = msm_float_bias_target_shifted(c);
    msm_moments l;
    l.b1 = MSM_ALPHA_FLOAT * (target.b1 - b.b1);
    l.b2 = MSM_ALPHA_FLOAT * (target.b2 - b.b2);
    l.b3 = MSM_ALPHA_FLOAT * (target.b3 - b.b3);
    l.b4 = MSM_ALPHA_FLOAT * (target.b4 - b.b4);
    float square = b.b1 * b.b1;
    float q2_sum = b.b2 - square;
    float q2_tail = msm_two_sum_error(b.b2, -square, q2_sum) - msm_two_prod_error(b.b1, b.b1, square) +
                    (l.b2 - l.b1 * (2.0f * b.b1 + l.b1));
    float q2 = q2_sum + q2_tail;
    float q2_lo = msm_two_sum_error(q2_sum, q2_tail, q2);
    float product = b.b1 * b.b2;
    float q1_sum = product - b.b3;
    float q1_tail = msm_two_sum_error(product, -b.b3, q1_sum) + msm_two_prod_error(b.b1, b.b2, product) +
                    (b.b1 * l.b2 + l.b1 * (b.b2 + l.b2) - l.b3);
    float q1 = q1_sum + q1_tail;
    float q1_lo = msm_two_sum_error(q1_sum, q1_tail, q1);
    float b1 = b.b1 + l.b1;
    float b2 = b.b2 + l.b2;
    float q0 = -b1 * q1 - b2 * q2;
    float discriminant = q1 * q1 - 4.0f * q2 * q0;
    const int single_depth = !(q2 > 0.0f) || !(discriminant > 0.0f);
    float root_d = sqrt(discriminant);
    float t = -0.5f * (q1 + (q1 >= 0.0f ? root_d : -root_d));
    float root_a = t / q2;
    float root_b = q0 / t;
    float y1 = msm_minf(root_a, root_b);
    float y2 = msm_maxf(root_a, root_b);
    float square2 = b.b2 * b.b2;
    float spread = b.b4 - square2;
    float spread_tail = msm_two_sum_error(b.b4, -square2, spread) - msm_two_prod_error(b.b2, b.b2, square2) +
                        (l.b4 - l.b2 * (2.0f * b.b2 + l.b2));
    float k = q1 / q2;
    float residual = fma(-k, q2, q1) + (q1_lo - k * q2_lo);
    float cross = k * q1;
    float xi4 = (spread - cross) + (spread_tail - msm_two_prod_error(k, q1, cross) - k * (q1_lo + residual));
    const float y = clamp(b1 + c, -1.0f, 1.0f);
    msm_nlq n;
    n.v2 = single_depth ? 0.5f : clamp((b1 - y1) / (y2 - y1), 0.0f, 1.0f);
    n.xi4 = single_depth ? 0.0f : clamp(xi4, 0.0f, MSM_XI4_MAX);
    n.y1 = single_depth ? y : clamp(y1 + c, -1.0f, 1.0f);
    n.y2 = single_depth ? y : clamp(y2 + c, -1.0f, 1.0f);
    return n;
}

// Column x's four filtered moments, one from each plane.
static inline msm_moments filtered_moments(__local const float* restrict b1, __local const float* restrict b2,
                                           __local const float* restrict b3, __local const float* restrict b4,
                                           int x) {
    msm_moments m;
    m.b1 = b1[x];
    m.b2 = b2[x];
    m.b3 = b3[x];
    m.b4 = b4[x];
    return m;
}

// Step "quantize": the filtered texels of one output row into the format's words at
// `out` (the row's first texel), `columns` of them (the tile's columns inside the image).
// The words of msm_store_texel (msm_formats.clh), written as scalar stores: a vector value
// in the loop body (vstore2, vstore4) stops the vectorization along x.
// The nlq formats take four loops over the row: Algorithm 2 in place in the `filtered`
// planes (b1..b4 -> y1, y2, v2, xi4), Psi4 rounded up into `scratch` (the code's bits), its
// check, then the words. Each body is short enough that the core overlaps the division and
// logarithm chains of several iterations; in one body the nlq formats took 1.7x the time.
// The first three are vectorized 16 wide (512 bits where the CPU has them: min_vector_width
// lets the compiler keep such vectors, which PoCL's LLVM otherwise splits into 256-bit
// halves) and unrolled by two: each costs fewer instructions per texel (docs/kernels.md).
static inline __attribute__((always_inline, flatten, min_vector_width(512))) void
quantize_row(__local float* restrict filtered, __local float* restrict scratch, float shift, int columns,
             __global uint* restrict out) {
    __local float* restrict b1 = filtered;
    __local float* restrict b2 = filtered + CPU_TILE_W;
    __local float* restrict b3 = filtered + 2 * CPU_TILE_W;
    __local float* restrict b4 = filtered + 3 * CPU_TILE_W;
#if MSM_FORMAT_SHIFTED
#pragma clang loop vectorize_width(16) interleave_count(2)
    for (int x = 0; x < columns; ++x) {
        const msm_moments m = filtered_moments(b1, b2, b3, b4, x);
        const msm_nlq n = cpu_nlq_from_shifted_moments(m, shift);
        b1[x] = n.y1;
        b2[x] = n.y2;
        b3[x] = n.v2;
        b4[x] = n.xi4;
    }
#if MSM_FORMAT == MSM_FORMAT_NLQ64
#define CPU_PSI_CODE_MAX 65535.0f
#else
#define CPU_PSI_CODE_MAX 63.0f
#endif
    __local float* restrict psi_code = scratch;
#pragma clang loop vectorize_width(16) interleave_count(2)
    for (int x = 0; x < columns; ++x) psi_code[x] = as_float(msm_psi4_code_up(b4[x], CPU_PSI_CODE_MAX));
#pragma clang loop vectorize_width(16) interleave_count(2)
    for (int x = 0; x < columns; ++x)
        psi_code[x] = as_float(msm_psi4_code_checked(as_uint(psi_code[x]), b4[x], CPU_PSI_CODE_MAX));
    for (int x = 0; x < columns; ++x) {
        msm_nlq n;
        n.y1 = b1[x];
        n.y2 = b2[x];
        n.v2 = b3[x];
        n.xi4 = 0.0f; // not read: its code is psi_code[x]
#if MSM_FORMAT == MSM_FORMAT_NLQ64
        const msm_word2 code = msm_encode_nlq64_psi_code(n, as_uint(psi_code[x]));
        out[2 * x] = code.w0;
        out[2 * x + 1] = code.w1;
#else
        out[x] = msm_encode_nlq32_psi_code(n, as_uint(psi_code[x]));
#endif
    }
#else
    for (int x = 0; x < columns; ++x) {
        const msm_moments m = filtered_moments(b1, b2, b3, b4, x);
#if MSM_FLOAT_TEXELS
        // Float texels are the filtered lanes' bits, the format's first MSM_TEXEL_WORDS lanes.
        out[MSM_TEXEL_WORDS * x] = as_uint(m.b1);
#if MSM_TEXEL_WORDS > 1
        out[MSM_TEXEL_WORDS * x + 1] = as_uint(m.b2);
#endif
#if MSM_TEXEL_WORDS > 2
        out[MSM_TEXEL_WORDS * x + 2] = as_uint(m.b3);
        out[MSM_TEXEL_WORDS * x + 3] = as_uint(m.b4);
#endif
#elif MSM_FORMAT == MSM_FORMAT_MSM64 || MSM_FORMAT == MSM_FORMAT_EVSM4_64
#if MSM_FORMAT == MSM_FORMAT_MSM64
        const msm_word2 code = msm_encode_msm64(m);
#else
        const msm_word2 code = msm_pack_codes16(msm_lane_code16(m.b1), msm_lane_code16(m.b2), msm_lane_code16(m.b3),
                                                msm_lane_code16(m.b4));
#endif
        out[2 * x] = code.w0;
        out[2 * x + 1] = code.w1;
#elif MSM_FORMAT == MSM_FORMAT_VSM32 || MSM_FORMAT == MSM_FORMAT_EVSM2_32
        out[x] = msm_lane_code16(m.b1) | (msm_lane_code16(m.b2) << 16);
#else
#error "filter_fused_cpu.cl: a format without its texel encoding"
#endif
    }
#endif
}

#define CPU_KERNEL_ARGS                                                                                   \
    __global const float *restrict depth, int width, int height, __global uint *restrict texture, float w0, \
        float w1, float w2, float w3, float w4, int ix0, int ix1 CPU_LAYER_PARAMS

// Texture arrays (MSM_ARRAY 1, msm_array.clh): the group's layer of the depth, the texture
// and the translucent layers.
#if MSM_LAYERS
#define CPU_ARRAY_LAYER_SLICES                                                                            \
    MSM_ARRAY_SLICE(layer_depth, (size_t)width * height * MSM_SAMPLES * MSM_LAYERS);                      \
    MSM_ARRAY_SLICE(layer_opacity, (size_t)width * height * MSM_SAMPLES * MSM_LAYERS);
#else
#define CPU_ARRAY_LAYER_SLICES
#endif
#define CPU_ARRAY_SLICES                                                                                  \
    MSM_ARRAY_SLICE(depth, (size_t)width * height * MSM_SAMPLES);                                         \
    MSM_ARRAY_SLICE(texture, (size_t)width * height * MSM_TEXEL_WORDS);                                   \
    CPU_ARRAY_LAYER_SLICES

// Both kernels: the tile of this group. Input rows 0..7 only fill the ring; each later row
// gives one output row, as many as the tile has inside the image. `border` is a constant
// at each use: the interior kernel's loops run over all columns with constant bounds.
#define CPU_PREFETCH_PART(part)                                                                           \
    prefetch_rows(depth, texture, width, height, x0, y0, first, last, columns, r, rows_in, part)
#define CPU_FILTER_TILE(BORDER)                                                                           \
    __local float resolved[CPU_RESOLVED_ENTRIES(CPU_TILE_W)];                                             \
    __local float ring[CPU_RING_ENTRIES(CPU_TILE_W)];                                                     \
    __local float filtered[CPU_FILTERED_ENTRIES(CPU_TILE_W)];                                             \
    CPU_ARRAY_SLICES                                                                                      \
    const int x0 = tile_x0(BORDER, ix0, ix1);                                                             \
    const int y0 = tile_y0();                                                                             \
    /* Input columns inside the image, output columns inside it, input rows to stream. */                \
    const int first = (BORDER) ? max(0, CPU_GUARD - x0) : 0;                                              \
    const int last = (BORDER) ? min(CPU_IN_W, width + CPU_GUARD - x0) : CPU_IN_W;                         \
    const int columns = (BORDER) ? min(CPU_TILE_W, width - x0) : CPU_TILE_W;                              \
    const int rows_in = min(CPU_TILE_H, height - y0) + 2 * CPU_GUARD;                                     \
    const float shift = tile_shift(depth, width, height, x0, y0, first, last, rows_in, filtered);        \
    for (int r = 0; r < rows_in; ++r) {                                                                   \
        const size_t row = (size_t)clamp(y0 - CPU_GUARD + r, 0, height - 1) * width;                      \
        CPU_PREFETCH_PART(0);                                                                             \
        resolve_row(depth, width, height, x0, first, last, row, shift, resolved CPU_LAYER_ARGS);          \
        CPU_PREFETCH_PART(1);                                                                             \
        blur_row(w0, w1, w2, w3, w4, resolved, ring + (r % 9) * 4 * CPU_TILE_W);                          \
        CPU_PREFETCH_PART(2);                                                                             \
        if (r < 2 * CPU_GUARD) {                                                                          \
            CPU_PREFETCH_PART(3);                                                                         \
            continue;                                                                                     \
        }                                                                                                 \
        blur_column(w0, w1, w2, w3, w4, r, ring, filtered);                                               \
        CPU_PREFETCH_PART(3);                                                                             \
        quantize_row(filtered, resolved, shift, columns,                                                  \
                     texture + ((size_t)(y0 + r - 2 * CPU_GUARD) * width + x0) * MSM_TEXEL_WORDS);       \
    }

// Tile columns ix0 .. ix1-1 (input columns and outputs inside the image), every tile row.
__kernel __attribute__((reqd_work_group_size(1, 1, 1)))
void filter_fused_cpu_interior(CPU_KERNEL_ARGS) {
    CPU_FILTER_TILE(0)
}

// Tile columns left of ix0 and from ix1 on, every tile row.
__kernel __attribute__((reqd_work_group_size(1, 1, 1)))
void filter_fused_cpu_border(CPU_KERNEL_ARGS) {
    CPU_FILTER_TILE(1)
}
