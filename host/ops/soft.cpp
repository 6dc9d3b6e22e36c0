// soft_shade: moment soft shadows of receivers from a summed-area table
// (kernels/sat_soft.cl on the device, kernels/msm_sat.clh compiled as C++ on the host).
#include "ops/kernel_variants.hpp"
#include "ops/transfer.hpp"
#include "ops/validation.hpp"
#include "runtime/context_impl.hpp"

#include "kernels/msm_sat.clh"

#include <msmcl/errors.hpp>
#include <msmcl/sat.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace msmcl {

namespace {

// floor(sqrt(n)) exactly.
int integer_sqrt(std::uint32_t n) {
    std::uint64_t root = static_cast<std::uint64_t>(std::sqrt(static_cast<double>(n)));
    while (root * root > n) --root;
    while ((root + 1) * (root + 1) <= n) ++root;
    return static_cast<int>(root);
}

void validate_table_header(int width, int height, std::uint32_t max_kernel_texels) {
    if (width <= 0 || height <= 0)
        throw input_error("soft: the table is empty (" + std::to_string(width) + "x" + std::to_string(height) + ")");
    sat_scale(max_kernel_texels);
}

void validate_host_table(const SatTable& table) {
    validate_table_header(table.width, table.height, table.max_kernel_texels);
    detail::require_single_layer("soft", "the table", table.layers);
    if (table.scale != sat_scale(table.max_kernel_texels))
        throw input_error("soft: table scale " + std::to_string(table.scale) + " does not match N = " +
                          std::to_string(table.max_kernel_texels));
    const std::size_t words = 4 * static_cast<std::size_t>(table.width) * table.height;
    if (table.words.size() != words)
        throw input_error("soft: the table holds " + std::to_string(table.words.size()) + " words, a " +
                          std::to_string(table.width) + "x" + std::to_string(table.height) + " table needs " +
                          std::to_string(words));
}

msm_sat_soft_params device_params(int width, int height, std::uint32_t max_kernel_texels,
                                  const SoftShadowOptions& options) {
    const SoftShadowLimits limits = soft_shadow_limits(max_kernel_texels, options);
    return msm_sat_soft_params_refine(msm_sat_soft_params_make(width, height, msm_sat_scale(max_kernel_texels),
                                                               limits.search_size, options.light_size,
                                                               options.min_filter_size, limits.max_filter_size),
                                      options.receiver_blocker_weight, options.filter_parts);
}

} // namespace

namespace detail {

std::vector<std::string> soft_defines(DepthRange range) {
    return {std::string("MSM_DEPTH_ZERO_ONE=") + (range == DepthRange::zero_one ? "1" : "0")};
}

} // namespace detail

SoftShadowLimits soft_shadow_limits(std::uint32_t max_kernel_texels, const SoftShadowOptions& options) {
    sat_scale(max_kernel_texels);
    const int side = integer_sqrt(max_kernel_texels);
    if (!std::isfinite(options.light_size) || options.light_size < 0.0f)
        throw input_error("soft: the light size must be finite and >= 0, got " + std::to_string(options.light_size));
    if (!std::isfinite(options.depth_bias))
        throw input_error("soft: the depth bias must be finite");
    if (options.search_size < 0 || options.search_size > side)
        throw input_error("soft: the blocker search side " + std::to_string(options.search_size) +
                          " must be in [1, " + std::to_string(side) + "] (its square may not exceed N = " +
                          std::to_string(max_kernel_texels) + " texels), or 0 for the largest");
    if (!std::isfinite(options.min_filter_size) || options.min_filter_size <= 0.0f ||
        options.min_filter_size > static_cast<float>(side))
        throw input_error("soft: the smallest filter side must be in (0, " + std::to_string(side) + "], got " +
                          std::to_string(options.min_filter_size));
    if (!std::isfinite(options.receiver_blocker_weight) || options.receiver_blocker_weight < 0.0f ||
        options.receiver_blocker_weight > 1.0f)
        throw input_error("soft: the receiver's blocker weight must be in [0, 1], got " +
                          std::to_string(options.receiver_blocker_weight));
    if (options.filter_parts < 1 || options.filter_parts > 4)
        throw input_error("soft: the filter parts per side must be in [1, 4], got " +
                          std::to_string(options.filter_parts));
    SoftShadowLimits limits;
    limits.search_size = options.search_size == 0 ? side : options.search_size;
    limits.max_filter_size = static_cast<float>(side);
    return limits;
}

