// The depth maps the bench filters: deterministic synthetic shadow maps.
#pragma once

#include <msmcl/formats.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace msmcl::bench {

/// A size^2 shadow map (depth in [0,1]) with `samples` samples per texel: a sloped wavy
/// receiver and a few dozen disk and box occluders, so that texels on edges mix depths
/// and nlq's Algorithm 2 sees two-depth texels as well as flat ones. Same seed, same map.
DepthImage make_scene(int size, int samples, std::uint32_t seed = 7);

/// `count` receivers at uniform random spots of `depth`, on its surface (sample 0 of their
/// texel): U, V, Z planar (count values each), in texel units. Same seed, same receivers.
std::vector<float> surface_receivers(const DepthImage& depth, std::size_t count, std::uint32_t seed);

} // namespace msmcl::bench
