// msmcl-scene: a procedural test scene in the spirit of Peters, HPG 2017, Figure 1: a slim
// railing casts a short-range shadow onto a banner hanging just behind it, and the banner
// casts onto the ground. Depth is exact (ray-box and ray-plane intersections in double)
// at every standard D3D MSAA sample position of an orthographic directional light.
// Also writes the receivers of a perspective view (each pixel's visible surface point in
// light space), the view's lighting terms and previews. With --smoke N, a plume of smoke in
// front of the banner as N translucent planes facing the light (Peters et al., i3D 2016, section 4): per sample
// and plane a depth and an opacity, channels layer<k>.Z, layer<k>.A (one sample) or
// layer<k>.sample<s>.Z, layer<k>.sample<s>.A, beside the unchanged opaque depth.
// With --materials, the material index of each view pixel (channel M: 0 sky, 1 ground,
// 2 banner, 3 railing), on the grid of the receivers.
#include "geometry.hpp"
#include "msaa_pattern.hpp"

#include "io/exr_io.hpp"
#include "io/png_io.hpp"

#include <msmcl/errors.hpp>

#include <CLI/CLI.hpp>

#include <cstdint>
#include <cstdio>
#include <iostream>
#include <string>

namespace {

using msmcl::data::Vec3;
using namespace msmcl::data::vector_operators;

enum class Material { sky, ground, banner, railing };
/// Legend of the --materials channel M (the enum's values).
constexpr const char* material_legend = "0 sky, 1 ground, 2 banner, 3 railing";

struct Box {
    Vec3 low{}, high{};
    Material material;
};

struct Hit {
    double t = std::numeric_limits<double>::infinity();
    Vec3 normal{};
    Material material = Material::sky;
};

/// A ground patch at y = 0, a banner (thin box) and a railing of posts, rails and balusters.
class RailingScene {
public:
    RailingScene() {
        // Banner: 2.2 x 1.0, hanging between y = 0.5 and 1.5, 6 mm thick, centred on z = 0.
        boxes_.push_back({{-1.1, 0.5, -0.006}, {1.1, 1.5, 0.006}, Material::banner});
        // Railing 14 cm in front of it: 5 posts, a top and a bottom rail, slim balusters.
        const double z = 0.14;
        for (int i = 0; i < 5; ++i) {
            const double x = -1.2 + 0.6 * i;
            boxes_.push_back({{x - 0.02, 0.0, z - 0.02}, {x + 0.02, 1.12, z + 0.02}, Material::railing});
        }
        boxes_.push_back({{-1.23, 1.08, z - 0.025}, {1.23, 1.13, z + 0.025}, Material::railing});
        boxes_.push_back({{-1.22, 0.30, z - 0.012}, {1.22, 0.33, z + 0.012}, Material::railing});
        for (int i = 0; i < 24; ++i) {
            const double x = -1.15 + 0.1 * i;
            boxes_.push_back({{x - 0.008, 0.33, z - 0.008}, {x + 0.008, 1.08, z + 0.008}, Material::railing});
        }
    }

    /// Points the light's map must cover: every box corner and a ground patch around them.
    std::vector<Vec3> extent() const {
        std::vector<Vec3> points;
        for (const Box& box : boxes_)
            for (int corner = 0; corner < 8; ++corner)
                points.push_back({corner & 1 ? box.high[0] : box.low[0], corner & 2 ? box.high[1] : box.low[1],
                                  corner & 4 ? box.high[2] : box.low[2]});
        for (double x : {ground_low_[0], ground_high_[0]})
            for (double z : {ground_low_[2], ground_high_[2]}) points.push_back({x, 0.0, z});
        return points;
    }

