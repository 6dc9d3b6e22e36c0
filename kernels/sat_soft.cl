// Moment soft shadow mapping (Peters et al., i3D 2016, section 3): shades receiver points from an integer
// modular summed-area table, one work-item per receiver (kernels/msm_sat.clh).
// Compile-time: MSM_DEPTH_ZERO_ONE (1: receiver z in [0,1], 0: in [-1,1]).
#include "msm_sat.clh"

__kernel void sat_soft_shade(__global const uint* table, int width, int height, uint scale,
                             int search_size, float light_size, float min_filter_size, float max_filter_size,
                             float receiver_weight, int filter_parts, __global const float* receivers_uvz,
                             uint count, float depth_bias, __global float* intensity) {
    const size_t i = get_global_id(0);
    if (i >= count) return;
    const msm_sat_soft_params p = msm_sat_soft_params_refine(
        msm_sat_soft_params_make(width, height, scale, search_size, light_size, min_filter_size, max_filter_size),
        receiver_weight, filter_parts);
    const float u = receivers_uvz[i];
    const float v = receivers_uvz[count + i];
    const float zf = msm_internal_depth(receivers_uvz[2 * (size_t)count + i], MSM_DEPTH_ZERO_ONE) - depth_bias;
    intensity[i] = msm_sat_soft_shadow(table, p, u, v, zf);
}
