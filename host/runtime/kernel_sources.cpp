// Looks up embedded kernel files and resolves their #include lines.
#include "runtime/kernel_sources.hpp"
#include "runtime/program_cache.hpp"

#include <msmcl/errors.hpp>

#include <cstddef>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

namespace msmcl::detail {

struct EmbeddedFile {
    const char* name;
    const unsigned char* data;
    std::size_t size;
};
// Defined in the generated embedded_kernels.cpp (cmake/embed_kernels.cmake).
const EmbeddedFile* embedded_kernel_files(std::size_t* count);

std::string_view embedded_kernel_file(std::string_view name) {
    std::size_t count = 0;
    const EmbeddedFile* files = embedded_kernel_files(&count);
    for (std::size_t i = 0; i < count; ++i)
        if (name == files[i].name)
            return {reinterpret_cast<const char*>(files[i].data), files[i].size};
    throw error("msmcl: no embedded kernel file named '" + std::string(name) + "'");
}

std::vector<std::string> embedded_kernel_names() {
    std::size_t count = 0;
    const EmbeddedFile* files = embedded_kernel_files(&count);
    std::vector<std::string> names;
    for (std::size_t i = 0; i < count; ++i) names.emplace_back(files[i].name);
    return names;
}

namespace {

// Appends `name` to `out`, inlining quoted includes not yet seen.
void append_resolved(std::string_view name, std::set<std::string>& seen, std::string& out) {
    if (!seen.insert(std::string(name)).second) return;
    std::istringstream lines{std::string(embedded_kernel_file(name))};
    std::string line;
    while (std::getline(lines, line)) {
        const std::size_t start = line.find_first_not_of(" \t");
        if (start != std::string::npos && line.compare(start, 8, "#include") == 0) {
            const std::size_t open = line.find('"', start);
            const std::size_t close = open == std::string::npos ? open : line.find('"', open + 1);
            if (close != std::string::npos) {
                append_resolved(std::string_view(line).substr(open + 1, close - open - 1), seen, out);
                continue;
            }
        }
        out += line;
        out += '\n';
    }
}

} // namespace

std::string assemble_kernel_source(std::string_view name) {
    std::set<std::string> seen;
    std::string source;
    append_resolved(name, seen, source);
    return source;
}

const KernelSource& kernel_source(std::string_view name, const std::vector<std::string>& defines) {
    // Assembled sources of the process, by file and defines; entries are never removed.
    static std::mutex mutex;
    static std::map<std::pair<std::string, std::vector<std::string>>, KernelSource> assembled;
    std::pair<std::string, std::vector<std::string>> key{std::string(name), defines};
    const std::lock_guard<std::mutex> lock(mutex);
    auto found = assembled.find(key);
    if (found != assembled.end()) return found->second;
    // Each define becomes a `#define NAME VALUE` line in front of the embedded source.
    KernelSource source;
    for (const std::string& define : defines) {
        const std::size_t equals = define.find('=');
        source.text += "#define " +
                       (equals == std::string::npos ? define
                                                    : define.substr(0, equals) + ' ' + define.substr(equals + 1)) +
                       '\n';
    }
    source.text += "#line 1\n";
    source.text += assemble_kernel_source(name);
    source.hash = fnv1a64(source.text);
    return assembled.emplace(std::move(key), std::move(source)).first->second;
}

} // namespace msmcl::detail
