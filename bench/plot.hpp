// The bench's PNG: cost (median ms, log scale) against map size, one line per case.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace msmcl::bench {

/// One panel per (format, sample count) found in `rows` (formats down, sample counts
/// across); x = map size (log scale), y = ms_median (log scale); build rows are left out.
void write_cost_plot(const std::string& path, const std::vector<nlohmann::json>& rows);

} // namespace msmcl::bench
