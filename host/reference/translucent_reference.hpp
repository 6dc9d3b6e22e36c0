// Double-precision reference of translucent occluders (Peters et al., i3D 2016, section 4.2, docs/math.md):
// the surfaces along a light ray, sorted nearest first, block the fraction a_i of the light
// that reaches them; the depth distribution Z has weight prod_{j<i} (1 - a_j) a_i at z_i, and
// the opaque surface takes part with a = 1. Independent of kernels/: an explicit sort and a
// running transmittance.
#pragma once

#include "reference/filter_reference.hpp"
#include "reference/moment_math.hpp"

#include <vector>

namespace msmcl::reference {

/// One translucent layer of a depth map: per sample a rendered depth and an opacity in
/// [0, 1], layout as DepthMap::depth.
struct LayerMap {
    std::vector<float> depth;
    std::vector<float> opacity;
};

/// A translucent surface along a ray: internal depth z in [-1, 1] and opacity a.
struct Surface {
    double z = 0;
    double opacity = 0;
};

/// The distribution Z of one ray: the opaque surface at internal depth opaque_z behind (or
/// among) the translucent surfaces, composited nearest first. Surfaces of zero weight are
/// left out.
Distribution composite(double opaque_z, std::vector<Surface> surfaces);

/// Per texel (row-major) the mean over its samples of the moments of Z.
std::vector<Moments> resolve_translucent(const DepthMap& opaque, const std::vector<LayerMap>& layers);

/// resolve_translucent, then the horizontal and vertical 9-tap blur (as filter_moments).
std::vector<Moments> filter_moments_translucent(const DepthMap& opaque, const std::vector<LayerMap>& layers,
                                                double sigma);

/// The light that reaches internal depth zf, as a shadow intensity: 1 - prod over the
/// surfaces nearer than zf of (1 - a), averaged over the samples of texel `texel`.
double transmittance_shadow(const DepthMap& opaque, const std::vector<LayerMap>& layers, std::size_t texel,
                            double zf);

} // namespace msmcl::reference
