// Whole-view soft-shadow references in double precision (docs/soft_shadows.md): brute-force
// PCSS made fast by a min/max quadtree of the depth samples (same result as pcss_shadow in
// sat_reference.hpp, summed in another order), and moment soft shadow mapping by exact
// 64-bit prefix sums (same result as moment_soft_shadow) whose stages can each be swapped
// for its exact counterpart, to take the method's error apart by cause.
#pragma once

#include "reference/sat_reference.hpp"

#include <cstdint>
#include <vector>

namespace msmcl::reference {

/// The depth samples of a map (internal depth) with a min/max quadtree over texels; counts
/// and sums of the samples in front of a depth over texel rectangles.
class PcssMap {
public:
    explicit PcssMap(const DepthMap& map);

    int width() const { return width_; }
    int height() const { return height_; }
    int samples() const { return samples_; }

    /// Samples in front of zf (z < zf) over texels [x0, x1] x [y0, y1] (inclusive, inside
    /// the map): their number and the sum of their depths.
    void in_front(int x0, int y0, int x1, int y1, double zf, double& count, double& depth_sum) const;

    /// Area-weighted share of the samples in front of zf over [left, right) x [top, bottom)
    /// (texel units, inside the map; texel i covers [i, i + 1)): percentage-closer filtering.
    double pcf(double left, double top, double right, double bottom, double zf) const;

    /// PCSS of one receiver: pcss_shadow() of sat_reference.hpp.
    SoftResult pcss(double u, double v, double zf, const SoftParams& params) const;

private:
    struct Level {
        int width = 0, height = 0;
        std::vector<double> min, max, sum, count;
    };
    void accumulate(int level, int nx, int ny, int x0, int y0, int x1, int y1, double zf, double& count,
                    double& depth_sum) const;
    double texel_in_front(int x, int y, double zf) const;

    int width_ = 0, height_ = 0, samples_ = 1;
    std::vector<double> depth_;   // internal depth per sample, texel-major
    std::vector<Level> levels_;   // level l: nodes of 2^l x 2^l texels
};

/// Stages of moment soft shadow mapping swapped for their exact counterparts.
struct SoftSwaps {
    bool unquantized_table = false; ///< table precision: moments of the double channels, no 32-bit rounding
    bool exact_blockers = false;    ///< three-depth reconstruction -> the samples' blocker share and mean depth
    bool plain_average = false;     ///< eps-weighted blocker average -> the plain one (eps = 0)
    bool no_umbra_early_out = false;///< umbra early-out -> always filter
    bool pcss_filter_size = false;  ///< filter side -> the one PCSS uses
    bool exact_filter = false;      ///< 4MSM lower bound of the filter region -> its exact PCF
};

/// Alternatives to the published method, evaluated in double (the candidates of
/// docs/soft_shadows.md). The defaults are the published method.
struct SoftVariant {
    /// Share of the receiver's own reconstructed point (weight w0 at zf) that the average
    /// blocker depth counts as blockers at zf: (eps zf + k w0 zf + sum w_i z_i) / (eps + k w0
    /// + sum w_i). 0: the published eps-weighted average.
    double receiver_weight = 0;
    /// The filter region split into parts x parts equal squares, each its own 4MSM lower
    /// bound, averaged by area. 1: one query, as published.
    int parts = 1;
};

/// The integer texels of a map with exact 64-bit prefix sums (no wrapping), and the double
/// channels before rounding with long double prefix sums.
class MomentTable {
public:
    MomentTable(const DepthMap& map, std::uint32_t max_kernel_texels);
    /// From integer texels quantized elsewhere (a device's table): then the "double
    /// channels" are the texels / scale.
    MomentTable(const SatTexels& texels, std::uint32_t scale);

    int width() const { return width_; }
    int height() const { return height_; }
    std::uint32_t scale() const { return scale_; }

    /// Mean moments (before the bias) over [left, right) x [top, bottom), area-weighted,
    /// from the quantized texels or from the double channels.
    Moments mean_moments(double left, double top, double right, double bottom, bool unquantized) const;

    /// moment_soft_shadow() of sat_reference.hpp with the given stages swapped (exact ones
    /// from `pcss_map`) and the given filter step.
    SoftResult soft_shadow(const PcssMap& pcss_map, double u, double v, double zf, const SoftParams& params,
                           const SoftSwaps& swaps = {}, const SoftVariant& variant = {}) const;

private:
    void build(const SatTexels& texels, const std::vector<double>& channels);
    std::array<long double, 4> box_sum(int x0, int y0, int x1, int y1, bool unquantized) const;

    int width_ = 0, height_ = 0;
    std::uint32_t scale_ = 0;
    std::vector<std::uint64_t> integer_prefix_;  // (width + 1) x (height + 1) x 4, zero row and column first
    std::vector<long double> channel_prefix_;    // likewise for the double channels
};

} // namespace msmcl::reference
