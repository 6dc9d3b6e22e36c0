// Internal to the scatter operation (host/ops/scatter*.cpp) and its tests: the frames of
// light and camera and the kernel parameter block of kernels/msm_scatter.clh.
#pragma once

#include "kernels/msm_scatter.clh"

#include <msmcl/scatter.hpp>

namespace msmcl::detail {

/// Orthonormal light axes in world space: right = normalize(direction x up hint),
/// up = right x direction, direction normalized.
struct LightFrame {
    Vector3 right, up, direction;
};
LightFrame light_frame(const ScatterLight& light);

/// Orthonormal camera axes in world space: forward, right = normalize(forward x up hint),
/// up = right x forward.
struct CameraFrame {
    Vector3 forward, right, up;
};
CameraFrame camera_frame(const ScatterCamera& camera);

/// The parameter block the kernels take, for a shadow map of map_width x map_height texels
/// with map_samples samples (in the light's depth convention). beta < 0: adaptive.
msm_scatter_params make_scatter_params(const ScatterScene& scene, const RectificationBounds& bounds, int map_width,
                                       int map_height, int map_samples, float beta);

} // namespace msmcl::detail
