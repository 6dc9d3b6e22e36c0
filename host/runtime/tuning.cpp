// Tuning overrides from the environment (tuning.hpp).
#include "runtime/tuning.hpp"

#include <cstdlib>
#include <sstream>
#include <string>

namespace msmcl::detail {

std::optional<TileSize> cpu_filter_tile_override(int min_width) {
    const char* text = std::getenv("MSMCL_CPU_TILE");
    if (!text) return std::nullopt;
    TileSize tile;
    char separator = 0;
    std::istringstream in(text);
    if (in >> tile.width >> separator >> tile.height && separator == 'x' && tile.width >= min_width &&
        tile.width <= 1024 && tile.height >= 1 && tile.height <= 1024)
        return tile;
    return std::nullopt;
}

std::optional<int> fused_work_items_override() {
    const char* text = std::getenv("MSMCL_FUSED_WORK_ITEMS");
    if (!text) return std::nullopt;
    const std::string value(text);
    if (value == "128" || value == "64" || value == "32") return std::stoi(value);
    return std::nullopt;
}

} // namespace msmcl::detail
