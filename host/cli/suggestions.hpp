// "Did you mean" for the msmcl command line. CLI11 reports an unknown subcommand as a
// missing one and an unknown option as a missing required one; this looks at the words
// itself, names the unknown one and suggests the nearest known name (edit distance).
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace msmcl::cli {

/// Levenshtein distance (insertions, deletions, substitutions; each costs 1).
std::size_t edit_distance(const std::string& a, const std::string& b);

/// The known name nearest to `word`, if it is near enough to be a typo of it.
std::optional<std::string> nearest_name(const std::string& word, const std::vector<std::string>& names);

/// For `arguments` (argv without the program name) that hold an unknown subcommand or an
/// unknown option of the chosen subcommand: a message naming it, with a suggestion where
/// one is near. std::nullopt when every word is known.
std::optional<std::string> unknown_word_message(CLI::App& app, const std::vector<std::string>& arguments);

} // namespace msmcl::cli
