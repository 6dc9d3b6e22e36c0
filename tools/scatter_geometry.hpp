// Box scenes for prefiltered single scattering: the "geometry" section of a scatter scene
// file (data/scatter/README.md), exact ray casting in double, and the two depth buffers
// `msmcl scatter` reads: the light's orthographic shadow map and the camera's depth buffer.
// Implements the conventions of include/msmcl/scatter.hpp with its own vector math (not the
// library's), so that a wrong axis in either shows up as a mismatch in the tests.
// Header-only: used by msmcl-scatter-scene, the tests and the bench.
#pragma once

#include <msmcl/errors.hpp>
#include <msmcl/formats.hpp>
#include <msmcl/scatter.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace msmcl::scatter_data {

using V3 = msmcl::Vector3;

inline V3 add(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline V3 mul(double s, const V3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline V3 cross(const V3& a, const V3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline V3 unit(const V3& a) { return mul(1.0 / std::sqrt(dot(a, a)), a); }

/// An axis-aligned solid box.
struct Box {
    V3 low, high;
};

struct Geometry {
    std::vector<Box> boxes;
};

/// The "geometry" section of a scene file: {"boxes": [{"min": [x,y,z], "max": [x,y,z]}, ...]}.
inline Geometry parse_geometry(const std::string& json_text) {
    nlohmann::json document;
    try {
        document = nlohmann::json::parse(json_text);
    } catch (const nlohmann::json::parse_error& e) {
        throw input_error(std::string("malformed JSON: ") + e.what());
    }
    if (!document.is_object() || !document.contains("geometry") || !document["geometry"].is_object() ||
        !document["geometry"].contains("boxes") || !document["geometry"]["boxes"].is_array())
        throw input_error("geometry: expected \"geometry\": {\"boxes\": [...]}");
    const auto vector_of = [](const nlohmann::json& v, const std::string& name) {
        if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
            throw input_error(name + ": expected an array of 3 numbers");
        return V3{v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
    };
    Geometry geometry;
    int index = 0;
    for (const nlohmann::json& box : document["geometry"]["boxes"]) {
        const std::string name = "geometry.boxes[" + std::to_string(index++) + "]";
        if (!box.is_object() || !box.contains("min") || !box.contains("max"))
            throw input_error(name + ": expected {\"min\": [...], \"max\": [...]}");
        Box b{vector_of(box["min"], name + ".min"), vector_of(box["max"], name + ".max")};
        for (int k = 0; k < 3; ++k)
            if (!(b.low[k] < b.high[k])) throw input_error(name + ": min must be below max on every axis");
        geometry.boxes.push_back(b);
    }
    return geometry;
}

/// Distance to the nearest surface along origin + t direction, t >= 0 (0 when the origin is
/// inside a box); infinity when nothing is hit.
inline double cast_ray(const Geometry& geometry, const V3& origin, const V3& direction) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const Box& box : geometry.boxes) {
        double enter = -std::numeric_limits<double>::infinity(), leave = std::numeric_limits<double>::infinity();
        bool missed = false;
        for (int axis = 0; axis < 3 && !missed; ++axis) {
            if (direction[axis] == 0.0) {
                missed = origin[axis] < box.low[axis] || origin[axis] > box.high[axis];
                continue;
            }
            double t0 = (box.low[axis] - origin[axis]) / direction[axis];
            double t1 = (box.high[axis] - origin[axis]) / direction[axis];
            if (t0 > t1) std::swap(t0, t1);
            enter = std::max(enter, t0);
            leave = std::min(leave, t1);
        }
        if (missed || enter > leave || leave < 0.0) continue;
        nearest = std::min(nearest, std::max(enter, 0.0));
    }
    return nearest;
}

/// Axes of the light (right, up, direction) and camera (right, up, forward) as documented in
/// include/msmcl/scatter.hpp.
struct Frame {
    V3 right, up, forward;
};
/// The axes of a view looking along `forward` with `up` roughly up.
inline Frame frame_of(const V3& forward, const V3& up) {
    Frame f;
    f.forward = unit(forward);
    f.right = unit(cross(f.forward, up));
    f.up = cross(f.right, f.forward);
    return f;
}
inline Frame light_frame_of(const ScatterLight& light) { return frame_of(light.direction, light.up); }
inline Frame camera_frame_of(const ScatterCamera& camera) { return frame_of(camera.forward, camera.up); }

/// The light's shadow map: `samples` rays per texel (offsets on a small rotated grid; one
/// sample = the texel centre), depth in [0,1] of the first hit, 1 where nothing is hit,
/// stored in the light's depth convention.
inline DepthImage render_shadow_map(const ScatterScene& scene, const Geometry& geometry, int width, int height,
                                    int samples = 1) {
    const ScatterLight& light = scene.light;
    const Frame frame = light_frame_of(light);
    DepthImage map;
    map.width = width;
    map.height = height;
    map.samples = samples;
    map.depth.resize(static_cast<std::size_t>(width) * height * samples);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int s = 0; s < samples; ++s) {
                // Sample offsets in (-1/2, 1/2): a rotated grid for several samples.
                const double ox = samples == 1 ? 0.0 : (s + 0.5) / samples - 0.5;
                const double oy = samples == 1 ? 0.0 : std::fmod((s * 0.618034) + 0.31, 1.0) - 0.5;
                const double a = ((x + 0.5 + ox) / width - 0.5) * light.width;
                const double b = (0.5 - (y + 0.5 + oy) / height) * light.height;
                const V3 start = add(add(light.center, add(mul(a, frame.right), mul(b, frame.up))),
                                     mul(light.near, frame.forward));
                const double t = cast_ray(geometry, start, frame.forward);
                double d = std::isfinite(t) ? t / (light.far - light.near) : 1.0;
                d = std::clamp(d, 0.0, 1.0);
                if (light.depth_range == DepthRange::minus_one_one) d = 2 * d - 1;
                map.depth[(static_cast<std::size_t>(y) * width + x) * samples + s] = static_cast<float>(d);
            }
    return map;
}

/// The camera's depth buffer (one ray through each pixel centre) in its convention; nothing
/// hit or beyond the far plane: the far plane. A camera inside a box sees its near plane.
inline std::vector<float> render_camera_depth(const ScatterScene& scene, const Geometry& geometry) {
    const ScatterCamera& camera = scene.camera;
    const Frame frame = camera_frame_of(camera);
    const double t = std::tan(0.5 * camera.vertical_fov_degrees * 3.14159265358979323846 / 180.0);
    std::vector<float> depth(static_cast<std::size_t>(camera.width) * camera.height);
    for (int py = 0; py < camera.height; ++py)
        for (int px = 0; px < camera.width; ++px) {
            const double sx = (2 * (px + 0.5) / camera.width - 1) * t * camera.width / camera.height;
            const double sy = (1 - 2 * (py + 0.5) / camera.height) * t;
            const V3 ray = add(frame.forward, add(mul(sx, frame.right), mul(sy, frame.up)));
            // Eye depth of the hit: distance / |ray| (the ray has eye depth 1 per unit of t).
            const double hit = cast_ray(geometry, camera.position, unit(ray));
            double z = std::isfinite(hit) ? hit / std::sqrt(dot(ray, ray)) : camera.far;
            z = std::clamp(z, 0.0, camera.far);
            double value;
            if (camera.depth == CameraDepth::linear) {
                value = std::max(z, camera.near);
            } else {
                // Perspective depth; in front of the near plane it clamps to the near plane.
                const double d =
                    z <= camera.near ? 0.0 : std::clamp(camera.far * (z - camera.near) / (z * (camera.far - camera.near)), 0.0, 1.0);
                value = camera.depth == CameraDepth::minus_one_one ? 2 * d - 1 : d;
            }
            depth[static_cast<std::size_t>(py) * camera.width + px] = static_cast<float>(value);
        }
    return depth;
}

/// parse_geometry of a scene file; errors read "<path>: <problem>".
inline Geometry load_geometry(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw input_error(path + ": cannot open");
    std::ostringstream text;
    text << file.rdbuf();
    try {
        return parse_geometry(text.str());
    } catch (const input_error& e) {
        throw input_error(path + ": " + e.what());
    }
}

/// The scene with the camera turned about the world's y axis by `degrees` (positive: to the
/// left, seen from above).
inline ScatterScene yawed(ScatterScene scene, double degrees) {
    const double a = degrees * 3.14159265358979323846 / 180.0, c = std::cos(a), s = std::sin(a);
    const auto turn = [&](const Vector3& v) { return Vector3{c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2]}; };
    scene.camera.forward = turn(scene.camera.forward);
    scene.camera.up = turn(scene.camera.up);
    return scene;
}

} // namespace msmcl::scatter_data
