// scatter: prefiltered single scattering (docs/math.md; math in msm_scatter.clh).
//   scatter_prefilter: one work-group per rectified row (one azimuth phi). Each work-item
//     resamples MSM_SCATTER_SEGMENT consecutive texels of a chunk of the row (filtered or
//     unfiltered, generated on the fly: no separate resampling pass), a work-group scan of
//     their transmittance-weighted moments gives the prefix sums, normalized by the weight
//     sums (a per-column table from the host), quantized and written. Chunks of
//     MSM_SCATTER_GROUP * MSM_SCATTER_SEGMENT texels follow each other with a carry.
//     source: the moments128 map (filtered) or the depth map (unfiltered); output_mode: the
//     quantized map into `quantized`, or float moments into `moments_out` (sums or the
//     resampled texels themselves, for inspection and tests).
//   scatter_evaluate: one work-item per camera pixel, one bilinear lookup.
//   scatter_ray_march: one work-item per camera pixel, the ground truth.
// Compile-time: MSM_SCATTER_MOMENTS (4 or 6), MSM_SCATTER_GROUP (work-items per row, a
// power of two), MSM_SCATTER_SEGMENT (texels per work-item and chunk).
#include "msm_scatter.clh"

#if MSM_SCATTER_MOMENTS == 6
#define MSM_K 6
#else
#define MSM_K 4
#endif

// Output modes of scatter_prefilter.
#define MSM_SCATTER_OUTPUT_QUANTIZED 0 // the prefiltered map (64 bits per texel)
#define MSM_SCATTER_OUTPUT_SUMS 1      // float normalized prefix sums, MSM_K per texel
#define MSM_SCATTER_OUTPUT_RESAMPLED 2 // float resampled moments (no sums), MSM_K per texel

static inline void moments_to_array(msm_moments6 m, float* v) {
    v[0] = m.b1;
    v[1] = m.b2;
    v[2] = m.b3;
    v[3] = m.b4;
#if MSM_K == 6
    v[4] = m.b5;
    v[5] = m.b6;
#endif
}

static inline msm_moments6 moments_from_array(const float* v) {
    msm_moments6 m;
    m.b1 = v[0];
    m.b2 = v[1];
    m.b3 = v[2];
    m.b4 = v[3];
#if MSM_K == 6
    m.b5 = v[4];
    m.b6 = v[5];
#else
    m.b5 = 0.0f;
    m.b6 = 0.0f;
#endif
    return m;
}

static inline void write_moments(__global uint* quantized, __global float* moments_out, int output_mode,
                                 msm_scatter_params p, size_t texel, const float* v) {
    if (output_mode != MSM_SCATTER_OUTPUT_QUANTIZED) {
        #pragma unroll
        for (int k = 0; k < MSM_K; ++k) moments_out[texel * MSM_K + k] = v[k];
        return;
    }
#if MSM_K == 6
    const msm_word_pair w = msm_encode_moments6(moments_from_array(v));
    quantized[texel] = w.odd;
    quantized[(size_t)p.rect_width * (size_t)p.rect_height + texel] = w.even;
#else
    const msm_word2 w = msm_encode_msm64(msm_moments6_first4(moments_from_array(v)));
    quantized[2 * texel] = w.w0;
    quantized[2 * texel + 1] = w.w1;
#endif
}

