// The one 3-vector type of msmcl: the library's scattering scenes (types.hpp includes this
// header), the tools' geometry (tools/geometry.hpp) and the test references
// (tests/reference/scatter_reference.hpp) all hold points and directions in it. A plain
// std::array without operations, so that each of them keeps its own vector math (the
// references must not share the library's).
#pragma once

#include <array>

namespace msmcl {

/// A point or direction in world space: x, y, z.
using Vector3 = std::array<double, 3>;

} // namespace msmcl
