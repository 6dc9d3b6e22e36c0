// Summed-area table for CPU devices: the same table as sat_build.cl (same bits), distributed
// for a CPU. PoCL vectorizes scalar code across work-items only inside one stretch between
// barriers, and a scan needs values to cross lanes; here each work-item owns one band of
// MSM_SAT_BAND_H full rows and walks it left to right, 16 columns at a time in 16-lane
// vectors, so no barrier or local memory is needed and every row is read front to back:
//   column walks: a running uint16 per channel and column chunk (one add per texel),
//   row scans:    4 shuffle-and-add steps across the 16 lanes, plus the row's left carry
//                 (the last lane of the chunk before, kept per row of the band),
//   layout:       16 texels are 16 * S contiguous depths (or 64 contiguous words): loaded
//                 with vload16 and de-interleaved by log2(S) levels of shuffles; the output
//                 row is re-interleaved to R,G,B,A words and stored with 4 vstore16.
// Three steps: band totals (the column sums of each band), the carries down the bands
// (sat_column_carries in sat_carries.cl), the band scan. Every input is read twice and the
// table written once (for depth maps of many samples, step 1 writes the integer texels into
// the table and the scan reads them back in place: sat_band_totals_texels_cpu); no carries
// across columns are needed, as a band spans the width.
// The vector arithmetic mirrors msm_sat_texel_of_depth (msm_sat.clh) operation by
// operation, so both builds give identical bits (tests/sat_test.cpp checks it).
// Compile-time: MSM_SAT_SOURCE (0 depth with MSM_SAMPLES, MSM_DEPTH_ZERO_ONE; 1 texels),
// MSM_SAT_BAND_H (rows per band).
#include "msm_sat.clh"

#define LANES 16
#define BAND_H MSM_SAT_BAND_H

// Lane masks of shuffle2 over the 32 lanes (a, b).
#define MASK_EVEN (uint16)(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30)
#define MASK_ODD (uint16)(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31)
#define MASK_ZIP_LO (uint16)(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23)
#define MASK_ZIP_HI (uint16)(8, 24, 9, 25, 10, 26, 11, 27, 12, 28, 13, 29, 14, 30, 15, 31)
#define MASK_PAIRS_LO (uint16)(0, 1, 16, 17, 2, 3, 18, 19, 4, 5, 20, 21, 6, 7, 22, 23)
#define MASK_PAIRS_HI (uint16)(8, 9, 24, 25, 10, 11, 26, 27, 12, 13, 28, 29, 14, 15, 30, 31)

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
            w[i] = shuffle2(v[2 * i], v[2 * i + 1], MASK_EVEN);                           \
            w[(n) / 2 + i] = shuffle2(v[2 * i], v[2 * i + 1], MASK_ODD);                  \
        }                                                                                 \
        _Pragma("unroll") for (int i = 0; i < (n); ++i) v[i] = w[i];                      \
    }

// msm_internal_depth for 16 depths.
static inline float16 internal_depth16(float16 d) {
    float16 z = MSM_DEPTH_ZERO_ONE ? 2.0f * d - 1.0f : d;
    const int16 nan = (as_int16(z) & 0x7fffffff) > 0x7f800000;
    return select(clamp(z, -1.0f, 1.0f), (float16)(-1.0f), nan);
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
    v[0] = vload16(0, words);
    v[1] = vload16(1, words);
    v[2] = vload16(2, words);
    v[3] = vload16(3, words);
    DEINTERLEAVE(uint16, v, 4)
    texels16 t;
    t.c0 = v[0];
    t.c1 = v[1];
    t.c2 = v[2];
    t.c3 = v[3];
    return t;
}

// The 64 words of 16 texels, R, G, B, A per texel.
static inline void store_interleaved(texels16 t, __global uint* words) {
    const uint16 rg_lo = shuffle2(t.c0, t.c1, MASK_ZIP_LO);
    const uint16 rg_hi = shuffle2(t.c0, t.c1, MASK_ZIP_HI);
    const uint16 ba_lo = shuffle2(t.c2, t.c3, MASK_ZIP_LO);
    const uint16 ba_hi = shuffle2(t.c2, t.c3, MASK_ZIP_HI);
    vstore16(shuffle2(rg_lo, ba_lo, MASK_PAIRS_LO), 0, words);
    vstore16(shuffle2(rg_lo, ba_lo, MASK_PAIRS_HI), 1, words);
    vstore16(shuffle2(rg_hi, ba_hi, MASK_PAIRS_LO), 2, words);
    vstore16(shuffle2(rg_hi, ba_hi, MASK_PAIRS_HI), 3, words);
}

#if MSM_SAT_SOURCE == 0
#define SOURCE_TYPE float

