// include/msmcl/device_math.hpp: the consumer-side math of kernels/msm_shading.clh compiled as
// C++ (float32, the very code the kernels run), and the host definition of the `shade`
// lookup of docs/math.md, Lookups.
#include "runtime/texture_kinds.hpp"

#include <msmcl/device_math.hpp>
#include <msmcl/errors.hpp>

#include "kernels/msm_filterable_shading.clh"
#include "kernels/msm_shading.clh"

#include <cmath>
#include <string>

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

namespace detail {

namespace {

// ---- The formats' rows of host shading (texel_shading.hpp): the device functions of
// kernels/msm_shading.clh per texel, blended texels for the linear formats, decoded quantities.

// Power moments b1..b4: odd ones in [-1, 1], even ones in [0, 1].
void moment_ranges(float, float, double min[4], double max[4]) {
    const double lo[4] = {-1, 0, -1, 0}, hi[4] = {1, 1, 1, 1};
    for (int c = 0; c < 4; ++c) min[c] = lo[c], max[c] = hi[c];
}
// Algorithm 2's representation: depths in [-1, 1], weight in [0, 1], xi4 in [0, 0.25].
void nlq_ranges(float, float, double min[4], double max[4]) {
    const double lo[4] = {-1, -1, 0, 0}, hi[4] = {1, 1, 1, 0.25};
    for (int c = 0; c < 4; ++c) min[c] = lo[c], max[c] = hi[c];
}
void put_moments(const msm_moments& m, float values[4]) { values[0] = m.b1, values[1] = m.b2, values[2] = m.b3, values[3] = m.b4; }
void put_nlq(const msm_nlq& n, float values[4]) { values[0] = n.y1, values[1] = n.y2, values[2] = n.v2, values[3] = n.xi4; }

} // namespace

const TexelShading kMoments128Shading{
    [](const std::uint32_t* w, float zf, const ShadingParameters&) { return msm_shadow_moments128(raw_moments128(w), zf); },
    [](const std::uint32_t* const t[4], float tx, float ty, float zf, const ShadingParameters&) {
        return msm_shadow_moments128_bilinear(raw_moments128(t[0]), raw_moments128(t[1]), raw_moments128(t[2]),
                                              raw_moments128(t[3]), tx, ty, zf);
    },
    false, 4, {"b1", "b2", "b3", "b4"},
    [](const std::uint32_t* w, float values[4]) { put_moments(raw_moments128(w), values); },
    moment_ranges};

const TexelShading kMsm64Shading{
    [](const std::uint32_t* w, float zf, const ShadingParameters&) { return msm_shadow_msm64(word2_of(w), zf); },
    [](const std::uint32_t* const t[4], float tx, float ty, float zf, const ShadingParameters&) {
        return msm_shadow_msm64_bilinear(word2_of(t[0]), word2_of(t[1]), word2_of(t[2]), word2_of(t[3]), tx, ty, zf);
    },
    false, 4, {"b1", "b2", "b3", "b4"},
    [](const std::uint32_t* w, float values[4]) { put_moments(msm_decode_msm64(word2_of(w)), values); },
    moment_ranges};

const TexelShading kNlq64Shading{
    [](const std::uint32_t* w, float zf, const ShadingParameters&) { return msm_shadow_nlq64(word2_of(w), zf); },
    nullptr, false, 4, {"y1", "y2", "v2", "xi4"},
    [](const std::uint32_t* w, float values[4]) { put_nlq(msm_decode_nlq64(word2_of(w)), values); }, nlq_ranges};

const TexelShading kNlq32Shading{
    [](const std::uint32_t* w, float zf, const ShadingParameters&) { return msm_shadow_nlq32(w[0], zf); }, nullptr,
    false, 4, {"y1", "y2", "v2", "xi4"},
    [](const std::uint32_t* w, float values[4]) { put_nlq(msm_decode_nlq32(w[0]), values); }, nlq_ranges};

namespace {

// ---- VSM, EVSM and ESM (msm_filterable_shading.clh): the texel's channels decoded, blended
// (bilinear) and shaded with the texture's exponents and the options' V and R.

msm_moments raw_channels4(const std::uint32_t* w) { return raw_moments128(w); }
msm_moments vsm32_channels(const std::uint32_t* w) { return msm_decode_vsm32(w[0]); }
msm_moments vsm64_channels(const std::uint32_t* w) { return msm_decode_vsm64(word2_of(w)); }
msm_moments evsm2_32_channels(const std::uint32_t* w) { return msm_decode_evsm2_32(w[0]); }
msm_moments evsm4_64_channels(const std::uint32_t* w) { return msm_decode_evsm4_64(word2_of(w)); }
msm_moments esm32_channels(const std::uint32_t* w) { return msm_decode_esm32(w[0]); }

msm_warp_shading vsm_shading(const ShadingParameters& p) {
    return msm_warp_shading_vsm(p.min_variance, p.light_bleed_reduction);
}
msm_warp_shading evsm2_shading(const ShadingParameters& p) {
    return msm_warp_shading_evsm2(p.positive, p.min_variance, p.light_bleed_reduction);
}
msm_warp_shading evsm4_shading(const ShadingParameters& p) {
    return msm_warp_shading_evsm4(p.positive, p.negative, p.min_variance, p.light_bleed_reduction);
}
msm_warp_shading esm_shading(const ShadingParameters& p) { return msm_warp_shading_esm(p.positive); }

template <msm_moments (*Channels)(const std::uint32_t*), msm_warp_shading (*Shading)(const ShadingParameters&)>
float warped_texel(const std::uint32_t* w, float zf, const ShadingParameters& p) {
    return msm_shadow_warped(Channels(w), zf, Shading(p));
}
template <msm_moments (*Channels)(const std::uint32_t*), msm_warp_shading (*Shading)(const ShadingParameters&)>
float warped_blend(const std::uint32_t* const t[4], float tx, float ty, float zf, const ShadingParameters& p) {
    return msm_shadow_warped(msm_moments_bilinear(Channels(t[0]), Channels(t[1]), Channels(t[2]), Channels(t[3]), tx, ty),
                             zf, Shading(p));
}
template <msm_moments (*Channels)(const std::uint32_t*)>
void warped_decode(const std::uint32_t* w, float values[4]) {
    put_moments(Channels(w), values);
}

// The ranges of the stored warps, widened by half precision's relative rounding (2^-11).
constexpr double kWarpSlack = 1.0 / 2048.0;
void vsm_ranges(float, float, double min[4], double max[4]) {
    min[0] = min[1] = 0.0, max[0] = max[1] = 1.0;
}
// p = exp(c+ x) in [exp(-c+), exp(c+)], p^2 likewise squared; n = -exp(-c- x), n^2.
void evsm_ranges(float positive, float negative, double min[4], double max[4]) {
    const double cp = positive, cn = negative;
    min[0] = std::exp(-cp) * (1 - kWarpSlack), max[0] = std::exp(cp) * (1 + kWarpSlack);
    min[1] = std::exp(-2 * cp) * (1 - kWarpSlack), max[1] = std::exp(2 * cp) * (1 + kWarpSlack);
    min[2] = -std::exp(cn) * (1 + kWarpSlack), max[2] = -std::exp(-cn) * (1 - kWarpSlack);
    min[3] = std::exp(-2 * cn) * (1 - kWarpSlack), max[3] = std::exp(2 * cn) * (1 + kWarpSlack);
}
// exp(c (t - 1)) in [exp(-c), 1].
void esm_ranges(float positive, float, double min[4], double max[4]) {
    min[0] = std::exp(-double(positive)) * (1 - kWarpSlack), max[0] = 1.0;
}

} // namespace

const TexelShading kVsm32Shading{warped_texel<vsm32_channels, vsm_shading>, warped_blend<vsm32_channels, vsm_shading>,
                                 true, 2, {"t", "t2"}, warped_decode<vsm32_channels>, vsm_ranges};
const TexelShading kVsm64Shading{warped_texel<vsm64_channels, vsm_shading>, warped_blend<vsm64_channels, vsm_shading>,
                                 true, 2, {"t", "t2"}, warped_decode<vsm64_channels>, vsm_ranges};
const TexelShading kEvsm2_32Shading{warped_texel<evsm2_32_channels, evsm2_shading>,
                                    warped_blend<evsm2_32_channels, evsm2_shading>, true, 2, {"p", "p2"},
                                    warped_decode<evsm2_32_channels>, evsm_ranges};
const TexelShading kEvsm4_64Shading{warped_texel<evsm4_64_channels, evsm4_shading>,
                                    warped_blend<evsm4_64_channels, evsm4_shading>, true, 4, {"p", "p2", "n", "n2"},
                                    warped_decode<evsm4_64_channels>, evsm_ranges};
const TexelShading kEvsm4_128Shading{warped_texel<raw_channels4, evsm4_shading>,
                                     warped_blend<raw_channels4, evsm4_shading>, true, 4, {"p", "p2", "n", "n2"},
                                     warped_decode<raw_channels4>, evsm_ranges};
const TexelShading kEsm32Shading{warped_texel<esm32_channels, esm_shading>, warped_blend<esm32_channels, esm_shading>,
                                 false, 1, {"e"}, warped_decode<esm32_channels>, esm_ranges};

} // namespace detail

