// msmcl shader functions (GLSL 4.50): decoding and shading of every texture msmcl writes,
// for renderers that sample the textures themselves. Paste or #include after `#version`.
// shaders/msm.hlsl is generated from this file (cmake -P cmake/glsl_to_hlsl.cmake).
//
// Kept in step with the OpenCL C device functions (kernels/*.clh): the functions carry the
// same names and the same operations in the same order; tests/shaders_test.cpp compiles
// this file with glslangValidator, runs it as C++ on the CPU and compares every function
// with its kernels/*.clh counterpart bit for bit on random inputs.
//
// Textures (include/msmcl/interop.hpp, host/io/gpu_image.hpp) and how to sample them:
//   moments128  RGBA32F            b1..b4; hardware bilinear filtering allowed (linear)
//   msm64       RGBA16_UNORM       affine basis; hardware bilinear filtering allowed (affine)
//   nlq64       RGBA16_UNORM       (y1+1)/2, (y2+1)/2, v2, Psi4: NEAREST only (texelFetch),
//                                  shade four texels and blend the intensities
//   nlq32       R32_UINT           packed: texelFetch, unpack, shade four texels, blend
//   SAT         RGBA32_UINT        wrapping prefix sums: texelFetch only, never filtered
//   6 moments   two RGB10_A2 UNORM odd powers, even powers: bilinear filtering allowed
//   blue noise  RG8UI, 64 x 4096   msmcl::blue_noise_textures() for the dithered lookup
// Texture arrays (cascades): msm_lookup_<format>_array(map, layer, ...) shade a layer of a
// sampler2DArray / usampler2DArray exactly as the 2D lookups shade a 2D map.
// Depths: zf = msm_internal_depth(fragment depth as rendered, 1 for [0,1]) - depth bias.
// Shadow intensity: 0 lit, 1 shadowed.
//
// moments128 and msm64 are shaded with the fast float32 Hamburger 4MSM (the GDC 2016
// HLSL; msm_shadow_*_fast in msm_shading.clh) by msm_lookup_moments128/msm_lookup_msm64.
// msmcl's own shade kernel uses a float-float variant; the fast path loses up to ~1e-3
// (msm64) or up to ~0.5 at sharp contact shadows (moments128, whose float bias 3e-7 is
// below float32 rounding) -- see msm_shading.clh. msm_lookup_moments128_accurate is that
// float-float variant without fused multiply-adds (Dekker's TwoProd, `precise`): it agrees
// with msmcl's kernel to ~3e-7, at several times the arithmetic of the fast path.
// On a GPU, results differ from the CPU by the usual float rounding (no denormals, fused
// multiply-adds where the compiler chooses, approximate exp/log/acos/asin).
#ifndef MSM_GLSL
#define MSM_GLSL

// ---- Constants (msm_moments.clh, msm_shading.clh, msm_sat.clh, msm_scatter.clh).
#define MSM_ALPHA_FLOAT 3e-7f
#define MSM_BSTAR_FLOAT 0.375f
#define MSM_ALPHA_MSM64 6e-5f
#define MSM_BSTAR_MSM64 0.628f
#define MSM_PSI4_L0 (-1.7019833552815005f)
#define MSM_PSI4_L1 2.6900085101561477f
#define MSM_XI4_MAX 0.25f
#define MSM_SQRT3 1.7320508075688772f
#define MSM_NLQ_TOLERANCE 1e-6f
#define MSM_NLQ_MIN_XI4 1e-24f
#define MSM_HAMBURGER_MIN_D33 1e-12f
#define MSM_SAT_ALPHA 5e-6f
#define MSM_SAT_BSTAR MSM_BSTAR_FLOAT
#define MSM_SAT_BLOCKER_EPS 0.01f
#define MSM_SAT_UMBRA_EPS 0.01f
#define MSM_PI 3.14159265358979323846f
#define MSM_SIX_OFFSET_B1 0.018888946f
#define MSM_SCATTER_ALPHA6 4e-3f
#define MSM_SCATTER_BSTAR2 0.5f
#define MSM_SCATTER_BSTAR4 0.375f
#define MSM_SCATTER_BSTAR6 0.3125f
#define MSM_SCATTER_MIN_D33 (0.1f * MSM_SCATTER_ALPHA6 * (MSM_SCATTER_BSTAR6 - MSM_SCATTER_BSTAR4 * MSM_SCATTER_BSTAR4 / MSM_SCATTER_BSTAR2))
#define MSM_SCATTER_MIN_NODE_GAP 1e-6f

// ---- Types.
struct msm_moments {
    float b1;
    float b2;
    float b3;
    float b4;
};
struct msm_nlq {
    float y1;
    float y2;
    float v2;
    float xi4;
};
struct msm_hamburger_bounds {
    float lower;
    float w0;
};
struct msm_bilinear_taps {
    int x0;
    int x1;
    int y0;
    int y1;
    float tx;
    float ty;
};

// ---- Scalars.
float msm_minf(float a, float b) { return a < b ? a : b; }
float msm_maxf(float a, float b) { return a > b ? a : b; }
int msm_clampi(int x, int lo, int hi) { return x < lo ? lo : (x > hi ? hi : x); }
// NaN, tested on the bits (fast-math compilers fold isnan away).
bool msm_is_nan(float x) { return (floatBitsToUint(x) & 0x7fffffffu) > 0x7f800000u; }
float msm_lerp(float a, float b, float t) { return a + t * (b - a); }

// Internal depth z in [-1,1] of a depth as rendered (zero_one: the [0,1] convention).
float msm_internal_depth(float d, bool zero_one) {
    float z = zero_one ? 2.0f * d - 1.0f : d;
    if (msm_is_nan(z)) return -1.0f;
    return clamp(z, -1.0f, 1.0f);
}

// b' = (1 - alpha) b + alpha (0, bstar, 0, bstar).
msm_moments msm_bias(msm_moments b, float alpha, float bstar) {
    msm_moments m;
    float keep = 1.0f - alpha;
    m.b1 = keep * b.b1 + alpha * 0.0f;
    m.b2 = keep * b.b2 + alpha * bstar;
    m.b3 = keep * b.b3 + alpha * 0.0f;
    m.b4 = keep * b.b4 + alpha * bstar;
    return m;
}

// ---- Hamburger 4MSM (Algorithm 1 of Peters, HPG 2017, the GDC 2016 HLSL with the fixes of docs/math.md).
msm_hamburger_bounds msm_hamburger4_factored(float b1, float b2, float d22, float l32, float d33, float zf) {
    msm_hamburger_bounds result;
    float inv_d22 = 1.0f / d22;
    d33 = msm_maxf(d33, MSM_HAMBURGER_MIN_D33);
    float z0 = zf;
    float c0 = 1.0f;
    float c1 = z0 - b1;
    float c2 = z0 * z0 - (b2 + l32 * c1);
    result.w0 = 1.0f / (1.0f + c1 * c1 * inv_d22 + c2 * c2 / d33);
    c1 *= inv_d22;
    c2 /= d33;
    c1 -= l32 * c2;
    c0 -= c1 * b1 + c2 * b2;
    float c2_floor = 1e-18f * msm_maxf(abs(c1), abs(c0)) + 1e-30f;
    if (abs(c2) < c2_floor) c2 = c2 >= 0.0f ? c2_floor : -c2_floor;
    float inv_c2 = 1.0f / c2;
    float half_p = 0.5f * c1 * inv_c2;
    float q = c0 * inv_c2;
    float r = sqrt(msm_maxf(half_p * half_p - q, 0.0f));
    float root_far = half_p > 0.0f ? -half_p - r : -half_p + r;
    float root_near = root_far != 0.0f ? q / root_far : 0.0f;
    float z1 = msm_minf(root_far, root_near);
    float z2 = msm_maxf(root_far, root_near);
    if (z2 < z0) {
        float quotient = (z1 * z2 - b1 * (z1 + z2) + b2) / ((z2 - z0) * (z0 - z1));
        result.lower = clamp(1.0f + quotient, 0.0f, 1.0f);
    } else if (z1 < z0) {
        float quotient = (z0 * z2 - b1 * (z0 + z2) + b2) / ((z2 - z1) * (z0 - z1));
        result.lower = clamp(quotient, 0.0f, 1.0f);
    } else {
        result.lower = 0.0f;
    }
    result.w0 = clamp(result.w0, 0.0f, 1.0f);
    return result;
}

