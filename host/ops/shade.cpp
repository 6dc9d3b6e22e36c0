// shade: evaluates a filtered map at receivers with kernels/shade.cl.
#include "ops/kernel_variants.hpp"
#include "ops/transfer.hpp"
#include "ops/validation.hpp"
#include "runtime/context_impl.hpp"
#include "runtime/enum_names.hpp"
#include "runtime/texture_kinds.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/shade.hpp>
#include <msmcl/device_math.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace msmcl {

// The names of Lookup values, both ways (lookup_name, parse_lookup).
constexpr detail::EnumNames<Lookup> lookup_names[] = {
    {Lookup::nearest, "nearest"},
    {Lookup::bilinear, "bilinear"},
    {Lookup::dither, "dither"},
};

const char* lookup_name(Lookup lookup) noexcept { return detail::name_in(lookup_names, lookup); }

std::optional<Lookup> parse_lookup(std::string_view name) noexcept { return detail::parse_in(lookup_names, name); }

namespace {

void check_map_shape(Format format, int width, int height, const detail::ContextImpl& impl) {
    if (width <= 0 || height <= 0)
        throw input_error("shade: the map is empty (" + std::to_string(width) + "x" + std::to_string(height) + ")");
    const unsigned long long bytes = static_cast<unsigned long long>(width) * height * texel_bytes(format);
    if (bytes > impl.info.max_alloc_bytes)
        throw device_error("shade: a " + std::to_string(width) + "x" + std::to_string(height) + " " +
                          format_name(format) + " map exceeds the device's largest buffer (" +
                          std::to_string(impl.info.max_alloc_bytes) + " bytes)");
}

void check_options(const ShadeOptions& options) {
    if (!std::isfinite(options.depth_bias))
        throw input_error("shade: the depth bias must be finite");
    if (options.lookup != Lookup::nearest && options.lookup != Lookup::bilinear && options.lookup != Lookup::dither)
        throw input_error("shade: unknown lookup " + std::to_string(static_cast<int>(options.lookup)));
}

// Bytes of one blue-noise texture (64 x 64 texels, 2 channels).
constexpr std::size_t blue_noise_texture_bytes = 64 * 64 * 2;

} // namespace

namespace detail {

// Variant per format, lookup and depth convention (dither: and where pixels come from).
std::vector<std::string> shade_defines(Format format, Lookup lookup, DepthRange range, bool receiver_pixels) {
    std::vector<std::string> defines = texture_kind_defines(format);
    defines.push_back("MSM_LOOKUP=" + std::to_string(static_cast<int>(lookup)));
    defines.push_back(std::string("MSM_DEPTH_ZERO_ONE=") + (range == DepthRange::zero_one ? "1" : "0"));
    if (lookup == Lookup::dither) defines.push_back(std::string("MSM_RECEIVER_PIXELS=") + (receiver_pixels ? "1" : "0"));
    return defines;
}

} // namespace detail

void shade(Context& context, const DeviceTexture& map, cl_mem receivers_uvz, std::size_t count,
           cl_mem intensity, const ShadeOptions& options, const Enqueue& enqueue) {
    shade(context, map, receivers_uvz, nullptr, count, intensity, options, enqueue);
}

