// The blue-noise textures of the dithered lookup (include/msmcl/device_math.hpp): the table
// cmake/blue_noise.cmake generates at build time (blue_noise_table.inc in the build's
// generated/ folder), compiled in. A build configured without that step generates the same
// bytes from the same seed on first use instead (void-and-cluster, a few seconds).
#include <msmcl/device_math.hpp>

#if __has_include("blue_noise_table.inc")
#include "blue_noise_table.inc"
#define MSMCL_BLUE_NOISE_GENERATED 1
#else
#include "bluenoise/void_and_cluster.hpp"
#define MSMCL_BLUE_NOISE_GENERATED 0
#endif

namespace msmcl {

namespace {
// 64 textures x 64 x 64 texels x 2 channels.
constexpr std::size_t kBlueNoiseBytes = 64 * 64 * 64 * 2;
} // namespace

const std::uint8_t* blue_noise_textures() noexcept {
#if MSMCL_BLUE_NOISE_GENERATED
    static_assert(sizeof(generated_blue_noise_table) == kBlueNoiseBytes, "blue-noise table size");
    return generated_blue_noise_table;
#else
    static const std::vector<std::uint8_t> table = bluenoise::generate_table(bluenoise::library_seed);
    return table.data();
#endif
}

std::size_t blue_noise_bytes() noexcept { return kBlueNoiseBytes; }

} // namespace msmcl