msm_hamburger_bounds msm_hamburger_step(float y, float zf) {
    msm_hamburger_bounds result;
    result.lower = zf > y ? 1.0f : 0.0f;
    result.w0 = zf == y ? 1.0f : 0.0f;
    return result;
}

// Bounds from biased moments (float32 Cholesky pivots).
msm_hamburger_bounds msm_hamburger4(msm_moments b, float zf) {
    float l32_d22 = b.b3 - b.b1 * b.b2;
    float d22 = b.b2 - b.b1 * b.b1;
    float squared_depth_variance = b.b4 - b.b2 * b.b2;
    float d33_d22 = squared_depth_variance * d22 - l32_d22 * l32_d22;
    if (!(d22 > 0.0f)) return msm_hamburger_step(b.b1, zf);
    float inv_d22 = 1.0f / d22;
    return msm_hamburger4_factored(b.b1, b.b2, d22, l32_d22 * inv_d22, d33_d22 * inv_d22, zf);
}

float msm_hamburger4_lower(msm_moments biased, float zf) { return msm_hamburger4(biased, zf).lower; }

float msm_hamburger4_upper(msm_moments biased, float zf) {
    msm_hamburger_bounds bounds = msm_hamburger4(biased, zf);
    return msm_minf(bounds.lower + bounds.w0, 1.0f);
}

// ---- Algorithm 2 (non-linear representation) on biased moments of (z - c).
msm_nlq msm_nlq_single_depth(float y) {
    msm_nlq n;
    n.y1 = y;
    n.y2 = y;
    n.v2 = 0.5f;
    n.xi4 = 0.0f;
    return n;
}

msm_nlq msm_nlq_from_biased_shifted(msm_moments b, float c) {
    float q2 = b.b2 - b.b1 * b.b1;
    float q1 = b.b1 * b.b2 - b.b3;
    float q0 = -b.b1 * q1 - b.b2 * q2;
    float discriminant = q1 * q1 - 4.0f * q2 * q0;
    if (!(q2 > 0.0f) || !(discriminant > 0.0f)) return msm_nlq_single_depth(clamp(b.b1 + c, -1.0f, 1.0f));
    float root_d = sqrt(discriminant);
    float t = -0.5f * (q1 + (q1 >= 0.0f ? root_d : -root_d));
    float root_a = t / q2;
    float root_b = q0 / t;
    float y1 = msm_minf(root_a, root_b);
    float y2 = msm_maxf(root_a, root_b);
    msm_nlq n;
    n.v2 = clamp((b.b1 - y1) / (y2 - y1), 0.0f, 1.0f);
    float l21 = -q1 / q2;
    n.xi4 = clamp(b.b4 - b.b2 * b.b2 - l21 * l21 * q2, 0.0f, MSM_XI4_MAX);
    n.y1 = clamp(y1 + c, -1.0f, 1.0f);
    n.y2 = clamp(y2 + c, -1.0f, 1.0f);
    return n;
}

// ---- Algorithm 3 (lower bound from y1, y2, v2, xi4), overflow-free form of msm_shading.clh.
float msm_nlq_shadow(msm_nlq t, float zf) {
    if (zf <= t.y1) return 0.0f;
    float dy = msm_maxf(t.y2 - t.y1, MSM_NLQ_TOLERANCE);
    float v2 = clamp(t.v2, MSM_NLQ_TOLERANCE, 1.0f - MSM_NLQ_TOLERANCE);
    float v1 = clamp(1.0f - t.v2, MSM_NLQ_TOLERANCE, 1.0f - MSM_NLQ_TOLERANCE);
    float xi = msm_maxf(t.xi4, MSM_NLQ_MIN_XI4);
    bool between = zf <= t.y2;
    float s = msm_minf(zf - t.y1, 4.0f);
    if (between) {
        float zc = msm_minf(s / dy, 1.0f);
        float dy2 = dy * dy;
        float xn = xi / (dy2 * dy2);
        float scale = 1.0f / (1.0f + xn);
        float a = v1 * v2 * zc * (1.0f - zc) * scale;
        float xs = xn * scale;
        float b = xs * (v2 - zc) - a;
        float c = -xs * v2 * (1.0f - zc);
        float root_d = sqrt(b * b - 4.0f * a * c);
        float zl = b > 0.0f ? (-b - root_d) / msm_maxf(2.0f * a, 1e-30f) : 2.0f * c / msm_maxf(root_d - b, 1e-30f);
        s = clamp(zl, -1e6f, 0.0f) * dy;
    }
    float gap = dy - s;
    float dts = dy * gap * s;
    float wl = dy * dy * xi / (xi * (gap * gap / v1 + s * s / v2) + dts * dts);
    return clamp(between ? wl : 1.0f - wl, 0.0f, 1.0f);
}

// ---- Decoding the textures. The 16-bit formats as the texture unit returns them
// (unorm channels = code / 65535), nlq32 as the raw uint.

// Inverse of Psi4.
float msm_psi4_inverse(float psi) {
    if (psi >= 1.0f) return MSM_XI4_MAX;
    return exp(exp(psi * (MSM_PSI4_L1 - MSM_PSI4_L0) + MSM_PSI4_L0)) / 1e7f;
}

msm_moments msm_decode_moments128(vec4 texel) {
    msm_moments m;
    m.b1 = texel.x;
    m.b2 = texel.y;
    m.b3 = texel.z;
    m.b4 = texel.w;
    return m;
}

// msm64: the inverse affine transform of docs/math.md (unbiased moments).
msm_moments msm_decode_msm64(vec4 channels) {
    float r = channels.x - 0.5f;
    float g = channels.y;
    float bl = channels.z - 0.5f;
    float a = channels.w;
    msm_moments m;
    m.b1 = -(1.0f / 3.0f) * r + MSM_SQRT3 * bl;
    m.b2 = 0.125f * g + a;
    m.b3 = -0.75f * r + (0.75f * MSM_SQRT3) * bl;
    m.b4 = -0.125f * g + a;
    return m;
}

msm_nlq msm_decode_nlq64(vec4 channels) {
    msm_nlq n;
    n.y1 = 2.0f * channels.x - 1.0f;
    n.y2 = 2.0f * channels.y - 1.0f;
    n.v2 = channels.z;
    n.xi4 = msm_psi4_inverse(channels.w);
    return n;
}

// nlq32: bits 0-5 ceil(63 Psi4), 6-12 round(127 sqrt(v2)), 13-21 t1, 22-31 t2 (folded depths).
float msm_nlq32_depth_decode(uint yt) { return (float(yt) + 0.5f) / 511.5f - 1.0f; }

msm_nlq msm_decode_nlq32(uint w) {
    uint psi_code = (w >> 0u) & 63u;
    uint sqrt_v2_code = (w >> 6u) & 127u;
    uint t1 = (w >> 13u) & 511u;
    uint t2 = (w >> 22u) & 1023u;
    uint yt1 = t1;
    uint yt2 = t2;
    if (t2 < t1) {
        yt1 = 1023u - t1;
        yt2 = 1022u - t2;
    }
    float sqrt_v2 = float(sqrt_v2_code) / 127.0f;
    msm_nlq n;
    n.y1 = msm_nlq32_depth_decode(yt1);
    n.y2 = msm_nlq32_depth_decode(yt2);
    n.v2 = sqrt_v2 * sqrt_v2;
    n.xi4 = msm_psi4_inverse(float(psi_code) / 63.0f);
    return n;
}

// ---- Shading one texel (or hardware-filtered moments) at internal depth zf.
float msm_shadow_moments128_fast(msm_moments raw, float zf) {
    return msm_hamburger4_lower(msm_bias(raw, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT), zf);
}

float msm_shadow_msm64_decoded_fast(msm_moments decoded, float zf) {
    return msm_hamburger4_lower(msm_bias(decoded, MSM_ALPHA_MSM64, MSM_BSTAR_MSM64), zf);
}

float msm_shadow_nlq64(vec4 channels, float zf) { return msm_nlq_shadow(msm_decode_nlq64(channels), zf); }

float msm_shadow_nlq32(uint w, float zf) { return msm_nlq_shadow(msm_decode_nlq32(w), zf); }

// ---- Lookups (docs/math.md, Lookups), clamped to the edge; u, v in texels.

// Texel floor(coordinate) clamped to [0, size - 1] (NaN -> 0): the nearest lookup.
int msm_texel_index(float coordinate, int size) {
    float c = clamp(coordinate, -1.0f, float(size));
    if (msm_is_nan(coordinate)) c = 0.0f;
    return msm_clampi(int(floor(c)), 0, size - 1);
}

