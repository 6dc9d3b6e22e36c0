// Summed-area tables of translucent shadow maps (docs/math.md): the integer texels
// of a depth map with translucent layers, for the prefix sums of sat_build*.cl
// (MSM_SAT_SOURCE 1). Per texel: each sample's surfaces composited (msm_translucent.clh),
// the mean over the samples, quantized as msm_sat_texel_of_depth quantizes opaque texels.
// Compile-time: MSM_SAMPLES, MSM_DEPTH_ZERO_ONE, MSM_LAYERS (1..MSM_MAX_LAYERS).
// Layers: layer k, texel t, sample s at [(k * width * height + t) * MSM_SAMPLES + s] of
// `layer_depth` (as rendered) and `layer_opacity`.
#include "msm_sat.clh"
#include "msm_translucent.clh"
#include "msm_array.clh"

__kernel void sat_translucent_texels(__global const float* depth, __global const float* layer_depth,
                                     __global const float* layer_opacity, int width, int height, uint scale,
                                     __global uint* texels) {
    // Texture arrays: this layer's depth, translucent layers and texels (msm_array.clh).
    MSM_ARRAY_SLICE_ANY_GROUP(depth, (size_t)width * height * MSM_SAMPLES);
    MSM_ARRAY_SLICE_ANY_GROUP(layer_depth, (size_t)width * height * MSM_SAMPLES * MSM_LAYERS);
    MSM_ARRAY_SLICE_ANY_GROUP(layer_opacity, (size_t)width * height * MSM_SAMPLES * MSM_LAYERS);
    MSM_ARRAY_SLICE_ANY_GROUP(texels, 4 * (size_t)width * height);
    const int x = (int)get_global_id(0);
    const int y = (int)get_global_id(1);
    if (x >= width || y >= height) return;
    const size_t texel = (size_t)y * width + x;
    const size_t layer_stride = (size_t)width * height * MSM_SAMPLES;

    // Mean over the samples of the composited moments (summed from sample 0 up, times 1/S, as
    // msm_sat_texel_of_depth averages b(z)).
    const msm_moments mean = msm_resolve_translucent_texel(depth, layer_depth, layer_opacity, layer_stride, texel,
                                                           MSM_SAMPLES, MSM_LAYERS, MSM_DEPTH_ZERO_ONE, 0.0f);
    const msm_sat_sum t = msm_sat_texel_of_moments(mean, scale);
    vstore4((uint4)(t.c0, t.c1, t.c2, t.c3), texel, texels);
}
