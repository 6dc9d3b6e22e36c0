// libFuzzer target: the filtered texture reader (every format, attributes, code ranges)
// and the generic EXR reader behind the tools.
#include "fuzz_input.hpp"
#include "io/exr_io.hpp"

#include <msmcl/errors.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string& file = msmcl::fuzz::input_file(data, size);
    try {
        msmcl::io::read_texture_exr(file);
    } catch (const msmcl::error&) {
    }
    try {
        msmcl::io::read_exr(file);
    } catch (const msmcl::error&) {
    }
    return 0;
}