void soft_shade(Context& context, const DeviceSat& table, cl_mem receivers_uvz, std::size_t count, cl_mem intensity,
                const SoftShadowOptions& options, const Enqueue& enqueue) {
    validate_table_header(table.width, table.height, table.max_kernel_texels);
    const msm_sat_soft_params p = device_params(table.width, table.height, table.max_kernel_texels, options);
    if (!table.buffer || !receivers_uvz || !intensity) throw input_error("soft: null cl_mem argument");
    if (count > std::numeric_limits<cl_uint>::max())
        throw input_error("soft: too many receivers in one call (" + std::to_string(count) + ")");
    detail::ContextImpl& impl = context.impl();
    cl::Kernel& kernel =
        impl.kernel("sat_soft.cl", detail::soft_defines(options.depth_range), "sat_soft_shade");
    const cl::CommandQueue queue = impl.queue_for(enqueue);
    std::vector<cl::Event> waits = detail::wait_list(enqueue);
    cl::Event done;
    if (count == 0) {
        detail::complete_without_work(enqueue, queue);
        return;
    }
    detail::set_arg(kernel, 0, table.buffer);
    detail::set_arg(kernel, 1, static_cast<cl_int>(p.width));
    detail::set_arg(kernel, 2, static_cast<cl_int>(p.height));
    detail::set_arg(kernel, 3, static_cast<cl_uint>(p.scale));
    detail::set_arg(kernel, 4, static_cast<cl_int>(p.search_size));
    detail::set_arg(kernel, 5, p.light_size);
    detail::set_arg(kernel, 6, p.min_filter_size);
    detail::set_arg(kernel, 7, p.max_filter_size);
    detail::set_arg(kernel, 8, p.receiver_weight);
    detail::set_arg(kernel, 9, static_cast<cl_int>(p.filter_parts));
    detail::set_arg(kernel, 10, receivers_uvz);
    detail::set_arg(kernel, 11, static_cast<cl_uint>(count));
    detail::set_arg(kernel, 12, options.depth_bias);
    detail::set_arg(kernel, 13, intensity);
    // One work-item per receiver; groups of 64 (a multiple of every warp/wavefront width), or
    // fewer where the built kernel allows fewer (docs/devices.md).
    const std::size_t group = detail::fitting_group(detail::kernel_fit(impl, kernel), 64);
    detail::check(queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange((count + group - 1) / group * group),
                                             cl::NDRange(group), waits.empty() ? nullptr : &waits, &done),
                  "clEnqueueNDRangeKernel(sat_soft_shade)");
    detail::complete(enqueue, queue, done);
}

std::vector<float> soft_shade(Context& context, const SatTable& table, const Receivers& receivers,
                              const SoftShadowOptions& options) {
    validate_host_table(table);
    soft_shadow_limits(table.max_kernel_texels, options);
    detail::validate_receivers("soft", receivers);
    const std::size_t count = receivers.size();
    if (count == 0) return {};

    // Upload the table and the receivers (planar u, v, z), shade, read back.
    detail::ContextImpl& impl = context.impl();
    const std::size_t table_bytes = table.words.size() * sizeof(std::uint32_t);
    if (impl.info.max_alloc_bytes != 0 && table_bytes > impl.info.max_alloc_bytes)
        throw device_error("soft: a " + std::to_string(table.width) + "x" + std::to_string(table.height) +
                          " table exceeds the device's largest buffer (" + std::to_string(impl.info.max_alloc_bytes) +
                          " bytes)");
    detail::StageTimer stages(impl, options.on_stage);
    const cl::Buffer table_buffer = detail::upload(impl, table.words.data(), table_bytes, "clCreateBuffer(sat table)");
    const cl::Buffer receiver_buffer = detail::upload_receivers(impl, receivers);
    const cl::Buffer result_buffer =
        detail::device_buffer(impl, CL_MEM_WRITE_ONLY, count * sizeof(float), "clCreateBuffer(intensity)");
    stages.uploaded({&table_buffer, &receiver_buffer});
    soft_shade(context, DeviceSat{table_buffer(), table.width, table.height, table.max_kernel_texels},
               receiver_buffer(), count, result_buffer(), options, Enqueue{});
    stages.computed();
    std::vector<float> intensity = detail::read_floats(impl, result_buffer, count, "clEnqueueReadBuffer(intensity)");
    stages.downloaded(result_buffer, count * sizeof(float));
    return intensity;
}

float soft_shadow_at(const SatTable& table, float u, float v, float z, const SoftShadowOptions& options) {
    validate_host_table(table);
    const msm_sat_soft_params p = device_params(table.width, table.height, table.max_kernel_texels, options);
    const float zf = msm_internal_depth(z, options.depth_range == DepthRange::zero_one ? 1 : 0) - options.depth_bias;
    return msm_sat_soft_shadow(table.words.data(), p, u, v, zf);
}

} // namespace msmcl
