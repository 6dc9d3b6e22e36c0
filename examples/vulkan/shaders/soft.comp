// Moment soft shadows from msmcl's summed-area table, uploaded as R32G32B32A32_UINT and
// read with texelFetch only (the sums wrap modulo 2^32: never filter them).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "msm.glsl"

layout(local_size_x = 64) in;

layout(binding = 0) uniform usampler2D sat_table; // nearest sampler, texelFetch only

struct Receiver {
    float u;
    float v;
    float z;
    uint px;
    uint py;
};
layout(std430, binding = 2) readonly buffer Receivers { Receiver receivers[]; };
layout(std430, binding = 3) writeonly buffer Shadow { float shadow[]; };

layout(push_constant) uniform Params {
    int width;
    int height;
    uint count;
    uint scale;          // floor((2^32 - 1) / N), the table's msmcl:scale
    int search_size;     // blocker search side K
    float light_size;    // penumbra texels per unit of internal depth
    float min_filter_size;
    float max_filter_size; // floor(sqrt(N))
    float depth_bias;
    uint zero_one;
    float receiver_weight; // SoftShadowOptions::receiver_blocker_weight
    int filter_parts;      // SoftShadowOptions::filter_parts
} params;

void main() {
    uint i = gl_GlobalInvocationID.x;
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
