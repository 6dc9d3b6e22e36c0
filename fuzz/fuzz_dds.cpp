// libFuzzer target: the DDS reader (header, DX10 header, texels).
#include "io/dds.hpp"

#include <msmcl/errors.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        msmcl::io::decode_dds(std::vector<std::uint8_t>(data, data + size), "input.dds");
    } catch (const msmcl::error&) {
    }
    return 0;
}
