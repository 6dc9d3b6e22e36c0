// OpenEXR files of summed-area tables (msmcl sat / msmcl soft): UINT channels R, G, B, A
// holding the table words, and the attributes a reader needs to query it.
// Errors are msmcl::input_error "<file>: <problem>"; writes are atomic (exr_io.hpp).
#pragma once

#include <msmcl/types.hpp>

#include <string>

namespace msmcl::io {

/// What a table file records besides its words.
struct SatInfo {
    DepthRange depth_range = DepthRange::zero_one; ///< convention of the depth map it was built from
    int samples = 1;                               ///< MSAA samples per texel of that map
};
struct SatFile {
    SatTable table;
    SatInfo info;
};

/// Channels R, G, B, A as UINT (the four table words of each texel); attributes
/// msmcl:format = "sat" (string), msmcl:maxKernel = N (int), msmcl:satScale =
/// floor((2^32 - 1) / N) (int), msmcl:samples (int), msmcl:depthRange (string).
void write_sat_exr(const std::string& path, const SatTable& table, const SatInfo& info);
/// Reads a file written by write_sat_exr bit-exactly, validating the format attribute,
/// N against the scale, the channel set and types and the other attributes.
SatFile read_sat_exr(const std::string& path);

} // namespace msmcl::io
