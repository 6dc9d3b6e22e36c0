#include "cli/option_values.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <optional>

namespace msmcl::cli {

float parse_finite_float(const std::string& option, const std::string& text) {
    char* end = nullptr;
    errno = 0;
    const float value = std::strtof(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(value))
        throw usage_error(option + " must be a finite number, got '" + text + "'");
    return value;
}

long long parse_integer(const std::string& option, const std::string& text, long long lowest, long long highest) {
    char* end = nullptr;
    errno = 0;
    const long long value = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || value < lowest || value > highest)
        throw usage_error(option + " must be an integer in [" + std::to_string(lowest) + ", " +
                          std::to_string(highest) + "], got '" + text + "'");
    return value;
}

DepthRange parse_depth_range_option(const std::string& text) {
    const std::optional<DepthRange> range = parse_depth_range(text);
    if (!range) throw usage_error("--depth-range must be 0,1 or -1,1, got '" + text + "'");
    return *range;
}

} // namespace msmcl::cli
