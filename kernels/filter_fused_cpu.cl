// The fused filter (resolve -> 9x9 Gaussian -> quantize, one global write) distributed
// for CPU devices. PoCL turns the code between two barriers into a loop over the
// work-items and vectorizes that loop (docs/devices.md). This kernel is written
// for that:
//  - scalar code; work-item x works on texel column x, so consecutive work-items touch
//    consecutive floats;
//  - nothing but uniform values is used across a barrier, and no value is computed once
//    and reused in a later phase (see CPU_X, CPU_BUFFER and the row counter);
//  - no vector value anywhere, including none that PoCL's SLP vectorizer could form out
//    of one work-item's code before it builds the loops (see CPU_END_BLOCK and the
//    quantization phases);
//  - math functions that vectorize (see below);
//  - interior and border tile columns are separate kernels, only the border one clamps
//    column indices; phases compute on every work-item and only stores are masked.
// A work-group of CPU_IN_W = CPU_TILE_W + 8 work-items (one per input column: the tile
// and its guard band) streams a CPU_TILE_W x CPU_TILE_H output tile one input row r at a
// time. Per row:
//   blur:     horizontal 9-tap of row r into slot r % 9 of a ring of the last 9 blurred
//             rows; from the ninth row on also the vertical 9-tap over the ring (each
//             work-item reads its own ring column only);
//   resolve:  moments of the S samples of input texel (x0 - 4 + x, row r + 1), averaged,
//             into the other of two row buffers (same phase as the blur);
//   quantize: one phase per channel, then one that stores output row r - 8;
//   a barrier after each phase, and one to advance the row.
// Same math headers, taps and float operation order as filter_fused_gpu.cl and
// filter_three_pass.cl: moments128 and msm64 equal them bit for bit; the nlq formats shift
// the moments by the midrange c of the tile's input depths (docs/math.md, see
// shift_partials).
// Compile-time: MSM_SAMPLES, MSM_FORMAT, MSM_DEPTH_ZERO_ONE, MSM_LAYERS as for
// filter_fused_gpu.cl; CPU_TILE_W, CPU_TILE_H: tuning parameters (host/ops/filter.cpp).

// Math functions for the quantizers of msm_formats.clh that vectorize across work-items
// (in this kernel only). PoCL's floor() and ceil() are library code with branches:
// clang's builtins become single instructions with the same IEEE results. PoCL's exp() is
// branchy: Psi4's inverse takes msm_exp (msm_filterable.clh), inline and branch-free, the
// algorithm the warps use in every kernel (FreeBSD's e_expf.c). Psi4's logarithm is msm_logf
// of msm_moments.clh in every kernel.
#define floor(x) __builtin_floorf(x)
#define ceil(x) __builtin_ceilf(x)
// exp: msm_exp (msm_filterable.clh), the same algorithm the warps use in every kernel.
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
#define CPU_ROW_PLANE CPU_ROW_PLANE_OF(CPU_TILE_W)

#if MSM_FORMAT_SHIFTED
#define CPU_SHIFTED 1
#else
#define CPU_SHIFTED 0
#endif

// Origin of this group's output tile. Interior groups: tile column ix0 + group x; border
// groups: the tile columns left of ix0, then those from ix1 on. Tile row = group y.
static inline int tile_x0(int border, int ix0, int ix1) {
    const int g = (int)get_group_id(0);
    const int column = border ? (g < ix0 ? g : ix1 + (g - ix0)) : ix0 + g;
    return column * CPU_TILE_W;
}
static inline int tile_y0(void) { return (int)get_group_id(1) * CPU_TILE_H; }

// Input texel (x0 - 4 + x, row / width) of a map of MSM_SAMPLES floats per texel, `row`
// the first texel of its row: border tiles clamp the column into the image; interior ones
// add the id last, to a uniform base pointer (see CPU_X).
static inline __global const float* input_texel(__global const float* map, size_t row, int border, int x0,
                                                int width, size_t x) {
    if (border) return map + (row + (size_t)clamp(x0 - CPU_GUARD + (int)x, 0, width - 1)) * MSM_SAMPLES;
    __global const float* first = map + (row + (size_t)(x0 - CPU_GUARD)) * MSM_SAMPLES;
    return first + x * MSM_SAMPLES;
}

// Rows alternate between two buffers of `size` floats.
#define CPU_BUFFER(r, size) ((size_t)((r) % 2) * (size))

