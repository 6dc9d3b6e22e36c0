// Validation the operations share (validation.hpp).
#include "ops/validation.hpp"

#include "ops/range_scan.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/formats.hpp>

#include <cmath>
#include <sstream>

namespace msmcl::detail {

std::string size_text(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

void validate_map_size(const std::string& what, int width, int height) {
    if (width <= 0 || height <= 0) throw input_error(what + " " + size_text(width, height) + " is empty or negative");
    if (width > max_map_side || height > max_map_side)
        throw input_error(what + " " + size_text(width, height) + " exceeds the limit of " +
                          std::to_string(max_map_side) + " texels per side");
}

void validate_array_layers(const std::string& call, int layers) {
    if (layers < 1 || layers > max_array_layers)
        throw input_error(call + ": " + std::to_string(layers) + " array layers (1 to " +
                          std::to_string(max_array_layers) + ")");
}

void require_single_layer(const std::string& call, const char* what, int layers) {
    if (layers != 1)
        throw input_error(call + ": " + what + " is a texture array of " + std::to_string(layers) +
                          " layers, this call takes one (take a layer with layer(i))");
}

std::string sample_position_text(const DepthImage& depth, std::size_t value_index) {
    // Value i is sample i % S of texel i / S, texels counted over the array layers.
    const std::size_t texel = value_index / depth.samples;
    const std::size_t layer_texels = texel_count(depth.width, depth.height);
    const std::size_t in_layer = texel % layer_texels;
    std::ostringstream text;
    text << "texel (" << in_layer % depth.width << ", " << in_layer / depth.width << ")";
    if (depth.layers != 1) text << " of array layer " << texel / layer_texels;
    text << " sample " << value_index % depth.samples;
    return text.str();
}

void validate_depth_values(const char* call, const DepthImage& depth, DepthRange range) {
    const float lowest = range == DepthRange::zero_one ? 0.0f : -1.0f;
    // Only the first bad value (if any) is looked at.
    const std::size_t count = depth.depth.size();
    if (const std::size_t i = first_outside(depth.depth.data(), count, lowest, 1.0f); i < count) {
        const float d = depth.depth[i];
        std::ostringstream text;
        text << call << ": depth at " << sample_position_text(depth, i) << " is " << d;
        if (std::isfinite(d)) text << ", outside the depth range [" << depth_range_name(range) << "]";
        throw input_error(text.str());
    }
}

void validate_receivers(const char* call, const Receivers& receivers) {
    const std::size_t count = receivers.size();
    if (receivers.u.size() != count || receivers.v.size() != count)
        throw input_error(std::string(call) + ": receiver arrays differ in length (u " +
                          std::to_string(receivers.u.size()) + ", v " + std::to_string(receivers.v.size()) + ", z " +
                          std::to_string(count) + ")");
    for (std::size_t i = 0; i < count; ++i)
        if (!std::isfinite(receivers.u[i]) || !std::isfinite(receivers.v[i]) || !std::isfinite(receivers.z[i]))
            throw input_error(std::string(call) + ": receiver " + std::to_string(i) + " is not finite (u " +
                              std::to_string(receivers.u[i]) + ", v " + std::to_string(receivers.v[i]) + ", z " +
                              std::to_string(receivers.z[i]) + ")");
}

cl_ulong buffer_size(cl_mem buffer) {
    std::size_t bytes = 0;
    check(clGetMemObjectInfo(buffer, CL_MEM_SIZE, sizeof bytes, &bytes, nullptr), "clGetMemObjectInfo");
    return bytes;
}

} // namespace msmcl::detail
