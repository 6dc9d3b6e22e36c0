// Shared by the fuzz targets: the readers take file names, so an input is written to one
// temporary file per process (in /dev/shm when there is one) and read back from there.
// Refusals (msmcl::error, input_error) are the expected outcome of bad input; any other
// exception escapes and libFuzzer reports it as a crash, like a sanitizer finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

namespace msmcl::fuzz {

/// The temporary file's name; removed when the process exits.
inline std::string& input_path() {
    static std::string path;
    return path;
}

/// The process's input file, holding exactly `size` bytes of `data`.
inline const std::string& input_file(const std::uint8_t* data, std::size_t size) {
    std::string& path = input_path();
    if (path.empty()) {
        std::string pattern = std::string(::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp") + "/msmcl-fuzz-XXXXXX";
        const int descriptor = ::mkstemp(pattern.data());
        if (descriptor < 0) std::abort();
        ::close(descriptor);
        path = pattern;
        std::atexit([] { ::unlink(input_path().c_str()); });
    }
    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (!file || (size && std::fwrite(data, 1, size, file) != size) || std::fclose(file) != 0) std::abort();
    return path;
}

} // namespace msmcl::fuzz
