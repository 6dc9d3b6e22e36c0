// Integer modular summed-area table (docs/math.md): input texels -> uint32 channels ->
// prefix sums in x and y, wrapping mod 2^32 (any order of additions gives the same bits).
//
// Tiled scan for GPUs (work-efficient: every texel is added once per direction, plus
// carries of 1/TILE of the texels), three steps with small carry arrays between them:
//   1. sat_tile_totals: per TILE x TILE tile, column totals, row totals and the tile total.
//   2. sat_carries.cl: exclusive prefix sums of those totals across tiles (what lies above,
//      to the left, and above-left of a tile).
//   3. sat_tile_scan: per tile, the texels again, scanned down the columns starting from the
//      column carries, then along the rows starting from the left carries, written once.
// Every input texel is read twice (steps 1 and 3) and every table texel written once.
// Work-item layout: one work-item per tile column; the tile goes through local memory one
// strip of TILE/4 rows at a time: column walks go down the strip in registers (coalesced
// loads), then each work-item walks one row of one channel of the strip (4 channels x
// TILE/4 rows = TILE walkers), in a rotated layout where both walks hit distinct banks.
// No work-group waits for another. sat_build_cpu.cl is the same algorithm for CPUs.
// Baseline (one thread per row, as in Peters et al., i3D 2016): sat_rows_per_thread then
// sat_columns_per_thread.
//
// Compile-time: MSM_SAT_SOURCE 0 = depth map (MSM_SAMPLES, MSM_DEPTH_ZERO_ONE; moments
// quantized with `scale`), 1 = ready integer texels (4 uints per texel); MSM_SAT_TILE;
// MSM_ARRAY (1: texture arrays, the NDRange's third dimension is the layer, msm_array.clh).
#include "msm_sat.clh"
#include "msm_array.clh"

#ifndef MSM_SAT_TILE
#define MSM_SAT_TILE 32
#endif
#define TILE MSM_SAT_TILE
// A tile is scanned in strips of STRIP rows: 4 channels x STRIP rows give one row walker per
// work-item, and local memory holds one strip (4 KiB for TILE 32: 16 groups of 32 in a
// 64 KiB compute unit).
#define STRIP (TILE / 4)
#define STRIP_WORDS (4 * STRIP * TILE)
#if TILE % 4 != 0
#error "MSM_SAT_TILE must be a multiple of 4"
#endif
// Word of channel c, strip row r, tile column x, rotated by r + STRIP c within its row: column
// walks (fixed c and r, x across the work-items) and row walks (fixed x, r + STRIP c across
// the work-items) both touch TILE distinct banks, with no padding.
#define STRIP_INDEX(c, r, x) (((c) * STRIP + (r)) * TILE + (((x) + (r) + STRIP * (c)) % TILE))

#if MSM_SAT_SOURCE == 0
#define SOURCE_TYPE float
#else
#define SOURCE_TYPE uint
#endif

// Integer texel (x, y) of the input; zero outside the map.
static inline __attribute__((always_inline)) msm_sat_sum source_texel(__global const SOURCE_TYPE* source, int width, int height, int x, int y,
                                       uint scale) {
    if (x >= width || y >= height) return msm_sat_sum_zero();
    const size_t texel = (size_t)y * (size_t)width + (size_t)x;
#if MSM_SAT_SOURCE == 0
    return msm_sat_texel_of_depth(source, texel, MSM_SAMPLES, MSM_DEPTH_ZERO_ONE, scale);
#else
    msm_sat_sum t;
    MSM_LOAD4(t.c0, t.c1, t.c2, t.c3, source, 1, 4 * texel);
    return t;
#endif
}

