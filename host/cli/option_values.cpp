#include "cli/option_values.hpp"
#include "cli/suggestions.hpp"

#include "runtime/texture_kinds.hpp"

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

std::string unknown_value_message(const std::string& option, const std::string& value,
                                  const std::vector<std::string>& valid) {
    // "a, b, c or d", as the messages of every option read.
    std::string list;
    for (std::size_t i = 0; i < valid.size(); ++i)
        list += (i == 0 ? "" : i + 1 == valid.size() ? " or " : ", ") + valid[i];
    const std::optional<std::string> suggestion = nearest_name(value, valid);
    const std::string hint = suggestion ? "did you mean '" + *suggestion + "'? " : std::string();
    return "unknown " + option + " '" + value + "' (" + hint + "expected " + list + ")";
}

DepthRange parse_depth_range_option(const std::string& text) {
    const std::optional<DepthRange> range = parse_depth_range(text);
    if (!range) throw usage_error("--depth-range must be 0,1 or -1,1, got '" + text + "'");
    return *range;
}

std::vector<std::string> format_names() {
    std::vector<std::string> names;
    for (Format format : detail::filter_formats()) names.emplace_back(format_name(format));
    return names;
}

namespace {

// The formats of the representations in `representations`, for messages: "evsm2_32, evsm4_64, evsm4_128".
std::string formats_text(std::initializer_list<detail::Representation> representations) {
    std::string text;
    for (detail::Representation representation : representations)
        for (Format format : detail::formats_of(representation))
            text += (text.empty() ? "" : ", ") + std::string(format_name(format));
    return text;
}

} // namespace

WarpExponents parse_exponent_options(Format format, const std::string& exponents, const std::string& exponent) {
    const detail::Representation representation = detail::representation_of(format);
    const bool evsm =
        representation == detail::Representation::evsm2 || representation == detail::Representation::evsm4;
    WarpExponents requested;
    if (!exponents.empty()) {
        if (!evsm)
            throw usage_error("--exponents belongs to the EVSM formats (" +
                              formats_text({detail::Representation::evsm2, detail::Representation::evsm4}) +
                              "), not " + format_name(format));
        const std::size_t comma = exponents.find(',');
        requested.positive = parse_finite_float("--exponents", exponents.substr(0, comma));
        if (comma != std::string::npos)
            requested.negative = parse_finite_float("--exponents", exponents.substr(comma + 1));
    }
    if (!exponent.empty()) {
        if (representation != detail::Representation::esm)
            throw usage_error("--exponent belongs to the ESM format (" + formats_text({detail::Representation::esm}) +
                              "), not " + format_name(format));
        requested.positive = parse_finite_float("--exponent", exponent);
    }
    return effective_exponents(format, requested, "filter");
}

} // namespace msmcl::cli
