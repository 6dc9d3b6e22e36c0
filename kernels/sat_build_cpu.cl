// Summed-area table for CPU devices: the same table as sat_build.cl (same bits), distributed
// for a CPU. PoCL vectorizes scalar code across work-items only inside one stretch between
// barriers, and a scan needs values to cross lanes; here each work-item owns one band of
// MSM_SAT_BAND_H full rows and walks it row by row, 16 columns at a time in 16-lane vectors,
// so no barrier or local memory is needed and both the input and the table stream front to
// back, two rows at a time (two read and two write streams: walking a chunk down the band's
// rows instead makes MSM_SAT_BAND_H streams whose addresses alias modulo 4 KiB), with a
// software prefetch 4 KiB ahead:
//   column sums:  the band's running sum of every column, 4 words a column, in the band's
//                 slot of the carries buffer (2048 columns: 32 KiB, it stays in cache);
//                 stored "planar" (the 16 words of R, then G, B, A of each 16 columns), so
//                 no shuffle is needed to load or store it,
//   row scans:    4 shuffle-and-add steps across the 16 lanes, plus the row's left carry
//                 (the last lane of the chunk before),
//   layout:       16 texels are 16 * S contiguous depths (or 64 contiguous words): loaded
//                 as 16-lane vectors and de-interleaved by log2(S) levels of shuffles; the
//                 output row is re-interleaved to R,G,B,A words and stored as 4 vectors.
// With clang (PoCL), shuffles are __builtin_shufflevector and vector loads and stores plain
// 4-byte-aligned vector accesses: PoCL's shuffle2, vload16 and vstore16 reach LLVM as
// element moves and narrower accesses (2048^2, S = 1: band scan 7.7 -> 4.5 ms; timings of
// the kernels alone, PoCL profiling events, 2-core AVX-512 VM).
// Three steps: band totals (the column sums of each band), the carries down the bands
// (sat_column_carries in sat_carries.cl, elementwise, so the planar order passes through),
// the band scan. Every input is read twice and the table written once (for depth maps of
// several samples, step 1 writes the integer texels into the table, planar per chunk, and the
// scan reads them back in place: sat_band_totals_texels_cpu, MSM_SAT_SOURCE 2); no carries
// across columns are needed, as a band spans the width.
// The vector arithmetic mirrors msm_sat_texel_of_depth (msm_sat.clh) operation by
// operation, so both builds give identical bits (tests/sat_test.cpp checks it).
// Compile-time: MSM_SAT_SOURCE (0 depth with MSM_SAMPLES, MSM_DEPTH_ZERO_ONE; 1 texels,
// R,G,B,A per texel; 2 the texels of step 1: planar per full chunk, R,G,B,A in the last,
// partial chunk of a row), MSM_SAT_BAND_H (rows per band).
#include "msm_sat.clh"
#include "msm_array.clh"

#define LANES 16
#define BAND_H MSM_SAT_BAND_H
// The texel loaders and the loops' bodies: left to itself LLVM outlined row_texels16 at
// S = 8 and returned its 16 texels through the stack.
#define ALWAYS_INLINE static inline __attribute__((always_inline))
#if BAND_H % 2
#error "MSM_SAT_BAND_H must be even: step 1 reads rows in pairs"
#endif

// Two-source shuffles with constant lanes over the 32 lanes (a, b): clang's
// __builtin_shufflevector is one LLVM shufflevector (PoCL's shuffle2 reaches LLVM as
// element inserts and extracts that it only partly folds back); shuffle2 elsewhere.
#if defined(__clang__)
#define SHUFFLE2(a, b, lanes) __builtin_shufflevector((a), (b), lanes)
#else
#define SHUFFLE2(a, b, lanes) shuffle2((a), (b), (uint16)(lanes))
#endif
// Loads and stores of 16 lanes at 4-byte alignment: one vector move (PoCL's vload16 and
// vstore16 become several narrower moves); vload16 and vstore16 elsewhere.
#if defined(__clang__)
typedef float16 float16_at4 __attribute__((aligned(4)));
typedef uint16 uint16_at4 __attribute__((aligned(4)));
#define LOAD16(TYPE, i, p) (((const __global TYPE##_at4*)(p))[i])
#define STORE16(v, i, p) (((__global uint16_at4*)(p))[i] = (v))
#else
#define LOAD16(TYPE, i, p) vload16((i), (p))
#define STORE16(v, i, p) vstore16((v), (i), (p))
#endif
// A software prefetch of the cache lines `lines` * 64 bytes from p, PREFETCH_BYTES ahead:
// the band walks are one long stream each, but with the arithmetic between its loads the
// core stalls on them (2048^2, S = 8: step 1 9.2 -> 6.9 ms); msm_prefetch where the kernel
// compiles to a CPU's instructions (msm_portable.clh), OpenCL's prefetch() elsewhere (the
// kernel also runs on other devices on request).
#define PREFETCH_BYTES 4096
#if MSM_CAN_PREFETCH
#define PREFETCH_AHEAD(p, lines)                                                                       \
    _Pragma("unroll") for (int line = 0; line < (lines); ++line)                                       \
        msm_prefetch((const __global char*)(p) + PREFETCH_BYTES + 64 * line, 0, 3)
