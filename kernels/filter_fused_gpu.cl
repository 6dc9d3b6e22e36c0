// The fused filter kernel of Peters, HPG 2017, section 4.1 (docs/kernels.md): one work-group of
// 256 work-items (8 sub-groups of 32) turns a 40x32 input block (output block 32x24 plus a
// guard band of 4) into 32x24 filtered, quantized texels, all in local memory:
// resolve -> horizontal 9-tap -> vertical 9-tap -> readout + quantize, one global write.
// Layout and work-item mapping: fused_layout.clh (verified bank-conflict free offline by
// tests/fused_layout_test.cpp). Local memory: FUSED_LOCAL_BYTES (moment planes, and the
// block shift's results for the nlq formats).
// Compile-time: MSM_SAMPLES (1, 2, 4, 8, 16), MSM_FORMAT and the format's row
// (msm_formats.clh), MSM_DEPTH_ZERO_ONE (1 for depth in [0,1]),
// MSM_LAYERS (translucent layers, 0 = opaque; two more arguments when > 0), MSM_ARRAY
// (1: texture arrays, group z = array layer, msm_array.clh), FUSED_WORK_ITEMS (below).
// Taps: w0 (centre) .. w4, as gaussian_taps() gives them; sums run over i = -4..4 with fma
// so that kernels/filter_three_pass.cl reproduces them bit for bit.
#include "msm_formats.clh"
#include "msm_translucent.clh"
#include "fused_layout.clh"
#include "msm_array.clh"

// Translucent layers (MSM_LAYERS > 0, docs/math.md): the resolve composites each sample's
// surfaces (msm_translucent.clh) instead of taking b(z); 0 compiles the opaque code alone.
#ifndef MSM_LAYERS
#define MSM_LAYERS 0
#endif

// Work-items of the launched group: FUSED_GROUP_SIZE (the paper's 256), or 128, 64 or 32
// for a device whose built kernel allows fewer (docs/devices.md). Each work-item then plays
// FUSED_ROLES of the layout's 256 roles in turn, role r as layout id local_id + r *
// FUSED_WORK_ITEMS: every texel sees the same operations in the same order (the same
// bits), and a sub-group of 32 roles stays within one role round.
#ifndef FUSED_WORK_ITEMS
#define FUSED_WORK_ITEMS FUSED_GROUP_SIZE
#endif
#define FUSED_ROLES (FUSED_GROUP_SIZE / FUSED_WORK_ITEMS)
#define FOR_EACH_ROLE(id) \
    for (uint role = 0, id = local_id; role < FUSED_ROLES; ++role, id += FUSED_WORK_ITEMS)

#if MSM_FORMAT_SHIFTED
// nlq formats: blur the moments of (z - c), c = the midrange of the depths of the block's
// input texels short of the far plane (docs/math.md): no rendered texel lies more than half
// the block's depth range from c.
#define FILTER_SHIFTED 1
#else
#define FILTER_SHIFTED 0
#endif

// 9-tap sum of v[0..8] with weights w4 w3 w2 w1 w0 w1 w2 w3 w4, in order i = -4..4.
#define FILTER_TAPS9(v, k)                                                                    \
    fma(w4, v[(k) + 8], fma(w3, v[(k) + 7], fma(w2, v[(k) + 6], fma(w1, v[(k) + 5],           \
    fma(w0, v[(k) + 4], fma(w1, v[(k) + 3], fma(w2, v[(k) + 2], fma(w3, v[(k) + 1],           \
    w4 * v[(k)]))))))))

