// libFuzzer target: the scatter scene parser (nlohmann-json with a depth limit, then the
// scene's keys, types and ranges).
#include "io/scene_json.hpp"

#include <msmcl/errors.hpp>

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        msmcl::parse_scatter_scene(std::string(reinterpret_cast<const char*>(data), size));
    } catch (const msmcl::error&) {
    }
    return 0;
}