// weights: rect_width relative weights w_i, then rect_width inverse sums 1 / sum_{k<=i} w_k.
// Each kernel copies its parameter struct into a private one as its first statement: read
// field by field after a branch, a by-value struct argument makes Mesa's llvmpipe load the
// kernel argument inside control flow, which it warns about (docs/devices.md).
__kernel __attribute__((reqd_work_group_size(MSM_SCATTER_GROUP, 1, 1)))
void scatter_prefilter(__global const float* source, int filtered, int output_mode, msm_scatter_params params,
                       __global const float* weights, __global uint* quantized, __global float* moments_out) {
    // The parameters copied before any control flow (see the comment above the kernel).
    const msm_scatter_params p = params;
    __local float scan[2 * MSM_K * MSM_SCATTER_GROUP];
    const int row = (int)get_group_id(0);
    const int lid = (int)get_local_id(0);
    const float phi = msm_scatter_texel_phi(p, row);
    const float cos_phi = cos(phi);
    const float sin_phi = sin(phi);
    const size_t row_start = (size_t)row * (size_t)p.rect_width;
    const int chunk = MSM_SCATTER_GROUP * MSM_SCATTER_SEGMENT;
    // Loops over the per-work-item arrays are unrolled: the arrays stay in registers on GPUs.
    float carry[MSM_K];
    #pragma unroll
    for (int k = 0; k < MSM_K; ++k) carry[k] = 0.0f;

    for (int start = 0; start < p.rect_width; start += chunk) {
        // Resample this work-item's texels; running weighted sums within the segment.
        float running[MSM_SCATTER_SEGMENT][MSM_K];
        float total[MSM_K];
        #pragma unroll
        for (int k = 0; k < MSM_K; ++k) total[k] = 0.0f;
        #pragma unroll
        for (int s = 0; s < MSM_SCATTER_SEGMENT; ++s) {
            const int i = start + lid * MSM_SCATTER_SEGMENT + s;
            if (i < p.rect_width) {
                const float r = msm_scatter_texel_r(p, i);
                const msm_moments6 m = filtered ? msm_scatter_resample_filtered(source, p, r, cos_phi, sin_phi)
                                                : msm_scatter_resample_unfiltered(source, p, r, cos_phi, sin_phi);
                float v[MSM_K];
                moments_to_array(m, v);
                if (output_mode == MSM_SCATTER_OUTPUT_RESAMPLED) write_moments(quantized, moments_out, output_mode, p, row_start + i, v);
                const float w = weights[i];
                #pragma unroll
                for (int k = 0; k < MSM_K; ++k) total[k] += w * v[k];
            }
            #pragma unroll
            for (int k = 0; k < MSM_K; ++k) running[s][k] = total[k];
        }
        if (output_mode == MSM_SCATTER_OUTPUT_RESAMPLED) continue;

        // Inclusive scan of the segment totals over the work-group (Hillis-Steele, two halves).
        #pragma unroll
        for (int k = 0; k < MSM_K; ++k) scan[k * MSM_SCATTER_GROUP + lid] = total[k];
        barrier(CLK_LOCAL_MEM_FENCE);
        int from = 0;
        for (int offset = 1; offset < MSM_SCATTER_GROUP; offset <<= 1) {
            const int to = MSM_K * MSM_SCATTER_GROUP - from;
            #pragma unroll
            for (int k = 0; k < MSM_K; ++k) {
                float x = scan[from + k * MSM_SCATTER_GROUP + lid];
                if (lid >= offset) x += scan[from + k * MSM_SCATTER_GROUP + lid - offset];
                scan[to + k * MSM_SCATTER_GROUP + lid] = x;
            }
            barrier(CLK_LOCAL_MEM_FENCE);
            from = to;
        }

        // Prefix sums: carry + earlier work-items + own running sum, normalized.
        float before[MSM_K];
        #pragma unroll
        for (int k = 0; k < MSM_K; ++k)
            before[k] = carry[k] + (lid > 0 ? scan[from + k * MSM_SCATTER_GROUP + lid - 1] : 0.0f);
        #pragma unroll
        for (int s = 0; s < MSM_SCATTER_SEGMENT; ++s) {
            const int i = start + lid * MSM_SCATTER_SEGMENT + s;
            if (i < p.rect_width) {
                const float inv_weight_sum = weights[p.rect_width + i];
                float v[MSM_K];
                #pragma unroll
                for (int k = 0; k < MSM_K; ++k) v[k] = (before[k] + running[s][k]) * inv_weight_sum;
                write_moments(quantized, moments_out, output_mode, p, row_start + i, v);
            }
        }
        #pragma unroll
        for (int k = 0; k < MSM_K; ++k) carry[k] += scan[from + k * MSM_SCATTER_GROUP + MSM_SCATTER_GROUP - 1];
        // The scan buffer is reused by the next chunk.
        barrier(CLK_LOCAL_MEM_FENCE);
    }
}

__kernel void scatter_evaluate(__global const uint* map, __global const float* camera_depth, msm_scatter_params params,
                               __global float* radiance) {
    // The parameters copied before any control flow (see above scatter_prefilter).
    const msm_scatter_params p = params;
    const int px = (int)get_global_id(0);
    const int py = (int)get_global_id(1);
    if (px >= p.cam_width || py >= p.cam_height) return;
    const size_t pixel = (size_t)py * (size_t)p.cam_width + (size_t)px;
#if MSM_K == 6
    radiance[pixel] = msm_scatter_pixel6(map, p, px, py, camera_depth[pixel]);
#else
    radiance[pixel] = msm_scatter_pixel4(map, p, px, py, camera_depth[pixel]);
#endif
}

__kernel void scatter_ray_march(__global const float* depth_map, __global const float* camera_depth,
                                msm_scatter_params params, int steps, uint jitter_seed, __global float* radiance) {
    // The parameters copied before any control flow (see above scatter_prefilter).
    const msm_scatter_params p = params;
    const int px = (int)get_global_id(0);
    const int py = (int)get_global_id(1);
    if (px >= p.cam_width || py >= p.cam_height) return;
    const size_t pixel = (size_t)py * (size_t)p.cam_width + (size_t)px;
    radiance[pixel] = msm_scatter_ray_march_pixel(depth_map, p, px, py, camera_depth[pixel], steps,
                                                  msm_scatter_jitter(px, py, jitter_seed));
}