#else
#define PREFETCH_AHEAD(p, lines) prefetch((const __global char*)(p) + PREFETCH_BYTES, (size_t)(64 * (lines)))
#endif
// Lane lists.
#define MASK_EVEN 0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30
#define MASK_ODD 1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31
// Lane 15 of a in every lane.
#define MASK_LAST 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15
// Lane i of (0, v) from lane i - k of v, zero below k: the steps of a lane prefix.
#define MASK_SHIFT_1 0, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30
#define MASK_SHIFT_2 0, 1, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29
#define MASK_SHIFT_4 0, 1, 2, 3, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27
#define MASK_SHIFT_8 0, 1, 2, 3, 4, 5, 6, 7, 16, 17, 18, 19, 20, 21, 22, 23
// vpunpckl/hdq, vpunpckl/hqdq: within each 128-bit block of (a, b).
#define MASK_UNPACK_LO 0, 16, 1, 17, 4, 20, 5, 21, 8, 24, 9, 25, 12, 28, 13, 29
#define MASK_UNPACK_HI 2, 18, 3, 19, 6, 22, 7, 23, 10, 26, 11, 27, 14, 30, 15, 31
#define MASK_UNPACK_QUADS_LO 0, 1, 16, 17, 4, 5, 20, 21, 8, 9, 24, 25, 12, 13, 28, 29
#define MASK_UNPACK_QUADS_HI 2, 3, 18, 19, 6, 7, 22, 23, 10, 11, 26, 27, 14, 15, 30, 31
// vshufi32x4: 128-bit blocks (a0, a1, b0, b1), (a2, a3, b2, b3), (a0, a2, b0, b2), (a1, a3, b1, b3).
#define MASK_BLOCKS_LO 0, 1, 2, 3, 4, 5, 6, 7, 16, 17, 18, 19, 20, 21, 22, 23
#define MASK_BLOCKS_HI 8, 9, 10, 11, 12, 13, 14, 15, 24, 25, 26, 27, 28, 29, 30, 31
#define MASK_BLOCKS_EVEN 0, 1, 2, 3, 8, 9, 10, 11, 16, 17, 18, 19, 24, 25, 26, 27
#define MASK_BLOCKS_ODD 4, 5, 6, 7, 12, 13, 14, 15, 20, 21, 22, 23, 28, 29, 30, 31

// The four channels of 16 texels.
typedef struct {
    uint16 c0, c1, c2, c3;
} texels16;

// n-way interleaved data in v[0..n-1] (element k of item t at flat index t * n + k) ->
// v[k] holds element k of items 0..15 (n = 1, 2, 4, 8, 16): log2(n) levels of unzips.
#define DEINTERLEAVE(TYPE, v, n)                                                          \
    _Pragma("unroll") for (int level = 1; level < (n); level *= 2) {                      \
        TYPE w[(n)];                                                                      \
        _Pragma("unroll") for (int i = 0; i < (n) / 2; ++i) {                             \
            w[i] = SHUFFLE2(v[2 * i], v[2 * i + 1], MASK_EVEN);                           \
            w[(n) / 2 + i] = SHUFFLE2(v[2 * i], v[2 * i + 1], MASK_ODD);                  \
        }                                                                                 \
        _Pragma("unroll") for (int i = 0; i < (n); ++i) v[i] = w[i];                      \
    }