// The local id as every phase of row r uses it: plus r * zero, where `zero` is a kernel
// argument that is always 0. Without the row in it, the compiler hoists id-derived
// indices (x * S, x + const) out of the row loop; PoCL then keeps them per work-item
// across the barriers and every access through them becomes a gather (docs/devices.md, PoCL).
// Constant and uniform offsets go into base pointers, never into an integer sum with the
// id (the compiler would regroup that sum and hoist the id part again).
#define CPU_X(r) ((size_t)get_local_id(0) + (size_t)((r) * zero))

// Ends a basic block with a store that never happens. PoCL optimizes each work-item's
// code before it builds the loops over the work-items, and its SLP vectorizer, which
// works within one basic block, would fuse independent, identical computations of one
// work-item (the samples of a texel, the moment planes, the channels of a code) into
// vectors; any vector value stops the vectorization across work-items (docs/devices.md, PoCL).
// The condition tests a value just computed (`bits`: a code below 0xffff0000, the upper
// half of one with a zero low half, or a finite float's bits) against a pattern it cannot
// have, distinct per `tag` (1 to 0xffff), through `zero` (else the compiler would see
// from the code's known bits that it is false): the compiler can neither prove it false
// nor merge two such branches. The store goes into the texture where nothing overwrites
// it later, so it is not removed as dead either; its index is the phase's own x (CPU_X),
// not a bare local id, which the compiler would compute once for all phases.
#define CPU_END_BLOCK(tag, bits) \
    if (((bits) ^ (uint)zero) == 0xffff0000u + (uint)(tag)) texture[x] = (bits)

// The shift c of the nlq formats (docs/math.md), as in filter_fused_gpu.cl: the midrange
// (min + max) / 2 of the internal depths z < 1 of sample 0 of the tile's input texels
// (CPU_IN_W x (CPU_TILE_H + 8), clamped into the image as the resolve clamps them); 1 if
// all are on the far plane, which takes no part (it would pull c halfway away from the
// geometry). No texel of the tile lies more than half its depth range from c. Two phases
// before the first resolve:
// 1. work-item x: min and max over its input column, into partials[x], partials[CPU_IN_W + x]
//    (the `filtered` planes, unused until the first output row);
// 2. every work-item: min and max of all partials, c into its own cell of `shift_of`, which
//    every later phase reads at its CPU_X (a per-work-item copy: PoCL keeps nothing live
//    across barriers, and a uniform local value would be forwarded per work-item anyway).
// min and max are exact in any order: c does not depend on the schedule.
#if CPU_SHIFTED
static inline void shift_partials(__global const float* depth, int width, int height, int border, int ix0, int ix1,
                                  int zero, int r, __local float* partials) {
    const size_t x = CPU_X(r);
    const int x0 = tile_x0(border, ix0, ix1);
    const int y0 = tile_y0();
    __global const float* column = input_texel(depth, 0, border, x0, width, x);
    float lowest = 1.0f, highest = -1.0f;
#pragma unroll
    for (int k = 0; k < CPU_TILE_H + 2 * CPU_GUARD; ++k) {
        const size_t row = (size_t)clamp(y0 - CPU_GUARD + k, 0, height - 1) * width * MSM_SAMPLES;
        const float z = msm_internal_depth(column[row], MSM_DEPTH_ZERO_ONE);
        const int rendered = z < 1.0f;
        lowest = rendered ? msm_minf(lowest, z) : lowest;
        highest = rendered ? msm_maxf(highest, z) : highest;
    }
    partials[x] = lowest;
    (partials + CPU_IN_W)[x] = highest;
}

static inline void shift_reduce(int zero, int r, __local const float* partials, __local float* shift_of) {
    const size_t x = CPU_X(r);
    float lowest = partials[0], highest = partials[CPU_IN_W];
#pragma unroll
    for (int k = 1; k < CPU_IN_W; ++k) {
        lowest = msm_minf(lowest, partials[k]);
        highest = msm_maxf(highest, partials[CPU_IN_W + k]);
    }
    shift_of[x] = lowest <= highest ? (lowest + highest) * 0.5f : 1.0f;
}
#endif

// The shift c of this work-item's tile (0 for the unshifted formats), in a phase of row r.
static inline float tile_shift(__local const float* shift_of, int zero, int r) {
#if CPU_SHIFTED
    return shift_of[CPU_X(r)];
#else
    return 0.0f;
#endif
}

