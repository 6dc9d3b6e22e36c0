// The C API (include/msmcl/msmcl.h) over the C++ one: every entry point catches what the
// C++ call throws and turns it into a status code and a per-thread message.
#include <msmcl/msmcl.h>

#include "runtime/texture_kinds.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/formats.hpp>
#include <msmcl/interop.hpp>
#include <msmcl/sat.hpp>
#include <msmcl/scatter.hpp>
#include <msmcl/shade.hpp>
#include <msmcl/version.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <new>
#include <optional>
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

// The C values are the C++ ones.
static_assert(MSMCL_FORMAT_MOMENTS128 == static_cast<int>(msmcl::Format::moments128) &&
                  MSMCL_FORMAT_MSM64 == static_cast<int>(msmcl::Format::msm64) &&
                  MSMCL_FORMAT_NLQ64 == static_cast<int>(msmcl::Format::nlq64) &&
                  MSMCL_FORMAT_NLQ32 == static_cast<int>(msmcl::Format::nlq32) &&
                  MSMCL_FORMAT_VSM32 == static_cast<int>(msmcl::Format::vsm32) &&
                  MSMCL_FORMAT_VSM64 == static_cast<int>(msmcl::Format::vsm64) &&
                  MSMCL_FORMAT_EVSM2_32 == static_cast<int>(msmcl::Format::evsm2_32) &&
                  MSMCL_FORMAT_EVSM4_64 == static_cast<int>(msmcl::Format::evsm4_64) &&
                  MSMCL_FORMAT_EVSM4_128 == static_cast<int>(msmcl::Format::evsm4_128) &&
                  MSMCL_FORMAT_ESM32 == static_cast<int>(msmcl::Format::esm32),
              "msmcl.h and formats.hpp disagree");

// The format of a C value, if it is one of the format table's.
std::optional<msmcl::Format> known_format(const msmcl_format& format) {
    const long long value = enum_value(format);
    if (value < 0 || static_cast<unsigned long long>(value) >= msmcl::detail::kFilterFormats) return std::nullopt;
    return static_cast<msmcl::Format>(value);
}

msmcl::Format to_format(const msmcl_format& format, const char* call) {
    if (const std::optional<msmcl::Format> known = known_format(format)) return *known;
    throw invalid_argument{std::string(call) + ": unknown format " + std::to_string(enum_value(format))};
}

msmcl::DepthRange to_depth_range(const msmcl_depth_range& range, const char* call) {
    switch (enum_value(range)) {
    case MSMCL_DEPTH_RANGE_ZERO_ONE: return msmcl::DepthRange::zero_one;
    case MSMCL_DEPTH_RANGE_MINUS_ONE_ONE: return msmcl::DepthRange::minus_one_one;
    }
    throw invalid_argument{std::string(call) + ": unknown depth range " + std::to_string(enum_value(range))};
}

msmcl::FilterKernel to_filter_kernel(const msmcl_filter_kernel& kernel, const char* call) {
    switch (enum_value(kernel)) {
    case MSMCL_FILTER_KERNEL_AUTOMATIC: return msmcl::FilterKernel::automatic;
    case MSMCL_FILTER_KERNEL_FUSED_PAPER: return msmcl::FilterKernel::fused_paper;
    case MSMCL_FILTER_KERNEL_THREE_PASS: return msmcl::FilterKernel::three_pass;
    case MSMCL_FILTER_KERNEL_FUSED_CPU: return msmcl::FilterKernel::fused_cpu;
    }
    throw invalid_argument{std::string(call) + ": unknown filter kernel " + std::to_string(enum_value(kernel))};
}

msmcl::FilterOptions to_filter_options(const msmcl_filter_options* options, const char* call) {
    msmcl_filter_options c;
    msmcl_filter_options_init(&c);
    if (options) c = *options;
    msmcl::FilterOptions result;
    result.format = to_format(c.format, call);
    result.sigma = c.sigma;
    result.depth_range = to_depth_range(c.depth_range, call);
    result.kernel = to_filter_kernel(c.kernel, call);
    result.exponents = {c.exponent_positive, c.exponent_negative};
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
    if (c.min_variance >= 0.0f || std::isnan(c.min_variance)) result.min_variance = c.min_variance;
    result.light_bleed_reduction = c.light_bleed_reduction;
    return result;
}

