// libFuzzer target: the depth map reader (opaque depth and translucent layers).
#include "fuzz_input.hpp"
#include "io/exr_io.hpp"

#include <msmcl/errors.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string& file = msmcl::fuzz::input_file(data, size);
    try {
        msmcl::io::read_translucent_depth_exr(file, msmcl::DepthRange::zero_one);
    } catch (const msmcl::error&) {
    }
    return 0;
}
