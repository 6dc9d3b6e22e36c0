// Single scattering from msmcl's prefiltered map, sampled with hardware bilinear filtering
// (docs/shaders.md allows it: the decoding is affine), decoded and bounded by shaders/msm.glsl.
// MSM_SCATTER_MOMENTS (set at build time): 6, two A2B10G10R10_UNORM_PACK32 layers (odd and
// even powers); 4, one R16G16B16A16_UNORM image in the msm64 layout. Per camera pixel
// the host gives where its view ray ends in the map (texel units), the rectified depth,
// the bounds blend beta and the unshadowed radiance (kernels/msm_scatter.clh geometry).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "msm.glsl"

layout(local_size_x = 64) in;

#if MSM_SCATTER_MOMENTS == 4
layout(binding = 0) uniform sampler2D moments4;      // linear; rows repeat for a full circle
#else
layout(binding = 0) uniform sampler2DArray moments6; // linear; rows repeat for a full circle
#endif

struct Ray {
    float u;           // texel units along r
    float v;           // texel units along phi
    float zf;          // rectified depth in [-1, 1]
    float beta;        // blend of the bounds
    float unshadowed;  // radiance of the fully lit ray
};
layout(std430, binding = 2) readonly buffer Rays { Ray rays[]; };
layout(std430, binding = 3) writeonly buffer Radiance { float radiance[]; };

layout(push_constant) uniform Params {
    int width;
    int height;
    uint count;
} params;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= params.count) return;
    Ray ray = rays[i];
    vec2 uv = vec2(ray.u / float(params.width), ray.v / float(params.height));
#if MSM_SCATTER_MOMENTS == 4
    float shadow = msm_scatter_shadow4(msm_decode_msm64(textureLod(moments4, uv, 0.0f)), ray.zf, ray.beta);
#else
    vec4 odd = textureLod(moments6, vec3(uv, 0.0f), 0.0f);
    vec4 even = textureLod(moments6, vec3(uv, 1.0f), 0.0f);
    float shadow = msm_scatter_shadow6(msm_decode_moments6(odd, even), ray.zf, ray.beta);
#endif
    radiance[i] = (1.0f - shadow) * ray.unshadowed;
}
