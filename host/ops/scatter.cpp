// scatter: rectification bounds, the kernel parameter block, and the device operations of
// prefiltered single scattering (kernels/scatter.cl).
#include "ops/scatter_params.hpp"
#include "ops/transfer.hpp"
#include "ops/kernel_variants.hpp"
#include "runtime/context_impl.hpp"
#include "runtime/enum_names.hpp"
#include "runtime/work_distribution.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/scatter.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace msmcl {

namespace {

constexpr double pi = 3.14159265358979323846;

Vector3 operator+(const Vector3& a, const Vector3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vector3 operator-(const Vector3& a, const Vector3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vector3 operator*(double s, const Vector3& a) { return {s * a[0], s * a[1], s * a[2]}; }
double dot(const Vector3& a, const Vector3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vector3 cross(const Vector3& a, const Vector3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double length(const Vector3& a) { return std::sqrt(dot(a, a)); }
Vector3 normalize(const Vector3& a) { return (1.0 / length(a)) * a; }

/// World vector in light coordinates (right, up, direction).
Vector3 to_light(const detail::LightFrame& light, const Vector3& v) {
    return {dot(v, light.right), dot(v, light.up), dot(v, light.direction)};
}

/// Inclination (angle to +z) of a unit vector.
double inclination(const Vector3& v) { return std::acos(std::clamp(v[2], -1.0, 1.0)); }

/// The four frustum corner directions (eye depth 1: forward + sx right + sy up) in light
/// coordinates, in cyclic order.
std::array<Vector3, 4> frustum_corners(const ScatterScene& scene) {
    const detail::LightFrame light = detail::light_frame(scene.light);
    const detail::CameraFrame camera = detail::camera_frame(scene.camera);
    const double ty = std::tan(0.5 * scene.camera.vertical_fov_degrees * pi / 180.0);
    const double tx = ty * scene.camera.width / scene.camera.height;
    const double sx[4] = {-tx, tx, tx, -tx}, sy[4] = {ty, ty, -ty, -ty};
    std::array<Vector3, 4> corners;
    for (int i = 0; i < 4; ++i)
        corners[i] = to_light(light, camera.forward + sx[i] * camera.right + sy[i] * camera.up);
    return corners;
}

/// Whether the unit direction `v` lies inside the cone spanned by the corners (or within
/// `tolerance` radians of its boundary).
bool cone_contains(const std::array<Vector3, 4>& corners, const Vector3& inside, const Vector3& v, double tolerance) {
    for (int i = 0; i < 4; ++i) {
        Vector3 normal = normalize(cross(corners[i], corners[(i + 1) % 4]));
        if (dot(normal, inside) < 0) normal = -1.0 * normal;
        if (dot(normal, v) < -std::sin(tolerance)) return false;
    }
    return true;
}

/// Extremes of the inclination along the great-circle arc from unit a to unit b.
void arc_inclination_extremes(const Vector3& a, const Vector3& b, double& lowest, double& highest) {
    lowest = std::min({lowest, inclination(a), inclination(b)});
    highest = std::max({highest, inclination(a), inclination(b)});
    const double cos_arc = std::clamp(dot(a, b), -1.0, 1.0);
    const Vector3 orthogonal = b - cos_arc * a;
    if (dot(orthogonal, orthogonal) < 1e-30) return;
    const Vector3 e2 = normalize(orthogonal);
    const double arc = std::acos(cos_arc);
    // cos(angle to +z) along the arc: A cos t + B sin t = R cos(t - t_max).
    const double A = a[2], B = e2[2], R = std::hypot(A, B);
    const double t_max = std::atan2(B, A);
    for (double t : {t_max, t_max + pi, t_max - pi, t_max + 2 * pi}) {
        if (t < 0 || t > arc) continue;
        const double c = A * std::cos(t) + B * std::sin(t);
        lowest = std::min(lowest, std::acos(std::clamp(c, -R, R)));
        highest = std::max(highest, std::acos(std::clamp(c, -R, R)));
    }
}

/// A number as %g prints it.
std::string number_text(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", x);
    return text;
}

/// Sine of the angle between two non-zero vectors.
double sine_between(const Vector3& a, const Vector3& b) {
    return length(cross(a, b)) / (length(a) * length(b));
}

/// The axes of a light or camera looking along `forward` (normalized), with `up_hint`
/// fixing the roll: right = forward x up_hint, up = right x forward.
detail::CameraFrame orthonormal_frame(const Vector3& forward, const Vector3& up_hint) {
    detail::CameraFrame frame;
    frame.forward = normalize(forward);
    frame.right = normalize(cross(frame.forward, up_hint));
    frame.up = cross(frame.right, frame.forward);
    return frame;
}

double wrap_angle(double phi) {
    phi = std::fmod(phi, 2 * pi);
    return phi < 0 ? phi + 2 * pi : phi;
}

} // namespace

namespace detail {

LightFrame light_frame(const ScatterLight& light) {
    const CameraFrame frame = orthonormal_frame(light.direction, light.up);
    LightFrame light_axes;
    light_axes.direction = frame.forward;
    light_axes.right = frame.right;
    light_axes.up = frame.up;
    return light_axes;
}

CameraFrame camera_frame(const ScatterCamera& camera) { return orthonormal_frame(camera.forward, camera.up); }

msm_scatter_params make_scatter_params(const ScatterScene& scene, const RectificationBounds& bounds, int map_width,
                                       int map_height, int map_samples, float beta) {
    const LightFrame light = light_frame(scene.light);
    const CameraFrame camera = camera_frame(scene.camera);
    // The camera in light coordinates relative to the map's centre.
    const Vector3 offset = to_light(light, scene.camera.position - scene.light.center);
    msm_scatter_params p{};
    p.map_du = static_cast<float>(map_width / scene.light.width);
    p.map_u0 = static_cast<float>((offset[0] / scene.light.width + 0.5) * map_width);
    p.map_dv = static_cast<float>(-map_height / scene.light.height);
    p.map_v0 = static_cast<float>((0.5 - offset[1] / scene.light.height) * map_height);
    // zmap in [-1,1] <-> camera-centred light z: z = zmap (far - near)/2 + (far + near)/2 - offset.z.
    p.depth_half_range = static_cast<float>(0.5 * (scene.light.far - scene.light.near));
    p.depth_offset = static_cast<float>(0.5 * (scene.light.far + scene.light.near) - offset[2]);
    p.map_width = map_width;
    p.map_height = map_height;
    p.map_samples = map_samples;
    p.map_depth_zero_one = scene.light.depth_range == DepthRange::zero_one ? 1 : 0;

    p.r_max = static_cast<float>(bounds.r_max);
    p.phi_min = static_cast<float>(bounds.phi_min);
    p.phi_range = static_cast<float>(bounds.phi_range);
    p.depth_min = static_cast<float>(bounds.depth_min);
    p.depth_range = static_cast<float>(bounds.depth_max - bounds.depth_min);
    p.rect_width = scene.rectified_width;
    p.rect_height = scene.rectified_height;
    p.full_circle = bounds.full_circle ? 1 : 0;
    p.extinction = static_cast<float>(scene.medium.extinction);
    p.texel_distance = static_cast<float>(bounds.texel_distance);

    const Vector3 forward = to_light(light, camera.forward), right = to_light(light, camera.right),
                  up = to_light(light, camera.up);
    p.cam_forward_x = static_cast<float>(forward[0]);
    p.cam_forward_y = static_cast<float>(forward[1]);
    p.cam_forward_z = static_cast<float>(forward[2]);
    p.cam_right_x = static_cast<float>(right[0]);
    p.cam_right_y = static_cast<float>(right[1]);
    p.cam_right_z = static_cast<float>(right[2]);
    p.cam_up_x = static_cast<float>(up[0]);
    p.cam_up_y = static_cast<float>(up[1]);
    p.cam_up_z = static_cast<float>(up[2]);
    p.tan_half_fov = static_cast<float>(std::tan(0.5 * scene.camera.vertical_fov_degrees * pi / 180.0));
    p.aspect = static_cast<float>(static_cast<double>(scene.camera.width) / scene.camera.height);
    p.cam_near = static_cast<float>(scene.camera.near);
    p.cam_far = static_cast<float>(scene.camera.far);
    p.cam_width = scene.camera.width;
    p.cam_height = scene.camera.height;
    p.cam_depth_mode = scene.camera.depth == CameraDepth::zero_one        ? MSM_CAMERA_DEPTH_ZERO_ONE
                       : scene.camera.depth == CameraDepth::minus_one_one ? MSM_CAMERA_DEPTH_MINUS_ONE_ONE
                                                                          : MSM_CAMERA_DEPTH_LINEAR;
    p.phase_g = static_cast<float>(scene.medium.phase_g);
    p.irradiance = static_cast<float>(scene.medium.irradiance);
    p.beta = beta;
    return p;
}

} // namespace detail

void validate_scatter_scene(const ScatterScene& scene) {
    const auto require = [](bool ok, const std::string& problem) {
        if (!ok) throw input_error(problem);
    };
    const auto finite3 = [](const Vector3& v) {
        return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
    };
    const ScatterLight& light = scene.light;
    require(finite3(light.direction) && length(light.direction) > 0, "light.direction: must be a non-zero finite vector");
    require(finite3(light.up) && length(light.up) > 0, "light.up: must be a non-zero finite vector");
    require(sine_between(light.direction, light.up) > 1e-6, "light.up: parallel to light.direction");
    require(finite3(light.center), "light.center: not finite");
    require(std::isfinite(light.width) && light.width > 0 && std::isfinite(light.height) && light.height > 0,
            "light.width/height: the map's extent must be positive");
    require(std::isfinite(light.near) && std::isfinite(light.far) && light.far > light.near,
            "light.near/far: need near < far (got " + number_text(light.near) + ", " + number_text(light.far) + ")");

    const ScatterCamera& camera = scene.camera;
    require(finite3(camera.position), "camera.position: not finite");
    require(finite3(camera.forward) && length(camera.forward) > 0, "camera.forward: must be a non-zero finite vector");
    require(finite3(camera.up) && length(camera.up) > 0, "camera.up: must be a non-zero finite vector");
    require(sine_between(camera.forward, camera.up) > 1e-6, "camera.up: parallel to the viewing direction");
    require(std::isfinite(camera.vertical_fov_degrees) && camera.vertical_fov_degrees > 0 &&
                camera.vertical_fov_degrees < 170,
            "camera.fov_y_degrees: must be in (0, 170), got " + number_text(camera.vertical_fov_degrees));
    require(std::isfinite(camera.near) && camera.near > 0 && std::isfinite(camera.far) && camera.far > camera.near,
            "camera.near/far: need 0 < near < far (got " + number_text(camera.near) + ", " +
                number_text(camera.far) + ")");
    require(camera.width >= 1 && camera.height >= 1 && camera.width <= 65536 && camera.height <= 65536,
            "camera.width/height: must be in [1, 65536]");
    // Wide views: the horizontal half-angle must stay below 90 degrees too.
    const double half = 0.5 * camera.vertical_fov_degrees * 3.14159265358979323846 / 180.0;
    require(std::tan(half) * camera.width / camera.height < 1e3, "camera: the horizontal field of view is too wide");

    const ScatterMedium& medium = scene.medium;
    require(std::isfinite(medium.extinction) && medium.extinction > 0,
            "medium.extinction: must be > 0 (got " + number_text(medium.extinction) +
                "); prefiltered single scattering weighs by the transmittance exp(-extinction t) and divides by "
                "the extinction");
    require(std::isfinite(medium.phase_g) && medium.phase_g > -1 && medium.phase_g < 1,
            "medium.phase_g: must be in (-1, 1), got " + number_text(medium.phase_g));
    require(std::isfinite(medium.irradiance) && medium.irradiance >= 0,
            "medium.irradiance: must be finite and >= 0");

    require(scene.rectified_width >= 1 && scene.rectified_height >= 1 && scene.rectified_width <= 65536 &&
                scene.rectified_height <= 65536,
            "rectified.width/height: must be in [1, 65536]");
    require(std::isfinite(scene.guard_band) && scene.guard_band >= 0 && scene.guard_band <= 1,
            "rectified.guard_band: must be in [0, 1]");
}

RectificationBounds rectification_bounds(const ScatterScene& scene) {
    validate_scatter_scene(scene);
    const std::array<Vector3, 4> corners = frustum_corners(scene);
    const detail::LightFrame light = detail::light_frame(scene.light);
    const Vector3 forward = to_light(light, detail::camera_frame(scene.camera).forward);
    std::array<Vector3, 4> unit;
    for (int i = 0; i < 4; ++i) unit[i] = normalize(corners[i]);

    RectificationBounds bounds;
    // r: convex, so its largest value on the frustum is at a far-plane corner.
    for (const Vector3& c : corners)
        bounds.r_max = std::max(bounds.r_max, scene.camera.far * std::hypot(c[0], c[1]));

    // Epipoles: the light's travel direction (+z, "into your shadow") and its opposite.
    const double pole_tolerance = 1e-6;
    bounds.shadow_in_view = cone_contains(unit, forward, {0, 0, 1}, pole_tolerance);
    bounds.light_in_view = cone_contains(unit, forward, {0, 0, -1}, pole_tolerance);

    // theta: extremes over the spherical quadrilateral (vertices, edge interiors, poles).
    double lowest = pi, highest = 0;
    for (int i = 0; i < 4; ++i) arc_inclination_extremes(unit[i], unit[(i + 1) % 4], lowest, highest);
    bounds.theta_min = bounds.shadow_in_view ? 0.0 : lowest;
    bounds.theta_max = bounds.light_in_view ? pi : highest;

    // phi: all of it around an epipole in view, else the wedge of the projected corners
    // (a pointed cone without a pole projects to a wedge narrower than pi).
    bounds.full_circle = bounds.shadow_in_view || bounds.light_in_view;
    if (!bounds.full_circle) {
        double mx = 0, my = 0;
        for (const Vector3& c : unit) {
            const double len = std::hypot(c[0], c[1]);
            mx += c[0] / len;
            my += c[1] / len;
        }
        const double middle = std::atan2(my, mx);
        double lo = pi, hi = -pi;
        for (const Vector3& c : unit) {
            const double delta = std::atan2(-std::sin(middle) * c[0] + std::cos(middle) * c[1],
                                            std::cos(middle) * c[0] + std::sin(middle) * c[1]);
            lo = std::min(lo, delta);
            hi = std::max(hi, delta);
        }
        // A hair of margin against rounding at the edges.
        const double margin = 1e-4;
        bounds.phi_min = wrap_angle(middle + lo - margin);
        bounds.phi_range = hi - lo + 2 * margin;
        bounds.full_circle = bounds.phi_range >= 2 * pi;
    }
    if (bounds.full_circle) {
        bounds.phi_min = 0;
        bounds.phi_range = 2 * pi;
    }

    // Rectified depth x = pi - theta with the guard band on both sides.
    const double x_low = pi - bounds.theta_max, x_high = pi - bounds.theta_min;
    const double guard = scene.guard_band * (x_high - x_low);
    bounds.depth_min = std::max(0.0, x_low - guard);
    bounds.depth_max = std::min(pi, x_high + guard);

    // World distance per texel step along a view ray at the mean inclination.
    const double mean_sine = std::max(std::sin(0.5 * (bounds.theta_min + bounds.theta_max)), 1e-3);
    bounds.texel_distance = bounds.r_max / scene.rectified_width / mean_sine;
    return bounds;
}

namespace {

constexpr int output_quantized = 0;
constexpr int output_sums = 1;
constexpr int output_resampled = 2;

void check_moments(int moments) {
    if (moments != 4 && moments != 6)
        throw input_error("scatter: moments must be 4 or 6, got " + std::to_string(moments));
}

/// Work-items per rectified row (a power of two the device allows) and texels per work-item
/// and chunk of the row. rows_cpu: 64 x 8 (measured on PoCL: 8 consecutive texels per
/// work-item take 40% less CPU time than 1 or 4); rows_gpu: 128 x 2 (more rows in flight,
/// neighbouring work-items on neighbouring texels). automatic: work_distribution.hpp.
struct RowTiling {
    int group = 64;
    int segment = 8;
};

RowTiling row_tiling(const DeviceInfo& device, ScatterKernel kernel) {
    RowTiling tiling;
    const bool gpu_rows = kernel == ScatterKernel::rows_gpu ||
                          (kernel == ScatterKernel::automatic && detail::prefers_gpu_distribution(device));
    if (gpu_rows) {
        tiling.group = 128;
        tiling.segment = 2;
    }
    while (tiling.group > 1 && static_cast<std::size_t>(tiling.group) > device.max_work_group_size) tiling.group /= 2;
    return tiling;
}

cl::Kernel& scatter_kernel(detail::ContextImpl& impl, int moments, const char* name,
                           ScatterKernel distribution = ScatterKernel::automatic) {
    return impl.kernel("scatter.cl", detail::scatter_defines(moments, impl.info, distribution), name);
}

void check_map_fits(const detail::ContextImpl& impl, const ScatterScene& scene, std::size_t bytes_per_texel) {
    const unsigned long long bytes =
        static_cast<unsigned long long>(scene.rectified_width) * scene.rectified_height * bytes_per_texel;
    if (bytes > impl.info.max_alloc_bytes)
        throw device_error("scatter: a " + std::to_string(scene.rectified_width) + "x" +
                          std::to_string(scene.rectified_height) + " rectified map exceeds the device's largest buffer");
}

/// Runs scatter_prefilter over all rows.
void run_prefilter(Context& context, const ScatterScene& scene, cl_mem source, bool filtered, int map_width,
                   int map_height, int map_samples, int moments, int output_mode, cl_mem quantized, cl_mem floats,
                   const Enqueue& enqueue, ScatterKernel distribution = ScatterKernel::automatic) {
    detail::ContextImpl& impl = context.impl();
    const RectificationBounds bounds = rectification_bounds(scene);
    const msm_scatter_params params =
        detail::make_scatter_params(scene, bounds, map_width, map_height, map_samples, -1.0f);
    // The row tiling of the device, with groups halved until the built kernel allows them
    // (llvmpipe: 32); the scan's grouping, and so the low bits of the sums, follow the group.
    DeviceInfo limits = impl.info;
    cl::Kernel* built = &scatter_kernel(impl, moments, "scatter_prefilter", distribution);
    for (detail::KernelFit fit = detail::kernel_fit(impl, *built);
         !fit.runs(static_cast<std::size_t>(row_tiling(limits, distribution).group));
         fit = detail::kernel_fit(impl, *built)) {
        limits.max_work_group_size = detail::fitting_group(fit, static_cast<std::size_t>(row_tiling(limits, distribution).group));
        built = &impl.kernel("scatter.cl", detail::scatter_defines(moments, limits, distribution), "scatter_prefilter");
    }
    cl::Kernel& kernel = *built;
    impl.note_choice("scatter prefilter", std::to_string(row_tiling(limits, distribution).group) + " work-items per row");
    cl::CommandQueue queue = impl.queue_for(enqueue);
    std::vector<cl::Event> waits = detail::wait_list(enqueue);
    // The weights of the prefix sums per column, in double: w_i = exp(-s D i) and
    // 1 / sum_{k<=i} w_k = expm1(-s D) / expm1(-s D (i + 1)).
    const int width = scene.rectified_width;
    const double step = -scene.medium.extinction * bounds.texel_distance;
    std::vector<float> weights(2 * static_cast<std::size_t>(width));
    for (int i = 0; i < width; ++i) {
        weights[i] = static_cast<float>(std::exp(step * i));
        weights[width + i] = static_cast<float>(std::expm1(step) / std::expm1(step * (i + 1)));
    }
    // Copied at creation: nothing is enqueued, nothing waits.
    cl_int status = CL_SUCCESS;
    cl::Buffer weight_buffer(impl.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, weights.size() * sizeof(float),
                             weights.data(), &status);
    detail::check(status, "clCreateBuffer(weights)");
    detail::set_arg(kernel, 0, source);
    detail::set_arg(kernel, 1, static_cast<cl_int>(filtered ? 1 : 0));
    detail::set_arg(kernel, 2, static_cast<cl_int>(output_mode));
    detail::check(kernel.setArg(3, sizeof(params), &params), "clSetKernelArg(params)");
    detail::set_arg(kernel, 4, weight_buffer());
    detail::set_arg(kernel, 5, quantized);
    detail::set_arg(kernel, 6, floats);
    const std::size_t group = static_cast<std::size_t>(row_tiling(limits, distribution).group);
    cl::Event done;
    detail::check(queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(group * scene.rectified_height),
                                             cl::NDRange(group), waits.empty() ? nullptr : &waits, &done),
                  "clEnqueueNDRangeKernel(scatter_prefilter)");
    detail::complete(enqueue, queue, done);
}

/// Global size of a per-pixel kernel: the camera rounded up to 16 x 4 groups.
cl::NDRange pixel_range(const ScatterScene& scene) {
    return cl::NDRange((scene.camera.width + 15) / 16 * 16, (scene.camera.height + 3) / 4 * 4);
}

/// Runs `kernel` over the camera's pixels (16x4 work-groups) after the wait list of
/// `enqueue`, on its queue, and completes as it asks.
void enqueue_over_pixels(detail::ContextImpl& impl, cl::Kernel& kernel, const ScatterScene& scene,
                         const Enqueue& enqueue, const char* what) {
    cl::CommandQueue queue = impl.queue_for(enqueue);
    std::vector<cl::Event> waits = detail::wait_list(enqueue);
    cl::Event done;
    // 16x4, or 16 columns of fewer rows where the built kernel allows fewer work-items.
    const std::size_t group = detail::fitting_group(detail::kernel_fit(impl, kernel), 64);
    const cl::NDRange shape(std::min<std::size_t>(group, 16), std::max<std::size_t>(group / 16, 1));
    detail::check(queue.enqueueNDRangeKernel(kernel, cl::NullRange, pixel_range(scene), shape,
                                             waits.empty() ? nullptr : &waits, &done),
                  what);
    detail::complete(enqueue, queue, done);
}

void check_depth_values(const DepthImage& depth, const char* what) {
    if (depth.width <= 0 || depth.height <= 0)
        throw input_error(std::string(what) + ": the shadow map is empty");
    if (depth.layers != 1)
        throw input_error(std::string(what) + ": the shadow map is a texture array of " + std::to_string(depth.layers) +
                          " layers, scattering takes one");
    if (!is_supported_sample_count(depth.samples))
        throw input_error(std::string(what) + ": unsupported sample count " + std::to_string(depth.samples));
    const std::size_t expected = static_cast<std::size_t>(depth.width) * depth.height * depth.samples;
    if (depth.depth.size() != expected)
        throw input_error(std::string(what) + ": the shadow map holds " + std::to_string(depth.depth.size()) +
                          " values, expected " + std::to_string(expected));
}

void check_shadow_map(const ScatterScene& scene, const DepthImage& depth) {
    check_depth_values(depth, "scatter");
    const double low = scene.light.depth_range == DepthRange::zero_one ? 0.0 : -1.0;
    for (std::size_t i = 0; i < depth.depth.size(); ++i) {
        const float d = depth.depth[i];
        if (!std::isfinite(d) || d < low || d > 1.0f) {
            const std::size_t texel = i / depth.samples;
            throw input_error("scatter: shadow map texel (" + std::to_string(texel % depth.width) + ", " +
                              std::to_string(texel / depth.width) + ") sample " + std::to_string(i % depth.samples) +
                              " holds " + number_text(d) + ", outside the light's depth range [" +
                              (low == 0.0 ? "0" : "-1") + ", 1]");
        }
    }
}

void check_camera_depth(const ScatterScene& scene, const std::vector<float>& camera_depth) {
    const ScatterCamera& camera = scene.camera;
    const std::size_t pixels = static_cast<std::size_t>(camera.width) * camera.height;
    if (camera_depth.size() != pixels)
        throw input_error("scatter: the camera depth buffer holds " + std::to_string(camera_depth.size()) +
                          " pixels, the scene's camera is " + std::to_string(camera.width) + "x" +
                          std::to_string(camera.height));
    const double low = camera.depth == CameraDepth::zero_one ? 0.0 : camera.depth == CameraDepth::minus_one_one ? -1.0 : camera.near;
    const double high = camera.depth == CameraDepth::linear ? camera.far : 1.0;
    std::size_t on_near_plane = 0;
    for (std::size_t i = 0; i < pixels; ++i) {
        const float d = camera_depth[i];
        if (!std::isfinite(d) || d < low || d > high)
            throw input_error("scatter: camera depth pixel (" + std::to_string(i % camera.width) + ", " +
                              std::to_string(i / camera.width) + ") holds " + number_text(d) + ", outside [" +
                              number_text(low) + ", " + number_text(high) + "]");
        on_near_plane += d <= low ? 1 : 0;
    }
    // Geometry around the camera clips the near plane everywhere.
    if (2 * on_near_plane > pixels)
        throw input_error("scatter: the camera is inside geometry: " + std::to_string(on_near_plane) + " of " +
                          std::to_string(pixels) + " camera depth pixels lie on the near plane");
}

/// The source buffer of resampling: the filtered moments128 map, or the depth map itself.
cl::Buffer resampling_source(Context& context, const ScatterScene& scene, const DepthImage& shadow_map,
                             const ScatterOptions& options) {
    detail::ContextImpl& impl = context.impl();
    cl::Buffer depth = detail::upload(impl, shadow_map.depth.data(), shadow_map.depth.size() * sizeof(float),
                              "clCreateBuffer(shadow map)");
    if (!options.filtered) return depth;
    const std::size_t texels = static_cast<std::size_t>(shadow_map.width) * shadow_map.height;
    cl::Buffer moments =
        detail::device_buffer(impl, CL_MEM_READ_WRITE, texels * texel_bytes(Format::moments128), "clCreateBuffer(moment map)");
    FilterOptions filter_options;
    filter_options.format = Format::moments128;
    filter_options.sigma = options.filter_sigma;
    filter_options.depth_range = scene.light.depth_range;
    filter_options.kernel = options.filter_kernel;
    filter(context, DeviceDepth{depth(), shadow_map.width, shadow_map.height, shadow_map.samples}, moments(),
           filter_options);
    return moments;
}

void check_options(const ScatterOptions& options) {
    check_moments(options.moments);
    if (!std::isfinite(options.filter_sigma) || options.filter_sigma < 0)
        throw input_error("scatter: the filter sigma must be finite and >= 0");
    if (!std::isfinite(options.beta) || options.beta > 1)
        throw input_error("scatter: beta must be in [0, 1] (or negative for adaptive)");
}

/// The camera pass of the host calls: the camera depth uploaded, `run(depth, radiance)`
/// enqueues the device call that writes one radiance per pixel, the radiance read back.
template <typename Run>
std::vector<float> camera_pass(detail::ContextImpl& impl, const std::vector<float>& camera_depth, Run run) {
    const cl::Buffer depth =
        detail::upload(impl, camera_depth.data(), camera_depth.size() * 4, "clCreateBuffer(camera depth)");
    const cl::Buffer radiance =
        detail::device_buffer(impl, CL_MEM_READ_WRITE, camera_depth.size() * 4, "clCreateBuffer(radiance)");
    run(depth(), radiance());
    return detail::read_floats(impl, radiance, camera_depth.size());
}

std::size_t rectified_texels(const ScatterScene& scene) {
    return static_cast<std::size_t>(scene.rectified_width) * scene.rectified_height;
}

} // namespace

namespace detail {

std::vector<std::string> scatter_defines(int moments, const DeviceInfo& device, ScatterKernel kernel) {
    const RowTiling tiling = row_tiling(device, kernel);
    return {"MSM_SCATTER_MOMENTS=" + std::to_string(moments), "MSM_SCATTER_GROUP=" + std::to_string(tiling.group),
            "MSM_SCATTER_SEGMENT=" + std::to_string(tiling.segment)};
}

} // namespace detail

void validate_scatter_inputs(const ScatterScene& scene, const DepthImage& shadow_map,
                             const std::vector<float>& camera_depth) {
    validate_scatter_scene(scene);
    check_shadow_map(scene, shadow_map);
    check_camera_depth(scene, camera_depth);
}

void scatter_prefilter(Context& context, const ScatterScene& scene, const DeviceTexture& moment_map, cl_mem scatter_map,
                       int moments, const Enqueue& enqueue) {
    check_moments(moments);
    if (moment_map.format != Format::moments128)
        throw input_error("scatter: filtered resampling needs a moments128 map, got " +
                          std::string(format_name(moment_map.format)));
    if (!moment_map.buffer || !scatter_map) throw input_error("scatter: null cl_mem argument");
    if (moment_map.width <= 0 || moment_map.height <= 0) throw input_error("scatter: the moment map is empty");
    check_map_fits(context.impl(), scene, 8);
    run_prefilter(context, scene, moment_map.buffer, true, moment_map.width, moment_map.height, 1, moments,
                  output_quantized, scatter_map, scatter_map, enqueue);
}

void scatter_prefilter(Context& context, const ScatterScene& scene, const DeviceDepth& shadow_map, cl_mem scatter_map,
                       int moments, const Enqueue& enqueue) {
    check_moments(moments);
    if (!shadow_map.buffer || !scatter_map) throw input_error("scatter: null cl_mem argument");
    if (shadow_map.width <= 0 || shadow_map.height <= 0) throw input_error("scatter: the shadow map is empty");
    if (!is_supported_sample_count(shadow_map.samples))
        throw input_error("scatter: unsupported sample count " + std::to_string(shadow_map.samples));
    check_map_fits(context.impl(), scene, 8);
    run_prefilter(context, scene, shadow_map.buffer, false, shadow_map.width, shadow_map.height, shadow_map.samples,
                  moments, output_quantized, scatter_map, scatter_map, enqueue);
}

void scatter_evaluate(Context& context, const ScatterScene& scene, cl_mem scatter_map, int moments, cl_mem camera_depth,
                      cl_mem radiance, float beta, const Enqueue& enqueue) {
    check_moments(moments);
    if (!scatter_map || !camera_depth || !radiance) throw input_error("scatter: null cl_mem argument");
    if (!std::isfinite(beta) || beta > 1) throw input_error("scatter: beta must be in [0, 1] (or negative for adaptive)");
    detail::ContextImpl& impl = context.impl();
    const RectificationBounds bounds = rectification_bounds(scene);
    // The map's size does not matter for evaluation.
    const msm_scatter_params params = detail::make_scatter_params(scene, bounds, 1, 1, 1, beta);
    cl::Kernel& kernel = scatter_kernel(impl, moments, "scatter_evaluate");
    detail::set_arg(kernel, 0, scatter_map);
    detail::set_arg(kernel, 1, camera_depth);
    detail::check(kernel.setArg(2, sizeof(params), &params), "clSetKernelArg(params)");
    detail::set_arg(kernel, 3, radiance);
    enqueue_over_pixels(impl, kernel, scene, enqueue, "clEnqueueNDRangeKernel(scatter_evaluate)");
}

void scatter_ray_march(Context& context, const ScatterScene& scene, const DeviceDepth& shadow_map, cl_mem camera_depth,
                       cl_mem radiance, int steps, std::uint32_t jitter_seed, const Enqueue& enqueue) {
    if (steps < 1 || steps > 1 << 20) throw input_error("scatter: ray marching needs 1 to 2^20 steps");
    if (!shadow_map.buffer || !camera_depth || !radiance) throw input_error("scatter: null cl_mem argument");
    if (!is_supported_sample_count(shadow_map.samples))
        throw input_error("scatter: unsupported sample count " + std::to_string(shadow_map.samples));
    detail::ContextImpl& impl = context.impl();
    const RectificationBounds bounds = rectification_bounds(scene);
    const msm_scatter_params params =
        detail::make_scatter_params(scene, bounds, shadow_map.width, shadow_map.height, shadow_map.samples, -1.0f);
    cl::Kernel& kernel = scatter_kernel(impl, 6, "scatter_ray_march");
    detail::set_arg(kernel, 0, shadow_map.buffer);
    detail::set_arg(kernel, 1, camera_depth);
    detail::check(kernel.setArg(2, sizeof(params), &params), "clSetKernelArg(params)");
    detail::set_arg(kernel, 3, static_cast<cl_int>(steps));
    detail::set_arg(kernel, 4, static_cast<cl_uint>(jitter_seed));
    detail::set_arg(kernel, 5, radiance);
    enqueue_over_pixels(impl, kernel, scene, enqueue, "clEnqueueNDRangeKernel(scatter_ray_march)");
}

ScatterMap scatter_prefilter(Context& context, const ScatterScene& scene, const DepthImage& shadow_map,
                             const ScatterOptions& options) {
    validate_scatter_scene(scene);
    check_options(options);
    check_shadow_map(scene, shadow_map);
    detail::ContextImpl& impl = context.impl();
    check_map_fits(impl, scene, 8);
    const cl::Buffer source = resampling_source(context, scene, shadow_map, options);
    const std::size_t texels = rectified_texels(scene);
    cl::Buffer map = detail::device_buffer(impl, CL_MEM_READ_WRITE, texels * 8, "clCreateBuffer(scatter map)");
    run_prefilter(context, scene, source(), options.filtered, shadow_map.width, shadow_map.height, shadow_map.samples,
                  options.moments, output_quantized, map(), map(), Enqueue{}, options.kernel);
    ScatterMap result;
    result.moments = options.moments;
    result.width = scene.rectified_width;
    result.height = scene.rectified_height;
    result.bounds = rectification_bounds(scene);
    result.words = detail::read_words(impl, map, texels * 2);
    return result;
}

std::vector<float> scatter_evaluate(Context& context, const ScatterScene& scene, const ScatterMap& map,
                                    const std::vector<float>& camera_depth, const ScatterOptions& options) {
    validate_scatter_scene(scene);
    check_options(options);
    check_camera_depth(scene, camera_depth);
    if (map.moments != options.moments)
        throw input_error("scatter: the map holds " + std::to_string(map.moments) + " moments, the options ask for " +
                          std::to_string(options.moments));
    if (map.width != scene.rectified_width || map.height != scene.rectified_height ||
        map.words.size() != rectified_texels(scene) * 2)
        throw input_error("scatter: the map does not match the scene's rectified size");
    detail::ContextImpl& impl = context.impl();
    const cl::Buffer map_buffer =
        detail::upload(impl, map.words.data(), map.words.size() * 4, "clCreateBuffer(scatter map)");
    return camera_pass(impl, camera_depth, [&](cl_mem depth, cl_mem radiance) {
        scatter_evaluate(context, scene, map_buffer(), options.moments, depth, radiance, options.beta);
    });
}

std::vector<float> scatter(Context& context, const ScatterScene& scene, const DepthImage& shadow_map,
                           const std::vector<float>& camera_depth, const ScatterOptions& options) {
    validate_scatter_inputs(scene, shadow_map, camera_depth);
    check_options(options);
    detail::ContextImpl& impl = context.impl();
    check_map_fits(impl, scene, 8);
    // Everything stays on the device until the radiance.
    const cl::Buffer source = resampling_source(context, scene, shadow_map, options);
    cl::Buffer map =
        detail::device_buffer(impl, CL_MEM_READ_WRITE, rectified_texels(scene) * 8, "clCreateBuffer(scatter map)");
    run_prefilter(context, scene, source(), options.filtered, shadow_map.width, shadow_map.height, shadow_map.samples,
                  options.moments, output_quantized, map(), map(), Enqueue{}, options.kernel);
    return camera_pass(impl, camera_depth, [&](cl_mem depth, cl_mem radiance) {
        scatter_evaluate(context, scene, map(), options.moments, depth, radiance, options.beta);
    });
}

std::vector<float> scatter_ray_march(Context& context, const ScatterScene& scene, const DepthImage& shadow_map,
                                     const std::vector<float>& camera_depth, int steps, std::uint32_t jitter_seed) {
    validate_scatter_inputs(scene, shadow_map, camera_depth);
    detail::ContextImpl& impl = context.impl();
    const cl::Buffer shadow = detail::upload(impl, shadow_map.depth.data(), shadow_map.depth.size() * 4,
                                             "clCreateBuffer(shadow map)");
    return camera_pass(impl, camera_depth, [&](cl_mem depth, cl_mem radiance) {
        scatter_ray_march(context, scene, DeviceDepth{shadow(), shadow_map.width, shadow_map.height, shadow_map.samples},
                          depth, radiance, steps, jitter_seed);
    });
}

std::vector<float> scatter_rectified_moments(Context& context, const ScatterScene& scene, const DepthImage& shadow_map,
                                             const ScatterOptions& options, bool prefix_sums) {
    validate_scatter_scene(scene);
    check_options(options);
    check_shadow_map(scene, shadow_map);
    detail::ContextImpl& impl = context.impl();
    check_map_fits(impl, scene, 4 * options.moments);
    const cl::Buffer source = resampling_source(context, scene, shadow_map, options);
    const std::size_t count = rectified_texels(scene) * options.moments;
    cl::Buffer floats = detail::device_buffer(impl, CL_MEM_READ_WRITE, count * 4, "clCreateBuffer(rectified moments)");
    cl::Buffer unused = detail::device_buffer(impl, CL_MEM_READ_WRITE, 4, "clCreateBuffer");
    run_prefilter(context, scene, source(), options.filtered, shadow_map.width, shadow_map.height, shadow_map.samples,
                  options.moments, prefix_sums ? output_sums : output_resampled, unused(), floats(), Enqueue{},
                  options.kernel);
    return detail::read_floats(impl, floats, count);
}

std::vector<float> decode_scatter_map(const ScatterMap& map) {
    check_moments(map.moments);
    const std::size_t texels = static_cast<std::size_t>(map.width) * map.height;
    if (map.words.size() != texels * 2) throw input_error("scatter: the map's word count does not match its size");
    std::vector<float> values(texels * map.moments);
    for (std::size_t t = 0; t < texels; ++t) {
        if (map.moments == 4) {
            msm_word2 w;
            w.w0 = map.words[2 * t];
            w.w1 = map.words[2 * t + 1];
            const msm_moments m = msm_decode_msm64(w);
            const float v[4] = {m.b1, m.b2, m.b3, m.b4};
            std::copy(v, v + 4, values.begin() + t * 4);
        } else {
            msm_word_pair w;
            w.odd = map.words[t];
            w.even = map.words[texels + t];
            const msm_moments6 m = msm_decode_moments6(w);
            const float v[6] = {m.b1, m.b2, m.b3, m.b4, m.b5, m.b6};
            std::copy(v, v + 6, values.begin() + t * 6);
        }
    }
    return values;
}

// The names of ScatterKernel values, both ways (scatter_kernel_name, parse_scatter_kernel).
constexpr detail::EnumNames<ScatterKernel> scatter_kernel_names[] = {
    {ScatterKernel::automatic, "automatic"},
    {ScatterKernel::rows_gpu, "rows_gpu"},
    {ScatterKernel::rows_cpu, "rows_cpu"},
};

const char* scatter_kernel_name(ScatterKernel kernel) noexcept { return detail::name_in(scatter_kernel_names, kernel); }

std::optional<ScatterKernel> parse_scatter_kernel(std::string_view name) noexcept {
    return detail::parse_in(scatter_kernel_names, name);
}

} // namespace msmcl
