// The HLSL route of soft.comp (shaders/msm.hlsl, glslang's HLSL front end).
#include "msm.hlsl"

[[vk::binding(0)]] Texture2D<uint4> sat_table; // R32G32B32A32_UINT, Load only

struct Receiver {
    float u;
    float v;
    float z;
    uint px;
    uint py;
};
[[vk::binding(2)]] StructuredBuffer<Receiver> receivers;
[[vk::binding(3)]] RWStructuredBuffer<float> shadow;

struct Params {
    int width;
    int height;
    uint count;
    uint scale;
    int search_size;
    float light_size;
    float min_filter_size;
    float max_filter_size;
    float depth_bias;
    uint zero_one;
    float receiver_weight; // SoftShadowOptions::receiver_blocker_weight
    int filter_parts;      // SoftShadowOptions::filter_parts
};
[[vk::push_constant]] ConstantBuffer<Params> params;

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {
    uint i = id.x;
    if (i >= params.count) return;
    Receiver r = receivers[i];
    msm_sat_soft_params p;
    p.width = params.width;
    p.height = params.height;
    p.scale = params.scale;
    p.search_size = params.search_size;
    p.light_size = params.light_size;
    p.min_filter_size = params.min_filter_size;
    p.max_filter_size = params.max_filter_size;
    p.receiver_weight = params.receiver_weight;
    p.filter_parts = params.filter_parts;
    float zf = msm_internal_depth(r.z, params.zero_one != 0u) - params.depth_bias;
    shadow[i] = msm_sat_soft_shadow(sat_table, p, r.u, r.v, zf);
}
