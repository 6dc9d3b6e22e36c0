// Option values CLI11 passes through as text, checked whole: every subcommand parses its
// numbers and depth ranges here, so the messages (usage_error, exit code 2) read alike.
#pragma once

#include "cli/commands.hpp"

#include <msmcl/formats.hpp>

#include <string>
#include <vector>

namespace msmcl::cli {

/// The whole of `text` as a finite float, else usage_error naming the option.
float parse_finite_float(const std::string& option, const std::string& text);

/// The whole of `text` as an integer in [lowest, highest], else usage_error naming the option.
long long parse_integer(const std::string& option, const std::string& text, long long lowest, long long highest);

/// A value of `option` that is none of `valid`, named with the nearest valid one where one
/// is near (as a mistyped option is, cli/suggestions.hpp): "unknown --lookup 'bilnear'
/// (did you mean 'bilinear'? expected nearest, bilinear or dither)".
std::string unknown_value_message(const std::string& option, const std::string& value,
                                  const std::vector<std::string>& valid);

/// --depth-range: "0,1" or "-1,1".
DepthRange parse_depth_range_option(const std::string& text);

/// The names of every format --format takes, in Format order.
std::vector<std::string> format_names();

/// --exponents C+[,C-] (EVSM) and --exponent C (ESM) of a filter of `format`, as the
/// library takes them (0: the default); usage_error for an option of another
/// representation or a malformed value, input_error naming the limit for one beyond it
/// (msmcl::effective_exponents). Empty texts: the defaults.
WarpExponents parse_exponent_options(Format format, const std::string& exponents, const std::string& exponent);

} // namespace msmcl::cli
