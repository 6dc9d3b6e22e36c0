// msmcl::shade of the VSM, EVSM and ESM formats on the OpenCL device against the double
// reference of tests/reference/filterable_reference.hpp (docs/math.md, "Shading VSM, EVSM and
// ESM"), every lookup, both depth ranges; the device against its host copy
// (msmcl::shade_receiver); and the options shade refuses. The textures are built here from the
// reference's warps, encoded in each format's texel layout (docs/formats.md), so that the
// shading is tested apart from the filter.
#include <msmcl/device_math.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/shade.hpp>

#include "reference/filterable_reference.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "seeded_test.hpp"

namespace ref = msmcl::reference;
using msmcl::Format;

namespace {

class FilterableShadeTest : public msmcl::testing::DeviceSuite<FilterableShadeTest, 20080528u> {};

struct FormatCase {
    Format format;
    ref::Warp warp;
    enum class Storage { unorm16, half, float32 } storage;
    int channels;
};

const FormatCase kFormats[] = {
    {Format::vsm32, ref::Warp::vsm, FormatCase::Storage::unorm16, 2},
    {Format::vsm64, ref::Warp::vsm, FormatCase::Storage::float32, 2},
    {Format::evsm2_32, ref::Warp::evsm2, FormatCase::Storage::half, 2},
    {Format::evsm4_64, ref::Warp::evsm4, FormatCase::Storage::half, 4},
    {Format::evsm4_128, ref::Warp::evsm4, FormatCase::Storage::float32, 4},
    {Format::esm32, ref::Warp::esm, FormatCase::Storage::float32, 1},
};

// The binary16 code nearest to x (ties to even), from the IEEE definition.
std::uint16_t half_code(double x) {
    std::uint16_t best = 0;
    double best_error = INFINITY;
    // Bisection over the ordered positive codes, then the sign.
    const double magnitude = std::fabs(x);
    int lo = 0, hi = 0x7bff;
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        (ref::half_value(std::uint16_t(mid)) <= magnitude ? lo : hi) = mid;
    }
    for (int code : {lo, hi}) {
        const double error = std::fabs(ref::half_value(std::uint16_t(code)) - magnitude);
        if (error < best_error || (error == best_error && (code & 1) == 0)) best = std::uint16_t(code), best_error = error;
    }
    return std::uint16_t(best | (x < 0 ? 0x8000u : 0u));
}

// A stored channel as the texture holds it: its code and the value the code stands for.
std::uint32_t encode(double value, FormatCase::Storage storage, double& stored) {
    if (storage == FormatCase::Storage::unorm16) {
        const double code = std::clamp(std::floor(value * 65535.0 + 0.5), 0.0, 65535.0);
        stored = code / 65535.0;
        return std::uint32_t(code);
    }
    if (storage == FormatCase::Storage::half) {
        const std::uint16_t code = half_code(value);
        stored = ref::half_value(code);
        return code;
    }
    const float f = float(value);
    stored = f;
    std::uint32_t bits;
    std::memcpy(&bits, &f, 4);
    return bits;
}

// A texture of `format` whose texels are filtered texels (the mean of the warps of 1 to 3
// random depths); `stored` receives each texel's channels as the texture holds them.
msmcl::Texture make_texture(const FormatCase& c, int width, int height, msmcl::WarpExponents exponents,
                            std::mt19937_64& random, std::vector<ref::Channels>& stored) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    msmcl::Texture map;
    map.format = c.format;
    map.width = width;
    map.height = height;
    map.exponents = exponents;
    stored.clear();
    for (int t = 0; t < width * height; ++t) {
        std::vector<double> depth, weight;
        const int count = 1 + int(random() % 3);
        // Clusters near one depth (contact shadows) as well as spread depths.
        const double base = unit(random);
        for (int k = 0; k < count; ++k)
            depth.push_back(random() % 2 ? std::min(1.0, base + 0.01 * unit(random)) : unit(random)),
                weight.push_back(0.1 + unit(random));
        const ref::Channels exact = ref::warp_channels(c.warp, depth, weight, exponents.positive, exponents.negative);
        ref::Channels held{0, 0, 0, 0};
        std::uint32_t codes[4] = {0, 0, 0, 0};
        for (int k = 0; k < c.channels; ++k) codes[k] = encode(exact[k], c.storage, held[k]);
        stored.push_back(held);
        if (c.storage == FormatCase::Storage::float32) {
            for (int k = 0; k < c.channels; ++k) map.words.push_back(codes[k]);
        } else {
            // Two 16-bit codes per word, channel 0 in the low half.
            for (int k = 0; k < c.channels; k += 2) map.words.push_back(codes[k] | (codes[k + 1] << 16));
        }
    }
    return map;
}

