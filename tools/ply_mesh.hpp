// A small PLY reader: ascii and binary_little_endian files, vertex positions (x, y, z) and
// face index lists (polygons are split into triangle fans). Other elements and
// properties are read past and ignored.
#pragma once

#include "geometry.hpp"

#include <array>
#include <string>
#include <vector>

namespace msmcl::data {

struct TriangleMesh {
    std::vector<Vec3> vertices;
    std::vector<std::array<int, 3>> triangles;
};

/// Throws std::runtime_error naming the file and the problem.
TriangleMesh read_ply(const std::string& path);

} // namespace msmcl::data
