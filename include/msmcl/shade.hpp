// shade: evaluate a filtered moment shadow map at receiver points.
#pragma once

#include <msmcl/context.hpp>
#include <msmcl/enqueue.hpp>
#include <msmcl/formats.hpp>

#include <optional>
#include <string_view>
#include <vector>

namespace msmcl {

enum class Lookup {
    nearest,  ///< texel floor(u), floor(v)
    bilinear, ///< between texel centres around (u-0.5, v-0.5): moments for moments128/msm64,
              ///< the four shadow intensities for nlq64/nlq32
};
const char* lookup_name(Lookup lookup) noexcept;
std::optional<Lookup> parse_lookup(std::string_view name) noexcept;

struct ShadeOptions {
    Lookup lookup = Lookup::bilinear;
    /// Subtracted from the receiver's internal depth z (SPEC section 2) before shading.
    float depth_bias = 1e-3f;
    /// Convention of the receivers' z (normally the map's).
    DepthRange depth_range = DepthRange::zero_one;
};

/// Shadow intensity (0 lit, 1 shadowed) for each receiver. Throws input_error for an
/// empty map, mismatched receiver arrays, or non-finite receiver values.
std::vector<float> shade(Context& context, const Texture& map, const Receivers& receivers,
                         const ShadeOptions& options);

/// A filtered map already on the device (a buffer, layout as Texture).
struct DeviceTexture {
    cl_mem buffer = nullptr;
    Format format = Format::nlq64;
    int width = 0;
    int height = 0;
};

/// Device-side shade: `receivers_uvz` holds 3*count floats, planar (all u, then all v,
/// then all z); `intensity` receives count floats.
void shade(Context& context, const DeviceTexture& map, cl_mem receivers_uvz, std::size_t count,
           cl_mem intensity, const ShadeOptions& options, const Enqueue& enqueue = {});

} // namespace msmcl