// Integer texels of 16 whole texels starting at `first` (msm_sat_texel_of_depth per lane).
static inline texels16 full_texels16(__global const float* depth, size_t first, uint scale) {
    float16 d[MSM_SAMPLES];
    __global const float* p = depth + first * MSM_SAMPLES;
#pragma unroll
    for (int k = 0; k < MSM_SAMPLES; ++k) d[k] = vload16(k, p);
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

static inline texels16 full_texels16(__global const uint* texels, size_t first, uint scale) {
    (void)scale;
    return deinterleave_words(texels + 4 * first);
}

static inline msm_sat_sum single_texel(__global const uint* texels, size_t texel, uint scale) {
    (void)scale;
    msm_sat_sum t;
    t.c0 = texels[4 * texel + 0];
    t.c1 = texels[4 * texel + 1];
    t.c2 = texels[4 * texel + 2];
    t.c3 = texels[4 * texel + 3];
    return t;
}
#endif

// Row y of the chunk at x0: the 16 texels, zero beyond the map.
static inline texels16 row_texels16(__global const SOURCE_TYPE* source, int width, int height, int x0, int y,
                                    uint scale) {
    if (y >= height) return zero_texels16();
    const size_t first = (size_t)y * (size_t)width + (size_t)x0;
    if (x0 + LANES <= width) return full_texels16(source, first, scale);
    // Right edge: texel by texel into a private row, zero beyond the map.
    uint lanes[4 * LANES];
    for (int i = 0; i < LANES; ++i) {
        msm_sat_sum t = msm_sat_sum_zero();
        if (x0 + i < width) t = single_texel(source, first + (size_t)i, scale);
        lanes[i] = t.c0;
        lanes[LANES + i] = t.c1;
        lanes[2 * LANES + i] = t.c2;
        lanes[3 * LANES + i] = t.c3;
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
    v += shuffle2(zero, v, (uint16)(0, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30));
    v += shuffle2(zero, v, (uint16)(0, 1, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29));
    v += shuffle2(zero, v, (uint16)(0, 1, 2, 3, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27));
    v += shuffle2(zero, v, (uint16)(0, 1, 2, 3, 4, 5, 6, 7, 16, 17, 18, 19, 20, 21, 22, 23));
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
        words[4 * i + 0] = lanes[i];
        words[4 * i + 1] = lanes[LANES + i];
        words[4 * i + 2] = lanes[2 * LANES + i];
        words[4 * i + 3] = lanes[3 * LANES + i];
    }
}

// Step 1: one work-item per band (global size = bands): the sums of each column over the
// band's rows, 4 words per column, at band_totals[band * padded_width + x] (padded_width =
// chunks * 16; rows and columns beyond the map count as zero). With `texels` (a constant
// at each use), also each texel's integer values into `texels` (the table's buffer), for
// step 3 to scan in place.
static inline __attribute__((always_inline)) void accumulate_band_totals(__global const SOURCE_TYPE* source, int width,
                                                              int height, uint scale, __global uint* band_totals,
                                                              __global uint* texels) {
    const int band = (int)get_global_id(0);
    const int y0 = band * BAND_H;
    const int chunks = (width + LANES - 1) / LANES;
    for (int chunk = 0; chunk < chunks; ++chunk) {
        const int x0 = chunk * LANES;
        // Down the band's rows of this chunk: BAND_H read streams advancing together.
        texels16 column = zero_texels16();
        for (int r = 0; r < BAND_H; ++r) {
            const texels16 t = row_texels16(source, width, height, x0, y0 + r, scale);
            column = add_texels16(column, t);
            if (texels && y0 + r < height) store_row(t, texels, width, x0, y0 + r);
        }
        store_interleaved(column, band_totals + 4 * ((size_t)band * (size_t)chunks * LANES + (size_t)x0));
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

// Step 3: one work-item per band, chunk by chunk from the left: column walks from the
// band's column carries (the sums of every row above the band), lane scans plus each row's
// left carry, one write per texel.
__kernel void sat_band_scan_cpu(__global const SOURCE_TYPE* source, int width, int height, uint scale,
                                __global const uint* column_carries, __global uint* table) {
    const int band = (int)get_global_id(0);
    const int y0 = band * BAND_H;
    const int rows = min(BAND_H, height - y0);
    const int chunks = (width + LANES - 1) / LANES;
    // The table just left of the current chunk, per row of the band and channel.
    uint left[4 * BAND_H];
    for (int i = 0; i < 4 * BAND_H; ++i) left[i] = 0u;
    for (int chunk = 0; chunk < chunks; ++chunk) {
        const int x0 = chunk * LANES;
        texels16 column =
            deinterleave_words(column_carries + 4 * ((size_t)band * (size_t)chunks * LANES + (size_t)x0));
        for (int r = 0; r < rows; ++r) {
            const texels16 t = row_texels16(source, width, height, x0, y0 + r, scale);
            column = add_texels16(column, t);
            texels16 out;
            out.c0 = lane_prefix(column.c0) + left[4 * r + 0];
            out.c1 = lane_prefix(column.c1) + left[4 * r + 1];
            out.c2 = lane_prefix(column.c2) + left[4 * r + 2];
            out.c3 = lane_prefix(column.c3) + left[4 * r + 3];
            left[4 * r + 0] = out.c0.sf;
            left[4 * r + 1] = out.c1.sf;
            left[4 * r + 2] = out.c2.sf;
            left[4 * r + 3] = out.c3.sf;
            store_row(out, table, width, x0, y0 + r);
        }
    }
}
