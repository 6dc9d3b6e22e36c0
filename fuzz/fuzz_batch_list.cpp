// libFuzzer target: the --list parser of msmcl filter and sat (host/cli/batch_list_text.cpp):
// JSON manifests and text lists. Besides not crashing, no entry it accepts may hold a NUL
// in a path or lack an input.
#include "cli/batch_list_text.hpp"

#include <msmcl/errors.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const auto entries = msmcl::cli::parse_batch_list(
            "list", text, {"format", "sigma", "depth-range", "kernel", "out-container"}, "filter");
        for (const msmcl::cli::BatchEntry& entry : entries)
            if (entry.input.empty() || entry.input.find('\0') != std::string::npos ||
                entry.output.find('\0') != std::string::npos)
                std::abort();
    } catch (const msmcl::error&) {
    }
    return 0;
}
