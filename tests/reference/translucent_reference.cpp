// Double-precision reference of translucent occluders: sort, then alpha blending front to back.
#include "reference/translucent_reference.hpp"

#include <algorithm>
#include <cstddef>

namespace msmcl::reference {

namespace {

// The surfaces of sample s of texel `texel`: every layer, in internal depth.
std::vector<Surface> layer_surfaces(const DepthMap& opaque, const std::vector<LayerMap>& layers, std::size_t texel,
                                    int s) {
    std::vector<Surface> surfaces;
    const std::size_t index = texel * opaque.samples + s;
    for (const LayerMap& layer : layers)
        surfaces.push_back({internal_depth(layer.depth[index], opaque.zero_one), layer.opacity[index]});
    return surfaces;
}

} // namespace

Distribution composite(double opaque_z, std::vector<Surface> surfaces) {
    // The opaque surface blocks everything that is left; at equal depth the translucent
    // surfaces go first (the moments do not depend on the order of equal depths).
    surfaces.push_back({opaque_z, 1.0});
    std::stable_sort(surfaces.begin(), surfaces.end(), [](const Surface& a, const Surface& b) { return a.z < b.z; });
    Distribution distribution;
    double transmitted = 1.0;
    for (const Surface& surface : surfaces) {
        const double weight = transmitted * surface.opacity;
        transmitted *= 1.0 - surface.opacity;
        if (weight <= 0.0) continue;
        distribution.depth.push_back(surface.z);
        distribution.weight.push_back(weight);
    }
    return distribution;
}

std::vector<Moments> resolve_translucent(const DepthMap& opaque, const std::vector<LayerMap>& layers) {
    std::vector<Moments> moments(static_cast<std::size_t>(opaque.width) * opaque.height);
    for (std::size_t texel = 0; texel < moments.size(); ++texel)
        for (int s = 0; s < opaque.samples; ++s) {
            // The sample's distribution, its moments, the mean over the samples.
            const double opaque_z = internal_depth(opaque.depth[texel * opaque.samples + s], opaque.zero_one);
            const Moments m = moments_of(composite(opaque_z, layer_surfaces(opaque, layers, texel, s)));
            moments[texel].b1 += m.b1 / opaque.samples;
            moments[texel].b2 += m.b2 / opaque.samples;
            moments[texel].b3 += m.b3 / opaque.samples;
            moments[texel].b4 += m.b4 / opaque.samples;
        }
    return moments;
}

std::vector<Moments> filter_moments_translucent(const DepthMap& opaque, const std::vector<LayerMap>& layers,
                                                double sigma) {
    const std::array<double, 9> weights = gaussian_weights(sigma);
    const std::vector<Moments> resolved = resolve_translucent(opaque, layers);
    return blur(blur(resolved, opaque.width, opaque.height, weights, true), opaque.width, opaque.height, weights,
                false);
}

double transmittance_shadow(const DepthMap& opaque, const std::vector<LayerMap>& layers, std::size_t texel,
                            double zf) {
    double shadow = 0.0;
    for (int s = 0; s < opaque.samples; ++s) {
        const double opaque_z = internal_depth(opaque.depth[texel * opaque.samples + s], opaque.zero_one);
        shadow += exact_shadow(composite(opaque_z, layer_surfaces(opaque, layers, texel, s)), zf) / opaque.samples;
    }
    return shadow;
}

} // namespace msmcl::reference