// Dithered lookup: texel floor(coordinate - 0.5 + noise) with blue noise in [0,1), one
// texel per pixel that averages to the bilinear lookup.
int msm_dither_index(float coordinate, float noise, int size) { return msm_texel_index(coordinate - 0.5f + noise, size); }

// The four texel centres around (u - 0.5, v - 0.5) and the weights of x1 and y1.
msm_bilinear_taps msm_bilinear_taps_at(float u, float v, int width, int height) {
    msm_bilinear_taps taps;
    float fx = msm_is_nan(u) ? 0.0f : clamp(u - 0.5f, -1.0f, float(width));
    float fy = msm_is_nan(v) ? 0.0f : clamp(v - 0.5f, -1.0f, float(height));
    float x0 = floor(fx);
    float y0 = floor(fy);
    taps.tx = fx - x0;
    taps.ty = fy - y0;
    taps.x0 = msm_clampi(int(x0), 0, width - 1);
    taps.x1 = msm_clampi(int(x0) + 1, 0, width - 1);
    taps.y0 = msm_clampi(int(y0), 0, height - 1);
    taps.y1 = msm_clampi(int(y0) + 1, 0, height - 1);
    return taps;
}

float msm_bilinear(float v00, float v10, float v01, float v11, float tx, float ty) {
    return msm_lerp(msm_lerp(v00, v10, tx), msm_lerp(v01, v11, tx), ty);
}

msm_moments msm_moments_bilinear(msm_moments m00, msm_moments m10, msm_moments m01, msm_moments m11, float tx,
                                 float ty) {
    msm_moments m;
    m.b1 = msm_bilinear(m00.b1, m10.b1, m01.b1, m11.b1, tx, ty);
    m.b2 = msm_bilinear(m00.b2, m10.b2, m01.b2, m11.b2, tx, ty);
    m.b3 = msm_bilinear(m00.b3, m10.b3, m01.b3, m11.b3, tx, ty);
    m.b4 = msm_bilinear(m00.b4, m10.b4, m01.b4, m11.b4, tx, ty);
    return m;
}

// ---- Blue noise of the dithered lookup (msm_bluenoise.clh): msmcl::blue_noise_textures()
// uploaded once as a 64 x 4096 RG8UI texture (noise texture k in rows 64 k .. 64 k + 63);
// per frame msm_blue_noise_frame_of(frame number) (pass its three values as uniforms), per
// pixel the offsets of the screen pixel (never a resampled position).
struct msm_blue_noise_frame {
    uint texture_index;
    uint offset_x;
    uint offset_y;
};

