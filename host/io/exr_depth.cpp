// Depth maps in EXR files (exr_io.hpp): `Z` for one sample per texel, `sample<s>.Z` for
// multisampled maps, HALF or FLOAT, every depth finite and inside its range.
#include "io/exr_file.hpp"

#include "ops/range_scan.hpp"

#include <msmcl/errors.hpp>

#include <algorithm>
#include <cmath>
#include <map>

namespace msmcl::io {
namespace exr {
namespace {

/// "sample<k>.Z" -> k; -1 for other names; throws for a malformed sample layer name.
int sample_layer_index(const std::string& path, const std::string& name) {
    static const std::string prefix = "sample";
    static const std::string suffix = ".Z";
    if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
        return -1;
    const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    const bool all_digits = std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (!all_digits) return -1; // another layer, e.g. "sampleA.Z": not a depth sample
    if (digits.size() > 4 || (digits.size() > 1 && digits[0] == '0'))
        fail(path, "bad sample layer name '" + name + "' (expected sample0.Z, sample1.Z, ...)");
    return std::stoi(digits);
}

} // namespace

bool is_supported_samples(int samples) {
    return samples == 1 || samples == 2 || samples == 4 || samples == 8 || samples == 16;
}

DepthImage read_depth(ExrReader& reader, DepthRange range) {
    const std::string& path = reader.path();

    // Find the sample layout: Z alone, or sample0.Z .. sample<S-1>.Z.
    const std::vector<std::string> names = reader.channel_names();
    bool has_plain_z = false;
    std::map<int, std::string> layers;
    for (const std::string& name : names) {
        if (name == "Z") has_plain_z = true;
        else if (const int index = sample_layer_index(path, name); index >= 0) layers[index] = name;
    }
    if (has_plain_z && !layers.empty())
        fail(path, "has both a Z channel and sample<N>.Z layers; use one layout");
    if (!has_plain_z && layers.empty())
        fail(path, "missing depth channel: expected Z or sample0.Z .. sample<S-1>.Z (channels: " +
                       list_names(names) + ")");
    std::vector<std::string> depth_channels;
    if (has_plain_z) {
        depth_channels.push_back("Z");
    } else {
        for (int index = 0; index < static_cast<int>(layers.size()); ++index) {
            if (!layers.count(index))
                fail(path, "sample layers must be contiguous from sample0.Z: sample" + std::to_string(index) +
                               ".Z is missing (found " + std::to_string(layers.size()) + " layers up to " +
                               layers.rbegin()->second + ")");
            depth_channels.push_back(layers[index]);
        }
    }
    const int samples = static_cast<int>(depth_channels.size());
    if (!is_supported_samples(samples))
        fail(path, "unsupported sample count " + std::to_string(samples) + " (must be 1, 2, 4, 8 or 16)");
    for (const std::string& name : depth_channels) require_float_channel(reader, name, "depth");

    // Read all samples of a texel next to each other (texel-major).
    DepthImage depth;
    depth.width = reader.width();
    depth.height = reader.height();
    depth.samples = samples;
    depth.depth.resize(reader.texel_count() * static_cast<std::size_t>(samples));
    Imf::FrameBuffer frame_buffer;
    const std::size_t texel_bytes = sizeof(float) * static_cast<std::size_t>(samples);
    for (int s = 0; s < samples; ++s)
        frame_buffer.insert(depth_channels[static_cast<std::size_t>(s)],
                            reader.float_slice(depth.depth.data() + s, texel_bytes,
                                               texel_bytes * static_cast<std::size_t>(depth.width)));
    reader.read(frame_buffer);

    // Every depth must be finite and inside the declared range.
    const float low = range == DepthRange::zero_one ? 0.0f : -1.0f;
    const float high = 1.0f;
    const std::size_t count = depth.depth.size();
    if (const std::size_t i = detail::first_outside(depth.depth.data(), count, low, high); i < count) {
        const float value = depth.depth[i];
        const std::size_t texel = i / static_cast<std::size_t>(samples);
        const long long x = static_cast<long long>(texel % static_cast<std::size_t>(depth.width));
        const long long y = static_cast<long long>(texel / static_cast<std::size_t>(depth.width));
        const std::string where = texel_name(x, y) + " " + depth_channels[i % static_cast<std::size_t>(samples)];
        if (!std::isfinite(value)) fail(path, where + ": depth is " + describe_value(value));
        fail(path, where + ": depth " + describe_value(value) + " is outside the depth range [" +
                       depth_range_name(range) + "]");
    }
    return depth;
}

} // namespace exr

using namespace exr;

DepthImage read_depth_exr(const std::string& path, DepthRange range) {
    ExrReader reader(path);
    return read_depth(reader, range);
}

void write_depth_exr(const std::string& path, const DepthImage& depth, SampleType type) {
    if (type == SampleType::uint32) fail(path, "depth must be written as HALF or FLOAT");
    if (depth.samples < 1 || depth.width <= 0 || depth.height <= 0 ||
        depth.depth.size() != static_cast<std::size_t>(depth.width) * depth.height * depth.samples)
        fail(path, "depth image size does not match its data");

    // One channel per sample: Z, or sample<s>.Z.
    ExrImage image;
    image.width = depth.width;
    image.height = depth.height;
    const std::size_t texels = static_cast<std::size_t>(depth.width) * depth.height;
    for (int s = 0; s < depth.samples; ++s) {
        ExrChannel channel;
        channel.name = depth.samples == 1 ? "Z" : "sample" + std::to_string(s) + ".Z";
        channel.type = type;
        channel.values.resize(texels);
        for (std::size_t t = 0; t < texels; ++t)
            channel.values[t] = depth.depth[t * static_cast<std::size_t>(depth.samples) + static_cast<std::size_t>(s)];
        image.channels.push_back(std::move(channel));
    }
    write_exr_atomically(path, image);
}

} // namespace msmcl::io
