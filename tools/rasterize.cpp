// msmcl-rasterize: a PLY mesh (default: assimp's Wuson) standing on a ground plane,
// rasterized into a multisampled orthographic shadow map (standard D3D sample positions,
// top-left rule, per-sample depth by barycentric interpolation), plus the receivers of an
// orthographic view of the mesh and the ground.
#include "geometry.hpp"
#include "msaa_pattern.hpp"
#include "ply_mesh.hpp"
#include "triangle_rasterizer.hpp"

#include "io/exr_io.hpp"
#include "io/png_io.hpp"

#include <msmcl/errors.hpp>

#include <CLI/CLI.hpp>

#include <iostream>

namespace {

using msmcl::data::OrthographicLight;
using msmcl::data::ScreenPoint;
using msmcl::data::Vec3;
using namespace msmcl::data::vector_operators;

/// The mesh triangles followed by two ground triangles far larger than any map.
struct Scene {
    std::vector<Vec3> vertices;
    std::vector<std::array<int, 3>> triangles;
    std::size_t mesh_triangles = 0;
    std::vector<Vec3> mesh_vertices;
};

/// Stands the mesh on y = 0, centred on the origin.
Scene build_scene(const msmcl::data::TriangleMesh& mesh) {
    Vec3 low{1e300, 1e300, 1e300}, high{-1e300, -1e300, -1e300};
    for (const Vec3& v : mesh.vertices) {
        low = {std::min(low[0], v[0]), std::min(low[1], v[1]), std::min(low[2], v[2])};
        high = {std::max(high[0], v[0]), std::max(high[1], v[1]), std::max(high[2], v[2])};
    }
    const Vec3 offset{-0.5 * (low[0] + high[0]), -low[1], -0.5 * (low[2] + high[2])};
    Scene scene;
    for (const Vec3& v : mesh.vertices) scene.vertices.push_back(v + offset);
    scene.mesh_vertices = scene.vertices;
    scene.triangles = mesh.triangles;
    scene.mesh_triangles = scene.triangles.size();
    const double extent = 100.0 * std::max({high[0] - low[0], high[1] - low[1], high[2] - low[2]});
    const int base = static_cast<int>(scene.vertices.size());
    for (double x : {-extent, extent})
        for (double z : {-extent, extent}) scene.vertices.push_back({x, 0.0, z});
    scene.triangles.push_back({base, base + 1, base + 3});
    scene.triangles.push_back({base, base + 3, base + 2});
    return scene;
}

/// Where a world point lands in a view (u, v in pixels) and its depth in [0,1].
ScreenPoint to_screen(const OrthographicLight& view, Vec3 p) { return {view.texel_u(p), view.texel_v(p)}; }

double albedo(bool is_mesh, Vec3 p) {
    if (is_mesh) return 0.75;
    const bool odd = (static_cast<long>(std::floor(p[0] * 2)) + static_cast<long>(std::floor(p[2] * 2))) & 1;
    return odd ? 0.50 : 0.58;
}

struct Options {
    std::string model = "/usr/share/assimp/models/PLY/Wuson.ply";
    int width = 256, height = 0, samples = 4;
    int view_width = 320, view_height = 240;
    bool half = false;
    std::string depth_path, receivers_path, lighting_path, hard_preview_path, depth_preview_path;
};

int run(const Options& options) {
    const int height = options.height > 0 ? options.height : options.width;
    const Scene scene = build_scene(msmcl::data::read_ply(options.model));

    // Shadow footprint on the ground: where light rays through the mesh land.
    const Vec3 light_direction = msmcl::data::normalize({0.45, -0.7, -0.35});
    std::vector<Vec3> footprint = scene.mesh_vertices;
    for (const Vec3& v : scene.mesh_vertices) footprint.push_back(v + (-v[1] / light_direction[1]) * light_direction);

    // The view (orthographic, from the front right, above) frames mesh and shadow; the
    // light's map covers the mesh and all the ground the view sees.
    const OrthographicLight view =
        msmcl::data::fit_light({-0.55, -0.55, -0.63}, footprint, options.view_width, options.view_height, 0.15);
    std::vector<Vec3> covered = scene.mesh_vertices;
    for (double u : {0.0, 1.0 * options.view_width})
        for (double v : {0.0, 1.0 * options.view_height}) {
            const Vec3 start = view.near_point(u, v);
            covered.push_back(start + (-start[1] / view.forward[1]) * view.forward);
        }
    const OrthographicLight light = msmcl::data::fit_light(light_direction, covered, options.width, height, 0.01);

    // Shadow map: nearest depth per sample.
    const std::vector<msmcl::data::SampleOffset> pattern = msmcl::data::standard_sample_pattern(options.samples);
    msmcl::DepthImage depth;
    depth.width = options.width;
    depth.height = height;
    depth.samples = options.samples;
    depth.depth.assign(static_cast<std::size_t>(options.width) * height * options.samples, 1.0f);
    std::vector<double> nearest(depth.depth.size(), std::numeric_limits<double>::infinity());
    for (const auto& triangle : scene.triangles) {
        const Vec3 p[3] = {scene.vertices[triangle[0]], scene.vertices[triangle[1]], scene.vertices[triangle[2]]};
        const double d[3] = {light.depth(p[0]), light.depth(p[1]), light.depth(p[2])};
        msmcl::data::rasterize_triangle(
            to_screen(light, p[0]), to_screen(light, p[1]), to_screen(light, p[2]), options.width, height, pattern,
            [&](int x, int y, int s, double w0, double w1, double w2) {
                const double sample_depth = w0 * d[0] + w1 * d[1] + w2 * d[2];
                const std::size_t index = (static_cast<std::size_t>(y) * options.width + x) * options.samples + s;
                if (sample_depth < nearest[index]) nearest[index] = sample_depth;
            });
    }
    for (std::size_t i = 0; i < nearest.size(); ++i)
        depth.depth[i] = static_cast<float>(std::clamp(nearest[i], 0.0, 1.0));
    msmcl::io::write_depth_exr(options.depth_path, depth,
                               options.half ? msmcl::io::SampleType::half : msmcl::io::SampleType::float32);
    if (!options.depth_preview_path.empty()) {
        std::vector<float> first_sample(static_cast<std::size_t>(options.width) * height);
        for (std::size_t t = 0; t < first_sample.size(); ++t) first_sample[t] = depth.depth[t * options.samples];
        msmcl::io::write_png_preview(options.depth_preview_path, options.width, height, 1, first_sample);
    }
    if (options.receivers_path.empty() && options.lighting_path.empty() && options.hard_preview_path.empty())
        return 0;

    // View: one sample at each pixel centre; keep the nearest triangle and its weights.
    const std::size_t pixels = static_cast<std::size_t>(options.view_width) * options.view_height;
    std::vector<double> view_depth(pixels, std::numeric_limits<double>::infinity());
    std::vector<Vec3> position(pixels);
    std::vector<std::size_t> triangle_of(pixels, 0);
    const std::vector<msmcl::data::SampleOffset> centre = msmcl::data::standard_sample_pattern(1);
    for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
        const auto& triangle = scene.triangles[t];
        const Vec3 p[3] = {scene.vertices[triangle[0]], scene.vertices[triangle[1]], scene.vertices[triangle[2]]};
        msmcl::data::rasterize_triangle(
            to_screen(view, p[0]), to_screen(view, p[1]), to_screen(view, p[2]), options.view_width,
            options.view_height, centre, [&](int x, int y, int, double w0, double w1, double w2) {
                const Vec3 point = w0 * p[0] + w1 * p[1] + w2 * p[2];
                const double d = view.depth(point);
                const std::size_t i = static_cast<std::size_t>(y) * options.view_width + x;
                if (d < view_depth[i]) {
                    view_depth[i] = d;
                    position[i] = point;
                    triangle_of[i] = t;
                }
            });
    }

