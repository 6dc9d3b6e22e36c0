// Double-precision reference of prefiltered single scattering; see scatter_reference.hpp.
#include "reference/scatter_reference.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <thread>

namespace msmcl::reference {

namespace {

constexpr double pi = 3.14159265358979323846;

Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 scaled(double s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 unit(const Vec3& a) { return scaled(1.0 / std::sqrt(dot(a, a)), a); }

/// Coordinates of a world vector along the light axes.
Vec3 in_light(const ScatterSetup& setup, const Vec3& v) {
    const Axes a = light_axes(setup);
    return {dot(v, a.x), dot(v, a.y), dot(v, a.z)};
}

/// Solves the n x n system (row-major) by Gaussian elimination with partial pivoting in long
/// double; false if singular.
bool solve(std::vector<long double> a, std::vector<long double> b, int n, std::vector<long double>& x) {
    for (int c = 0; c < n; ++c) {
        int pivot = c;
        for (int r = c + 1; r < n; ++r)
            if (std::fabs(a[r * n + c]) > std::fabs(a[pivot * n + c])) pivot = r;
        if (a[pivot * n + c] == 0) return false;
        for (int k = 0; k < n; ++k) std::swap(a[c * n + k], a[pivot * n + k]);
        std::swap(b[c], b[pivot]);
        for (int r = c + 1; r < n; ++r) {
            const long double f = a[r * n + c] / a[c * n + c];
            for (int k = c; k < n; ++k) a[r * n + k] -= f * a[c * n + k];
            b[r] -= f * b[c];
        }
    }
    x.assign(n, 0);
    for (int r = n - 1; r >= 0; --r) {
        long double s = b[r];
        for (int k = r + 1; k < n; ++k) s -= a[r * n + k] * x[k];
        x[r] = s / a[r * n + r];
    }
    return true;
}

long double polynomial(const std::vector<long double>& c, long double x) {
    long double y = 0;
    for (int k = static_cast<int>(c.size()) - 1; k >= 0; --k) y = y * x + c[k];
    return y;
}

/// A root of the polynomial in [lo, hi] where it changes sign, by bisection.
long double bisect(const std::vector<long double>& c, long double lo, long double hi) {
    long double flo = polynomial(c, lo);
    for (int i = 0; i < 200; ++i) {
        const long double mid = 0.5L * (lo + hi);
        const long double fmid = polynomial(c, mid);
        if ((fmid <= 0) == (flo <= 0)) {
            lo = mid;
            flo = fmid;
        } else {
            hi = mid;
        }
    }
    return 0.5L * (lo + hi);
}

/// The real roots of a cubic c0 + c1 x + c2 x^2 + c3 x^3 (c3 != 0): bisection between the
/// critical points and far brackets.
std::vector<long double> cubic_roots(const std::vector<long double>& c) {
    // Critical points: roots of c1 + 2 c2 x + 3 c3 x^2.
    std::vector<long double> breaks;
    const long double a = 3 * c[3], b = 2 * c[2], d = c[1];
    const long double disc = b * b - 4 * a * d;
    if (disc > 0) {
        const long double s = std::sqrt(disc);
        breaks.push_back((-b - s) / (2 * a));
        breaks.push_back((-b + s) / (2 * a));
        std::sort(breaks.begin(), breaks.end());
    }
    // Cauchy bound on the roots.
    const long double bound = 1 + std::max({std::fabs(c[0] / c[3]), std::fabs(c[1] / c[3]), std::fabs(c[2] / c[3])});
    std::vector<long double> edges{-bound};
    for (long double x : breaks) edges.push_back(std::clamp(x, -bound, bound));
    edges.push_back(bound);
    std::vector<long double> roots;
    for (std::size_t i = 0; i + 1 < edges.size(); ++i) {
        const long double f0 = polynomial(c, edges[i]), f1 = polynomial(c, edges[i + 1]);
        if (f0 == 0) roots.push_back(edges[i]);
        else if ((f0 < 0) != (f1 < 0)) roots.push_back(bisect(c, edges[i], edges[i + 1]));
    }
    return roots;
}

} // namespace

Axes light_axes(const ScatterSetup& setup) {
    Axes a;
    a.z = unit(setup.light_direction);
    a.x = unit(cross(a.z, setup.light_up));
    a.y = cross(a.x, a.z);
    return a;
}

Axes camera_axes(const ScatterSetup& setup) {
    Axes a;
    a.z = unit(setup.camera_forward);
    a.x = unit(cross(a.z, setup.camera_up));
    a.y = cross(a.x, a.z);
    return a;
}

Rectified rectify(const ScatterSetup& setup, const Vec3& world) {
    const Vec3 p = in_light(setup, sub(world, setup.camera_position));
    Rectified rc;
    rc.r = std::hypot(p[0], p[1]);
    rc.phi = std::atan2(p[1], p[0]);
    if (rc.phi < 0) rc.phi += 2 * pi;
    // Angle between p and -z (towards the light).
    rc.x = std::acos(std::clamp(-p[2] / std::sqrt(dot(p, p)), -1.0, 1.0));
    return rc;
}

Vec3 unrectify(const ScatterSetup& setup, double phi, double x, double distance) {
    // theta = pi - x: the direction (sin theta cos phi, sin theta sin phi, cos theta).
    const double theta = pi - x;
    const Vec3 local{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
    const Axes a = light_axes(setup);
    const Vec3 world_direction = add(add(scaled(local[0], a.x), scaled(local[1], a.y)), scaled(local[2], a.z));
    return add(setup.camera_position, scaled(distance, world_direction));
}

Vec3 view_direction(const ScatterSetup& setup, double px, double py) {
    const Axes c = camera_axes(setup);
    const double t = std::tan(0.5 * setup.fov_y_degrees * pi / 180.0);
    const double sx = (2 * px / setup.camera_width - 1) * t * setup.camera_width / setup.camera_height;
    const double sy = (1 - 2 * py / setup.camera_height) * t;
    return unit(add(add(c.z, scaled(sx, c.x)), scaled(sy, c.y)));
}

double eye_depth(const ScatterSetup& setup, double depth_value) {
    const double n = setup.camera_near, f = setup.camera_far;
    if (setup.camera_depth_mode == 2) return depth_value;
    const double d = setup.camera_depth_mode == 1 ? (depth_value + 1) / 2 : depth_value;
    // Inverse of d = f (z - n) / (z (f - n)).
    return n * f / (f - d * (f - n));
}

double ray_length(const ScatterSetup& setup, double px, double py, double depth_value) {
    const Vec3 direction = view_direction(setup, px, py);
    return eye_depth(setup, depth_value) / dot(direction, camera_axes(setup).z);
}

FrustumExtent frustum_extent(const ScatterSetup& setup, int grid) {
    FrustumExtent e;
    for (int iy = 0; iy <= grid; ++iy)
        for (int ix = 0; ix <= grid; ++ix) {
            const double px = setup.camera_width * static_cast<double>(ix) / grid;
            const double py = setup.camera_height * static_cast<double>(iy) / grid;
            const Vec3 d = view_direction(setup, px, py);
            const Vec3 far_point = add(setup.camera_position, scaled(ray_length(setup, px, py, setup.camera_depth_mode == 2 ? setup.camera_far : 1.0), d));
            const Rectified rc = rectify(setup, far_point);
            e.r_max = std::max(e.r_max, rc.r);
            e.theta_min = std::min(e.theta_min, pi - rc.x);
            e.theta_max = std::max(e.theta_max, pi - rc.x);
            e.phis.push_back(rc.phi);
        }
    return e;
}

MapPoint map_point(const ScatterSetup& setup, int map_width, int map_height, const Vec3& world) {
    const Vec3 p = in_light(setup, sub(world, setup.light_center));
    MapPoint m;
    m.u = (p[0] / setup.light_width + 0.5) * map_width;
    m.v = (0.5 - p[1] / setup.light_height) * map_height;
    const double d = (p[2] - setup.light_near) / (setup.light_far - setup.light_near);
    m.z = 2 * d - 1;
    return m;
}

TwoDepths two_depths(double b1_, double b2_, double b3_) {
    const long double b1 = b1_, b2 = b2_, b3 = b3_;
    const long double c2 = b2 - b1 * b1, c1 = b1 * b2 - b3, c0 = -b1 * c1 - b2 * c2;
    TwoDepths t;
    const long double disc = c1 * c1 - 4 * c2 * c0;
    if (!(c2 > 0) || !(disc > 0)) {
        t.z2 = t.z3 = b1_;
        t.w3 = 0;
        return t;
    }
    const long double s = std::sqrt(disc);
    const long double lo = (-c1 - s) / (2 * c2), hi = (-c1 + s) / (2 * c2);
    t.z2 = static_cast<double>(lo);
    t.z3 = static_cast<double>(hi);
    t.w3 = static_cast<double>((b1 - lo) / (hi - lo));
    return t;
}

Moments6 moments6_of(double z) {
    Moments6 m;
    double p = 1;
    for (int k = 0; k < 6; ++k) m[k] = p *= z;
    return m;
}

double rectified_depth(const ScatterRectification& rect, double x) {
    return std::clamp(2 * (x - rect.depth_min) / (rect.depth_max - rect.depth_min) - 1, -1.0, 1.0);
}

namespace {

/// World point on the light ray of rectified texel (i, j) at internal map depth z, and the
/// rectified depth of that point.
double occluder_rectified_depth(const ScatterSetup& setup, const ScatterRectification& rect, double r, double phi,
                                double zmap) {
    zmap = std::clamp(zmap, -1.0, 1.0);
    // Camera-centred light coordinates of the point: (r cos phi, r sin phi, z).
    const Vec3 camera_offset = in_light(setup, sub(setup.camera_position, setup.light_center));
    const double light_depth = setup.light_near + 0.5 * (zmap + 1) * (setup.light_far - setup.light_near);
    const double z = light_depth - camera_offset[2];
    const double x = std::atan2(r, -z); // angle to -z
    (void)phi;
    return rectified_depth(rect, x);
}

void texel_ray(const ScatterRectification& rect, const ScatterSetup& setup, int i, int j, double& r, double& phi) {
    r = (i + 0.5) * rect.r_max / setup.rect_width;
    phi = rect.phi_min + (j + 0.5) * rect.phi_range / setup.rect_height;
}

/// Map coordinates (u, v) of the light ray at (r, phi) around the camera.
void light_ray_texel(const ScatterSetup& setup, int map_width, int map_height, double r, double phi, double& u,
                     double& v) {
    const Axes a = light_axes(setup);
    const Vec3 world = add(setup.camera_position, add(scaled(r * std::cos(phi), a.x), scaled(r * std::sin(phi), a.y)));
    const MapPoint m = map_point(setup, map_width, map_height, world);
    u = m.u;
    v = m.v;
}

} // namespace

RectifiedDepths resample_filtered_depths(const ScatterSetup& setup, const ScatterRectification& rect,
                                         const std::vector<Moments>& moment_map, int map_width, int map_height, int i,
                                         int j) {
    double r, phi, u, v;
    texel_ray(rect, setup, i, j, r, phi);
    light_ray_texel(setup, map_width, map_height, r, phi, u, v);
    // Bilinear between texel centres; beyond the map every moment is 1 (z = 1).
    const double fx = u - 0.5, fy = v - 0.5;
    const double x0 = std::floor(fx), y0 = std::floor(fy), tx = fx - x0, ty = fy - y0;
    double b[3] = {0, 0, 0};
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            const double x = x0 + dx, y = y0 + dy;
            const double w = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty);
            Moments m{1, 1, 1, 1};
            if (x >= 0 && y >= 0 && x < map_width && y < map_height)
                m = moment_map[static_cast<std::size_t>(y) * map_width + static_cast<std::size_t>(x)];
            b[0] += w * m.b1;
            b[1] += w * m.b2;
            b[2] += w * m.b3;
        }
    const TwoDepths t = two_depths(b[0], b[1], b[2]);
    RectifiedDepths d;
    d.d2 = occluder_rectified_depth(setup, rect, r, phi, t.z2);
    d.d3 = occluder_rectified_depth(setup, rect, r, phi, t.z3);
    d.w3 = t.w3;
    return d;
}

Moments6 resample_filtered(const ScatterSetup& setup, const ScatterRectification& rect,
                           const std::vector<Moments>& moment_map, int map_width, int map_height, int i, int j) {
    const RectifiedDepths d = resample_filtered_depths(setup, rect, moment_map, map_width, map_height, i, j);
    const Moments6 m2 = moments6_of(d.d2);
    const Moments6 m3 = moments6_of(d.d3);
    Moments6 out;
    for (int k = 0; k < 6; ++k) out[k] = (1 - d.w3) * m2[k] + d.w3 * m3[k];
    return out;
}

Moments6 resample_unfiltered(const ScatterSetup& setup, const ScatterRectification& rect, const DepthMap& depth,
                             int i, int j) {
    double r, phi, u, v;
    texel_ray(rect, setup, i, j, r, phi);
    light_ray_texel(setup, depth.width, depth.height, r, phi, u, v);
    const double x = std::floor(u), y = std::floor(v);
    double zmap = 1;
    if (x >= 0 && y >= 0 && x < depth.width && y < depth.height) {
        const double d =
            depth.depth[(static_cast<std::size_t>(y) * depth.width + static_cast<std::size_t>(x)) * depth.samples];
        zmap = internal_depth(d, depth.zero_one);
    }
    return moments6_of(occluder_rectified_depth(setup, rect, r, phi, zmap));
}

std::vector<Moments6> prefix_sums(const std::vector<Moments6>& row, double extinction, double texel_distance) {
    std::vector<Moments6> sums(row.size());
    long double weight_sum = 0;
    std::array<long double, 6> sum{};
    for (std::size_t i = 0; i < row.size(); ++i) {
        const long double w = (std::exp(-extinction * i * texel_distance) - std::exp(-extinction * (i + 1.0) * texel_distance)) /
                              extinction;
        weight_sum += w;
        for (int k = 0; k < 6; ++k) {
            sum[k] += w * row[i][k];
            sums[i][k] = static_cast<double>(sum[k] / weight_sum);
        }
    }
    return sums;
}

std::array<double, 6> six_moment_channels(const Moments6& b) {
    // (R0, G0, B0) = Mo^T (b1, b3, b5) + 0.5, (R1, G1, B1) = Me^T (b2, b4, b6) + (0, 0, 0.018888946).
    const double mo[3][3] = {{2.5, -1.87499864, 1.26583039}, {-10, 4.20757543, -1.47644883}, {8, -1.83257679, 0.71061660}};
    const double me[3][3] = {{4, 9, -0.57759806}, {-4, -24, 4.61936648}, {0, 16, -3.07953907}};
    const double odd[3] = {b[0], b[2], b[4]}, even[3] = {b[1], b[3], b[5]};
    std::array<double, 6> c{};
    for (int col = 0; col < 3; ++col) {
        for (int row = 0; row < 3; ++row) {
            c[col] += mo[row][col] * odd[row];
            c[3 + col] += me[row][col] * even[row];
        }
        c[col] += 0.5;
    }
    c[5] += 0.018888946;
    return c;
}

Moments6 six_moment_from_channels(const std::array<double, 6>& channels) {
    const double mo[3][3] = {{2.5, -1.87499864, 1.26583039}, {-10, 4.20757543, -1.47644883}, {8, -1.83257679, 0.71061660}};
    const double me[3][3] = {{4, 9, -0.57759806}, {-4, -24, 4.61936648}, {0, 16, -3.07953907}};
    // Solve Mo^T x = c - offset (and likewise for the even powers).
    std::vector<long double> ao(9), ae(9), bo(3), be(3), xo, xe;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            ao[r * 3 + c] = mo[c][r];
            ae[r * 3 + c] = me[c][r];
        }
    for (int k = 0; k < 3; ++k) {
        bo[k] = channels[k] - 0.5;
        be[k] = channels[3 + k] - (k == 2 ? 0.018888946 : 0.0);
    }
    solve(ao, bo, 3, xo);
    solve(ae, be, 3, xe);
    return {static_cast<double>(xo[0]), static_cast<double>(xe[0]), static_cast<double>(xo[1]),
            static_cast<double>(xe[1]), static_cast<double>(xo[2]), static_cast<double>(xe[2])};
}