uint msm_hash32(uint x) {
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

msm_blue_noise_frame msm_blue_noise_frame_of(uint frame) {
    uint bits = msm_hash32(frame + 0x9e3779b9u);
    msm_blue_noise_frame f;
    f.texture_index = bits & 63u;
    f.offset_x = (bits >> 6u) & 63u;
    f.offset_y = (bits >> 12u) & 63u;
    return f;
}

// Dither offset of an 8-bit level: the centre of its interval, in (0, 1).
float msm_blue_noise_value(uint level) { return (float(level) + 0.5f) * (1.0f / 256.0f); }

// The dither offsets (nx, ny) of screen pixel (px, py) in frame f.
vec2 msm_blue_noise_at(usampler2D noise, msm_blue_noise_frame f, uint px, uint py) {
    int x = int((px + f.offset_x) & 63u);
    int y = int(f.texture_index * 64u + ((py + f.offset_y) & 63u));
    uvec4 levels = texelFetch(noise, ivec2(x, y), 0);
    return vec2(msm_blue_noise_value(levels.x), msm_blue_noise_value(levels.y));
}

// Whole lookups on the textures (texelFetch, so every sampler state works): lookup 0
// nearest, 1 bilinear, 2 dithered with `noise` = msm_blue_noise_at(...) of the pixel.
ivec2 msm_lookup_texel(float u, float v, vec2 noise, int lookup, int width, int height) {
    if (lookup == 2) return ivec2(msm_dither_index(u, noise.x, width), msm_dither_index(v, noise.y, height));
    return ivec2(msm_texel_index(u, width), msm_texel_index(v, height));
}

// The bilinear lookup's four texels shaded and blended (c00 at (x0, y0), c10 at (x1, y0),
// c01 at (x0, y1), c11 at (x1, y1)): shared by the lookups on 2D textures and on layers of
// texture arrays, which differ only in how they fetch.
float msm_bilinear_moments128(vec4 c00, vec4 c10, vec4 c01, vec4 c11, msm_bilinear_taps k, float zf) {
    msm_moments m = msm_moments_bilinear(msm_decode_moments128(c00), msm_decode_moments128(c10),
                                         msm_decode_moments128(c01), msm_decode_moments128(c11), k.tx, k.ty);
    return msm_shadow_moments128_fast(m, zf);
}

float msm_bilinear_msm64(vec4 c00, vec4 c10, vec4 c01, vec4 c11, msm_bilinear_taps k, float zf) {
    msm_moments m = msm_moments_bilinear(msm_decode_msm64(c00), msm_decode_msm64(c10), msm_decode_msm64(c01),
                                         msm_decode_msm64(c11), k.tx, k.ty);
    return msm_shadow_msm64_decoded_fast(m, zf);
}

float msm_bilinear_nlq64(vec4 c00, vec4 c10, vec4 c01, vec4 c11, msm_bilinear_taps k, float zf) {
    return msm_bilinear(msm_shadow_nlq64(c00, zf), msm_shadow_nlq64(c10, zf), msm_shadow_nlq64(c01, zf),
                        msm_shadow_nlq64(c11, zf), k.tx, k.ty);
}

float msm_bilinear_nlq32(uint w00, uint w10, uint w01, uint w11, msm_bilinear_taps k, float zf) {
    return msm_bilinear(msm_shadow_nlq32(w00, zf), msm_shadow_nlq32(w10, zf), msm_shadow_nlq32(w01, zf),
                        msm_shadow_nlq32(w11, zf), k.tx, k.ty);
}

float msm_lookup_moments128(sampler2D map, int width, int height, float u, float v, float zf, int lookup, vec2 noise) {
    if (lookup != 1) {
        ivec2 t = msm_lookup_texel(u, v, noise, lookup, width, height);
        return msm_shadow_moments128_fast(msm_decode_moments128(texelFetch(map, ivec2(t.x, t.y), 0)), zf);
    }
    msm_bilinear_taps k = msm_bilinear_taps_at(u, v, width, height);
    return msm_bilinear_moments128(texelFetch(map, ivec2(k.x0, k.y0), 0), texelFetch(map, ivec2(k.x1, k.y0), 0),
                                   texelFetch(map, ivec2(k.x0, k.y1), 0), texelFetch(map, ivec2(k.x1, k.y1), 0), k, zf);
}

float msm_lookup_msm64(sampler2D map, int width, int height, float u, float v, float zf, int lookup, vec2 noise) {
    if (lookup != 1) {
        ivec2 t = msm_lookup_texel(u, v, noise, lookup, width, height);
        return msm_shadow_msm64_decoded_fast(msm_decode_msm64(texelFetch(map, ivec2(t.x, t.y), 0)), zf);
    }
    msm_bilinear_taps k = msm_bilinear_taps_at(u, v, width, height);
    return msm_bilinear_msm64(texelFetch(map, ivec2(k.x0, k.y0), 0), texelFetch(map, ivec2(k.x1, k.y0), 0),
                              texelFetch(map, ivec2(k.x0, k.y1), 0), texelFetch(map, ivec2(k.x1, k.y1), 0), k, zf);
}

float msm_lookup_nlq64(sampler2D map, int width, int height, float u, float v, float zf, int lookup, vec2 noise) {
    if (lookup != 1) {
        ivec2 t = msm_lookup_texel(u, v, noise, lookup, width, height);
        return msm_shadow_nlq64(texelFetch(map, ivec2(t.x, t.y), 0), zf);
    }
    msm_bilinear_taps k = msm_bilinear_taps_at(u, v, width, height);
    return msm_bilinear_nlq64(texelFetch(map, ivec2(k.x0, k.y0), 0), texelFetch(map, ivec2(k.x1, k.y0), 0),
                              texelFetch(map, ivec2(k.x0, k.y1), 0), texelFetch(map, ivec2(k.x1, k.y1), 0), k, zf);
}

float msm_lookup_nlq32(usampler2D map, int width, int height, float u, float v, float zf, int lookup, vec2 noise) {
    if (lookup != 1) {
        ivec2 t = msm_lookup_texel(u, v, noise, lookup, width, height);
        return msm_shadow_nlq32(texelFetch(map, ivec2(t.x, t.y), 0).x, zf);
    }
    msm_bilinear_taps k = msm_bilinear_taps_at(u, v, width, height);
    return msm_bilinear_nlq32(texelFetch(map, ivec2(k.x0, k.y0), 0).x, texelFetch(map, ivec2(k.x1, k.y0), 0).x,
                              texelFetch(map, ivec2(k.x0, k.y1), 0).x, texelFetch(map, ivec2(k.x1, k.y1), 0).x, k, zf);
}

// ---- Texture arrays (a cascaded shadow map's cascades; KTX2 layerCount N bound as a
// VK_IMAGE_VIEW_TYPE_2D_ARRAY view): the lookups above on array layer `layer` of a
// sampler2DArray (usampler2DArray for nlq32), the same texels, decoding and shading.
float msm_lookup_moments128_array(sampler2DArray map, int layer, int width, int height, float u, float v, float zf,
                                  int lookup, vec2 noise) {
    if (lookup != 1) {
        ivec2 t = msm_lookup_texel(u, v, noise, lookup, width, height);
        return msm_shadow_moments128_fast(msm_decode_moments128(texelFetch(map, ivec3(t.x, t.y, layer), 0)), zf);
    }
    msm_bilinear_taps k = msm_bilinear_taps_at(u, v, width, height);
    return msm_bilinear_moments128(texelFetch(map, ivec3(k.x0, k.y0, layer), 0), texelFetch(map, ivec3(k.x1, k.y0, layer), 0),
                                   texelFetch(map, ivec3(k.x0, k.y1, layer), 0), texelFetch(map, ivec3(k.x1, k.y1, layer), 0),
                                   k, zf);
}

float msm_lookup_msm64_array(sampler2DArray map, int layer, int width, int height, float u, float v, float zf,
                             int lookup, vec2 noise) {
    if (lookup != 1) {
        ivec2 t = msm_lookup_texel(u, v, noise, lookup, width, height);
        return msm_shadow_msm64_decoded_fast(msm_decode_msm64(texelFetch(map, ivec3(t.x, t.y, layer), 0)), zf);
    }
    msm_bilinear_taps k = msm_bilinear_taps_at(u, v, width, height);
    return msm_bilinear_msm64(texelFetch(map, ivec3(k.x0, k.y0, layer), 0), texelFetch(map, ivec3(k.x1, k.y0, layer), 0),
                              texelFetch(map, ivec3(k.x0, k.y1, layer), 0), texelFetch(map, ivec3(k.x1, k.y1, layer), 0),
                              k, zf);
}

float msm_lookup_nlq64_array(sampler2DArray map, int layer, int width, int height, float u, float v, float zf,
                             int lookup, vec2 noise) {
    if (lookup != 1) {
        ivec2 t = msm_lookup_texel(u, v, noise, lookup, width, height);
        return msm_shadow_nlq64(texelFetch(map, ivec3(t.x, t.y, layer), 0), zf);
    }
    msm_bilinear_taps k = msm_bilinear_taps_at(u, v, width, height);
    return msm_bilinear_nlq64(texelFetch(map, ivec3(k.x0, k.y0, layer), 0), texelFetch(map, ivec3(k.x1, k.y0, layer), 0),
                              texelFetch(map, ivec3(k.x0, k.y1, layer), 0), texelFetch(map, ivec3(k.x1, k.y1, layer), 0),
                              k, zf);
}

float msm_lookup_nlq32_array(usampler2DArray map, int layer, int width, int height, float u, float v, float zf,
                             int lookup, vec2 noise) {
    if (lookup != 1) {
        ivec2 t = msm_lookup_texel(u, v, noise, lookup, width, height);
        return msm_shadow_nlq32(texelFetch(map, ivec3(t.x, t.y, layer), 0).x, zf);
    }
    msm_bilinear_taps k = msm_bilinear_taps_at(u, v, width, height);
    return msm_bilinear_nlq32(texelFetch(map, ivec3(k.x0, k.y0, layer), 0).x, texelFetch(map, ivec3(k.x1, k.y0, layer), 0).x,
                              texelFetch(map, ivec3(k.x0, k.y1, layer), 0).x, texelFetch(map, ivec3(k.x1, k.y1, layer), 0).x,
                              k, zf);
}

// ---- Accurate moments128 (msm_shadow_moments128 of msm_shading.clh): the fast path above
// loses up to ~0.5 at contact shadows, because moments128's bias (3e-7) is below float32
// rounding. This path takes the moments about their own mean in float-float arithmetic
// (msm_df.clh) as msmcl's shade kernel does (msm_shading.clh counts ~365 against ~70
// flops per nearest lookup with fma; Dekker's product adds 15 per product). Shaders
// cannot count on an exactly fused multiply-add (Vulkan lets fma() round twice; HLSL has
// none for float), so products are split (Veltkamp, Dekker's TwoProd): exact with correctly
// rounded float32 add and multiply, which Vulkan and D3D require. `precise` keeps the
// compiler from contracting or re-associating the error terms (they would fold to zero).
struct msm_df {
    float hi;
    float lo;
};
struct msm_moments_df {
    msm_df b1;
    msm_df b2;
    msm_df b3;
    msm_df b4;
};

msm_df msm_df_make(float hi, float lo) {
    msm_df r;
    r.hi = hi;
    r.lo = lo;
    return r;
}

msm_df msm_df_from_float(float a) { return msm_df_make(a, 0.0f); }

// s + e = a + b exactly (TwoSum).
msm_df msm_two_sum(float a, float b) {
    precise float s = a + b;
    precise float b_virtual = s - a;
    precise float a_virtual = s - b_virtual;
    precise float e = (a - a_virtual) + (b - b_virtual);
    return msm_df_make(s, e);
}

// s + e = a + b exactly for |a| >= |b| or a = 0 (FastTwoSum).
msm_df msm_fast_two_sum(float a, float b) {
    precise float s = a + b;
    precise float e = b - (s - a);
    return msm_df_make(s, e);
}

// a = hi + lo with 12 significant bits in hi (Veltkamp's split, 4097 = 2^12 + 1).
msm_df msm_split(float a) {
    precise float c = 4097.0f * a;
    precise float hi = c - (c - a);
    precise float lo = a - hi;
    return msm_df_make(hi, lo);
}

// p + e = a * b exactly (Dekker's TwoProd; the same pair as msm_df.clh's fma version).
msm_df msm_two_prod(float a, float b) {
    precise float p = a * b;
    msm_df x = msm_split(a);
    msm_df y = msm_split(b);
    precise float e = ((x.hi * y.hi - p) + x.hi * y.lo + x.lo * y.hi) + x.lo * y.lo;
    return msm_df_make(p, e);
}

msm_df msm_df_neg(msm_df a) { return msm_df_make(-a.hi, -a.lo); }

msm_df msm_df_scale_pow2(msm_df a, float s) { return msm_df_make(a.hi * s, a.lo * s); }

// a + b, relative error <= 3u^2 for one sign, absolute ~2u^2 (|a| + |b|) under cancellation.
msm_df msm_df_add_sloppy(msm_df a, msm_df b) {
    msm_df s = msm_two_sum(a.hi, b.hi);
    precise float lo = s.lo + (a.lo + b.lo);
    return msm_fast_two_sum(s.hi, lo);
}

msm_df msm_df_sub_sloppy(msm_df a, msm_df b) { return msm_df_add_sloppy(a, msm_df_neg(b)); }

// a + b for a float b.
msm_df msm_df_add_f(msm_df a, float b) {
    msm_df s = msm_two_sum(a.hi, b);
    precise float lo = a.lo + s.lo;
    return msm_fast_two_sum(s.hi, lo);
}

// a * b for a float b.
msm_df msm_df_mul_f(msm_df a, float b) {
    msm_df c = msm_two_prod(a.hi, b);
    precise float lo = a.lo * b + c.lo;
    return msm_fast_two_sum(c.hi, lo);
}

// a * b.
msm_df msm_df_mul(msm_df a, msm_df b) {
    msm_df c = msm_two_prod(a.hi, b.hi);
    precise float cross = a.lo * b.hi + (a.hi * b.lo + a.lo * b.lo);
    precise float lo = c.lo + cross;
    return msm_fast_two_sum(c.hi, lo);
}

// a + t (b - a) for t in [0,1].
msm_df msm_df_lerp(msm_df a, msm_df b, float t) { return msm_df_add_sloppy(a, msm_df_mul_f(msm_df_sub_sloppy(b, a), t)); }

// The same blend of two floats, held exactly until the product.
msm_df msm_df_lerp_f(float a, float b, float t) { return msm_df_add_f(msm_df_mul_f(msm_two_sum(b, -a), t), a); }

msm_moments_df msm_moments_df_from_float(msm_moments m) {
    msm_moments_df r;
    r.b1 = msm_df_from_float(m.b1);
    r.b2 = msm_df_from_float(m.b2);
    r.b3 = msm_df_from_float(m.b3);
    r.b4 = msm_df_from_float(m.b4);
    return r;
}

// Bilinear blend (x first, then y) of float moments, in float-float.
msm_moments_df msm_moments_df_bilinear_f(msm_moments m00, msm_moments m10, msm_moments m01, msm_moments m11, float tx,
                                         float ty) {
    msm_moments_df m;
    m.b1 = msm_df_lerp(msm_df_lerp_f(m00.b1, m10.b1, tx), msm_df_lerp_f(m01.b1, m11.b1, tx), ty);
    m.b2 = msm_df_lerp(msm_df_lerp_f(m00.b2, m10.b2, tx), msm_df_lerp_f(m01.b2, m11.b2, tx), ty);
    m.b3 = msm_df_lerp(msm_df_lerp_f(m00.b3, m10.b3, tx), msm_df_lerp_f(m01.b3, m11.b3, tx), ty);
    m.b4 = msm_df_lerp(msm_df_lerp_f(m00.b4, m10.b4, tx), msm_df_lerp_f(m01.b4, m11.b4, tx), ty);
    return m;
}

// Moments of z - c from the moments of z (binomial expansion, Horner in u = -c).
msm_moments_df msm_moments_df_about(msm_moments_df b, float c) {
    float u = 0.0f - c;
    msm_moments_df m;
    m.b1 = msm_df_add_f(b.b1, u);
    m.b2 = msm_df_add_sloppy(b.b2, msm_df_mul_f(msm_df_add_f(msm_df_scale_pow2(b.b1, 2.0f), u), u));
    msm_df t = msm_df_add_f(msm_df_mul_f(b.b1, 3.0f), u);
    t = msm_df_add_sloppy(msm_df_mul_f(b.b2, 3.0f), msm_df_mul_f(t, u));
    m.b3 = msm_df_add_sloppy(b.b3, msm_df_mul_f(t, u));
    t = msm_df_add_f(msm_df_scale_pow2(b.b1, 4.0f), u);
    t = msm_df_add_sloppy(msm_df_mul_f(b.b2, 6.0f), msm_df_mul_f(t, u));
    t = msm_df_add_sloppy(msm_df_scale_pow2(b.b3, 4.0f), msm_df_mul_f(t, u));
    m.b4 = msm_df_add_sloppy(b.b4, msm_df_mul_f(t, u));
    return m;
}

// The bias b' = (1 - alpha) b + alpha (0, bstar, 0, bstar) applied to the moments of z - c.
msm_moments_df msm_bias_about_df(msm_moments_df m, float c, float alpha, float bstar) {
    precise float c2 = c * c;
    precise float t1 = 0.0f - c;
    precise float t2 = bstar + c2;
    precise float t3 = 0.0f - c * (3.0f * bstar + c2);
    precise float t4 = bstar + c2 * (6.0f * bstar + c2);
    precise float d1 = alpha * (t1 - m.b1.hi);
    precise float d2 = alpha * (t2 - m.b2.hi);
    precise float d3 = alpha * (t3 - m.b3.hi);
    precise float d4 = alpha * (t4 - m.b4.hi);
    msm_moments_df r;
    r.b1 = msm_df_add_f(m.b1, d1);
    r.b2 = msm_df_add_f(m.b2, d2);
    r.b3 = msm_df_add_f(m.b3, d3);
    r.b4 = msm_df_add_f(m.b4, d4);
    return r;
}

// 4MSM bounds from biased float-float moments of z - c (zf in the same frame).
msm_hamburger_bounds msm_hamburger4_df(msm_moments_df m, float zf) {
    msm_df d22 = msm_df_sub_sloppy(m.b2, msm_df_mul(m.b1, m.b1));
    if (!(d22.hi > 0.0f)) return msm_hamburger_step(m.b1.hi, zf);
    msm_df l32_d22 = msm_df_sub_sloppy(m.b3, msm_df_mul(m.b1, m.b2));
    msm_df d33_d22 = msm_df_sub_sloppy(msm_df_mul(msm_df_sub_sloppy(m.b4, msm_df_mul(m.b2, m.b2)), d22),
                                       msm_df_mul(l32_d22, l32_d22));
    float inv_d22 = 1.0f / d22.hi;
    return msm_hamburger4_factored(m.b1.hi, m.b2.hi, d22.hi, l32_d22.hi * inv_d22, d33_d22.hi * inv_d22, zf);
}

// Lower bound from unbiased moments: about c = b1, biased there, the 4MSM at zf - c.
float msm_shadow_linear_df(msm_moments_df raw, float alpha, float bstar, float zf) {
    float c = raw.b1.hi;
    msm_moments_df biased = msm_bias_about_df(msm_moments_df_about(raw, c), c, alpha, bstar);
    return msm_hamburger4_df(biased, zf - c).lower;
}

float msm_shadow_moments128(msm_moments raw, float zf) {
    return msm_shadow_linear_df(msm_moments_df_from_float(raw), MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT, zf);
}

float msm_shadow_moments128_df(msm_moments_df raw, float zf) {
    return msm_shadow_linear_df(raw, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT, zf);
}

// The bilinear taps of the accurate path (as msm_bilinear_moments128).
float msm_bilinear_moments128_accurate(vec4 c00, vec4 c10, vec4 c01, vec4 c11, msm_bilinear_taps k, float zf) {
    return msm_shadow_moments128_df(msm_moments_df_bilinear_f(msm_decode_moments128(c00), msm_decode_moments128(c10),
                                                              msm_decode_moments128(c01), msm_decode_moments128(c11),
                                                              k.tx, k.ty),
                                    zf);
}

// msm_lookup_moments128 with the accurate path: what msmcl's shade kernel computes.
float msm_lookup_moments128_accurate(sampler2D map, int width, int height, float u, float v, float zf, int lookup,
                                     vec2 noise) {
    if (lookup != 1) {
        ivec2 t = msm_lookup_texel(u, v, noise, lookup, width, height);
        return msm_shadow_moments128(msm_decode_moments128(texelFetch(map, ivec2(t.x, t.y), 0)), zf);
    }
    msm_bilinear_taps k = msm_bilinear_taps_at(u, v, width, height);
    return msm_bilinear_moments128_accurate(texelFetch(map, ivec2(k.x0, k.y0), 0), texelFetch(map, ivec2(k.x1, k.y0), 0),
                                            texelFetch(map, ivec2(k.x0, k.y1), 0), texelFetch(map, ivec2(k.x1, k.y1), 0),
                                            k, zf);
}

// The accurate path on array layer `layer` (texture arrays, as msm_lookup_moments128_array).
float msm_lookup_moments128_accurate_array(sampler2DArray map, int layer, int width, int height, float u, float v,
                                           float zf, int lookup, vec2 noise) {
    if (lookup != 1) {
        ivec2 t = msm_lookup_texel(u, v, noise, lookup, width, height);
        return msm_shadow_moments128(msm_decode_moments128(texelFetch(map, ivec3(t.x, t.y, layer), 0)), zf);
    }
    msm_bilinear_taps k = msm_bilinear_taps_at(u, v, width, height);
    return msm_bilinear_moments128_accurate(texelFetch(map, ivec3(k.x0, k.y0, layer), 0),
                                            texelFetch(map, ivec3(k.x1, k.y0, layer), 0),
                                            texelFetch(map, ivec3(k.x0, k.y1, layer), 0),
                                            texelFetch(map, ivec3(k.x1, k.y1, layer), 0), k, zf);
}

// ---- Summed-area tables and moment soft shadows (msm_sat.clh; docs/math.md).
struct msm_sat_sum {
    uint c0;
    uint c1;
    uint c2;
    uint c3;
};
struct msm_sat_basis {
    float c0;
    float c1;
    float c2;
    float c3;
};
struct msm_sat_axis {
    int i0;
    int i1;
    float w0;
    float w1;
    float w2;
};
struct msm_sat_blockers {
    float shadow;
    float blocker_depth;
};
// Filled from uniforms: map size, scale = floor((2^32 - 1) / N), blocker search side K
// (K^2 <= N), penumbra texels per unit of depth, filter side limits (max <= floor(sqrt(N))),
// the refinements of msmcl's SoftShadowOptions (receiver blocker weight, default 0.1, and
// filter parts per side, default 2; 0 and 1 give the published method).
struct msm_sat_soft_params {
    int width;
    int height;
    uint scale;
    int search_size;
    float light_size;
    float min_filter_size;
    float max_filter_size;
    float receiver_weight;
    int filter_parts;
};

msm_moments msm_sat_moments_of_basis(msm_sat_basis c) {
    float r = c.c0 - 0.5f;
    float bl = c.c2 - 0.5f;
    msm_moments m;
    m.b1 = -(1.0f / 3.0f) * r + MSM_SQRT3 * bl;
    m.b2 = 0.125f * c.c1 + c.c3;
    m.b3 = -0.75f * r + (0.75f * MSM_SQRT3) * bl;
    m.b4 = -0.125f * c.c1 + c.c3;
    return m;
}

msm_sat_sum msm_sat_sum_zero() {
    msm_sat_sum s;
    s.c0 = 0u;
    s.c1 = 0u;
    s.c2 = 0u;
    s.c3 = 0u;
    return s;
}

// a + b - c - d per channel, wrapping.
msm_sat_sum msm_sat_sum_combine(msm_sat_sum a, msm_sat_sum b, msm_sat_sum c, msm_sat_sum d) {
    msm_sat_sum s;
    s.c0 = a.c0 + b.c0 - c.c0 - d.c0;
    s.c1 = a.c1 + b.c1 - c.c1 - d.c1;
    s.c2 = a.c2 + b.c2 - c.c2 - d.c2;
    s.c3 = a.c3 + b.c3 - c.c3 - d.c3;
    return s;
}

// Table entry S(x, y); S(-1, .) = S(., -1) = 0.
msm_sat_sum msm_sat_fetch(usampler2D table, int x, int y) {
    if (x < 0 || y < 0) return msm_sat_sum_zero();
    uvec4 t = texelFetch(table, ivec2(x, y), 0);
    msm_sat_sum s;
    s.c0 = t.x;
    s.c1 = t.y;
    s.c2 = t.z;
    s.c3 = t.w;
    return s;
}

// Sum over the texels [x0, x1] x [y0, y1]: exact when it holds at most N texels.
msm_sat_sum msm_sat_rectangle_sum(usampler2D table, int x0, int y0, int x1, int y1) {
    return msm_sat_sum_combine(msm_sat_fetch(table, x1, y1), msm_sat_fetch(table, x0 - 1, y0 - 1),
                               msm_sat_fetch(table, x0 - 1, y1), msm_sat_fetch(table, x1, y0 - 1));
}

msm_sat_basis msm_sat_mean_of_sum(msm_sat_sum s, uint scale, float texels) {
    float inverse = 1.0f / (float(scale) * texels);
    msm_sat_basis c;
    c.c0 = float(s.c0) * inverse;
    c.c1 = float(s.c1) * inverse;
    c.c2 = float(s.c2) * inverse;
    c.c3 = float(s.c3) * inverse;
    return c;
}

msm_sat_axis msm_sat_axis_of(float low, float high) {
    msm_sat_axis a;
    a.i0 = int(floor(low));
    a.i1 = int(ceil(high)) - 1;
    if (a.i1 < a.i0) a.i1 = a.i0;
    bool spans = a.i1 > a.i0;
    a.w0 = msm_minf(high, float(a.i0 + 1)) - low;
    a.w1 = spans ? 1.0f : 0.0f;
    a.w2 = spans ? high - float(a.i1) : 0.0f;
    return a;
}

// True when each of the 3x3 range sums of an interpolated query holds at most N texels.
bool msm_sat_interpolation_fits(float left, float top, float right, float bottom, uint max_kernel_texels) {
    msm_sat_axis ax = msm_sat_axis_of(left, right);
    msm_sat_axis ay = msm_sat_axis_of(top, bottom);
    uint columns = uint(ax.i1 - ax.i0 > 1 ? ax.i1 - ax.i0 - 1 : 1);
    uint rows = uint(ay.i1 - ay.i0 > 1 ? ay.i1 - ay.i0 - 1 : 1);
    // columns * rows <= N without 64-bit integers.
    return columns <= max_kernel_texels / rows;
}

msm_sat_basis msm_sat_accumulate(msm_sat_basis acc, msm_sat_sum s, float weight) {
    acc.c0 += weight * float(s.c0);
    acc.c1 += weight * float(s.c1);
    acc.c2 += weight * float(s.c2);
    acc.c3 += weight * float(s.c3);
    return acc;
}

// Mean channels over [left, right) x [top, bottom) (texel i covers [i, i + 1)): 4x4 table
// entries, 3x3 exact range sums, each converted to float and weighted by covered area.
msm_sat_basis msm_sat_interpolated_mean(usampler2D table, uint scale, float left, float top, float right,
                                        float bottom) {
    msm_sat_axis ax = msm_sat_axis_of(left, right);
    msm_sat_axis ay = msm_sat_axis_of(top, bottom);
    int ex[4];
    int ey[4];
    ex[0] = ax.i0 - 1;
    ex[1] = ax.i0;
    ex[2] = ax.i1 - 1;
    ex[3] = ax.i1;
    ey[0] = ay.i0 - 1;
    ey[1] = ay.i0;
    ey[2] = ay.i1 - 1;
    ey[3] = ay.i1;
    float wx[3];
    float wy[3];
    wx[0] = ax.w0;
    wx[1] = ax.w1;
    wx[2] = ax.w2;
    wy[0] = ay.w0;
    wy[1] = ay.w1;
    wy[2] = ay.w2;
    msm_sat_sum s[16];
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) s[4 * j + i] = msm_sat_fetch(table, ex[i], ey[j]);
    msm_sat_basis acc;
    acc.c0 = 0.0f;
    acc.c1 = 0.0f;
    acc.c2 = 0.0f;
    acc.c3 = 0.0f;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            msm_sat_sum r = msm_sat_sum_combine(s[4 * (j + 1) + i + 1], s[4 * j + i], s[4 * (j + 1) + i],
                                                s[4 * j + i + 1]);
            acc = msm_sat_accumulate(acc, r, wx[i] * wy[j]);
        }
    float inverse = 1.0f / (float(scale) * (right - left) * (bottom - top));
    acc.c0 *= inverse;
    acc.c1 *= inverse;
    acc.c2 *= inverse;
    acc.c3 *= inverse;
    return acc;
}

