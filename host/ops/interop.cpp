// Device data in and out (include/msmcl/interop.hpp): depth images staged into the
// buffer layout of DeviceDepth, textures and tables copied into caller-owned images, table
// images staged for soft shadows (sat.hpp). Only device-side commands, chained by events.
#include "ops/validation.hpp"
#include "runtime/context_impl.hpp"
#include "runtime/texture_kinds.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/interop.hpp>
#include <msmcl/sat.hpp>

#include <string>
#include <vector>

// CL_DEPTH is an OpenCL 2.0 (or cl_khr_depth_images) channel order; the headers only name it
// for a 2.0 target.
#ifndef CL_DEPTH
#define CL_DEPTH 0x10BD
#endif

namespace msmcl {

namespace {

std::string size_text(std::size_t width, std::size_t height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

std::string format_text(const cl_image_format& format) {
    return std::string(format.image_channel_order == CL_R       ? "CL_R"
                       : format.image_channel_order == CL_RGBA  ? "CL_RGBA"
                       : format.image_channel_order == CL_DEPTH ? "CL_DEPTH"
                                                                 : "channel order " +
                                                                       std::to_string(format.image_channel_order)) +
           "/" +
           (format.image_channel_data_type == CL_FLOAT              ? "CL_FLOAT"
            : format.image_channel_data_type == CL_UNORM_INT16      ? "CL_UNORM_INT16"
            : format.image_channel_data_type == CL_UNSIGNED_INT16   ? "CL_UNSIGNED_INT16"
            : format.image_channel_data_type == CL_UNSIGNED_INT32   ? "CL_UNSIGNED_INT32"
                                                                    : "channel type " +
                                                                          std::to_string(format.image_channel_data_type));
}

// What the calls need to know of a caller's image.
struct ImageShape {
    cl_mem_object_type type = 0;
    cl_image_format format{};
    std::size_t width = 0;
    std::size_t height = 0;
    std::size_t layers = 1;
};

ImageShape describe_image(cl_mem image, cl_context expected_context, const char* call, const char* what) {
    if (!image) throw input_error(std::string(call) + ": the " + what + " is null");
    ImageShape shape;
    cl_context owner = nullptr;
    detail::check(clGetMemObjectInfo(image, CL_MEM_TYPE, sizeof shape.type, &shape.type, nullptr),
                  "clGetMemObjectInfo(CL_MEM_TYPE)");
    detail::check(clGetMemObjectInfo(image, CL_MEM_CONTEXT, sizeof owner, &owner, nullptr),
                  "clGetMemObjectInfo(CL_MEM_CONTEXT)");
    if (owner != expected_context)
        throw input_error(std::string(call) + ": the " + what + " belongs to another cl_context than the msmcl::Context");
    if (shape.type != CL_MEM_OBJECT_IMAGE2D && shape.type != CL_MEM_OBJECT_IMAGE2D_ARRAY)
        throw input_error(std::string(call) + ": the " + what + " is not a 2D image or 2D image array");
    detail::check(clGetImageInfo(image, CL_IMAGE_FORMAT, sizeof shape.format, &shape.format, nullptr),
                  "clGetImageInfo(CL_IMAGE_FORMAT)");
    detail::check(clGetImageInfo(image, CL_IMAGE_WIDTH, sizeof shape.width, &shape.width, nullptr),
                  "clGetImageInfo(CL_IMAGE_WIDTH)");
    detail::check(clGetImageInfo(image, CL_IMAGE_HEIGHT, sizeof shape.height, &shape.height, nullptr),
                  "clGetImageInfo(CL_IMAGE_HEIGHT)");
    if (shape.type == CL_MEM_OBJECT_IMAGE2D_ARRAY)
        detail::check(clGetImageInfo(image, CL_IMAGE_ARRAY_SIZE, sizeof shape.layers, &shape.layers, nullptr),
                      "clGetImageInfo(CL_IMAGE_ARRAY_SIZE)");
    return shape;
}

// The caller's output image: a plain 2D image of an accepted format, large enough.
void check_output_image(const ImageShape& shape, bool format_ok, const std::string& expected_format, int width,
                        int height, int layers, const char* call) {
    if (layers == 1 && shape.type != CL_MEM_OBJECT_IMAGE2D)
        throw input_error(std::string(call) + ": the output image is a 2D image array, expected a 2D image");
    // Texture arrays: one array layer per map.
    if (layers > 1 && (shape.type != CL_MEM_OBJECT_IMAGE2D_ARRAY || shape.layers < static_cast<std::size_t>(layers)))
        throw input_error(std::string(call) + ": the output image has " + std::to_string(shape.layers) +
                          " layers, a texture array of " + std::to_string(layers) +
                          " maps needs a 2D image array of at least that many");
    if (!format_ok)
        throw input_error(std::string(call) + ": the output image has format " + format_text(shape.format) +
                          ", expected " + expected_format);
    if (shape.width < static_cast<std::size_t>(width) || shape.height < static_cast<std::size_t>(height))
        throw input_error(std::string(call) + ": the output image is " + size_text(shape.width, shape.height) +
                          ", smaller than the " + size_text(width, height) + " map");
}

bool is_depth_format(const cl_image_format& format) {
    return (format.image_channel_order == CL_R || format.image_channel_order == CL_DEPTH) &&
           format.image_channel_data_type == CL_FLOAT;
}

// The depth image's shape against its declared width, height, samples and layout.
ImageShape check_depth_image(const DeviceDepthImage& depth, cl_context context, const char* call) {
    if (depth.width <= 0 || depth.height <= 0)
        throw input_error(std::string(call) + ": depth map size " + std::to_string(depth.width) + "x" +
                          std::to_string(depth.height) + " is empty or negative");
    if (!is_supported_sample_count(depth.samples))
        throw input_error(std::string(call) + ": unsupported sample count " + std::to_string(depth.samples) +
                          " (supported: 1, 2, 4, 8, 16)");
    detail::validate_array_layers(call, depth.layers);
    const ImageShape shape = describe_image(depth.image, context, call, "depth image");
    if (!is_depth_format(shape.format))
        throw input_error(std::string(call) + ": the depth image has format " + format_text(shape.format) +
                          ", expected CL_R/CL_FLOAT or CL_DEPTH/CL_FLOAT");
    const std::size_t samples = static_cast<std::size_t>(depth.samples);
    const std::size_t maps = static_cast<std::size_t>(depth.layers);
    if (depth.layout == SampleLayout::side_by_side && maps > 1) {
        // A texture array: one array layer per map.
        if (shape.type != CL_MEM_OBJECT_IMAGE2D_ARRAY || shape.layers < maps)
            throw input_error(std::string(call) + ": a side_by_side depth image of " + std::to_string(maps) +
                              " maps must be a 2D image array of at least that many layers");
    } else if (depth.layout == SampleLayout::side_by_side) {
        if (shape.type != CL_MEM_OBJECT_IMAGE2D)
            throw input_error(std::string(call) + ": a side_by_side depth image must be a 2D image, not an array");
    }
    if (depth.layout == SampleLayout::side_by_side) {
        if (shape.width < depth.width * samples || shape.height < static_cast<std::size_t>(depth.height))
            throw input_error(std::string(call) + ": the depth image is " + size_text(shape.width, shape.height) +
                              ", a " + size_text(depth.width, depth.height) + " map with " +
                              std::to_string(depth.samples) + " samples side by side needs " +
                              size_text(depth.width * samples, depth.height));
    } else {
        if (shape.type != CL_MEM_OBJECT_IMAGE2D_ARRAY)
            throw input_error(std::string(call) + ": a layered depth image must be a 2D image array");
        if (shape.width < static_cast<std::size_t>(depth.width) ||
            shape.height < static_cast<std::size_t>(depth.height) || shape.layers < samples * maps)
            throw input_error(std::string(call) + ": the depth image is " + size_text(shape.width, shape.height) +
                              " with " + std::to_string(shape.layers) + " layers, " + std::to_string(maps) + " " +
                              size_text(depth.width, depth.height) + " map(s) with " + std::to_string(depth.samples) +
                              " samples need as many layers of at least that size");
    }
    return shape;
}

// The raw handles of an event list (null for an empty one, as OpenCL wants).
std::vector<cl_event> raw_events(const std::vector<cl::Event>& events) {
    std::vector<cl_event> raw;
    for (const cl::Event& event : events) raw.push_back(event());
    return raw;
}

cl::Buffer device_only_buffer(detail::ContextImpl& impl, std::size_t bytes, const char* what) {
    cl_int status = CL_SUCCESS;
    cl::Buffer buffer(impl.context, CL_MEM_READ_WRITE | CL_MEM_HOST_NO_ACCESS, bytes, nullptr, &status);
    detail::check(status, (std::string("clCreateBuffer(") + what + ")").c_str());
    return buffer;
}

// A depth image staged into the texel-major float layout of DeviceDepth, on `queue` after
// `waits`; `staged` receives the event of the last command.
DeviceDepth stage_depth_image(detail::ContextImpl& impl, const cl::CommandQueue& queue,
                              const std::vector<cl::Event>& waits, const DeviceDepthImage& depth, cl::Buffer& buffer,
                              cl::Event& staged) {
    const std::size_t texels = static_cast<std::size_t>(depth.width) * depth.height;
    const std::size_t samples = static_cast<std::size_t>(depth.samples);
    // Texture arrays: the maps one after the other, as a layered DeviceDepth holds them.
    const std::size_t maps = static_cast<std::size_t>(depth.layers);
    buffer = device_only_buffer(impl, texels * samples * maps * sizeof(float), "staged depth");
    const std::vector<cl_event> raw_waits = raw_events(waits);
    const cl_event* wait_data = raw_waits.empty() ? nullptr : raw_waits.data();
    if (depth.layout == SampleLayout::side_by_side || samples == 1) {
        // Rows of S * width floats: exactly the DeviceDepth layout.
        const std::size_t columns = depth.layout == SampleLayout::side_by_side ? depth.width * samples : depth.width;
        const cl::array<cl::size_type, 3> origin{0, 0, 0};
        const cl::array<cl::size_type, 3> region{columns, static_cast<std::size_t>(depth.height), maps};
        cl_event event = nullptr;
        detail::check(clEnqueueCopyImageToBuffer(queue(), depth.image, buffer(), origin.data(), region.data(), 0,
                                                 static_cast<cl_uint>(raw_waits.size()), wait_data, &event),
                      "clEnqueueCopyImageToBuffer(depth)");
        staged = cl::Event(event);
        return DeviceDepth{buffer(), depth.width, depth.height, depth.samples, depth.layers};
    }
    // Layers: the S planes into a buffer, then interleaved per texel.
    cl::Buffer planes = device_only_buffer(impl, texels * samples * maps * sizeof(float), "depth planes");
    const cl::array<cl::size_type, 3> origin{0, 0, 0};
    const cl::array<cl::size_type, 3> region{static_cast<std::size_t>(depth.width),
                                             static_cast<std::size_t>(depth.height), samples * maps};
    cl_event copied = nullptr;
    detail::check(clEnqueueCopyImageToBuffer(queue(), depth.image, planes(), origin.data(), region.data(), 0,
                                             static_cast<cl_uint>(raw_waits.size()), wait_data, &copied),
                  "clEnqueueCopyImageToBuffer(depth layers)");
    const std::vector<cl::Event> after_copy{cl::Event(copied)};
    cl::Kernel& interleave = impl.kernel("interop.cl", {}, "depth_interleave_layers");
    detail::set_arg(interleave, 0, planes);
    detail::set_arg(interleave, 1, static_cast<cl_uint>(texels));
    detail::set_arg(interleave, 2, static_cast<cl_uint>(samples));
    detail::set_arg(interleave, 3, buffer);
    // Groups of 64, or fewer where the built kernel allows fewer (docs/devices.md).
    const std::size_t group = detail::fitting_group(detail::kernel_fit(impl, interleave), 64);
    // One row of work-items per map.
    detail::check(queue.enqueueNDRangeKernel(interleave, cl::NullRange,
                                             cl::NDRange((texels + group - 1) / group * group, maps),
                                             cl::NDRange(group, 1), &after_copy, &staged),
                  "clEnqueueNDRangeKernel(depth_interleave_layers)");
    // `planes` is released here; OpenCL keeps it until the kernel is done.
    return DeviceDepth{buffer(), depth.width, depth.height, depth.samples, depth.layers};
}

// Copies width x height texels from a buffer (rows packed) into the top-left of `image`
// after `after`; returns the copy's event.
cl::Event copy_buffer_to_image(const cl::CommandQueue& queue, const cl::Buffer& buffer, cl_mem image, int width,
                               int height, int layers, const cl::Event& after) {
    const cl::array<cl::size_type, 3> origin{0, 0, 0};
    const cl::array<cl::size_type, 3> region{static_cast<std::size_t>(width), static_cast<std::size_t>(height),
                                             static_cast<std::size_t>(layers)};
    cl_event wait = after();
    cl_event event = nullptr;
    detail::check(clEnqueueCopyBufferToImage(queue(), buffer(), image, 0, origin.data(), region.data(), 1, &wait, &event),
                  "clEnqueueCopyBufferToImage");
    return cl::Event(event);
}

// An Enqueue for an inner call: the same queue, waiting for `waits`, reporting into `done`.
Enqueue inner_enqueue(const cl::CommandQueue& queue, const std::vector<cl::Event>& waits, cl_event* done) {
    Enqueue inner;
    inner.queue = queue();
    for (const cl::Event& event : waits) inner.wait_for.push_back(event());
    inner.done = done;
    return inner;
}

// Output image checks of a texture format.
void check_texture_image(detail::ContextImpl& impl, cl_mem image, Format format, int width, int height, int layers,
                         const char* call) {
    const ImageShape shape = describe_image(image, impl.context(), call, "output image");
    std::string expected = format_text(texture_image_format(format));
    if (const cl_channel_type also = detail::texture_kind(format).cl_type_also)
        expected += " or " + format_text(cl_image_format{texture_image_format(format).image_channel_order, also});
    check_output_image(shape, image_format_matches(format, shape.format), expected, width, height, layers, call);
}

void check_sat_image(detail::ContextImpl& impl, cl_mem image, int width, int height, int layers, const char* call) {
    const ImageShape shape = describe_image(image, impl.context(), call, "output image");
    const cl_image_format wanted = sat_image_format();
    const bool format_ok = shape.format.image_channel_order == wanted.image_channel_order &&
                           shape.format.image_channel_data_type == wanted.image_channel_data_type;
    check_output_image(shape, format_ok, format_text(wanted), width, height, layers, call);
}

// The inner operation a call wraps: writes `output` (a buffer) from `depth`, after the
// events of the Enqueue, reporting its last event.
template <class Operation>
void run_into_image(Context& context, const DeviceDepth& depth, cl_mem image, std::size_t texel_bytes,
                    const Enqueue& enqueue, Operation operation) {
    detail::ContextImpl& impl = context.impl();
    const cl::CommandQueue queue = impl.queue_for(enqueue);
    // The texture or table in a staging buffer, then one copy into the image.
    cl::Buffer output = device_only_buffer(
        impl, static_cast<std::size_t>(depth.width) * depth.height * texel_bytes * static_cast<std::size_t>(depth.layers),
        "staged output");
    cl_event computed = nullptr;
    operation(depth, output(), inner_enqueue(queue, detail::wait_list(enqueue), &computed));
    const cl::Event computed_event(computed); // takes the reference the inner call handed over
    const cl::Event copied =
        copy_buffer_to_image(queue, output, image, depth.width, depth.height, depth.layers, computed_event);
    detail::complete(enqueue, queue, copied);
}

template <class Operation>
void run_from_depth_image(Context& context, const DeviceDepthImage& depth, cl_mem output, std::size_t texel_bytes,
                          bool output_is_image, const Enqueue& enqueue, Operation operation) {
    detail::ContextImpl& impl = context.impl();
    const cl::CommandQueue queue = impl.queue_for(enqueue);
    cl::Buffer staged_depth;
    cl::Event staged;
    const DeviceDepth as_buffer = stage_depth_image(impl, queue, detail::wait_list(enqueue), depth, staged_depth, staged);
    Enqueue after_staging;
    after_staging.queue = queue();
    after_staging.wait_for = {staged()};
    after_staging.done = enqueue.done;
    after_staging.blocking = enqueue.blocking;
    if (output_is_image)
        run_into_image(context, as_buffer, output, texel_bytes, after_staging, operation);
    else
        operation(as_buffer, output, after_staging);
}

const auto filter_operation(Context& context, const FilterOptions& options) {
    return [&context, options](const DeviceDepth& depth, cl_mem output, const Enqueue& enqueue) {
        filter(context, depth, output, options, enqueue);
    };
}

const auto sat_operation(Context& context, const SatOptions& options) {
    return [&context, options](const DeviceDepth& depth, cl_mem output, const Enqueue& enqueue) {
        build_sat(context, depth, output, options, enqueue);
    };
}

const std::size_t kSatTexelBytes = detail::gpu_format_info(detail::kSatKind).texel_bytes;

} // namespace

cl_image_format texture_image_format(Format format) noexcept {
    if (!detail::is_known(format)) return cl_image_format{0, 0};
    const detail::TextureKind& kind = detail::texture_kind(format);
    return cl_image_format{kind.cl_order, kind.cl_type};
}

bool image_format_matches(Format format, const cl_image_format& image_format) noexcept {
    if (!detail::is_known(format)) return false;
    const detail::TextureKind& kind = detail::texture_kind(format);
    if (image_format.image_channel_order != kind.cl_order) return false;
    return image_format.image_channel_data_type == kind.cl_type ||
           (kind.cl_type_also != 0 && image_format.image_channel_data_type == kind.cl_type_also);
}

cl_image_format sat_image_format() noexcept {
    const detail::TextureKind& sat = detail::kSatKind;
    return cl_image_format{sat.cl_order, sat.cl_type};
}

void filter_to_image(Context& context, const DeviceDepth& depth, cl_mem image, const FilterOptions& options,
                     const Enqueue& enqueue) {
    detail::validate_array_layers("filter", depth.layers);
    check_texture_image(context.impl(), image, options.format, depth.width, depth.height, depth.layers, "filter");
    run_into_image(context, depth, image, texel_bytes(options.format), enqueue, filter_operation(context, options));
}

void filter_to_image(Context& context, const DeviceDepthImage& depth, cl_mem image, const FilterOptions& options,
                     const Enqueue& enqueue) {
    check_depth_image(depth, context.impl().context(), "filter");
    check_texture_image(context.impl(), image, options.format, depth.width, depth.height, depth.layers, "filter");
    gaussian_taps(options.sigma); // a bad sigma throws before anything is enqueued
    run_from_depth_image(context, depth, image, texel_bytes(options.format), true, enqueue,
                         filter_operation(context, options));
}

void filter(Context& context, const DeviceDepthImage& depth, cl_mem texture, const FilterOptions& options,
            const Enqueue& enqueue) {
    check_depth_image(depth, context.impl().context(), "filter");
    if (!texture) throw input_error("filter: the texture buffer is null");
    gaussian_taps(options.sigma);
    run_from_depth_image(context, depth, texture, texel_bytes(options.format), false, enqueue,
                         filter_operation(context, options));
}

void build_sat_to_image(Context& context, const DeviceDepth& depth, cl_mem image, const SatOptions& options,
                        const Enqueue& enqueue) {
    detail::validate_array_layers("sat", depth.layers);
    check_sat_image(context.impl(), image, depth.width, depth.height, depth.layers, "sat");
    run_into_image(context, depth, image, kSatTexelBytes, enqueue, sat_operation(context, options));
}

void build_sat_to_image(Context& context, const DeviceDepthImage& depth, cl_mem image, const SatOptions& options,
                        const Enqueue& enqueue) {
    check_depth_image(depth, context.impl().context(), "sat");
    check_sat_image(context.impl(), image, depth.width, depth.height, depth.layers, "sat");
    sat_scale(options.max_kernel_texels); // a bad N throws before anything is enqueued
    run_from_depth_image(context, depth, image, kSatTexelBytes, true, enqueue, sat_operation(context, options));
}

void build_sat(Context& context, const DeviceDepthImage& depth, cl_mem table, const SatOptions& options,
               const Enqueue& enqueue) {
    check_depth_image(depth, context.impl().context(), "sat");
    if (!table) throw input_error("sat: the table buffer is null");
    sat_scale(options.max_kernel_texels);
    run_from_depth_image(context, depth, table, kSatTexelBytes, false, enqueue, sat_operation(context, options));
}

void soft_shade(Context& context, const DeviceSatImage& table, cl_mem receivers_uvz, std::size_t count,
                cl_mem intensity, const SoftShadowOptions& options, const Enqueue& enqueue) {
    // What the buffer call refuses, refused before the copy is enqueued.
    if (table.width <= 0 || table.height <= 0)
        throw input_error("soft: the table is empty (" + std::to_string(table.width) + "x" +
                          std::to_string(table.height) + ")");
    soft_shadow_limits(table.max_kernel_texels, options);
    if (!receivers_uvz || !intensity) throw input_error("soft: null cl_mem argument");
    detail::ContextImpl& impl = context.impl();
    const ImageShape shape = describe_image(table.image, impl.context(), "soft", "table image");
    const cl_image_format wanted = sat_image_format();
    if (shape.type != CL_MEM_OBJECT_IMAGE2D)
        throw input_error("soft: the table image is a 2D image array, expected a 2D image");
    if (shape.format.image_channel_order != wanted.image_channel_order ||
        shape.format.image_channel_data_type != wanted.image_channel_data_type)
        throw input_error("soft: the table image has format " + format_text(shape.format) + ", expected " +
                          format_text(wanted));
    if (shape.width < static_cast<std::size_t>(table.width) || shape.height < static_cast<std::size_t>(table.height))
        throw input_error("soft: the table image is " + size_text(shape.width, shape.height) + ", smaller than the " +
                          size_text(table.width, table.height) + " table");
    // The table's texels into a staging buffer after the caller's events.
    const cl::CommandQueue queue = impl.queue_for(enqueue);
    const cl::Buffer staged = device_only_buffer(
        impl, static_cast<std::size_t>(table.width) * table.height * kSatTexelBytes, "staged table");
    const std::vector<cl_event> raw_waits = raw_events(detail::wait_list(enqueue));
    const cl::array<cl::size_type, 3> origin{0, 0, 0};
    const cl::array<cl::size_type, 3> region{static_cast<std::size_t>(table.width),
                                             static_cast<std::size_t>(table.height), 1};
    cl_event copied = nullptr;
    detail::check(clEnqueueCopyImageToBuffer(queue(), table.image, staged(), origin.data(), region.data(), 0,
                                             static_cast<cl_uint>(raw_waits.size()),
                                             raw_waits.empty() ? nullptr : raw_waits.data(), &copied),
                  "clEnqueueCopyImageToBuffer(table)");
    const cl::Event copied_event(copied);
    // Then the buffer call, completing as the caller asked; `staged` lives until it is done.
    Enqueue after_copy;
    after_copy.queue = queue();
    after_copy.wait_for = {copied_event()};
    after_copy.done = enqueue.done;
    after_copy.blocking = enqueue.blocking;
    soft_shade(context, DeviceSat{staged(), table.width, table.height, table.max_kernel_texels}, receivers_uvz, count,
               intensity, options, after_copy);
}

} // namespace msmcl
