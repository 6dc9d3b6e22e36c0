#include "io/image_limits.hpp"

#include <msmcl/errors.hpp>

#include <cerrno>
#include <cstdlib>

namespace msmcl::io {
namespace {

/// The value of environment variable `name` as a positive whole number, else `fallback`.
std::uint64_t environment_limit(const char* name, std::uint64_t fallback) {
    const char* text = std::getenv(name);
    if (!text || !*text) return fallback;
    char* end = nullptr;
    errno = 0;
    const unsigned long long value = std::strtoull(text, &end, 10);
    if (*text < '0' || *text > '9' || *end != '\0' || errno == ERANGE || value == 0)
        throw input_error(std::string(name) + ": expected a positive whole number, got '" + text + "'");
    return value;
}

} // namespace

ImageLimits image_limits() {
    ImageLimits limits;
    limits.max_texels = environment_limit("MSMCL_MAX_TEXELS", limits.max_texels);
    limits.max_bytes = environment_limit("MSMCL_MAX_BYTES", limits.max_bytes);
    return limits;
}

void check_image_size(const std::string& path, std::uint64_t width, std::uint64_t height,
                      std::uint64_t stored_bytes_per_texel, std::uint64_t decoded_bytes_per_texel,
                      std::uint64_t file_bytes, std::uint64_t max_expansion) {
    const ImageLimits limits = image_limits();
    const std::string size = std::to_string(width) + " x " + std::to_string(height);
    // Division first: no product below can overflow 64 bits (stored <= decoded bytes).
    if (width == 0 || height == 0) throw input_error(path + ": empty image (" + size + ")");
    if (height > limits.max_texels / width)
        throw input_error(path + ": " + size + " texels exceed the limit of " + std::to_string(limits.max_texels) +
                          " (MSMCL_MAX_TEXELS)");
    const std::uint64_t texels = width * height;
    if (decoded_bytes_per_texel > limits.max_bytes / texels)
        throw input_error(path + ": " + size + " texels of " + std::to_string(decoded_bytes_per_texel) +
                          " bytes exceed the limit of " + std::to_string(limits.max_bytes) + " bytes (MSMCL_MAX_BYTES)");
    // The header's size must fit in the file: a claim the data cannot back is a damaged
    // or hostile file, refused before anything is allocated for it.
    if (stored_bytes_per_texel > decoded_bytes_per_texel)
        throw input_error(path + ": internal error: more bytes stored than decoded per texel");
    if (stored_bytes_per_texel > 0 && texels * stored_bytes_per_texel / max_expansion > file_bytes)
        throw input_error(path + ": the header claims " + size + " texels (" +
                          std::to_string(texels * stored_bytes_per_texel) + " bytes of data), more than the " +
                          std::to_string(file_bytes) + " bytes of the file can hold");
}

} // namespace msmcl::io
