// libFuzzer target: the receivers reader (U, V, Z and optional pixels PX, PY).
#include "fuzz_input.hpp"
#include "io/exr_io.hpp"

#include <msmcl/errors.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string& file = msmcl::fuzz::input_file(data, size);
    try {
        msmcl::io::read_receivers_exr(file);
    } catch (const msmcl::error&) {
    }
    return 0;
}
