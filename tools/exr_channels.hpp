// The tools' access to an EXR channel they read as floats (previews, signed differences).
#pragma once

#include "io/exr_io.hpp"

#include <msmcl/errors.hpp>

#include <string>
#include <vector>

namespace msmcl::tools {

/// The values of HALF or FLOAT channel `name` of `image` (read from `path`); input_error
/// naming the file when the channel is missing or holds uint32 codes.
inline const std::vector<float>& float_channel(const msmcl::io::ExrImage& image, const std::string& path,
                                               const std::string& name) {
    const msmcl::io::ExrChannel* channel = image.find_channel(name);
    if (!channel || channel->type == msmcl::io::SampleType::uint32)
        throw msmcl::input_error(path + ": no HALF or FLOAT channel " + name);
    return channel->values;
}

} // namespace msmcl::tools
