// shade: evaluates a filtered map at receivers with kernels/shade.cl.
#include "runtime/context_impl.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/shade.hpp>

#include <cmath>
#include <limits>
#include <string>

namespace msmcl {

const char* lookup_name(Lookup lookup) noexcept {
    switch (lookup) {
        case Lookup::nearest: return "nearest";
        case Lookup::bilinear: return "bilinear";
    }
    return "unknown";
}

std::optional<Lookup> parse_lookup(std::string_view name) noexcept {
    for (Lookup l : {Lookup::nearest, Lookup::bilinear})
        if (name == lookup_name(l)) return l;
    return std::nullopt;
}

namespace {

void check_map_shape(Format format, int width, int height, const detail::ContextImpl& impl) {
    if (width <= 0 || height <= 0)
        throw input_error("shade: the map is empty (" + std::to_string(width) + "x" + std::to_string(height) + ")");
    const unsigned long long bytes = static_cast<unsigned long long>(width) * height * texel_bytes(format);
    if (bytes > impl.info.max_alloc_bytes)
        throw input_error("shade: a " + std::to_string(width) + "x" + std::to_string(height) + " " +
                          format_name(format) + " map exceeds the device's largest buffer (" +
                          std::to_string(impl.info.max_alloc_bytes) + " bytes)");
}

void check_options(const ShadeOptions& options) {
    if (!std::isfinite(options.depth_bias))
        throw input_error("shade: the depth bias must be finite");
}

} // namespace

void shade(Context& context, const DeviceTexture& map, cl_mem receivers_uvz, std::size_t count,
           cl_mem intensity, const ShadeOptions& options, const Enqueue& enqueue) {
    detail::ContextImpl& impl = context.impl();
    check_map_shape(map.format, map.width, map.height, impl);
    check_options(options);
    if (!map.buffer || !receivers_uvz || !intensity)
        throw input_error("shade: null cl_mem argument");
    if (count > std::numeric_limits<cl_uint>::max())
        throw input_error("shade: too many receivers in one call (" + std::to_string(count) + ")");

    // Variant per format, lookup and depth convention.
    cl::Kernel& kernel = impl.kernel(
        "shade.cl",
        {"MSM_FORMAT=" + std::to_string(static_cast<int>(map.format)),
         "MSM_LOOKUP=" + std::to_string(static_cast<int>(options.lookup)),
         std::string("MSM_DEPTH_ZERO_ONE=") + (options.depth_range == DepthRange::zero_one ? "1" : "0")},
        "shade");
    cl::CommandQueue queue = impl.queue_for(enqueue);
    std::vector<cl::Event> waits = detail::wait_list(enqueue);
    cl::Event done;
    if (count == 0) {
        // Nothing to shade: still honour the event contract with a marker.
        detail::check(queue.enqueueMarkerWithWaitList(&waits, &done), "clEnqueueMarkerWithWaitList");
        detail::complete(enqueue, queue, done);
        return;
    }
    detail::set_arg(kernel, 0, map.buffer);
    detail::set_arg(kernel, 1, static_cast<cl_int>(map.width));
    detail::set_arg(kernel, 2, static_cast<cl_int>(map.height));
    detail::set_arg(kernel, 3, receivers_uvz);
    detail::set_arg(kernel, 4, static_cast<cl_uint>(count));
    detail::set_arg(kernel, 5, intensity);
    detail::set_arg(kernel, 6, options.depth_bias);
    // One work-item per receiver; groups of 64 (a multiple of every warp/wavefront width).
    const std::size_t group = 64;
    const std::size_t global = (count + group - 1) / group * group;
    detail::check(queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(global), cl::NDRange(group),
                                             waits.empty() ? nullptr : &waits, &done),
                  "clEnqueueNDRangeKernel(shade)");
    detail::complete(enqueue, queue, done);
}

std::vector<float> shade(Context& context, const Texture& map, const Receivers& receivers,
                         const ShadeOptions& options) {
    detail::ContextImpl& impl = context.impl();
    check_map_shape(map.format, map.width, map.height, impl);
    check_options(options);
    const std::size_t texels = static_cast<std::size_t>(map.width) * map.height;
    if (map.words.size() != texels * texel_words(map.format))
        throw input_error("shade: the map holds " + std::to_string(map.words.size()) + " words, a " +
                          std::to_string(map.width) + "x" + std::to_string(map.height) + " " +
                          format_name(map.format) + " map needs " + std::to_string(texels * texel_words(map.format)));
    const std::size_t count = receivers.size();
    if (receivers.u.size() != count || receivers.v.size() != count)
        throw input_error("shade: receiver arrays differ in length (u " + std::to_string(receivers.u.size()) +
                          ", v " + std::to_string(receivers.v.size()) + ", z " + std::to_string(count) + ")");
    for (std::size_t i = 0; i < count; ++i)
        if (!std::isfinite(receivers.u[i]) || !std::isfinite(receivers.v[i]) || !std::isfinite(receivers.z[i]))
            throw input_error("shade: receiver " + std::to_string(i) + " is not finite (u " +
                              std::to_string(receivers.u[i]) + ", v " + std::to_string(receivers.v[i]) + ", z " +
                              std::to_string(receivers.z[i]) + ")");
    std::vector<float> result(count);
    if (count == 0) return result;

    // Upload the map and the receivers (planar u, v, z), shade, read back.
    cl_int status = CL_SUCCESS;
    cl::Buffer map_buffer(impl.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                          map.words.size() * sizeof(std::uint32_t), const_cast<std::uint32_t*>(map.words.data()),
                          &status);
    detail::check(status, "clCreateBuffer(map)");
    std::vector<float> uvz(3 * count);
    std::copy(receivers.u.begin(), receivers.u.end(), uvz.begin());
    std::copy(receivers.v.begin(), receivers.v.end(), uvz.begin() + count);
    std::copy(receivers.z.begin(), receivers.z.end(), uvz.begin() + 2 * count);
    cl::Buffer receiver_buffer(impl.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, uvz.size() * sizeof(float),
                               uvz.data(), &status);
    detail::check(status, "clCreateBuffer(receivers)");
    cl::Buffer result_buffer(impl.context, CL_MEM_WRITE_ONLY, count * sizeof(float), nullptr, &status);
    detail::check(status, "clCreateBuffer(intensity)");

    shade(context, DeviceTexture{map_buffer(), map.format, map.width, map.height}, receiver_buffer(), count,
          result_buffer(), options, Enqueue{});
    detail::check(impl.queue.enqueueReadBuffer(result_buffer, CL_TRUE, 0, count * sizeof(float), result.data()),
                  "clEnqueueReadBuffer(intensity)");
    return result;
}

} // namespace msmcl