void shade(Context& context, const DeviceTexture& map, cl_mem receivers_uvz, cl_mem receiver_pixels,
           std::size_t count, cl_mem intensity, const ShadeOptions& options, const Enqueue& enqueue) {
    detail::ContextImpl& impl = context.impl();
    check_map_shape(map.format, map.width, map.height, impl);
    check_options(options);
    if (!map.buffer || !receivers_uvz || !intensity)
        throw input_error("shade: null cl_mem argument");
    if (count > std::numeric_limits<cl_uint>::max())
        throw input_error("shade: too many receivers in one call (" + std::to_string(count) + ")");

    const bool dither = options.lookup == Lookup::dither;
    const std::vector<std::string> defines =
        detail::shade_defines(map.format, options.lookup, options.depth_range, receiver_pixels);
    cl::Kernel& kernel = impl.kernel("shade.cl", defines, dither ? "shade_dither" : "shade");
    cl::CommandQueue queue = impl.queue_for(enqueue);
    std::vector<cl::Event> waits = detail::wait_list(enqueue);
    cl::Event done;
    if (count == 0) {
        detail::complete_without_work(enqueue, queue);
        return;
    }
    detail::set_arg(kernel, 0, map.buffer);
    detail::set_arg(kernel, 1, static_cast<cl_int>(map.width));
    detail::set_arg(kernel, 2, static_cast<cl_int>(map.height));
    detail::set_arg(kernel, 3, receivers_uvz);
    detail::set_arg(kernel, 4, static_cast<cl_uint>(count));
    detail::set_arg(kernel, 5, intensity);
    detail::set_arg(kernel, 6, options.depth_bias);
    cl::Buffer noise_buffer;
    if (dither) {
        // The frame's blue-noise texture (8 KiB) and its shift; pixels given or row-major.
        const BlueNoiseFrame frame = blue_noise_frame(options.frame);
        cl_int status = CL_SUCCESS;
        noise_buffer = cl::Buffer(impl.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, blue_noise_texture_bytes,
                                  const_cast<std::uint8_t*>(blue_noise_textures() + frame.texture * blue_noise_texture_bytes),
                                  &status);
        detail::check(status, "clCreateBuffer(blue noise)");
        const cl_uint screen_width = options.screen_width ? options.screen_width : static_cast<cl_uint>(std::max<std::size_t>(count, 1));
        detail::set_arg(kernel, 7, noise_buffer());
        detail::set_arg(kernel, 8, static_cast<cl_uint>(frame.offset_x));
        detail::set_arg(kernel, 9, static_cast<cl_uint>(frame.offset_y));
        detail::set_arg(kernel, 10, receiver_pixels);
        detail::set_arg(kernel, 11, screen_width);
    }
    // One work-item per receiver; groups of 64 (a multiple of every warp/wavefront width), or
    // fewer where the built kernel allows fewer (docs/devices.md).
    const std::size_t group = detail::fitting_group(detail::kernel_fit(impl, kernel), 64);
    const std::size_t global = (count + group - 1) / group * group;
    detail::check(queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(global), cl::NDRange(group),
                                             waits.empty() ? nullptr : &waits, &done),
                  "clEnqueueNDRangeKernel(shade)");
    detail::complete(enqueue, queue, done);
}

std::vector<float> shade(Context& context, const Texture& map, const Receivers& receivers,
                         const ShadeOptions& options) {
    return shade(context, map, receivers, ReceiverPixels{}, options);
}

std::vector<float> shade(Context& context, const Texture& map, const Receivers& receivers,
                         const ReceiverPixels& pixels, const ShadeOptions& options) {
    detail::ContextImpl& impl = context.impl();
    check_map_shape(map.format, map.width, map.height, impl);
    detail::require_single_layer("shade", "the map", map.layers);
    check_options(options);
    const std::size_t texels = static_cast<std::size_t>(map.width) * map.height;
    if (map.words.size() != texels * texel_words(map.format))
        throw input_error("shade: the map holds " + std::to_string(map.words.size()) + " words, a " +
                          std::to_string(map.width) + "x" + std::to_string(map.height) + " " +
                          format_name(map.format) + " map needs " + std::to_string(texels * texel_words(map.format)));
    detail::validate_receivers("shade", receivers);
    const std::size_t count = receivers.size();
    const bool with_pixels = !pixels.x.empty() || !pixels.y.empty();
    if (with_pixels && (pixels.x.size() != count || pixels.y.size() != count))
        throw input_error("shade: " + std::to_string(count) + " receivers but " + std::to_string(pixels.x.size()) +
                          " x and " + std::to_string(pixels.y.size()) + " y pixel coordinates");
    if (count == 0) return {};

    // Upload the map and the receivers (planar u, v, z), shade, read back.
    detail::StageTimer stages(impl, options.on_stage);
    const cl::Buffer map_buffer =
        detail::upload(impl, map.words.data(), map.words.size() * sizeof(std::uint32_t), "clCreateBuffer(map)");
    const cl::Buffer receiver_buffer = detail::upload_receivers(impl, receivers);
    const cl::Buffer result_buffer =
        detail::device_buffer(impl, CL_MEM_WRITE_ONLY, count * sizeof(float), "clCreateBuffer(intensity)");

    cl::Buffer pixel_buffer;
    if (with_pixels && options.lookup == Lookup::dither) {
        // Screen pixels, planar x then y (only dither reads them).
        std::vector<std::uint32_t> xy(2 * count);
        std::copy(pixels.x.begin(), pixels.x.end(), xy.begin());
        std::copy(pixels.y.begin(), pixels.y.end(), xy.begin() + count);
        pixel_buffer = detail::upload(impl, xy.data(), xy.size() * sizeof(std::uint32_t), "clCreateBuffer(pixels)");
    }

    stages.uploaded({&map_buffer, &receiver_buffer, &pixel_buffer});
    shade(context, DeviceTexture{map_buffer(), map.format, map.width, map.height}, receiver_buffer(), pixel_buffer(),
          count, result_buffer(), options, Enqueue{});
    stages.computed();
    std::vector<float> intensity = detail::read_floats(impl, result_buffer, count, "clEnqueueReadBuffer(intensity)");
    stages.downloaded(result_buffer, count * sizeof(float));
    return intensity;
}

} // namespace msmcl
