// Tuning overrides from the environment, read in one place: work-distribution sizes that
// were measured on one machine and that a user may re-tune for another. (Device quirks,
// which are not a matter of taste, are in quirks.hpp.)
#pragma once

#include <optional>

namespace msmcl::detail {

/// A tile of texels.
struct TileSize {
    int width = 0;
    int height = 0;
};

/// MSMCL_CPU_TILE="WxH": the tile of the CPU filter distribution (kernels/filter_fused_cpu.cl),
/// W in [min_width, 1024], H in [1, 1024]. std::nullopt when unset or not of that form (the
/// default tiling then applies).
std::optional<TileSize> cpu_filter_tile_override(int min_width);

/// MSMCL_FUSED_WORK_ITEMS=128, 64 or 32: the fused GPU filter starts with groups of that
/// many work-items instead of 256 (kernels/filter_fused_gpu.cl, FUSED_WORK_ITEMS), as a
/// device that allows fewer would run it. std::nullopt when unset or another value.
std::optional<int> fused_work_items_override();

} // namespace msmcl::detail
