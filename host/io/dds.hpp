// DDS files with the DX10 extended header (the DirectDraw Surface layout of the Direct3D 10+
// documentation): one mip level of a 2D texture or 2D texture array of a DXGI format.
//
// Layout written (all little-endian):
//   0    magic "DDS " (0x20534444)
//   4    DDS_HEADER (124 bytes): dwSize 124, dwFlags CAPS|HEIGHT|WIDTH|PITCH|PIXELFORMAT|
//        MIPMAPCOUNT (0x2100F), dwHeight, dwWidth, dwPitchOrLinearSize = width * texel
//        bytes, dwDepth 0, dwMipMapCount 1, dwReserved1[11] 0,
//        ddspf (32 bytes): dwSize 32, dwFlags FOURCC (4), dwFourCC "DX10", bit count and
//        masks 0; dwCaps TEXTURE (0x1000), dwCaps2..4 and dwReserved2 0
//   128  DDS_HEADER_DXT10 (20 bytes): dxgiFormat, resourceDimension TEXTURE2D (3),
//        miscFlag 0, arraySize (layers), miscFlags2 = alpha mode (4 CUSTOM: the fourth
//        channel is data, not opacity; 0 for single-channel formats)
//   148  the texels, layer after layer, rows top to bottom
// DDS has no place for metadata: GpuImage::metadata is not written.
#pragma once

#include "io/gpu_image.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace msmcl::io {

/// The bytes of a DDS file holding `image`. Throws input_error for an inconsistent image.
std::vector<std::uint8_t> encode_dds(const GpuImage& image);
/// Parses a DDS file with a DX10 header, one mip level, a 2D texture or array of one of
/// the GpuFormats. Errors are input_error messages starting with `name`. A one-layer file
/// reads back as a plain 2D texture (DDS does not tell the two apart).
GpuImage decode_dds(const std::vector<std::uint8_t>& bytes, const std::string& name);

/// encode_dds written atomically (write_file_atomically).
void write_dds(const std::string& path, const GpuImage& image);
GpuImage read_dds(const std::string& path);

} // namespace msmcl::io
