// Small double-precision geometry for the sample-data tools: vector arithmetic on the one
// 3-vector type (msmcl::Vector3, include/msmcl/vector3.hpp), an orthographic directional
// light that maps world points to shadow-map texels and depth in [0,1], and cameras that
// produce view rays. Code outside namespace msmcl::data brings the operators in with
// `using namespace msmcl::data::vector_operators;`.
#pragma once

#include <msmcl/vector3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace msmcl::data {

using Vec3 = msmcl::Vector3;

// Operators of a std::array are not found by argument-dependent lookup (its namespace is
// std): code outside msmcl::data says `using namespace msmcl::data::vector_operators;`.
namespace vector_operators {
inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 operator*(double s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
} // namespace vector_operators
using namespace vector_operators;

inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline Vec3 normalize(const Vec3& a) { return (1.0 / std::sqrt(dot(a, a))) * a; }

/// An orthographic directional light looking along `forward`, with a width x height
/// texel shadow map. Texel coordinates: u to the right, v down (row 0 at the top),
/// texel centres at i + 0.5. Depth d = 0 at the near plane, 1 at the far plane.
struct OrthographicLight {
    Vec3 forward, right, up;
    double right_min = 0, right_max = 1, up_min = 0, up_max = 1;
    double near = 0, far = 1;
    int width = 1, height = 1;

    double texel_u(Vec3 p) const { return (dot(p, right) - right_min) / (right_max - right_min) * width; }
    double texel_v(Vec3 p) const { return (up_max - dot(p, up)) / (up_max - up_min) * height; }
    double depth(Vec3 p) const { return (dot(p, forward) - near) / (far - near); }
    /// World point on the near plane at texel coordinates (u, v).
    Vec3 near_point(double u, double v) const {
        const double r = right_min + u / width * (right_max - right_min);
        const double a = up_max - v / height * (up_max - up_min);
        return r * right + a * up + near * forward;
    }
};

/// Fits the light's map around `points` (with a margin, keeping texels square) and its
/// depth range from the nearest point to the farthest ground (y = 0) point the map sees.
inline OrthographicLight fit_light(Vec3 direction, const std::vector<Vec3>& points, int width, int height,
                                   double margin = 0.04) {
    OrthographicLight light;
    light.width = width;
    light.height = height;
    light.forward = normalize(direction);
    // Right is horizontal; up completes the frame.
    light.right = normalize(cross(light.forward, Vec3{0, 1, 0}));
    light.up = cross(light.right, light.forward);

    // Extent across the light, widened to the map's aspect ratio.
    double r0 = std::numeric_limits<double>::max(), r1 = -r0, a0 = r0, a1 = -r0, near = r0;
    for (const Vec3& p : points) {
        r0 = std::min(r0, dot(p, light.right));
        r1 = std::max(r1, dot(p, light.right));
        a0 = std::min(a0, dot(p, light.up));
        a1 = std::max(a1, dot(p, light.up));
        near = std::min(near, dot(p, light.forward));
    }
    double half_r = 0.5 * (r1 - r0) * (1 + margin), half_a = 0.5 * (a1 - a0) * (1 + margin);
    const double aspect = static_cast<double>(width) / height;
    if (half_r < half_a * aspect) half_r = half_a * aspect;
    else half_a = half_r / aspect;
    const double centre_r = 0.5 * (r0 + r1), centre_a = 0.5 * (a0 + a1);
    light.right_min = centre_r - half_r;
    light.right_max = centre_r + half_r;
    light.up_min = centre_a - half_a;
    light.up_max = centre_a + half_a;

    // Depth: the ground is affine across the map, so its farthest point is at a corner.
    light.near = near;
    light.far = near;
    for (double u : {0.0, 1.0 * width})
        for (double v : {0.0, 1.0 * height}) {
            const Vec3 start = light.near_point(u, v);
            const double t = -start[1] / light.forward[1]; // forward.y < 0: the light shines down
            light.far = std::max(light.far, dot(start + t * light.forward, light.forward));
        }
    const double slack = 0.01 * (light.far - light.near);
    light.near -= slack;
    light.far += slack;
    return light;
}

/// A pinhole camera: `ray(px, py)` for pixel coordinates (centres at i + 0.5, y down).
struct PerspectiveCamera {
    Vec3 position, forward, right, up;
    double tan_half_fov = 0.5;
    int width = 1, height = 1;

    PerspectiveCamera(Vec3 eye, Vec3 target, double vertical_fov_degrees, int w, int h)
        : position(eye), width(w), height(h) {
        forward = normalize(target - eye);
        right = normalize(cross(forward, Vec3{0, 1, 0}));
        up = cross(right, forward);
        tan_half_fov = std::tan(0.5 * vertical_fov_degrees * 3.14159265358979323846 / 180.0);
    }
    Vec3 ray(double px, double py) const {
        const double sx = (2 * px / width - 1) * tan_half_fov * width / height;
        const double sy = (1 - 2 * py / height) * tan_half_fov;
        return normalize(forward + sx * right + sy * up);
    }
};

} // namespace msmcl::data
