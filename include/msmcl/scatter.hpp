// scatter: prefiltered single scattering with moment shadow maps (docs/math.md; Peters et al., i3D 2016
// section 2 after Klehm et al. 2014; Peters, GDC Europe 2016, "Prefiltered single scattering").
//
// A directional light with an orthographic shadow map lights a homogeneous medium. The
// shadow map is resampled into rectified coordinates around the camera (u = r, the distance
// of a light ray to the camera; v = phi, its azimuth about the light direction; depth =
// pi - theta, the angle of a point as seen from the camera to the direction towards the
// light), so that every view ray is part of one row at one depth. Per rectified texel the
// moments (4 or 6) of the occluders' rectified depth are stored; transmittance-weighted
// prefix sums along the rows precompute the integral over every view ray. Per camera pixel
// one lookup gives the share of the ray in shadow (a blend of the moment bounds), and
//   radiance = (1 - shadow) * f(phase) * E * (1 - exp(-sigma_t * distance)) / sigma_t.
//
// The device functions a renderer includes are in kernels/msm_scatter.clh.
#pragma once

#include <msmcl/context.hpp>
#include <msmcl/enqueue.hpp>
#include <msmcl/types.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace msmcl {

/// The directional light and its orthographic shadow map. Map axes: right =
/// normalize(direction x up), map_up = right x direction. A world point P has texel
/// coordinates u = (dot(P - center, right) / width + 1/2) * map width, v = (1/2 -
/// dot(P - center, map_up) / height) * map height (rows top to bottom, centres at i + 1/2)
/// and depth d = (dot(P - center, direction) - near) / (far - near) in [0,1], stored as
/// d (depth_range 0,1) or 2d - 1 (depth_range -1,1).
struct ScatterLight {
    Vector3 direction{0, -1, 0}; ///< the direction the light travels (normalized on use)
    Vector3 up{0, 0, -1};        ///< hint for the map's up axis; not parallel to direction
    Vector3 center{0, 0, 0};     ///< world point at the map's centre
    double width = 1, height = 1; ///< world extent of the map across u and v
    double near = 0, far = 1;     ///< depth range along direction, measured from center
    DepthRange depth_range = DepthRange::zero_one;
};

/// Convention of the camera's depth buffer.
enum class CameraDepth {
    zero_one,      ///< perspective depth in [0,1] (D3D/Vulkan): d = f (z - n) / (z (f - n))
    minus_one_one, ///< perspective depth in [-1,1] (OpenGL): (d + 1) / 2 as above
    linear,        ///< eye depth z along the forward axis, world units, in [near, far]
};

/// A pinhole camera. Axes: forward, right = normalize(forward x up), camera_up = right x
/// forward. Pixel (x, y) (row 0 at the top) looks along forward + sx right + sy camera_up,
/// sx = (2 (x + 1/2) / width - 1) tan(fov/2) width / height, sy = (1 - 2 (y + 1/2) / height) tan(fov/2).
/// A depth at the far plane (sky) ends the view ray there.
struct ScatterCamera {
    Vector3 position{0, 0, 0};
    Vector3 forward{0, 0, -1}; ///< normalized on use
    Vector3 up{0, 1, 0};       ///< hint; not parallel to forward
    double vertical_fov_degrees = 60;
    double near = 0.1, far = 100;
    int width = 128, height = 96;
    CameraDepth depth = CameraDepth::zero_one;
};

/// A homogeneous participating medium.
struct ScatterMedium {
    double extinction = 0.1; ///< sigma_t per world unit, > 0
    double phase_g = 0.0;    ///< Henyey-Greenstein asymmetry in (-1, 1); 0 = isotropic
    double irradiance = 1.0; ///< E of the light, >= 0
};

/// Everything `msmcl scatter` reads from the scene file (see data/scatter/README.md).
struct ScatterScene {
    ScatterLight light;
    ScatterCamera camera;
    ScatterMedium medium;
    int rectified_width = 256;  ///< texels along r
    int rectified_height = 256; ///< texels along phi (rows)
    double guard_band = 0.05;   ///< extra share of the inclination range on each side, in [0, 1]
};

/// Throws input_error for anything unusable: zero, negative or non-finite extinction,
/// degenerate axes, fov outside (0, 180), near/far, sizes, g outside (-1, 1).
void validate_scatter_scene(const ScatterScene& scene);

/// Rectification bounds that cover the camera's view frustum (docs/math.md).
struct RectificationBounds {
    double r_max = 0;         ///< largest light-ray distance of the frustum (a far corner)
    double phi_min = 0;       ///< azimuth range [phi_min, phi_min + phi_range], radians
    double phi_range = 0;
    bool full_circle = false; ///< the epipole (light direction or its opposite) is in view
    bool light_in_view = false;  ///< the direction towards the light is inside the frustum
    bool shadow_in_view = false; ///< the light's travel direction is inside the frustum
    double theta_min = 0;     ///< inclinations (angle to the light's travel direction) of
    double theta_max = 0;     ///< the frustum's view directions
    double depth_min = 0;     ///< rectified depth x = pi - theta covered, guard band included:
    double depth_max = 0;     ///< [depth_min, depth_max] maps to [-1, 1]
    double texel_distance = 0; ///< world distance per texel step along a view ray at the mean inclination
};
RectificationBounds rectification_bounds(const ScatterScene& scene);

