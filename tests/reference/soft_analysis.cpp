// Written from docs/soft_shadows.md and Peters et al., i3D 2016, section 3 without kernels/:
// a min/max quadtree for PCSS, exact 64-bit prefix sums for the moments.
#include "reference/soft_analysis.hpp"

#include <algorithm>
#include <cmath>

namespace msmcl::reference {

namespace {

// Overlap of texel i ([i, i+1)) with [low, high).
double overlap(int i, double low, double high) {
    return std::max(0.0, std::min(high, i + 1.0) - std::max(low, double(i)));
}

// The texel ranges of [low, high) with one coverage each: the first texel, the fully
// covered middle, the last texel (texel i covers [i, i + 1)).
struct AxisRange {
    int first, last;
    double weight;
};
std::vector<AxisRange> axis_ranges(double low, double high) {
    const int first = static_cast<int>(std::floor(low));
    const int last = std::max(static_cast<int>(std::ceil(high)) - 1, first);
    if (first == last) return {{first, first, high - low}};
    std::vector<AxisRange> ranges{{first, first, overlap(first, low, high)}};
    if (last - first > 1) ranges.push_back({first + 1, last - 1, 1.0});
    ranges.push_back({last, last, overlap(last, low, high)});
    return ranges;
}

} // namespace

// ---- PCSS on a min/max quadtree.

PcssMap::PcssMap(const DepthMap& map) : width_(map.width), height_(map.height), samples_(map.samples) {
    depth_.resize(map.depth.size());
    for (std::size_t i = 0; i < map.depth.size(); ++i) depth_[i] = internal_depth(map.depth[i], map.zero_one);
    // Level 0: one node per texel.
    Level texels;
    texels.width = width_;
    texels.height = height_;
    const std::size_t count = static_cast<std::size_t>(width_) * height_;
    texels.min.assign(count, 0);
    texels.max.assign(count, 0);
    texels.sum.assign(count, 0);
    texels.count.assign(count, samples_);
    for (std::size_t t = 0; t < count; ++t) {
        const double* z = &depth_[t * samples_];
        texels.min[t] = *std::min_element(z, z + samples_);
        texels.max[t] = *std::max_element(z, z + samples_);
        for (int s = 0; s < samples_; ++s) texels.sum[t] += z[s];
    }
    levels_.push_back(std::move(texels));
    // Coarser levels: each node merges its (up to) 2 x 2 children.
    while (levels_.back().width > 1 || levels_.back().height > 1) {
        const Level& fine = levels_.back();
        Level coarse;
        coarse.width = (fine.width + 1) / 2;
        coarse.height = (fine.height + 1) / 2;
        const std::size_t nodes = static_cast<std::size_t>(coarse.width) * coarse.height;
        coarse.min.assign(nodes, INFINITY);
        coarse.max.assign(nodes, -INFINITY);
        coarse.sum.assign(nodes, 0);
        coarse.count.assign(nodes, 0);
        for (int y = 0; y < fine.height; ++y)
            for (int x = 0; x < fine.width; ++x) {
                const std::size_t child = static_cast<std::size_t>(y) * fine.width + x;
                const std::size_t node = static_cast<std::size_t>(y / 2) * coarse.width + x / 2;
                coarse.min[node] = std::min(coarse.min[node], fine.min[child]);
                coarse.max[node] = std::max(coarse.max[node], fine.max[child]);
                coarse.sum[node] += fine.sum[child];
                coarse.count[node] += fine.count[child];
            }
        levels_.push_back(std::move(coarse));
    }
}

double PcssMap::texel_in_front(int x, int y, double zf) const {
    const std::size_t t = static_cast<std::size_t>(y) * width_ + x;
    const Level& texels = levels_[0];
    if (texels.min[t] >= zf) return 0;
    if (texels.max[t] < zf) return samples_;
    double in_front = 0;
    for (int s = 0; s < samples_; ++s) in_front += depth_[t * samples_ + s] < zf ? 1 : 0;
    return in_front;
}

void PcssMap::accumulate(int level, int nx, int ny, int x0, int y0, int x1, int y1, double zf, double& count,
                         double& depth_sum) const {
    const Level& l = levels_[level];
    if (nx >= l.width || ny >= l.height) return;
    // Texels of the node, clipped to the rectangle.
    const int size = 1 << level;
    const int left = nx * size, top = ny * size;
    const int right = std::min(left + size, width_) - 1, bottom = std::min(top + size, height_) - 1;
    if (right < x0 || left > x1 || bottom < y0 || top > y1) return;
    const std::size_t node = static_cast<std::size_t>(ny) * l.width + nx;
    if (l.min[node] >= zf) return;
    const bool inside = left >= x0 && right <= x1 && top >= y0 && bottom <= y1;
    if (inside && l.max[node] < zf) {
        count += l.count[node];
        depth_sum += l.sum[node];
        return;
    }
    if (level == 0) {
        const std::size_t t = node;
        for (int s = 0; s < samples_; ++s) {
            const double z = depth_[t * samples_ + s];
            if (z < zf) {
                count += 1;
                depth_sum += z;
            }
        }
        return;
    }
    for (int cy = 0; cy < 2; ++cy)
        for (int cx = 0; cx < 2; ++cx)
            accumulate(level - 1, 2 * nx + cx, 2 * ny + cy, x0, y0, x1, y1, zf, count, depth_sum);
}

void PcssMap::in_front(int x0, int y0, int x1, int y1, double zf, double& count, double& depth_sum) const {
    count = 0;
    depth_sum = 0;
    if (x1 < x0 || y1 < y0) return;
    // Start at the level whose nodes are at least as large as the rectangle (at most 2 x 2 of them).
    int level = 0;
    while (level + 1 < static_cast<int>(levels_.size()) && (1 << level) < std::max(x1 - x0 + 1, y1 - y0 + 1)) ++level;
    for (int ny = y0 >> level; ny <= y1 >> level; ++ny)
        for (int nx = x0 >> level; nx <= x1 >> level; ++nx) accumulate(level, nx, ny, x0, y0, x1, y1, zf, count, depth_sum);
}

double PcssMap::pcf(double left, double top, double right, double bottom, double zf) const {
    // Texels covered fully: the quadtree; the partly covered rim: texel by texel.
    const int ix0 = static_cast<int>(std::ceil(left)), ix1 = static_cast<int>(std::floor(right)) - 1;
    const int iy0 = static_cast<int>(std::ceil(top)), iy1 = static_cast<int>(std::floor(bottom)) - 1;
    double inner = 0, unused = 0;
    in_front(ix0, iy0, ix1, iy1, zf, inner, unused);
    double shadow = inner / samples_;
    const int x0 = static_cast<int>(std::floor(left)), x1 = static_cast<int>(std::ceil(right)) - 1;
    const int y0 = static_cast<int>(std::floor(top)), y1 = static_cast<int>(std::ceil(bottom)) - 1;
    for (int y = y0; y <= y1; ++y) {
        const bool inner_row = y >= iy0 && y <= iy1;
        const double wy = overlap(y, top, bottom);
        for (int x = x0; x <= x1; ++x) {
            if (inner_row && x >= ix0 && x <= ix1) continue;
            shadow += wy * overlap(x, left, right) * texel_in_front(x, y, zf) / samples_;
        }
    }
    return shadow / ((right - left) * (bottom - top));
}

SoftResult PcssMap::pcss(double u, double v, double zf, const SoftParams& p) const {
    SoftResult result;
    u = std::clamp(u, 0.0, double(width_));
    v = std::clamp(v, 0.0, double(height_));
    // Blocker search over every sample of the search square.
    const TexelSquare s = search_square(width_, height_, u, v, p.search_size);
    double blockers = 0, depth_sum = 0;
    in_front(s.x0, s.y0, s.x1, s.y1, zf, blockers, depth_sum);
    result.blocker_shadow = blockers / (double(s.x1 - s.x0 + 1) * (s.y1 - s.y0 + 1) * samples_);
    if (blockers == 0) {
        result.blocker_depth = zf;
        return result; // fully lit
    }
    result.blocker_depth = depth_sum / blockers;
    // Percentage-closer filtering over the filter square, clipped to the map.
    result.filter_size = filter_side(p, zf, result.blocker_depth);
    const double half = 0.5 * result.filter_size;
    result.shadow = pcf(std::max(u - half, 0.0), std::max(v - half, 0.0), std::min(u + half, double(width_)),
                        std::min(v + half, double(height_)), zf);
    return result;
}

// ---- Moment soft shadows with swappable stages.

MomentTable::MomentTable(const DepthMap& map, std::uint32_t max_kernel_texels)
    : width_(map.width), height_(map.height), scale_(sat_scale(max_kernel_texels)) {
    build(quantize_depth_map(map, scale_), affine_channels(map));
}

MomentTable::MomentTable(const SatTexels& texels, std::uint32_t scale)
    : width_(texels.width), height_(texels.height), scale_(scale) {
    std::vector<double> channels;
    for (std::uint32_t value : texels.values) channels.push_back(double(value) / scale);
    build(texels, channels);
}

void MomentTable::build(const SatTexels& texels, const std::vector<double>& channels) {
    const std::size_t row = 4 * (static_cast<std::size_t>(width_) + 1);
    integer_prefix_.assign(row * (height_ + 1), 0);
    channel_prefix_.assign(row * (height_ + 1), 0);
    // P(x + 1, y + 1) = sum over texels i <= x, j <= y.
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x)
            for (int c = 0; c < 4; ++c) {
                const std::size_t at = row * (y + 1) + 4 * (x + 1) + c;
                const std::size_t texel = 4 * (static_cast<std::size_t>(y) * width_ + x) + c;
                integer_prefix_[at] = texels.values[texel] + integer_prefix_[at - 4] + integer_prefix_[at - row] -
                                      integer_prefix_[at - row - 4];
                channel_prefix_[at] = channels[texel] + channel_prefix_[at - 4] + channel_prefix_[at - row] -
                                      channel_prefix_[at - row - 4];
            }
}

