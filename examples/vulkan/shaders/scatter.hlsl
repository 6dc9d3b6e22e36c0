// The HLSL route of scatter.comp (shaders/msm.hlsl, glslang's HLSL front end).
#include "msm.hlsl"

#if MSM_SCATTER_MOMENTS == 4
[[vk::binding(0)]] Texture2D<float4> moments4;      // R16G16B16A16_UNORM, msm64 layout
#else
[[vk::binding(0)]] Texture2DArray<float4> moments6; // 2 layers of A2B10G10R10_UNORM_PACK32
#endif

struct Ray {
    float u;
    float v;
    float zf;
    float beta;
    float unshadowed;
};
[[vk::binding(2)]] StructuredBuffer<Ray> rays;
[[vk::binding(3)]] RWStructuredBuffer<float> radiance;
[[vk::binding(4)]] SamplerState moments_sampler; // linear

struct Params {
    int width;
    int height;
    uint count;
};
[[vk::push_constant]] ConstantBuffer<Params> params;

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {
    uint i = id.x;
    if (i >= params.count) return;
    Ray ray = rays[i];
    float2 uv = float2(ray.u / float(params.width), ray.v / float(params.height));
#if MSM_SCATTER_MOMENTS == 4
    float shadow = msm_scatter_shadow4(msm_decode_msm64(moments4.SampleLevel(moments_sampler, uv, 0)), ray.zf, ray.beta);
#else
    float4 odd = moments6.SampleLevel(moments_sampler, float3(uv, 0.0f), 0);
    float4 even = moments6.SampleLevel(moments_sampler, float3(uv, 1.0f), 0);
    float shadow = msm_scatter_shadow6(msm_decode_moments6(odd, even), ray.zf, ray.beta);
#endif
    radiance[i] = (1.0f - shadow) * ray.unshadowed;
}
