// Summed-area table files through the generic EXR reader and writer of exr_io.hpp.
#include "io/sat_exr.hpp"

#include "io/exr_io.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/sat.hpp>

#include <algorithm>
#include <array>
#include <variant>

namespace msmcl::io {
namespace {

const std::array<const char*, 4> kChannels = {"R", "G", "B", "A"};

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
    throw input_error(path + ": " + problem);
}

// The attribute `name` of type T, else an error naming what is missing.
template <class T>
const T& required_attribute(const std::string& path, const ExrImage& image, const std::string& name,
                            const char* type) {
    const ExrAttribute* attribute = image.find_attribute(name);
    if (!attribute || !std::holds_alternative<T>(attribute->value))
        fail(path, "attribute " + name + " (" + type + ") is missing or not " + (type[0] == 'i' ? "an " : "a ") + type);
    return std::get<T>(attribute->value);
}

} // namespace

void write_sat_exr(const std::string& path, const SatTable& table, const SatInfo& info) {
    const std::size_t texels = static_cast<std::size_t>(std::max(table.width, 0)) * std::max(table.height, 0);
    if (texels == 0 || table.words.size() != 4 * texels) fail(path, "table size does not match its data");
    if (table.max_kernel_texels < sat_min_kernel_texels || table.max_kernel_texels > sat_max_kernel_texels ||
        table.scale != sat_scale(table.max_kernel_texels))
        fail(path, "table scale " + std::to_string(table.scale) + " does not match N = " +
                       std::to_string(table.max_kernel_texels));

    // One UINT channel per table word of a texel.
    ExrImage image;
    image.width = table.width;
    image.height = table.height;
    for (std::size_t c = 0; c < 4; ++c) {
        ExrChannel channel{kChannels[c], SampleType::uint32, {}, std::vector<std::uint32_t>(texels)};
        for (std::size_t t = 0; t < texels; ++t) channel.codes[t] = table.words[4 * t + c];
        image.channels.push_back(std::move(channel));
    }
    image.attributes = {{"msmcl:format", std::string("sat")},
                        {"msmcl:maxKernel", static_cast<int>(table.max_kernel_texels)},
                        {"msmcl:satScale", static_cast<int>(table.scale)},
                        {"msmcl:samples", info.samples},
                        {"msmcl:depthRange", std::string(depth_range_name(info.depth_range))}};
    write_exr(path, image);
}

SatFile read_sat_exr(const std::string& path) {
    const ExrImage image = read_exr(path);

    // The attributes: a table, its N and a scale that belongs to that N.
    const ExrAttribute* format = image.find_attribute("msmcl:format");
    if (!format) fail(path, "not an msmcl summed-area table (attribute msmcl:format is missing)");
    if (!std::holds_alternative<std::string>(format->value) || std::get<std::string>(format->value) != "sat")
        fail(path, "not a summed-area table (msmcl:format is not \"sat\")");
    const int n = required_attribute<int>(path, image, "msmcl:maxKernel", "int");
    if (n < static_cast<int>(sat_min_kernel_texels))
        fail(path, "attribute msmcl:maxKernel is " + std::to_string(n) + "; it must be >= " +
                       std::to_string(sat_min_kernel_texels));
    const int scale = required_attribute<int>(path, image, "msmcl:satScale", "int");
    if (static_cast<std::uint32_t>(scale) != sat_scale(static_cast<std::uint32_t>(n)) || scale <= 0)
        fail(path, "attribute msmcl:satScale is " + std::to_string(scale) + "; N = " + std::to_string(n) +
                       " needs " + std::to_string(sat_scale(static_cast<std::uint32_t>(n))));
    const int samples = required_attribute<int>(path, image, "msmcl:samples", "int");
    if (!is_supported_sample_count(samples))
        fail(path, "attribute msmcl:samples is " + std::to_string(samples) + "; it must be 1, 2, 4, 8 or 16");
    const std::string& range_text = required_attribute<std::string>(path, image, "msmcl:depthRange", "string");
    const std::optional<DepthRange> range = parse_depth_range(range_text);
    if (!range) fail(path, "attribute msmcl:depthRange is '" + range_text + "'; it must be 0,1 or -1,1");

    // Exactly the UINT channels R, G, B, A.
    for (const ExrChannel& channel : image.channels)
        if (std::find_if(kChannels.begin(), kChannels.end(), [&](const char* name) { return channel.name == name; }) ==
            kChannels.end())
            fail(path, "unexpected channel " + channel.name + " in a summed-area table");
    SatFile result;
    SatTable& table = result.table;
    table.width = image.width;
    table.height = image.height;
    table.max_kernel_texels = static_cast<std::uint32_t>(n);
    table.scale = static_cast<std::uint32_t>(scale);
    const std::size_t texels = static_cast<std::size_t>(image.width) * image.height;
    table.words.resize(4 * texels);
    for (std::size_t c = 0; c < 4; ++c) {
        const ExrChannel* channel = image.find_channel(kChannels[c]);
        if (!channel) fail(path, std::string("missing channel ") + kChannels[c] + " of a summed-area table");
        if (channel->type != SampleType::uint32 || channel->codes.size() != texels)
            fail(path, std::string("channel ") + kChannels[c] + " must be UINT");
        for (std::size_t t = 0; t < texels; ++t) table.words[4 * t + c] = channel->codes[t];
    }
    result.info = {*range, samples};
    return result;
}

} // namespace msmcl::io