// Blocker search: three-depth reconstruction through zf, average blocker depth weighted
// towards zf by eps plus receiver_weight times the weight w0 of the point at zf.
msm_sat_blockers msm_sat_blocker_search(msm_moments biased, float zf, float receiver_weight) {
    msm_hamburger_bounds bounds = msm_hamburger4(biased, zf);
    float rest = 1.0f - bounds.w0;
    msm_sat_blockers result;
    float share = 0.0f;
    float weighted_depth = 0.0f;
    if (rest > 1e-6f) {
        float inverse_rest = 1.0f / rest;
        float zf2 = zf * zf;
        msm_moments two;
        two.b1 = (biased.b1 - bounds.w0 * zf) * inverse_rest;
        two.b2 = (biased.b2 - bounds.w0 * zf2) * inverse_rest;
        two.b3 = (biased.b3 - bounds.w0 * zf2 * zf) * inverse_rest;
        two.b4 = (biased.b4 - bounds.w0 * zf2 * zf2) * inverse_rest;
        msm_nlq points = msm_nlq_from_biased_shifted(two, 0.0f);
        float w_low = rest * (1.0f - points.v2);
        float w_high = rest * points.v2;
        if (points.y1 < zf) {
            share += w_low;
            weighted_depth += w_low * points.y1;
        }
        if (points.y2 < zf) {
            share += w_high;
            weighted_depth += w_high * points.y2;
        }
    }
    result.shadow = share;
    float at_receiver = MSM_SAT_BLOCKER_EPS + receiver_weight * clamp(bounds.w0, 0.0f, 1.0f);
    result.blocker_depth = (at_receiver * zf + weighted_depth) / (at_receiver + share);
    return result;
}

