// The baseline the paper compares against (Peters, HPG 2017, section 4): three passes through
// global memory. (a) resolve -> float4 moments, (b) horizontal 9-tap -> float4 moments,
// (c) vertical 9-tap + bias + quantize -> texture. Unshifted moments (c = 0).
// Same compile-time defines (MSM_LAYERS included), taps and float operations as
// filter_fused_gpu.cl, so moments128 and msm64 agree with it bit for bit. MSM_ARRAY 1:
// texture arrays, the third NDRange dimension is the array layer (msm_array.clh).
#include "msm_formats.clh"
#include "msm_translucent.clh"
#include "msm_array.clh"

// Translucent layers (MSM_LAYERS > 0, docs/math.md): the resolve composites each sample's
// surfaces (msm_translucent.clh) instead of taking b(z); 0 compiles the opaque code alone.
#ifndef MSM_LAYERS
#define MSM_LAYERS 0
#endif

// 9-tap sum over the texels at offsets i = -4..4 of one moment (weights w4 .. w0 .. w4).
#define FILTER_TAPS9(v)                                                                       \
    fma(w4, v(4), fma(w3, v(3), fma(w2, v(2), fma(w1, v(1),                                   \
    fma(w0, v(0), fma(w1, v(-1), fma(w2, v(-2), fma(w3, v(-3), w4 * v(-4)))))))))

static inline msm_moments load_moments(__global const float* moments, size_t texel) {
    msm_moments m;
    MSM_LOAD4(m.b1, m.b2, m.b3, m.b4, moments, 1, 4 * texel);
    return m;
}

static inline void store_moments(__global float* moments, size_t texel, msm_moments m) {
    vstore4((float4)(m.b1, m.b2, m.b3, m.b4), texel, moments);
}

// (a) One texel per work-item: resolve its samples (unshifted, c = 0).
__kernel void filter_resolve(__global const float* depth, int width, int height, __global float* moments
#if MSM_LAYERS
                             , __global const float* layer_depth, __global const float* layer_opacity
#endif
) {
    MSM_ARRAY_SLICE_ANY_GROUP(depth, (size_t)width * height * MSM_SAMPLES);
    MSM_ARRAY_SLICE_ANY_GROUP(moments, (size_t)width * height * 4);
#if MSM_LAYERS
    MSM_ARRAY_SLICE_ANY_GROUP(layer_depth, (size_t)width * height * MSM_SAMPLES * MSM_LAYERS);
    MSM_ARRAY_SLICE_ANY_GROUP(layer_opacity, (size_t)width * height * MSM_SAMPLES * MSM_LAYERS);
#endif
    const int x = (int)get_global_id(0);
    const int y = (int)get_global_id(1);
    if (x >= width || y >= height) return;
    const size_t texel = (size_t)y * width + x;
#if MSM_LAYERS
    const size_t layer_stride = (size_t)width * height * MSM_SAMPLES;
    store_moments(moments, texel, msm_resolve_translucent_texel(depth, layer_depth, layer_opacity, layer_stride, texel,
                                                                MSM_SAMPLES, MSM_LAYERS, MSM_DEPTH_ZERO_ONE, 0.0f));
#else
    store_moments(moments, texel, msm_resolve_texel(depth + texel * MSM_SAMPLES, MSM_SAMPLES, MSM_DEPTH_ZERO_ONE, 0.0f));
#endif
}

// (b) Horizontal 9-tap blur, clamp-to-edge.
__kernel void filter_horizontal(__global const float* moments, int width, int height, __global float* blurred,
                                float w0, float w1, float w2, float w3, float w4) {
    MSM_ARRAY_SLICE_ANY_GROUP(moments, (size_t)width * height * 4);
    MSM_ARRAY_SLICE_ANY_GROUP(blurred, (size_t)width * height * 4);
    const int x = (int)get_global_id(0);
    const int y = (int)get_global_id(1);
    if (x >= width || y >= height) return;
    const size_t row = (size_t)y * width;
    msm_moments n[9];
    for (int i = -4; i <= 4; ++i) n[i + 4] = load_moments(moments, row + clamp(x + i, 0, width - 1));
    msm_moments m;
#define TAP_B1(i) n[(i) + 4].b1
#define TAP_B2(i) n[(i) + 4].b2
#define TAP_B3(i) n[(i) + 4].b3
#define TAP_B4(i) n[(i) + 4].b4
    m.b1 = FILTER_TAPS9(TAP_B1);
    m.b2 = FILTER_TAPS9(TAP_B2);
    m.b3 = FILTER_TAPS9(TAP_B3);
    m.b4 = FILTER_TAPS9(TAP_B4);
    store_moments(blurred, row + x, m);
}

// (c) Vertical 9-tap blur, clamp-to-edge, then bias/quantize into the texture format (nlq:
// Algorithm 2 in the unshifted frame, c = 0, bias held apart as in the fused kernels).
__kernel void filter_vertical_quantize(__global const float* moments, int width, int height, __global uint* texture,
                                       float w0, float w1, float w2, float w3, float w4) {
    MSM_ARRAY_SLICE_ANY_GROUP(moments, (size_t)width * height * 4);
    MSM_ARRAY_SLICE_ANY_GROUP(texture, (size_t)width * height * MSM_TEXEL_WORDS);
    const int x = (int)get_global_id(0);
    const int y = (int)get_global_id(1);
    if (x >= width || y >= height) return;
    msm_moments n[9];
    for (int i = -4; i <= 4; ++i) n[i + 4] = load_moments(moments, (size_t)clamp(y + i, 0, height - 1) * width + x);
    msm_moments m;
    m.b1 = FILTER_TAPS9(TAP_B1);
    m.b2 = FILTER_TAPS9(TAP_B2);
    m.b3 = FILTER_TAPS9(TAP_B3);
    m.b4 = FILTER_TAPS9(TAP_B4);
    msm_store_texel(texture, (size_t)y * width + x, m, 0.0f);
}