__kernel __attribute__((reqd_work_group_size(FUSED_WORK_ITEMS, 1, 1)))
void filter_fused_gpu(__global const float* depth, int width, int height, __global uint* texture,
                      float w0, float w1, float w2, float w3, float w4
#if MSM_LAYERS
                      , __global const float* layer_depth, __global const float* layer_opacity
#endif
) {
    __local float block[FUSED_LOCAL_FLOATS];
#if FILTER_SHIFTED
    __local float shift_extremes[FUSED_SHIFT_FLOATS];
#endif
    // Texture arrays: this group's layer of the depth, the texture and the translucent layers.
    MSM_ARRAY_SLICE(depth, (size_t)width * height * MSM_SAMPLES);
    MSM_ARRAY_SLICE(texture, (size_t)width * height * MSM_TEXEL_WORDS);
#if MSM_LAYERS
    MSM_ARRAY_SLICE(layer_depth, (size_t)width * height * MSM_SAMPLES * MSM_LAYERS);
    MSM_ARRAY_SLICE(layer_opacity, (size_t)width * height * MSM_SAMPLES * MSM_LAYERS);
#endif
    const uint local_id = (uint)get_local_id(0);
    const int out_x0 = (int)get_group_id(0) * FUSED_OUT_W;
    const int out_y0 = (int)get_group_id(1) * FUSED_OUT_H;

#if FILTER_SHIFTED
    // Shift c = (min + max) / 2 of the internal depths z < 1 of sample 0 of the 40x32 input
    // texels, clamped into the image as the resolve clamps them (translucent layers: the opaque
    // depth); c = 1 where all are at 1. The far plane z = 1 (cleared depth, nothing rendered)
    // takes no part: it would pull c halfway away from the geometry, whose low-variance
    // texels lose the digits of xi4 with |z - c|^4 (railing 256^2, nearest nlq64 against
    // double: 269 receivers off by > 3% with it, 0 without). min and max are exact in any
    // order: c does not depend on the reduction's schedule. Empty sets are (1, -1), neutral
    // for min and max.
    // Step 1: min and max over each role's 5 resolve texels, into the moment planes.
    FOR_EACH_ROLE(id) {
        float lowest = 1.0f, highest = -1.0f;
        for (uint round = 0; round < FUSED_RESOLVE_ROUNDS; ++round) {
            const int gx = clamp(out_x0 - FUSED_GUARD + (int)fused_resolve_x(id, round), 0, width - 1);
            const int gy = clamp(out_y0 - FUSED_GUARD + (int)fused_resolve_y(id), 0, height - 1);
            const float z = msm_internal_depth(depth[((size_t)gy * width + gx) * MSM_SAMPLES], MSM_DEPTH_ZERO_ONE);
            if (z < 1.0f) {
                lowest = fmin(lowest, z);
                highest = fmax(highest, z);
            }
        }
        block[fused_shift_partial_index(0u, id)] = lowest;
        block[fused_shift_partial_index(1u, id)] = highest;
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    // Step 2: sub-group 0 alone (round 0), lanes 0..15 reduce the minima, 16..31 the maxima.
    if (local_id < FUSED_SUBGROUP) {
        const uint id = local_id;
        const bool is_max = id >= 16u;
        float extreme = block[fused_shift_step2_index(id, 0u)];
        for (uint k = 1; k < FUSED_SHIFT_STEP2_READS; ++k) {
            const float partial = block[fused_shift_step2_index(id, k)];
            extreme = is_max ? fmax(extreme, partial) : fmin(extreme, partial);
        }
        shift_extremes[id] = extreme;
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    // Every work-item: c from the 16 minima and the 16 maxima (the resolve may now overwrite
    // the partials; shift_extremes stays).
    float block_min = shift_extremes[0], block_max = shift_extremes[FUSED_SHIFT_FLOATS / 2];
    for (uint k = 1; k < FUSED_SHIFT_FLOATS / 2; ++k) {
        block_min = fmin(block_min, shift_extremes[k]);
        block_max = fmax(block_max, shift_extremes[FUSED_SHIFT_FLOATS / 2 + k]);
    }
    const float shift = block_min <= block_max ? (block_min + block_max) * 0.5f : 1.0f;
#else
    const float shift = 0.0f;
#endif

    // Phase 1, resolve: 5 rounds, one texel each; guard-band texels clamp to the image edge.
    FOR_EACH_ROLE(id)
    for (uint round = 0; round < FUSED_RESOLVE_ROUNDS; ++round) {
        const uint x = fused_resolve_x(id, round);
        const uint y = fused_resolve_y(id);
        const int gx = clamp(out_x0 - FUSED_GUARD + (int)x, 0, width - 1);
        const int gy = clamp(out_y0 - FUSED_GUARD + (int)y, 0, height - 1);
#if MSM_LAYERS
        const msm_moments m = msm_resolve_translucent_texel(depth, layer_depth, layer_opacity,
                                                            (size_t)width * height * MSM_SAMPLES, (size_t)gy * width + gx,
                                                            MSM_SAMPLES, MSM_LAYERS, MSM_DEPTH_ZERO_ONE, shift);
#else
        const msm_moments m = msm_resolve_texel(depth + ((size_t)gy * width + gx) * MSM_SAMPLES, MSM_SAMPLES,
                                                MSM_DEPTH_ZERO_ONE, shift);
#endif
        block[fused_local_index(1, x, y)] = m.b1;
        block[fused_local_index(2, x, y)] = m.b2;
        block[fused_local_index(3, x, y)] = m.b3;
        block[fused_local_index(4, x, y)] = m.b4;
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    // Phase 2, horizontal: one moment and one half per sub-group, one row per work-item;
    // 24 values in registers, 16 outputs written where no other work-item reads.
    FOR_EACH_ROLE(id) {
        const uint j = fused_blur_moment(id);
        const uint y = fused_row_y(id);
        const uint read_x = fused_row_read_x(id);
        const uint write_x = fused_row_write_x(id);
        // Fully unrolled: the arrays stay in registers (NVPTX keeps loops over them on the stack).
        float row[FUSED_ROW_READS];
#pragma unroll
        for (uint k = 0; k < FUSED_ROW_READS; ++k) row[k] = block[fused_local_index(j, read_x + k, y)];
#pragma unroll
        for (uint k = 0; k < FUSED_ROW_WRITES; ++k) block[fused_local_index(j, write_x + k, y)] = FILTER_TAPS9(row, k);
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    // Phase 3, vertical: the sub-group's 16x32 strip, upper and lower halves; 20 values in
    // registers, barrier (the halves overlap in rows 12..19), 12 outputs in place. Roles of
    // different rounds work on different strips: one barrier per round suffices.
    FOR_EACH_ROLE(id) {
        const uint j = fused_blur_moment(id);
        const uint x = fused_column_x(id);
        const uint read_y = fused_column_read_y(id);
        float column[FUSED_COLUMN_READS];
#pragma unroll
        for (uint k = 0; k < FUSED_COLUMN_READS; ++k) column[k] = block[fused_local_index(j, x, read_y + k)];
        barrier(CLK_LOCAL_MEM_FENCE);
        const uint write_y = fused_column_write_y(id);
#pragma unroll
        for (uint k = 0; k < FUSED_COLUMN_WRITES; ++k)
            block[fused_local_index(j, x, write_y + k)] = FILTER_TAPS9(column, k);
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    // Phase 4, readout: 3 texels per work-item, one output row per sub-group at a time;
    // quantize and write each texel once.
    FOR_EACH_ROLE(id)
    for (uint round = 0; round < FUSED_READOUT_ROUNDS; ++round) {
        const uint ox = fused_readout_ox(id);
        const uint oy = fused_readout_oy(id, round);
        const int gx = out_x0 + (int)ox;
        const int gy = out_y0 + (int)oy;
        if (gx >= width || gy >= height) continue;
        const uint sx = fused_stored_x(ox);
        const uint sy = fused_stored_y(oy);
        msm_moments m;
        m.b1 = block[fused_local_index(1, sx, sy)];
        m.b2 = block[fused_local_index(2, sx, sy)];
        m.b3 = block[fused_local_index(3, sx, sy)];
        m.b4 = block[fused_local_index(4, sx, sy)];
        msm_store_texel(texture, (size_t)gy * width + gx, m, shift);
    }
}