// Biased moments of the texel-aligned square of search_size texels around (u, v), clipped.
msm_moments msm_sat_search_moments(usampler2D table, msm_sat_soft_params p, float u, float v) {
    float start = 0.5f - 0.5f * float(p.search_size);
    int x0 = int(floor(u + start));
    int y0 = int(floor(v + start));
    int x1 = msm_clampi(x0 + p.search_size - 1, 0, p.width - 1);
    int y1 = msm_clampi(y0 + p.search_size - 1, 0, p.height - 1);
    x0 = msm_clampi(x0, 0, p.width - 1);
    y0 = msm_clampi(y0, 0, p.height - 1);
    float texels = float((x1 - x0 + 1) * (y1 - y0 + 1));
    msm_sat_sum s = msm_sat_rectangle_sum(table, x0, y0, x1, y1);
    msm_moments b = msm_sat_moments_of_basis(msm_sat_mean_of_sum(s, p.scale, texels));
    return msm_bias(b, MSM_SAT_ALPHA, MSM_SAT_BSTAR);
}

float msm_sat_filter_size(msm_sat_soft_params p, float zf, float blocker_depth) {
    float penumbra = p.light_size * msm_maxf(zf - blocker_depth, 0.0f);
    return clamp(penumbra, p.min_filter_size, p.max_filter_size);
}