Bounds hamburger6(const Moments6& b, double zf) {
    const long double m[7] = {1, b[0], b[1], b[2], b[3], b[4], b[5]};
    std::vector<long double> hankel(16), rhs(4), c;
    for (int r = 0; r < 4; ++r)
        for (int k = 0; k < 4; ++k) hankel[r * 4 + k] = m[r + k];
    const long double z0 = zf;
    for (int k = 0; k < 4; ++k) rhs[k] = std::pow(z0, k);
    if (!solve(hankel, rhs, 4, c)) throw std::runtime_error("hamburger6: singular Hankel matrix");
    // Support: zf and the real roots of c.
    std::vector<long double> support{z0};
    for (long double root : cubic_roots(c)) support.push_back(root);
    const int n = static_cast<int>(support.size());
    // Weights: sum_k w_k z_k^j = m_j for j < n.
    std::vector<long double> vandermonde(n * n), moments(n), w;
    for (int j = 0; j < n; ++j) {
        for (int k = 0; k < n; ++k) vandermonde[j * n + k] = std::pow(support[k], j);
        moments[j] = m[j];
    }
    if (!solve(vandermonde, moments, n, w)) throw std::runtime_error("hamburger6: coincident support points");
    Bounds bounds;
    long double lower = 0;
    for (int k = 1; k < n; ++k)
        if (support[k] < z0) lower += w[k];
    bounds.lower = static_cast<double>(lower);
    bounds.upper = static_cast<double>(lower + w[0]);
    return bounds;
}

