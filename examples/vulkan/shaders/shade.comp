// Shading receivers from one msmcl texture, as a renderer's shader would: the functions
// of shaders/msm.glsl on a VkImage of the texture's documented format.
// MSM_FORMAT (set at build time, include/msmcl/formats.hpp order): 0 moments128
// (R32G32B32A32_SFLOAT), 1 msm64 and 2 nlq64 (R16G16B16A16_UNORM), 3 nlq32 (R32_UINT); 4 and up
// the VSM, EVSM and ESM formats (vsm32 R16G16_UNORM, vsm64 R32G32_SFLOAT, evsm2_32 R16G16_SFLOAT,
// evsm4_64 R16G16B16A16_SFLOAT, evsm4_128 R32G32B32A32_SFLOAT, esm32 R32_SFLOAT), sampled as
// floats and shaded by msm_lookup_warped with the push constants' msm_warp_shading.
// Lookups: 0 nearest, 1 bilinear, 2 dithered (blue noise, RG8UI), all through texelFetch
// (msm_lookup_*), and 3 hardware bilinear: one textureLod through the linear sampler
// (the formats docs/shaders.md allows filtering: moments128, msm64, VSM, EVSM, ESM).
// MSM_ARRAY=1: the map is a texture array (sampler2DArray, usampler2DArray) and the
// receivers are shaded from its layer `params.layer` (msm_lookup_*_array).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "msm.glsl"

#ifndef MSM_ARRAY
#define MSM_ARRAY 0
#endif

layout(local_size_x = 64) in;

#if MSM_ARRAY && MSM_FORMAT == 3
layout(binding = 0) uniform usampler2DArray shadow_map; // nearest sampler (texelFetch only)
#elif MSM_ARRAY
layout(binding = 0) uniform sampler2DArray shadow_map;  // linear (moments128, msm64) or nearest (nlq64)
#elif MSM_FORMAT == 3
layout(binding = 0) uniform usampler2D shadow_map; // nearest sampler (texelFetch only)
#else
layout(binding = 0) uniform sampler2D shadow_map;  // linear (moments128, msm64) or nearest (nlq64)
#endif
layout(binding = 1) uniform usampler2D blue_noise; // 64 x 4096 RG8UI, nearest

struct Receiver {
    float u; // texel units
    float v;
    float z; // depth as rendered
    uint px; // screen pixel (dithered lookup)
    uint py;
};
layout(std430, binding = 2) readonly buffer Receivers { Receiver receivers[]; };
layout(std430, binding = 3) writeonly buffer Shadow { float shadow[]; };

layout(push_constant) uniform Params {
    int width;
    int height;
    uint count;
    int lookup;
    float depth_bias;
    uint zero_one;       // depth convention of z: 1 for [0,1]
    uint noise_texture;  // msm_blue_noise_frame_of(frame), computed once per frame
    uint noise_offset_x;
    uint noise_offset_y;
    uint accurate;       // moments128: the float-float path (msm_lookup_moments128_accurate)
    int layer;           // MSM_ARRAY: the array layer shaded
    int representation;  // VSM, EVSM, ESM: msm_warp_shading as the host makes it
    float warp_positive;
    float warp_negative;
    float min_variance;
    float light_bleed_reduction;
} params;

// The map's lookups, on the 2D map or on layer params.layer of the array (the same math).
#if MSM_ARRAY
#define MSM_LOOKUP(name) name##_array(shadow_map, params.layer,
#define MSM_FILTERED_UV(uv) vec3(uv, float(params.layer))
#else
#define MSM_LOOKUP(name) name(shadow_map,
#define MSM_FILTERED_UV(uv) uv
#endif

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= params.count) return;
    Receiver r = receivers[i];
    float zf = msm_internal_depth(r.z, params.zero_one != 0u) - params.depth_bias;
    vec2 noise = vec2(0.0f);
    if (params.lookup == 2) {
        msm_blue_noise_frame frame;
        frame.texture_index = params.noise_texture;
        frame.offset_x = params.noise_offset_x;
        frame.offset_y = params.noise_offset_y;
        noise = msm_blue_noise_at(blue_noise, frame, r.px, r.py);
    }
#if MSM_FORMAT == 0
    if (params.lookup == 3) {
        vec2 uv = vec2(r.u / float(params.width), r.v / float(params.height));
        shadow[i] = msm_shadow_moments128_fast(msm_decode_moments128(textureLod(shadow_map, MSM_FILTERED_UV(uv), 0.0f)), zf);
        return;
    }
    if (params.accurate != 0u) {
        shadow[i] = MSM_LOOKUP(msm_lookup_moments128_accurate) params.width, params.height, r.u, r.v, zf, params.lookup,
                                                               noise);
        return;
    }
    shadow[i] = MSM_LOOKUP(msm_lookup_moments128) params.width, params.height, r.u, r.v, zf, params.lookup, noise);
#elif MSM_FORMAT == 1
    if (params.lookup == 3) {
        vec2 uv = vec2(r.u / float(params.width), r.v / float(params.height));
        shadow[i] = msm_shadow_msm64_decoded_fast(msm_decode_msm64(textureLod(shadow_map, MSM_FILTERED_UV(uv), 0.0f)), zf);
        return;
    }
    shadow[i] = MSM_LOOKUP(msm_lookup_msm64) params.width, params.height, r.u, r.v, zf, params.lookup, noise);
#elif MSM_FORMAT == 2
    shadow[i] = MSM_LOOKUP(msm_lookup_nlq64) params.width, params.height, r.u, r.v, zf, params.lookup, noise);
#elif MSM_FORMAT == 3
    shadow[i] = MSM_LOOKUP(msm_lookup_nlq32) params.width, params.height, r.u, r.v, zf, params.lookup, noise);
#else
    msm_warp_shading warp = msm_warp_shading_make(params.representation, params.warp_positive, params.warp_negative,
                                                  params.min_variance, params.light_bleed_reduction);
    if (params.lookup == 3) {
        vec2 uv = vec2(r.u / float(params.width), r.v / float(params.height));
        shadow[i] = msm_shadow_warped(msm_decode_moments128(textureLod(shadow_map, MSM_FILTERED_UV(uv), 0.0f)), zf, warp);
        return;
    }
    shadow[i] = MSM_LOOKUP(msm_lookup_warped) params.width, params.height, r.u, r.v, zf, params.lookup, noise, warp);
#endif
}