#if MSM_LAYERS
// Sample s of a texel with its translucent layers: msm_translucent_sample and
// msm_translucent_moments (msm_translucent.clh) with the same operations in the same
// order, and CPU_END_BLOCK between the layers and between the surfaces (the SLP vectorizer
// would pack the layers' identical computations into vectors). Tested against the same
// double reference as every kernel, and bit for bit against the other kernels.
static inline __attribute__((always_inline)) msm_moments
cpu_translucent_sample(__global const float* samples, __global const float* layer_z, __global const float* layer_a,
                       size_t layer_stride, int s, float shift, __global uint* texture, size_t x, int zero) {
    MSM_NO_CONTRACT
    float z[MSM_LAYERS], a[MSM_LAYERS];
#pragma unroll
    for (int k = 0; k < MSM_LAYERS; ++k) {
        z[k] = msm_internal_depth((layer_z + k * layer_stride)[s], MSM_DEPTH_ZERO_ONE);
        a[k] = msm_layer_opacity((layer_a + k * layer_stride)[s]);
        CPU_END_BLOCK(500 + k, as_uint(z[k]));
    }
    const float opaque_z = msm_internal_depth(samples[s], MSM_DEPTH_ZERO_ONE);
    msm_moments sum;
    sum.b1 = 0.0f;
    sum.b2 = 0.0f;
    sum.b3 = 0.0f;
    sum.b4 = 0.0f;
    float total = 0.0f;
#pragma unroll
    for (int i = 0; i < MSM_LAYERS; ++i) {
        float transmitted = z[i] <= opaque_z ? 1.0f : 0.0f;
#pragma unroll
        for (int j = 0; j < MSM_LAYERS; ++j) {
            const int in_front = z[j] < z[i] || (z[j] == z[i] && j < i);
            transmitted *= in_front ? 1.0f - a[j] : 1.0f;
        }
        const float weight = transmitted * a[i];
        sum = msm_moments_add(sum, msm_moments_scale(msm_filter_lanes(z[i], shift), weight));
        total += weight;
        CPU_END_BLOCK(600 + i, as_uint(sum.b1));
    }
    float transmitted = 1.0f;
#pragma unroll
    for (int j = 0; j < MSM_LAYERS; ++j) transmitted *= z[j] <= opaque_z ? 1.0f - a[j] : 1.0f;
    sum = msm_moments_add(sum, msm_moments_scale(msm_filter_lanes(opaque_z, shift), transmitted));
    total += transmitted;
    return msm_moments_scale(sum, 1.0f / total);
}
#endif

// Before the first phase: zeros into the 8 padding floats of every plane of both row
// buffers, which the last 8 work-items' 9-tap windows read. Their results are never
// stored, but a value read from memory nothing wrote is undefined (and a GPU or an
// uninitialized-value checker rightly flags the branches of CPU_END_BLOCK on it).
static inline void clear_row_padding(int zero, __local float* resolved) {
    const size_t x = CPU_X(0);
    if (x < 2 * CPU_GUARD) {
#pragma unroll
        for (int plane = 0; plane < 2 * 4; ++plane) (resolved + plane * CPU_ROW_PLANE + CPU_IN_W)[x] = 0.0f;
    }
}

