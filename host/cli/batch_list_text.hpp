// The text of a --list file (docs/batch.md): a JSON manifest, or one input per line. Parsed
// apart from reading it, so that the parser alone can be fuzzed (fuzz/fuzz_batch_list.cpp).
#pragma once

#include "cli/batch.hpp"

#include <string>
#include <vector>

namespace msmcl::cli {

/// The entries of list `text`, read from `name` (named in messages): a JSON manifest when its
/// first non-blank character is '[' (an array of input paths, or of objects with "input",
/// optionally "output", "samples" and the keys `manifest_keys` of msmcl `command_name`),
/// else one input per line (blank lines and lines starting with '#' skipped). Throws
/// input_error naming the entry or line of a mistake, a NUL in a path included.
std::vector<BatchEntry> parse_batch_list(const std::string& name, const std::string& text,
                                         const std::vector<std::string>& manifest_keys,
                                         const std::string& command_name);

} // namespace msmcl::cli