// Step 1. Carry layouts (4 uints per entry):
//   column_totals[(tile_y * padded_width + x)]   sum of column x within tile row tile_y
//   row_totals[(tile_x * padded_height + y)]     sum of row y within tile column tile_x
//   tile_totals[(tile_y * tiles_x + tile_x)]     sum of the tile
__kernel __attribute__((reqd_work_group_size(TILE, 1, 1)))
void sat_tile_totals(__global const SOURCE_TYPE* source, int width, int height, uint scale,
                     __global uint* column_totals, __global uint* row_totals, __global uint* tile_totals) {
    __local uint strip[STRIP_WORDS];
    // Texture arrays: this layer's input and carries (msm_array.clh).
    MSM_ARRAY_SLICE(source, MSM_SAT_SOURCE_ELEMENTS(width, height));
    MSM_ARRAY_SLICE(column_totals, 4 * get_num_groups(0) * TILE * get_num_groups(1));
    MSM_ARRAY_SLICE(row_totals, 4 * get_num_groups(0) * get_num_groups(1) * TILE);
    MSM_ARRAY_SLICE(tile_totals, 4 * get_num_groups(0) * get_num_groups(1));
    const uint lx = (uint)get_local_id(0);
    const size_t x = get_group_id(0) * TILE + lx;
    const int y0 = (int)(get_group_id(1) * TILE);
    // Row walker of this work-item: one row and one channel of each strip.
    const uint walk_row = lx % STRIP, walk_channel = lx / STRIP;
    const size_t rows_at = 4 * (get_group_id(0) * get_num_groups(1) * TILE + (size_t)y0);
    uint c0 = 0u, c1 = 0u, c2 = 0u, c3 = 0u;
    uint tile_part = 0u;
    // Loops over strips and rows stay loops: unrolled, the compiler hoists every load of the
    // tile (gfx90a: 183 VGPRs, 2 waves per SIMD); row walks unroll by 8.
#pragma unroll 1
    for (int strip0 = 0; strip0 < TILE; strip0 += STRIP) {
        // Each work-item walks its column through the strip: column total, texels into local memory.
#pragma unroll 1
        for (uint r = 0; r < STRIP; ++r) {
            const msm_sat_sum t = source_texel(source, width, height, (int)x, y0 + strip0 + (int)r, scale);
            c0 += t.c0;
            c1 += t.c1;
            c2 += t.c2;
            c3 += t.c3;
            strip[STRIP_INDEX(0u, r, lx)] = t.c0;
            strip[STRIP_INDEX(1u, r, lx)] = t.c1;
            strip[STRIP_INDEX(2u, r, lx)] = t.c2;
            strip[STRIP_INDEX(3u, r, lx)] = t.c3;
        }
        barrier(CLK_LOCAL_MEM_FENCE);
        // Each work-item sums its row and channel of the strip.
        uint sum = 0u;
#pragma unroll 8
        for (uint i = 0; i < TILE; ++i) sum += strip[STRIP_INDEX(walk_channel, walk_row, i)];
        row_totals[rows_at + 4 * (size_t)(strip0 + (int)walk_row) + walk_channel] = sum;
        tile_part += sum;
        // The next strip overwrites what the row walks read.
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    const size_t at = 4 * (get_group_id(1) * get_num_groups(0) * TILE + x);
    column_totals[at + 0] = c0;
    column_totals[at + 1] = c1;
    column_totals[at + 2] = c2;
    column_totals[at + 3] = c3;

    // The tile total per channel: the sums of its STRIP row walkers.
    strip[lx] = tile_part;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lx < 4u) {
        uint total = 0u;
        for (uint r = 0; r < STRIP; ++r) total += strip[lx * STRIP + r];
        tile_totals[4 * (get_group_id(1) * get_num_groups(0) + get_group_id(0)) + lx] = total;
    }
}

