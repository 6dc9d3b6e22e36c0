// Translucent layers as filter() and build_sat() take them (include/msmcl/types.hpp):
// validation and the device layout (layer after layer).
#pragma once

#include <msmcl/types.hpp>

#include <string>
#include <vector>

namespace msmcl::detail {

/// input_error "<call>: N translucent layers (at most 8)" unless 0 <= count <= max.
void validate_layer_count(const std::string& call, int count);

/// Every layer as large as the depth map, every depth finite and in the range, every
/// opacity in [0, 1]; input_error names the first bad value by layer, texel and sample.
void validate_layers(const std::string& call, const DepthImage& depth, const std::vector<TranslucentLayer>& layers,
                     DepthRange range);

/// The layers' depths (or opacities) one layer after the other, as DeviceLayers holds them;
/// over a layered depth map (each TranslucentLayer holding `array_layers` slices like the
/// DepthImage), array layer after array layer, each with its translucent layers in order.
std::vector<float> concatenated_depths(const std::vector<TranslucentLayer>& layers, int array_layers = 1);
std::vector<float> concatenated_opacities(const std::vector<TranslucentLayer>& layers, int array_layers = 1);

} // namespace msmcl::detail
