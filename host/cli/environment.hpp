// The environment variables msmcl reads (the library, its file readers and the CLI): one
// table, shown by `msmcl --help` and so in the man page generated from it; docs/environment.md
// says the same for readers of the documentation.
#pragma once

#include <string>
#include <vector>

namespace msmcl::cli {

struct EnvironmentVariable {
    const char* name;
    const char* meaning;
};

/// Every MSMCL_* variable msmcl reads, in the order a user meets them.
const std::vector<EnvironmentVariable>& environment_variables();

/// The table as the --help footer prints it: an "Environment:" heading, then one entry per
/// variable, its meaning wrapped to `width` columns.
std::string environment_help(std::size_t width = 80);

} // namespace msmcl::cli