namespace {

// The format's row of host shading; input_error for a value outside the table.
const detail::TexelShading& host_shading(Format format) {
    if (!detail::is_known(format))
        throw input_error("shade: unknown format " + std::to_string(static_cast<int>(format)));
    return *detail::texture_kind(format).host_shading;
}

// What shading a texel of `map` needs from the options and the texture.
detail::ShadingParameters shading_parameters(const Texture& map, const ShadeOptions& options) {
    detail::ShadingParameters p;
    // The exponents the texture was made with (0: the format's default); beyond the format's
    // limit, input_error.
    const WarpExponents exponents = effective_exponents(map.format, map.exponents, "shade");
    p.positive = exponents.positive;
    p.negative = exponents.negative;
    p.min_variance = options.min_variance.value_or(detail::texture_kind(map.format).shading_defaults.min_variance);
    p.light_bleed_reduction = options.light_bleed_reduction;
    return p;
}

float shade_texel(const Texture& map, int x, int y, float zf, const detail::ShadingParameters& parameters) {
    return host_shading(map.format).texel(map.texel(x, y), zf, parameters);
}

} // namespace

float shade_texel(const Texture& map, int x, int y, float zf) { return shade_texel(map, x, y, zf, ShadeOptions{}); }

float shade_texel(const Texture& map, int x, int y, float zf, const ShadeOptions& options) {
    return shade_texel(map, x, y, zf, shading_parameters(map, options));
}

