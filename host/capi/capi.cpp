// The C API (include/msmcl/msmcl.h) over the C++ one: every entry point catches what the
// C++ call throws and turns it into a status code and a per-thread message.
#include <msmcl/msmcl.h>

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/formats.hpp>
#include <msmcl/interop.hpp>
#include <msmcl/sat.hpp>
#include <msmcl/shade.hpp>
#include <msmcl/version.hpp>

#include <algorithm>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <type_traits>
#include <vector>

struct msmcl_context {
    msmcl::Context context;
    std::string device_name;

    explicit msmcl_context(msmcl::Context&& c) : context(std::move(c)), device_name(context.device().name) {}
};

namespace {

// The last error of this thread.
thread_local std::string last_message;
thread_local cl_int last_opencl_code = CL_SUCCESS;

// A C-level misuse found before the C++ API is called.
struct invalid_argument {
    std::string message;
};

msmcl_status fail(msmcl_status status, std::string message, cl_int opencl_code = CL_SUCCESS) {
    last_message = std::move(message);
    last_opencl_code = opencl_code;
    return status;
}

// Runs `body`, mapping every exception to a status; nothing escapes.
template <class Body>
msmcl_status guarded(Body&& body) noexcept {
    try {
        last_message.clear();
        last_opencl_code = CL_SUCCESS;
        body();
        return MSMCL_SUCCESS;
    } catch (const invalid_argument& e) {
        return fail(MSMCL_ERROR_INVALID_ARGUMENT, e.message);
    } catch (const msmcl::build_error& e) {
        return fail(MSMCL_ERROR_BUILD, std::string(e.what()) + "\n" + e.log(), e.code());
    } catch (const msmcl::opencl_error& e) {
        return fail(MSMCL_ERROR_OPENCL, e.what(), e.code());
    } catch (const msmcl::input_error& e) {
        return fail(MSMCL_ERROR_INPUT, e.what());
    } catch (const msmcl::device_error& e) {
        return fail(MSMCL_ERROR_DEVICE, e.what());
    } catch (const std::bad_alloc&) {
        return fail(MSMCL_ERROR_OUT_OF_MEMORY, "out of host memory");
    } catch (const std::exception& e) {
        return fail(MSMCL_ERROR_INTERNAL, e.what());
    } catch (...) {
        return fail(MSMCL_ERROR_INTERNAL, "unknown exception");
    }
}

template <class T>
void require(const T* pointer, const char* call, const char* name) {
    if (!pointer) throw invalid_argument{std::string(call) + ": " + name + " is NULL"};
}

/// The value a caller stored in a C enum, read as an integer: a value outside the
/// enumerators (any int can arrive from C) must not be loaded as the enum type, which is
/// undefined behaviour in C++.
template <class Enum>
long long enum_value(const Enum& value) {
    static_assert(std::is_enum_v<Enum>);
    // Signed, as C callers see their enums (int).
    std::make_signed_t<std::underlying_type_t<Enum>> raw;
    static_assert(sizeof raw == sizeof value);
    std::memcpy(&raw, &value, sizeof raw);
    return static_cast<long long>(raw);
}

msmcl::Format to_format(const msmcl_format& format, const char* call) {
    switch (enum_value(format)) {
    case MSMCL_FORMAT_MOMENTS128: return msmcl::Format::moments128;
    case MSMCL_FORMAT_MSM64: return msmcl::Format::msm64;
    case MSMCL_FORMAT_NLQ64: return msmcl::Format::nlq64;
    case MSMCL_FORMAT_NLQ32: return msmcl::Format::nlq32;
    }
    throw invalid_argument{std::string(call) + ": unknown format " + std::to_string(enum_value(format))};
}

msmcl::DepthRange to_depth_range(const msmcl_depth_range& range, const char* call) {
    switch (enum_value(range)) {
    case MSMCL_DEPTH_RANGE_ZERO_ONE: return msmcl::DepthRange::zero_one;
    case MSMCL_DEPTH_RANGE_MINUS_ONE_ONE: return msmcl::DepthRange::minus_one_one;
    }
    throw invalid_argument{std::string(call) + ": unknown depth range " + std::to_string(enum_value(range))};
}

msmcl::FilterOptions to_filter_options(const msmcl_filter_options* options, const char* call) {
    msmcl_filter_options c;
    msmcl_filter_options_init(&c);
    if (options) c = *options;
    msmcl::FilterOptions result;
    result.format = to_format(c.format, call);
    result.sigma = c.sigma;
    result.depth_range = to_depth_range(c.depth_range, call);
    switch (enum_value(c.kernel)) {
    case MSMCL_FILTER_KERNEL_AUTOMATIC: result.kernel = msmcl::FilterKernel::automatic; break;
    case MSMCL_FILTER_KERNEL_FUSED_PAPER: result.kernel = msmcl::FilterKernel::fused_paper; break;
    case MSMCL_FILTER_KERNEL_THREE_PASS: result.kernel = msmcl::FilterKernel::three_pass; break;
    case MSMCL_FILTER_KERNEL_FUSED_CPU: result.kernel = msmcl::FilterKernel::fused_cpu; break;
    default:
        throw invalid_argument{std::string(call) + ": unknown filter kernel " + std::to_string(enum_value(c.kernel))};
    }
    return result;
}

msmcl::ShadeOptions to_shade_options(const msmcl_shade_options* options, const char* call) {
    msmcl_shade_options c;
    msmcl_shade_options_init(&c);
    if (options) c = *options;
    msmcl::ShadeOptions result;
    switch (enum_value(c.lookup)) {
    case MSMCL_LOOKUP_NEAREST: result.lookup = msmcl::Lookup::nearest; break;
    case MSMCL_LOOKUP_BILINEAR: result.lookup = msmcl::Lookup::bilinear; break;
    case MSMCL_LOOKUP_DITHER: result.lookup = msmcl::Lookup::dither; break;
    default: throw invalid_argument{std::string(call) + ": unknown lookup " + std::to_string(enum_value(c.lookup))};
    }
    result.depth_bias = c.depth_bias;
    result.depth_range = to_depth_range(c.depth_range, call);
    result.frame = c.frame;
    result.screen_width = c.screen_width;
    return result;
}

msmcl::SoftShadowOptions to_soft_options(const msmcl_soft_options* options, const char* call) {
    msmcl_soft_options c;
    msmcl_soft_options_init(&c);
    if (options) c = *options;
    msmcl::SoftShadowOptions result;
    result.light_size = c.light_size;
    result.search_size = c.search_size;
    result.min_filter_size = c.min_filter_size;
    result.depth_bias = c.depth_bias;
    result.depth_range = to_depth_range(c.depth_range, call);
    result.receiver_blocker_weight = c.receiver_blocker_weight;
    result.filter_parts = c.filter_parts;
    return result;
}

msmcl::SatOptions to_sat_options(const msmcl_sat_options* options, const char* call) {
    msmcl_sat_options c;
    msmcl_sat_options_init(&c);
    if (options) c = *options;
    msmcl::SatOptions result;
    result.max_kernel_texels = c.max_kernel_texels;
    result.depth_range = to_depth_range(c.depth_range, call);
    switch (enum_value(c.kernel)) {
    case MSMCL_SAT_KERNEL_AUTOMATIC: result.kernel = msmcl::SatKernel::automatic; break;
    case MSMCL_SAT_KERNEL_TILED_GPU: result.kernel = msmcl::SatKernel::tiled_gpu; break;
    case MSMCL_SAT_KERNEL_TILED_CPU: result.kernel = msmcl::SatKernel::tiled_cpu; break;
    case MSMCL_SAT_KERNEL_ROW_PER_THREAD: result.kernel = msmcl::SatKernel::row_per_thread; break;
    default:
        throw invalid_argument{std::string(call) + ": unknown SAT kernel " + std::to_string(enum_value(c.kernel))};
    }
    return result;
}

msmcl::Enqueue to_enqueue(const msmcl_enqueue* enqueue, const char* call) {
    msmcl::Enqueue result;
    if (!enqueue) return result;
    if (enqueue->wait_count > 0 && !enqueue->wait_for)
        throw invalid_argument{std::string(call) + ": wait_count is " + std::to_string(enqueue->wait_count) +
                               " but wait_for is NULL"};
    result.queue = enqueue->queue;
    result.wait_for.assign(enqueue->wait_for, enqueue->wait_for + enqueue->wait_count);
    result.done = enqueue->done;
    result.blocking = enqueue->blocking != 0;
    return result;
}

cl_mem_object_type memory_type(cl_mem memory) {
    cl_mem_object_type type = 0;
    const cl_int status = clGetMemObjectInfo(memory, CL_MEM_TYPE, sizeof type, &type, nullptr);
    if (status != CL_SUCCESS) throw msmcl::opencl_error(status, "clGetMemObjectInfo(CL_MEM_TYPE)");
    return type;
}

bool is_buffer(cl_mem memory) { return memory_type(memory) == CL_MEM_OBJECT_BUFFER; }

// `array_layers` maps of one size (texture arrays), 1 for one map.
msmcl::DeviceDepth to_device_depth(const msmcl_device_depth& depth, int array_layers) {
    return msmcl::DeviceDepth{depth.memory, depth.width, depth.height, depth.samples, array_layers};
}

msmcl::DeviceDepthImage to_device_depth_image(const msmcl_device_depth& depth, int array_layers, const char* call) {
    msmcl::DeviceDepthImage image;
    image.image = depth.memory;
    image.width = depth.width;
    image.height = depth.height;
    image.samples = depth.samples;
    image.layers = array_layers;
    switch (enum_value(depth.layout)) {
    case MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE: image.layout = msmcl::SampleLayout::side_by_side; break;
    case MSMCL_SAMPLE_LAYOUT_LAYERS: image.layout = msmcl::SampleLayout::layers; break;
    default:
        throw invalid_argument{std::string(call) + ": unknown sample layout " +
                               std::to_string(enum_value(depth.layout))};
    }
    return image;
}

// Host arrays: width * height * samples values, checked for overflow of the counts.
std::size_t texel_count(int width, int height, const char* call) {
    if (width <= 0 || height <= 0)
        throw msmcl::input_error(std::string(call) + ": size " + std::to_string(width) + "x" + std::to_string(height) +
                                 " is empty or negative");
    return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
}

static_assert(MSMCL_MAX_ARRAY_LAYERS == msmcl::max_array_layers, "msmcl.h and formats.hpp disagree");

// `array_layers` maps of one size, layer after layer (texture arrays).
msmcl::DepthImage to_depth_image(const float* depth, int width, int height, int samples, const char* call,
                                 int array_layers = 1) {
    require(depth, call, "depth");
    const std::size_t texels = texel_count(width, height, call);
    if (!msmcl::is_supported_sample_count(samples))
        throw msmcl::input_error(std::string(call) + ": unsupported sample count " + std::to_string(samples) +
                                 " (supported: 1, 2, 4, 8, 16)");
    // Refuse a bad layer count before copying (the C++ API would, after).
    if (array_layers < 1 || array_layers > msmcl::max_array_layers)
        throw msmcl::input_error(std::string(call) + ": " + std::to_string(array_layers) + " array layers (1 to " +
                                 std::to_string(msmcl::max_array_layers) + ")");
    msmcl::DepthImage image;
    image.width = width;
    image.height = height;
    image.samples = samples;
    image.layers = array_layers;
    image.depth.assign(depth, depth + texels * static_cast<std::size_t>(samples) * static_cast<std::size_t>(array_layers));
    return image;
}

static_assert(MSMCL_MAX_TRANSLUCENT_LAYERS == msmcl::max_translucent_layers, "msmcl.h and filter.hpp disagree");

// Host layers: count arrays of `values` floats each (depth, opacity), copied.
std::vector<msmcl::TranslucentLayer> to_layers(const msmcl_translucent_layer* layers, std::size_t count,
                                               std::size_t values, const char* call) {
    if (count > 0 && !layers)
        throw invalid_argument{std::string(call) + ": layers is NULL but layer_count is " + std::to_string(count)};
    // Refuse too many layers before copying them (the C++ API would, after).
    if (count > static_cast<std::size_t>(msmcl::max_translucent_layers))
        throw msmcl::input_error(std::string(call) + ": " + std::to_string(count) + " translucent layers (at most " +
                                 std::to_string(msmcl::max_translucent_layers) + ")");
    std::vector<msmcl::TranslucentLayer> result(count);
    for (std::size_t k = 0; k < count; ++k) {
        if (!layers[k].depth || !layers[k].opacity)
            throw invalid_argument{std::string(call) + ": layers[" + std::to_string(k) + "]." +
                                   (layers[k].depth ? "opacity" : "depth") + " is NULL"};
        result[k].depth.assign(layers[k].depth, layers[k].depth + values);
        result[k].opacity.assign(layers[k].opacity, layers[k].opacity + values);
    }
    return result;
}

// Device layers: none for NULL; buffers required when count > 0.
msmcl::DeviceLayers to_device_layers(const msmcl_device_layers* layers, const char* call) {
    if (!layers) return {};
    if (layers->count > 0 && (!layers->depth || !layers->opacity))
        throw invalid_argument{std::string(call) + ": layers->" + (layers->depth ? "opacity" : "depth") +
                               " is NULL but layers->count is " + std::to_string(layers->count)};
    return msmcl::DeviceLayers{layers->depth, layers->opacity, layers->count};
}

// Translucent layers on the device go with buffers only (the C++ API has no image overloads).
void require_buffers_for_layers(cl_mem depth, cl_mem output, const char* output_name, const char* call) {
    if (!is_buffer(depth))
        throw msmcl::input_error(std::string(call) + ": translucent layers need the depth in a buffer, not an image");
    if (!is_buffer(output))
        throw msmcl::input_error(std::string(call) + ": translucent layers need the " + output_name +
                                 " in a buffer, not an image");
}

// msmcl_filter and msmcl_filter_layered.
void filter_host(msmcl_context* context, const float* depth, int width, int height, int samples,
                 const msmcl_translucent_layer* layers, std::size_t layer_count, const msmcl_filter_options* options,
                 void* texture, std::size_t texture_bytes, const char* call, int array_layers = 1) {
    require(context, call, "context");
    require(texture, call, "texture");
    const msmcl::FilterOptions filter_options = to_filter_options(options, call);
    const msmcl::DepthImage image = to_depth_image(depth, width, height, samples, call, array_layers);
    const std::size_t needed = image.depth.size() / samples * msmcl::texel_bytes(filter_options.format);
    if (texture_bytes < needed)
        throw invalid_argument{std::string(call) + ": texture_bytes is " + std::to_string(texture_bytes) + ", a " +
                               std::to_string(width) + "x" + std::to_string(height) + " " +
                               msmcl::format_name(filter_options.format) + " texture of " +
                               std::to_string(array_layers) + " layer(s) needs " + std::to_string(needed)};
    const std::vector<msmcl::TranslucentLayer> translucent = to_layers(layers, layer_count, image.depth.size(), call);
    const msmcl::Texture result = msmcl::filter(context->context, image, translucent, filter_options);
    std::memcpy(texture, result.words.data(), needed);
}

// msmcl_filter_device and msmcl_filter_layered_device: buffers or images, as the cl_mem types say.
void filter_device(msmcl_context* context, const msmcl_device_depth* depth, const msmcl_device_layers* layers,
                   cl_mem texture, const msmcl_filter_options* options, const msmcl_enqueue* enqueue,
                   const char* call, int array_layers = 1) {
    require(context, call, "context");
    require(depth, call, "depth");
    if (!depth->memory) throw invalid_argument{std::string(call) + ": depth->memory is NULL"};
    if (!texture) throw invalid_argument{std::string(call) + ": texture is NULL"};
    const msmcl::FilterOptions filter_options = to_filter_options(options, call);
    const msmcl::DeviceLayers device_layers = to_device_layers(layers, call);
    const msmcl::Enqueue plumbing = to_enqueue(enqueue, call);
    const msmcl::DeviceDepth in_buffer = to_device_depth(*depth, array_layers);
    const auto in_image = [&] { return to_device_depth_image(*depth, array_layers, call); };
    // With layers (or a bad count, which the C++ API reports): buffers only.
    if (device_layers.count != 0) {
        require_buffers_for_layers(depth->memory, texture, "texture", call);
        msmcl::filter(context->context, in_buffer, device_layers, texture, filter_options, plumbing);
        return;
    }
    const bool depth_in_buffer = is_buffer(depth->memory);
    const bool texture_in_buffer = is_buffer(texture);
    if (depth_in_buffer && texture_in_buffer)
        msmcl::filter(context->context, in_buffer, texture, filter_options, plumbing);
    else if (depth_in_buffer)
        msmcl::filter_to_image(context->context, in_buffer, texture, filter_options, plumbing);
    else if (texture_in_buffer)
        msmcl::filter(context->context, in_image(), texture, filter_options, plumbing);
    else
        msmcl::filter_to_image(context->context, in_image(), texture, filter_options, plumbing);
}

// Host receivers of msmcl_shade* and msmcl_soft_shade: u, v, z and the output checked
// (non-NULL) when there is any receiver.
msmcl::Receivers to_receivers(const float* u, const float* v, const float* z, std::size_t count,
                              const float* intensity, const char* call) {
    msmcl::Receivers receivers;
    if (count == 0) return receivers;
    require(u, call, "u");
    require(v, call, "v");
    require(z, call, "z");
    require(intensity, call, "intensity");
    receivers.u.assign(u, u + count);
    receivers.v.assign(v, v + count);
    receivers.z.assign(z, z + count);
    return receivers;
}

// msmcl_shade and msmcl_shade_with_pixels.
void shade_host(msmcl_context* context, const msmcl_format& format, int width, int height, const void* texture,
                std::size_t texture_bytes, const float* u, const float* v, const float* z, const uint32_t* pixel_x,
                const uint32_t* pixel_y, std::size_t count, const msmcl_shade_options* options, float* intensity,
                const char* call) {
    require(context, call, "context");
    require(texture, call, "texture");
    if (!pixel_x != !pixel_y)
        throw invalid_argument{std::string(call) + ": pixel_" + (pixel_x ? "y" : "x") + " is NULL but pixel_" +
                               (pixel_x ? "x" : "y") + " is not"};
    const msmcl::ShadeOptions shade_options = to_shade_options(options, call);
    msmcl::Texture map;
    map.format = to_format(format, call);
    map.width = width;
    map.height = height;
    const std::size_t needed = texel_count(width, height, call) * msmcl::texel_bytes(map.format);
    if (texture_bytes < needed)
        throw invalid_argument{std::string(call) + ": texture_bytes is " + std::to_string(texture_bytes) + ", a " +
                               std::to_string(width) + "x" + std::to_string(height) + " " +
                               msmcl::format_name(map.format) + " texture needs " + std::to_string(needed)};
    map.words.resize(needed / sizeof(std::uint32_t));
    std::memcpy(map.words.data(), texture, needed);
    const msmcl::Receivers receivers = to_receivers(u, v, z, count, intensity, call);
    msmcl::ReceiverPixels pixels;
    if (count > 0 && pixel_x) {
        pixels.x.assign(pixel_x, pixel_x + count);
        pixels.y.assign(pixel_y, pixel_y + count);
    }
    const std::vector<float> result = msmcl::shade(context->context, map, receivers, pixels, shade_options);
    if (count > 0) std::memcpy(intensity, result.data(), count * sizeof(float));
}

// msmcl_build_sat and msmcl_build_sat_layered.
void build_sat_host(msmcl_context* context, const float* depth, int width, int height, int samples,
                    const msmcl_translucent_layer* layers, std::size_t layer_count, const msmcl_sat_options* options,
                    uint32_t* table, std::size_t table_words, const char* call, int array_layers = 1) {
    require(context, call, "context");
    require(table, call, "table");
    const msmcl::SatOptions sat_options = to_sat_options(options, call);
    const msmcl::DepthImage image = to_depth_image(depth, width, height, samples, call, array_layers);
    const std::size_t needed = 4 * (image.depth.size() / samples);
    if (table_words < needed)
        throw invalid_argument{std::string(call) + ": table_words is " + std::to_string(table_words) + ", a " +
                               std::to_string(width) + "x" + std::to_string(height) + " table of " +
                               std::to_string(array_layers) + " layer(s) needs " + std::to_string(needed)};
    const std::vector<msmcl::TranslucentLayer> translucent = to_layers(layers, layer_count, image.depth.size(), call);
    const msmcl::SatTable result = msmcl::build_sat(context->context, image, translucent, sat_options);
    std::memcpy(table, result.words.data(), needed * sizeof(std::uint32_t));
}

// msmcl_build_sat_device and msmcl_build_sat_layered_device.
void build_sat_device(msmcl_context* context, const msmcl_device_depth* depth, const msmcl_device_layers* layers,
                      cl_mem table, const msmcl_sat_options* options, const msmcl_enqueue* enqueue, const char* call,
                      int array_layers = 1) {
    require(context, call, "context");
    require(depth, call, "depth");
    if (!depth->memory) throw invalid_argument{std::string(call) + ": depth->memory is NULL"};
    if (!table) throw invalid_argument{std::string(call) + ": table is NULL"};
    const msmcl::SatOptions sat_options = to_sat_options(options, call);
    const msmcl::DeviceLayers device_layers = to_device_layers(layers, call);
    const msmcl::Enqueue plumbing = to_enqueue(enqueue, call);
    const msmcl::DeviceDepth in_buffer = to_device_depth(*depth, array_layers);
    const auto in_image = [&] { return to_device_depth_image(*depth, array_layers, call); };
    // With layers (or a bad count, which the C++ API reports): buffers only.
    if (device_layers.count != 0) {
        require_buffers_for_layers(depth->memory, table, "table", call);
        msmcl::build_sat(context->context, in_buffer, device_layers, table, sat_options, plumbing);
        return;
    }
    const bool depth_in_buffer = is_buffer(depth->memory);
    const bool table_in_buffer = is_buffer(table);
    if (depth_in_buffer && table_in_buffer)
        msmcl::build_sat(context->context, in_buffer, table, sat_options, plumbing);
    else if (depth_in_buffer)
        msmcl::build_sat_to_image(context->context, in_buffer, table, sat_options, plumbing);
    else if (table_in_buffer)
        msmcl::build_sat(context->context, in_image(), table, sat_options, plumbing);
    else
        msmcl::build_sat_to_image(context->context, in_image(), table, sat_options, plumbing);
}

} // namespace