// The reference lookup: nearest/dithered texel, or bilinear blend of the stored channels,
// shaded by the double reference at the receiver's t_r.
struct ReferenceShade {
    double value;
    double tolerance;
    ref::Channels blended;
};

ReferenceShade reference_shade(const std::vector<ref::Channels>& stored, int width, int height, double u, double v,
                               double t_r, msmcl::Lookup lookup, msmcl::DitherNoise noise, const ref::WarpShading& s) {
    const auto texel = [&](double coordinate, int size) {
        return int(std::clamp(std::floor(std::clamp(coordinate, -1.0, double(size))), 0.0, double(size - 1)));
    };
    ref::Channels blended{0, 0, 0, 0}, largest{0, 0, 0, 0};
    if (lookup == msmcl::Lookup::bilinear) {
        const double fx = std::clamp(u - 0.5, -1.0, double(width)), fy = std::clamp(v - 0.5, -1.0, double(height));
        const double x0 = std::floor(fx), y0 = std::floor(fy), tx = fx - x0, ty = fy - y0;
        const int x[2] = {std::clamp(int(x0), 0, width - 1), std::clamp(int(x0) + 1, 0, width - 1)};
        const int y[2] = {std::clamp(int(y0), 0, height - 1), std::clamp(int(y0) + 1, 0, height - 1)};
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i)
                for (int k = 0; k < 4; ++k) {
                    const double channel = stored[std::size_t(y[j]) * width + x[i]][k];
                    blended[k] += (i ? tx : 1 - tx) * (j ? ty : 1 - ty) * channel;
                    largest[k] = std::max(largest[k], std::fabs(channel));
                }
    } else {
        const double du = lookup == msmcl::Lookup::dither ? u - 0.5 + noise.x : u;
        const double dv = lookup == msmcl::Lookup::dither ? v - 0.5 + noise.y : v;
        blended = stored[std::size_t(texel(dv, height)) * width + texel(du, width)];
    }
    const double value = ref::warp_shadow(blended, t_r, s);
    // What the reference moves when its inputs move by their float32 rounding: each blended
    // channel by 2^-21 relative (m2 - m1^2) and, bilinear, by 2^-21 of the largest of the four
    // texels' values (the float lerps a + t (b - a) cancel where the blend is far below a);
    // t_r by 2^-21 (the receiver's float depth and the warp's argument); plus 1e-6.
    const double eps = std::ldexp(1.0, -21);
    double tolerance = 0;
    for (int signs = 0; signs < 16; ++signs)
        for (double dt : {-eps, 0.0, eps}) {
            ref::Channels moved = blended;
            for (int k = 0; k < 4; ++k)
                moved[k] += ((signs >> k) & 1 ? 1.0 : -1.0) * eps * (std::fabs(moved[k]) + largest[k]);
            tolerance = std::max(tolerance, std::fabs(ref::warp_shadow(moved, t_r + dt, s) - value));
        }
    return {value, tolerance + 1e-6, blended};
}

} // namespace