/// How the prefilter (resampling and prefix sums, one work-group per rectified row) splits
/// a row. Both give the same bits.
enum class ScatterKernel {
    automatic, ///< rows_cpu on devices that report CPU and not GPU, rows_gpu on the others
               ///< (docs/devices.md)
    rows_gpu,  ///< 128 work-items per row, 2 neighbouring texels each (neighbouring
               ///< work-items on neighbouring texels, more rows in flight)
    rows_cpu,  ///< 64 work-items per row, 8 consecutive texels each (measured on PoCL: 40%
               ///< less CPU time than 1 or 4)
};
/// "automatic", "rows_gpu", "rows_cpu".
const char* scatter_kernel_name(ScatterKernel kernel) noexcept;
std::optional<ScatterKernel> parse_scatter_kernel(std::string_view name) noexcept;

struct ScatterOptions {
    int moments = 6;     ///< 4 (msm64 layout) or 6 (two 10:10:10:2 planes)
    bool filtered = true; ///< bilinear samples of a moment shadow map; false: one depth sample
    /// Gaussian sigma (texels) of the moments128 map that filtered resampling samples
    /// (msmcl::filter); 0 = bilinear interpolation of the resolved moments only.
    float filter_sigma = 1.0f;
    /// shadow = beta * upper + (1 - beta) * lower bound; negative: adaptive, the weight
    /// (1 + dot(towards light, view direction)) / 2 of Peters, GDC Europe 2016, times the upper
    /// bound itself (docs/math.md).
    float beta = -1.0f;
    /// The prefilter's distribution of a row over work-items.
    ScatterKernel kernel = ScatterKernel::automatic;
    /// The filter kernel of the moments128 map that filtered resampling reads.
    FilterKernel filter_kernel = FilterKernel::automatic;
};

/// A prefiltered map: rectified_width x rectified_height texels, 64 bits each.
///  - 4 moments: 2 words per texel, the msm64 layout (docs/formats.md affine basis, unorm16);
///  - 6 moments: plane 0 (width * height words: R | G << 10 | B << 20 of the odd powers),
///    then plane 1 (the even powers), docs/math.md transform.
struct ScatterMap {
    int moments = 6;
    int width = 0;
    int height = 0;
    std::vector<std::uint32_t> words;
    RectificationBounds bounds;
};

/// Checks that a shadow map and camera depth buffer fit the scene: camera depth size equals
/// the camera's, all values finite and inside their convention's range (input_error names
/// the first bad pixel), and the camera is not inside geometry (more than half of its depth
/// buffer on the near plane: input_error).
void validate_scatter_inputs(const ScatterScene& scene, const DepthImage& shadow_map,
                             const std::vector<float>& camera_depth);

/// Resampling + prefix sums on the device. Filtered: the shadow map is filtered into a
/// moments128 map (options.filter_sigma) first.
ScatterMap scatter_prefilter(Context& context, const ScatterScene& scene, const DepthImage& shadow_map,
                             const ScatterOptions& options);
/// Radiance per camera pixel (row-major, camera width x height) from a prefiltered map.
std::vector<float> scatter_evaluate(Context& context, const ScatterScene& scene, const ScatterMap& map,
                                    const std::vector<float>& camera_depth, const ScatterOptions& options);
/// Both, after validate_scatter_inputs.
std::vector<float> scatter(Context& context, const ScatterScene& scene, const DepthImage& shadow_map,
                           const std::vector<float>& camera_depth, const ScatterOptions& options);

/// Ground truth: ray marching of the hard shadow map along every view ray with `steps`
/// equal segments (visibility at each midpoint, shifted per pixel by a hashed jitter in
/// [-1/2, 1/2) segments when jitter_seed != 0, times the segment's exact transmittance).
std::vector<float> scatter_ray_march(Context& context, const ScatterScene& scene, const DepthImage& shadow_map,
                                     const std::vector<float>& camera_depth, int steps,
                                     std::uint32_t jitter_seed = 0);

/// For inspection: float moments per rectified texel (moments() floats each, row-major),
/// either the resampled moments or their normalized prefix sums before quantization.
std::vector<float> scatter_rectified_moments(Context& context, const ScatterScene& scene,
                                             const DepthImage& shadow_map, const ScatterOptions& options,
                                             bool prefix_sums);
/// The moments a prefiltered map stores, decoded (map.moments floats per texel).
std::vector<float> decode_scatter_map(const ScatterMap& map);

// ---- Device versions (caller-owned buffers, no host copies).

/// Bytes of a prefiltered map: 8 per texel.
inline std::size_t scatter_map_bytes(const ScatterScene& scene) {
    return static_cast<std::size_t>(scene.rectified_width) * static_cast<std::size_t>(scene.rectified_height) * 8;
}
/// Filtered resampling from a moments128 map (`moment_map.format` must be moments128)
/// into `scatter_map` (scatter_map_bytes). The map's depth convention is the scene light's.
void scatter_prefilter(Context& context, const ScatterScene& scene, const DeviceTexture& moment_map,
                       cl_mem scatter_map, int moments, const Enqueue& enqueue = {});
/// Unfiltered resampling (sample 0 of the nearest texel) from a depth map.
void scatter_prefilter(Context& context, const ScatterScene& scene, const DeviceDepth& shadow_map,
                       cl_mem scatter_map, int moments, const Enqueue& enqueue = {});
/// Per-pixel evaluation: `camera_depth` and `radiance` hold camera width x height floats.
void scatter_evaluate(Context& context, const ScatterScene& scene, cl_mem scatter_map, int moments,
                      cl_mem camera_depth, cl_mem radiance, float beta = -1.0f, const Enqueue& enqueue = {});
/// Ray marching on the device.
void scatter_ray_march(Context& context, const ScatterScene& scene, const DeviceDepth& shadow_map,
                       cl_mem camera_depth, cl_mem radiance, int steps, std::uint32_t jitter_seed = 0,
                       const Enqueue& enqueue = {});

} // namespace msmcl
