// The baseline the paper compares against (Peters, HPG 2017, section 4): three passes through
// global memory. (a) resolve -> float4 moments, (b) horizontal 9-tap -> float4 moments,
// (c) vertical 9-tap + bias + quantize -> texture. Unshifted moments (c = 0).
// Same compile-time defines (MSM_LAYERS included), taps and float operations as
// filter_fused_gpu.cl, so moments128 and msm64 agree with it bit for bit.
#include "msm_formats.clh"
#include "msm_translucent.clh"

// Translucent layers (MSM_LAYERS > 0, docs/math.md): the resolve composites each sample's
// surfaces (msm_translucent.clh) instead of taking b(z); 0 compiles the opaque code alone.
#ifndef MSM_LAYERS
#define MSM_LAYERS 0
#endif

// Moments of z averaged over the samples of texel `texel` (as in filter_fused_gpu.cl, c = 0).
static inline msm_moments resolve_texel(__global const float* depth, size_t texel) {
    __global const float* samples = depth + texel * MSM_SAMPLES;
    msm_moments sum = msm_moments_of(msm_internal_depth(samples[0], MSM_DEPTH_ZERO_ONE) - 0.0f);
    for (int s = 1; s < MSM_SAMPLES; ++s)
        sum = msm_moments_add(sum, msm_moments_of(msm_internal_depth(samples[s], MSM_DEPTH_ZERO_ONE) - 0.0f));
    return msm_moments_scale(sum, 1.0f / (float)MSM_SAMPLES);
}

// 9-tap sum over the texels at offsets i = -4..4 of one moment (weights w4 .. w0 .. w4).
#define FILTER_TAPS9(v)                                                                       \
    fma(w4, v(4), fma(w3, v(3), fma(w2, v(2), fma(w1, v(1),                                   \
    fma(w0, v(0), fma(w1, v(-1), fma(w2, v(-2), fma(w3, v(-3), w4 * v(-4)))))))))

static inline msm_moments load_moments(__global const float* moments, size_t texel) {
    msm_moments m;
    m.b1 = moments[4 * texel + 0];
    m.b2 = moments[4 * texel + 1];
    m.b3 = moments[4 * texel + 2];
    m.b4 = moments[4 * texel + 3];
    return m;
}

static inline void store_moments(__global float* moments, size_t texel, msm_moments m) {
    vstore4((float4)(m.b1, m.b2, m.b3, m.b4), texel, moments);
}

#if MSM_LAYERS
// The same with the texel's translucent layers: layer k of texel t, sample s at
// [(k * width * height + t) * MSM_SAMPLES + s].
static inline msm_moments resolve_translucent_texel(__global const float* depth, __global const float* layer_depth,
                                                    __global const float* layer_opacity, size_t layer_stride,
                                                    size_t texel) {
    __global const float* first = depth + texel * MSM_SAMPLES;
    __global const float* first_z = layer_depth + texel * MSM_SAMPLES;
    __global const float* first_a = layer_opacity + texel * MSM_SAMPLES;
    msm_moments sum = msm_translucent_sample(first, first_z, first_a, layer_stride, MSM_LAYERS, 0, MSM_DEPTH_ZERO_ONE, 0.0f);
    for (int s = 1; s < MSM_SAMPLES; ++s)
        sum = msm_moments_add(sum, msm_translucent_sample(first, first_z, first_a, layer_stride, MSM_LAYERS, s,
                                                          MSM_DEPTH_ZERO_ONE, 0.0f));
    return msm_moments_scale(sum, 1.0f / (float)MSM_SAMPLES);
}
#endif

// (a) One texel per work-item: resolve its samples.
__kernel void filter_resolve(__global const float* depth, int width, int height, __global float* moments
#if MSM_LAYERS
                             , __global const float* layer_depth, __global const float* layer_opacity
#endif
) {
    const int x = (int)get_global_id(0);
    const int y = (int)get_global_id(1);
    if (x >= width || y >= height) return;
    const size_t texel = (size_t)y * width + x;
#if MSM_LAYERS
    const size_t layer_stride = (size_t)width * height * MSM_SAMPLES;
    store_moments(moments, texel, resolve_translucent_texel(depth, layer_depth, layer_opacity, layer_stride, texel));
#else
    store_moments(moments, texel, resolve_texel(depth, texel));
#endif
}

// (b) Horizontal 9-tap blur, clamp-to-edge.
__kernel void filter_horizontal(__global const float* moments, int width, int height, __global float* blurred,
                                float w0, float w1, float w2, float w3, float w4) {
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
    const size_t texel = (size_t)y * width + x;
#if MSM_FORMAT == 0
    vstore4((uint4)(as_uint(m.b1), as_uint(m.b2), as_uint(m.b3), as_uint(m.b4)), texel, texture);
#elif MSM_FORMAT == 1
    const msm_word2 code = msm_encode_msm64(m);
    vstore2((uint2)(code.w0, code.w1), texel, texture);
#elif MSM_FORMAT == 2
    const msm_word2 code = msm_encode_nlq64(msm_nlq_from_shifted_moments(m, 0.0f));
    vstore2((uint2)(code.w0, code.w1), texel, texture);
#else
    texture[texel] = msm_encode_nlq32(msm_nlq_from_shifted_moments(m, 0.0f));
#endif
}