// The exponents a shaded texture was made with (msmcl_shade_options; 0: the format's default).
msmcl::WarpExponents to_shade_exponents(const msmcl_shade_options* options) {
    msmcl_shade_options c;
    msmcl_shade_options_init(&c);
    if (options) c = *options;
    return {c.exponent_positive, c.exponent_negative};
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
    map.exponents = to_shade_exponents(options);
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

// A C 3-vector as msmcl::Vector3.
msmcl::Vector3 to_vector(const double (&v)[3]) { return {v[0], v[1], v[2]}; }

msmcl::ScatterScene to_scatter_scene(const msmcl_scatter_scene* scene, const char* call) {
    require(scene, call, "scene");
    msmcl::ScatterScene result;
    const msmcl_scatter_light& light = scene->light;
    result.light.direction = to_vector(light.direction);
    result.light.up = to_vector(light.up);
    result.light.center = to_vector(light.center);
    result.light.width = light.width;
    result.light.height = light.height;
    result.light.near = light.near_plane;
    result.light.far = light.far_plane;
    result.light.depth_range = to_depth_range(light.depth_range, call);
    const msmcl_scatter_camera& camera = scene->camera;
    result.camera.position = to_vector(camera.position);
    result.camera.forward = to_vector(camera.forward);
    result.camera.up = to_vector(camera.up);
    result.camera.vertical_fov_degrees = camera.vertical_fov_degrees;
    result.camera.near = camera.near_plane;
    result.camera.far = camera.far_plane;
    result.camera.width = camera.width;
    result.camera.height = camera.height;
    switch (enum_value(camera.depth)) {
    case MSMCL_CAMERA_DEPTH_ZERO_ONE: result.camera.depth = msmcl::CameraDepth::zero_one; break;
    case MSMCL_CAMERA_DEPTH_MINUS_ONE_ONE: result.camera.depth = msmcl::CameraDepth::minus_one_one; break;
    case MSMCL_CAMERA_DEPTH_LINEAR: result.camera.depth = msmcl::CameraDepth::linear; break;
    default:
        throw invalid_argument{std::string(call) + ": unknown camera depth " + std::to_string(enum_value(camera.depth))};
    }
    result.medium.extinction = scene->medium.extinction;
    result.medium.phase_g = scene->medium.phase_g;
    result.medium.irradiance = scene->medium.irradiance;
    result.rectified_width = scene->rectified_width;
    result.rectified_height = scene->rectified_height;
    result.guard_band = scene->guard_band;
    return result;
}

msmcl::ScatterOptions to_scatter_options(const msmcl_scatter_options* options, const char* call) {
    msmcl_scatter_options c;
    msmcl_scatter_options_init(&c);
    if (options) c = *options;
    msmcl::ScatterOptions result;
    result.moments = c.moments;
    result.filtered = c.filtered != 0;
    result.filter_sigma = c.filter_sigma;
    result.beta = c.beta;
    switch (enum_value(c.kernel)) {
    case MSMCL_SCATTER_KERNEL_AUTOMATIC: result.kernel = msmcl::ScatterKernel::automatic; break;
    case MSMCL_SCATTER_KERNEL_ROWS_GPU: result.kernel = msmcl::ScatterKernel::rows_gpu; break;
    case MSMCL_SCATTER_KERNEL_ROWS_CPU: result.kernel = msmcl::ScatterKernel::rows_cpu; break;
    default:
        throw invalid_argument{std::string(call) + ": unknown scatter kernel " + std::to_string(enum_value(c.kernel))};
    }
    result.filter_kernel = to_filter_kernel(c.filter_kernel, call);
    return result;
}

// The camera depth of a scene's camera, copied (the scene validated first: its size is read).
std::vector<float> to_camera_depth(const msmcl::ScatterScene& scene, const float* camera_depth, const char* call) {
    require(camera_depth, call, "camera_depth");
    msmcl::validate_scatter_scene(scene);
    const std::size_t pixels = static_cast<std::size_t>(scene.camera.width) * scene.camera.height;
    return std::vector<float>(camera_depth, camera_depth + pixels);
}

// Bytes of a scene's prefiltered map, checked against what the caller holds.
std::size_t require_map_bytes(const msmcl::ScatterScene& scene, std::size_t map_bytes, const char* call) {
    msmcl::validate_scatter_scene(scene);
    const std::size_t needed = msmcl::scatter_map_bytes(scene);
    if (map_bytes < needed)
        throw invalid_argument{std::string(call) + ": map_bytes is " + std::to_string(map_bytes) + ", a " +
                               std::to_string(scene.rectified_width) + "x" + std::to_string(scene.rectified_height) +
                               " prefiltered map needs " + std::to_string(needed)};
    return needed;
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
    const std::optional<msmcl::Format> known = known_format(format);
    return known ? msmcl::texel_bytes(*known) : 0;
}

const char* msmcl_format_name(msmcl_format format) {
    // The value is looked at as an integer only (see enum_value).
    const std::optional<msmcl::Format> known = known_format(format);
    return known ? msmcl::format_name(*known) : nullptr;
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
    options->exponent_positive = defaults.exponents.positive;
    options->exponent_negative = defaults.exponents.negative;
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
    options->min_variance = -1.0f;
    options->light_bleed_reduction = defaults.light_bleed_reduction;
    options->exponent_positive = 0.0f;
    options->exponent_negative = 0.0f;
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
        const msmcl::DeviceTexture map{texture, to_format(format, call), width, height, to_shade_exponents(options)};
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
        const msmcl::DeviceTexture map{texture, to_format(format, call), width, height, to_shade_exponents(options)};
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

msmcl_status msmcl_soft_shade_device(msmcl_context* context, cl_mem table, int width, int height,
                                     uint32_t max_kernel_texels, cl_mem receivers_uvz, size_t count, cl_mem intensity,
                                     const msmcl_soft_options* options, const msmcl_enqueue* enqueue) {
    return guarded([&] {
        const char* call = "msmcl_soft_shade_device";
        require(context, call, "context");
        if (!table || !receivers_uvz || !intensity)
            throw invalid_argument{std::string(call) + ": " +
                                   (!table ? "table" : !receivers_uvz ? "receivers_uvz" : "intensity") + " is NULL"};
        const msmcl::SoftShadowOptions soft_options = to_soft_options(options, call);
        const msmcl::Enqueue plumbing = to_enqueue(enqueue, call);
        // A buffer, or an image the C++ API stages into one.
        if (is_buffer(table))
            msmcl::soft_shade(context->context, msmcl::DeviceSat{table, width, height, max_kernel_texels},
                              receivers_uvz, count, intensity, soft_options, plumbing);
        else
            msmcl::soft_shade(context->context, msmcl::DeviceSatImage{table, width, height, max_kernel_texels},
                              receivers_uvz, count, intensity, soft_options, plumbing);
    });
}

msmcl_status msmcl_filter_array_layered(msmcl_context* context, const float* depth, int width, int height, int samples,
                                        int layers, const msmcl_translucent_layer* translucent, size_t layer_count,
                                        const msmcl_filter_options* options, void* texture, size_t texture_bytes) {
    return guarded([&] {
        filter_host(context, depth, width, height, samples, translucent, layer_count, options, texture, texture_bytes,
                    "msmcl_filter_array_layered", layers);
    });
}

msmcl_status msmcl_filter_array_layered_device(msmcl_context* context, const msmcl_device_depth* depth, int layers,
                                               const msmcl_device_layers* translucent, cl_mem texture,
                                               const msmcl_filter_options* options, const msmcl_enqueue* enqueue) {
    return guarded([&] {
        filter_device(context, depth, translucent, texture, options, enqueue, "msmcl_filter_array_layered_device",
                      layers);
    });
}

msmcl_status msmcl_build_sat_array_layered(msmcl_context* context, const float* depth, int width, int height,
                                           int samples, int layers, const msmcl_translucent_layer* translucent,
                                           size_t layer_count, const msmcl_sat_options* options, uint32_t* table,
                                           size_t table_words) {
    return guarded([&] {
        build_sat_host(context, depth, width, height, samples, translucent, layer_count, options, table, table_words,
                       "msmcl_build_sat_array_layered", layers);
    });
}

msmcl_status msmcl_build_sat_array_layered_device(msmcl_context* context, const msmcl_device_depth* depth, int layers,
                                                  const msmcl_device_layers* translucent, cl_mem table,
                                                  const msmcl_sat_options* options, const msmcl_enqueue* enqueue) {
    return guarded([&] {
        build_sat_device(context, depth, translucent, table, options, enqueue, "msmcl_build_sat_array_layered_device",
                         layers);
    });
}

void msmcl_scatter_scene_init(msmcl_scatter_scene* scene) {
    if (!scene) return;
    const msmcl::ScatterScene defaults;
    const auto copy = [](const msmcl::Vector3& from, double (&to)[3]) { std::copy(from.begin(), from.end(), to); };
    copy(defaults.light.direction, scene->light.direction);
    copy(defaults.light.up, scene->light.up);
    copy(defaults.light.center, scene->light.center);
    scene->light.width = defaults.light.width;
    scene->light.height = defaults.light.height;
    scene->light.near_plane = defaults.light.near;
    scene->light.far_plane = defaults.light.far;
    scene->light.depth_range = static_cast<msmcl_depth_range>(defaults.light.depth_range);
    copy(defaults.camera.position, scene->camera.position);
    copy(defaults.camera.forward, scene->camera.forward);
    copy(defaults.camera.up, scene->camera.up);
    scene->camera.vertical_fov_degrees = defaults.camera.vertical_fov_degrees;
    scene->camera.near_plane = defaults.camera.near;
    scene->camera.far_plane = defaults.camera.far;
    scene->camera.width = defaults.camera.width;
    scene->camera.height = defaults.camera.height;
    scene->camera.depth = static_cast<msmcl_camera_depth>(defaults.camera.depth);
    scene->medium.extinction = defaults.medium.extinction;
    scene->medium.phase_g = defaults.medium.phase_g;
    scene->medium.irradiance = defaults.medium.irradiance;
    scene->rectified_width = defaults.rectified_width;
    scene->rectified_height = defaults.rectified_height;
    scene->guard_band = defaults.guard_band;
}

void msmcl_scatter_options_init(msmcl_scatter_options* options) {
    if (!options) return;
    const msmcl::ScatterOptions defaults;
    options->moments = defaults.moments;
    options->filtered = defaults.filtered ? 1 : 0;
    options->filter_sigma = defaults.filter_sigma;
    options->beta = defaults.beta;
    options->kernel = static_cast<msmcl_scatter_kernel>(defaults.kernel);
    options->filter_kernel = static_cast<msmcl_filter_kernel>(defaults.filter_kernel);
}

size_t msmcl_scatter_map_bytes(const msmcl_scatter_scene* scene) {
    if (!scene || scene->rectified_width <= 0 || scene->rectified_height <= 0) return 0;
    return static_cast<std::size_t>(scene->rectified_width) * static_cast<std::size_t>(scene->rectified_height) * 8;
}

msmcl_status msmcl_scatter(msmcl_context* context, const msmcl_scatter_scene* scene, const float* shadow_depth,
                           int width, int height, int samples, const float* camera_depth,
                           const msmcl_scatter_options* options, float* radiance) {
    return guarded([&] {
        const char* call = "msmcl_scatter";
        require(context, call, "context");
        require(radiance, call, "radiance");
        const msmcl::ScatterScene cpp_scene = to_scatter_scene(scene, call);
        const msmcl::ScatterOptions scatter_options = to_scatter_options(options, call);
        const msmcl::DepthImage shadow = to_depth_image(shadow_depth, width, height, samples, call);
        const std::vector<float> camera = to_camera_depth(cpp_scene, camera_depth, call);
        const std::vector<float> result = msmcl::scatter(context->context, cpp_scene, shadow, camera, scatter_options);
        std::copy(result.begin(), result.end(), radiance);
    });
}

msmcl_status msmcl_scatter_prefilter(msmcl_context* context, const msmcl_scatter_scene* scene,
                                     const float* shadow_depth, int width, int height, int samples,
                                     const msmcl_scatter_options* options, void* map, size_t map_bytes) {
    return guarded([&] {
        const char* call = "msmcl_scatter_prefilter";
        require(context, call, "context");
        require(map, call, "map");
        const msmcl::ScatterScene cpp_scene = to_scatter_scene(scene, call);
        const std::size_t needed = require_map_bytes(cpp_scene, map_bytes, call);
        const msmcl::ScatterOptions scatter_options = to_scatter_options(options, call);
        const msmcl::DepthImage shadow = to_depth_image(shadow_depth, width, height, samples, call);
        const msmcl::ScatterMap result = msmcl::scatter_prefilter(context->context, cpp_scene, shadow, scatter_options);
        std::memcpy(map, result.words.data(), needed);
    });
}

msmcl_status msmcl_scatter_evaluate(msmcl_context* context, const msmcl_scatter_scene* scene, const void* map,
                                    size_t map_bytes, const float* camera_depth, const msmcl_scatter_options* options,
                                    float* radiance) {
    return guarded([&] {
        const char* call = "msmcl_scatter_evaluate";
        require(context, call, "context");
        require(map, call, "map");
        require(radiance, call, "radiance");
        const msmcl::ScatterScene cpp_scene = to_scatter_scene(scene, call);
        const std::size_t needed = require_map_bytes(cpp_scene, map_bytes, call);
        const msmcl::ScatterOptions scatter_options = to_scatter_options(options, call);
        // The map as the C++ API holds it: its words, its size the scene's.
        msmcl::ScatterMap cpp_map;
        cpp_map.moments = scatter_options.moments;
        cpp_map.width = cpp_scene.rectified_width;
        cpp_map.height = cpp_scene.rectified_height;
        cpp_map.words.resize(needed / sizeof(std::uint32_t));
        std::memcpy(cpp_map.words.data(), map, needed);
        const std::vector<float> camera = to_camera_depth(cpp_scene, camera_depth, call);
        const std::vector<float> result =
            msmcl::scatter_evaluate(context->context, cpp_scene, cpp_map, camera, scatter_options);
        std::copy(result.begin(), result.end(), radiance);
    });
}

msmcl_status msmcl_scatter_prefilter_device(msmcl_context* context, const msmcl_scatter_scene* scene,
                                            cl_mem moment_map, int map_width, int map_height, int moments,
                                            cl_mem scatter_map, const msmcl_enqueue* enqueue) {
    return guarded([&] {
        const char* call = "msmcl_scatter_prefilter_device";
        require(context, call, "context");
        if (!moment_map) throw invalid_argument{std::string(call) + ": moment_map is NULL"};
        if (!scatter_map) throw invalid_argument{std::string(call) + ": scatter_map is NULL"};
        const msmcl::ScatterScene cpp_scene = to_scatter_scene(scene, call);
        const msmcl::Enqueue plumbing = to_enqueue(enqueue, call);
        const msmcl::DeviceTexture map{moment_map, msmcl::Format::moments128, map_width, map_height, {}};
        msmcl::scatter_prefilter(context->context, cpp_scene, map, scatter_map, moments, plumbing);
    });
}

msmcl_status msmcl_scatter_prefilter_depth_device(msmcl_context* context, const msmcl_scatter_scene* scene,
                                                  const msmcl_device_depth* shadow_map, int moments,
                                                  cl_mem scatter_map, const msmcl_enqueue* enqueue) {
    return guarded([&] {
        const char* call = "msmcl_scatter_prefilter_depth_device";
        require(context, call, "context");
        require(shadow_map, call, "shadow_map");
        if (!shadow_map->memory) throw invalid_argument{std::string(call) + ": shadow_map->memory is NULL"};
        if (!scatter_map) throw invalid_argument{std::string(call) + ": scatter_map is NULL"};
        const msmcl::ScatterScene cpp_scene = to_scatter_scene(scene, call);
        const msmcl::Enqueue plumbing = to_enqueue(enqueue, call);
        // The C++ API resamples depth buffers only.
        if (!is_buffer(shadow_map->memory))
            throw msmcl::input_error(std::string(call) + ": the shadow map must be a buffer, not an image");
        msmcl::scatter_prefilter(context->context, cpp_scene, to_device_depth(*shadow_map, 1), scatter_map, moments,
                                 plumbing);
    });
}

msmcl_status msmcl_scatter_evaluate_device(msmcl_context* context, const msmcl_scatter_scene* scene,
                                           cl_mem scatter_map, int moments, cl_mem camera_depth, cl_mem radiance,
                                           float beta, const msmcl_enqueue* enqueue) {
    return guarded([&] {
        const char* call = "msmcl_scatter_evaluate_device";
        require(context, call, "context");
        if (!scatter_map || !camera_depth || !radiance)
            throw invalid_argument{std::string(call) + ": " +
                                   (!scatter_map ? "scatter_map" : !camera_depth ? "camera_depth" : "radiance") +
                                   " is NULL"};
        const msmcl::ScatterScene cpp_scene = to_scatter_scene(scene, call);
        const msmcl::Enqueue plumbing = to_enqueue(enqueue, call);
        msmcl::scatter_evaluate(context->context, cpp_scene, scatter_map, moments, camera_depth, radiance, beta,
                                plumbing);
    });
}

} // extern "C"
