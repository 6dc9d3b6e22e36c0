// shade: evaluates a filtered moment shadow map at receiver points (docs/math.md, Lookups).
// Compile-time: MSM_FORMAT and the format's row (msm_formats.clh), MSM_LOOKUP (0 nearest,
// 1 bilinear, 2 dither: kernel shade_dither), MSM_DEPTH_ZERO_ONE (1 for [0,1]); for dither
// MSM_RECEIVER_PIXELS (1: a buffer of screen pixels, 0: receivers are the pixels of a
// row-major image).
// The linear formats take the accurate (float-float) path of msm_shading.clh; VSM, EVSM and
// ESM (MSM_REPRESENTATION other than moments) the shading of msm_filterable_shading.clh with the
// texture's exponents and the options' minimum variance and light-bleed reduction (the last
// four arguments; the moment formats ignore them). The host twin is msmcl::shade_receiver
// (host/shading/shading.cpp).
#include "msm_filterable_shading.clh"
#include "msm_shading.clh"

#define MSM_LOOKUP_NEAREST 0
#define MSM_LOOKUP_BILINEAR 1
#define MSM_LOOKUP_DITHER 2

#if MSM_FORMAT == MSM_FORMAT_MOMENTS128 || MSM_FORMAT == MSM_FORMAT_EVSM4_128
// Raw moments of a moments128 texel (the four floats of evsm4_128 likewise).
static inline msm_moments raw_texel_moments(__global const uint* map, size_t texel) {
    __global const uint* t = map + texel * MSM_TEXEL_WORDS;
    msm_moments m = {as_float(t[0]), as_float(t[1]), as_float(t[2]), as_float(t[3])};
    return m;
}
#endif
#if MSM_TEXEL_WORDS == 2
// The words of a 64-bit texel.
static inline msm_word2 texel_word2(__global const uint* map, size_t texel) {
    __global const uint* t = map + texel * MSM_TEXEL_WORDS;
    msm_word2 w = {t[0], t[1]};
    return w;
}
#endif

#if MSM_REPRESENTATION != MSM_REPRESENTATION_MOMENTS
// The stored channels of a VSM, EVSM or ESM texel (msm_filterable_shading.clh).
static inline msm_moments texel_channels(__global const uint* map, size_t texel) {
#if MSM_FORMAT == MSM_FORMAT_VSM32
    return msm_decode_vsm32(map[texel]);
#elif MSM_FORMAT == MSM_FORMAT_VSM64
    return msm_decode_vsm64(texel_word2(map, texel));
#elif MSM_FORMAT == MSM_FORMAT_EVSM2_32
    return msm_decode_evsm2_32(map[texel]);
#elif MSM_FORMAT == MSM_FORMAT_EVSM4_64
    return msm_decode_evsm4_64(texel_word2(map, texel));
#elif MSM_FORMAT == MSM_FORMAT_EVSM4_128
    return raw_texel_moments(map, texel);
#else
    return msm_decode_esm32(map[texel]);
#endif
}

// How the representation shades: the texture's exponents, the options' V and R.
static inline msm_warp_shading warp_shading(float positive, float negative, float min_variance,
                                            float light_bleed_reduction) {
#if MSM_REPRESENTATION == MSM_REPRESENTATION_VSM
    return msm_warp_shading_vsm(min_variance, light_bleed_reduction);
#elif MSM_REPRESENTATION == MSM_REPRESENTATION_EVSM2
    return msm_warp_shading_evsm2(positive, min_variance, light_bleed_reduction);
#elif MSM_REPRESENTATION == MSM_REPRESENTATION_EVSM4
    return msm_warp_shading_evsm4(positive, negative, min_variance, light_bleed_reduction);
#else
    return msm_warp_shading_esm(positive);
#endif
}
#endif

#if MSM_LOOKUP == MSM_LOOKUP_NEAREST || MSM_LOOKUP == MSM_LOOKUP_DITHER || !MSM_BLENDS_MOMENTS
// Shadow intensity of one texel at internal depth zf, as the format's consumer does it.
static inline float texel_shadow(__global const uint* map, size_t texel, float zf, msm_warp_shading warp) {
#if MSM_REPRESENTATION != MSM_REPRESENTATION_MOMENTS
    return msm_shadow_warped(texel_channels(map, texel), zf, warp);
#elif MSM_FORMAT == MSM_FORMAT_MOMENTS128
    return msm_shadow_moments128(raw_texel_moments(map, texel), zf);
#elif MSM_FORMAT == MSM_FORMAT_MSM64
    return msm_shadow_msm64(texel_word2(map, texel), zf);
#elif MSM_FORMAT == MSM_FORMAT_NLQ64
    return msm_shadow_nlq64(texel_word2(map, texel), zf);
#else
    return msm_shadow_nlq32(map[texel], zf);
#endif
}
#endif

// The shading of every format's texels: the warped formats' parameters (unused elsewhere).
#if MSM_REPRESENTATION != MSM_REPRESENTATION_MOMENTS
#define MSM_WARP_SHADING warp_shading(warp_positive, warp_negative, min_variance, light_bleed_reduction)
#else
#define MSM_WARP_SHADING msm_warp_shading_vsm(min_variance, light_bleed_reduction)
#endif

