// Scene files of `msmcl scatter`: JSON text (format: data/scatter/README.md) to a
// ScatterScene. Part of msmcl_io, not of the library: the library takes a ScatterScene.
#pragma once

#include <msmcl/scatter.hpp>

#include <string>

namespace msmcl {

/// Parses a scene from JSON text (nlohmann-json). Throws input_error naming the key, with
/// line and column for malformed JSON; validates like validate_scatter_scene.
ScatterScene parse_scatter_scene(const std::string& json_text);
/// Reads and parses a scene file; errors read "<path>: <problem>".
ScatterScene load_scatter_scene(const std::string& path);

} // namespace msmcl
