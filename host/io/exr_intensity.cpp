// Shading results in EXR files (exr_io.hpp): one FLOAT channel `Y`.
#include "io/exr_file.hpp"

namespace msmcl::io {
using namespace exr;

void write_intensity_exr(const std::string& path, int width, int height, const std::vector<float>& intensity) {
    if (width <= 0 || height <= 0 || intensity.size() != static_cast<std::size_t>(width) * height)
        fail(path, "intensity image size does not match its data");
    ExrImage image;
    image.width = width;
    image.height = height;
    image.channels = {{"Y", SampleType::float32, intensity, {}}};
    write_exr_atomically(path, image);
}

} // namespace msmcl::io