double henyey_greenstein(double g, double cos_angle) {
    const double d = 1 + g * g - 2 * g * cos_angle;
    return (1 - g * g) / (4 * pi * std::pow(d, 1.5));
}

double ray_march(const ScatterSetup& setup, const DepthMap& depth, int px, int py, double depth_value, int steps) {
    const Vec3 direction = view_direction(setup, px + 0.5, py + 0.5);
    const double length = ray_length(setup, px + 0.5, py + 0.5, depth_value);
    if (steps <= 0) {
        // Segments of at most a tenth of a texel across the map (at least 256, at most 8192).
        const Vec3 local = in_light(setup, direction);
        const double texel = std::min(setup.light_width / depth.width, setup.light_height / depth.height);
        const double across = std::hypot(local[0], local[1]) * length / texel;
        steps = static_cast<int>(std::clamp(10 * across, 256.0, 8192.0));
    }
    const double s = setup.extinction, segment = length / steps;
    double sum = 0;
    for (int k = 0; k < steps; ++k) {
        const Vec3 point = add(setup.camera_position, scaled((k + 0.5) * segment, direction));
        const MapPoint m = map_point(setup, depth.width, depth.height, point);
        const double x = std::floor(m.u), y = std::floor(m.v);
        double lit = m.z <= 1 ? 1 : 0;
        if (x >= 0 && y >= 0 && x < depth.width && y < depth.height) {
            int count = 0;
            for (int i = 0; i < depth.samples; ++i) {
                const double d = depth.depth[(static_cast<std::size_t>(y) * depth.width + static_cast<std::size_t>(x)) *
                                                 depth.samples + i];
                count += m.z <= internal_depth(d, depth.zero_one) ? 1 : 0;
            }
            lit = static_cast<double>(count) / depth.samples;
        }
        sum += lit * (std::exp(-s * k * segment) - std::exp(-s * (k + 1) * segment)) / s;
    }
    const double cos_angle = -dot(direction, light_axes(setup).z);
    return henyey_greenstein(setup.phase_g, cos_angle) * setup.irradiance * sum;
}