// Phase "resolve" of input row r: work-item x averages the moments of (z - shift) of the
// S samples of input texel (x0 - 4 + x, clamped row) into buffer r % 2 of `resolved`, in
// the order of msm_resolve_texel (msm_moments.clh) (sum from sample 0 up, times 1/S).
static inline void resolve_row(__global const float* depth, int width, int height, __global uint* texture,
                               int border, int ix0, int ix1, int zero, int r, __local const float* shift_of,
                               __local float* resolved CPU_LAYER_PARAMS) {
    const size_t x = CPU_X(r);
    const int x0 = tile_x0(border, ix0, ix1);
    const int y0 = tile_y0();
    const float shift = tile_shift(shift_of, zero, r);
    CPU_END_BLOCK(400, as_uint(shift)); // else the SLP vectorizer pairs it with sample 0
    const size_t row = (size_t)clamp(y0 - CPU_GUARD + r, 0, height - 1) * width;
    __global const float* samples = input_texel(depth, row, border, x0, width, x);
#if MSM_LAYERS
    // The same texel of layer 0 (layer k lies k * layer_stride floats further), addressed
    // like the depth samples.
    const size_t layer_stride = (size_t)width * height * MSM_SAMPLES;
    __global const float* layer_z = input_texel(layer_depth, row, border, x0, width, x);
    __global const float* layer_a = input_texel(layer_opacity, row, border, x0, width, x);
    msm_moments sum = cpu_translucent_sample(samples, layer_z, layer_a, layer_stride, 0, shift, texture, x, zero);
#pragma unroll
    for (int s = 1; s < MSM_SAMPLES; ++s) {
        CPU_END_BLOCK(s, as_uint(sum.b1));
        sum = msm_moments_add(sum, cpu_translucent_sample(samples, layer_z, layer_a, layer_stride, s, shift, texture,
                                                          x, zero));
    }
#else
    msm_moments sum = msm_filter_lanes(msm_internal_depth(samples[0], MSM_DEPTH_ZERO_ONE), shift);
#pragma unroll
    for (int s = 1; s < MSM_SAMPLES; ++s) {
        CPU_END_BLOCK(s, as_uint(sum.b1));
        sum = msm_moments_add(sum, msm_filter_lanes(msm_internal_depth(samples[s], MSM_DEPTH_ZERO_ONE), shift));
    }
#endif
    const msm_moments m = msm_moments_scale(sum, 1.0f / (float)MSM_SAMPLES);
    __local float* out = resolved + CPU_BUFFER(r, 4 * CPU_ROW_PLANE);
    MSM_STORE4(out, CPU_ROW_PLANE, x, m.b1, m.b2, m.b3, m.b4);
}

// 9-tap sum of v(0..8) with weights w4 w3 w2 w1 w0 w1 w2 w3 w4, the first tap innermost
// (the order of the other kernels).
#define CPU_TAPS9(v)                                                                          \
    fma(w4, v(8), fma(w3, v(7), fma(w2, v(6), fma(w1, v(5),                                   \
    fma(w0, v(4), fma(w1, v(3), fma(w2, v(2), fma(w3, v(1), w4 * v(0)))))))))

#define CPU_AT_H(i) in[(i)]
// Ring row i (0 = oldest, input row r - 8) of moment plane j.
#define CPU_AT_V(i) (ring + (size_t)((r + 1 + (i)) % 9) * 4 * CPU_IN_W + j * CPU_IN_W)[x]

// Phase "blur", first half: horizontal 9-tap of input row r into ring slot r % 9.
static inline void blur_row(__global uint* texture, float w0, float w1, float w2, float w3, float w4, int zero,
                            int r, __local const float* resolved, __local float* ring) {
    const size_t x = CPU_X(r);
    __local const float* row_in = resolved + CPU_BUFFER(r, 4 * CPU_ROW_PLANE);
    __local float* slot = ring + (size_t)(r % 9) * 4 * CPU_IN_W;
#pragma unroll
    for (int j = 0; j < 4; ++j) {
        __local const float* in = row_in + j * CPU_ROW_PLANE;
        in += x;
        const float h = CPU_TAPS9(CPU_AT_H);
        (slot + j * CPU_IN_W)[x] = h;
        CPU_END_BLOCK(100 + j, as_uint(h));
    }
}

// Phase "blur", second half (r >= 8): vertical 9-tap over the ring, rows r-8 .. r, into
// the planes of `filtered` (each work-item its own column).
static inline void blur_column(__global uint* texture, float w0, float w1, float w2, float w3, float w4, int zero,
                               int r, __local const float* ring, __local float* filtered) {
    const size_t x = CPU_X(r);
#pragma unroll
    for (int j = 0; j < 4; ++j) {
        const float b = CPU_TAPS9(CPU_AT_V);
        (filtered + j * CPU_IN_W)[x] = b;
        CPU_END_BLOCK(300 + j, as_uint(b));
    }
}

