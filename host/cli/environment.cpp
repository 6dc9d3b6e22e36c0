#include "cli/environment.hpp"

#include <sstream>

namespace msmcl::cli {

const std::vector<EnvironmentVariable>& environment_variables() {
    // Read in host/runtime/device_selection.cpp, context.cpp, tuning.cpp,
    // host/io/image_limits.cpp and host/cli/progress.cpp.
    static const std::vector<EnvironmentVariable> variables = {
        {"MSMCL_DEVICE", "the device when --device is not given: gpu, cpu, an index, P:D (platform:device) or a "
                         "name substring; one that matches nothing falls back to the default (the first GPU, else "
                         "the first CPU) unless MSMCL_STRICT is set"},
        {"MSMCL_PLATFORM", "only devices of this platform: its index or a substring of its name"},
        {"MSMCL_STRICT", "1: an MSMCL_DEVICE or MSMCL_PLATFORM that matches no device is an error (exit 1) instead "
                         "of a fallback to the default device"},
        {"MSMCL_CACHE_DIR", "folder of compiled OpenCL programs, reused by later runs on the same driver; created "
                            "when missing (unset: programs are built in every run)"},
        {"MSMCL_MAX_TEXELS", "most texels of one image read from a file (default 268435456, 16384 x 16384); a "
                             "larger one is refused (exit 2)"},
        {"MSMCL_MAX_BYTES", "most bytes of a file read and of its decoded channels (default 1073741824, 1 GiB)"},
        {"MSMCL_CPU_TILE", "WxH: the tile of the CPU filter kernel (default 128x64; W and H at most 1024); a value "
                           "of another form is ignored"},
        {"MSMCL_FUSED_WORK_ITEMS", "128, 64 or 32: start the fused GPU filter kernel with groups of that many "
                                   "work-items instead of 256 (the same texels; other values are ignored)"},
        {"MSMCL_PROGRESS_AFTER_MS", "milliseconds of work before the progress line appears on a terminal (default "
                                    "500; 0: at once)"},
    };
    return variables;
}

std::string environment_help(std::size_t width) {
    // Name in the first columns, meaning wrapped beside it, as CLI11 lays out options.
    const std::size_t indent = 30;
    std::ostringstream out;
    out << "Environment:\n";
    for (const EnvironmentVariable& variable : environment_variables()) {
        std::string line = "  " + std::string(variable.name);
        if (line.size() + 1 > indent) {
            out << line << '\n';
            line.clear();
        }
        line.resize(indent, ' ');
        std::istringstream words(variable.meaning);
        std::string word;
        bool first = true;
        while (words >> word) {
            if (!first && line.size() + 1 + word.size() > width) {
                out << line << '\n';
                line = std::string(indent, ' ');
                first = true;
            }
            line += (first ? "" : " ") + word;
            first = false;
        }
        out << line << '\n';
    }
    return out.str();
}

} // namespace msmcl::cli