std::vector<double> ray_march_image(const ScatterSetup& setup, const DepthMap& depth,
                                    const std::vector<float>& camera_depth, int steps, int threads) {
    if (steps < 1) throw std::invalid_argument("ray_march_image: steps must be >= 1");
    const std::size_t pixels = static_cast<std::size_t>(setup.camera_width) * setup.camera_height;
    if (camera_depth.size() != pixels) throw std::invalid_argument("ray_march_image: camera depth size");
    std::vector<double> radiance(pixels);
    const Axes light = light_axes(setup);
    // Map point of the camera and of a unit step along each light axis (map_point is affine).
    const MapPoint origin = map_point(setup, depth.width, depth.height, setup.camera_position);
    const auto map_step = [&](const Vec3& direction) {
        const MapPoint m = map_point(setup, depth.width, depth.height, add(setup.camera_position, direction));
        return Vec3{m.u - origin.u, m.v - origin.v, m.z - origin.z};
    };
    const auto march_row = [&](int py) {
        for (int px = 0; px < setup.camera_width; ++px) {
            const std::size_t pixel = static_cast<std::size_t>(py) * setup.camera_width + px;
            const Vec3 direction = view_direction(setup, px + 0.5, py + 0.5);
            const double length = ray_length(setup, px + 0.5, py + 0.5, camera_depth[pixel]);
            const double segment = length / steps;
            const Vec3 per_unit = map_step(direction);
            // Transmittance at the segment's start, and its factor per segment.
            const double s = setup.extinction, factor = std::exp(-s * segment);
            double transmittance = 1, sum = 0;
            for (int k = 0; k < steps; ++k) {
                const double t = (k + 0.5) * segment;
                const double u = origin.u + t * per_unit[0], v = origin.v + t * per_unit[1];
                const double z = origin.z + t * per_unit[2];
                const double x = std::floor(u), y = std::floor(v);
                double lit = z <= 1 ? 1 : 0;
                if (x >= 0 && y >= 0 && x < depth.width && y < depth.height) {
                    const float* texel = depth.depth.data() +
                                         (static_cast<std::size_t>(y) * depth.width + static_cast<std::size_t>(x)) *
                                             depth.samples;
                    int count = 0;
                    for (int i = 0; i < depth.samples; ++i) count += z <= internal_depth(texel[i], depth.zero_one) ? 1 : 0;
                    lit = static_cast<double>(count) / depth.samples;
                }
                sum += lit * transmittance;
                transmittance *= factor;
            }
            const double cos_angle = -dot(direction, light.z);
            radiance[pixel] =
                henyey_greenstein(setup.phase_g, cos_angle) * setup.irradiance * sum * -std::expm1(-s * segment) / s;
        }
    };
    // Rows dealt out round-robin to the threads.
    const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
    const int count = std::max(1, std::min(threads > 0 ? threads : static_cast<int>(hardware), setup.camera_height));
    std::vector<std::thread> workers;
    for (int w = 0; w < count; ++w)
        workers.emplace_back([&, w] {
            for (int py = w; py < setup.camera_height; py += count) march_row(py);
        });
    for (std::thread& worker : workers) worker.join();
    return radiance;
}

