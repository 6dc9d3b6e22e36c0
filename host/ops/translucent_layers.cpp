// Validation and device layout of translucent layers (shared by filter and sat).
#include "ops/translucent_layers.hpp"
#include "ops/validation.hpp"

#include <msmcl/errors.hpp>

#include <cmath>
#include <sstream>

namespace msmcl::detail {

void validate_layer_count(const std::string& call, int count) {
    if (count < 0 || count > max_translucent_layers)
        throw input_error(call + ": " + std::to_string(count) + " translucent layers (at most " +
                          std::to_string(max_translucent_layers) + ")");
}

void validate_layers(const std::string& call, const DepthImage& depth, const std::vector<TranslucentLayer>& layers,
                     DepthRange range) {
    validate_layer_count(call, static_cast<int>(layers.size()));
    const std::size_t values = depth.depth.size();
    const float lowest = range == DepthRange::zero_one ? 0.0f : -1.0f;
    for (std::size_t k = 0; k < layers.size(); ++k) {
        const TranslucentLayer& layer = layers[k];
        if (layer.depth.size() != values || layer.opacity.size() != values)
            throw input_error(call + ": translucent layer " + std::to_string(k) + " holds " +
                              std::to_string(layer.depth.size()) + " depths and " +
                              std::to_string(layer.opacity.size()) + " opacities, the depth map needs " +
                              std::to_string(values) + " of each");
        for (std::size_t i = 0; i < values; ++i) {
            const float d = layer.depth[i], a = layer.opacity[i];
            const bool depth_ok = std::isfinite(d) && d >= lowest && d <= 1.0f;
            const bool opacity_ok = a >= 0.0f && a <= 1.0f;
            if (depth_ok && opacity_ok) continue;
            // The first bad value: the depth if that is bad, else the opacity.
            std::ostringstream text;
            text << call << ": translucent layer " << k << (depth_ok ? " opacity" : " depth") << " at "
                 << sample_position_text(depth, i) << " is " << (depth_ok ? a : d);
            if (depth_ok) text << ", outside [0, 1]";
            else if (std::isfinite(d)) text << ", outside the depth range [" << depth_range_name(range) << "]";
            throw input_error(text.str());
        }
    }
}

namespace {

// Array layer after array layer, in each the translucent layers in order (DeviceLayers).
std::vector<float> interleaved(const std::vector<TranslucentLayer>& layers, int array_layers,
                               std::vector<float> TranslucentLayer::*values) {
    std::vector<float> out;
    if (layers.empty()) return out;
    const std::size_t slice = (layers.front().*values).size() / static_cast<std::size_t>(array_layers);
    out.reserve(slice * layers.size() * static_cast<std::size_t>(array_layers));
    for (std::size_t a = 0; a < static_cast<std::size_t>(array_layers); ++a)
        for (const TranslucentLayer& layer : layers) {
            const auto first = (layer.*values).begin() + static_cast<std::ptrdiff_t>(a * slice);
            out.insert(out.end(), first, first + static_cast<std::ptrdiff_t>(slice));
        }
    return out;
}

} // namespace

std::vector<float> concatenated_depths(const std::vector<TranslucentLayer>& layers, int array_layers) {
    return interleaved(layers, array_layers, &TranslucentLayer::depth);
}

std::vector<float> concatenated_opacities(const std::vector<TranslucentLayer>& layers, int array_layers) {
    return interleaved(layers, array_layers, &TranslucentLayer::opacity);
}

} // namespace msmcl::detail