std::vector<DecodedQuantity> decoded_quantities(const Texture& texture) {
    const detail::TexelShading& shading = host_shading(texture.format);
    double min[4], max[4];
    const WarpExponents exponents = effective_exponents(texture.format, texture.exponents, "texture");
    shading.ranges(exponents.positive, exponents.negative, min, max);
    std::vector<DecodedQuantity> quantities;
    for (int c = 0; c < shading.quantities; ++c) quantities.push_back({shading.names[c], min[c], max[c]});
    return quantities;
}

void decode_texel(const Texture& texture, std::size_t index, float values[4]) {
    host_shading(texture.format).decode(texture.words.data() + index * texel_words(texture.format), values);
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
    const detail::TexelShading& shading = host_shading(map.format);
    const detail::ShadingParameters parameters = shading_parameters(map, options);
    // Receiver depth: internal z of the declared range, minus the constant depth bias.
    float zf = msm_internal_depth(z, options.depth_range == DepthRange::zero_one) - options.depth_bias;
    // Nearest: texel floor(u), floor(v), clamped to the edge.
    if (options.lookup == Lookup::nearest)
        return shade_texel(map, msm_texel_index(u, map.width), msm_texel_index(v, map.height), zf, parameters);
    // Dither: texel floor(u - 0.5 + n) with the pixel's blue noise in this frame, shaded alone.
    if (options.lookup == Lookup::dither) {
        const DitherNoise noise = blue_noise_at(options.frame, px, py);
        return shade_texel(map, msm_dither_index(u, noise.x, map.width), msm_dither_index(v, noise.y, map.height), zf,
                           parameters);
    }
    // Bilinear: the four texels around (u - 0.5, v - 0.5), clamped to the edge.
    msm_bilinear_taps taps = msm_bilinear_taps_at(u, v, map.width, map.height);
    // Formats that blend their stored values: blend, then shade once.
    const std::uint32_t* const texels[4] = {map.texel(taps.x0, taps.y0), map.texel(taps.x1, taps.y0),
                                            map.texel(taps.x0, taps.y1), map.texel(taps.x1, taps.y1)};
    if (shading.blend) return shading.blend(texels, taps.tx, taps.ty, zf, parameters);
    // The others: shade the four texels, interpolate the intensities.
    return clamp(msm_bilinear(shading.texel(texels[0], zf, parameters), shading.texel(texels[1], zf, parameters),
                              shading.texel(texels[2], zf, parameters), shading.texel(texels[3], zf, parameters),
                              taps.tx, taps.ty),
                 0.0f, 1.0f);
}

} // namespace msmcl
