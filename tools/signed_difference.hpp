// Signed-difference images: how an approximation departs from its ground truth, drawn with
// one diverging colour map for every quality figure of msmcl (soft shadows against PCSS,
// scattering against ray marching).
//
// Convention: the difference is taken in *light*, d = light(approximation) - light(truth),
// so the colours mean the same whatever the images store:
//   red   d > 0  the approximation is lighter than the truth (light leaks);
//   white d = 0;
//   blue  d < 0  the approximation is darker than the truth.
// For a shadow intensity (1 = fully shadowed) light = 1 - intensity; for a lit fraction or
// an in-scattered radiance light = the value itself (`Quantity`).
//
// Colour map: ColorBrewer's diverging RdBu scheme (C. Brewer, colorbrewer2.org, 9 classes),
// its centre #f7f7f7 replaced by pure white so that d = 0 is exactly white, interpolated
// linearly in sRGB between the 9 anchors. |d| >= range saturates at the end colours
// (#2166ac blue, #b2182b red). NaN on either side is drawn mid gray (#808080).
//
// Legend: below the image, a gray gap of 4 rows, then a colour bar of 16 rows that spans the
// image's width from d = -range (left) to +range (right), with black ticks 4 rows deep at
// -range, -range/2, 0, +range/2, +range, then a row of labels (tools/label_text.hpp): the
// values at the ends and at 0, and what each end means ("-0.5 darker", "0", "lighter +0.5";
// the words are dropped where the image is too narrow for them).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace msmcl::tools {

/// What the compared images store: darker means a larger value (`shadow_intensity`) or a
/// smaller one (`light`).
enum class Quantity { shadow_intensity, light };

/// Statistics of d = light(approximation) - light(truth) over the compared pixels.
struct DifferenceStats {
    std::size_t pixels = 0;          ///< pixels compared (both values finite)
    double mean_abs = 0.0;           ///< mean |d|
    double p99_abs = 0.0;            ///< 99th percentile of |d| (nearest rank)
    double max_abs = 0.0;            ///< largest |d|
    double share_lighter = 0.0;      ///< share of pixels with d > threshold
    double share_darker = 0.0;       ///< share of pixels with d < -threshold
};

/// sRGB colour (components in [0, 1]) of the signed difference `d`, saturating at |d| = range.
std::array<float, 3> signed_difference_colour(double d, double range);

/// d = light(approximation) - light(truth) per pixel (NaN where either is not finite).
std::vector<double> signed_difference(const std::vector<float>& approximation, const std::vector<float>& truth,
                                      Quantity quantity);

/// Mean, p99 and the shares beyond +-threshold of the finite differences.
DifferenceStats difference_stats(const std::vector<double>& difference, double threshold);

/// Rows the legend adds below a width x height image: gap, bar, labels with a margin.
constexpr int kLegendRows = 4 + 16 + 11;

/// What the ends of the colour bar mean.
struct BarWords {
    std::string negative = "darker"; ///< d = -range
    std::string positive = "lighter"; ///< d = +range
};

/// Writes the width x height difference image with the legend below it as an RGB PNG of
/// width x (height + kLegendRows) pixels (atomic, byte-deterministic). Throws
/// msmcl::input_error for a size mismatch or a range that is not finite and positive.
void write_signed_difference_png(const std::string& path, int width, int height,
                                 const std::vector<double>& difference, double range, const BarWords& words = {});

} // namespace msmcl::tools
