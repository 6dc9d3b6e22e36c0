#include "signed_difference.hpp"
#include "label_text.hpp"

#include "io/png_io.hpp"

#include <msmcl/errors.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace msmcl::tools {
namespace {

/// ColorBrewer RdBu (9 classes) from blue (d = -range) to red (d = +range); the centre is white.
constexpr std::array<std::array<int, 3>, 9> kAnchors{{
    {0x21, 0x66, 0xac}, {0x43, 0x93, 0xc3}, {0x92, 0xc5, 0xde}, {0xd1, 0xe5, 0xf0}, {0xff, 0xff, 0xff},
    {0xfd, 0xdb, 0xc7}, {0xf4, 0xa5, 0x82}, {0xd6, 0x60, 0x4d}, {0xb2, 0x18, 0x2b},
}};

} // namespace

std::array<float, 3> signed_difference_colour(double d, double range) {
    if (!std::isfinite(d)) return {0.5f, 0.5f, 0.5f};
    // Position along the anchors: 0 at -range, 8 at +range.
    const double t = (std::clamp(d / range, -1.0, 1.0) + 1.0) * 0.5 * (kAnchors.size() - 1);
    const std::size_t lower = std::min<std::size_t>(static_cast<std::size_t>(t), kAnchors.size() - 2);
    const double weight = t - static_cast<double>(lower);
    std::array<float, 3> colour{};
    for (int c = 0; c < 3; ++c)
        colour[c] = static_cast<float>(((1.0 - weight) * kAnchors[lower][c] + weight * kAnchors[lower + 1][c]) / 255.0);
    return colour;
}

std::vector<double> signed_difference(const std::vector<float>& approximation, const std::vector<float>& truth,
                                      Quantity quantity) {
    if (approximation.size() != truth.size())
        throw input_error("signed difference: the two images differ in size");
    std::vector<double> difference(truth.size());
    const double sign = quantity == Quantity::light ? 1.0 : -1.0;
    for (std::size_t i = 0; i < truth.size(); ++i) {
        const bool finite = std::isfinite(approximation[i]) && std::isfinite(truth[i]);
        difference[i] = finite ? sign * (double(approximation[i]) - double(truth[i])) : std::nan("");
    }
    return difference;
}

DifferenceStats difference_stats(const std::vector<double>& difference, double threshold) {
    DifferenceStats stats;
    std::vector<double> magnitudes;
    magnitudes.reserve(difference.size());
    std::size_t lighter = 0, darker = 0;
    double sum = 0.0;
    for (double d : difference) {
        if (!std::isfinite(d)) continue;
        magnitudes.push_back(std::abs(d));
        sum += std::abs(d);
        lighter += d > threshold;
        darker += d < -threshold;
    }
    stats.pixels = magnitudes.size();
    if (magnitudes.empty()) return stats;
    const double count = static_cast<double>(magnitudes.size());
    // Nearest-rank percentile: the smallest value with at least 99% of the pixels at or below it.
    const std::size_t rank = static_cast<std::size_t>(std::ceil(0.99 * count)) - 1;
    std::nth_element(magnitudes.begin(), magnitudes.begin() + rank, magnitudes.end());
    stats.p99_abs = magnitudes[rank];
    stats.max_abs = *std::max_element(magnitudes.begin(), magnitudes.end());
    stats.mean_abs = sum / count;
    stats.share_lighter = lighter / count;
    stats.share_darker = darker / count;
    return stats;
}

void write_signed_difference_png(const std::string& path, int width, int height,
                                 const std::vector<double>& difference, double range, const BarWords& words) {
    if (width <= 0 || height <= 0 || difference.size() != static_cast<std::size_t>(width) * height)
        throw input_error(path + ": difference image size does not match its data");
    if (!(range > 0.0) || !std::isfinite(range))
        throw input_error(path + ": the colour range must be finite and positive");
    const int rows = height + kLegendRows;
    std::vector<float> rgb(static_cast<std::size_t>(width) * rows * 3, 0.5f);
    auto put = [&](int x, int y, const std::array<float, 3>& colour) {
        for (int c = 0; c < 3; ++c) rgb[(static_cast<std::size_t>(y) * width + x) * 3 + c] = colour[c];
    };
    // The image itself.
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            put(x, y, signed_difference_colour(difference[static_cast<std::size_t>(y) * width + x], range));
    // The colour bar: column x shows d at its centre, from -range to +range.
    const int bar_top = height + 4;
    for (int x = 0; x < width; ++x) {
        const double d = width == 1 ? 0.0 : range * (2.0 * x / (width - 1) - 1.0);
        for (int y = bar_top; y < rows; ++y) put(x, y, signed_difference_colour(d, range));
    }
    // Ticks at -range, -range/2, 0, +range/2, +range, reaching down from the top of the bar.
    for (int tick = 0; tick <= 4; ++tick) {
        const int x = static_cast<int>(std::lround(tick * (width - 1) / 4.0));
        for (int y = bar_top; y < bar_top + 4; ++y) put(x, y, {0.0f, 0.0f, 0.0f});
    }
    // Labels under the bar: the values at its ends and at 0, with what the ends mean.
    char low[32], high[32];
    std::snprintf(low, sizeof low, "%.3g", -range);
    std::snprintf(high, sizeof high, "+%.3g", range);
    std::string left = std::string(low) + " " + words.negative, right = words.positive + " " + high;
    const int centre = text_width("0"), margin = 2 * kGlyphAdvance;
    if (text_width(left) + text_width(right) + centre + 2 * margin > width) left = low, right = high;
    const int label_top = bar_top + 16 + 2;
    draw_text(rgb, width, rows, 3, 0, label_top, left, {0.0f, 0.0f, 0.0f});
    draw_text(rgb, width, rows, 3, (width - centre) / 2, label_top, "0", {0.0f, 0.0f, 0.0f});
    draw_text(rgb, width, rows, 3, width - text_width(right), label_top, right, {0.0f, 0.0f, 0.0f});
    msmcl::io::write_png_preview(path, width, rows, 3, rgb, 0.0f, 1.0f);
}

} // namespace msmcl::tools
