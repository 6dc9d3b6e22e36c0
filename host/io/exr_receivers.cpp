// Receiver grids in EXR files (exr_io.hpp): FLOAT (or HALF) `U`, `V`, `Z`, optionally the
// screen pixels `PX`, `PY`.
#include "io/exr_file.hpp"

#include <msmcl/errors.hpp>

#include <algorithm>
#include <cmath>

namespace msmcl::io {
using namespace exr;

ReceiverGrid read_receivers_exr(const std::string& path) {
    ExrReader reader(path);
    for (const char* name : {"U", "V", "Z"})
        require_float_channel(reader, name, "receivers need channels U, V, Z");

    // Read the three planes.
    ReceiverGrid grid;
    grid.width = reader.width();
    grid.height = reader.height();
    std::vector<float> planes[3];
    Imf::FrameBuffer frame_buffer;
    const char* names[3] = {"U", "V", "Z"};
    for (int c = 0; c < 3; ++c) {
        planes[c].resize(reader.texel_count());
        frame_buffer.insert(names[c], reader.float_slice(planes[c].data(), sizeof(float),
                                                         sizeof(float) * static_cast<std::size_t>(grid.width)));
    }
    reader.read(frame_buffer);

    // Every coordinate must be finite (points outside the map are fine: lookups clamp).
    for (int c = 0; c < 3; ++c)
        for (std::size_t i = 0; i < planes[c].size(); ++i)
            if (!std::isfinite(planes[c][i]))
                fail(path, texel_name(static_cast<long long>(i % static_cast<std::size_t>(grid.width)),
                                      static_cast<long long>(i / static_cast<std::size_t>(grid.width))) +
                               ": " + names[c] + " is " + describe_value(planes[c][i]));
    grid.points.u = std::move(planes[0]);
    grid.points.v = std::move(planes[1]);
    grid.points.z = std::move(planes[2]);

    // Optional screen pixels: PX and PY together, whole numbers.
    const bool has_px = reader.find_channel("PX") != nullptr, has_py = reader.find_channel("PY") != nullptr;
    if (has_px != has_py) fail(path, std::string("has channel ") + (has_px ? "PX" : "PY") + " without " + (has_px ? "PY" : "PX"));
    if (has_px) {
        std::vector<std::uint32_t>* targets[2] = {&grid.pixels.x, &grid.pixels.y};
        const char* pixel_names[2] = {"PX", "PY"};
        for (int c = 0; c < 2; ++c) {
            std::vector<std::uint32_t>& target = *targets[c];
            target.resize(reader.texel_count());
            Imf::FrameBuffer pixel_buffer;
            if (reader.find_channel(pixel_names[c])->type == Imf::UINT) {
                pixel_buffer.insert(pixel_names[c], Imf::Slice::Make(Imf::UINT, target.data(), reader.data_window(),
                                                                     sizeof(std::uint32_t),
                                                                     sizeof(std::uint32_t) * static_cast<std::size_t>(grid.width)));
                reader.read(pixel_buffer);
                continue;
            }
            // HALF or FLOAT: every value a whole number in [0, 2^24] (exact in float).
            std::vector<float> values(reader.texel_count());
            pixel_buffer.insert(pixel_names[c], reader.float_slice(values.data(), sizeof(float),
                                                                   sizeof(float) * static_cast<std::size_t>(grid.width)));
            reader.read(pixel_buffer);
            for (std::size_t i = 0; i < values.size(); ++i) {
                const float value = values[i];
                if (!(value >= 0.0f && value <= 16777216.0f && std::floor(value) == value))
                    fail(path, texel_name(static_cast<long long>(i % static_cast<std::size_t>(grid.width)),
                                          static_cast<long long>(i / static_cast<std::size_t>(grid.width))) +
                                   ": " + pixel_names[c] + " is " + describe_value(value) +
                                   "; screen pixels must be whole numbers in [0, 16777216]");
                target[i] = static_cast<std::uint32_t>(value);
            }
        }
    }
    return grid;
}

void write_receivers_exr(const std::string& path, const ReceiverGrid& receivers) {
    const std::size_t count = static_cast<std::size_t>(std::max(receivers.width, 0)) * std::max(receivers.height, 0);
    if (receivers.points.u.size() != count || receivers.points.v.size() != count || receivers.points.z.size() != count)
        fail(path, "receiver grid size does not match its data");
    ExrImage image;
    image.width = receivers.width;
    image.height = receivers.height;
    image.channels = {{"U", SampleType::float32, receivers.points.u, {}},
                      {"V", SampleType::float32, receivers.points.v, {}},
                      {"Z", SampleType::float32, receivers.points.z, {}}};
    if (!receivers.pixels.x.empty() || !receivers.pixels.y.empty()) {
        if (receivers.pixels.x.size() != count || receivers.pixels.y.size() != count)
            fail(path, "receiver pixels do not match the grid size");
        image.channels.push_back({"PX", SampleType::uint32, {}, receivers.pixels.x});
        image.channels.push_back({"PY", SampleType::uint32, {}, receivers.pixels.y});
    }
    write_exr_atomically(path, image);
}

} // namespace msmcl::io