// Algorithm 2 exactly as msm_nlq_from_shifted_moments (msm_moments.clh) computes it (bias
// held as offsets, q2, q1 and xi4 in float-float), the same operations in the same order,
// written for the vectorization across work-items: a single return (the header's early
// return merges two 16-byte structs, which the x86-64 calling convention passes as pairs
// of float2, and that vector-typed merge stays after inlining), and CPU_END_BLOCK after
// each of the computations that have the same shape (the four bias offsets, the three
// float-float differences, the four clamped outputs), which the SLP vectorizer would pack
// into vectors otherwise (it did: the four outputs became one <4 x float> merge and this
// phase ran one work-item at a time). y2 is a default NaN on the single-depth path, never
// CPU_END_BLOCK's pattern. Tested against the same double reference as every kernel.
static inline __attribute__((always_inline)) msm_nlq cpu_nlq_from_shifted_moments(msm_moments b, float c,
                                                                                 __global uint* texture, size_t x,
                                                                                 int zero) {
    MSM_NO_CONTRACT
    const msm_moments target = msm_float_bias_target_shifted(c);
    msm_moments l;
    l.b1 = MSM_ALPHA_FLOAT * (target.b1 - b.b1);
    CPU_END_BLOCK(701, as_uint(l.b1));
    l.b2 = MSM_ALPHA_FLOAT * (target.b2 - b.b2);
    CPU_END_BLOCK(702, as_uint(l.b2));
    l.b3 = MSM_ALPHA_FLOAT * (target.b3 - b.b3);
    CPU_END_BLOCK(703, as_uint(l.b3));
    l.b4 = MSM_ALPHA_FLOAT * (target.b4 - b.b4);
    CPU_END_BLOCK(704, as_uint(l.b4));
    float square = b.b1 * b.b1;
    float q2_sum = b.b2 - square;
    float q2_tail = msm_two_sum_error(b.b2, -square, q2_sum) - msm_two_prod_error(b.b1, b.b1, square) +
                    (l.b2 - l.b1 * (2.0f * b.b1 + l.b1));
    float q2 = q2_sum + q2_tail;
    float q2_lo = msm_two_sum_error(q2_sum, q2_tail, q2);
    CPU_END_BLOCK(705, as_uint(q2_lo));
    float product = b.b1 * b.b2;
    float q1_sum = product - b.b3;
    float q1_tail = msm_two_sum_error(product, -b.b3, q1_sum) + msm_two_prod_error(b.b1, b.b2, product) +
                    (b.b1 * l.b2 + l.b1 * (b.b2 + l.b2) - l.b3);
    float q1 = q1_sum + q1_tail;
    float q1_lo = msm_two_sum_error(q1_sum, q1_tail, q1);
    CPU_END_BLOCK(706, as_uint(q1_lo));
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
    CPU_END_BLOCK(707, as_uint(y2));
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
    CPU_END_BLOCK(708, as_uint(n.v2));
    n.xi4 = single_depth ? 0.0f : clamp(xi4, 0.0f, MSM_XI4_MAX);
    CPU_END_BLOCK(709, as_uint(n.xi4));
    n.y1 = single_depth ? y : clamp(y1 + c, -1.0f, 1.0f);
    CPU_END_BLOCK(710, as_uint(n.y1));
    n.y2 = single_depth ? y : clamp(y2 + c, -1.0f, 1.0f);
    return n;
}

// Quantization: one phase per channel and a barrier between phases. Within one phase
// there is a single chain of work per work-item (the compiler drops the other channels of
// each encoder call), so the SLP vectorizer finds nothing to fuse, and no code moves
// across a barrier (docs/devices.md, PoCL). The texel's words collect in the `words` planes and
// the last phase stores them (adjacent stores of values loaded from different planes:
// not worth fusing for the SLP vectorizer, and a contiguous, interleaved store once
// vectorized across work-items). The nlq representation (y1, y2, v2, xi4) replaces the
// moments in `filtered`.
// Float texels (moments128, vsm64, evsm4_128, esm32) are the filtered lanes' bits: the store
// phase alone. The 16-bit codes of vsm32 and evsm2_32 (one word) and evsm4_64 (two words):
// one phase per channel, as msm64.
#if MSM_FLOAT_TEXELS
#define CPU_QUANTIZE_PHASES 1
#elif MSM_FORMAT == MSM_FORMAT_VSM32 || MSM_FORMAT == MSM_FORMAT_EVSM2_32
#define CPU_QUANTIZE_PHASES 3
#elif MSM_FORMAT == MSM_FORMAT_EVSM4_64
#define CPU_QUANTIZE_PHASES 5
#elif MSM_FORMAT == MSM_FORMAT_MSM64
#define CPU_QUANTIZE_PHASES 5
#elif MSM_FORMAT == MSM_FORMAT_NLQ64
#define CPU_QUANTIZE_PHASES 6
#elif MSM_FORMAT == MSM_FORMAT_NLQ32
#define CPU_QUANTIZE_PHASES 4
#endif
#define CPU_WORDS MSM_TEXEL_WORDS

