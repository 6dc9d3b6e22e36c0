// libFuzzer target: the KTX2 reader (header, data format descriptor, key/value data, level).
#include "io/ktx2.hpp"

#include <msmcl/errors.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        msmcl::io::decode_ktx2(std::vector<std::uint8_t>(data, data + size), "input.ktx2");
    } catch (const msmcl::error&) {
    }
    return 0;
}
