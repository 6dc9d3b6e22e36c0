// PNG previews of float images (8 bits per channel, no gamma curve, no time stamp).
#pragma once

#include <string>
#include <vector>

namespace msmcl::io {

/// Writes a width x height image with `channels` = 1 (gray) or 3 (RGB, interleaved)
/// floats per pixel, row-major, top row first. Each value maps linearly from
/// [black, white] to [0, 255] (clamped, rounded to nearest; NaN becomes 0).
/// Atomic and byte-deterministic like every msmcl write.
void write_png_preview(const std::string& path, int width, int height, int channels,
                       const std::vector<float>& values, float black = 0.0f, float white = 1.0f);

} // namespace msmcl::io