// Every format, lookup and depth range, with and without a light-bleed reduction: the
// device against the double reference and against its host copy.
TEST_F(FilterableShadeTest, EveryFormatAndLookupMatchesTheDoubleReference) {
    std::mt19937_64 random(seed_);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const int width = 13, height = 9;
    double worst = 0, worst_host = 0;
    std::size_t compared = 0;
    for (const FormatCase& c : kFormats) {
        const msmcl::WarpExponents exponents = msmcl::effective_exponents(c.format, {}, "test");
        std::vector<ref::Channels> stored;
        const msmcl::Texture map = make_texture(c, width, height, exponents, random, stored);
        for (float reduction : {0.0f, 0.15f}) {
            if (c.warp == ref::Warp::esm && reduction != 0.0f) continue;
            for (msmcl::DepthRange range : {msmcl::DepthRange::zero_one, msmcl::DepthRange::minus_one_one}) {
                for (msmcl::Lookup lookup : {msmcl::Lookup::nearest, msmcl::Lookup::bilinear, msmcl::Lookup::dither}) {
                    msmcl::ShadeOptions options = msmcl::shade_defaults(c.format);
                    options.lookup = lookup;
                    options.depth_range = range;
                    options.light_bleed_reduction = reduction;
                    options.frame = 7;
                    options.screen_width = 17;
                    // Receivers over the map and beyond its edges, depths near the texels' own.
                    msmcl::Receivers receivers;
                    for (int i = 0; i < 500; ++i) {
                        const float u = float(unit(random) * (width + 4) - 2), v = float(unit(random) * (height + 4) - 2);
                        const ref::Channels& near = stored[std::size_t(std::clamp(int(v), 0, height - 1)) * width +
                                                           std::clamp(int(u), 0, width - 1)];
                        // t near the texel's mean depth (VSM: b1; else a random t).
                        const double t = c.warp == ref::Warp::vsm && i % 2 ? near[0] + 0.02 * (unit(random) - 0.5)
                                                                           : unit(random) * 1.1 - 0.05;
                        receivers.u.push_back(u);
                        receivers.v.push_back(v);
                        receivers.z.push_back(float(range == msmcl::DepthRange::zero_one ? t : 2 * t - 1));
                    }
                    const std::vector<float> device = msmcl::shade(context(), map, receivers, options);
                    const ref::WarpShading s{c.warp, exponents.positive, exponents.negative,
                                             double(options.min_variance.value_or(0.0f)), double(reduction)};
                    for (std::size_t i = 0; i < receivers.size(); ++i) {
                        const std::uint32_t px = std::uint32_t(i % 17), py = std::uint32_t(i / 17);
                        const float host = msmcl::shade_receiver(map, receivers.u[i], receivers.v[i], receivers.z[i], px,
                                                                 py, options);
                        const double z = range == msmcl::DepthRange::zero_one ? 2.0 * receivers.z[i] - 1.0
                                                                               : double(receivers.z[i]);
                        const double t_r = (std::clamp(z, -1.0, 1.0) - options.depth_bias + 1.0) / 2.0;
                        const ReferenceShade expected =
                            reference_shade(stored, width, height, receivers.u[i], receivers.v[i], t_r, lookup,
                                            msmcl::blue_noise_at(options.frame, px, py), s);
                        const std::string where = std::string(msmcl::format_name(c.format)) + " " +
                                                  msmcl::lookup_name(lookup) + " R " + std::to_string(reduction) +
                                                  " receiver " + std::to_string(i);
                        ASSERT_TRUE(device[i] >= 0.0f && device[i] <= 1.0f) << where << ": " << device[i];
                        // The device and the host run the same float operations (FP_CONTRACT off).
                        ASSERT_NEAR(device[i], host, 1e-6) << where;
                        ASSERT_NEAR(device[i], expected.value, expected.tolerance)
                            << where << " t_r " << t_r << " channels " << expected.blended[0] << " "
                            << expected.blended[1] << " " << expected.blended[2] << " " << expected.blended[3];
                        worst = std::max(worst, std::fabs(device[i] - expected.value));
                        worst_host = std::max(worst_host, double(std::fabs(device[i] - host)));
                        ++compared;
                    }
                }
            }
        }
    }
    std::printf("%zu receivers: largest difference from the double reference %.3g, from the host copy %.3g\n",
                compared, worst, worst_host);
}