// msm_internal_depth for 16 depths: NaN and anything below -1 fail the ordered compare and
// become -1, then anything not below 1 becomes 1 (on x86 one vmaxps and one vminps).
static inline float16 internal_depth16(float16 d) {
    const float16 z = MSM_DEPTH_ZERO_ONE ? 2.0f * d - 1.0f : d;
    const float16 above = select((float16)(-1.0f), z, z > -1.0f);
    return select((float16)(1.0f), above, above < 1.0f);
}

// msm_sat_quantize for 16 values.
static inline uint16 quantize16(float16 m, uint scale) {
    float16 c = select((float16)(0.0f), m, m > 0.0f);
    c = select((float16)(1.0f), c, c < 1.0f);
    const uint16 q = convert_uint16(fma(c, (float16)((float)scale), (float16)(0.5f)));
    return min(q, (uint16)(scale));
}

static inline texels16 zero_texels16(void) {
    texels16 t;
    t.c0 = (uint16)(0u);
    t.c1 = (uint16)(0u);
    t.c2 = (uint16)(0u);
    t.c3 = (uint16)(0u);
    return t;
}

static inline texels16 add_texels16(texels16 a, texels16 b) {
    a.c0 += b.c0;
    a.c1 += b.c1;
    a.c2 += b.c2;
    a.c3 += b.c3;
    return a;
}

// Four channels from 64 consecutive words (16 texels of R, G, B, A).
static inline texels16 deinterleave_words(__global const uint* words) {
    uint16 v[4];
    v[0] = LOAD16(uint16, 0, words);
    v[1] = LOAD16(uint16, 1, words);
    v[2] = LOAD16(uint16, 2, words);
    v[3] = LOAD16(uint16, 3, words);
    DEINTERLEAVE(uint16, v, 4)
    texels16 t;
    t.c0 = v[0];
    t.c1 = v[1];
    t.c2 = v[2];
    t.c3 = v[3];
    return t;
}

// The 64 words of 16 texels, R, G, B, A per texel: a 4x16 transpose in shuffles that each
// map to one AVX-512 instruction (word and quad-word unpacks within 128-bit blocks, then a
// 4x4 transpose of the blocks); a generic zip lowers to element moves through the stack.
static inline void store_interleaved(texels16 t, __global uint* words) {
    // Per 128-bit block i: (c0, c1) of texels 4i, 4i+1 and of texels 4i+2, 4i+3.
    const uint16 rg01 = SHUFFLE2(t.c0, t.c1, MASK_UNPACK_LO);
    const uint16 rg23 = SHUFFLE2(t.c0, t.c1, MASK_UNPACK_HI);
    const uint16 ba01 = SHUFFLE2(t.c2, t.c3, MASK_UNPACK_LO);
    const uint16 ba23 = SHUFFLE2(t.c2, t.c3, MASK_UNPACK_HI);
    // Block i of texel_k: texel 4i + k, R, G, B, A.
    const uint16 texel0 = SHUFFLE2(rg01, ba01, MASK_UNPACK_QUADS_LO);
    const uint16 texel1 = SHUFFLE2(rg01, ba01, MASK_UNPACK_QUADS_HI);
    const uint16 texel2 = SHUFFLE2(rg23, ba23, MASK_UNPACK_QUADS_LO);
    const uint16 texel3 = SHUFFLE2(rg23, ba23, MASK_UNPACK_QUADS_HI);
    // Blocks (0, 1) and (2, 3) of two texel vectors, then every other block: texels in order.
    const uint16 t01_lo = SHUFFLE2(texel0, texel1, MASK_BLOCKS_LO);
    const uint16 t01_hi = SHUFFLE2(texel0, texel1, MASK_BLOCKS_HI);
    const uint16 t23_lo = SHUFFLE2(texel2, texel3, MASK_BLOCKS_LO);
    const uint16 t23_hi = SHUFFLE2(texel2, texel3, MASK_BLOCKS_HI);
    STORE16(SHUFFLE2(t01_lo, t23_lo, MASK_BLOCKS_EVEN), 0, words);
    STORE16(SHUFFLE2(t01_lo, t23_lo, MASK_BLOCKS_ODD), 1, words);
    STORE16(SHUFFLE2(t01_hi, t23_hi, MASK_BLOCKS_EVEN), 2, words);
    STORE16(SHUFFLE2(t01_hi, t23_hi, MASK_BLOCKS_ODD), 3, words);
}

