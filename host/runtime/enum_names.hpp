// The names of the API's enums (formats, kernels, lookups): one table per enum, read both
// ways by the public *_name and parse_* functions.
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>
#include <utility>

namespace msmcl::detail {

template <class Enum>
using EnumNames = std::pair<Enum, const char*>;

/// The name of `value` in `table`; "unknown" for a value outside it.
template <class Enum, std::size_t N>
const char* name_in(const EnumNames<Enum> (&table)[N], Enum value) noexcept {
    for (const EnumNames<Enum>& entry : table)
        if (entry.first == value) return entry.second;
    return "unknown";
}

/// The value named `name` in `table`; std::nullopt for an unknown name.
template <class Enum, std::size_t N>
std::optional<Enum> parse_in(const EnumNames<Enum> (&table)[N], std::string_view name) noexcept {
    for (const EnumNames<Enum>& entry : table)
        if (name == entry.second) return entry.first;
    return std::nullopt;
}

} // namespace msmcl::detail