    /// The nearest surface along origin + t direction (t > 0).
    Hit intersect(Vec3 origin, Vec3 direction) const {
        Hit nearest;
        if (direction[1] < 0 && origin[1] > 0) {
            const double t = -origin[1] / direction[1];
            const Vec3 p = origin + t * direction;
            if (p[0] >= ground_low_[0] && p[0] <= ground_high_[0] && p[2] >= ground_low_[2] && p[2] <= ground_high_[2]) {
                nearest.t = t;
                nearest.normal = {0, 1, 0};
                nearest.material = Material::ground;
            }
        }
        for (const Box& box : boxes_) {
            // Slabs: the entry is the last of the three axis entries.
            double enter = -std::numeric_limits<double>::infinity(), leave = std::numeric_limits<double>::infinity();
            int enter_axis = 0;
            const double o[3] = {origin[0], origin[1], origin[2]}, d[3] = {direction[0], direction[1], direction[2]};
            const double lo[3] = {box.low[0], box.low[1], box.low[2]}, hi[3] = {box.high[0], box.high[1], box.high[2]};
            bool missed = false;
            for (int axis = 0; axis < 3 && !missed; ++axis) {
                if (d[axis] == 0.0) {
                    missed = o[axis] < lo[axis] || o[axis] > hi[axis];
                    continue;
                }
                double t0 = (lo[axis] - o[axis]) / d[axis], t1 = (hi[axis] - o[axis]) / d[axis];
                if (t0 > t1) std::swap(t0, t1);
                if (t0 > enter) {
                    enter = t0;
                    enter_axis = axis;
                }
                leave = std::min(leave, t1);
            }
            if (missed || enter > leave || enter <= 0.0 || enter >= nearest.t) continue;
            nearest.t = enter;
            nearest.material = box.material;
            const double sign = d[enter_axis] > 0 ? -1.0 : 1.0;
            nearest.normal = {enter_axis == 0 ? sign : 0.0, enter_axis == 1 ? sign : 0.0, enter_axis == 2 ? sign : 0.0};
        }
        return nearest;
    }

private:
    std::vector<Box> boxes_;
    // The ground is a finite patch (all of it inside the shadow map); beyond it is sky.
    Vec3 ground_low_{-1.7, 0.0, -2.4};
    Vec3 ground_high_{2.3, 0.0, 0.9};
};

/// A smoke plume rising from the ground in front of the banner, sliced by planes that face
/// the light (as a volume renderer slices it for opacity shadow maps): plane k stands for a
/// slab of the plume at light depth depth(k), with the opacity 1 - exp(-density * thickness)
/// of that slab along each light ray. The density is value-noise fBm inside a widening,
/// swaying column.
class SmokePlume {
public:
    explicit SmokePlume(int planes) : planes_(planes) {}

    /// Corners of the column's bounding box (the light's map must cover them).
    std::vector<Vec3> corners() const {
        std::vector<Vec3> points;
        const double reach = sway_ + radius_ + growth_;
        for (int corner = 0; corner < 8; ++corner)
            points.push_back({corner & 1 ? axis_x_ + reach : axis_x_ - reach, corner & 2 ? top_ : bottom_,
                              corner & 4 ? axis_z_ + reach : axis_z_ - reach});
        return points;
    }

    /// Spreads the planes over the column's depth range in the light's map.
    void place(const msmcl::data::OrthographicLight& light) {
        first_ = 1.0;
        last_ = 0.0;
        for (const Vec3& p : corners()) {
            first_ = std::min(first_, light.depth(p));
            last_ = std::max(last_, light.depth(p));
        }
        world_range_ = light.far - light.near;
    }

    int planes() const { return planes_; }
    /// Light depth in [0, 1] of plane k: the centres of equal slabs of the plume's range.
    double depth(int k) const { return first_ + (last_ - first_) * (k + 0.5) / planes_; }

