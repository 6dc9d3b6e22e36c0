// Synthetic shadow maps for the bench (generated on all hardware threads).
#include "scene.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

namespace msmcl::bench {

namespace {

struct Occluder {
    bool disk;
    double cx, cy, rx, ry, depth;
};

} // namespace

DepthImage make_scene(int size, int samples, std::uint32_t seed) {
    // Occluders in texel units of a unit square scaled to the map.
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Occluder> occluders;
    for (int i = 0; i < 40; ++i) {
        Occluder o;
        o.disk = random() % 2 == 0;
        o.cx = unit(random);
        o.cy = unit(random);
        o.rx = 0.01 + 0.12 * unit(random);
        o.ry = 0.01 + 0.12 * unit(random);
        o.depth = 0.05 + 0.5 * unit(random);
        occluders.push_back(o);
    }
    DepthImage image;
    image.width = size;
    image.height = size;
    image.samples = samples;
    image.depth.resize(static_cast<std::size_t>(size) * size * samples);
    const auto rows = [&](int y_begin, int y_end) {
        std::vector<const Occluder*> near_row;
        for (int y = y_begin; y < y_end; ++y) {
            // Only occluders that reach this row of texels.
            near_row.clear();
            for (const Occluder& o : occluders)
                if (std::fabs((y + 0.5) / size - o.cy) <= o.ry + 1.0 / size) near_row.push_back(&o);
            for (int x = 0; x < size; ++x)
                for (int s = 0; s < samples; ++s) {
                    // Sample positions spread over the texel, in map units.
                    const double px = (x + (samples == 1 ? 0.5 : std::fmod(0.25 + 0.618034 * s, 1.0))) / size;
                    const double py = (y + (samples == 1 ? 0.5 : std::fmod(0.5 + 0.381966 * s, 1.0))) / size;
                    double d = 0.7 + 0.15 * std::sin(9.0 * px) * std::cos(7.0 * py) + 0.1 * (px - 0.5);
                    for (const Occluder* o : near_row) {
                        const double u = (px - o->cx) / o->rx, v = (py - o->cy) / o->ry;
                        const bool inside = o->disk ? u * u + v * v <= 1.0 : std::fabs(u) <= 1.0 && std::fabs(v) <= 1.0;
                        if (inside) d = std::min(d, o->depth);
                    }
                    image.depth[(static_cast<std::size_t>(y) * size + x) * samples + s] = static_cast<float>(d);
                }
        }
    };
    const int threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    const int band = (size + threads - 1) / threads;
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) pool.emplace_back(rows, std::min(size, t * band), std::min(size, (t + 1) * band));
    for (std::thread& thread : pool) thread.join();
    return image;
}

std::vector<float> surface_receivers(const DepthImage& depth, std::size_t count, std::uint32_t seed) {
    std::vector<float> uvz(3 * count);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (std::size_t i = 0; i < count; ++i) {
        const float u = unit(rng) * depth.width, v = unit(rng) * depth.height;
        const int x = std::min(static_cast<int>(u), depth.width - 1), y = std::min(static_cast<int>(v), depth.height - 1);
        uvz[i] = u;
        uvz[count + i] = v;
        uvz[2 * count + i] = depth.at(x, y, 0);
    }
    return uvz;
}

} // namespace msmcl::bench