std::array<long double, 4> MomentTable::box_sum(int x0, int y0, int x1, int y1, bool unquantized) const {
    const std::size_t row = 4 * (static_cast<std::size_t>(width_) + 1);
    const std::size_t a = row * (y1 + 1) + 4 * (x1 + 1), b = row * y0 + 4 * x0, c = row * y0 + 4 * (x1 + 1),
                      d = row * (y1 + 1) + 4 * x0;
    std::array<long double, 4> sum{};
    for (int k = 0; k < 4; ++k) {
        if (unquantized)
            sum[k] = channel_prefix_[a + k] + channel_prefix_[b + k] - channel_prefix_[c + k] - channel_prefix_[d + k];
        else // exact integers first, then one conversion
            sum[k] = static_cast<long double>(integer_prefix_[a + k] + integer_prefix_[b + k] - integer_prefix_[c + k] -
                                              integer_prefix_[d + k]);
    }
    return sum;
}

Moments MomentTable::mean_moments(double left, double top, double right, double bottom, bool unquantized) const {
    std::array<long double, 4> sum{};
    for (const AxisRange& ry : axis_ranges(top, bottom))
        for (const AxisRange& rx : axis_ranges(left, right)) {
            const std::array<long double, 4> box = box_sum(rx.first, ry.first, rx.last, ry.last, unquantized);
            for (int c = 0; c < 4; ++c) sum[c] += static_cast<long double>(rx.weight * ry.weight) * box[c];
        }
    const long double area = static_cast<long double>(right - left) * (bottom - top);
    const long double unit = unquantized ? 1.0L : static_cast<long double>(scale_);
    std::array<double, 4> mean{};
    for (int c = 0; c < 4; ++c) mean[c] = static_cast<double>(sum[c] / (area * unit));
    return msm64_affine_inverse(mean);
}