double unshadowed_radiance(const ScatterSetup& setup, int px, int py, double depth_value) {
    const Vec3 direction = view_direction(setup, px + 0.5, py + 0.5);
    const double length = ray_length(setup, px + 0.5, py + 0.5, depth_value);
    const double s = setup.extinction;
    return henyey_greenstein(setup.phase_g, -dot(direction, light_axes(setup).z)) * setup.irradiance *
           -std::expm1(-s * length) / s;
}

double prefiltered_radiance(const ScatterSetup& setup, const ScatterRectification& rect,
                           const std::vector<Moments6>& sums, int moments, double beta, int px, int py,
                           double depth_value) {
    const Vec3 direction = view_direction(setup, px + 0.5, py + 0.5);
    const double length = ray_length(setup, px + 0.5, py + 0.5, depth_value);
    const Rectified rc = rectify(setup, add(setup.camera_position, scaled(length, direction)));
    // Texel i holds the sums up to r = (i + 1) dr.
    const double fx = std::clamp(rc.r / (rect.r_max / setup.rect_width) - 1, 0.0, setup.rect_width - 1.0);
    double relative = rc.phi - rect.phi_min;
    if (!rect.full_circle) {
        while (relative - 0.5 * rect.phi_range < -pi) relative += 2 * pi;
        while (relative - 0.5 * rect.phi_range >= pi) relative -= 2 * pi;
    }
    double fy = relative / rect.phi_range * setup.rect_height - 0.5;
    const int x0 = static_cast<int>(std::floor(fx)), x1 = std::min(x0 + 1, setup.rect_width - 1);
    const double tx = fx - x0;
    int y0, y1;
    double ty;
    if (rect.full_circle) {
        const double f = std::floor(fy);
        ty = fy - f;
        y0 = (static_cast<int>(f) + setup.rect_height) % setup.rect_height;
        y1 = (y0 + 1) % setup.rect_height;
    } else {
        fy = std::clamp(fy, 0.0, setup.rect_height - 1.0);
        y0 = static_cast<int>(std::floor(fy));
        ty = fy - y0;
        y1 = std::min(y0 + 1, setup.rect_height - 1);
    }
    const auto at = [&](int x, int y) { return sums[static_cast<std::size_t>(y) * setup.rect_width + x]; };
    Moments6 b;
    for (int k = 0; k < 6; ++k)
        b[k] = (1 - ty) * ((1 - tx) * at(x0, y0)[k] + tx * at(x1, y0)[k]) + ty * ((1 - tx) * at(x0, y1)[k] + tx * at(x1, y1)[k]);
    const double zf = rectified_depth(rect, rc.x);
    const double cos_towards_light = -dot(direction, light_axes(setup).z);
    const double adaptive = 0.5 * (1 + cos_towards_light);
    Bounds bounds;
    if (moments == 4) {
        // The msm64 bias of the four-moment map.
        const Moments biased = bias(Moments{b[0], b[1], b[2], b[3]}, alpha_msm64, bstar_msm64);
        bounds = hamburger4(biased, zf);
    } else {
        // alpha of docs/math.md; b* = moments of the arcsine distribution on [-1,1]. The bounds of the
        // mixture, less its known share below zf, bound the stored distribution.
        const double alpha = 4e-3, bstar[6] = {0, 0.5, 0, 0.375, 0, 0.3125};
        Moments6 biased;
        for (int k = 0; k < 6; ++k) biased[k] = (1 - alpha) * b[k] + alpha * bstar[k];
        const Bounds mixture = hamburger6(biased, zf);
        const double bias_below = 0.5 + std::asin(std::clamp(zf, -1.0, 1.0)) / pi;
        bounds.lower = (mixture.lower - alpha * bias_below) / (1 - alpha);
        bounds.upper = (mixture.upper - alpha * bias_below) / (1 - alpha);
    }
    // Fixed beta: beta upper + (1 - beta) lower. Adaptive: the weight scaled by the upper bound.
    const double weight = beta >= 0 ? beta : adaptive * std::clamp(bounds.upper, 0.0, 1.0);
    const double shadow = std::clamp(bounds.lower + weight * (bounds.upper - bounds.lower), 0.0, 1.0);
    const double s = setup.extinction;
    return (1 - shadow) * henyey_greenstein(setup.phase_g, cos_towards_light) * setup.irradiance *
           (1 - std::exp(-s * length)) / s;
}

} // namespace msmcl::reference
