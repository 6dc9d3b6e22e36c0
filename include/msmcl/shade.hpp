// shade: evaluate a filtered moment shadow map at receiver points.
#pragma once

#include <msmcl/context.hpp>
#include <msmcl/enqueue.hpp>
#include <msmcl/types.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace msmcl {

/// "nearest", "bilinear", "dither"; parse_lookup is the inverse (std::nullopt for an
/// unknown name).
const char* lookup_name(Lookup lookup) noexcept;
std::optional<Lookup> parse_lookup(std::string_view name) noexcept;

/// The shading options of `format` from the format table (docs/formats.md): its depth bias,
/// lookup and, for VSM and EVSM, its minimum variance.
ShadeOptions shade_defaults(Format format);

/// Shadow intensity (0 lit, 1 shadowed) for each receiver. Throws input_error for an
/// empty map, mismatched receiver arrays, or non-finite receiver values.
std::vector<float> shade(Context& context, const Texture& map, const Receivers& receivers,
                         const ShadeOptions& options);
/// The same with the receivers' screen pixels (for dither); also throws input_error when
/// `pixels` differs in length from the receivers.
std::vector<float> shade(Context& context, const Texture& map, const Receivers& receivers,
                         const ReceiverPixels& pixels, const ShadeOptions& options);

/// Device-side shade: `receivers_uvz` holds 3*count floats, planar (all u, then all v,
/// then all z); `intensity` receives count floats.
void shade(Context& context, const DeviceTexture& map, cl_mem receivers_uvz, std::size_t count,
           cl_mem intensity, const ShadeOptions& options, const Enqueue& enqueue = {});
/// The same with the receivers' screen pixels: `receiver_pixels` holds 2*count uints, planar
/// (all x, then all y), or is null (row-major, ShadeOptions::screen_width).
void shade(Context& context, const DeviceTexture& map, cl_mem receivers_uvz, cl_mem receiver_pixels,
           std::size_t count, cl_mem intensity, const ShadeOptions& options, const Enqueue& enqueue = {});

} // namespace msmcl
