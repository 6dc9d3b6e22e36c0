// Depth maps with translucent layers in EXR files (exr_io.hpp, docs/math.md): the opaque
// depth as exr_depth.cpp reads it, plus `layer<k>.Z` and `layer<k>.A` per layer (or per
// layer and sample `layer<k>.sample<s>.Z`, `.A`).
#include "io/exr_file.hpp"

#include <msmcl/errors.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace msmcl::io {
using namespace exr;
namespace {

/// "layer<k>.<rest>" -> k (and rest); -1 for other names. A malformed index is an error.
int translucent_layer_index(const std::string& path, const std::string& name, std::string& rest) {
    static const std::string prefix = "layer";
    if (name.compare(0, prefix.size(), prefix) != 0) return -1;
    const std::size_t dot = name.find('.', prefix.size());
    if (dot == std::string::npos || dot == prefix.size()) return -1;
    const std::string digits = name.substr(prefix.size(), dot - prefix.size());
    if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) return -1;
    if (digits.size() > 4 || (digits.size() > 1 && digits[0] == '0'))
        fail(path, "bad translucent layer name '" + name + "' (expected layer0.Z, layer0.A, layer1.Z, ...)");
    rest = name.substr(dot + 1);
    return std::stoi(digits);
}

/// Inserts the slices that read the channels `names` (one per sample, or a single one for
/// sample 0 of every texel) into a texel-major array of `samples` values per texel.
void insert_per_sample(const ExrReader& reader, Imf::FrameBuffer& frame_buffer, const std::vector<std::string>& names,
                       std::vector<float>& values, int samples) {
    values.resize(reader.texel_count() * static_cast<std::size_t>(samples));
    const std::size_t texel_bytes = sizeof(float) * static_cast<std::size_t>(samples);
    for (std::size_t s = 0; s < names.size(); ++s)
        frame_buffer.insert(names[s], reader.float_slice(values.data() + s, texel_bytes,
                                                         texel_bytes * static_cast<std::size_t>(reader.width())));
}

/// After the read: a single channel's value (in sample 0) copied to the other samples.
void broadcast_sample0(std::vector<float>& values, std::size_t channels, int samples) {
    if (channels != 1) return;
    for (std::size_t t = 0; t < values.size(); t += static_cast<std::size_t>(samples))
        for (int s = 1; s < samples; ++s) values[t + static_cast<std::size_t>(s)] = values[t];
}

} // namespace