// 4MSM lower bound at zf of the moments over [left, right) x [top, bottom).
float msm_sat_filtered_shadow(usampler2D table, msm_sat_soft_params p, float left, float top, float right,
                              float bottom, float zf) {
    msm_moments b = msm_sat_moments_of_basis(msm_sat_interpolated_mean(table, p.scale, left, top, right, bottom));
    return msm_hamburger4_lower(msm_bias(b, MSM_SAT_ALPHA, MSM_SAT_BSTAR), zf);
}

// Soft shadow (0 lit, 1 shadowed) of a receiver at (u, v) in texels, internal depth zf
// (bias already subtracted).
float msm_sat_soft_shadow(usampler2D table, msm_sat_soft_params p, float u, float v, float zf) {
    u = msm_is_nan(u) ? 0.0f : clamp(u, 0.0f, float(p.width));
    v = msm_is_nan(v) ? 0.0f : clamp(v, 0.0f, float(p.height));
    msm_sat_blockers blockers = msm_sat_blocker_search(msm_sat_search_moments(table, p, u, v), zf, p.receiver_weight);
    if (blockers.shadow > 1.0f - MSM_SAT_UMBRA_EPS) return 1.0f;
    float half_side = 0.5f * msm_sat_filter_size(p, zf, blockers.blocker_depth);
    float left = msm_maxf(u - half_side, 0.0f);
    float right = msm_minf(u + half_side, float(p.width));
    float top = msm_maxf(v - half_side, 0.0f);
    float bottom = msm_minf(v + half_side, float(p.height));
    if (p.filter_parts <= 1) return msm_sat_filtered_shadow(table, p, left, top, right, bottom, zf);
    // n x n equal parts, each its own 4MSM bound, weighted by area.
    float n = float(p.filter_parts);
    float shadow = 0.0f;
    float area = 0.0f;
    for (int j = 0; j < p.filter_parts; ++j)
        for (int i = 0; i < p.filter_parts; ++i) {
            float l = i == 0 ? left : left + (right - left) * (float(i) / n);
            float r = i + 1 == p.filter_parts ? right : left + (right - left) * (float(i + 1) / n);
            float t = j == 0 ? top : top + (bottom - top) * (float(j) / n);
            float b = j + 1 == p.filter_parts ? bottom : top + (bottom - top) * (float(j + 1) / n);
            float part_area = (r - l) * (b - t);
            if (part_area > 0.0f) {
                shadow += part_area * msm_sat_filtered_shadow(table, p, l, t, r, b, zf);
                area += part_area;
            }
        }
    return area > 0.0f ? shadow / area : msm_sat_filtered_shadow(table, p, left, top, right, bottom, zf);
}

// ---- Prefiltered single scattering (msm_scatter.clh; docs/math.md): decoding the
// six-moment textures (two RGB10_A2 unorm, bilinear filtering allowed) and the bounds.
struct msm_moments6 {
    float b1;
    float b2;
    float b3;
    float b4;
    float b5;
    float b6;
};

msm_moments6 msm_decode_moments6(vec4 odd, vec4 even) {
    float r0 = odd.x - 0.5f;
    float g0 = odd.y - 0.5f;
    // Blue: 12 bits, the top 10 in B, the low 2 in A (msm_scatter.clh, msm_pack_unorm10).
    float b0 = (odd.z + odd.w / 1364.0f) - 0.5f;
    float r1 = even.x;
    float g1 = even.y;
    float b1 = (even.z + even.w / 1364.0f) - MSM_SIX_OFFSET_B1;
    msm_moments6 m;
    m.b1 = -0.0287778902855f * r0 + 0.476355509863f * g0 + 1.55242809336f * b0;
    m.b3 = 0.099952358754f * r0 + 0.845325814122f * g0 + 1.05472570851f * b0;
    m.b5 = 0.258933539157f * r0 + 0.907796170821f * g0 + 0.833273356468f * b0;
    m.b2 = 1.25303050231e-05f * r1 + 0.166684941156f * g1 + 0.866025401163f * b1;
    m.b4 = -0.249987469695f * r1 + 0.166684941156f * g1 + 0.866025401163f * b1;
    m.b6 = -0.374988252839f * r1 + 0.218767132334f * g1 + 0.81189881359f * b1;
    return m;
}

float msm_node_gap(float a, float b) {
    float d = a - b;
    if (abs(d) < MSM_SCATTER_MIN_NODE_GAP) d = d < 0.0f ? -MSM_SCATTER_MIN_NODE_GAP : MSM_SCATTER_MIN_NODE_GAP;
    return d;
}

// One Newton step on c0 + c1 x + c2 x^2 + c3 x^3 (skipped where the slope vanishes and
// beyond 1e4).
float msm_cubic_newton(float c0, float c1, float c2, float c3, float x) {
    float f = ((c3 * x + c2) * x + c1) * x + c0;
    float df = (3.0f * c3 * x + 2.0f * c2) * x + c1;
    return df != 0.0f && abs(x) < 1e4f ? x - f / df : x;
}

struct msm_cubic_roots {
    float r1;
    float r2;
    float r3;
};

// The three real roots of k0 + k1 x + k2 x^2 + k3 x^3 in trigonometric form.
msm_cubic_roots msm_cubic_roots_trig(float k0, float k1, float k2, float k3) {
    float largest = msm_maxf(msm_maxf(abs(k0), abs(k1)), abs(k2));
    float k3_floor = 1e-6f * largest + 1e-30f;
    if (abs(k3) < k3_floor) k3 = k3 >= 0.0f ? k3_floor : -k3_floor;
    float inv_k3 = 1.0f / k3;
    float a = k2 * inv_k3;
    float b = k1 * inv_k3;
    float c = k0 * inv_k3;
    float shift = a / 3.0f;
    float p = b - a * shift;
    float q = (2.0f / 27.0f) * a * a * a - a * b / 3.0f + c;
    float m = 2.0f * sqrt(msm_maxf(-p / 3.0f, 0.0f));
    float cos_arg = m > 0.0f ? clamp(3.0f * q / (p * m), -1.0f, 1.0f) : 1.0f;
    float angle = acos(cos_arg) / 3.0f;
    float ca = cos(angle);
    float sa = 0.86602540378443865f * sin(angle);
    msm_cubic_roots roots;
    roots.r1 = m * ca - shift;
    roots.r2 = m * (sa - 0.5f * ca) - shift;
    roots.r3 = m * (-sa - 0.5f * ca) - shift;
    return roots;
}

msm_moments msm_moments6_first4(msm_moments6 a) {
    msm_moments m;
    m.b1 = a.b1;
    m.b2 = a.b2;
    m.b3 = a.b3;
    m.b4 = a.b4;
    return m;
}

// Expectation under the moments b of the cubic through (z0, f0), (z1, f1), (z2, f2), (z3, f3).
float msm_newton_expectation(msm_moments6 b, float z0, float z1, float z2, float z3, float f0, float f1,
                             float f2, float f3) {
    float f01 = (f1 - f0) / msm_node_gap(z1, z0);
    float f12 = (f2 - f1) / msm_node_gap(z2, z1);
    float f23 = (f3 - f2) / msm_node_gap(z3, z2);
    float f012 = (f12 - f01) / msm_node_gap(z2, z0);
    float f123 = (f23 - f12) / msm_node_gap(z3, z1);
    float f0123 = (f123 - f012) / msm_node_gap(z3, z0);
    // p(x) = f0 + f01 (x - z0) + f012 (x - z0)(x - z1) + f0123 (x - z0)(x - z1)(x - z2) in the
    // monomial basis, then E p = p0 + p1 b1 + p2 b2 + p3 b3.
    float p3 = f0123;
    float p2 = f012 - f0123 * (z0 + z1 + z2);
    float p1 = f01 - f012 * (z0 + z1) + f0123 * (z0 * z1 + z0 * z2 + z1 * z2);
    float p0 = f0 - f01 * z0 + f012 * z0 * z1 - f0123 * z0 * z1 * z2;
    return p0 + p1 * b.b1 + p2 * b.b2 + p3 * b.b3;
}

