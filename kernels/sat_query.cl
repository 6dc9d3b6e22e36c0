// Queries of an integer modular summed-area table (kernels/msm_sat.clh): mean power moments
// over rectangles with arbitrary corners. A rectangle that is empty, not finite, leaves the
// map or needs sums over more than N texels gives NaN moments, never a wrapped result.
#include "msm_sat.clh"

__kernel void sat_query_moments(__global const uint* table, int width, int height, uint scale,
                                uint max_kernel_texels, __global const float* rectangles, uint count,
                                __global float* moments) {
    const size_t i = get_global_id(0);
    if (i >= count) return;
    const float left = rectangles[4 * i + 0], top = rectangles[4 * i + 1];
    const float right = rectangles[4 * i + 2], bottom = rectangles[4 * i + 3];
    // The comparisons fail for NaN; Inf fails the bounds.
    const int valid = left >= 0.0f && top >= 0.0f && right <= (float)width && bottom <= (float)height &&
                      left < right && top < bottom &&
                      msm_sat_interpolation_fits(left, top, right, bottom, max_kernel_texels);
    msm_moments b;
    if (valid) {
        b = msm_sat_moments_of_basis(msm_sat_interpolated_mean(table, width, scale, left, top, right, bottom));
    } else {
        const float nan = as_float(0x7fc00000u);
        b.b1 = nan;
        b.b2 = nan;
        b.b3 = nan;
        b.b4 = nan;
    }
    moments[4 * i + 0] = b.b1;
    moments[4 * i + 1] = b.b2;
    moments[4 * i + 2] = b.b3;
    moments[4 * i + 3] = b.b4;
}
