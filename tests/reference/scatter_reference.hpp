// Double-precision reference of prefiltered single scattering (docs/math.md), written
// independently of kernels/msm_scatter.clh and of the library: rectified coordinates and
// their inverse, bounds by brute force over the image plane, resampling (Algorithm 1 of
// Peters et al., i3D 2016 in long double), transmittance-weighted prefix sums, six-moment bounds by
// generic linear algebra (Hankel solve, polynomial roots by bisection, Vandermonde
// weights), and ray-marching ground truth.
#pragma once

#include "reference/filter_reference.hpp"
#include "reference/moment_math.hpp"

#include <msmcl/vector3.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace msmcl::reference {

/// The library's 3-vector type (include/msmcl/vector3.hpp); the vector math on it is the
/// reference's own (scatter_reference.cpp).
using Vec3 = msmcl::Vector3;

/// The scene as plain numbers (mirrors msmcl::ScatterScene; see include/msmcl/scatter.hpp
/// for the conventions).
struct ScatterSetup {
    Vec3 light_direction{0, -1, 0}, light_up{0, 0, -1}, light_center{0, 0, 0};
    double light_width = 1, light_height = 1, light_near = 0, light_far = 1;
    bool light_zero_one = true;
    Vec3 camera_position{0, 0, 0}, camera_forward{0, 0, -1}, camera_up{0, 1, 0};
    double fov_y_degrees = 60, camera_near = 0.1, camera_far = 100;
    int camera_width = 1, camera_height = 1;
    int camera_depth_mode = 0; ///< 0: perspective [0,1], 1: perspective [-1,1], 2: linear eye depth
    double extinction = 0.1, phase_g = 0, irradiance = 1;
    int rect_width = 1, rect_height = 1;
};

/// The rectification the library chose (the reference checks it covers the frustum
/// separately, see frustum_extent).
struct ScatterRectification {
    double r_max = 1, phi_min = 0, phi_range = 6.283185307179586;
    bool full_circle = true;
    double depth_min = 0, depth_max = 3.141592653589793; ///< x = pi - theta range -> [-1, 1]
    double texel_distance = 1;
};

/// Orthonormal axes: light (right, up, direction) and camera (right, up, forward).
struct Axes {
    Vec3 x, y, z;
};
Axes light_axes(const ScatterSetup& setup);
Axes camera_axes(const ScatterSetup& setup);

/// Rectified coordinates of a world point relative to the camera: r (distance of its light
/// ray to the camera), phi in [0, 2 pi), x = pi - theta (angle to the direction towards the
/// light) in [0, pi].
struct Rectified {
    double r = 0, phi = 0, x = 0;
};
Rectified rectify(const ScatterSetup& setup, const Vec3& world);
/// The world point at distance `distance` from the camera with these coordinates' phi and x
/// (r is implied: distance * sin(theta)). Inverse of rectify for points off the light axis.
Vec3 unrectify(const ScatterSetup& setup, double phi, double x, double distance);

/// Unit world direction of the view ray through image point (px, py) in pixels (pixel
/// centres at i + 1/2, row 0 at the top); eye_distance: distance to the point at eye depth
/// z_eye along it.
Vec3 view_direction(const ScatterSetup& setup, double px, double py);
double eye_depth(const ScatterSetup& setup, double depth_value);
double ray_length(const ScatterSetup& setup, double px, double py, double depth_value);

/// What the frustum spans, by brute force: every pixel edge and centre of a dense grid
/// over the image plane (`grid` points per side), far-plane distances for r.
struct FrustumExtent {
    double r_max = 0, theta_min = 3.2, theta_max = 0;
    std::vector<double> phis; ///< azimuth of every sampled direction
};
FrustumExtent frustum_extent(const ScatterSetup& setup, int grid);

/// Shadow-map texel coordinates (u, v) and internal depth z in [-1,1] of a world point.
struct MapPoint {
    double u = 0, v = 0, z = 0;
};
MapPoint map_point(const ScatterSetup& setup, int map_width, int map_height, const Vec3& world);

/// Algorithm 1 of Peters et al., i3D 2016 in long double: z2 <= z3, w3 = weight of z3; zero variance
/// gives z2 = z3 = b1, w3 = 0.
struct TwoDepths {
    double z2 = 0, z3 = 0, w3 = 0;
};
TwoDepths two_depths(double b1, double b2, double b3);

/// Six moments (z, ..., z^6).
using Moments6 = std::array<double, 6>;
Moments6 moments6_of(double z);

/// Rectified depth in [-1,1] of the angle x (clamped).
double rectified_depth(const ScatterRectification& rect, double x);

/// Resampled moments (first `moments` of Moments6) of rectified texel (i, j).
/// Filtered: bilinear sample (texel centres, beyond the map: z = 1) of `moment_map`
/// (b1..b4 per texel, row-major), Algorithm 1, each depth converted. Unfiltered: sample 0 of
/// the nearest texel of `depth`.
Moments6 resample_filtered(const ScatterSetup& setup, const ScatterRectification& rect,
                           const std::vector<Moments>& moment_map, int map_width, int map_height, int i, int j);
Moments6 resample_unfiltered(const ScatterSetup& setup, const ScatterRectification& rect, const DepthMap& depth,
                             int i, int j);

/// Normalized transmittance-weighted prefix sums of one row of moments:
/// B(u) = sum_{i<=u} w_i b_i / sum_{i<=u} w_i, w_i = integral of exp(-s t) over
/// [i D, (i + 1) D].
std::vector<Moments6> prefix_sums(const std::vector<Moments6>& row, double extinction, double texel_distance);

/// The six-moment texel transform of docs/math.md before quantization, and its inverse
/// (solved by Gaussian elimination).
std::array<double, 6> six_moment_channels(const Moments6& b);
Moments6 six_moment_from_channels(const std::array<double, 6>& channels);

/// Bounds on the mass strictly below zf of all distributions with moments b1..b6 (given
/// biased, b0 = 1): canonical representation through zf (Hankel system by Gaussian
/// elimination, cubic roots by bisection, weights from the Vandermonde system).
Bounds hamburger6(const Moments6& biased, double zf);

/// Phase function, Henyey-Greenstein, of the cosine between light travel and the direction
/// towards the camera.
double henyey_greenstein(double g, double cos_angle);

/// Ray marching the hard shadow map along pixel (px, py)'s view ray: `steps` segments,
/// visibility at midpoints (nearest texel, share of samples with depth >= the point's;
/// beyond the map: z = 1), exact transmittance per segment. steps = 0: adaptive "exact"
/// integration (segments of at most a tenth of a shadow-map texel's width).
double ray_march(const ScatterSetup& setup, const DepthMap& depth, int px, int py, double depth_value, int steps);

/// The prefiltered estimate of a pixel in double: exact prefix-summed moments `sums`
/// (rect_width x rect_height, row-major, 6 per texel), bilinear lookup as the device does,
/// bounds blend with beta (negative: adaptive), from 4 moments (msm64 bias) or 6 (bias 4e-3
/// towards the arcsine distribution, whose share below zf is then taken out again).
double prefiltered_radiance(const ScatterSetup& setup, const ScatterRectification& rect,
                           const std::vector<Moments6>& sums, int moments, double beta, int px, int py,
                           double depth_value);

} // namespace msmcl::reference
