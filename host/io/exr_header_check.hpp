// What msmcl checks in an untrusted EXR file before OpenEXR reads it: the header's
// attributes against their size fields, then the first header's data window, claimed
// size and tiles against the limits and the file's own size (exr_header_check.cpp).
// Every refusal is an input_error "<file>: <problem>". Internal to msmcl_io.
#pragma once

#include <ImfIO.h>
#include <ImathBox.h>

#include <cstdint>
#include <string>

namespace msmcl::io::exr {

/// Walks the attributes of the header after the magic number and version, as OpenEXR will
/// read them, and refuses a header on which OpenEXR's reader and the size fields disagree:
/// - a size field larger than what is left of the file (OpenEXR allocates an attribute of
///   unknown type by its size before reading it: a 500-byte file could ask for 2 GB);
/// - a fixed-size type, channel list or preview whose size field differs from what its
///   value takes: OpenEXR reads those by their own layout, so it would lose step with the
///   size fields and take later bytes for sizes that this walk never saw.
/// Multi-part and deep files are refused: msmcl reads single-part scanline and tiled images.
void check_header_attributes(const std::string& path, const std::string& bytes);

/// Reads the first header from `stream` (at its start) and refuses one that is not an
/// OpenEXR header, whose data window is empty or absurd, whose claimed size breaks the
/// limits (image_limits.hpp) or cannot come from `file_bytes` bytes, or whose tiles do not
/// fit the data window or the file; returns its data window. The stream is left anywhere.
Imath::Box2i check_first_header(const std::string& path, Imf::IStream& stream, std::uint64_t file_bytes);

} // namespace msmcl::io::exr