// Flattened: every call inside is inlined (the compiler would keep the encoders, called
// from several phases, out of line, and a call stops the vectorization).
// The buffers are `restrict` and the row is read here: then the compiler knows that the
// phase's stores leave the row counter alone and reads it once, not once per work-item.
static inline __attribute__((always_inline, flatten)) void quantize_phase(int phase, __global const float* depth, int width, int height,
                                  __global uint* texture, int border, int ix0, int ix1, int zero,
                                  __global const int* row, __local const float* restrict shift_of,
                                  __local float* restrict filtered, __local uint* restrict words) {
    const int r = *row;
    const size_t x = CPU_X(r);
    const int x0 = tile_x0(border, ix0, ix1);
    const int y0 = tile_y0();
    __local uint* word0 = words;
    __local uint* word1 = words + CPU_IN_W;
#if MSM_FLOAT_TEXELS
    __local const uint* bits = (__local const uint*)filtered; // the moments' bits are the words
#else
    __local const uint* bits = words;
#endif
    if (phase == CPU_QUANTIZE_PHASES - 1) {
        // Store the texel: inside the tile and the image only.
        if (x < CPU_TILE_W && (!border || x0 + (int)x < width)) {
            __global uint* out = texture + ((size_t)(y0 + r - 2 * CPU_GUARD) * width + x0) * CPU_WORDS;
#if MSM_TEXEL_WORDS == 2 && !MSM_FLOAT_TEXELS
            // Both words as one 64-bit store (a contiguous masked store once vectorized,
            // where two 32-bit stores became a scatter).
            const uint low = word0[x] | (words + 2 * CPU_IN_W)[x];
            const uint high = word1[x] | (words + 3 * CPU_IN_W)[x];
            ((__global ulong*)out)[x] = (ulong)low | ((ulong)high << 32);
#else
            out += CPU_WORDS * x;
#pragma unroll
            for (int k = 0; k < CPU_WORDS; ++k) out[k] = (bits + k * CPU_IN_W)[x];
#endif
        }
        return;
    }
#if CPU_SHIFTED
    if (phase == 0) {
        // Algorithm 2 (with the tile's shift): the nlq values replace the moments in `filtered`.
        msm_moments m;
        MSM_LOAD4(m.b1, m.b2, m.b3, m.b4, filtered, CPU_IN_W, x);
        const float shift = tile_shift(shift_of, zero, r);
        CPU_END_BLOCK(401, as_uint(shift));
        const msm_nlq n = cpu_nlq_from_shifted_moments(m, shift, texture, x, zero);
        MSM_STORE4(filtered, CPU_IN_W, x, n.y1, n.y2, n.v2, n.xi4);
        return;
    }
    // The encoder's phases count from 0 after it.
    --phase;
    msm_nlq n;
    MSM_LOAD4(n.y1, n.y2, n.v2, n.xi4, filtered, CPU_IN_W, x);
#elif MSM_FORMAT == MSM_FORMAT_MSM64 || !MSM_FLOAT_TEXELS
    msm_moments m;
    MSM_LOAD4(m.b1, m.b2, m.b3, m.b4, filtered, CPU_IN_W, x);
#endif
#if MSM_FORMAT == MSM_FORMAT_MSM64 || MSM_FORMAT == MSM_FORMAT_NLQ64
    // The two 32-bit words of the 64-bit formats, 16 bits a phase.
#if MSM_FORMAT == MSM_FORMAT_MSM64
#define CPU_ENCODE msm_encode_msm64(m)
#else
#define CPU_ENCODE msm_encode_nlq64(n)
#endif
    if (phase == 0) word0[x] = CPU_ENCODE.w0 & 0xffffu;
    if (phase == 1) (words + 2 * CPU_IN_W)[x] = CPU_ENCODE.w0 & 0xffff0000u;
    if (phase == 2) word1[x] = CPU_ENCODE.w1 & 0xffffu;
    if (phase == 3) (words + 3 * CPU_IN_W)[x] = CPU_ENCODE.w1 & 0xffff0000u;
#undef CPU_ENCODE
#elif MSM_FORMAT == MSM_FORMAT_NLQ32
    if (phase == 0) word0[x] = msm_encode_nlq32(n) & 0x1fc0u;              // sqrt(v2)
    if (phase == 1) word0[x] |= msm_encode_nlq32(n) & 0xffffe03fu;         // folded depths, Psi4
#elif MSM_FORMAT == MSM_FORMAT_VSM32 || MSM_FORMAT == MSM_FORMAT_EVSM2_32
    // Two 16-bit codes in one word (msm_store_texel's layout).
    if (phase == 0) word0[x] = msm_lane_code16(m.b1);
    if (phase == 1) word0[x] |= msm_lane_code16(m.b2) << 16;
#elif MSM_FORMAT == MSM_FORMAT_EVSM4_64
    // Four half codes in the planes of the 64-bit formats (stored as one 64-bit word).
    if (phase == 0) word0[x] = msm_lane_code16(m.b1);
    if (phase == 1) (words + 2 * CPU_IN_W)[x] = msm_lane_code16(m.b2) << 16;
    if (phase == 2) word1[x] = msm_lane_code16(m.b3);
    if (phase == 3) (words + 3 * CPU_IN_W)[x] = msm_lane_code16(m.b4) << 16;
#endif
}