TranslucentDepth read_translucent_depth_exr(const std::string& path, DepthRange range) {
    TranslucentDepth result;
    ExrReader reader(path);
    result.depth = read_depth(reader, range);
    const int samples = result.depth.samples;

    // Collect the layer channels: layer<k>.Z / .A, or layer<k>.sample<s>.Z / .A.
    struct LayerChannels {
        std::map<int, std::string> z, a; // per sample; key -1: one channel for every sample
    };
    std::map<int, LayerChannels> found;
    for (const std::string& name : reader.channel_names()) {
        std::string rest;
        const int k = translucent_layer_index(path, name, rest);
        if (k < 0) continue;
        int sample = -1;
        std::string kind = rest;
        if (rest.compare(0, 6, "sample") == 0 && rest.size() > 8) {
            const std::string tail = rest.substr(6);
            const std::size_t dot = tail.find('.');
            const std::string digits = tail.substr(0, dot);
            if (dot == std::string::npos || digits.empty() || digits.size() > 4 || (digits.size() > 1 && digits[0] == '0') ||
                !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
                fail(path, "bad translucent layer channel '" + name + "' (expected layer<k>.sample<s>.Z or .A)");
            sample = std::stoi(digits);
            kind = tail.substr(dot + 1);
        }
        if (kind != "Z" && kind != "A")
            fail(path, "bad translucent layer channel '" + name + "' (expected a depth .Z or an opacity .A)");
        if (sample >= samples)
            fail(path, "translucent layer channel " + name + " names a sample the depth map (" + std::to_string(samples) +
                           " samples) does not have");
        (kind == "Z" ? found[k].z : found[k].a)[sample] = name;
        require_float_channel(reader, name, "translucent layer");
    }
    if (found.empty()) return result;
    if (static_cast<int>(found.size()) > max_translucent_layers)
        fail(path, std::to_string(found.size()) + " translucent layers (at most " +
                       std::to_string(max_translucent_layers) + ")");

    // Every layer 0 .. K-1 complete: both channels, one for every sample or one per sample.
    const int count = static_cast<int>(found.size());
    std::vector<std::array<std::vector<std::string>, 2>> names(static_cast<std::size_t>(count));
    for (int k = 0; k < count; ++k) {
        if (!found.count(k))
            fail(path, "translucent layers must be numbered from layer0 without gaps: layer" + std::to_string(k) +
                           " is missing");
        const LayerChannels& channels = found[k];
        for (int c = 0; c < 2; ++c) {
            const std::map<int, std::string>& by_sample = c == 0 ? channels.z : channels.a;
            const char* kind = c == 0 ? "Z" : "A";
            const std::string base = "layer" + std::to_string(k) + ".";
            std::vector<std::string>& list = names[static_cast<std::size_t>(k)][static_cast<std::size_t>(c)];
            if (by_sample.count(-1) && by_sample.size() == 1) {
                list = {by_sample.at(-1)};
            } else if (!by_sample.count(-1) && static_cast<int>(by_sample.size()) == samples && samples > 1) {
                for (int s = 0; s < samples; ++s) list.push_back(by_sample.at(s));
            } else {
                fail(path, "translucent layer " + std::to_string(k) + " needs " + base + kind +
                               (samples > 1 ? " or " + base + "sample0." + kind + " .. " + base + "sample" +
                                                  std::to_string(samples - 1) + "." + kind
                                            : std::string()) +
                               ", and not both");
            }
        }
    }

    // One read for all layers (each read decompresses every channel of the file).
    result.layers.resize(static_cast<std::size_t>(count));
    Imf::FrameBuffer frame_buffer;
    for (int k = 0; k < count; ++k) {
        TranslucentLayer& layer = result.layers[static_cast<std::size_t>(k)];
        insert_per_sample(reader, frame_buffer, names[static_cast<std::size_t>(k)][0], layer.depth, samples);
        insert_per_sample(reader, frame_buffer, names[static_cast<std::size_t>(k)][1], layer.opacity, samples);
    }
    reader.read(frame_buffer);

    for (int k = 0; k < count; ++k) {
        TranslucentLayer& layer = result.layers[static_cast<std::size_t>(k)];
        const std::array<std::vector<std::string>, 2>& layer_names = names[static_cast<std::size_t>(k)];
        broadcast_sample0(layer.depth, layer_names[0].size(), samples);
        broadcast_sample0(layer.opacity, layer_names[1].size(), samples);

        // Depths finite and in the range, opacities in [0, 1].
        const float low = range == DepthRange::zero_one ? 0.0f : -1.0f;
        for (std::size_t i = 0; i < layer.depth.size(); ++i) {
            const float d = layer.depth[i], a = layer.opacity[i];
            const bool depth_ok = std::isfinite(d) && d >= low && d <= 1.0f;
            if (depth_ok && a >= 0.0f && a <= 1.0f) continue;
            const std::size_t texel = i / static_cast<std::size_t>(samples);
            const std::size_t s = i % static_cast<std::size_t>(samples);
            const std::vector<std::string>& bad = layer_names[depth_ok ? 1 : 0];
            const std::string where =
                texel_name(static_cast<long long>(texel % static_cast<std::size_t>(result.depth.width)),
                           static_cast<long long>(texel / static_cast<std::size_t>(result.depth.width))) +
                " " + bad[bad.size() == 1 ? 0 : s];
            if (!depth_ok && !std::isfinite(d)) fail(path, where + ": depth is " + describe_value(d));
            if (!depth_ok)
                fail(path, where + ": depth " + describe_value(d) + " is outside the depth range [" +
                               depth_range_name(range) + "]");
            fail(path, where + ": opacity " + describe_value(a) + " is outside [0, 1]");
        }
    }
    return result;
}

void write_translucent_depth_exr(const std::string& path, const TranslucentDepth& depth, SampleType type) {
    const DepthImage& opaque = depth.depth;
    if (type == SampleType::uint32) fail(path, "depth must be written as HALF or FLOAT");
    if (opaque.samples < 1 || opaque.width <= 0 || opaque.height <= 0 ||
        opaque.depth.size() != static_cast<std::size_t>(opaque.width) * opaque.height * opaque.samples)
        fail(path, "depth image size does not match its data");
    for (const TranslucentLayer& layer : depth.layers)
        if (layer.depth.size() != opaque.depth.size() || layer.opacity.size() != opaque.depth.size())
            fail(path, "translucent layer size does not match the depth map");

    // Per sample: the opaque channel, then every layer's depth and opacity.
    ExrImage image;
    image.width = opaque.width;
    image.height = opaque.height;
    const std::size_t texels = static_cast<std::size_t>(opaque.width) * opaque.height;
    const auto add = [&](const std::string& name, const std::vector<float>& all, int s) {
        ExrChannel channel;
        channel.name = name;
        channel.type = type;
        channel.values.resize(texels);
        for (std::size_t t = 0; t < texels; ++t)
            channel.values[t] = all[t * static_cast<std::size_t>(opaque.samples) + static_cast<std::size_t>(s)];
        image.channels.push_back(std::move(channel));
    };
    for (int s = 0; s < opaque.samples; ++s) {
        const std::string sample = opaque.samples == 1 ? "" : "sample" + std::to_string(s) + ".";
        add(sample + "Z", opaque.depth, s);
        for (std::size_t k = 0; k < depth.layers.size(); ++k) {
            const std::string layer = "layer" + std::to_string(k) + "." + sample;
            add(layer + "Z", depth.layers[k].depth, s);
            add(layer + "A", depth.layers[k].opacity, s);
        }
    }
    write_exr_atomically(path, image);
}

} // namespace msmcl::io
