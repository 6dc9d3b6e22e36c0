// The shader snippets (shaders/msm.glsl, shaders/msm.hlsl):
//  - msm.hlsl is exactly what cmake/glsl_to_hlsl.cmake generates from msm.glsl;
//  - both compile with glslangValidator (GLSL to SPIR-V for Vulkan and for OpenGL, HLSL
//    through glslang's HLSL front end), in a compute shader that calls every lookup;
//  - both run on the CPU as C++ (a small shim gives the GLSL/HLSL types, intrinsics and
//    texel fetches) and agree bit for bit with the OpenCL C device functions of
//    kernels/*.clh compiled as C++ on random inputs: the same operations in the same order;
//  - a batch is also evaluated by those device functions on the OpenCL device and compared
//    with the GLSL functions run on the CPU (tolerance below).
// Not covered: running the SPIR-V on a GPU (no Vulkan or GL device in CI). On a GPU the
// results differ by the GPU's float rounding (see the GLSL file's header).
// Seed: MSMCL_TEST_SEED (default 6), printed.
#include "kernels/msm_filterable_shading.clh"
#include "kernels/msm_sat.clh"
#include "kernels/msm_scatter.clh"
#include "runtime/kernel_sources.hpp"
#include "runtime/opencl.hpp"

#include <msmcl/context.hpp>
#include <msmcl/device_math.hpp>
#include <msmcl/shade.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

// ---- The GLSL file as C++: GLSL's types, intrinsics and texelFetch on host arrays.
// `precise` (no contraction or re-association) is what C++ does anyway without -ffast-math.
#define precise
namespace glsl_shader {
using std::acos;
using std::asin;
using std::sin;
using std::ceil;
using std::cos;
using std::exp;
using std::floor;
using std::log;
using std::sqrt;
inline float abs(float x) { return std::fabs(x); }
inline float clamp(float x, float lo, float hi) { return std::fmin(std::fmax(x, lo), hi); }
inline unsigned floatBitsToUint(float f) {
    unsigned u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}
inline float uintBitsToFloat(unsigned u) {
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
}
using uint = unsigned;
struct vec2 {
    float x, y;
    explicit vec2(float s) : x(s), y(s) {}
    vec2(float a, float b) : x(a), y(b) {}
};
struct vec4 {
    float x, y, z, w;
    vec4(float a, float b, float c, float d) : x(a), y(b), z(c), w(d) {}
};
struct uvec4 {
    unsigned x, y, z, w;
};
struct ivec2 {
    int x, y;
    ivec2(int a, int b) : x(a), y(b) {}
};
// Row-major texels: 4 floats, or `channels` (1, 2 or 4) uints.
struct sampler2D {
    const float* texels;
    int width;
};
struct usampler2D {
    const unsigned* texels;
    int width;
    int channels;
};
inline vec4 texelFetch(const sampler2D& t, ivec2 at, int) {
    const float* p = t.texels + 4 * (static_cast<std::size_t>(at.y) * t.width + at.x);
    return vec4(p[0], p[1], p[2], p[3]);
}
inline uvec4 texelFetch(const usampler2D& t, ivec2 at, int) {
    const unsigned* p = t.texels + t.channels * (static_cast<std::size_t>(at.y) * t.width + at.x);
    if (t.channels == 1) return uvec4{p[0], 0u, 0u, 1u};
    if (t.channels == 2) return uvec4{p[0], p[1], 0u, 1u};
    return uvec4{p[0], p[1], p[2], p[3]};
}
// Texture arrays: layer after layer of width x height texels.
struct ivec3 {
    int x, y, z;
    ivec3(int a, int b, int c) : x(a), y(b), z(c) {}
};
struct sampler2DArray {
    const float* texels;
    int width;
    int height;
};
struct usampler2DArray {
    const unsigned* texels;
    int width;
    int height;
};
inline vec4 texelFetch(const sampler2DArray& t, ivec3 at, int) {
    return texelFetch(sampler2D{t.texels + 4 * static_cast<std::size_t>(at.z) * t.width * t.height, t.width},
                      ivec2(at.x, at.y), 0);
}
inline uvec4 texelFetch(const usampler2DArray& t, ivec3 at, int) {
    return texelFetch(usampler2D{t.texels + static_cast<std::size_t>(at.z) * t.width * t.height, t.width, 1},
                      ivec2(at.x, at.y), 0);
}
#include "shaders/msm.glsl"
} // namespace glsl_shader

// ---- The HLSL file as C++.
namespace hlsl_shader {
using std::acos;
using std::asin;
using std::sin;
using std::ceil;
using std::cos;
using std::exp;
using std::floor;
using std::log;
using std::sqrt;
inline float abs(float x) { return std::fabs(x); }
inline float clamp(float x, float lo, float hi) { return std::fmin(std::fmax(x, lo), hi); }
inline unsigned asuint(float f) {
    unsigned u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}
inline float asfloat(unsigned u) {
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
}
using uint = unsigned;
struct float2 {
    float x, y;
    float2(float a, float b) : x(a), y(b) {}
};
struct float4 {
    float x, y, z, w;
    float4(float a, float b, float c, float d) : x(a), y(b), z(c), w(d) {}
};
struct uint4 {
    unsigned x, y, z, w;
};
struct int2 {
    int x, y;
    int2(int a, int b) : x(a), y(b) {}
};
struct int3 {
    int x, y, z;
    int3(int a, int b, int c) : x(a), y(b), z(c) {}
};
template <class Texel>
struct Texture2D;
template <>
struct Texture2D<float4> {
    const float* texels;
    int width;
    float4 Load(int3 at) const {
        const float* p = texels + 4 * (static_cast<std::size_t>(at.y) * width + at.x);
        return float4(p[0], p[1], p[2], p[3]);
    }
};
template <>
struct Texture2D<uint4> {
    const unsigned* texels;
    int width;
    int channels;
    uint4 Load(int3 at) const {
        const unsigned* p = texels + channels * (static_cast<std::size_t>(at.y) * width + at.x);
        if (channels == 1) return uint4{p[0], 0u, 0u, 1u};
        if (channels == 2) return uint4{p[0], p[1], 0u, 1u};
        return uint4{p[0], p[1], p[2], p[3]};
    }
};
// Texture arrays (one channel for uint4: nlq32): layer after layer of width x height texels.
struct int4 {
    int x, y, z, w;
    int4(int a, int b, int c, int d) : x(a), y(b), z(c), w(d) {}
};
template <class Texel>
struct Texture2DArray;
template <>
struct Texture2DArray<float4> {
    const float* texels;
    int width;
    int height;
    float4 Load(int4 at) const {
        return Texture2D<float4>{texels + 4 * static_cast<std::size_t>(at.z) * width * height, width}.Load(
            int3(at.x, at.y, 0));
    }
};
template <>
struct Texture2DArray<uint4> {
    const unsigned* texels;
    int width;
    int height;
    uint4 Load(int4 at) const {
        return Texture2D<uint4>{texels + static_cast<std::size_t>(at.z) * width * height, width, 1}.Load(
            int3(at.x, at.y, 0));
    }
};
#include "shaders/msm.hlsl"
} // namespace hlsl_shader

