// The double-precision reference's view (tests/reference/scatter_reference.hpp) of a library
// scatter scene and its rectification: shared by tests/scatter_test.cpp and
// bench/scatter_quality.cpp, so that both hand the reference the same numbers.
#pragma once

#include "reference/scatter_reference.hpp"

#include <msmcl/scatter.hpp>

namespace msmcl::testing {

/// The reference's view of a scene.
inline reference::ScatterSetup setup_of(const ScatterScene& s) {
    reference::ScatterSetup r;
    r.light_direction = s.light.direction;
    r.light_up = s.light.up;
    r.light_center = s.light.center;
    r.light_width = s.light.width;
    r.light_height = s.light.height;
    r.light_near = s.light.near;
    r.light_far = s.light.far;
    r.light_zero_one = s.light.depth_range == DepthRange::zero_one;
    r.camera_position = s.camera.position;
    r.camera_forward = s.camera.forward;
    r.camera_up = s.camera.up;
    r.fov_y_degrees = s.camera.vertical_fov_degrees;
    r.camera_near = s.camera.near;
    r.camera_far = s.camera.far;
    r.camera_width = s.camera.width;
    r.camera_height = s.camera.height;
    r.camera_depth_mode = s.camera.depth == CameraDepth::zero_one        ? 0
                          : s.camera.depth == CameraDepth::minus_one_one ? 1
                                                                         : 2;
    r.extinction = s.medium.extinction;
    r.phase_g = s.medium.phase_g;
    r.irradiance = s.medium.irradiance;
    r.rect_width = s.rectified_width;
    r.rect_height = s.rectified_height;
    return r;
}

/// The rectification the library chose, as the reference takes it.
inline reference::ScatterRectification rectification_of(const RectificationBounds& b) {
    return {b.r_max, b.phi_min, b.phi_range, b.full_circle, b.depth_min, b.depth_max, b.texel_distance};
}

} // namespace msmcl::testing
