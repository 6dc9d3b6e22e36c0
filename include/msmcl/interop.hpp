// Device data in and out, for engines: depth maps in cl_mem buffers or 2D images, results
// written into caller-owned images of each texture's natural format, chained to the
// engine's queue by events. Nothing passes through host memory: every call enqueues
// device-side copies and kernels only, and never maps or reads the caller's objects (they
// may be created with CL_MEM_HOST_NO_ACCESS).
//
// Cost: the image paths stage through device buffers (one device copy in for an image
// input, one out for an image output) because the kernels work on buffers; the staging
// buffers are created per call and released once the commands are done.
//
// Shared GL/D3D/Vulkan images (clCreateFromGLTexture and the like): acquire them on the
// queue first and pass that event in Enqueue::wait_for; release them after Enqueue::done.
#pragma once

#include <msmcl/context.hpp>
#include <msmcl/enqueue.hpp>
#include <msmcl/types.hpp>

#include <CL/cl.h>

namespace msmcl {

/// How the S samples of each texel lie in a depth image.
enum class SampleLayout {
    /// One 2D image of (width * S) x height pixels: sample s of texel (x, y) at pixel
    /// (x * S + s, y), the byte layout of DepthImage and DeviceDepth. S = 1: a plain depth image.
    side_by_side,
    /// One 2D image array of S layers of width x height: sample s of texel (x, y) at pixel
    /// (x, y) of layer s (what an engine gets by resolving each MSAA sample into a layer).
    layers,
};

/// A depth map in an OpenCL image. Channel order CL_R or CL_DEPTH, channel type CL_FLOAT;
/// values as rendered (DepthRange). The image may be larger than the map: the top-left
/// width x height texels (times S, see SampleLayout) are read. Values are not validated,
/// as for DeviceDepth: out-of-range depths clamp to the range, NaN counts as the near plane.
/// Texture arrays (`layers` > 1, N maps of one size, docs/formats.md): a 2D image array
/// whose array layer a holds map a (side_by_side), or whose array layer a * S + s holds
/// sample s of map a (SampleLayout::layers); the output image, if any, is then a 2D image
/// array of at least N layers, map a in its layer a.
struct DeviceDepthImage {
    cl_mem image = nullptr;
    int width = 0;
    int height = 0;
    int samples = 1; ///< 1, 2, 4, 8 or 16
    SampleLayout layout = SampleLayout::side_by_side;
    int layers = 1; ///< array layers (maps), 1 .. max_array_layers
};

/// The natural OpenCL image format of a texture:
///   moments128 CL_RGBA / CL_FLOAT        (b1..b4)
///   msm64      CL_RGBA / CL_UNORM_INT16  (affine basis R, G, B, A; sampled as unorm floats)
///   nlq64      CL_RGBA / CL_UNORM_INT16  ((y1+1)/2, (y2+1)/2, v2, Psi4)
///   nlq32      CL_R    / CL_UNSIGNED_INT32
cl_image_format texture_image_format(Format format) noexcept;

/// Whether an image of `image_format` takes the texel bytes of `format` unchanged:
/// texture_image_format(format), and for msm64 and nlq64 also CL_RGBA / CL_UNSIGNED_INT16
/// (the raw 16-bit codes, for shaders that decode integers).
bool image_format_matches(Format format, const cl_image_format& image_format) noexcept;

/// The OpenCL image format of a summed-area table: CL_RGBA / CL_UNSIGNED_INT32 (channels
/// R, G, B, A of SatTable, one uint32 each).
cl_image_format sat_image_format() noexcept;

/// Filters a depth map (buffer) into `image`: a 2D image of the Context's cl_context, at
/// least width x height, whose format image_format_matches(options.format). Texels
/// [0, width) x [0, height) are written. Throws input_error for a wrong object, format or
/// size (before anything is enqueued).
void filter_to_image(Context& context, const DeviceDepth& depth, cl_mem image, const FilterOptions& options,
                     const Enqueue& enqueue = {});
/// The same from a depth image.
void filter_to_image(Context& context, const DeviceDepthImage& depth, cl_mem image, const FilterOptions& options,
                     const Enqueue& enqueue = {});
/// A depth image filtered into a texture buffer (layout as Texture), as filter() does for
/// a DeviceDepth.
void filter(Context& context, const DeviceDepthImage& depth, cl_mem texture, const FilterOptions& options,
            const Enqueue& enqueue = {});

/// Builds the summed-area table of a depth map (buffer) into `image`: a 2D image of
/// sat_image_format(), at least width x height.
void build_sat_to_image(Context& context, const DeviceDepth& depth, cl_mem image, const SatOptions& options,
                        const Enqueue& enqueue = {});
/// The same from a depth image.
void build_sat_to_image(Context& context, const DeviceDepthImage& depth, cl_mem image, const SatOptions& options,
                        const Enqueue& enqueue = {});
/// A depth image into a table buffer (layout as SatTable::words).
void build_sat(Context& context, const DeviceDepthImage& depth, cl_mem table, const SatOptions& options,
               const Enqueue& enqueue = {});

} // namespace msmcl
