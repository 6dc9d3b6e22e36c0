// A multisample triangle rasterizer with exact coverage: vertices snap to 1/256 pixel,
// edge functions are evaluated in 64-bit integers, and samples exactly on an edge belong
// to the triangle only for top and left edges (Direct3D's top-left rule), so triangles
// sharing an edge cover each sample once. Barycentric weights of the snapped triangle
// let the caller interpolate depth (exact for orthographic projections) and attributes.
#pragma once

#include "msaa_pattern.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace msmcl::data {

/// A vertex in pixel coordinates: x right, y down, pixel (i, j) spans [i, i+1) x [j, j+1).
struct ScreenPoint {
    double x = 0, y = 0;
};

inline constexpr std::int64_t subpixel_steps = 256;

/// Calls visit(px, py, sample, w0, w1, w2) for every sample of `pattern` inside the
/// triangle (a, b, c), either winding, with w the barycentric weights of a, b, c.
template <class Visit>
void rasterize_triangle(ScreenPoint a, ScreenPoint b, ScreenPoint c, int width, int height,
                        const std::vector<SampleOffset>& pattern, Visit&& visit) {
    // Snap to the fixed-point grid; skip triangles too far out for exact 64-bit products.
    const double limit = 1 << 26;
    for (const ScreenPoint& p : {a, b, c})
        if (!(std::fabs(p.x) < limit && std::fabs(p.y) < limit)) return;
    std::int64_t x[3] = {std::llround(a.x * subpixel_steps), std::llround(b.x * subpixel_steps),
                         std::llround(c.x * subpixel_steps)};
    std::int64_t y[3] = {std::llround(a.y * subpixel_steps), std::llround(b.y * subpixel_steps),
                         std::llround(c.y * subpixel_steps)};
    int order[3] = {0, 1, 2};

    // Orient so that the interior has positive edge functions; flat triangles cover nothing.
    std::int64_t area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
    if (area == 0) return;
    if (area < 0) {
        std::swap(x[1], x[2]);
        std::swap(y[1], y[2]);
        std::swap(order[1], order[2]);
        area = -area;
    }

    // Edge k runs from vertex k+1 to k+2 (opposite vertex k); E_k(p) = dx (p.y - y0) - dy (p.x - x0).
    struct Edge {
        std::int64_t x0, y0, dx, dy;
        bool owns_zero; // top or left edge: samples exactly on it are inside
    };
    Edge edges[3];
    for (int k = 0; k < 3; ++k) {
        const int from = (k + 1) % 3, to = (k + 2) % 3;
        Edge& edge = edges[k];
        edge.x0 = x[from];
        edge.y0 = y[from];
        edge.dx = x[to] - x[from];
        edge.dy = y[to] - y[from];
        // The inward normal is (-dy, dx): left edge if it points right, top edge if it
        // points down along a horizontal edge.
        edge.owns_zero = -edge.dy > 0 || (edge.dy == 0 && edge.dx > 0);
    }

    // Pixels whose samples can fall inside (samples lie within half a pixel of the centre).
    const std::int64_t x_low = *std::min_element(x, x + 3), x_high = *std::max_element(x, x + 3);
    const std::int64_t y_low = *std::min_element(y, y + 3), y_high = *std::max_element(y, y + 3);
    const int px0 = static_cast<int>(std::max<std::int64_t>(0, x_low / subpixel_steps - 1));
    const int px1 = static_cast<int>(std::min<std::int64_t>(width - 1, x_high / subpixel_steps + 1));
    const int py0 = static_cast<int>(std::max<std::int64_t>(0, y_low / subpixel_steps - 1));
    const int py1 = static_cast<int>(std::min<std::int64_t>(height - 1, y_high / subpixel_steps + 1));

    const double inverse_area = 1.0 / static_cast<double>(area);
    for (int py = py0; py <= py1; ++py)
        for (int px = px0; px <= px1; ++px)
            for (std::size_t s = 0; s < pattern.size(); ++s) {
                // Sample position in fixed point: pixel centre + offset in 1/16 pixel.
                const std::int64_t sx = px * subpixel_steps + subpixel_steps / 2 + pattern[s].x16 * (subpixel_steps / 16);
                const std::int64_t sy = py * subpixel_steps + subpixel_steps / 2 + pattern[s].y16 * (subpixel_steps / 16);
                std::int64_t e[3];
                bool inside = true;
                for (int k = 0; k < 3 && inside; ++k) {
                    e[k] = edges[k].dx * (sy - edges[k].y0) - edges[k].dy * (sx - edges[k].x0);
                    inside = e[k] > 0 || (e[k] == 0 && edges[k].owns_zero);
                }
                if (!inside) continue;
                // Weights back in the caller's vertex order.
                double weights[3];
                for (int k = 0; k < 3; ++k) weights[order[k]] = static_cast<double>(e[k]) * inverse_area;
                visit(px, py, static_cast<int>(s), weights[0], weights[1], weights[2]);
            }
}

} // namespace msmcl::data
