// The depth maps the bench filters: deterministic synthetic shadow maps.
#pragma once

#include <msmcl/formats.hpp>

#include <cstdint>

namespace msmcl::bench {

/// A size^2 shadow map (depth in [0,1]) with `samples` samples per texel: a sloped wavy
/// receiver and a few dozen disk and box occluders, so that texels on edges mix depths
/// and nlq's Algorithm 2 sees two-depth texels as well as flat ones. Same seed, same map.
DepthImage make_scene(int size, int samples, std::uint32_t seed = 7);

} // namespace msmcl::bench