    // Receivers in light space and the lighting terms of each pixel.
    msmcl::io::ReceiverGrid receivers;
    receivers.width = options.view_width;
    receivers.height = options.view_height;
    std::vector<float> ambient(pixels), direct(pixels), hard(pixels);
    const double ambient_share = 0.3;
    for (std::size_t i = 0; i < pixels; ++i) {
        const Vec3 p = position[i];
        const double u = light.texel_u(p), v = light.texel_v(p), d = light.depth(p);
        receivers.points.u.push_back(static_cast<float>(u));
        receivers.points.v.push_back(static_cast<float>(v));
        receivers.points.z.push_back(static_cast<float>(std::clamp(d, 0.0, 1.0)));

        // Flat normal facing the viewer; Lambert with the light.
        const auto& triangle = scene.triangles[triangle_of[i]];
        Vec3 normal = msmcl::data::normalize(msmcl::data::cross(scene.vertices[triangle[1]] - scene.vertices[triangle[0]],
                                                   scene.vertices[triangle[2]] - scene.vertices[triangle[0]]));
        if (msmcl::data::dot(normal, view.forward) > 0) normal = -1.0 * normal;
        const bool is_mesh = triangle_of[i] < scene.mesh_triangles;
        const double a = albedo(is_mesh, p);
        ambient[i] = static_cast<float>(a * ambient_share);
        direct[i] = static_cast<float>(a * (1 - ambient_share) * std::max(0.0, -msmcl::data::dot(normal, light.forward)));

        // Unfiltered reference: share of the nearest texel's samples that do not occlude.
        const int tx = std::clamp(static_cast<int>(std::floor(u)), 0, options.width - 1);
        const int ty = std::clamp(static_cast<int>(std::floor(v)), 0, height - 1);
        int lit = 0;
        for (int s = 0; s < options.samples; ++s) lit += depth.at(tx, ty, s) >= d - 2e-3 ? 1 : 0;
        hard[i] = ambient[i] + direct[i] * static_cast<float>(lit) / options.samples;
    }
    if (!options.receivers_path.empty()) msmcl::io::write_receivers_exr(options.receivers_path, receivers);
    if (!options.lighting_path.empty()) {
        msmcl::io::ExrImage lighting;
        lighting.width = options.view_width;
        lighting.height = options.view_height;
        lighting.channels = {{"ambient", msmcl::io::SampleType::float32, ambient, {}},
                             {"direct", msmcl::io::SampleType::float32, direct, {}}};
        msmcl::io::write_exr(options.lighting_path, lighting);
    }
    if (!options.hard_preview_path.empty())
        msmcl::io::write_png_preview(options.hard_preview_path, options.view_width, options.view_height, 1, hard);
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"msmcl-rasterize: a PLY mesh on a ground plane -> MSAA shadow map and view receivers",
                 "msmcl-rasterize"};
    Options options;
    app.add_option("--model", options.model, "PLY mesh (ascii or binary_little_endian), y up")->capture_default_str();
    app.add_option("--depth", options.depth_path, "depth EXR to write (Z or sample<N>.Z, range [0,1])")->required();
    app.add_option("--width", options.width, "shadow map width")->capture_default_str()->check(CLI::Range(8, 16384));
    app.add_option("--height", options.height, "shadow map height (default: width)")->check(CLI::Range(8, 16384));
    app.add_option("--samples", options.samples, "MSAA samples: 1, 2, 4, 8, 16")
        ->capture_default_str()
        ->check(CLI::IsMember({1, 2, 4, 8, 16}));
    app.add_flag("--half", options.half, "store depth as HALF instead of FLOAT");
    app.add_option("--receivers", options.receivers_path, "receivers EXR (U, V, Z) of the view");
    app.add_option("--view-width", options.view_width, "view width in pixels")->capture_default_str()->check(CLI::Range(1, 16384));
    app.add_option("--view-height", options.view_height, "view height in pixels")->capture_default_str()->check(CLI::Range(1, 16384));
    app.add_option("--lighting", options.lighting_path, "EXR with the view's ambient and direct terms (for msmcl-preview)");
    app.add_option("--hard-preview", options.hard_preview_path, "PNG of the view with unfiltered hard shadows");
    app.add_option("--depth-preview", options.depth_preview_path, "PNG of sample 0 of the depth map");
    CLI11_PARSE(app, argc, argv);
    try {
        return run(options);
    } catch (const std::exception& e) {
        std::cerr << "msmcl-rasterize: " << e.what() << std::endl;
        return dynamic_cast<const msmcl::input_error*>(&e) ? 2 : 1;
    }
}
