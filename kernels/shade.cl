// shade: evaluates a filtered moment shadow map at receiver points (SPEC section 8).
// Compile-time: MSM_FORMAT (0 moments128, 1 msm64, 2 nlq64, 3 nlq32; the order of
// msmcl::Format), MSM_LOOKUP (0 nearest, 1 bilinear), MSM_DEPTH_ZERO_ONE (1 for [0,1]).
#include "msm_shading.clh"

#define MSM_LOOKUP_NEAREST 0
#define MSM_LOOKUP_BILINEAR 1

#if MSM_FORMAT == 0
#define MSM_TEXEL_WORDS 4
#elif MSM_FORMAT == 1 || MSM_FORMAT == 2
#define MSM_TEXEL_WORDS 2
#else
#define MSM_TEXEL_WORDS 1
#endif

// Moments of a texel of a linear format (moments128 raw, msm64 decoded), not yet biased.
static inline msm_moments linear_texel_moments(__global const uint* map, size_t texel) {
    __global const uint* t = map + texel * MSM_TEXEL_WORDS;
#if MSM_FORMAT == 0
    msm_moments m = {as_float(t[0]), as_float(t[1]), as_float(t[2]), as_float(t[3])};
    return m;
#else
    msm_word2 w = {t[0], t[1]};
    return msm_decode_msm64(w);
#endif
}

// Shadow intensity of one texel at internal depth zf, as the format's consumer does it.
static inline float texel_shadow(__global const uint* map, size_t texel, float zf) {
    __global const uint* t = map + texel * MSM_TEXEL_WORDS;
#if MSM_FORMAT == 0
    msm_moments m = {as_float(t[0]), as_float(t[1]), as_float(t[2]), as_float(t[3])};
    return msm_shadow_moments128(m, zf);
#elif MSM_FORMAT == 1
    msm_word2 w = {t[0], t[1]};
    return msm_shadow_msm64(w, zf);
#elif MSM_FORMAT == 2
    msm_word2 w = {t[0], t[1]};
    return msm_shadow_nlq64(w, zf);
#else
    return msm_shadow_nlq32(t[0], zf);
#endif
}

__kernel void shade(__global const uint* map, int width, int height,
                    __global const float* receivers_uvz, uint count,
                    __global float* intensity, float depth_bias) {
    const size_t i = get_global_id(0);
    if (i >= count) return;
    const float u = receivers_uvz[i];
    const float v = receivers_uvz[count + i];
    const float zf = msm_internal_depth(receivers_uvz[2 * (size_t)count + i], MSM_DEPTH_ZERO_ONE) - depth_bias;

#if MSM_LOOKUP == MSM_LOOKUP_NEAREST
    const int x = msm_texel_index(u, width);
    const int y = msm_texel_index(v, height);
    intensity[i] = texel_shadow(map, (size_t)y * width + x, zf);
#else
    // The four texel centres around (u - 0.5, v - 0.5), clamped to the edge.
    const msm_bilinear_taps taps = msm_bilinear_taps_at(u, v, width, height);
    const size_t t00 = (size_t)taps.y0 * width + taps.x0, t10 = (size_t)taps.y0 * width + taps.x1;
    const size_t t01 = (size_t)taps.y1 * width + taps.x0, t11 = (size_t)taps.y1 * width + taps.x1;
#if MSM_FORMAT == 0 || MSM_FORMAT == 1
    // Linear formats: interpolate the moments, then bias and reconstruct once.
    const msm_moments m = msm_moments_bilinear(linear_texel_moments(map, t00), linear_texel_moments(map, t10),
                                               linear_texel_moments(map, t01), linear_texel_moments(map, t11),
                                               taps.tx, taps.ty);
#if MSM_FORMAT == 0
    intensity[i] = msm_shadow_moments128(m, zf);
#else
    intensity[i] = msm_shadow_msm64_decoded(m, zf);
#endif
#else
    // Non-linear formats: shade the four texels, interpolate the intensities.
    intensity[i] = msm_bilinear(texel_shadow(map, t00, zf), texel_shadow(map, t10, zf),
                                texel_shadow(map, t01, zf), texel_shadow(map, t11, zf), taps.tx, taps.ty);
#endif
#endif
}
