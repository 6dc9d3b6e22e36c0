// Limits on the images msmcl reads from files, so that a small hostile file cannot make it
// allocate gigabytes: a cap on texels and on decoded bytes, and a check that the size a
// header claims fits in what the file can hold.
#pragma once

#include <cstdint>
#include <string>

namespace msmcl::io {

struct ImageLimits {
    /// Most texels (width x height) of one image: 2^28 (16384 x 16384) unless
    /// MSMCL_MAX_TEXELS says otherwise.
    std::uint64_t max_texels = std::uint64_t(1) << 28;
    /// Most bytes a file may hold, and most bytes its channels may decode to in memory
    /// (4 bytes per value): 1 GiB unless MSMCL_MAX_BYTES says otherwise (an 8192^2 depth
    /// map of 4 FLOAT samples is exactly 1 GiB).
    std::uint64_t max_bytes = std::uint64_t(1) << 30;
};

/// The limits in force: the defaults above, or the positive whole numbers in
/// MSMCL_MAX_TEXELS and MSMCL_MAX_BYTES (read on every call; a malformed value is an
/// input_error naming the variable).
ImageLimits image_limits();

/// Refuses (input_error "<path>: ...") an image of `width` x `height` texels whose channels
/// take `stored_bytes_per_texel` in the file and `decoded_bytes_per_texel` in memory when
/// it exceeds the limits, or when its data could not fit in `file_bytes` bytes even at
/// `max_expansion`, the largest ratio of decoded to stored bytes its compression allows.
void check_image_size(const std::string& path, std::uint64_t width, std::uint64_t height,
                      std::uint64_t stored_bytes_per_texel, std::uint64_t decoded_bytes_per_texel,
                      std::uint64_t file_bytes, std::uint64_t max_expansion);

} // namespace msmcl::io