#define CPU_KERNEL_ARGS                                                                                   \
    __global const float *restrict depth, int width, int height, __global uint *restrict texture, float w0, \
        float w1, float w2, float w3, float w4, int ix0, int ix1, __global int *progress, int zero CPU_LAYER_PARAMS

// One quantization phase and its barrier (the phase is a constant at each use). The last
// phase's barrier also orders global memory: every work-item has read the row counter in
// it, and work-item 0 advances the counter after it (CPU_ROW_FENCE).
#define CPU_QUANTIZE(PHASE, BORDER)                                                                       \
    if ((PHASE) < CPU_QUANTIZE_PHASES) {                                                                  \
        quantize_phase((PHASE), depth, width, height, texture, BORDER, ix0, ix1, zero, row, shift_of,    \
                       filtered, words);                                                                  \
        barrier((PHASE) == CPU_QUANTIZE_PHASES - 1 ? CPU_ROW_FENCE : CLK_LOCAL_MEM_FENCE);               \
    }

// The barrier between the last reads of the row counter and work-item 0's increment: the
// counter is global memory, which a barrier orders only with CLK_GLOBAL_MEM_FENCE (OpenCL
// 1.2, section 6.12.8); with the local fence alone the reads race with the increment.
#define CPU_ROW_FENCE (CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE)

// The texel words' planes; float texels are the filtered values' bits and need none (the
// quantization never touches `words` then).
#if MSM_FLOAT_TEXELS
#define CPU_WORD_STORAGE __local uint* words = (__local uint*)filtered;
#else
#define CPU_WORD_STORAGE __local uint words[CPU_WORD_ENTRIES(CPU_TILE_W)];
#endif

// The shift's storage and its two phases (nlq formats); the other formats pass a pointer
// nothing reads.
#if CPU_SHIFTED
#define CPU_SHIFT_STORAGE __local float shift_of[CPU_SHIFT_ENTRIES(CPU_TILE_W)];
#define CPU_SHIFT_PHASES(BORDER)                                                                          \
    shift_partials(depth, width, height, BORDER, ix0, ix1, zero, *row, filtered);                        \
    barrier(CLK_LOCAL_MEM_FENCE);                                                                         \
    shift_reduce(zero, *row, filtered, shift_of);                                                         \
    barrier(CLK_LOCAL_MEM_FENCE);
#else
#define CPU_SHIFT_STORAGE __local const float* shift_of = filtered;
#define CPU_SHIFT_PHASES(BORDER)
#endif

// Texture arrays (MSM_ARRAY 1, msm_array.clh): the group's layer of the depth, the texture,
// the translucent layers and the row counters (one per group of each layer).
#if MSM_LAYERS
#define CPU_ARRAY_LAYER_SLICES                                                                            \
    MSM_ARRAY_SLICE(layer_depth, (size_t)width * height * MSM_SAMPLES * MSM_LAYERS);                      \
    MSM_ARRAY_SLICE(layer_opacity, (size_t)width * height * MSM_SAMPLES * MSM_LAYERS);