SoftResult MomentTable::soft_shadow(const PcssMap& pcss_map, double u, double v, double zf, const SoftParams& p,
                                    const SoftSwaps& swaps, const SoftVariant& variant) const {
    SoftResult result;
    u = std::clamp(u, 0.0, double(width_));
    v = std::clamp(v, 0.0, double(height_));
    // Blocker search: three depths from the search square's moments, or the samples themselves.
    const TexelSquare s = search_square(width_, height_, u, v, p.search_size);
    double share = 0, weighted = 0, receiver = 0;
    if (swaps.exact_blockers) {
        double count = 0, depth_sum = 0;
        pcss_map.in_front(s.x0, s.y0, s.x1, s.y1, zf, count, depth_sum);
        const double total = double(s.x1 - s.x0 + 1) * (s.y1 - s.y0 + 1) * pcss_map.samples();
        share = count / total;
        weighted = depth_sum / total;
    } else {
        const Moments search =
            bias(mean_moments(s.x0, s.y0, s.x1 + 1, s.y1 + 1, swaps.unquantized_table), p.alpha, bstar_float);
        const ThreePoints points = three_point_reconstruction(search, zf);
        for (int i = 0; i < 3; ++i) {
            const bool is_receiver = points.count > 1 && i == 0;
            if (!is_receiver && points.depth[i] < zf) {
                share += points.weight[i];
                weighted += points.weight[i] * points.depth[i];
            }
        }
        receiver = points.count > 1 ? variant.receiver_weight * std::clamp(points.weight[0], 0.0, 1.0) : 0.0;
    }
    result.blocker_shadow = share;
    if (swaps.plain_average)
        result.blocker_depth = share > 0 ? weighted / share : zf;
    else
        result.blocker_depth = ((p.blocker_eps + receiver) * zf + weighted) / (p.blocker_eps + receiver + share);
    // Umbra early-out.
    if (!swaps.no_umbra_early_out && share > 1 - p.umbra_eps) {
        result.shadow = 1;
        return result;
    }
    // Filter side: from this blocker depth, or the one PCSS finds.
    result.filter_size = swaps.pcss_filter_size ? pcss_map.pcss(u, v, zf, p).filter_size : 0.0;
    if (result.filter_size == 0.0) // PCSS found no blockers (lit): its filter would be the smallest
        result.filter_size = swaps.pcss_filter_size ? p.min_filter_size : filter_side(p, zf, result.blocker_depth);
    const double half = 0.5 * result.filter_size;
    const double left = std::max(u - half, 0.0), right = std::min(u + half, double(width_));
    const double top = std::max(v - half, 0.0), bottom = std::min(v + half, double(height_));
    if (swaps.exact_filter) {
        result.shadow = pcss_map.pcf(left, top, right, bottom, zf);
        return result;
    }
    // The filter region as one query or split into n x n equal parts, each its own 4MSM bound,
    // weighted by area.
    const int parts = std::max(variant.parts, 1);
    double shadow = 0, area = 0;
    for (int j = 0; j < parts; ++j)
        for (int i = 0; i < parts; ++i) {
            // Part edges; the outer ones are the filter square's own.
            const double l = i == 0 ? left : left + (right - left) * i / parts;
            const double r = i + 1 == parts ? right : left + (right - left) * (i + 1) / parts;
            const double t = j == 0 ? top : top + (bottom - top) * j / parts;
            const double b = j + 1 == parts ? bottom : top + (bottom - top) * (j + 1) / parts;
            const Moments filtered = bias(mean_moments(l, t, r, b, swaps.unquantized_table), p.alpha, bstar_float);
            shadow += (r - l) * (b - t) * std::clamp(hamburger4(filtered, zf).lower, 0.0, 1.0);
            area += (r - l) * (b - t);
        }
    result.shadow = shadow / area;
    return result;
}

} // namespace msmcl::reference
