// The HLSL route of shade.comp: the same work through shaders/msm.hlsl, compiled by
// glslang's HLSL front end, as a D3D engine's shader would sample the textures
// (Texture2D + SamplerState; SampleLevel for the hardware-filtered lookup 3).
// MSM_ARRAY=1: a Texture2DArray, shaded from its layer `params.layer`.
#include "msm.hlsl"

#ifndef MSM_ARRAY
#define MSM_ARRAY 0
#endif

#if MSM_ARRAY && MSM_FORMAT == 3
[[vk::binding(0)]] Texture2DArray<uint4> shadow_map;
#elif MSM_ARRAY
[[vk::binding(0)]] Texture2DArray<float4> shadow_map;
#elif MSM_FORMAT == 3
[[vk::binding(0)]] Texture2D<uint4> shadow_map;
#else
[[vk::binding(0)]] Texture2D<float4> shadow_map;
#endif
[[vk::binding(1)]] Texture2D<uint4> blue_noise;

struct Receiver {
    float u;
    float v;
    float z;
    uint px;
    uint py;
};
[[vk::binding(2)]] StructuredBuffer<Receiver> receivers;
[[vk::binding(3)]] RWStructuredBuffer<float> shadow;
[[vk::binding(4)]] SamplerState map_sampler; // linear, clamp to edge

struct Params {
    int width;
    int height;
    uint count;
    int lookup;
    float depth_bias;
    uint zero_one;
    uint noise_texture;
    uint noise_offset_x;
    uint noise_offset_y;
    uint accurate;
    int layer; // MSM_ARRAY: the array layer shaded
    int representation; // VSM, EVSM, ESM: msm_warp_shading as the host makes it
    float warp_positive;
    float warp_negative;
    float min_variance;
    float light_bleed_reduction;
};
[[vk::push_constant]] ConstantBuffer<Params> params;

// The map's lookups, on the 2D map or on layer params.layer of the array (the same math).
#if MSM_ARRAY
#define MSM_LOOKUP(name) name##_array(shadow_map, params.layer,
#define MSM_FILTERED_UV(uv) float3(uv, float(params.layer))
#else
#define MSM_LOOKUP(name) name(shadow_map,
#define MSM_FILTERED_UV(uv) uv
#endif

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {
    uint i = id.x;
    if (i >= params.count) return;
    Receiver r = receivers[i];
    float zf = msm_internal_depth(r.z, params.zero_one != 0u) - params.depth_bias;
    float2 noise = float2(0.0f, 0.0f);
    if (params.lookup == 2) {
        msm_blue_noise_frame frame;
        frame.texture_index = params.noise_texture;
        frame.offset_x = params.noise_offset_x;
        frame.offset_y = params.noise_offset_y;
        noise = msm_blue_noise_at(blue_noise, frame, r.px, r.py);
    }
#if MSM_FORMAT == 0
    if (params.lookup == 3) {
        float2 uv = float2(r.u / float(params.width), r.v / float(params.height));
        shadow[i] = msm_shadow_moments128_fast(
            msm_decode_moments128(shadow_map.SampleLevel(map_sampler, MSM_FILTERED_UV(uv), 0)), zf);
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
        float2 uv = float2(r.u / float(params.width), r.v / float(params.height));
        shadow[i] =
            msm_shadow_msm64_decoded_fast(msm_decode_msm64(shadow_map.SampleLevel(map_sampler, MSM_FILTERED_UV(uv), 0)), zf);
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
        float2 uv = float2(r.u / float(params.width), r.v / float(params.height));
        shadow[i] = msm_shadow_warped(msm_decode_moments128(shadow_map.SampleLevel(map_sampler, MSM_FILTERED_UV(uv), 0)), zf, warp);
        return;
    }
    shadow[i] = MSM_LOOKUP(msm_lookup_warped) params.width, params.height, r.u, r.v, zf, params.lookup, noise, warp);
#endif
}