#else
#define CPU_ARRAY_LAYER_SLICES
#endif
#define CPU_ARRAY_SLICES                                                                                  \
    MSM_ARRAY_SLICE(depth, (size_t)width * height * MSM_SAMPLES);                                         \
    MSM_ARRAY_SLICE(texture, (size_t)width * height * CPU_WORDS);                                         \
    MSM_ARRAY_SLICE(progress, get_num_groups(0) * get_num_groups(1));                                     \
    CPU_ARRAY_LAYER_SLICES

// Both kernels. The current row lives in global memory (progress[group], scratch the host
// provides) and every phase reads it anew: a loop counter would be kept per work-item by
// PoCL (it does not see that it is uniform), a __local one the compiler forwards from
// store to load into a per-work-item copy, and every address computed from such a copy
// becomes a gather. Rows 0..7 only fill the ring; each later row writes one output row,
// as many as the tile has inside the image. Per row: blur row r (and the vertical blur),
// resolve row r + 1 | the quantization phases | advance the row.
#define CPU_FILTER_TILE(BORDER)                                                                           \
    __local float resolved[CPU_RESOLVED_ENTRIES(CPU_TILE_W)];                                             \
    __local float ring[CPU_RING_ENTRIES(CPU_TILE_W)];                                                     \
    __local float filtered[CPU_FILTERED_ENTRIES(CPU_TILE_W)];                                             \
    CPU_WORD_STORAGE                                                                                      \
    CPU_SHIFT_STORAGE                                                                                     \
    CPU_ARRAY_SLICES                                                                                      \
    __global int* row = progress + get_group_id(1) * get_num_groups(0) + get_group_id(0);               \
    if (get_local_id(0) == 0) *row = 0;                                                                   \
    clear_row_padding(zero, resolved);                                                                    \
    barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);                                                  \
    CPU_SHIFT_PHASES(BORDER)                                                                              \
    resolve_row(depth, width, height, texture, BORDER, ix0, ix1, zero, *row, shift_of, resolved CPU_LAYER_ARGS);                  \
    barrier(CLK_LOCAL_MEM_FENCE);                                                                         \
    for (int fill = 2 * CPU_GUARD; fill > 0; --fill) {                                                    \
        blur_row(texture, w0, w1, w2, w3, w4, zero, *row, resolved, ring);                               \
        resolve_row(depth, width, height, texture, BORDER, ix0, ix1, zero, *row + 1, shift_of, resolved CPU_LAYER_ARGS);          \
        barrier(CPU_ROW_FENCE);                                                                           \
        if (get_local_id(0) == 0) *row += 1;                                                              \
        barrier(CLK_GLOBAL_MEM_FENCE);                                                                    \
    }                                                                                                     \
    for (int rows_out = min(CPU_TILE_H, height - tile_y0()); rows_out > 0; --rows_out) {                  \
        blur_row(texture, w0, w1, w2, w3, w4, zero, *row, resolved, ring);                               \
        blur_column(texture, w0, w1, w2, w3, w4, zero, *row, ring, filtered);                            \
        resolve_row(depth, width, height, texture, BORDER, ix0, ix1, zero, *row + 1, shift_of, resolved CPU_LAYER_ARGS);          \
        barrier(CLK_LOCAL_MEM_FENCE);                                                                     \
        CPU_QUANTIZE(0, BORDER)                                                                           \
        CPU_QUANTIZE(1, BORDER)                                                                           \
        CPU_QUANTIZE(2, BORDER)                                                                           \
        CPU_QUANTIZE(3, BORDER)                                                                           \
        CPU_QUANTIZE(4, BORDER)                                                                           \
        CPU_QUANTIZE(5, BORDER)                                                                           \
        if (get_local_id(0) == 0) *row += 1;                                                              \
        barrier(CLK_GLOBAL_MEM_FENCE);                                                                    \
    }

// Tile columns ix0 .. ix1-1 (input columns and outputs inside the image), every tile row.
__kernel __attribute__((reqd_work_group_size(CPU_IN_W, 1, 1)))
void filter_fused_cpu_interior(CPU_KERNEL_ARGS) {
    CPU_FILTER_TILE(0)
}

// Tile columns left of ix0 and from ix1 on, every tile row.
__kernel __attribute__((reqd_work_group_size(CPU_IN_W, 1, 1)))
void filter_fused_cpu_border(CPU_KERNEL_ARGS) {
    CPU_FILTER_TILE(1)
}