// A light-bleed reduction R maps the bound p to clamp((p - R)/(1 - R), 0, 1): the shadow of
// a receiver with R is 1 - (1 - s0 - R)/(1 - R) clamped, s0 its shadow without.
TEST_F(FilterableShadeTest, LightBleedReductionRescalesTheBound) {
    std::mt19937_64 random(seed_ + 1);
    std::vector<ref::Channels> stored;
    const msmcl::Texture map = make_texture(kFormats[1], 8, 8, {}, random, stored);
    msmcl::Receivers receivers;
    for (int i = 0; i < 64; ++i)
        receivers.u.push_back(float(i % 8) + 0.5f), receivers.v.push_back(float(i / 8) + 0.5f),
            receivers.z.push_back(float(stored[i][0] + 0.01));
    msmcl::ShadeOptions options = msmcl::shade_defaults(Format::vsm64);
    options.lookup = msmcl::Lookup::nearest;
    const std::vector<float> plain = msmcl::shade(context(), map, receivers, options);
    options.light_bleed_reduction = 0.3f;
    const std::vector<float> reduced = msmcl::shade(context(), map, receivers, options);
    for (int i = 0; i < 64; ++i) {
        const double p = 1.0 - plain[i];
        EXPECT_NEAR(reduced[i], 1.0 - std::clamp((p - 0.3) / 0.7, 0.0, 1.0), 1e-5) << i;
        EXPECT_GE(reduced[i], plain[i]) << i;
    }
}

// The options shade refuses: a minimum variance or light-bleed reduction for a format whose
// shading is no variance bound, values out of range, exponents beyond the storage's limit.
TEST_F(FilterableShadeTest, RefusesOptionsThatDoNotBelongToTheFormat) {
    std::mt19937_64 random(seed_ + 2);
    msmcl::Receivers receivers;
    receivers.u = {1.0f};
    receivers.v = {1.0f};
    receivers.z = {0.5f};
    std::vector<ref::Channels> stored;
    const msmcl::Texture vsm = make_texture(kFormats[0], 4, 4, {}, random, stored);
    const msmcl::Texture esm = make_texture(kFormats[5], 4, 4, msmcl::effective_exponents(Format::esm32, {}, "test"),
                                            random, stored);
    msmcl::Texture msm64;
    msm64.format = Format::msm64;
    msm64.width = msm64.height = 4;
    msm64.words.assign(32, 0x80008000u);
    const auto refused = [&](const msmcl::Texture& map, const msmcl::ShadeOptions& options) {
        try {
            msmcl::shade(context(), map, receivers, options);
        } catch (const msmcl::input_error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    msmcl::ShadeOptions options;
    options.min_variance = 1e-4f;
    EXPECT_NE(refused(msm64, options).find("minimum variance is for VSM and EVSM"), std::string::npos);
    EXPECT_NE(refused(esm, options).find("not esm32"), std::string::npos);
    EXPECT_EQ(refused(vsm, options), "");
    options.min_variance = 0.5f;
    EXPECT_NE(refused(vsm, options).find("[0, 0.25]"), std::string::npos);
    options.min_variance.reset();
    options.light_bleed_reduction = 0.15f;
    EXPECT_NE(refused(msm64, options).find("light-bleed reduction is for VSM and EVSM"), std::string::npos);
    EXPECT_EQ(refused(vsm, options), "");
    for (float r : {1.0f, -0.1f, NAN}) {
        options.light_bleed_reduction = r;
        EXPECT_NE(refused(vsm, options).find("[0, 1)"), std::string::npos) << r;
    }
    // Exponents beyond the format's limit (a file may claim any).
    msmcl::Texture far = esm;
    far.exponents.positive = 200.0f;
    EXPECT_NE(refused(far, msmcl::ShadeOptions{}), "");
    // The table's defaults: every format bilinear with a depth bias; VSM/EVSM a minimum variance.
    for (const FormatCase& c : kFormats) {
        const msmcl::ShadeOptions defaults = msmcl::shade_defaults(c.format);
        EXPECT_EQ(defaults.lookup, msmcl::Lookup::bilinear);
        EXPECT_GT(defaults.depth_bias, 0.0f);
        EXPECT_EQ(defaults.min_variance.has_value(), c.warp != ref::Warp::esm) << msmcl::format_name(c.format);
    }
}
