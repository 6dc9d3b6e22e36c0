// Carries between the tiles of a summed-area table (step 2 of sat_build.cl and
// sat_build_cpu.cl): exclusive prefix sums of the per-tile totals across tiles. Layouts
// (4 uints per entry, any tile size):
//   column_totals[ty * padded_width + x]     sum of column x within tile row ty
//   row_totals[tx * padded_height + y]       sum of row y within tile column tx
//   tile_totals / corner_carries[ty * tiles_x + tx]
// One work-item per column, row or tile column; accesses are consecutive across
// work-items. MSM_ARRAY 1: texture arrays, the third NDRange dimension is the layer
// (msm_array.clh).
#include "msm_array.clh"

// One work-item per column x: column_totals -> the sum of column x above each tile
// row (exclusive prefix over tile rows), in place.
__kernel void sat_column_carries(__global uint* column_totals, int padded_width, int tiles_y) {
    MSM_ARRAY_SLICE_ANY_GROUP(column_totals, 4 * (size_t)padded_width * tiles_y);
    const size_t x = get_global_id(0);
    if (x >= (size_t)padded_width) return;
    uint s0 = 0u, s1 = 0u, s2 = 0u, s3 = 0u;
    for (int ty = 0; ty < tiles_y; ++ty) {
        const size_t at = 4 * ((size_t)ty * (size_t)padded_width + x);
        const uint t0 = column_totals[at + 0], t1 = column_totals[at + 1];
        const uint t2 = column_totals[at + 2], t3 = column_totals[at + 3];
        column_totals[at + 0] = s0;
        column_totals[at + 1] = s1;
        column_totals[at + 2] = s2;
        column_totals[at + 3] = s3;
        s0 += t0;
        s1 += t1;
        s2 += t2;
        s3 += t3;
    }
}

// One work-item per row y: row_totals -> the sum of row y left of each tile column
// (exclusive prefix over tile columns), in place.
__kernel void sat_row_carries(__global uint* row_totals, int padded_height, int tiles_x) {
    MSM_ARRAY_SLICE_ANY_GROUP(row_totals, 4 * (size_t)padded_height * tiles_x);
    const size_t y = get_global_id(0);
    if (y >= (size_t)padded_height) return;
    uint s0 = 0u, s1 = 0u, s2 = 0u, s3 = 0u;
    for (int tx = 0; tx < tiles_x; ++tx) {
        const size_t at = 4 * ((size_t)tx * (size_t)padded_height + y);
        const uint t0 = row_totals[at + 0], t1 = row_totals[at + 1];
        const uint t2 = row_totals[at + 2], t3 = row_totals[at + 3];
        row_totals[at + 0] = s0;
        row_totals[at + 1] = s1;
        row_totals[at + 2] = s2;
        row_totals[at + 3] = s3;
        s0 += t0;
        s1 += t1;
        s2 += t2;
        s3 += t3;
    }
}

// One work-item per tile column tx: corner_carries[(ty * tiles_x + tx)] = sum of
// all tiles above and to the left, (tx', ty') < (tx, ty).
__kernel void sat_corner_carries(__global const uint* tile_totals, int tiles_x, int tiles_y,
                                 __global uint* corner_carries) {
    MSM_ARRAY_SLICE_ANY_GROUP(tile_totals, 4 * (size_t)tiles_x * tiles_y);
    MSM_ARRAY_SLICE_ANY_GROUP(corner_carries, 4 * (size_t)tiles_x * tiles_y);
    const size_t tx = get_global_id(0);
    if (tx >= (size_t)tiles_x) return;
    uint s0 = 0u, s1 = 0u, s2 = 0u, s3 = 0u;
    for (int ty = 0; ty < tiles_y; ++ty) {
        const size_t out = 4 * ((size_t)ty * (size_t)tiles_x + tx);
        corner_carries[out + 0] = s0;
        corner_carries[out + 1] = s1;
        corner_carries[out + 2] = s2;
        corner_carries[out + 3] = s3;
        for (size_t left = 0; left < tx; ++left) {
            const size_t at = 4 * ((size_t)ty * (size_t)tiles_x + left);
            s0 += tile_totals[at + 0];
            s1 += tile_totals[at + 1];
            s2 += tile_totals[at + 2];
            s3 += tile_totals[at + 3];
        }
    }
}