extern "C" {

const char* msmcl_status_name(msmcl_status status) {
    switch (enum_value(status)) {
    case MSMCL_SUCCESS: return "MSMCL_SUCCESS";
    case MSMCL_ERROR_INVALID_ARGUMENT: return "MSMCL_ERROR_INVALID_ARGUMENT";
    case MSMCL_ERROR_INPUT: return "MSMCL_ERROR_INPUT";
    case MSMCL_ERROR_OPENCL: return "MSMCL_ERROR_OPENCL";
    case MSMCL_ERROR_BUILD: return "MSMCL_ERROR_BUILD";
    case MSMCL_ERROR_DEVICE: return "MSMCL_ERROR_DEVICE";
    case MSMCL_ERROR_OUT_OF_MEMORY: return "MSMCL_ERROR_OUT_OF_MEMORY";
    case MSMCL_ERROR_INTERNAL: return "MSMCL_ERROR_INTERNAL";
    }
    return "MSMCL_UNKNOWN_STATUS";
}

const char* msmcl_last_error_message(void) { return last_message.c_str(); }

cl_int msmcl_last_opencl_error(void) { return last_opencl_code; }

const char* msmcl_version_string(void) { return msmcl::version_string; }

void msmcl_version(int* major, int* minor, int* patch) {
    if (major) *major = msmcl::version_major;
    if (minor) *minor = msmcl::version_minor;
    if (patch) *patch = msmcl::version_patch;
}

size_t msmcl_texel_bytes(msmcl_format format) {
    switch (enum_value(format)) {
    case MSMCL_FORMAT_MOMENTS128:
    case MSMCL_FORMAT_MSM64:
    case MSMCL_FORMAT_NLQ64:
    case MSMCL_FORMAT_NLQ32: return msmcl::texel_bytes(static_cast<msmcl::Format>(enum_value(format)));
    }
    return 0;
}

const char* msmcl_format_name(msmcl_format format) {
    // The value is looked at as an integer only (see enum_value).
    switch (enum_value(format)) {
    case MSMCL_FORMAT_MOMENTS128:
    case MSMCL_FORMAT_MSM64:
    case MSMCL_FORMAT_NLQ64:
    case MSMCL_FORMAT_NLQ32: return msmcl::format_name(static_cast<msmcl::Format>(enum_value(format)));
    }
    return nullptr;
}

msmcl_status msmcl_parse_format(const char* name, msmcl_format* format) {
    return guarded([&] {
        require(name, "msmcl_parse_format", "name");
        require(format, "msmcl_parse_format", "format");
        const auto parsed = msmcl::parse_format(name);
        if (!parsed) throw invalid_argument{std::string("msmcl_parse_format: unknown format '") + name + "'"};
        *format = static_cast<msmcl_format>(*parsed);
    });
}

msmcl_status msmcl_texture_image_format(msmcl_format format, cl_image_format* image_format) {
    return guarded([&] {
        require(image_format, "msmcl_texture_image_format", "image_format");
        *image_format = msmcl::texture_image_format(to_format(format, "msmcl_texture_image_format"));
    });
}

cl_image_format msmcl_sat_image_format(void) { return msmcl::sat_image_format(); }

void msmcl_context_options_init(msmcl_context_options* options) {
    if (!options) return;
    options->device = nullptr;
    options->platform = nullptr;
    options->strict = 0;
    options->use_environment = 1;
}

msmcl_status msmcl_context_create(const msmcl_context_options* options, msmcl_context** context) {
    return guarded([&] {
        require(context, "msmcl_context_create", "context");
        *context = nullptr;
        msmcl_context_options c;
        msmcl_context_options_init(&c);
        if (options) c = *options;
        msmcl::DeviceSelection selection;
        if (c.device) selection.device = c.device;
        if (c.platform) selection.platform = c.platform;
        selection.strict = c.strict != 0;
        selection.use_environment = c.use_environment != 0;
        *context = new msmcl_context(msmcl::Context(selection));
    });
}

msmcl_status msmcl_context_create_from_cl(cl_context opencl_context, cl_device_id device, cl_command_queue queue,
                                          msmcl_context** context) {
    return guarded([&] {
        require(context, "msmcl_context_create_from_cl", "context");
        *context = nullptr;
        if (!opencl_context || !device)
            throw invalid_argument{"msmcl_context_create_from_cl: cl_context or cl_device_id is NULL"};
        *context = new msmcl_context(msmcl::Context(opencl_context, device, queue));
    });
}

void msmcl_context_destroy(msmcl_context* context) { delete context; }

cl_context msmcl_context_cl_context(const msmcl_context* context) {
    return context ? context->context.cl_context_handle() : nullptr;
}

cl_device_id msmcl_context_cl_device(const msmcl_context* context) {
    return context ? context->context.cl_device_handle() : nullptr;
}

cl_command_queue msmcl_context_cl_queue(const msmcl_context* context) {
    return context ? context->context.cl_queue_handle() : nullptr;
}

const char* msmcl_context_device_name(const msmcl_context* context) {
    return context ? context->device_name.c_str() : "";
}

msmcl_status msmcl_context_finish(msmcl_context* context) {
    return guarded([&] {
        require(context, "msmcl_context_finish", "context");
        context->context.finish();
    });
}

msmcl_status msmcl_context_set_binary_cache_dir(msmcl_context* context, const char* directory) {
    return guarded([&] {
        require(context, "msmcl_context_set_binary_cache_dir", "context");
        context->context.set_binary_cache_dir(directory ? directory : "");
    });
}

size_t msmcl_context_programs_built(const msmcl_context* context) {
    return context ? context->context.programs_built() : 0;
}

void msmcl_filter_options_init(msmcl_filter_options* options) {
    if (!options) return;
    const msmcl::FilterOptions defaults;
    options->format = static_cast<msmcl_format>(defaults.format);
    options->sigma = defaults.sigma;
    options->depth_range = static_cast<msmcl_depth_range>(defaults.depth_range);
    options->kernel = MSMCL_FILTER_KERNEL_AUTOMATIC;
}

msmcl_status msmcl_filter(msmcl_context* context, const float* depth, int width, int height, int samples,
                          const msmcl_filter_options* options, void* texture, size_t texture_bytes) {
    return guarded([&] {
        filter_host(context, depth, width, height, samples, nullptr, 0, options, texture, texture_bytes,
                    "msmcl_filter");
    });
}

msmcl_status msmcl_filter_layered(msmcl_context* context, const float* depth, int width, int height, int samples,
                                  const msmcl_translucent_layer* layers, size_t layer_count,
                                  const msmcl_filter_options* options, void* texture, size_t texture_bytes) {
    return guarded([&] {
        filter_host(context, depth, width, height, samples, layers, layer_count, options, texture, texture_bytes,
                    "msmcl_filter_layered");
    });
}

msmcl_status msmcl_filter_device(msmcl_context* context, const msmcl_device_depth* depth, cl_mem texture,
                                 const msmcl_filter_options* options, const msmcl_enqueue* enqueue) {
    return guarded([&] { filter_device(context, depth, nullptr, texture, options, enqueue, "msmcl_filter_device"); });
}

msmcl_status msmcl_filter_layered_device(msmcl_context* context, const msmcl_device_depth* depth,
                                         const msmcl_device_layers* layers, cl_mem texture,
                                         const msmcl_filter_options* options, const msmcl_enqueue* enqueue) {
    return guarded(
        [&] { filter_device(context, depth, layers, texture, options, enqueue, "msmcl_filter_layered_device"); });
}

void msmcl_shade_options_init(msmcl_shade_options* options) {
    if (!options) return;
    const msmcl::ShadeOptions defaults;
    options->lookup = static_cast<msmcl_lookup>(defaults.lookup);
    options->depth_bias = defaults.depth_bias;
    options->depth_range = static_cast<msmcl_depth_range>(defaults.depth_range);
    options->frame = defaults.frame;
    options->screen_width = defaults.screen_width;
}

msmcl_status msmcl_shade(msmcl_context* context, msmcl_format format, int width, int height, const void* texture,
                         size_t texture_bytes, const float* u, const float* v, const float* z, size_t count,
                         const msmcl_shade_options* options, float* intensity) {
    return guarded([&] {
        shade_host(context, format, width, height, texture, texture_bytes, u, v, z, nullptr, nullptr, count, options,
                   intensity, "msmcl_shade");
    });
}

msmcl_status msmcl_shade_with_pixels(msmcl_context* context, msmcl_format format, int width, int height,
                                     const void* texture, size_t texture_bytes, const float* u, const float* v,
                                     const float* z, const uint32_t* pixel_x, const uint32_t* pixel_y, size_t count,
                                     const msmcl_shade_options* options, float* intensity) {
    return guarded([&] {
        shade_host(context, format, width, height, texture, texture_bytes, u, v, z, pixel_x, pixel_y, count, options,
                   intensity, "msmcl_shade_with_pixels");
    });
}

msmcl_status msmcl_shade_device(msmcl_context* context, msmcl_format format, int width, int height, cl_mem texture,
                                cl_mem receivers_uvz, size_t count, cl_mem intensity,
                                const msmcl_shade_options* options, const msmcl_enqueue* enqueue) {
    return guarded([&] {
        const char* call = "msmcl_shade_device";
        require(context, call, "context");
        const msmcl::ShadeOptions shade_options = to_shade_options(options, call);
        const msmcl::DeviceTexture map{texture, to_format(format, call), width, height};
        msmcl::shade(context->context, map, receivers_uvz, count, intensity, shade_options, to_enqueue(enqueue, call));
    });
}

msmcl_status msmcl_shade_with_pixels_device(msmcl_context* context, msmcl_format format, int width, int height,
                                            cl_mem texture, cl_mem receivers_uvz, cl_mem receiver_pixels, size_t count,
                                            cl_mem intensity, const msmcl_shade_options* options,
                                            const msmcl_enqueue* enqueue) {
    return guarded([&] {
        const char* call = "msmcl_shade_with_pixels_device";
        require(context, call, "context");
        const msmcl::ShadeOptions shade_options = to_shade_options(options, call);
        const msmcl::DeviceTexture map{texture, to_format(format, call), width, height};
        msmcl::shade(context->context, map, receivers_uvz, receiver_pixels, count, intensity, shade_options,
                     to_enqueue(enqueue, call));
    });
}

void msmcl_sat_options_init(msmcl_sat_options* options) {
    if (!options) return;
    const msmcl::SatOptions defaults;
    options->max_kernel_texels = defaults.max_kernel_texels;
    options->depth_range = static_cast<msmcl_depth_range>(defaults.depth_range);
    options->kernel = MSMCL_SAT_KERNEL_AUTOMATIC;
}

msmcl_status msmcl_sat_scale(uint32_t max_kernel_texels, uint32_t* scale) {
    return guarded([&] {
        require(scale, "msmcl_sat_scale", "scale");
        *scale = msmcl::sat_scale(max_kernel_texels);
    });
}

msmcl_status msmcl_build_sat(msmcl_context* context, const float* depth, int width, int height, int samples,
                             const msmcl_sat_options* options, uint32_t* table, size_t table_words) {
    return guarded([&] {
        build_sat_host(context, depth, width, height, samples, nullptr, 0, options, table, table_words,
                       "msmcl_build_sat");
    });
}

msmcl_status msmcl_build_sat_layered(msmcl_context* context, const float* depth, int width, int height, int samples,
                                     const msmcl_translucent_layer* layers, size_t layer_count,
                                     const msmcl_sat_options* options, uint32_t* table, size_t table_words) {
    return guarded([&] {
        build_sat_host(context, depth, width, height, samples, layers, layer_count, options, table, table_words,
                       "msmcl_build_sat_layered");
    });
}

msmcl_status msmcl_build_sat_device(msmcl_context* context, const msmcl_device_depth* depth, cl_mem table,
                                    const msmcl_sat_options* options, const msmcl_enqueue* enqueue) {
    return guarded(
        [&] { build_sat_device(context, depth, nullptr, table, options, enqueue, "msmcl_build_sat_device"); });
}

msmcl_status msmcl_build_sat_layered_device(msmcl_context* context, const msmcl_device_depth* depth,
                                            const msmcl_device_layers* layers, cl_mem table,
                                            const msmcl_sat_options* options, const msmcl_enqueue* enqueue) {
    return guarded(
        [&] { build_sat_device(context, depth, layers, table, options, enqueue, "msmcl_build_sat_layered_device"); });
}

void msmcl_soft_options_init(msmcl_soft_options* options) {
    if (!options) return;
    const msmcl::SoftShadowOptions defaults;
    options->light_size = defaults.light_size;
    options->search_size = defaults.search_size;
    options->min_filter_size = defaults.min_filter_size;
    options->depth_bias = defaults.depth_bias;
    options->depth_range = static_cast<msmcl_depth_range>(defaults.depth_range);
    options->receiver_blocker_weight = defaults.receiver_blocker_weight;
    options->filter_parts = defaults.filter_parts;
}

msmcl_status msmcl_soft_shade(msmcl_context* context, const uint32_t* table, int width, int height,
                              uint32_t max_kernel_texels, const float* u, const float* v, const float* z, size_t count,
                              const msmcl_soft_options* options, float* intensity) {
    return guarded([&] {
        const char* call = "msmcl_soft_shade";
        require(context, call, "context");
        require(table, call, "table");
        const msmcl::SoftShadowOptions soft_options = to_soft_options(options, call);
        // The table: its words copied, its scale the one of N (the library checks N).
        msmcl::SatTable sat;
        sat.width = width;
        sat.height = height;
        sat.max_kernel_texels = max_kernel_texels;
        sat.scale = msmcl::sat_scale(max_kernel_texels);
        sat.words.assign(table, table + 4 * texel_count(width, height, call));
        const msmcl::Receivers receivers = to_receivers(u, v, z, count, intensity, call);
        const std::vector<float> result = msmcl::soft_shade(context->context, sat, receivers, soft_options);
        std::copy(result.begin(), result.end(), intensity);
    });
}

msmcl_status msmcl_filter_array(msmcl_context* context, const float* depth, int width, int height, int samples,
                                int layers, const msmcl_filter_options* options, void* texture, size_t texture_bytes) {
    return guarded([&] {
        filter_host(context, depth, width, height, samples, nullptr, 0, options, texture, texture_bytes,
                    "msmcl_filter_array", layers);
    });
}

msmcl_status msmcl_filter_array_device(msmcl_context* context, const msmcl_device_depth* depth, int layers,
                                       cl_mem texture, const msmcl_filter_options* options,
                                       const msmcl_enqueue* enqueue) {
    return guarded([&] {
        filter_device(context, depth, nullptr, texture, options, enqueue, "msmcl_filter_array_device", layers);
    });
}

msmcl_status msmcl_build_sat_array(msmcl_context* context, const float* depth, int width, int height, int samples,
                                   int layers, const msmcl_sat_options* options, uint32_t* table, size_t table_words) {
    return guarded([&] {
        build_sat_host(context, depth, width, height, samples, nullptr, 0, options, table, table_words,
                       "msmcl_build_sat_array", layers);
    });
}

msmcl_status msmcl_build_sat_array_device(msmcl_context* context, const msmcl_device_depth* depth, int layers,
                                          cl_mem table, const msmcl_sat_options* options,
                                          const msmcl_enqueue* enqueue) {
    return guarded([&] {
        build_sat_device(context, depth, nullptr, table, options, enqueue, "msmcl_build_sat_array_device", layers);
    });
}

} // extern "C"