// Six-moment bounds from biased moments: lower and w0, unclamped (four-moment bounds where the
// quantized moments are not valid).
msm_hamburger_bounds msm_hamburger6_bounds(msm_moments6 b, float zf) {
    float d11 = b.b2 - b.b1 * b.b1;
    if (!(d11 > 0.0f)) {
        msm_hamburger_bounds step;
        step.lower = zf > b.b1 ? 1.0f : 0.0f;
        step.w0 = zf == b.b1 ? 1.0f : 0.0f;
        return step;
    }
    float inv_d11 = 1.0f / d11;
    float l21_d11 = b.b3 - b.b1 * b.b2;
    float l21 = l21_d11 * inv_d11;
    float d22 = msm_maxf((b.b4 - b.b2 * b.b2) - l21_d11 * l21, 1e-12f);
    float l31_d11 = b.b4 - b.b1 * b.b3;
    float l31 = l31_d11 * inv_d11;
    float inv_d22 = 1.0f / d22;
    float l32_d22 = (b.b5 - b.b2 * b.b3) - l21_d11 * l31;
    float l32 = l32_d22 * inv_d22;
    float d33 = (b.b6 - b.b3 * b.b3) - l31_d11 * l31 - l32_d22 * l32;
    if (!(d33 > MSM_SCATTER_MIN_D33)) {
        return msm_hamburger4(msm_moments6_first4(b), zf);
    }
    float z0 = zf;
    float c1 = z0 - b.b1;
    float c2 = z0 * z0 - b.b2 - l21 * c1;
    float c3 = z0 * z0 * z0 - b.b3 - l31 * c1 - l32 * c2;
    c1 *= inv_d11;
    c2 *= inv_d22;
    c3 /= d33;
    c2 -= l32 * c3;
    c1 -= l21 * c2 + l31 * c3;
    float c0 = 1.0f - (b.b1 * c1 + b.b2 * c2 + b.b3 * c3);
    // Closed form; the largest root refined by Newton and divided out from the constant
    // term up, the other two from the remaining quadratic, each then one Newton step
    // (msm_scatter.clh: the closed form alone loses the small roots with a far one).
    msm_cubic_roots roots = msm_cubic_roots_trig(c0, c1, c2, c3);
    float far_root = roots.r1;
    if (abs(roots.r2) > abs(far_root)) far_root = roots.r2;
    if (abs(roots.r3) > abs(far_root)) far_root = roots.r3;
    float z1 = roots.r1;
    float z2 = roots.r2;
    float z3 = roots.r3;
    if (abs(far_root) > 1e-6f) {
        far_root = msm_cubic_newton(c0, c1, c2, c3, far_root);
        z3 = far_root;
        // c(x) = (x - R)(a2 x^2 + a1 x + a0) from the constant term.
        float a0 = -c0 / far_root;
        float a1 = (a0 - c1) / far_root;
        float a2 = (a1 - c2) / far_root;
        float discriminant = msm_maxf(a1 * a1 - 4.0f * a2 * a0, 0.0f);
        float half_sum = -0.5f * (a1 + (a1 >= 0.0f ? sqrt(discriminant) : -sqrt(discriminant)));
        z1 = half_sum != 0.0f ? a0 / half_sum : 0.0f;
        z2 = a2 != 0.0f ? half_sum / a2 : z1;
    }
    z1 = msm_cubic_newton(c0, c1, c2, c3, z1);
    z2 = msm_cubic_newton(c0, c1, c2, c3, z2);
    // The farthest root last (it then enters only the divided differences' denominators).
    if (abs(z1) > abs(z3)) {
        float t = z1;
        z1 = z3;
        z3 = t;
    }
    if (abs(z2) > abs(z3)) {
        float t = z2;
        z2 = z3;
        z3 = t;
    }
    // Newton polynomials through (z0, f0), (zk, [zk < z0]): with f0 = 0 the expectation is the
    // lower bound, with f0 = 1 the upper one.
    float f1 = z1 < z0 ? 1.0f : 0.0f;
    float f2 = z2 < z0 ? 1.0f : 0.0f;
    float f3 = z3 < z0 ? 1.0f : 0.0f;
    msm_hamburger_bounds bounds;
    bounds.lower = msm_newton_expectation(b, z0, z1, z2, z3, 0.0f, f1, f2, f3);
    bounds.w0 = msm_newton_expectation(b, z0, z1, z2, z3, 1.0f, f1, f2, f3) - bounds.lower;
    return bounds;
}

// The bounds blended, lower + beta w0, clamped to [0, 1].
float msm_hamburger6_blend(msm_moments6 b, float zf, float beta) {
    msm_hamburger_bounds bounds = msm_hamburger6_bounds(b, zf);
    return clamp(bounds.lower + beta * bounds.w0, 0.0f, 1.0f);
}

// The weight of the bounds' gap: shadow = lower + weight (upper - lower). beta >= 0: beta,
// i.e. beta upper + (1 - beta) lower. beta < 0 (adaptive, msm_scatter_beta): -beta scaled by
// the upper bound itself: a view ray the upper bound calls mostly lit leans to the lower
// bound, one it calls dark (walls between it and the light) to the upper one (docs/math.md;
// docs/methods.md, "Scattering quality", has the measurements).
float msm_scatter_gap_weight(float beta, float upper) {
    return beta >= 0.0f ? beta : -beta * upper;
}

msm_moments6 msm_scatter_bias6(msm_moments6 b) {
    float keep = 1.0f - MSM_SCATTER_ALPHA6;
    msm_moments6 m;
    m.b1 = keep * b.b1;
    m.b2 = keep * b.b2 + MSM_SCATTER_ALPHA6 * MSM_SCATTER_BSTAR2;
    m.b3 = keep * b.b3;
    m.b4 = keep * b.b4 + MSM_SCATTER_ALPHA6 * MSM_SCATTER_BSTAR4;
    m.b5 = keep * b.b5;
    m.b6 = keep * b.b6 + MSM_SCATTER_ALPHA6 * MSM_SCATTER_BSTAR6;
    return m;
}

// Shadow of a view ray at rectified depth zf from prefix-summed moments, blended by beta
// ((1 + dot(light direction, view direction)) / 2 in docs/math.md). The bias distribution
// (arcsine on [-1, 1]) has the share 1/2 + asin(zf) / pi below zf: taken out again, so the
// bounds are those of the stored moments (no uniform leak of up to alpha in full shadow).
float msm_scatter_shadow6(msm_moments6 unbiased, float zf, float beta) {
    msm_hamburger_bounds mixture = msm_hamburger6_bounds(msm_scatter_bias6(unbiased), zf);
    float bias_share_below = 0.5f + asin(clamp(zf, -1.0f, 1.0f)) / MSM_PI;
    float upper = clamp((mixture.lower + mixture.w0 - MSM_SCATTER_ALPHA6 * bias_share_below) / (1.0f - MSM_SCATTER_ALPHA6),
                        0.0f, 1.0f);
    float blend = clamp(mixture.lower + msm_scatter_gap_weight(beta, upper) * mixture.w0, 0.0f, 1.0f);
    return clamp((blend - MSM_SCATTER_ALPHA6 * bias_share_below) / (1.0f - MSM_SCATTER_ALPHA6), 0.0f, 1.0f);
}

// Four moments (msm64 layout): the msm64 bias and the Hamburger 4MSM bounds.
float msm_scatter_shadow4(msm_moments unbiased, float zf, float beta) {
    msm_hamburger_bounds bounds = msm_hamburger4(msm_bias(unbiased, MSM_ALPHA_MSM64, MSM_BSTAR_MSM64), zf);
    float weight = msm_scatter_gap_weight(beta, clamp(bounds.lower + bounds.w0, 0.0f, 1.0f));
    return clamp(bounds.lower + weight * bounds.w0, 0.0f, 1.0f);
}

#endif
