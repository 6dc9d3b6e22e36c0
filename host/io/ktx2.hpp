// KTX 2.0 files (Khronos KTX 2.0 specification): one mip level of a 2D texture or 2D
// texture array, no supercompression, a basic data format descriptor for the format,
// key/value data (KTXorientation "rd", KTXwriter, and the image's metadata).
//
// Layout written (all little-endian):
//   0    identifier  AB 4B 54 58 20 32 30 BB 0D 0A 1A 0A ("«KTX 20»\r\n\x1A\n")
//   12   vkFormat, typeSize, pixelWidth, pixelHeight, pixelDepth = 0,
//        layerCount (0 = not an array), faceCount = 1, levelCount = 1,
//        supercompressionScheme = 0                                       (9 x uint32)
//   48   dfdByteOffset, dfdByteLength, kvdByteOffset, kvdByteLength      (4 x uint32)
//        sgdByteOffset = 0, sgdByteLength = 0                            (2 x uint64)
//   80   level 0: byteOffset, byteLength, uncompressedByteLength          (3 x uint64)
//   104  DFD: dfdTotalSize, then one basic descriptor block (KDF 1.3): 6 words of header
//        (vendor 0 / type 0, version 2 / size, model RGBSDA / primaries BT709 / transfer
//        linear / flags 0, block 1x1x1x1, bytesPlane0 = texel bytes) and 4 words per sample
//        (bit offset / bit length - 1 / channel id and qualifiers, position 0, lower, upper)
//        as libktx generates them for the Vulkan format
//        key/value pairs sorted by key: uint32 length, key NUL value NUL, padding to 4
//        padding to lcm(texel bytes, 4), then the texels (layer after layer)
#pragma once

#include "io/gpu_image.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace msmcl::io {

/// The bytes of a KTX2 file holding `image`. Throws input_error for an inconsistent image.
std::vector<std::uint8_t> encode_ktx2(const GpuImage& image);
/// Parses a KTX2 file written by encode_ktx2 (any valid file with one level of a 2D
/// texture or array of these formats, without supercompression). Errors are input_error
/// messages starting with `name`.
GpuImage decode_ktx2(const std::vector<std::uint8_t>& bytes, const std::string& name);

/// encode_ktx2 written atomically (write_file_atomically).
void write_ktx2(const std::string& path, const GpuImage& image);
GpuImage read_ktx2(const std::string& path);

/// The data format descriptor (dfdTotalSize first) of a format, as 32-bit words.
std::vector<std::uint32_t> ktx2_data_format_descriptor(GpuFormat format);

} // namespace msmcl::io
