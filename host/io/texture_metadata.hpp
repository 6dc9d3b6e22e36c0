// The msmcl record kept in a KTX2 file's key/value data (docs/formats.md), read and checked
// once for every reader: the msmcl CLI and msmcl-vulkan refuse the same bad values.
#pragma once

#include "io/exr_io.hpp"
#include "io/gpu_image.hpp"

#include <cstdint>
#include <optional>
#include <string>

namespace msmcl::io {

/// The value of key `key` as a whole number in [lowest, highest], if present; input_error
/// naming `path` and the key when it is something else.
std::optional<long long> metadata_integer(const GpuImage& image, const std::string& path, const char* key,
                                          long long lowest, long long highest);

/// The record of a filtered map (msmcl:sigma, msmcl:samples, msmcl:depthRange), each value
/// checked; defaults where a key is absent.
TextureInfo texture_info_of(const GpuImage& image, const std::string& path);

/// The record of the warp's exponents of a texture (key msmcl:exponents of KTX2 files,
/// attribute of EXR files): "c+,c-", each as short as reads back exactly (ESM: "c,0");
/// nothing for the formats without a warp. 0 in Texture::exponents records the default.
std::optional<std::string> exponents_record(const Texture& texture);
/// The exponents of a texture of `format` from its record, checked (effective_exponents);
/// no record: the format's defaults (what a DDS file, which keeps no record, is read with).
WarpExponents exponents_of_record(const std::optional<std::string>& record, Format format, const std::string& path);

/// The largest kernel N of a summed-area table: msmcl:maxKernelTexels, else `given` (what the
/// user said; required when the file records none, as DDS never does), checked against each
/// other and against msmcl:scale. `container` names the file's kind in messages.
std::uint32_t sat_max_kernel_of(const GpuImage& image, const std::string& path, std::optional<std::uint32_t> given,
                                const char* container);

} // namespace msmcl::io
