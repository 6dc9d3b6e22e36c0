// The host copy of one format's consumer side, a column of the format table
// (host/runtime/texture_kinds.hpp): how a texel decodes and shades on the host, with the
// very device functions of kernels/*.clh compiled as C++ (host/shading/shading.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

namespace msmcl::detail {

/// What shading a texel needs besides the texel: the texture's warp exponents (EVSM's c+ and
/// c-, ESM's c in `positive`) and the options' minimum variance and light-bleed reduction.
struct ShadingParameters {
    float positive = 0, negative = 0;
    float min_variance = 0;
    float light_bleed_reduction = 0;
};

/// One format's host shading and decoding.
struct TexelShading {
    /// Shadow intensity of one texel (its words as a Texture stores them) at internal depth zf.
    float (*texel)(const std::uint32_t* words, float zf, const ShadingParameters& parameters);
    /// The bilinear lookup of a format that blends its stored values (TextureKind::blends_moments):
    /// texels (x0,y0), (x1,y0), (x0,y1), (x1,y1), weights tx, ty of x1 and y1, shaded once.
    /// Null for the formats that shade four texels and blend the intensities.
    float (*blend)(const std::uint32_t* const texels[4], float tx, float ty, float zf,
                   const ShadingParameters& parameters);
    /// Whether the shading is Chebyshev's bound (VSM, EVSM), which alone takes a minimum variance
    /// and a light-bleed reduction.
    bool variance_bound;
    /// What `msmcl info` reports of a texel: `quantities` decoded values, their names, and the
    /// range each may take for a texture of these exponents.
    int quantities;
    const char* names[4];
    void (*decode)(const std::uint32_t* words, float values[4]);
    void (*ranges)(float positive, float negative, double min[4], double max[4]);
};

// One per format (host/shading/shading.cpp), named by the format table's rows.
extern const TexelShading kMoments128Shading, kMsm64Shading, kNlq64Shading, kNlq32Shading, kVsm32Shading,
    kVsm64Shading, kEvsm2_32Shading, kEvsm4_64Shading, kEvsm4_128Shading, kEsm32Shading;

} // namespace msmcl::detail
