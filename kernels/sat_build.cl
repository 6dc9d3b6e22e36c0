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
// Work-item layout: one work-item per tile column; column walks go down in registers
// (coalesced loads), row walks run in local memory with a padded pitch (one work-item per
// row, distinct banks). sat_build_cpu.cl is the same algorithm for CPUs.
// Baseline (one thread per row, as in Peters et al., i3D 2016): sat_rows_per_thread then
// sat_columns_per_thread.
//
// Compile-time: MSM_SAT_SOURCE 0 = depth map (MSM_SAMPLES, MSM_DEPTH_ZERO_ONE; moments
// quantized with `scale`), 1 = ready integer texels (4 uints per texel); MSM_SAT_TILE.
#include "msm_sat.clh"

#ifndef MSM_SAT_TILE
#define MSM_SAT_TILE 32
#endif
#define TILE MSM_SAT_TILE
// Row pitch of the local tile: row walks (one work-item per row) hit distinct banks.
#define PITCH (TILE + 1)
#define PLANE (TILE * PITCH)

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
    t.c0 = source[4 * texel + 0];
    t.c1 = source[4 * texel + 1];
    t.c2 = source[4 * texel + 2];
    t.c3 = source[4 * texel + 3];
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
    __local uint texels[4 * PLANE];
    __local uint rows[4 * TILE];

    // Each work-item walks its column of the tile: column total, texels into local memory.
    {
        const size_t lx = get_local_id(0);
        const size_t x = get_group_id(0) * TILE + lx;
        const int y0 = (int)(get_group_id(1) * TILE);
        uint c0 = 0u, c1 = 0u, c2 = 0u, c3 = 0u;
        for (int j = 0; j < TILE; ++j) {
            const msm_sat_sum t = source_texel(source, width, height, (int)x, y0 + j, scale);
            c0 += t.c0;
            c1 += t.c1;
            c2 += t.c2;
            c3 += t.c3;
            texels[0 * PLANE + j * PITCH + lx] = t.c0;
            texels[1 * PLANE + j * PITCH + lx] = t.c1;
            texels[2 * PLANE + j * PITCH + lx] = t.c2;
            texels[3 * PLANE + j * PITCH + lx] = t.c3;
        }
        const size_t at = 4 * (get_group_id(1) * get_num_groups(0) * TILE + x);
        column_totals[at + 0] = c0;
        column_totals[at + 1] = c1;
        column_totals[at + 2] = c2;
        column_totals[at + 3] = c3;
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    // Work-item j sums row j of the tile.
    {
        const size_t j = get_local_id(0);
        uint r0 = 0u, r1 = 0u, r2 = 0u, r3 = 0u;
        for (int i = 0; i < TILE; ++i) {
            r0 += texels[0 * PLANE + j * PITCH + i];
            r1 += texels[1 * PLANE + j * PITCH + i];
            r2 += texels[2 * PLANE + j * PITCH + i];
            r3 += texels[3 * PLANE + j * PITCH + i];
        }
        const size_t at = 4 * (get_group_id(0) * get_num_groups(1) * TILE + get_group_id(1) * TILE + j);
        row_totals[at + 0] = r0;
        row_totals[at + 1] = r1;
        row_totals[at + 2] = r2;
        row_totals[at + 3] = r3;
        rows[0 * TILE + j] = r0;
        rows[1 * TILE + j] = r1;
        rows[2 * TILE + j] = r2;
        rows[3 * TILE + j] = r3;
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    // One work-item adds up the row totals.
    if (get_local_id(0) == 0) {
        uint t0 = 0u, t1 = 0u, t2 = 0u, t3 = 0u;
        for (int j = 0; j < TILE; ++j) {
            t0 += rows[0 * TILE + j];
            t1 += rows[1 * TILE + j];
            t2 += rows[2 * TILE + j];
            t3 += rows[3 * TILE + j];
        }
        const size_t at = 4 * (get_group_id(1) * get_num_groups(0) + get_group_id(0));
        tile_totals[at + 0] = t0;
        tile_totals[at + 1] = t1;
        tile_totals[at + 2] = t2;
        tile_totals[at + 3] = t3;
    }
}

// Step 3. The table: S(x, y) = corner + (left carries of rows <= y) + (column carries of
// columns <= x) + the tile's own 2D prefix sum.
__kernel __attribute__((reqd_work_group_size(TILE, 1, 1)))
void sat_tile_scan(__global const SOURCE_TYPE* source, int width, int height, uint scale,
                   __global const uint* column_carries, __global const uint* row_carries,
                   __global const uint* corner_carries, __global uint* table) {
    __local uint sums[4 * PLANE];
    __local uint left[4 * TILE];

    // One work-item: the table just left of the tile, E(j) = corner + sum_{j' <= j} row carry.
    if (get_local_id(0) == 0) {
        const size_t corner = 4 * (get_group_id(1) * get_num_groups(0) + get_group_id(0));
        uint e0 = corner_carries[corner + 0], e1 = corner_carries[corner + 1];
        uint e2 = corner_carries[corner + 2], e3 = corner_carries[corner + 3];
        const size_t first = get_group_id(0) * get_num_groups(1) * TILE + get_group_id(1) * TILE;
        for (int j = 0; j < TILE; ++j) {
            const size_t at = 4 * (first + (size_t)j);
            e0 += row_carries[at + 0];
            e1 += row_carries[at + 1];
            e2 += row_carries[at + 2];
            e3 += row_carries[at + 3];
            left[0 * TILE + j] = e0;
            left[1 * TILE + j] = e1;
            left[2 * TILE + j] = e2;
            left[3 * TILE + j] = e3;
        }
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    // Each work-item walks its column: prefix sums from the column carry down.
    {
        const size_t lx = get_local_id(0);
        const size_t x = get_group_id(0) * TILE + lx;
        const int y0 = (int)(get_group_id(1) * TILE);
        const size_t carry = 4 * (get_group_id(1) * get_num_groups(0) * TILE + x);
        uint v0 = column_carries[carry + 0], v1 = column_carries[carry + 1];
        uint v2 = column_carries[carry + 2], v3 = column_carries[carry + 3];
        for (int j = 0; j < TILE; ++j) {
            const msm_sat_sum t = source_texel(source, width, height, (int)x, y0 + j, scale);
            v0 += t.c0;
            v1 += t.c1;
            v2 += t.c2;
            v3 += t.c3;
            sums[0 * PLANE + j * PITCH + lx] = v0;
            sums[1 * PLANE + j * PITCH + lx] = v1;
            sums[2 * PLANE + j * PITCH + lx] = v2;
            sums[3 * PLANE + j * PITCH + lx] = v3;
        }
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    // Work-item j walks row j: prefix sums from the left carry along the row.
    {
        const size_t j = get_local_id(0);
        uint h0 = left[0 * TILE + j], h1 = left[1 * TILE + j];
        uint h2 = left[2 * TILE + j], h3 = left[3 * TILE + j];
        for (int i = 0; i < TILE; ++i) {
            h0 += sums[0 * PLANE + j * PITCH + i];
            h1 += sums[1 * PLANE + j * PITCH + i];
            h2 += sums[2 * PLANE + j * PITCH + i];
            h3 += sums[3 * PLANE + j * PITCH + i];
            sums[0 * PLANE + j * PITCH + i] = h0;
            sums[1 * PLANE + j * PITCH + i] = h1;
            sums[2 * PLANE + j * PITCH + i] = h2;
            sums[3 * PLANE + j * PITCH + i] = h3;
        }
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    // Each work-item writes its column of the tile (4 consecutive uints per texel).
    {
        const size_t lx = get_local_id(0);
        const size_t x = get_group_id(0) * TILE + lx;
        const size_t y0 = get_group_id(1) * TILE;
        if (x < (size_t)width) {
            for (int j = 0; j < TILE; ++j) {
                const size_t y = y0 + (size_t)j;
                if (y >= (size_t)height) break;
                const size_t at = 4 * (y * (size_t)width + x);
                table[at + 0] = sums[0 * PLANE + j * PITCH + lx];
                table[at + 1] = sums[1 * PLANE + j * PITCH + lx];
                table[at + 2] = sums[2 * PLANE + j * PITCH + lx];
                table[at + 3] = sums[3 * PLANE + j * PITCH + lx];
            }
        }
    }
}

// Baseline, horizontal: one work-item per row, texels converted on the fly (Peters et al., i3D 2016).
__kernel void sat_rows_per_thread(__global const SOURCE_TYPE* source, int width, int height, uint scale,
                                  __global uint* table) {
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