// 16 texels planar: the 16 words of channel 0, then channels 1, 2, 3 (band state, step-1 texels).
static inline texels16 load_planar(__global const uint* words) {
    texels16 t;
    t.c0 = LOAD16(uint16, 0, words);
    t.c1 = LOAD16(uint16, 1, words);
    t.c2 = LOAD16(uint16, 2, words);
    t.c3 = LOAD16(uint16, 3, words);
    return t;
}

static inline void store_planar(texels16 t, __global uint* words) {
    STORE16(t.c0, 0, words);
    STORE16(t.c1, 1, words);
    STORE16(t.c2, 2, words);
    STORE16(t.c3, 3, words);
}

#if MSM_SAT_SOURCE == 0
#define SOURCE_TYPE float

// Integer texels of 16 whole texels starting at `first` (msm_sat_texel_of_depth per lane).
ALWAYS_INLINE texels16 full_texels16(__global const float* depth, size_t first, uint scale) {
    float16 d[MSM_SAMPLES];
    __global const float* p = depth + first * MSM_SAMPLES;
    PREFETCH_AHEAD(p, MSM_SAMPLES);
#pragma unroll
    for (int k = 0; k < MSM_SAMPLES; ++k) d[k] = LOAD16(float16, k, p);
    DEINTERLEAVE(float16, d, MSM_SAMPLES)
    // Moments summed in sample order, then scaled, as msm_moments_add / msm_moments_scale.
    float16 z = internal_depth16(d[0]);
    float16 z2 = z * z;
    float16 b1 = z, b2 = z2, b3 = z2 * z, b4 = z2 * z2;
#pragma unroll
    for (int k = 1; k < MSM_SAMPLES; ++k) {
        z = internal_depth16(d[k]);
        z2 = z * z;
        const float16 z3 = z2 * z;
        const float16 z4 = z2 * z2;
        b1 = b1 + z;
        b2 = b2 + z2;
        b3 = b3 + z3;
        b4 = b4 + z4;
    }
    const float inverse = 1.0f / (float)MSM_SAMPLES;
    b1 = b1 * inverse;
    b2 = b2 * inverse;
    b3 = b3 * inverse;
    b4 = b4 * inverse;
    // The affine basis of msm_sat_basis_of.
    texels16 t;
    t.c0 = quantize16(1.5f * b1 - 2.0f * b3 + 0.5f, scale);
    t.c1 = quantize16(4.0f * b2 - 4.0f * b4, scale);
    t.c2 = quantize16(MSM_SAT_SQRT3 * (0.5f * b1 - (2.0f / 9.0f) * b3) + 0.5f, scale);
    t.c3 = quantize16(0.5f * b2 + 0.5f * b4, scale);
    return t;
}

// One texel on its own (chunks that cross the right edge).
static inline msm_sat_sum single_texel(__global const float* depth, size_t texel, uint scale) {
    return msm_sat_texel_of_depth(depth, texel, MSM_SAMPLES, MSM_DEPTH_ZERO_ONE, scale);
}
#else
#define SOURCE_TYPE uint

// Ready texels: R,G,B,A per texel (MSM_SAT_SOURCE 1), or step 1's planar chunks (2).
ALWAYS_INLINE texels16 full_texels16(__global const uint* texels, size_t first, uint scale) {
    (void)scale;
    PREFETCH_AHEAD(texels + 4 * first, 4);
#if MSM_SAT_SOURCE == 2
    return load_planar(texels + 4 * first);
#else
    return deinterleave_words(texels + 4 * first);
#endif
}

// A texel of a partial chunk: R,G,B,A in both texel layouts.
static inline msm_sat_sum single_texel(__global const uint* texels, size_t texel, uint scale) {
    (void)scale;
    msm_sat_sum t;
    MSM_LOAD4(t.c0, t.c1, t.c2, t.c3, texels, 1, 4 * texel);
    return t;
}
#endif

