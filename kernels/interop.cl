// Device data in (host/ops/interop.cpp): the S planes of a layered depth image, copied to a
// buffer (plane s = sample s, texels row-major), interleaved into the texel-major layout of
// DeviceDepth: depth[texel * S + s]. Texture arrays: one row of work-items per map (global
// id 1), map m's S planes after those of map m - 1, its texels after those of map m - 1.
__kernel void depth_interleave_layers(__global const float* planes, uint texels, uint samples,
                                      __global float* depth) {
    planes += get_global_id(1) * samples * (size_t)texels;
    depth += get_global_id(1) * samples * (size_t)texels;
    const size_t texel = get_global_id(0);
    if (texel >= texels) return;
    for (uint s = 0; s < samples; ++s) depth[texel * samples + s] = planes[(size_t)s * texels + texel];
}