#if MSM_LOOKUP != MSM_LOOKUP_DITHER
__kernel void shade(__global const uint* map, int width, int height,
                    __global const float* receivers_uvz, uint count,
                    __global float* intensity, float depth_bias, float warp_positive, float warp_negative,
                    float min_variance, float light_bleed_reduction) {
    const size_t i = get_global_id(0);
    if (i >= count) return;
    const float u = receivers_uvz[i];
    const float v = receivers_uvz[count + i];
    const float zf = msm_internal_depth(receivers_uvz[2 * (size_t)count + i], MSM_DEPTH_ZERO_ONE) - depth_bias;

#if MSM_LOOKUP == MSM_LOOKUP_NEAREST
    const int x = msm_texel_index(u, width);
    const int y = msm_texel_index(v, height);
    intensity[i] = texel_shadow(map, (size_t)y * width + x, zf, MSM_WARP_SHADING);
#else
    // The four texel centres around (u - 0.5, v - 0.5), clamped to the edge.
    const msm_bilinear_taps taps = msm_bilinear_taps_at(u, v, width, height);
    const size_t t00 = (size_t)taps.y0 * width + taps.x0, t10 = (size_t)taps.y0 * width + taps.x1;
    const size_t t01 = (size_t)taps.y1 * width + taps.x0, t11 = (size_t)taps.y1 * width + taps.x1;
#if MSM_REPRESENTATION != MSM_REPRESENTATION_MOMENTS
    // VSM, EVSM, ESM: blend the stored values (as a texture unit's filter), then shade once.
    intensity[i] = msm_shadow_warped(msm_moments_bilinear(texel_channels(map, t00), texel_channels(map, t10),
                                                          texel_channels(map, t01), texel_channels(map, t11),
                                                          taps.tx, taps.ty),
                                     zf, MSM_WARP_SHADING);
#elif MSM_FORMAT == MSM_FORMAT_MOMENTS128
    // Linear formats: blend the moments in float-float, then bias and reconstruct once.
    intensity[i] = msm_shadow_moments128_bilinear(raw_texel_moments(map, t00), raw_texel_moments(map, t10),
                                                  raw_texel_moments(map, t01), raw_texel_moments(map, t11),
                                                  taps.tx, taps.ty, zf);
#elif MSM_FORMAT == MSM_FORMAT_MSM64
    intensity[i] = msm_shadow_msm64_bilinear(texel_word2(map, t00), texel_word2(map, t10), texel_word2(map, t01),
                                             texel_word2(map, t11), taps.tx, taps.ty, zf);
#else
    // Non-linear formats: shade the four texels, interpolate the intensities.
    const msm_warp_shading warp = MSM_WARP_SHADING;
    intensity[i] = msm_bilinear(texel_shadow(map, t00, zf, warp), texel_shadow(map, t10, zf, warp),
                                texel_shadow(map, t01, zf, warp), texel_shadow(map, t11, zf, warp), taps.tx, taps.ty);
#endif
#endif
}
#endif

#if MSM_LOOKUP == MSM_LOOKUP_DITHER
// Dithered lookup: one texel, floor(u - 0.5 + n) per axis with the blue noise n of the
// receiver's screen pixel. `noise` is the frame's 64x64 texture (2 bytes per texel),
// `offset_x/y` its shift (msm_blue_noise_frame_of). Pixels: `pixels` holds count x then count
// y (MSM_RECEIVER_PIXELS 1), else receiver i is pixel (i % screen_width, i / screen_width).
__kernel void shade_dither(__global const uint* map, int width, int height,
                           __global const float* receivers_uvz, uint count,
                           __global float* intensity, float depth_bias,
                           __global const uchar* noise, uint offset_x, uint offset_y,
                           __global const uint* pixels, uint screen_width, float warp_positive,
                           float warp_negative, float min_variance, float light_bleed_reduction) {
    const size_t i = get_global_id(0);
    if (i >= count) return;
    const float u = receivers_uvz[i];
    const float v = receivers_uvz[count + i];
    const float zf = msm_internal_depth(receivers_uvz[2 * (size_t)count + i], MSM_DEPTH_ZERO_ONE) - depth_bias;

    // The receiver's screen pixel and its noise texel in this frame's texture.
#if MSM_RECEIVER_PIXELS
    const uint px = pixels[i];
    const uint py = pixels[count + i];
#else
    const uint px = (uint)i % screen_width;
    const uint py = (uint)i / screen_width;
#endif
    msm_blue_noise_frame frame;
    frame.texture = 0u; // `noise` holds the frame's texture alone
    frame.offset_x = offset_x;
    frame.offset_y = offset_y;
    const uint t = msm_blue_noise_texel_in_texture(frame, px, py);

    // One texel, shaded as the nearest lookup shades it.
    const int x = msm_dither_index(u, msm_blue_noise_value(noise[2 * t]), width);
    const int y = msm_dither_index(v, msm_blue_noise_value(noise[2 * t + 1]), height);
    intensity[i] = texel_shadow(map, (size_t)y * width + x, zf, MSM_WARP_SHADING);
}
#endif