// Row y of the chunk at x0: the 16 texels, zero beyond the map.
ALWAYS_INLINE texels16 row_texels16(__global const SOURCE_TYPE* source, int width, int height, int x0, int y,
                                   uint scale) {
    if (y >= height) return zero_texels16();
    const size_t first = (size_t)y * (size_t)width + (size_t)x0;
    if (x0 + LANES <= width) return full_texels16(source, first, scale);
    // Right edge: texel by texel into a private row, zero beyond the map.
    uint lanes[4 * LANES];
    for (int i = 0; i < LANES; ++i) {
        msm_sat_sum t = msm_sat_sum_zero();
        if (x0 + i < width) t = single_texel(source, first + (size_t)i, scale);
        MSM_STORE4(lanes, LANES, i, t.c0, t.c1, t.c2, t.c3);
    }
    texels16 t;
    t.c0 = vload16(0, lanes);
    t.c1 = vload16(1, lanes);
    t.c2 = vload16(2, lanes);
    t.c3 = vload16(3, lanes);
    return t;
}

// Inclusive prefix sums across the 16 lanes: 4 shift-and-add steps.
static inline uint16 lane_prefix(uint16 v) {
    const uint16 zero = (uint16)(0u);
    v += SHUFFLE2(zero, v, MASK_SHIFT_1);
    v += SHUFFLE2(zero, v, MASK_SHIFT_2);
    v += SHUFFLE2(zero, v, MASK_SHIFT_4);
    v += SHUFFLE2(zero, v, MASK_SHIFT_8);
    return v;
}

// The 64 words of 16 texels into row y of the table at x0, only the texels inside the map.
static inline void store_row(texels16 out, __global uint* table, int width, int x0, int y) {
    __global uint* words = table + 4 * ((size_t)y * (size_t)width + (size_t)x0);
    if (x0 + LANES <= width) {
        store_interleaved(out, words);
        return;
    }
    uint lanes[4 * LANES];
    vstore16(out.c0, 0, lanes);
    vstore16(out.c1, 1, lanes);
    vstore16(out.c2, 2, lanes);
    vstore16(out.c3, 3, lanes);
    for (int i = 0; i < width - x0; ++i) {
        msm_sat_sum texel;
        MSM_LOAD4(texel.c0, texel.c1, texel.c2, texel.c3, lanes, LANES, i);
        MSM_STORE4(words, 1, 4 * i, texel.c0, texel.c1, texel.c2, texel.c3);
    }
}

// Row y's texels of step 1 at x0 for the band scan to read back: planar for a full chunk,
// R,G,B,A per texel for the partial chunk at the right edge (as single_texel reads it).
static inline void store_step1_texels(texels16 t, __global uint* texels, int width, int x0, int y) {
    if (x0 + LANES <= width) {
        store_planar(t, texels + 4 * ((size_t)y * (size_t)width + (size_t)x0));
        return;
    }
    store_row(t, texels, width, x0, y);
}

// Step 1: one work-item per band (global size = bands): the sums of each column over the
// band's rows, planar per chunk of 16 columns, at band_totals[4 * band * padded_width + 64 *
// chunk] (padded_width = chunks * 16; columns beyond the map count as zero). With `texels`
// (a constant at each use), also each texel's integer values into `texels` (the table's
// buffer), for step 3 to scan in place.
ALWAYS_INLINE void accumulate_band_totals(__global const SOURCE_TYPE* source, int width, int height, uint scale,
                                         __global uint* band_totals, __global uint* texels) {
    // Texture arrays: this layer's input, band totals and texels (msm_array.clh).
    MSM_ARRAY_SLICE(source, MSM_SAT_SOURCE_ELEMENTS(width, height));
    MSM_ARRAY_SLICE(band_totals, 4 * (size_t)((height + BAND_H - 1) / BAND_H) * ((width + LANES - 1) / LANES) * LANES);
    if (texels) MSM_ARRAY_SLICE(texels, 4 * (size_t)width * height);
    const int band = (int)get_global_id(0);
    const int y0 = band * BAND_H;
    const int rows = min(BAND_H, height - y0);
    const int chunks = (width + LANES - 1) / LANES;
    __global uint* sums = band_totals + 4 * (size_t)band * (size_t)chunks * LANES;
    // Two rows a pass (one load and store of the sums per two rows of texels; a row below
    // the map reads as zero), the first pass setting the sums.
    for (int r = 0; r < rows; r += 2) {
        for (int chunk = 0; chunk < chunks; ++chunk) {
            const int x0 = chunk * LANES;
            const texels16 upper = row_texels16(source, width, height, x0, y0 + r, scale);
            const texels16 lower = row_texels16(source, width, height, x0, y0 + r + 1, scale);
            if (texels) {
                store_step1_texels(upper, texels, width, x0, y0 + r);
                if (r + 1 < rows) store_step1_texels(lower, texels, width, x0, y0 + r + 1);
            }
            __global uint* column = sums + 4 * LANES * (size_t)chunk;
            const texels16 pair = add_texels16(upper, lower);
            store_planar(r == 0 ? pair : add_texels16(load_planar(column), pair), column);
        }
    }
}