namespace {

namespace fs = std::filesystem;

unsigned test_seed() {
    static const unsigned seed = [] {
        const char* text = std::getenv("MSMCL_TEST_SEED");
        const unsigned value = text ? static_cast<unsigned>(std::strtoul(text, nullptr, 10)) : 6u;
        std::printf("shaders_test: seed %u (MSMCL_TEST_SEED overrides)\n", value);
        return value;
    }();
    return seed;
}

std::string read_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// ---- One adapter per shading language: kernels/*.clh types in, kernels/*.clh types out.
// Textures are passed as host arrays (4 floats or 4/1 uints per texel, row-major).
#define MSMCL_SHADER_ADAPTER(Name, ns, vec2_t, vec4_t, sampler_t, usampler_t, usampler_make)                          \
    struct Name {                                                                                                    \
        static const char* name() { return #ns; }                                                                    \
        static ns::msm_moments moments(const msm_moments& b) { return ns::msm_moments{b.b1, b.b2, b.b3, b.b4}; }    \
        static ns::msm_nlq nlq(const msm_nlq& n) { return ns::msm_nlq{n.y1, n.y2, n.v2, n.xi4}; }                    \
        static msm_moments back(const ns::msm_moments& b) { return msm_moments{b.b1, b.b2, b.b3, b.b4}; }           \
        static msm_nlq back(const ns::msm_nlq& n) { return msm_nlq{n.y1, n.y2, n.v2, n.xi4}; }                       \
        static vec4_t unorm16(msm_word2 w) {                                                                         \
            return vec4_t(float(w.w0 & 0xffffu) / 65535.0f, float(w.w0 >> 16) / 65535.0f,                           \
                          float(w.w1 & 0xffffu) / 65535.0f, float(w.w1 >> 16) / 65535.0f);                           \
        }                                                                                                            \
        static msm_hamburger_bounds hamburger4(const msm_moments& b, float zf) {                                     \
            const ns::msm_hamburger_bounds r = ns::msm_hamburger4(moments(b), zf);                                   \
            return msm_hamburger_bounds{r.lower, r.w0};                                                              \
        }                                                                                                            \
        static float hamburger4_upper(const msm_moments& b, float zf) {                                              \
            return ns::msm_hamburger4_upper(moments(b), zf);                                                         \
        }                                                                                                            \
        static msm_nlq nlq_from_biased_shifted(const msm_moments& b, float c) {                                      \
            return back(ns::msm_nlq_from_biased_shifted(moments(b), c));                                             \
        }                                                                                                            \
        static float nlq_shadow(const msm_nlq& n, float zf) { return ns::msm_nlq_shadow(nlq(n), zf); }              \
        static float psi4_inverse(float psi) { return ns::msm_psi4_inverse(psi); }                                   \
        static float internal_depth(float d, int zero_one) { return ns::msm_internal_depth(d, zero_one != 0); }      \
        static msm_moments decode_msm64(msm_word2 w) { return back(ns::msm_decode_msm64(unorm16(w))); }              \
        static msm_nlq decode_nlq64(msm_word2 w) { return back(ns::msm_decode_nlq64(unorm16(w))); }                  \
        static msm_nlq decode_nlq32(unsigned w) { return back(ns::msm_decode_nlq32(w)); }                            \
        static float shadow_moments128_fast(const msm_moments& b, float zf) {                                        \
            return ns::msm_shadow_moments128_fast(moments(b), zf);                                                   \
        }                                                                                                            \
        static float shadow_msm64_fast(msm_word2 w, float zf) {                                                      \
            return ns::msm_shadow_msm64_decoded_fast(ns::msm_decode_msm64(unorm16(w)), zf);                          \
        }                                                                                                            \
        static float shadow_nlq64(msm_word2 w, float zf) { return ns::msm_shadow_nlq64(unorm16(w), zf); }           \
        static float shadow_nlq32(unsigned w, float zf) { return ns::msm_shadow_nlq32(w, zf); }                     \
        static int texel_index(float c, int size) { return ns::msm_texel_index(c, size); }                          \
        static int dither_index(float c, float noise, int size) { return ns::msm_dither_index(c, noise, size); }    \
        static msm_blue_noise_frame blue_noise_frame_of(unsigned frame) {                                            \
            const ns::msm_blue_noise_frame f = ns::msm_blue_noise_frame_of(frame);                                   \
            return msm_blue_noise_frame{f.texture_index, f.offset_x, f.offset_y};                                    \
        }                                                                                                            \
        static vec2_t blue_noise_at(const unsigned* table, const msm_blue_noise_frame& f, unsigned px,             \
                                    unsigned py) {                                                                   \
            const ns::msm_blue_noise_frame g{f.texture, f.offset_x, f.offset_y};                                     \
            return ns::msm_blue_noise_at(usampler_make(table, 64, 2), g, px, py);                                    \
        }                                                                                                            \
        static msm_bilinear_taps taps(float u, float v, int w, int h) {                                              \
            const ns::msm_bilinear_taps t = ns::msm_bilinear_taps_at(u, v, w, h);                                    \
            return msm_bilinear_taps{t.x0, t.x1, t.y0, t.y1, t.tx, t.ty};                                            \
        }                                                                                                            \
        static float lookup_moments128(const float* texels, int w, int h, float u, float v, float zf, int lookup,   \
                                       float nx, float ny) {                                                         \
            return ns::msm_lookup_moments128(sampler_t{texels, w}, w, h, u, v, zf, lookup, vec2_t(nx, ny));          \
        }                                                                                                            \
        static float lookup_msm64(const float* texels, int w, int h, float u, float v, float zf, int lookup,        \
                                  float nx, float ny) {                                                              \
            return ns::msm_lookup_msm64(sampler_t{texels, w}, w, h, u, v, zf, lookup, vec2_t(nx, ny));               \
        }                                                                                                            \
        static float lookup_nlq64(const float* texels, int w, int h, float u, float v, float zf, int lookup,        \
                                  float nx, float ny) {                                                              \
            return ns::msm_lookup_nlq64(sampler_t{texels, w}, w, h, u, v, zf, lookup, vec2_t(nx, ny));               \
        }                                                                                                            \
        static float lookup_nlq32(const unsigned* texels, int w, int h, float u, float v, float zf, int lookup,     \
                                  float nx, float ny) {                                                              \
            return ns::msm_lookup_nlq32(usampler_make(texels, w, 1), w, h, u, v, zf, lookup, vec2_t(nx, ny));       \
        }                                                                                                            \
        static ns::msm_warp_shading warp(const msm_warp_shading& s) {                                               \
            return ns::msm_warp_shading_make(s.representation, s.positive, s.negative, s.min_variance,             \
                                             s.light_bleed_reduction);                                               \
        }                                                                                                            \
        static float shadow_warped(const msm_moments& b, float zf, const msm_warp_shading& s) {                      \
            return ns::msm_shadow_warped(moments(b), zf, warp(s));                                                   \
        }                                                                                                            \
        static float lookup_warped(const float* texels, int w, int h, float u, float v, float zf, int lookup,       \
                                   float nx, float ny, const msm_warp_shading& s) {                                  \
            return ns::msm_lookup_warped(sampler_t{texels, w}, w, h, u, v, zf, lookup, vec2_t(nx, ny), warp(s));    \
        }                                                                                                            \
        static msm_sat_sum sat_rectangle_sum(const unsigned* table, int w, int x0, int y0, int x1, int y1) {         \
            const ns::msm_sat_sum s = ns::msm_sat_rectangle_sum(usampler_make(table, w, 4), x0, y0, x1, y1);        \
            return msm_sat_sum{s.c0, s.c1, s.c2, s.c3};                                                              \
        }                                                                                                            \
        static msm_sat_basis sat_interpolated_mean(const unsigned* table, int w, unsigned scale, float l, float t,  \
                                                   float r, float b) {                                               \
            const ns::msm_sat_basis m = ns::msm_sat_interpolated_mean(usampler_make(table, w, 4), scale, l, t, r, b); \
            return msm_sat_basis{m.c0, m.c1, m.c2, m.c3};                                                            \
        }                                                                                                            \
        static int sat_interpolation_fits(float l, float t, float r, float b, unsigned n) {                         \
            return ns::msm_sat_interpolation_fits(l, t, r, b, n) ? 1 : 0;                                            \
        }                                                                                                            \
        static float sat_soft_shadow(const unsigned* table, const msm_sat_soft_params& p, float u, float v,         \
                                     float zf) {                                                                     \
            const ns::msm_sat_soft_params q{p.width,           p.height,          p.scale,          p.search_size,   \
                                            p.light_size,      p.min_filter_size, p.max_filter_size,                 \
                                            p.receiver_weight, p.filter_parts};                                      \
            return ns::msm_sat_soft_shadow(usampler_make(table, p.width, 4), q, u, v, zf);                           \
        }                                                                                                            \
        static ns::msm_moments6 moments6(const msm_moments6& b) {                                                    \
            return ns::msm_moments6{b.b1, b.b2, b.b3, b.b4, b.b5, b.b6};                                             \
        }                                                                                                            \
        static msm_moments6 decode_moments6(msm_word_pair w) {                                                       \
            const auto unorm10 = [](unsigned word, int c) { return float((word >> (10 * c)) & 1023u) / 1023.0f; };  \
            const ns::msm_moments6 m = ns::msm_decode_moments6(                                                      \
                vec4_t(unorm10(w.odd, 0), unorm10(w.odd, 1), unorm10(w.odd, 2), float(w.odd >> 30) / 3.0f),         \
                vec4_t(unorm10(w.even, 0), unorm10(w.even, 1), unorm10(w.even, 2), float(w.even >> 30) / 3.0f));     \
            return msm_moments6{m.b1, m.b2, m.b3, m.b4, m.b5, m.b6};                                                 \
        }                                                                                                            \
        static float hamburger6_blend(const msm_moments6& b, float zf, float beta) {                                 \
            return ns::msm_hamburger6_blend(moments6(b), zf, beta);                                                  \
        }                                                                                                            \
        static float scatter_shadow6(const msm_moments6& b, float zf, float beta) {                                  \
            return ns::msm_scatter_shadow6(moments6(b), zf, beta);                                                   \
        }                                                                                                            \
        static float scatter_shadow4(const msm_moments& b, float zf, float beta) {                                   \
            return ns::msm_scatter_shadow4(moments(b), zf, beta);                                                    \
        }                                                                                                            \
    };

glsl_shader::usampler2D make_glsl_usampler(const unsigned* texels, int width, int channels) {
    return glsl_shader::usampler2D{texels, width, channels};
}
hlsl_shader::Texture2D<hlsl_shader::uint4> make_hlsl_usampler(const unsigned* texels, int width, int channels) {
    return hlsl_shader::Texture2D<hlsl_shader::uint4>{texels, width, channels};
}
MSMCL_SHADER_ADAPTER(Glsl, glsl_shader, glsl_shader::vec2, glsl_shader::vec4, glsl_shader::sampler2D,
                     glsl_shader::usampler2D, make_glsl_usampler)
MSMCL_SHADER_ADAPTER(Hlsl, hlsl_shader, hlsl_shader::float2, hlsl_shader::float4,
                     hlsl_shader::Texture2D<hlsl_shader::float4>, hlsl_shader::Texture2D<hlsl_shader::uint4>,
                     make_hlsl_usampler)

// ---- Random inputs.

// Moments of 1 to 4 depths with random weights (valid), about 1 in 8 a single depth.
msm_moments random_moments(std::mt19937& random) {
    std::uniform_real_distribution<float> depth(-1.0f, 1.0f), unit(0.0f, 1.0f);
    const int points = 1 + static_cast<int>(random() % 4);
    double b[4] = {0, 0, 0, 0}, total = 0;
    const float base = depth(random);
    for (int i = 0; i < points; ++i) {
        // Clusters near one depth as well as spread ones.
        const double z = (random() % 2) ? base + 0.01 * unit(random) : depth(random);
        const double w = 0.05 + unit(random);
        total += w;
        for (int k = 0; k < 4; ++k) b[k] += w * std::pow(std::min(1.0, z), k + 1);
    }
    return msm_moments{float(b[0] / total), float(b[1] / total), float(b[2] / total), float(b[3] / total)};
}

msm_nlq random_nlq(std::mt19937& random) {
    std::uniform_real_distribution<float> depth(-1.0f, 1.0f), unit(0.0f, 1.0f);
    float y1 = depth(random), y2 = depth(random);
    if (y1 > y2) std::swap(y1, y2);
    if (random() % 8 == 0) y2 = y1 + 1e-7f * unit(random);
    const float xi4 = random() % 8 == 0 ? 0.0f : 0.25f * std::pow(unit(random), 6.0f);
    return msm_nlq{y1, y2, unit(random), xi4};
}

float random_zf(std::mt19937& random, float near) {
    std::uniform_real_distribution<float> depth(-1.0f, 1.0f), offset(-0.02f, 0.02f);
    return random() % 2 ? depth(random) : std::max(-1.0f, std::min(1.0f, near + offset(random)));
}

constexpr int kCases = 20000;

template <class Shader>
class ShaderLanguage : public ::testing::Test {};
using Languages = ::testing::Types<Glsl, Hlsl>;
class LanguageNames {
public:
    template <class T>
    static std::string GetName(int) {
        return T::name();
    }
};
TYPED_TEST_SUITE(ShaderLanguage, Languages, LanguageNames);

TYPED_TEST(ShaderLanguage, MomentMathMatchesTheDeviceFunctions) {
    std::mt19937 random(test_seed());
    for (int i = 0; i < kCases; ++i) {
        const msm_moments raw = random_moments(random);
        const msm_moments biased = msm_bias(raw, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT);
        const float zf = random_zf(random, raw.b1);
        const msm_hamburger_bounds expected = msm_hamburger4(biased, zf);
        const msm_hamburger_bounds actual = TypeParam::hamburger4(biased, zf);
        ASSERT_TRUE(same_bits(actual.lower, expected.lower) && same_bits(actual.w0, expected.w0))
            << "case " << i << " zf " << zf << ": " << actual.lower << " " << actual.w0 << " vs " << expected.lower
            << " " << expected.w0;
        ASSERT_TRUE(same_bits(TypeParam::hamburger4_upper(biased, zf), msm_hamburger4_upper(biased, zf))) << i;
        ASSERT_TRUE(same_bits(TypeParam::shadow_moments128_fast(raw, zf), msm_shadow_moments128_fast(raw, zf))) << i;
        const float c = random() % 2 ? 0.0f : raw.b1;
        const msm_nlq n_expected = msm_nlq_from_biased_shifted(biased, c);
        const msm_nlq n_actual = TypeParam::nlq_from_biased_shifted(biased, c);
        ASSERT_TRUE(same_bits(n_actual.y1, n_expected.y1) && same_bits(n_actual.y2, n_expected.y2) &&
                    same_bits(n_actual.v2, n_expected.v2) && same_bits(n_actual.xi4, n_expected.xi4))
            << i;
        const msm_nlq nlq = random_nlq(random);
        const float zn = random_zf(random, random() % 2 ? nlq.y1 : nlq.y2);
        ASSERT_TRUE(same_bits(TypeParam::nlq_shadow(nlq, zn), msm_nlq_shadow(nlq, zn)))
            << "case " << i << " y1 " << nlq.y1 << " y2 " << nlq.y2 << " v2 " << nlq.v2 << " xi4 " << nlq.xi4;
        const float d = std::uniform_real_distribution<float>(-1.5f, 1.5f)(random);
        ASSERT_TRUE(same_bits(TypeParam::internal_depth(d, i % 2), msm_internal_depth(d, i % 2))) << d;
        const float psi = std::uniform_real_distribution<float>(0.0f, 1.0f)(random);
        ASSERT_TRUE(same_bits(TypeParam::psi4_inverse(psi), msm_psi4_inverse(psi))) << psi;
    }
    ASSERT_TRUE(same_bits(TypeParam::internal_depth(NAN, 1), msm_internal_depth(NAN, 1)));
}

TYPED_TEST(ShaderLanguage, DecodersAndTexelShadingMatchTheDeviceFunctions) {
    std::mt19937 random(test_seed() + 1);
    const auto same_moments = [](const msm_moments& a, const msm_moments& b) {
        return same_bits(a.b1, b.b1) && same_bits(a.b2, b.b2) && same_bits(a.b3, b.b3) && same_bits(a.b4, b.b4);
    };
    const auto same_nlq = [](const msm_nlq& a, const msm_nlq& b) {
        return same_bits(a.y1, b.y1) && same_bits(a.y2, b.y2) && same_bits(a.v2, b.v2) && same_bits(a.xi4, b.xi4);
    };
    for (int i = 0; i < kCases; ++i) {
        // Random codes, and codes of real texels (random moments encoded).
        const msm_moments raw = random_moments(random);
        const msm_word2 words = i % 2 ? msm_word2{static_cast<uint>(random()), static_cast<uint>(random())}
                                      : msm_encode_msm64(raw);
        const msm_word2 nlq_words =
            i % 2 ? words : msm_encode_nlq64(msm_nlq_from_moments(msm_bias(raw, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT)));
        const uint word32 = i % 2 ? static_cast<uint>(random())
                                  : msm_encode_nlq32(msm_nlq_from_moments(msm_bias(raw, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT)));
        const float zf = random_zf(random, raw.b1);
        ASSERT_TRUE(same_moments(TypeParam::decode_msm64(words), msm_decode_msm64(words))) << i;
        ASSERT_TRUE(same_nlq(TypeParam::decode_nlq64(nlq_words), msm_decode_nlq64(nlq_words))) << i;
        ASSERT_TRUE(same_nlq(TypeParam::decode_nlq32(word32), msm_decode_nlq32(word32))) << i;
        ASSERT_TRUE(same_bits(TypeParam::shadow_msm64_fast(words, zf), msm_shadow_msm64_fast(words, zf))) << i;
        ASSERT_TRUE(same_bits(TypeParam::shadow_nlq64(nlq_words, zf), msm_shadow_nlq64(nlq_words, zf))) << i;
        ASSERT_TRUE(same_bits(TypeParam::shadow_nlq32(word32, zf), msm_shadow_nlq32(word32, zf))) << i;
    }
}

// The whole lookups on random textures: nearest and bilinear against the composition of
// the device functions that kernels/shade.cl makes (with the fast 4MSM for the linear
// formats), dithered against docs/math.md directly.
TYPED_TEST(ShaderLanguage, LookupsMatchTheShadeKernelsComposition) {
    std::mt19937 random(test_seed() + 2);
    const int width = 13, height = 9;
    std::vector<msm_moments> raw(width * height);
    std::vector<float> moments128, msm64, nlq64;
    std::vector<uint> nlq32, msm64_words, nlq64_words;
    for (msm_moments& m : raw) {
        m = random_moments(random);
        const msm_word2 w = msm_encode_msm64(m);
        const msm_nlq n = msm_nlq_from_moments(msm_bias(m, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT));
        const msm_word2 v = msm_encode_nlq64(n);
        moments128.insert(moments128.end(), {m.b1, m.b2, m.b3, m.b4});
        msm64_words.insert(msm64_words.end(), {w.w0, w.w1});
        nlq64_words.insert(nlq64_words.end(), {v.w0, v.w1});
        // The unorm channels a texture unit returns for the 16-bit codes.
        const auto push_channels = [](std::vector<float>& channels, const msm_word2& x) {
            channels.insert(channels.end(), {float(x.w0 & 0xffffu) / 65535.0f, float(x.w0 >> 16) / 65535.0f,
                                             float(x.w1 & 0xffffu) / 65535.0f, float(x.w1 >> 16) / 65535.0f});
        };
        push_channels(msm64, w);
        push_channels(nlq64, v);
        nlq32.push_back(msm_encode_nlq32(n));
    }
    const auto at = [&](int x, int y) { return static_cast<std::size_t>(y) * width + x; };
    const auto w2 = [](const std::vector<uint>& words, std::size_t t) { return msm_word2{words[2 * t], words[2 * t + 1]}; };
    std::uniform_real_distribution<float> coordinate(-2.0f, 16.0f), unit(0.0f, 0.999f);
    for (int i = 0; i < 4000; ++i) {
        const float u = coordinate(random), v = coordinate(random);
        const float zf = random_zf(random, raw[at(msm_texel_index(u, width), msm_texel_index(v, height))].b1);
        // nearest
        const int x = msm_texel_index(u, width), y = msm_texel_index(v, height);
        ASSERT_EQ(TypeParam::texel_index(u, width), x);
        ASSERT_TRUE(same_bits(TypeParam::lookup_moments128(moments128.data(), width, height, u, v, zf, 0, 0, 0),
                              msm_shadow_moments128_fast(raw[at(x, y)], zf)));
        ASSERT_TRUE(same_bits(TypeParam::lookup_msm64(msm64.data(), width, height, u, v, zf, 0, 0, 0),
                              msm_shadow_msm64_fast(w2(msm64_words, at(x, y)), zf)));
        ASSERT_TRUE(same_bits(TypeParam::lookup_nlq64(nlq64.data(), width, height, u, v, zf, 0, 0, 0),
                              msm_shadow_nlq64(w2(nlq64_words, at(x, y)), zf)));
        ASSERT_TRUE(same_bits(TypeParam::lookup_nlq32(nlq32.data(), width, height, u, v, zf, 0, 0, 0),
                              msm_shadow_nlq32(nlq32[at(x, y)], zf)));
        // bilinear
        const msm_bilinear_taps k = msm_bilinear_taps_at(u, v, width, height);
        const msm_bilinear_taps kk = TypeParam::taps(u, v, width, height);
        ASSERT_TRUE(kk.x0 == k.x0 && kk.x1 == k.x1 && kk.y0 == k.y0 && kk.y1 == k.y1 && same_bits(kk.tx, k.tx) &&
                    same_bits(kk.ty, k.ty));
        const std::size_t t00 = at(k.x0, k.y0), t10 = at(k.x1, k.y0), t01 = at(k.x0, k.y1), t11 = at(k.x1, k.y1);
        ASSERT_TRUE(same_bits(
            TypeParam::lookup_moments128(moments128.data(), width, height, u, v, zf, 1, 0, 0),
            msm_shadow_moments128_fast(msm_moments_bilinear(raw[t00], raw[t10], raw[t01], raw[t11], k.tx, k.ty), zf)));
        const auto decoded = [&](std::size_t t) { return msm_decode_msm64(w2(msm64_words, t)); };
        ASSERT_TRUE(same_bits(TypeParam::lookup_msm64(msm64.data(), width, height, u, v, zf, 1, 0, 0),
                              msm_shadow_msm64_decoded_fast(
                                  msm_moments_bilinear(decoded(t00), decoded(t10), decoded(t01), decoded(t11), k.tx, k.ty),
                                  zf)));
        const auto nlq64_shadow = [&](std::size_t t) { return msm_shadow_nlq64(w2(nlq64_words, t), zf); };
        ASSERT_TRUE(same_bits(TypeParam::lookup_nlq64(nlq64.data(), width, height, u, v, zf, 1, 0, 0),
                              msm_bilinear(nlq64_shadow(t00), nlq64_shadow(t10), nlq64_shadow(t01), nlq64_shadow(t11),
                                           k.tx, k.ty)));
        const auto nlq32_shadow = [&](std::size_t t) { return msm_shadow_nlq32(nlq32[t], zf); };
        ASSERT_TRUE(same_bits(TypeParam::lookup_nlq32(nlq32.data(), width, height, u, v, zf, 1, 0, 0),
                              msm_bilinear(nlq32_shadow(t00), nlq32_shadow(t10), nlq32_shadow(t01), nlq32_shadow(t11),
                                           k.tx, k.ty)));
        // dithered: texel floor(u - 0.5 + n), clamped to the edge (docs/math.md, Lookups)
        const float nx = unit(random), ny = unit(random);
        const int dx = std::clamp(static_cast<int>(std::floor(u - 0.5f + nx)), 0, width - 1);
        const int dy = std::clamp(static_cast<int>(std::floor(v - 0.5f + ny)), 0, height - 1);
        ASSERT_EQ(TypeParam::dither_index(u, nx, width), dx) << u << " " << nx;
        ASSERT_EQ(TypeParam::dither_index(u, nx, width), msm_dither_index(u, nx, width));
        ASSERT_TRUE(same_bits(TypeParam::lookup_nlq32(nlq32.data(), width, height, u, v, zf, 2, nx, ny),
                              msm_shadow_nlq32(nlq32[at(dx, dy)], zf)));
    }
    ASSERT_EQ(TypeParam::texel_index(NAN, width), msm_texel_index(NAN, width));
}

// VSM, EVSM and ESM (msm_filterable_shading.clh): the shading of random stored values and the whole
// lookups on random textures of each representation (channels as a texture unit returns
// them: floats) against the composition of the device functions that kernels/shade.cl makes.
TYPED_TEST(ShaderLanguage, FilterableLookupsMatchTheDeviceFunctions) {
    std::mt19937 random(test_seed() + 7);
    const msm_warp_shading shadings[] = {msm_warp_shading_vsm(1e-5f, 0.0f), msm_warp_shading_vsm(1e-4f, 0.3f),
                                         msm_warp_shading_evsm2(5.54f, 1e-5f, 0.15f),
                                         msm_warp_shading_evsm4(5.54f, 5.54f, 1e-5f, 0.0f),
                                         msm_warp_shading_evsm4(40.0f, 5.0f, 1e-7f, 0.15f), msm_warp_shading_esm(80.0f)};
    const int width = 11, height = 7;
    std::uniform_real_distribution<float> depth(0.0f, 1.0f), coordinate(-2.0f, 14.0f), unit(0.0f, 0.999f);
    for (const msm_warp_shading& s : shadings) {
        // Each texel: the mean of the warps of two random depths (a filtered texel).
        std::vector<float> texels;
        std::vector<msm_moments> stored;
        for (int t = 0; t < width * height; ++t) {
            msm_moments m = {0, 0, 0, 0};
            for (int k = 0; k < 2; ++k) {
                const float x = 2.0f * depth(random) - 1.0f;
                const float p = std::exp(s.positive * x), n = -std::exp(-s.negative * x);
                const float e = std::exp(s.positive * 0.5f * (x - 1.0f));
                const msm_moments w = s.representation == MSM_WARP_VSM ? msm_moments{0.5f * x + 0.5f, (0.5f * x + 0.5f) * (0.5f * x + 0.5f), 0, 0}
                                      : s.representation == MSM_WARP_ESM ? msm_moments{e, 0, 0, 0}
                                                                         : msm_moments{p, p * p, n, n * n};
                m.b1 += 0.5f * w.b1, m.b2 += 0.5f * w.b2, m.b3 += 0.5f * w.b3, m.b4 += 0.5f * w.b4;
            }
            stored.push_back(m);
            texels.insert(texels.end(), {m.b1, m.b2, m.b3, m.b4});
        }
        const auto at = [&](int x, int y) { return static_cast<std::size_t>(y) * width + x; };
        for (int i = 0; i < 2000; ++i) {
            const float u = coordinate(random), v = coordinate(random), zf = 2.0f * depth(random) - 1.0f;
            const int x = msm_texel_index(u, width), y = msm_texel_index(v, height);
            ASSERT_TRUE(same_bits(TypeParam::shadow_warped(stored[at(x, y)], zf, s), msm_shadow_warped(stored[at(x, y)], zf, s)));
            ASSERT_TRUE(same_bits(TypeParam::lookup_warped(texels.data(), width, height, u, v, zf, 0, 0, 0, s),
                                  msm_shadow_warped(stored[at(x, y)], zf, s)));
            const msm_bilinear_taps k = msm_bilinear_taps_at(u, v, width, height);
            const msm_moments blend = msm_moments_bilinear(stored[at(k.x0, k.y0)], stored[at(k.x1, k.y0)],
                                                           stored[at(k.x0, k.y1)], stored[at(k.x1, k.y1)], k.tx, k.ty);
            ASSERT_TRUE(same_bits(TypeParam::lookup_warped(texels.data(), width, height, u, v, zf, 1, 0, 0, s),
                                  msm_shadow_warped(blend, zf, s)))
                << "representation " << s.representation << " case " << i;
            const float nx = unit(random), ny = unit(random);
            const int dx = msm_dither_index(u, nx, width), dy = msm_dither_index(v, ny, height);
            ASSERT_TRUE(same_bits(TypeParam::lookup_warped(texels.data(), width, height, u, v, zf, 2, nx, ny, s),
                                  msm_shadow_warped(stored[at(dx, dy)], zf, s)));
        }
    }
}

// The blue noise of the dithered lookup: frames, and the offsets of screen pixels read from
// msmcl::blue_noise_textures() as the 64 x 4096 two-channel texture the shaders expect.
TYPED_TEST(ShaderLanguage, BlueNoiseMatchesTheDeviceFunctions) {
    std::mt19937 random(test_seed() + 6);
    const std::uint8_t* bytes = msmcl::blue_noise_textures();
    ASSERT_EQ(msmcl::blue_noise_bytes(), 64u * 4096u * 2u);
    const std::vector<unsigned> table(bytes, bytes + msmcl::blue_noise_bytes());
    for (int i = 0; i < 4000; ++i) {
        const unsigned frame = i < 100 ? static_cast<unsigned>(i) : static_cast<unsigned>(random());
        const msm_blue_noise_frame expected = msm_blue_noise_frame_of(frame);
        const msm_blue_noise_frame actual = TypeParam::blue_noise_frame_of(frame);
        ASSERT_TRUE(actual.texture == expected.texture && actual.offset_x == expected.offset_x &&
                    actual.offset_y == expected.offset_y)
            << frame;
        const unsigned px = random() % 4000, py = random() % 3000;
        const uint t = msm_blue_noise_texel(expected, px, py);
        const auto noise = TypeParam::blue_noise_at(table.data(), expected, px, py);
        ASSERT_TRUE(same_bits(noise.x, msm_blue_noise_value(bytes[2 * t])) &&
                    same_bits(noise.y, msm_blue_noise_value(bytes[2 * t + 1])))
            << "frame " << frame << " pixel " << px << ", " << py;
    }
}

// Summed-area tables: random wrapping tables (any table exercises the queries).
TYPED_TEST(ShaderLanguage, SatQueriesAndSoftShadowsMatchTheDeviceFunctions) {
    std::mt19937 random(test_seed() + 3);
    const int width = 40, height = 30;
    const uint n = 15 * 15, scale = msm_sat_scale(n);
    // Texels of real moments, then the wrapping prefix sums.
    std::vector<uint> table(4 * width * height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const msm_sat_sum t = msm_sat_texel_of_moments(random_moments(random), scale);
            const uint value[4] = {t.c0, t.c1, t.c2, t.c3};
            for (int c = 0; c < 4; ++c) {
                uint sum = value[c];
                if (x > 0) sum += table[4 * (y * width + x - 1) + c];
                if (y > 0) sum += table[4 * ((y - 1) * width + x) + c];
                if (x > 0 && y > 0) sum -= table[4 * ((y - 1) * width + x - 1) + c];
                table[4 * (y * width + x) + c] = sum;
            }
        }
    std::uniform_real_distribution<float> position(0.0f, 1.0f), size(0.2f, 15.0f);
    int interpolated = 0, penumbra = 0;
    for (int i = 0; i < 4000; ++i) {
        const int x0 = static_cast<int>(random() % width), y0 = static_cast<int>(random() % height);
        const int x1 = std::min(width - 1, x0 + static_cast<int>(random() % 15));
        const int y1 = std::min(height - 1, y0 + static_cast<int>(random() % 15));
        const msm_sat_sum e = msm_sat_rectangle_sum(table.data(), width, x0, y0, x1, y1);
        const msm_sat_sum a = TypeParam::sat_rectangle_sum(table.data(), width, x0, y0, x1, y1);
        ASSERT_TRUE(a.c0 == e.c0 && a.c1 == e.c1 && a.c2 == e.c2 && a.c3 == e.c3) << i;

        const float left = position(random) * (width - 1), top = position(random) * (height - 1);
        const float right = std::min(float(width), left + size(random));
        const float bottom = std::min(float(height), top + size(random));
        const int fits = msm_sat_interpolation_fits(left, top, right, bottom, n);
        ASSERT_EQ(TypeParam::sat_interpolation_fits(left, top, right, bottom, n), fits);
        ASSERT_EQ(TypeParam::sat_interpolation_fits(left, top, left + 40.0f, top + 30.0f, 3u),
                  msm_sat_interpolation_fits(left, top, left + 40.0f, top + 30.0f, 3u));
        if (fits) {
            ++interpolated;
            const msm_sat_basis em = msm_sat_interpolated_mean(table.data(), width, scale, left, top, right, bottom);
            const msm_sat_basis am = TypeParam::sat_interpolated_mean(table.data(), width, scale, left, top, right, bottom);
            ASSERT_TRUE(same_bits(am.c0, em.c0) && same_bits(am.c1, em.c1) && same_bits(am.c2, em.c2) &&
                        same_bits(am.c3, em.c3))
                << i;
        }
        // The published method and its refinements in turns.
        const msm_sat_soft_params p = msm_sat_soft_params_refine(
            msm_sat_soft_params_make(width, height, scale, 15, 40.0f, 1.0f, 15.0f), i % 2 ? 0.1f : 0.0f, 1 + i % 3);
        const float u = position(random) * width, v = position(random) * height;
        const float zf = std::uniform_real_distribution<float>(-1.0f, 1.0f)(random);
        const float shadow = msm_sat_soft_shadow(table.data(), p, u, v, zf);
        ASSERT_TRUE(same_bits(TypeParam::sat_soft_shadow(table.data(), p, u, v, zf), shadow))
            << "u " << u << " v " << v << " zf " << zf;
        penumbra += shadow > 0.0f && shadow < 1.0f;
    }
    // The cases exercise the interpolated query and partial shadows, not only the ends.
    EXPECT_GT(interpolated, 1000);
    EXPECT_GT(penumbra, 400);
}

TYPED_TEST(ShaderLanguage, SingleScatteringMatchesTheDeviceFunctions) {
    std::mt19937 random(test_seed() + 4);
    std::uniform_real_distribution<float> depth(-1.0f, 1.0f), unit(0.0f, 1.0f);
    for (int i = 0; i < kCases; ++i) {
        // Six moments of 1 to 3 depths, quantized and decoded as the textures hold them.
        msm_moments6 b = msm_moments6_zero();
        const int points = 1 + static_cast<int>(random() % 3);
        for (int k = 0; k < points; ++k) b = msm_moments6_add_scaled(b, msm_moments6_of(depth(random)), 1.0f / points);
        const msm_word_pair words = i % 4 == 0 ? msm_word_pair{static_cast<uint>(random()), static_cast<uint>(random())}
                                               : msm_encode_moments6(b);
        const msm_moments6 e = msm_decode_moments6(words);
        const msm_moments6 a = TypeParam::decode_moments6(words);
        ASSERT_TRUE(same_bits(a.b1, e.b1) && same_bits(a.b2, e.b2) && same_bits(a.b3, e.b3) && same_bits(a.b4, e.b4) &&
                    same_bits(a.b5, e.b5) && same_bits(a.b6, e.b6))
            << i;
        const float zf = depth(random), beta = unit(random);
        ASSERT_TRUE(same_bits(TypeParam::scatter_shadow6(e, zf, beta), msm_scatter_shadow6(e, zf, beta))) << i;
        ASSERT_TRUE(same_bits(TypeParam::hamburger6_blend(msm_scatter_bias6(b), zf, beta),
                              msm_hamburger6_blend(msm_scatter_bias6(b), zf, beta)))
            << i;
        const msm_moments four = msm_moments6_first4(b);
        ASSERT_TRUE(same_bits(TypeParam::scatter_shadow4(four, zf, beta), msm_scatter_shadow4(four, zf, beta))) << i;
    }
}

// ---- msm.hlsl is generated from msm.glsl.
// The accurate moments128 path of the shaders (float-float with Dekker's TwoProd, no fma)
// against msm_shading.clh's (TwoProd by fma): the product pairs are the same exact pairs;
// only the low parts of DWTimesFP/DWTimesDW round differently (a * b + c against fma), an
// error of ~u^2 relative. On moments of contact shadows, where the fast float32 path is off
// by up to ~0.5, both agree to within 1e-5.
TEST(ShaderFunctions, AccurateMoments128MatchesTheDeviceFunctions) {
    std::mt19937 random(test_seed());
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    double largest = 0, largest_fast = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        // Moments of two or three depths, often nearly equal (contact shadows, flat regions).
        msm_moments texel[4];
        for (msm_moments& m : texel) {
            const float base = unit(random) * 2.0f - 1.0f;
            const float spread = trial % 2 ? 1e-3f * unit(random) : unit(random);
            double b[4] = {0, 0, 0, 0};
            const int depths = 2 + trial % 2;
            for (int k = 0; k < depths; ++k) {
                const double z = std::clamp(base + spread * (unit(random) - 0.5f), -1.0f, 1.0f);
                for (int p = 0; p < 4; ++p) b[p] += std::pow(z, p + 1) / depths;
            }
            m = msm_moments{float(b[0]), float(b[1]), float(b[2]), float(b[3])};
        }
        const float zf = texel[0].b1 + (unit(random) - 0.5f) * (trial % 3 ? 2e-3f : 0.5f);
        const float tx = unit(random), ty = unit(random);
        const auto as_glsl = [](const msm_moments& m) { return glsl_shader::msm_moments{m.b1, m.b2, m.b3, m.b4}; };
        const auto as_hlsl = [](const msm_moments& m) { return hlsl_shader::msm_moments{m.b1, m.b2, m.b3, m.b4}; };
        const float device = msm_shadow_moments128(texel[0], zf);
        const float device_bilinear = msm_shadow_moments128_bilinear(texel[0], texel[1], texel[2], texel[3], tx, ty, zf);
        const float glsl = glsl_shader::msm_shadow_moments128(as_glsl(texel[0]), zf);
        const float hlsl = hlsl_shader::msm_shadow_moments128(as_hlsl(texel[0]), zf);
        const float glsl_bilinear = glsl_shader::msm_shadow_moments128_df(
            glsl_shader::msm_moments_df_bilinear_f(as_glsl(texel[0]), as_glsl(texel[1]), as_glsl(texel[2]),
                                                   as_glsl(texel[3]), tx, ty),
            zf);
        ASSERT_TRUE(same_bits(glsl, hlsl)) << "trial " << trial;
        largest = std::max({largest, std::fabs(double(glsl) - device), std::fabs(double(glsl_bilinear) - device_bilinear)});
        largest_fast = std::max(largest_fast, std::fabs(double(msm_shadow_moments128_fast(texel[0], zf)) - device));
    }
    std::printf("accurate moments128: shaders vs msm_shading.clh max %.3g (fast path: %.3g)\n", largest, largest_fast);
    EXPECT_LE(largest, 1e-5);
}

// The texture-array lookups read layer `layer` and shade it as the 2D lookups shade a
// texture holding that layer alone: bit for bit, every format and lookup, GLSL and HLSL.
TEST(ShaderFunctions, ArrayLookupsEqualTheLookupsOfTheLayer) {
    std::mt19937 random(test_seed());
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::uniform_int_distribution<unsigned> word;
    const int width = 13, height = 9, layers = 3;
    const std::size_t texels = static_cast<std::size_t>(width) * height;
    // Moments of one depth per texel (moments128), unorm16 channels (msm64, nlq64), packed words (nlq32).
    std::vector<float> moments(4 * texels * layers), channels(4 * texels * layers);
    std::vector<unsigned> words(texels * layers);
    for (std::size_t i = 0; i < texels * layers; ++i) {
        const float z = unit(random) * 2.0f - 1.0f;
        moments[4 * i] = z, moments[4 * i + 1] = z * z, moments[4 * i + 2] = z * z * z, moments[4 * i + 3] = z * z * z * z;
        for (int c = 0; c < 4; ++c) channels[4 * i + c] = float(word(random) & 0xffffu) / 65535.0f;
        words[i] = word(random);
    }
    int compared = 0;
    for (int layer = 0; layer < layers; ++layer) {
        const float* moment_layer = moments.data() + 4 * texels * layer;
        const float* channel_layer = channels.data() + 4 * texels * layer;
        const unsigned* word_layer = words.data() + texels * layer;
        for (int trial = 0; trial < 200; ++trial) {
            const float u = unit(random) * (width + 2) - 1, v = unit(random) * (height + 2) - 1;
            const float zf = unit(random) * 2.0f - 1.0f, nx = unit(random), ny = unit(random);
            for (int lookup = 0; lookup < 3; ++lookup) {
                SCOPED_TRACE("layer " + std::to_string(layer) + ", lookup " + std::to_string(lookup));
                namespace g = glsl_shader;
                namespace h = hlsl_shader;
                using HFloats = h::Texture2DArray<h::float4>;
                using HWords = h::Texture2DArray<h::uint4>;
                const g::vec2 gn(nx, ny);
                const h::float2 hn(nx, ny);
                const float expected[6] = {
                    g::msm_lookup_moments128(g::sampler2D{moment_layer, width}, width, height, u, v, zf, lookup, gn),
                    g::msm_lookup_msm64(g::sampler2D{channel_layer, width}, width, height, u, v, zf, lookup, gn),
                    g::msm_lookup_nlq64(g::sampler2D{channel_layer, width}, width, height, u, v, zf, lookup, gn),
                    g::msm_lookup_nlq32(g::usampler2D{word_layer, width, 1}, width, height, u, v, zf, lookup, gn),
                    g::msm_lookup_moments128_accurate(g::sampler2D{moment_layer, width}, width, height, u, v, zf, lookup,
                                                      gn),
                    g::msm_lookup_warped(g::sampler2D{moment_layer, width}, width, height, u, v, zf, lookup, gn,
                                         g::msm_warp_shading_evsm4(5.54f, 5.54f, 1e-5f, 0.15f))};
                const g::sampler2DArray gm{moments.data(), width, height}, gc{channels.data(), width, height};
                const g::usampler2DArray gw{words.data(), width, height};
                const float glsl[6] = {
                    g::msm_lookup_moments128_array(gm, layer, width, height, u, v, zf, lookup, gn),
                    g::msm_lookup_msm64_array(gc, layer, width, height, u, v, zf, lookup, gn),
                    g::msm_lookup_nlq64_array(gc, layer, width, height, u, v, zf, lookup, gn),
                    g::msm_lookup_nlq32_array(gw, layer, width, height, u, v, zf, lookup, gn),
                    g::msm_lookup_moments128_accurate_array(gm, layer, width, height, u, v, zf, lookup, gn),
                    g::msm_lookup_warped_array(gm, layer, width, height, u, v, zf, lookup, gn,
                                               g::msm_warp_shading_evsm4(5.54f, 5.54f, 1e-5f, 0.15f))};
                const HFloats hm{moments.data(), width, height}, hc{channels.data(), width, height};
                const HWords hw{words.data(), width, height};
                const float hlsl[6] = {
                    h::msm_lookup_moments128_array(hm, layer, width, height, u, v, zf, lookup, hn),
                    h::msm_lookup_msm64_array(hc, layer, width, height, u, v, zf, lookup, hn),
                    h::msm_lookup_nlq64_array(hc, layer, width, height, u, v, zf, lookup, hn),
                    h::msm_lookup_nlq32_array(hw, layer, width, height, u, v, zf, lookup, hn),
                    h::msm_lookup_moments128_accurate_array(hm, layer, width, height, u, v, zf, lookup, hn),
                    h::msm_lookup_warped_array(hm, layer, width, height, u, v, zf, lookup, hn,
                                               h::msm_warp_shading_evsm4(5.54f, 5.54f, 1e-5f, 0.15f))};
                for (int f = 0; f < 6; ++f) {
                    ASSERT_TRUE(same_bits(glsl[f], expected[f])) << "function " << f << ": " << glsl[f] << " vs " << expected[f];
                    ASSERT_TRUE(same_bits(hlsl[f], expected[f])) << "function " << f << ": " << hlsl[f] << " vs " << expected[f];
                    ++compared;
                }
            }
        }
    }
    std::printf("texture-array lookups: %d results equal to the 2D lookups of their layer\n", compared);
}

TEST(ShaderFiles, HlslIsGeneratedFromGlsl) {
    const fs::path source = MSMCL_SOURCE_DIR, shaders = MSMCL_SHADER_DIR;
    const fs::path generated = fs::temp_directory_path() / ("msmcl-msm-" + std::to_string(::getpid()) + ".hlsl");
    const std::string command = std::string("'") + MSMCL_CMAKE_COMMAND + "' -DINPUT='" +
                                (shaders / "msm.glsl").string() + "' -DOUTPUT='" + generated.string() +
                                "' -P '" + (source / "cmake" / "glsl_to_hlsl.cmake").string() + "'";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    const std::string expected = read_text(generated);
    fs::remove(generated);
    const std::string checked_in = read_text(shaders / "msm.hlsl");
    ASSERT_FALSE(expected.empty());
    EXPECT_TRUE(checked_in == expected)
        << "shaders/msm.hlsl is out of date: cmake -DINPUT=shaders/msm.glsl -DOUTPUT=shaders/msm.hlsl -P "
           "cmake/glsl_to_hlsl.cmake";
}

// ---- glslangValidator: every function type-checked and the lookups compiled in context.
#ifdef MSMCL_GLSLANG_VALIDATOR
const char* kGlslMain = R"(
layout(local_size_x = 1) in;
layout(binding = 0) uniform sampler2D moments128_map;
layout(binding = 1) uniform sampler2D msm64_map;
layout(binding = 2) uniform sampler2D nlq64_map;
layout(binding = 3) uniform usampler2D nlq32_map;
layout(binding = 4) uniform usampler2D sat_table;
layout(binding = 5) uniform sampler2D moments6_odd;
layout(binding = 6) uniform sampler2D moments6_even;
layout(binding = 8) uniform usampler2D blue_noise;
layout(binding = 9) uniform sampler2DArray float_array;
layout(binding = 10) uniform usampler2DArray uint_array;
layout(std430, binding = 7) buffer Results { float results[]; };
void main() {
    float zf = msm_internal_depth(0.5f, true) - 1e-3f;
    vec2 noise = msm_blue_noise_at(blue_noise, msm_blue_noise_frame_of(17u), gl_GlobalInvocationID.x, 3u);
    for (int lookup = 0; lookup < 3; ++lookup) {
        results[4 * lookup + 0] = msm_lookup_moments128(moments128_map, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
        results[4 * lookup + 1] = msm_lookup_msm64(msm64_map, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
        results[4 * lookup + 2] = msm_lookup_nlq64(nlq64_map, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
        results[4 * lookup + 3] = msm_lookup_nlq32(nlq32_map, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
    }
    msm_sat_soft_params p;
    p.width = 16;
    p.height = 16;
    p.scale = 0xffffffffu / 729u;
    p.search_size = 27;
    p.light_size = 64.0f;
    p.min_filter_size = 1.0f;
    p.max_filter_size = 27.0f;
    p.receiver_weight = 0.1f;
    p.filter_parts = 2;
    results[12] = msm_sat_soft_shadow(sat_table, p, 3.2f, 4.7f, zf);
    vec2 uv = vec2(0.3f, 0.7f);
    msm_moments6 six = msm_decode_moments6(texture(moments6_odd, uv), texture(moments6_even, uv));
    results[13] = msm_scatter_shadow6(six, zf, 0.5f);
    results[14] = msm_scatter_shadow4(msm_decode_msm64(texture(msm64_map, uv)), zf, 0.5f);
    results[15] = msm_lookup_moments128_accurate(moments128_map, 16, 16, 3.2f, 4.7f, zf, 1, noise);
    for (int lookup = 0; lookup < 3; ++lookup) {
        results[16 + 5 * lookup] = msm_lookup_moments128_array(float_array, 2, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
        results[17 + 5 * lookup] = msm_lookup_msm64_array(float_array, 2, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
        results[18 + 5 * lookup] = msm_lookup_nlq64_array(float_array, 2, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
        results[19 + 5 * lookup] = msm_lookup_nlq32_array(uint_array, 2, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
        results[20 + 5 * lookup] = msm_lookup_moments128_accurate_array(float_array, 2, 16, 16, 3.2f, 4.7f, zf, lookup,
                                                                        noise);
        results[31 + 2 * lookup] = msm_lookup_warped(moments128_map, 16, 16, 3.2f, 4.7f, zf, lookup, noise,
                                                     msm_warp_shading_evsm4(5.54f, 5.54f, 1e-5f, 0.15f));
        results[32 + 2 * lookup] = msm_lookup_warped_array(float_array, 1, 16, 16, 3.2f, 4.7f, zf, lookup, noise,
                                                           msm_warp_shading_esm(80.0f));
    }
    results[37] = msm_lookup_warped(msm64_map, 16, 16, 3.2f, 4.7f, zf, 1, noise, msm_warp_shading_vsm(1e-5f, 0.0f));
    results[38] = msm_lookup_warped(msm64_map, 16, 16, 3.2f, 4.7f, zf, 1, noise, msm_warp_shading_evsm2(5.54f, 1e-5f, 0.0f));
}
)";

const char* kHlslMain = R"(
Texture2D<float4> moments128_map : register(t0);
Texture2D<float4> msm64_map : register(t1);
Texture2D<float4> nlq64_map : register(t2);
Texture2D<uint4> nlq32_map : register(t3);
Texture2D<uint4> sat_table : register(t4);
Texture2D<float4> moments6_odd : register(t5);
Texture2D<float4> moments6_even : register(t6);
SamplerState bilinear : register(s0);
Texture2D<uint4> blue_noise : register(t7);
Texture2DArray<float4> float_array : register(t8);
Texture2DArray<uint4> uint_array : register(t9);
RWStructuredBuffer<float> results : register(u0);
[numthreads(1, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {
    float zf = msm_internal_depth(0.5f, true) - 1e-3f;
    float2 noise = msm_blue_noise_at(blue_noise, msm_blue_noise_frame_of(17u), id.x, 3u);
    for (int lookup = 0; lookup < 3; ++lookup) {
        results[4 * lookup + 0] = msm_lookup_moments128(moments128_map, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
        results[4 * lookup + 1] = msm_lookup_msm64(msm64_map, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
        results[4 * lookup + 2] = msm_lookup_nlq64(nlq64_map, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
        results[4 * lookup + 3] = msm_lookup_nlq32(nlq32_map, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
    }
    msm_sat_soft_params p;
    p.width = 16;
    p.height = 16;
    p.scale = 0xffffffffu / 729u;
    p.search_size = 27;
    p.light_size = 64.0f;
    p.min_filter_size = 1.0f;
    p.max_filter_size = 27.0f;
    p.receiver_weight = 0.1f;
    p.filter_parts = 2;
    results[12] = msm_sat_soft_shadow(sat_table, p, 3.2f, 4.7f, zf);
    float2 uv = float2(0.3f, 0.7f);
    msm_moments6 six = msm_decode_moments6(moments6_odd.SampleLevel(bilinear, uv, 0), moments6_even.SampleLevel(bilinear, uv, 0));
    results[13] = msm_scatter_shadow6(six, zf, 0.5f);
    results[14] = msm_scatter_shadow4(msm_decode_msm64(msm64_map.SampleLevel(bilinear, uv, 0)), zf, 0.5f);
    results[15] = msm_lookup_moments128_accurate(moments128_map, 16, 16, 3.2f, 4.7f, zf, 1, noise);
    for (int lookup = 0; lookup < 3; ++lookup) {
        results[16 + 5 * lookup] = msm_lookup_moments128_array(float_array, 2, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
        results[17 + 5 * lookup] = msm_lookup_msm64_array(float_array, 2, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
        results[18 + 5 * lookup] = msm_lookup_nlq64_array(float_array, 2, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
        results[19 + 5 * lookup] = msm_lookup_nlq32_array(uint_array, 2, 16, 16, 3.2f, 4.7f, zf, lookup, noise);
        results[20 + 5 * lookup] = msm_lookup_moments128_accurate_array(float_array, 2, 16, 16, 3.2f, 4.7f, zf, lookup,
                                                                        noise);
        results[31 + 2 * lookup] = msm_lookup_warped(moments128_map, 16, 16, 3.2f, 4.7f, zf, lookup, noise,
                                                     msm_warp_shading_evsm4(5.54f, 5.54f, 1e-5f, 0.15f));
        results[32 + 2 * lookup] = msm_lookup_warped_array(float_array, 1, 16, 16, 3.2f, 4.7f, zf, lookup, noise,
                                                           msm_warp_shading_esm(80.0f));
    }
    results[37] = msm_lookup_warped(msm64_map, 16, 16, 3.2f, 4.7f, zf, 1, noise, msm_warp_shading_vsm(1e-5f, 0.0f));
    results[38] = msm_lookup_warped(msm64_map, 16, 16, 3.2f, 4.7f, zf, 1, noise, msm_warp_shading_evsm2(5.54f, 1e-5f, 0.0f));
}
)";

struct Compiled {
    int exit_code = -1;
    std::string log;
};

Compiled run_validator(const std::string& name, const std::string& text, const std::string& options) {
    const fs::path directory = fs::temp_directory_path() / ("msmcl-shaders-" + std::to_string(::getpid()));
    fs::create_directories(directory);
    const fs::path file = directory / name;
    std::ofstream(file) << text;
    const fs::path log = directory / (name + ".log");
    const std::string command = std::string("'") + MSMCL_GLSLANG_VALIDATOR + "' " + options + " '" + file.string() +
                                "' -o '" + (directory / (name + ".spv")).string() + "' > '" + log.string() + "' 2>&1";
    Compiled result;
    const int status = std::system(command.c_str());
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    result.log = read_text(log);
    fs::remove_all(directory);
    return result;
}

TEST(ShaderFiles, GlslCompilesForVulkanAndOpenGL) {
    const std::string glsl = read_text(fs::path(MSMCL_SHADER_DIR) / "msm.glsl");
    const std::string shader = "#version 450\n" + glsl + kGlslMain;
    const Compiled vulkan = run_validator("msm_vulkan.comp", shader, "-V --target-env vulkan1.0");
    EXPECT_EQ(vulkan.exit_code, 0) << vulkan.log;
    const Compiled opengl = run_validator("msm_opengl.comp", shader, "-G --target-env opengl");
    EXPECT_EQ(opengl.exit_code, 0) << opengl.log;
}

TEST(ShaderFiles, HlslCompilesWithGlslangsHlslFrontEnd) {
    const std::string hlsl = read_text(fs::path(MSMCL_SHADER_DIR) / "msm.hlsl");
    const Compiled compiled = run_validator("msm.hlsl", hlsl + kHlslMain, "-D -V -e main -S comp");
    EXPECT_EQ(compiled.exit_code, 0) << compiled.log;
}
#else
TEST(ShaderFiles, GlslCompilesForVulkanAndOpenGL) { GTEST_SKIP() << "glslangValidator not found (Debian: glslang-tools)"; }
TEST(ShaderFiles, HlslCompilesWithGlslangsHlslFrontEnd) {
    GTEST_SKIP() << "glslangValidator not found (Debian: glslang-tools)";
}
#endif

// ---- The same functions on the OpenCL device against the GLSL run on the CPU.
const char* kParityKernel = R"(
__kernel void shader_parity(__global const float* inputs, __global const uint* words, __global float* outputs,
                            uint count) {
    const size_t i = get_global_id(0);
    if (i >= count) return;
    __global const float* in = inputs + 10 * i;
    __global const uint* w = words + 5 * i;
    __global float* out = outputs + 8 * i;
    msm_moments raw = {in[0], in[1], in[2], in[3]};
    float zf = in[4];
    msm_nlq n = {in[5], in[6], in[7], in[8]};
    float beta = in[9];
    msm_word2 w64 = {w[0], w[1]};
    msm_word_pair w6 = {w[3], w[4]};
    out[0] = msm_shadow_moments128_fast(raw, zf);
    out[1] = msm_hamburger4_upper(msm_bias(raw, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT), zf);
    out[2] = msm_nlq_shadow(n, zf);
    out[3] = msm_shadow_nlq32(w[2], zf);
    out[4] = msm_shadow_nlq64(w64, zf);
    out[5] = msm_shadow_msm64_fast(w64, zf);
    out[6] = msm_scatter_shadow6(msm_decode_moments6(w6), zf, beta);
    out[7] = msm_scatter_shadow4(raw, zf, beta);
}
)";

TEST(ShaderDevice, GlslOnTheCpuAgreesWithTheOpenClDevice) {
    msmcl::Context context;
    std::mt19937 random(test_seed() + 5);
    const std::size_t count = 4096;
    std::vector<float> inputs;
    std::vector<uint> words;
    for (std::size_t i = 0; i < count; ++i) {
        const msm_moments raw = random_moments(random);
        const msm_nlq n = random_nlq(random);
        const float zf = random_zf(random, i % 2 ? raw.b1 : n.y1);
        inputs.insert(inputs.end(), {raw.b1, raw.b2, raw.b3, raw.b4, zf, n.y1, n.y2, n.v2, n.xi4,
                                     std::uniform_real_distribution<float>(0.0f, 1.0f)(random)});
        const msm_nlq fitted = msm_nlq_from_moments(msm_bias(raw, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT));
        const msm_word2 w64 = i % 2 ? msm_encode_msm64(raw) : msm_encode_nlq64(fitted);
        msm_moments6 six = msm_moments6_zero();
        for (int k = 0; k < 2; ++k)
            six = msm_moments6_add_scaled(six, msm_moments6_of(i % 2 ? raw.b1 : n.y1 + 0.3f * k), 0.5f);
        const msm_word_pair w6 = msm_encode_moments6(six);
        words.insert(words.end(), {w64.w0, w64.w1, msm_encode_nlq32(fitted), w6.odd, w6.even});
    }

    // The device functions, assembled from the embedded kernels/*.clh.
    const std::string source = msmcl::detail::assemble_kernel_source("msm_scatter.clh") + kParityKernel;
    cl::Context cl_context(context.cl_context_handle(), true);
    cl::Device device(context.cl_device_handle(), true);
    cl::Program program(cl_context, source);
    if (program.build({device}, "-cl-std=CL1.2 -w") != CL_SUCCESS)
        FAIL() << program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device);
    cl_int status = CL_SUCCESS;
    cl::Buffer input_buffer(cl_context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, inputs.size() * sizeof(float),
                            inputs.data(), &status);
    cl::Buffer word_buffer(cl_context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, words.size() * sizeof(uint),
                           words.data(), &status);
    cl::Buffer output_buffer(cl_context, CL_MEM_WRITE_ONLY, 8 * count * sizeof(float), nullptr, &status);
    cl::Kernel kernel(program, "shader_parity");
    kernel.setArg(0, input_buffer);
    kernel.setArg(1, word_buffer);
    kernel.setArg(2, output_buffer);
    kernel.setArg(3, static_cast<cl_uint>(count));
    cl::CommandQueue queue(context.cl_queue_handle(), true);
    ASSERT_EQ(queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(count)), CL_SUCCESS);
    std::vector<float> device_results(8 * count);
    ASSERT_EQ(queue.enqueueReadBuffer(output_buffer, CL_TRUE, 0, device_results.size() * sizeof(float),
                                      device_results.data()),
              CL_SUCCESS);

    // The GLSL functions on the CPU.
    double worst[8] = {};
    int close[8] = {};
    int bit_identical = 0;
    for (std::size_t i = 0; i < count; ++i) {
        const float* in = &inputs[10 * i];
        const uint* w = &words[5 * i];
        const msm_moments raw{in[0], in[1], in[2], in[3]};
        const float zf = in[4], beta = in[9];
        const msm_nlq n{in[5], in[6], in[7], in[8]};
        const msm_word2 w64{w[0], w[1]};
        const float cpu[8] = {Glsl::shadow_moments128_fast(raw, zf),
                              Glsl::hamburger4_upper(msm_bias(raw, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT), zf),
                              Glsl::nlq_shadow(n, zf),
                              Glsl::shadow_nlq32(w[2], zf),
                              Glsl::shadow_nlq64(w64, zf),
                              Glsl::shadow_msm64_fast(w64, zf),
                              Glsl::scatter_shadow6(Glsl::decode_moments6(msm_word_pair{w[3], w[4]}), zf, beta),
                              Glsl::scatter_shadow4(raw, zf, beta)};
        for (int k = 0; k < 8; ++k) {
            const double difference = std::fabs(double(cpu[k]) - double(device_results[8 * i + k]));
            worst[k] = std::max(worst[k], difference);
            close[k] += difference <= 1e-5;
            bit_identical += same_bits(cpu[k], device_results[8 * i + k]);
        }
    }
    std::printf("shaders_test: %d of %zu results bit-identical; worst differences:", bit_identical, 8 * count);
    for (double d : worst) std::printf(" %.3g", d);
    std::printf("; within 1e-5:");
    for (int c : close) std::printf(" %d", c);
    std::printf(" of %zu\n", count);
    // The device's exp, log, sqrt, acos, cos and sin may differ from the host's by a few ulps
    // (OpenCL allows up to 4); every other operation is the same IEEE float32 sequence. The
    // 4-moment and nlq intensities are continuous and their slopes small: an ulp of
    // difference stays below 1e-5 (seen: <= 3e-7). The six-moment bound (result 6) builds a
    // Newton polynomial over support points found with acos/cos/sin; divided differences by
    // node gaps down to 1e-6 amplify an ulp of a root, and its terms cancel to the
    // intensity. Since the root finder refines the largest root and divides it out, seeds
    // 1-30 gave 100% within 1e-5 (worst 9.6e-6); the looser bound below (99.5%, 5e-2) is
    // what the earlier closed-form cubic needed and still catches a wrong formula by far.
    for (int k = 0; k < 8; ++k) {
        if (k == 6) continue;
        EXPECT_LE(worst[k], 1e-5) << "result " << k;
    }
    EXPECT_GE(close[6], static_cast<int>(count * 995 / 1000));
    EXPECT_LE(worst[6], 5e-2);
}

} // namespace
