// Random moment shadow maps for the consumer-side tests (shade, dither): texels encoded by
// the double-precision REFERENCE encoders from exact moments, so that the device's encoders
// play no part in them.
#pragma once

#include "reference/moment_math.hpp"

#include <msmcl/formats.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <random>

namespace msmcl::testing {

namespace ref = msmcl::reference;

// clusters) and elsewhere (one slightly spread surface), in internal depth z.
inline ref::Distribution random_texel_distribution(std::mt19937& rng) {
    std::uniform_real_distribution<double> depth(-0.95, 0.95), spread(0.0, 0.02), unit(0.0, 1.0);
    ref::Distribution d;
    const int clusters = unit(rng) < 0.5 ? 1 : 2;
    for (int c = 0; c < clusters; ++c) {
        const double centre = depth(rng), width = spread(rng), mass = 0.05 + unit(rng);
        for (int k = 0; k < 3; ++k) {
            d.depth.push_back(std::clamp(centre + width * (unit(rng) - 0.5), -1.0, 1.0));
            d.weight.push_back(mass / 3);
        }
    }
    return d;
}

// A texture whose texels are encoded by the REFERENCE encoders from exact moments.
inline msmcl::Texture random_texture(msmcl::Format format, int width, int height, std::mt19937& rng) {
    msmcl::Texture t;
    t.format = format;
    t.width = width;
    t.height = height;
    for (int i = 0; i < width * height; ++i) {
        const ref::Moments b = ref::moments_of(random_texel_distribution(rng));
        switch (format) {
            case msmcl::Format::moments128:
                for (double m : {b.b1, b.b2, b.b3, b.b4}) {
                    const float f = static_cast<float>(m);
                    std::uint32_t w;
                    std::memcpy(&w, &f, 4);
                    t.words.push_back(w);
                }
                break;
            case msmcl::Format::msm64: {
                const auto words = ref::pack_codes16(ref::encode_msm64(b));
                t.words.insert(t.words.end(), words.begin(), words.end());
                break;
            }
            case msmcl::Format::nlq64: {
                const auto nlq = ref::nlq_from_moments(ref::bias(b, ref::alpha_float, ref::bstar_float));
                const auto words = ref::pack_codes16(ref::encode_nlq64(nlq));
                t.words.insert(t.words.end(), words.begin(), words.end());
                break;
            }
            case msmcl::Format::nlq32:
                t.words.push_back(
                    ref::encode_nlq32(ref::nlq_from_moments(ref::bias(b, ref::alpha_float, ref::bstar_float))));
                break;
        }
    }
    return t;
}

} // namespace msmcl::testing