    /// Opacity in [0, 1) of plane k's slab at point p (on the plane).
    double opacity(Vec3 p) const {
        // Column: axis sways with height, radius grows.
        const double axis_x = axis_x_ + sway_ * std::sin(3.0 * p[1]);
        const double radius = radius_ + growth_ * std::clamp((p[1] - bottom_) / (top_ - bottom_), 0.0, 1.0);
        const double r = std::hypot(p[0] - axis_x, p[2] - axis_z_) / radius;
        const double column = 1.0 - smoothstep(0.35, 1.0, r);
        const double fade = smoothstep(bottom_, bottom_ + 0.2, p[1]) * (1.0 - smoothstep(top_ - 0.25, top_, p[1]));
        if (column <= 0.0 || fade <= 0.0) return 0.0;
        // Turbulence: four octaves of value noise.
        double noise = 0.0, amplitude = 0.5, frequency = 6.0;
        for (int octave = 0; octave < 4; ++octave, amplitude *= 0.5, frequency *= 2.0)
            noise += amplitude * value_noise(frequency * p[0], frequency * p[1], frequency * p[2]);
        const double density = column * fade * std::max(0.0, 2.2 * noise - 0.35);
        // Slab thickness in world units along the light (the depth range spans far - near).
        return 1.0 - std::exp(-density * extinction_ * slab_world_thickness());
    }

private:
    double slab_world_thickness() const { return (last_ - first_) * world_range_ / planes_; }
    static double smoothstep(double edge0, double edge1, double x) {
        const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
        return t * t * (3.0 - 2.0 * t);
    }
    // Lattice values in [0, 1) from an integer hash (SplitMix64's finalizer).
    static double lattice(long x, long y, long z) {
        std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9e3779b97f4a7c15ull ^
                          static_cast<std::uint64_t>(y) * 0xc2b2ae3d27d4eb4full ^
                          static_cast<std::uint64_t>(z) * 0x165667b19e3779f9ull;
        h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
        h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
        h ^= h >> 31;
        return static_cast<double>(h >> 11) * 0x1.0p-53;
    }
    // Trilinear value noise with smoothstep weights, in [0, 1).
    static double value_noise(double x, double y, double z) {
        const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
        const long ix = static_cast<long>(fx), iy = static_cast<long>(fy), iz = static_cast<long>(fz);
        const double tx = smoothstep(0, 1, x - fx), ty = smoothstep(0, 1, y - fy), tz = smoothstep(0, 1, z - fz);
        double result = 0.0;
        for (int corner = 0; corner < 8; ++corner) {
            const int cx = corner & 1, cy = (corner >> 1) & 1, cz = corner >> 2;
            result += (cx ? tx : 1 - tx) * (cy ? ty : 1 - ty) * (cz ? tz : 1 - tz) * lattice(ix + cx, iy + cy, iz + cz);
        }
        return result;
    }

