// include/msmcl/device_math.hpp: the consumer-side math of kernels/msm_shading.clh compiled as
// C++ (float32, the very code the kernels run), and the host definition of the `shade`
// lookup of docs/math.md, Lookups.
#include <msmcl/device_math.hpp>

#include "kernels/msm_shading.clh"

namespace msmcl {

namespace {

msm_moments to_clh(const Moments4& m) {
    msm_moments r;
    r.b1 = m.b1;
    r.b2 = m.b2;
    r.b3 = m.b3;
    r.b4 = m.b4;
    return r;
}

Moments4 from_clh(const msm_moments& m) { return {m.b1, m.b2, m.b3, m.b4}; }

msm_nlq to_clh(const NlqTexel& t) {
    msm_nlq r;
    r.y1 = t.y1;
    r.y2 = t.y2;
    r.v2 = t.v2;
    r.xi4 = t.xi4;
    return r;
}

NlqTexel from_clh(const msm_nlq& t) { return {t.y1, t.y2, t.v2, t.xi4}; }

msm_word2 word2_of(const std::uint32_t* words) {
    msm_word2 w;
    w.w0 = words[0];
    w.w1 = words[1];
    return w;
}

msm_moments raw_moments128(const std::uint32_t* words) {
    msm_moments m;
    m.b1 = as_float(words[0]);
    m.b2 = as_float(words[1]);
    m.b3 = as_float(words[2]);
    m.b4 = as_float(words[3]);
    return m;
}

} // namespace

Moments4 bias_moments(const Moments4& b, float alpha, float bstar) {
    return from_clh(msm_bias(to_clh(b), alpha, bstar));
}

NlqTexel nlq_from_moments(const Moments4& biased) { return from_clh(msm_nlq_from_moments(to_clh(biased))); }

float psi4(float xi4) { return msm_psi4(xi4); }

float psi4_inverse(float psi) { return msm_psi4_inverse(psi); }

Moments4 decode_moments128(const std::uint32_t* words) { return from_clh(raw_moments128(words)); }

Moments4 decode_msm64(const std::uint32_t* words) { return from_clh(msm_decode_msm64(word2_of(words))); }

NlqTexel decode_nlq64(const std::uint32_t* words) { return from_clh(msm_decode_nlq64(word2_of(words))); }

NlqTexel decode_nlq32(std::uint32_t word) { return from_clh(msm_decode_nlq32(word)); }

float hamburger4_lower(const Moments4& biased, float zf) { return msm_hamburger4_lower(to_clh(biased), zf); }

float hamburger4_upper(const Moments4& biased, float zf) { return msm_hamburger4_upper(to_clh(biased), zf); }

float linear_shadow(const Moments4& unbiased, float alpha, float bstar, float zf) {
    return msm_shadow_linear_df(msm_moments_df_from_float(to_clh(unbiased)), alpha, bstar, zf);
}

float nlq_shadow(const NlqTexel& texel, float zf) { return msm_nlq_shadow(to_clh(texel), zf); }

float shade_texel(const Texture& map, int x, int y, float zf) {
    const std::uint32_t* words = map.texel(x, y);
    switch (map.format) {
    case Format::moments128: return msm_shadow_moments128(raw_moments128(words), zf);
    case Format::msm64: return msm_shadow_msm64(word2_of(words), zf);
    case Format::nlq64: return msm_shadow_nlq64(word2_of(words), zf);
    case Format::nlq32: return msm_shadow_nlq32(words[0], zf);
    }
    return 0.0f;
}

BlueNoiseFrame blue_noise_frame(std::uint32_t frame) {
    const msm_blue_noise_frame f = msm_blue_noise_frame_of(frame);
    return {f.texture, f.offset_x, f.offset_y};
}

DitherNoise blue_noise_at(std::uint32_t frame, std::uint32_t px, std::uint32_t py) {
    const std::uint8_t* texel = blue_noise_textures() + 2 * std::size_t(msm_blue_noise_texel(msm_blue_noise_frame_of(frame), px, py));
    return {msm_blue_noise_value(texel[0]), msm_blue_noise_value(texel[1])};
}

float shade_receiver(const Texture& map, float u, float v, float z, const ShadeOptions& options) {
    return shade_receiver(map, u, v, z, 0, 0, options);
}

float shade_receiver(const Texture& map, float u, float v, float z, std::uint32_t px, std::uint32_t py,
                     const ShadeOptions& options) {
    // Receiver depth: internal z of the declared range, minus the constant depth bias.
    float zf = msm_internal_depth(z, options.depth_range == DepthRange::zero_one) - options.depth_bias;
    // Nearest: texel floor(u), floor(v), clamped to the edge.
    if (options.lookup == Lookup::nearest)
        return shade_texel(map, msm_texel_index(u, map.width), msm_texel_index(v, map.height), zf);
    // Dither: texel floor(u - 0.5 + n) with the pixel's blue noise in this frame, shaded alone.
    if (options.lookup == Lookup::dither) {
        const DitherNoise noise = blue_noise_at(options.frame, px, py);
        return shade_texel(map, msm_dither_index(u, noise.x, map.width), msm_dither_index(v, noise.y, map.height), zf);
    }
    // Bilinear: the four texels around (u - 0.5, v - 0.5), clamped to the edge.
    msm_bilinear_taps taps = msm_bilinear_taps_at(u, v, map.width, map.height);
    // moments128/msm64: blend the moments in float-float, then bias and shade once.
    const std::uint32_t* t00 = map.texel(taps.x0, taps.y0);
    const std::uint32_t* t10 = map.texel(taps.x1, taps.y0);
    const std::uint32_t* t01 = map.texel(taps.x0, taps.y1);
    const std::uint32_t* t11 = map.texel(taps.x1, taps.y1);
    if (map.format == Format::moments128)
        return msm_shadow_moments128_bilinear(raw_moments128(t00), raw_moments128(t10), raw_moments128(t01),
                                              raw_moments128(t11), taps.tx, taps.ty, zf);
    if (map.format == Format::msm64)
        return msm_shadow_msm64_bilinear(word2_of(t00), word2_of(t10), word2_of(t01), word2_of(t11), taps.tx,
                                         taps.ty, zf);
    // nlq64/nlq32: shade the four texels, interpolate the intensities.
    return clamp(msm_bilinear(shade_texel(map, taps.x0, taps.y0, zf), shade_texel(map, taps.x1, taps.y0, zf),
                              shade_texel(map, taps.x0, taps.y1, zf), shade_texel(map, taps.x1, taps.y1, zf),
                              taps.tx, taps.ty),
                 0.0f, 1.0f);
}

} // namespace msmcl