__kernel void sat_band_totals_cpu(__global const SOURCE_TYPE* source, int width, int height, uint scale,
                                  __global uint* band_totals) {
    accumulate_band_totals(source, width, height, scale, band_totals, 0);
}

#if MSM_SAT_SOURCE == 0
// Step 1 that also writes the integer texels of the depth map into `texels`: step 3 then
// reads them (16 bytes a texel) instead of resolving the depths a second time.
__kernel void sat_band_totals_texels_cpu(__global const float* source, int width, int height, uint scale,
                                         __global uint* band_totals, __global uint* texels) {
    accumulate_band_totals(source, width, height, scale, band_totals, texels);
}
#endif

// One row of the table from the column sums at its row, for 16 columns: lane scans plus the
// row's left carry (updated to this chunk's last lane), stored at (x0, y).
ALWAYS_INLINE void scan_chunk_row(texels16 column, texels16* left, __global uint* table, int width, int x0,
                                  int y) {
    texels16 out;
    out.c0 = lane_prefix(column.c0) + left->c0;
    out.c1 = lane_prefix(column.c1) + left->c1;
    out.c2 = lane_prefix(column.c2) + left->c2;
    out.c3 = lane_prefix(column.c3) + left->c3;
    left->c0 = SHUFFLE2(out.c0, out.c0, MASK_LAST);
    left->c1 = SHUFFLE2(out.c1, out.c1, MASK_LAST);
    left->c2 = SHUFFLE2(out.c2, out.c2, MASK_LAST);
    left->c3 = SHUFFLE2(out.c3, out.c3, MASK_LAST);
    store_row(out, table, width, x0, y);
}

// Step 3: one work-item per band, two rows at a time, each pair chunk by chunk from the
// left: the column sums (from the band's carries: the sums of every row above the band)
// plus each row's texels, lane scans plus the row's left carry, one write per texel.
__kernel void sat_band_scan_cpu(__global const SOURCE_TYPE* source, int width, int height, uint scale,
                                __global uint* column_carries, __global uint* table) {
    // Texture arrays: this layer's input, carries and table (msm_array.clh).
    MSM_ARRAY_SLICE(source, MSM_SAT_SOURCE_ELEMENTS(width, height));
    MSM_ARRAY_SLICE(column_carries, 4 * (size_t)((height + BAND_H - 1) / BAND_H) * ((width + LANES - 1) / LANES) * LANES);
    MSM_ARRAY_SLICE(table, 4 * (size_t)width * height);
    const int band = (int)get_global_id(0);
    const int y0 = band * BAND_H;
    const int rows = min(BAND_H, height - y0);
    const int chunks = (width + LANES - 1) / LANES;
    __global uint* sums = column_carries + 4 * (size_t)band * (size_t)chunks * LANES;
    for (int r = 0; r < rows; r += 2) {
        const bool lower_in_map = r + 1 < rows;
        // The table just left of the current chunk in both rows, per channel, in every lane
        // (a vector broadcast of lane 15: a scalar there costs element moves every chunk).
        texels16 upper_left = zero_texels16(), lower_left = zero_texels16();
        for (int chunk = 0; chunk < chunks; ++chunk) {
            const int x0 = chunk * LANES;
            __global uint* column_at = sums + 4 * LANES * (size_t)chunk;
            const texels16 upper =
                add_texels16(load_planar(column_at), row_texels16(source, width, height, x0, y0 + r, scale));
            scan_chunk_row(upper, &upper_left, table, width, x0, y0 + r);
            if (lower_in_map) {
                const texels16 lower =
                    add_texels16(upper, row_texels16(source, width, height, x0, y0 + r + 1, scale));
                scan_chunk_row(lower, &lower_left, table, width, x0, y0 + r + 1);
                store_planar(lower, column_at);
            } else {
                store_planar(upper, column_at);
            }
        }
    }
}