    int planes_;
    // The column: axis at (axis_x, axis_z) swaying by sway, radius growing from radius to
    // radius + growth between bottom and top.
    double axis_x_ = -0.1, axis_z_ = 0.6, sway_ = 0.1, radius_ = 0.15, growth_ = 0.3;
    double bottom_ = 0.05, top_ = 1.3;
    double first_ = 0, last_ = 1;
    double world_range_ = 1;
    double extinction_ = 9.0; // per world unit at density 1
};

double albedo(Material material, Vec3 p) {
    switch (material) {
    case Material::ground: {
        // A faint 0.5 m checkerboard makes the ground read as a floor.
        const bool odd = (static_cast<long>(std::floor(p[0] * 2)) + static_cast<long>(std::floor(p[2] * 2))) & 1;
        return odd ? 0.50 : 0.58;
    }
    case Material::banner: return 0.85;
    case Material::railing: return 0.30;
    case Material::sky: return 0.0;
    }
    return 0.0;
}

struct Options {
    int width = 256, height = 0, samples = 4, smoke_planes = 0;
    int view_width = 320, view_height = 240;
    bool half = false;
    // Light direction (towards the scene), the view's eye and target; other values give
    // maps and views no test uses.
    std::vector<double> light_direction{0.35, -0.55, -0.75}, eye{0.9, 1.9, 3.4}, target{0.3, 0.55, -0.6};
    std::string depth_path, receivers_path, lighting_path, hard_preview_path, depth_preview_path, materials_path;
};

int run(const Options& options) {
    const int height = options.height > 0 ? options.height : options.width;
    const RailingScene scene;
    // Light from the upper left front, shining down and back onto the banner and the ground.
    const Vec3 light_direction =
        msmcl::data::normalize({options.light_direction[0], options.light_direction[1], options.light_direction[2]});
    // With smoke, the map also covers the plume (nearer to the light than the opaque scene).
    SmokePlume smoke(options.smoke_planes);
    std::vector<Vec3> extent = scene.extent();
    if (smoke.planes() > 0) for (const Vec3& p : smoke.corners()) extent.push_back(p);
    const msmcl::data::OrthographicLight light =
        msmcl::data::fit_light(light_direction, extent, options.width, height);
    smoke.place(light);

    // Shadow map: one light ray per MSAA sample; depth of the nearest surface.
    const std::vector<msmcl::data::SampleOffset> pattern = msmcl::data::standard_sample_pattern(options.samples);
    msmcl::DepthImage depth;
    depth.width = options.width;
    depth.height = height;
    depth.samples = options.samples;
    depth.depth.resize(static_cast<std::size_t>(options.width) * height * options.samples);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < options.width; ++x)
            for (int s = 0; s < options.samples; ++s) {
                const double u = x + 0.5 + pattern[s].x16 / 16.0, v = y + 0.5 + pattern[s].y16 / 16.0;
                const Vec3 start = light.near_point(u, v);
                const Hit hit = scene.intersect(start, light.forward);
                // A ray that misses everything sees the far plane.
                const double d = hit.material == Material::sky ? 1.0 : light.depth(start + hit.t * light.forward);
                depth.depth[(static_cast<std::size_t>(y) * options.width + x) * options.samples + s] =
                    static_cast<float>(std::clamp(d, 0.0, 1.0));
            }
    // Smoke: each light ray crosses every plane once, at the plane's depth.
    msmcl::io::TranslucentDepth layered;
    layered.layers.resize(smoke.planes());
    for (int k = 0; k < smoke.planes(); ++k) {
        msmcl::TranslucentLayer& layer = layered.layers[k];
        layer.depth.assign(depth.depth.size(), static_cast<float>(std::clamp(smoke.depth(k), 0.0, 1.0)));
        layer.opacity.resize(depth.depth.size());
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < options.width; ++x)
                for (int s = 0; s < options.samples; ++s) {
                    const double u = x + 0.5 + pattern[s].x16 / 16.0, v = y + 0.5 + pattern[s].y16 / 16.0;
                    const Vec3 p = light.near_point(u, v) + (smoke.depth(k) * (light.far - light.near)) * light.forward;
                    layer.opacity[(static_cast<std::size_t>(y) * options.width + x) * options.samples + s] =
                        static_cast<float>(smoke.opacity(p));
                }
    }
    const msmcl::io::SampleType type = options.half ? msmcl::io::SampleType::half : msmcl::io::SampleType::float32;
    if (smoke.planes() == 0) {
        msmcl::io::write_depth_exr(options.depth_path, depth, type);
    } else {
        layered.depth = depth;
        msmcl::io::write_translucent_depth_exr(options.depth_path, layered, type);
    }
    if (!options.depth_preview_path.empty()) {
        std::vector<float> first_sample(static_cast<std::size_t>(options.width) * height);
        for (std::size_t t = 0; t < first_sample.size(); ++t) first_sample[t] = depth.depth[t * options.samples];
        msmcl::io::write_png_preview(options.depth_preview_path, options.width, height, 1, first_sample);
    }
    if (options.receivers_path.empty() && options.lighting_path.empty() && options.hard_preview_path.empty() &&
        options.materials_path.empty())
        return 0;

    // View: each pixel's visible point, in light space, plus its lighting terms.
    const msmcl::data::PerspectiveCamera camera({options.eye[0], options.eye[1], options.eye[2]},
                                                {options.target[0], options.target[1], options.target[2]}, 42.0,
                                                options.view_width, options.view_height);
    msmcl::io::ReceiverGrid receivers;
    receivers.width = options.view_width;
    receivers.height = options.view_height;
    const std::size_t pixels = static_cast<std::size_t>(options.view_width) * options.view_height;
    std::vector<float> ambient(pixels), direct(pixels), hard(pixels), material(pixels);
    const double ambient_share = 0.3;
    for (int py = 0; py < options.view_height; ++py)
        for (int px = 0; px < options.view_width; ++px) {
            const std::size_t i = static_cast<std::size_t>(py) * options.view_width + px;
            const Hit hit = scene.intersect(camera.position, camera.ray(px + 0.5, py + 0.5));
            material[i] = static_cast<float>(static_cast<int>(hit.material));
            if (hit.material == Material::sky) {
                // Sky: a lit receiver at the map's near plane, shown bright.
                receivers.points.u.push_back(0.5f);
                receivers.points.v.push_back(0.5f);
                receivers.points.z.push_back(0.0f);
                ambient[i] = 0.9f;
                direct[i] = 0.0f;
                hard[i] = 0.9f;
                continue;
            }
            const Vec3 p = camera.position + hit.t * camera.ray(px + 0.5, py + 0.5);
            const double u = light.texel_u(p), v = light.texel_v(p), d = light.depth(p);
            receivers.points.u.push_back(static_cast<float>(u));
            receivers.points.v.push_back(static_cast<float>(v));
            receivers.points.z.push_back(static_cast<float>(std::clamp(d, 0.0, 1.0)));
            const double a = albedo(hit.material, p);
            const double lambert = std::max(0.0, -msmcl::data::dot(hit.normal, light.forward));
            ambient[i] = static_cast<float>(a * ambient_share);
            direct[i] = static_cast<float>(a * (1 - ambient_share) * lambert);

            // Unfiltered reference: share of the nearest texel's samples that do not occlude,
            // times the smoke's transmittance in front of the receiver.
            const int tx = std::clamp(static_cast<int>(std::floor(u)), 0, options.width - 1);
            const int ty = std::clamp(static_cast<int>(std::floor(v)), 0, height - 1);
            double lit = 0;
            for (int s = 0; s < options.samples; ++s) {
                if (depth.at(tx, ty, s) < d - 2e-3) continue;
                double transmitted = 1.0;
                const std::size_t at = (static_cast<std::size_t>(ty) * options.width + tx) * options.samples + s;
                for (const msmcl::TranslucentLayer& layer : layered.layers)
                    if (layer.depth[at] < d - 2e-3) transmitted *= 1.0 - layer.opacity[at];
                lit += transmitted;
            }
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
    if (!options.materials_path.empty()) {
        msmcl::io::ExrImage materials;
        materials.width = options.view_width;
        materials.height = options.view_height;
        materials.channels = {{"M", msmcl::io::SampleType::float32, material, {}}};
        materials.attributes = {{"msmcl:materials", std::string(material_legend)}};
        msmcl::io::write_exr(options.materials_path, materials);
    }
    if (!options.hard_preview_path.empty())
        msmcl::io::write_png_preview(options.hard_preview_path, options.view_width, options.view_height, 1, hard);
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"msmcl-scene: railing + banner + ground test scene (exact MSAA depth, receivers of a view)",
                 "msmcl-scene"};
    Options options;
    app.add_option("--depth", options.depth_path, "depth EXR to write (Z or sample<N>.Z, range [0,1])")->required();
    app.add_option("--width", options.width, "shadow map width")->capture_default_str()->check(CLI::Range(8, 16384));
    app.add_option("--height", options.height, "shadow map height (default: width)")->check(CLI::Range(8, 16384));
    app.add_option("--samples", options.samples, "MSAA samples: 1, 2, 4, 8, 16")
        ->capture_default_str()
        ->check(CLI::IsMember({1, 2, 4, 8, 16}));
    app.add_flag("--half", options.half, "store depth as HALF instead of FLOAT");
    app.add_option("--smoke", options.smoke_planes,
                   "translucent smoke in front of the banner: N planes written as layer<k>.Z / layer<k>.A")
        ->capture_default_str()
        ->check(CLI::Range(0, 8));
    app.add_option("--receivers", options.receivers_path, "receivers EXR (U, V, Z) of the view");
    app.add_option("--view-width", options.view_width, "view width in pixels")->capture_default_str()->check(CLI::Range(1, 16384));
    app.add_option("--view-height", options.view_height, "view height in pixels")->capture_default_str()->check(CLI::Range(1, 16384));
    app.add_option("--lighting", options.lighting_path, "EXR with the view's ambient and direct terms (for msmcl-preview)");
    app.add_option("--materials", options.materials_path,
                   std::string("EXR with the material of each view pixel, channel M (") + material_legend + ")");
    app.add_option("--hard-preview", options.hard_preview_path, "PNG of the view with unfiltered hard shadows");
    app.add_option("--depth-preview", options.depth_preview_path, "PNG of sample 0 of the depth map");
    app.add_option("--light-direction", options.light_direction, "direction the light shines in: X,Y,Z (y up)")
        ->delimiter(',')
        ->expected(3)
        ->capture_default_str();
    app.add_option("--eye", options.eye, "the view's camera position: X,Y,Z")->delimiter(',')->expected(3)->capture_default_str();
    app.add_option("--target", options.target, "the point the view looks at: X,Y,Z")
        ->delimiter(',')
        ->expected(3)
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    try {
        return run(options);
    } catch (const std::exception& e) {
        std::cerr << "msmcl-scene: " << e.what() << std::endl;
        return dynamic_cast<const msmcl::input_error*>(&e) ? 2 : 1;
    }
}