// Step 3. The table: S(x, y) = E(y) + sum over columns x' <= x of V(x', y), where V is the
// column prefix sum from the column carry and E(y) = corner + the left carries of rows
// <= y (the table just left of the tile).
__kernel __attribute__((reqd_work_group_size(TILE, 1, 1)))
void sat_tile_scan(__global const SOURCE_TYPE* source, int width, int height, uint scale,
                   __global const uint* column_carries, __global const uint* row_carries,
                   __global const uint* corner_carries, __global uint* table) {
    __local uint strip[STRIP_WORDS];
    // Texture arrays: this layer's input, carries and table (msm_array.clh).
    MSM_ARRAY_SLICE(source, MSM_SAT_SOURCE_ELEMENTS(width, height));
    MSM_ARRAY_SLICE(column_carries, 4 * get_num_groups(0) * TILE * get_num_groups(1));
    MSM_ARRAY_SLICE(row_carries, 4 * get_num_groups(0) * get_num_groups(1) * TILE);
    MSM_ARRAY_SLICE(corner_carries, 4 * get_num_groups(0) * get_num_groups(1));
    MSM_ARRAY_SLICE(table, 4 * (size_t)width * height);
    const uint lx = (uint)get_local_id(0);
    const size_t x = get_group_id(0) * TILE + lx;
    const int y0 = (int)(get_group_id(1) * TILE);
    // Column walker state: V of this work-item's column, from its carry.
    const size_t carry = 4 * (get_group_id(1) * get_num_groups(0) * TILE + x);
    uint v0 = column_carries[carry + 0], v1 = column_carries[carry + 1];
    uint v2 = column_carries[carry + 2], v3 = column_carries[carry + 3];
    // Row walker state: E of its channel above the current strip.
    const uint walk_row = lx % STRIP, walk_channel = lx / STRIP;
    uint left_above = corner_carries[4 * (get_group_id(1) * get_num_groups(0) + get_group_id(0)) + walk_channel];
    const size_t rows_at = 4 * (get_group_id(0) * get_num_groups(1) * TILE + (size_t)y0);
#pragma unroll 1
    for (int strip0 = 0; strip0 < TILE; strip0 += STRIP) {
        // Each work-item walks its column through the strip: V into local memory.
#pragma unroll 1
        for (uint r = 0; r < STRIP; ++r) {
            const msm_sat_sum t = source_texel(source, width, height, (int)x, y0 + strip0 + (int)r, scale);
            v0 += t.c0;
            v1 += t.c1;
            v2 += t.c2;
            v3 += t.c3;
            strip[STRIP_INDEX(0u, r, lx)] = v0;
            strip[STRIP_INDEX(1u, r, lx)] = v1;
            strip[STRIP_INDEX(2u, r, lx)] = v2;
            strip[STRIP_INDEX(3u, r, lx)] = v3;
        }
        barrier(CLK_LOCAL_MEM_FENCE);

        // Each work-item walks its row and channel from E(y), in place; E from the left
        // carries of the strip's rows (its own and those above it).
        uint h = left_above;
        for (uint r = 0; r < STRIP; ++r) {
            const uint left_carry = row_carries[rows_at + 4 * (size_t)(strip0 + (int)r) + walk_channel];
            h += r <= walk_row ? left_carry : 0u;
            left_above += left_carry;
        }
#pragma unroll 8
        for (uint i = 0; i < TILE; ++i) {
            h += strip[STRIP_INDEX(walk_channel, walk_row, i)];
            strip[STRIP_INDEX(walk_channel, walk_row, i)] = h;
        }
        barrier(CLK_LOCAL_MEM_FENCE);

        // Each work-item writes its column of the strip (4 consecutive uints per texel). The
        // next column walk overwrites only these same words of its own column: no barrier.
        if (x < (size_t)width) {
            for (uint r = 0; r < STRIP; ++r) {
                const size_t y = (size_t)(y0 + strip0) + r;
                if (y >= (size_t)height) break;
                const size_t at = 4 * (y * (size_t)width + x);
                table[at + 0] = strip[STRIP_INDEX(0u, r, lx)];
                table[at + 1] = strip[STRIP_INDEX(1u, r, lx)];
                table[at + 2] = strip[STRIP_INDEX(2u, r, lx)];
                table[at + 3] = strip[STRIP_INDEX(3u, r, lx)];
            }
        }
    }
}

// Baseline, horizontal: one work-item per row, texels converted on the fly (Peters et al., i3D 2016).
__kernel void sat_rows_per_thread(__global const SOURCE_TYPE* source, int width, int height, uint scale,
                                  __global uint* table) {
    MSM_ARRAY_SLICE_ANY_GROUP(source, MSM_SAT_SOURCE_ELEMENTS(width, height));
    MSM_ARRAY_SLICE_ANY_GROUP(table, 4 * (size_t)width * height);
    const size_t y = get_global_id(0);
    if (y >= (size_t)height) return;
    uint s0 = 0u, s1 = 0u, s2 = 0u, s3 = 0u;
    for (int x = 0; x < width; ++x) {
        const msm_sat_sum t = source_texel(source, width, height, x, (int)y, scale);
        s0 += t.c0;
        s1 += t.c1;
        s2 += t.c2;
        s3 += t.c3;
        const size_t at = 4 * (y * (size_t)width + (size_t)x);
        table[at + 0] = s0;
        table[at + 1] = s1;
        table[at + 2] = s2;
        table[at + 3] = s3;
    }
}

// Baseline, vertical: one work-item per column, in place.
__kernel void sat_columns_per_thread(__global uint* table, int width, int height) {
    MSM_ARRAY_SLICE_ANY_GROUP(table, 4 * (size_t)width * height);
    const size_t x = get_global_id(0);
    if (x >= (size_t)width) return;
    uint s0 = 0u, s1 = 0u, s2 = 0u, s3 = 0u;
    for (int y = 0; y < height; ++y) {
        const size_t at = 4 * ((size_t)y * (size_t)width + x);
        s0 += table[at + 0];
        s1 += table[at + 1];
        s2 += table[at + 2];
        s3 += table[at + 3];
        table[at + 0] = s0;
        table[at + 1] = s1;
        table[at + 2] = s2;
        table[at + 3] = s3;
    }
}
