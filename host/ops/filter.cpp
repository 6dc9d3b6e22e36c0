// filter: depth map -> resolved, blurred, quantized moment shadow map (docs/math.md).
#include "ops/kernel_variants.hpp"
#include "ops/transfer.hpp"
#include "ops/translucent_layers.hpp"
#include "ops/validation.hpp"
#include "runtime/context_impl.hpp"
#include "runtime/enum_names.hpp"
#include "runtime/quirks.hpp"
#include "runtime/texture_kinds.hpp"
#include "runtime/tuning.hpp"
#include "runtime/work_distribution.hpp"

#include "kernels/fused_cpu_layout.clh"
#include "kernels/fused_layout.clh"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <cstddef>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace msmcl {

namespace {

// The fused kernel's work-group, tile and local memory: the sizes the kernel compiles with
// (kernels/fused_layout.clh).
constexpr std::size_t kFusedGroupSize = FUSED_GROUP_SIZE;
constexpr int kFusedTileWidth = FUSED_OUT_W;
constexpr int kFusedTileHeight = FUSED_OUT_H;
// The fused kernel's smaller groups, tried in this order where the built kernel allows
// fewer than kFusedGroupSize work-items: each work-item plays 2, 4 or 8 of the 256 roles
// (FUSED_WORK_ITEMS in kernels/filter_fused_gpu.cl), the same tile and the same bits.
constexpr std::size_t kFusedSmallerGroups[] = {128, 64, 32};
// The CPU distribution (kernels/filter_fused_cpu.cl, layout in fused_cpu_layout.clh): one
// work-item per group filters a whole tile, streaming its rows.
// Tuning parameters, measured on PoCL 3.1 / AVX-512 (bench/): MSMCL_CPU_TILE="WxH"
// overrides them for other CPUs (host/runtime/tuning.hpp).
constexpr int kCpuTileWidth = 128;
constexpr int kCpuTileHeight = 64;

struct CpuTiling {
    int width = kCpuTileWidth;
    int height = kCpuTileHeight;

    // The widest tile of at most half this width whose group needs at most `local_bytes`
    // of local memory (none below the guard band's 8 columns).
    std::optional<CpuTiling> narrowed_to(unsigned long long local_bytes) const {
        for (int narrower = width / 2; narrower >= kCpuNarrowestTile; narrower /= 2) {
            if (static_cast<unsigned long long>(CPU_LOCAL_BYTES(narrower)) <= local_bytes) return CpuTiling{narrower, height};
        }
        return std::nullopt;
    }

    // Local memory of one group (every format the same).
    unsigned long long local_bytes() const { return static_cast<unsigned long long>(CPU_LOCAL_BYTES(width)); }

    // Loop iterations of the one work-item over its tile (kernels/filter_fused_cpu.cl), an
    // upper bound: per input row the resolve, the 4 horizontal and 4 vertical blur loops,
    // the quantization and the guard copies; the block shift's passes. A compiler that
    // unrolls runs fewer.
    long loop_iterations() const {
        const long input_columns = CPU_IN_W_OF(width), input_rows = height + 2 * CPU_GUARD;
        return input_rows * (2 * input_columns + 9L * width + 2 * CPU_GUARD + 1) + 2 * input_columns;
    }

    // Work-items per group: one, which filters the whole tile.
    static constexpr std::size_t group_size() { return 1; }

    static constexpr int kCpuNarrowestTile = 2 * CPU_GUARD;
};

// The most local memory a variant of `kernel` (fused_paper or fused_cpu) needs over every
// format: a device runs the kernel for all formats or for none.
unsigned long long most_local_bytes(FilterKernel kernel, const CpuTiling& tiling) {
    unsigned long long most = 0;
    for (Format format : detail::filter_formats())
        most = std::max(most, detail::filter_local_bytes(kernel, format, tiling.width));
    return most;
}

// The default tiling, or the MSMCL_CPU_TILE override (host/runtime/tuning.hpp), on
// `device`: where the device stops long loops (runtime/quirks.hpp), the tile
// height halves until one work-item's loops stay within the limit.
CpuTiling cpu_tiling(const DeviceInfo& device) {
    CpuTiling tiling;
    if (const std::optional<detail::TileSize> tile = detail::cpu_filter_tile_override(2 * CPU_GUARD)) {
        tiling.width = tile->width;
        tiling.height = tile->height;
    }
    if (const std::optional<long> limit = detail::loop_iteration_limit(device)) {
        while (tiling.height > 1 && tiling.loop_iterations() > *limit) tiling.height /= 2;
    }
    return tiling;
}

std::string describe_size(int width, int height, int samples) {
    std::ostringstream text;
    text << width << "x" << height << " with " << samples << " sample" << (samples == 1 ? "" : "s");
    return text.str();
}

// ", 4 array layers" for texture arrays, nothing for one map.
std::string layers_text(int array_layers) {
    return array_layers == 1 ? std::string() : ", " + std::to_string(array_layers) + " array layers";
}

// Width, height and sample count the filter can work with.
void validate_shape(int width, int height, int samples) {
    detail::validate_map_size("filter: depth map size", width, height);
    if (!is_supported_sample_count(samples)) {
        throw input_error("filter: unsupported sample count " + std::to_string(samples) +
                          " (supported: 1, 2, 4, 8, 16)");
    }
}

// Translucent layers of a call on the device: none (count 0), or the two buffers holding
// count layers each (include/msmcl/filter.hpp, DeviceLayers).
struct LayerBuffers {
    cl::Buffer depth;
    cl::Buffer opacity;
    int count = 0;
};

// Buffers the call allocates or reads, against the device's largest allocation.
void validate_device_sizes(const DeviceInfo& device, int width, int height, int samples, Format format,
                           FilterKernel kernel, int layers, int array_layers) {
    // A texture array's buffers hold every array layer.
    const unsigned long long texels = detail::texel_count(width, height) * static_cast<unsigned long long>(array_layers);
    const auto check = [&](unsigned long long bytes, const char* what) {
        if (device.max_alloc_bytes != 0 && bytes > device.max_alloc_bytes) {
            throw device_error(std::string("filter: ") + what + " for a " + describe_size(width, height, samples) +
                              " depth map needs " + std::to_string(bytes) + " bytes, more than the device's " +
                              "largest buffer (" + std::to_string(device.max_alloc_bytes) + " bytes)");
        }
    };
    check(texels * samples * sizeof(float), "the depth buffer");
    check(layers * texels * samples * sizeof(float), "the translucent layers");
    check(texels * texel_bytes(format), "the texture");
    if (kernel == FilterKernel::three_pass) check(texels * 4 * sizeof(float), "the three-pass moment buffer");
}

// Whether the device could run the fused kernel in its smallest group (plan_filter then
// fits the group to the built kernel).
bool device_runs_fused(const DeviceInfo& device) {
    return device.max_work_group_size >= kFusedSmallerGroups[std::size(kFusedSmallerGroups) - 1] &&
           device.local_mem_bytes >= most_local_bytes(FilterKernel::fused_paper, CpuTiling{});
}

// Whether the device could run the CPU kernel in `tiling` or a narrower tile.
bool device_runs_fused_cpu(const DeviceInfo& device, const CpuTiling& tiling) {
    return device.local_mem_bytes >= tiling.local_bytes() || tiling.narrowed_to(device.local_mem_bytes).has_value();
}

std::string device_limits(const DeviceInfo& device) {
    return std::to_string(device.max_work_group_size) + " and " + std::to_string(device.local_mem_bytes);
}

// automatic -> fused_cpu on CPU devices that are not GPUs (runtime/work_distribution.hpp),
// fused_paper elsewhere, each where the device can run it, else three_pass. A device that
// is not a CPU never gets fused_cpu (its budgets are a CPU's: scripts/gpu_compile_report.py
// exempts it). An explicit choice is honoured or refused with device_error.
FilterKernel choose_kernel(const DeviceInfo& device, FilterKernel requested) {
    const CpuTiling tiling = cpu_tiling(device);
    if (requested == FilterKernel::automatic) {
        if (!detail::prefers_gpu_distribution(device) && device_runs_fused_cpu(device, tiling))
            return FilterKernel::fused_cpu;
        return device_runs_fused(device) ? FilterKernel::fused_paper : FilterKernel::three_pass;
    }
    if (requested == FilterKernel::fused_paper && !device_runs_fused(device)) {
        throw unfit_kernel_error("filter: device '" + device.name + "' cannot run the fused kernel (needs " +
                           std::to_string(kFusedGroupSize) + " work-items per group and " +
                           std::to_string(most_local_bytes(FilterKernel::fused_paper, tiling)) +
                           " bytes of local memory; it has " +
                           device_limits(device) + ")");
    }
    if (requested == FilterKernel::fused_cpu && !device_runs_fused_cpu(device, tiling)) {
        throw unfit_kernel_error("filter: device '" + device.name + "' cannot run the CPU fused kernel (needs " +
                           std::to_string(CPU_LOCAL_BYTES(CpuTiling::kCpuNarrowestTile)) +
                           " bytes of local memory for its narrowest tile; it has " +
                           std::to_string(device.local_mem_bytes) + ")");
    }
    return requested;
}

std::vector<std::string> kernel_defines(int samples, const FilterOptions& options, int layers, int array_layers) {
    return detail::filter_defines(samples, options.format, options.depth_range, layers, array_layers > 1,
                                  options.exponents);
}

// The launch grid of `groups` (2D) over `array_layers` layers: a third dimension for texture
// arrays (one group per layer in it), the plain 2D grid for one map.
cl::NDRange layered(std::size_t x, std::size_t y, int array_layers) {
    if (array_layers == 1) return cl::NDRange(x, y);
    return cl::NDRange(x, y, static_cast<std::size_t>(array_layers));
}
// A work-group of `x` work-items in a grid from layered().
cl::NDRange group_of(std::size_t x, int array_layers) {
    return array_layers == 1 ? cl::NDRange(x, 1) : cl::NDRange(x, 1, 1);
}

// Sets the 5 distinct taps w0 (centre) .. w4 as float arguments starting at `first`.
void set_tap_arguments(cl::Kernel& kernel, cl_uint first, const std::array<float, 9>& taps) {
    for (cl_uint i = 0; i < 5; ++i) detail::check(kernel.setArg(first + i, taps[4 + i]), "clSetKernelArg");
}

// The CPU distribution (kernels/filter_fused_cpu.cl): interior tile columns (guard band
// inside the image) and border tile columns as two launches; returns the event of the
// last one, which waits for the first.
cl::Event enqueue_fused_cpu(detail::ContextImpl& impl, const cl::CommandQueue& queue,
                            const std::vector<cl::Event>& waits, const cl::Buffer& depth, int width, int height,
                            const cl::Buffer& texture, const FilterOptions& options, int samples,
                            const std::array<float, 9>& taps, const LayerBuffers& layers, int array_layers,
                            const CpuTiling& tiling) {
    const std::vector<std::string> defines =
        detail::filter_cpu_defines(samples, options.format, options.depth_range, layers.count, array_layers > 1,
                                   {tiling.width, tiling.height}, options.exponents);
    // Tile grid; tile columns [ix0, ix1) read and write no column outside the image.
    const int tiles_x = (width + tiling.width - 1) / tiling.width;
    const int tiles_y = (height + tiling.height - 1) / tiling.height;
    const int ix0 = 1; // the first tile column's guard band leaves the image
    const int ix1 = std::max(ix0, (width - CPU_GUARD) / tiling.width);
    const std::size_t interior_columns = static_cast<std::size_t>(ix1 - ix0);
    const std::size_t border_columns = static_cast<std::size_t>(tiles_x) - interior_columns;

    const auto prepare = [&](const char* name) -> cl::Kernel& {
        cl::Kernel& kernel = impl.kernel("filter_fused_cpu.cl", defines, name);
        detail::set_arg(kernel, 0, depth);
        detail::set_arg(kernel, 1, width);
        detail::set_arg(kernel, 2, height);
        detail::set_arg(kernel, 3, texture);
        set_tap_arguments(kernel, 4, taps);
        detail::set_arg(kernel, 9, ix0);
        detail::set_arg(kernel, 10, ix1);
        return kernel;
    };

    std::vector<cl::Event> before = waits;
    cl::Event last;
    const auto launch = [&](const char* name, std::size_t columns) {
        cl::Kernel& kernel = prepare(name);
        if (layers.count > 0) {
            detail::set_arg(kernel, 11, layers.depth);
            detail::set_arg(kernel, 12, layers.opacity);
        }
        // One group (of one work-item) per tile.
        detail::check(queue.enqueueNDRangeKernel(kernel, cl::NullRange,
                                                 layered(columns, static_cast<std::size_t>(tiles_y), array_layers),
                                                 group_of(CpuTiling::group_size(), array_layers), &before, &last),
                      (std::string("clEnqueueNDRangeKernel(") + name + ")").c_str());
        before = {last};
    };
    if (interior_columns > 0) launch("filter_fused_cpu_interior", interior_columns);
    if (border_columns > 0) launch("filter_fused_cpu_border", border_columns);
    return last;
}

// The defines of filter_fused_gpu.cl for groups of `work_items` (the paper's 256 keep the
// plain program).
std::vector<std::string> fused_defines(int samples, const FilterOptions& options, int layers, int array_layers,
                                       std::size_t work_items) {
    std::vector<std::string> defines = kernel_defines(samples, options, layers, array_layers);
    if (work_items != kFusedGroupSize) defines.push_back("FUSED_WORK_ITEMS=" + std::to_string(work_items));
    return defines;
}

// The distribution a call runs with, fitted to what the built kernels allow.
struct FilterPlan {
    FilterKernel kernel = FilterKernel::three_pass;
    std::size_t fused_work_items = kFusedGroupSize; // fused_paper
    CpuTiling tiling;                               // fused_cpu
};

// automatic: the device's preferred distribution (choose_kernel), then its variants with
// smaller groups, then three_pass; an explicit fused_paper or fused_cpu takes the first of
// its own variants that fits, else throws unfit_kernel_error with the built kernel's
// limits. Each candidate is built and asked for CL_KERNEL_WORK_GROUP_SIZE and its local
// memory (docs/devices.md); the choice and its reason go to Context::kernel_choices.
FilterPlan plan_filter(detail::ContextImpl& impl, FilterKernel requested, int samples, const FilterOptions& options,
                       int layers, int array_layers) {
    const FilterKernel preferred = choose_kernel(impl.info, requested);
    std::string reasons; // why the candidates before the chosen one were passed over
    FilterPlan plan;
    if (preferred == FilterKernel::fused_paper) {
        const std::optional<int> start = detail::fused_work_items_override();
        std::size_t work_items = start ? static_cast<std::size_t>(*start) : kFusedGroupSize;
        for (std::size_t next = 0;; ++next) {
            const detail::KernelFit fit = detail::kernel_fit(
                impl, impl.kernel("filter_fused_gpu.cl", fused_defines(samples, options, layers, array_layers, work_items),
                                  "filter_fused_gpu"));
            if (fit.runs(work_items)) {
                plan.kernel = FilterKernel::fused_paper;
                plan.fused_work_items = work_items;
                impl.note_choice("filter", "fused_paper, " + std::to_string(work_items) + " work-items per 40x32 tile" +
                                               (reasons.empty() ? "" : " (" + reasons + ")"));
                return plan;
            }
            reasons += std::string(reasons.empty() ? "" : "; ") + "fused_paper with " + std::to_string(work_items) +
                       " work-items: the built kernel allows " + fit.limits();
            // The next smaller group that the limit allows.
            while (next < std::size(kFusedSmallerGroups) && kFusedSmallerGroups[next] > fit.work_items) ++next;
            if (next >= std::size(kFusedSmallerGroups)) break;
            work_items = kFusedSmallerGroups[next];
        }
    } else if (preferred == FilterKernel::fused_cpu) {
        std::optional<CpuTiling> tiling = cpu_tiling(impl.info);
        // Translucent layers where the device stops long loops (runtime/quirks.hpp): the
        // composite loops over the layers, and their square, for every sample of every
        // texel, far past the limit in any useful tile.
        if (layers > 0 && detail::loop_iteration_limit(impl.info)) {
            reasons = "fused_cpu with translucent layers: the device stops a work-item after " +
                      std::to_string(*detail::loop_iteration_limit(impl.info)) +
                      " loop iterations, fewer than the composite takes over a tile";
            tiling.reset();
        }
        while (tiling) {
            const detail::KernelFit fit = detail::kernel_fit(
                impl, impl.kernel("filter_fused_cpu.cl",
                                  detail::filter_cpu_defines(samples, options.format, options.depth_range, layers,
                                                             array_layers > 1, {tiling->width, tiling->height},
                                                             options.exponents),
                                  "filter_fused_cpu_border"));
            if (fit.runs(CpuTiling::group_size()) && tiling->local_bytes() <= fit.device_local_bytes) {
                plan.kernel = FilterKernel::fused_cpu;
                plan.tiling = *tiling;
                // Why the tile is lower than asked: the device's loop limit (cpu_tiling).
                if (tiling->height < cpu_tiling(DeviceInfo{}).height)
                    reasons += std::string(reasons.empty() ? "" : "; ") + "height cut so that one work-item runs at most " +
                               std::to_string(*detail::loop_iteration_limit(impl.info)) + " loop iterations";
                impl.note_choice("filter", "fused_cpu, tile " + std::to_string(tiling->width) + "x" +
                                               std::to_string(tiling->height) + " (one work-item a tile)" +
                                               (reasons.empty() ? "" : " (" + reasons + ")"));
                return plan;
            }
            reasons += std::string(reasons.empty() ? "" : "; ") + "fused_cpu with tile width " +
                       std::to_string(tiling->width) + " (" + std::to_string(tiling->local_bytes()) +
                       " bytes of local memory): the built kernel allows " + fit.limits();
            // A work-item too many cannot be narrowed away; too little local memory can.
            if (!fit.runs(CpuTiling::group_size())) break;
            tiling = tiling->narrowed_to(fit.device_local_bytes);
        }
    } else {
        impl.note_choice("filter", std::string("three_pass") + (requested == FilterKernel::three_pass
                                                                    ? " (requested)"
                                                                    : " (the device's limits rule out the fused kernels)"));
        return plan;
    }
    if (requested != FilterKernel::automatic) {
        throw unfit_kernel_error("filter: device '" + impl.info.name + "' cannot run --kernel " +
                                 filter_kernel_name(requested) + ": " + reasons);
    }
    impl.note_choice("filter", "three_pass (" + reasons + ")");
    return plan;
}

// Enqueues the whole filter on `queue`; returns the event of its last command.
cl::Event enqueue_filter(detail::ContextImpl& impl, const cl::CommandQueue& queue, const std::vector<cl::Event>& waits,
                         const cl::Buffer& depth, int width, int height, int samples, const cl::Buffer& texture,
                         const FilterOptions& options, const LayerBuffers& layers, int array_layers) {
    const std::array<float, 9> taps = gaussian_taps(options.sigma);
    const FilterPlan plan = plan_filter(impl, options.kernel, samples, options, layers.count, array_layers);
    const FilterKernel kernel_choice = plan.kernel;
    validate_device_sizes(impl.info, width, height, samples, options.format, kernel_choice, layers.count, array_layers);
    const std::vector<std::string> defines = kernel_defines(samples, options, layers.count, array_layers);
    const cl::NDRange image = layered(static_cast<std::size_t>(width), static_cast<std::size_t>(height), array_layers);
    cl::Event last;

    if (kernel_choice == FilterKernel::fused_paper) {
        cl::Kernel& fused = impl.kernel("filter_fused_gpu.cl", fused_defines(samples, options, layers.count, array_layers,
                                                                             plan.fused_work_items),
                                        "filter_fused_gpu");
        detail::check(fused.setArg(0, depth), "clSetKernelArg");
        detail::check(fused.setArg(1, width), "clSetKernelArg");
        detail::check(fused.setArg(2, height), "clSetKernelArg");
        detail::check(fused.setArg(3, texture), "clSetKernelArg");
        set_tap_arguments(fused, 4, taps);
        if (layers.count > 0) {
            detail::check(fused.setArg(9, layers.depth), "clSetKernelArg");
            detail::check(fused.setArg(10, layers.opacity), "clSetKernelArg");
        }
        // One work-group of 256 (or its smaller variant) per 32x24 output tile.
        const std::size_t groups_x = (static_cast<std::size_t>(width) + kFusedTileWidth - 1) / kFusedTileWidth;
        const std::size_t groups_y = (static_cast<std::size_t>(height) + kFusedTileHeight - 1) / kFusedTileHeight;
        detail::check(queue.enqueueNDRangeKernel(fused, cl::NullRange,
                                                 layered(groups_x * plan.fused_work_items, groups_y, array_layers),
                                                 group_of(plan.fused_work_items, array_layers), &waits, &last),
                      "clEnqueueNDRangeKernel(filter_fused_gpu)");
        return last;
    }

    if (kernel_choice == FilterKernel::fused_cpu)
        return enqueue_fused_cpu(impl, queue, waits, depth, width, height, texture, options, samples, taps, layers,
                                 array_layers, plan.tiling);

    // Three passes through two float4 moment buffers (one map's worth per array layer).
    cl_int status = CL_SUCCESS;
    const std::size_t moment_bytes = detail::texel_count(width, height) * array_layers * 4 * sizeof(float);
    cl::Buffer resolved(impl.context, CL_MEM_READ_WRITE, moment_bytes, nullptr, &status);
    detail::check(status, "clCreateBuffer(three-pass moments)");
    cl::Buffer rows(impl.context, CL_MEM_READ_WRITE, moment_bytes, nullptr, &status);
    detail::check(status, "clCreateBuffer(three-pass moments)");

    // (a) resolve
    cl::Kernel& resolve = impl.kernel("filter_three_pass.cl", defines, "filter_resolve");
    detail::check(resolve.setArg(0, depth), "clSetKernelArg");
    detail::check(resolve.setArg(1, width), "clSetKernelArg");
    detail::check(resolve.setArg(2, height), "clSetKernelArg");
    detail::check(resolve.setArg(3, resolved), "clSetKernelArg");
    if (layers.count > 0) {
        detail::check(resolve.setArg(4, layers.depth), "clSetKernelArg");
        detail::check(resolve.setArg(5, layers.opacity), "clSetKernelArg");
    }
    cl::Event resolved_event;
    detail::check(queue.enqueueNDRangeKernel(resolve, cl::NullRange, image, cl::NullRange, &waits, &resolved_event),
                  "clEnqueueNDRangeKernel(filter_resolve)");

    // (b) horizontal blur; events chain the passes even on an out-of-order queue.
    cl::Kernel& horizontal = impl.kernel("filter_three_pass.cl", defines, "filter_horizontal");
    detail::check(horizontal.setArg(0, resolved), "clSetKernelArg");
    detail::check(horizontal.setArg(1, width), "clSetKernelArg");
    detail::check(horizontal.setArg(2, height), "clSetKernelArg");
    detail::check(horizontal.setArg(3, rows), "clSetKernelArg");
    set_tap_arguments(horizontal, 4, taps);
    const std::vector<cl::Event> after_resolve{resolved_event};
    cl::Event rows_event;
    detail::check(queue.enqueueNDRangeKernel(horizontal, cl::NullRange, image, cl::NullRange, &after_resolve, &rows_event),
                  "clEnqueueNDRangeKernel(filter_horizontal)");

    // (c) vertical blur, bias, quantize
    cl::Kernel& vertical = impl.kernel("filter_three_pass.cl", defines, "filter_vertical_quantize");
    detail::check(vertical.setArg(0, rows), "clSetKernelArg");
    detail::check(vertical.setArg(1, width), "clSetKernelArg");
    detail::check(vertical.setArg(2, height), "clSetKernelArg");
    detail::check(vertical.setArg(3, texture), "clSetKernelArg");
    set_tap_arguments(vertical, 4, taps);
    const std::vector<cl::Event> after_rows{rows_event};
    detail::check(queue.enqueueNDRangeKernel(vertical, cl::NullRange, image, cl::NullRange, &after_rows, &last),
                  "clEnqueueNDRangeKernel(filter_vertical_quantize)");
    // The temporaries are released here; OpenCL frees them once the kernels are done.
    return last;
}

} // namespace

// The names of FilterKernel values, both ways (filter_kernel_name, parse_filter_kernel).
constexpr detail::EnumNames<FilterKernel> filter_kernel_names[] = {
    {FilterKernel::automatic, "automatic"},
    {FilterKernel::fused_paper, "fused_paper"},
    {FilterKernel::three_pass, "three_pass"},
    {FilterKernel::fused_cpu, "fused_cpu"},
};

const char* filter_kernel_name(FilterKernel kernel) noexcept { return detail::name_in(filter_kernel_names, kernel); }

std::optional<FilterKernel> parse_filter_kernel(std::string_view name) noexcept {
    return detail::parse_in(filter_kernel_names, name);
}

FilterKernel filter_kernel_for(const Context& context, FilterKernel requested) {
    return choose_kernel(context.device(), requested);
}

namespace detail {

unsigned long long filter_local_bytes(FilterKernel kernel, Format format, int cpu_tile_width) {
    const TextureKind& kind = texture_kind(format);
    if (kernel == FilterKernel::fused_paper) return FUSED_LOCAL_BYTES(kind.shifted);
    if (kernel == FilterKernel::fused_cpu)
        return static_cast<unsigned long long>(CPU_LOCAL_BYTES(cpu_tile_width));
    return 0;
}

int filter_cpu_tile_width() { return cpu_tiling(DeviceInfo{}).width; }

TileSize filter_cpu_tile(const DeviceInfo& device) {
    const CpuTiling tiling = cpu_tiling(device);
    return {tiling.width, tiling.height};
}

FilterKernel filter_kernel_for(const DeviceInfo& device, FilterKernel requested) {
    return choose_kernel(device, requested);
}

// Compile-time variant: sample count, format (its row of the format table, with the warp's
// exponents), depth convention.
std::vector<std::string> filter_defines(int samples, Format format, DepthRange range, int layers, bool array,
                                        WarpExponents exponents) {
    std::vector<std::string> defines = texture_kind_defines(format, exponents);
    defines.push_back("MSM_SAMPLES=" + std::to_string(samples));
    defines.push_back("MSM_DEPTH_ZERO_ONE=" + std::string(range == DepthRange::zero_one ? "1" : "0"));
    // Translucent layers: the compositing resolve (opaque maps keep the opaque program).
    if (layers > 0) defines.push_back("MSM_LAYERS=" + std::to_string(layers));
    // Texture arrays: the layer-slicing program (single maps keep the plain one).
    if (array) defines.push_back("MSM_ARRAY=1");
    return defines;
}

// The CPU kernel adds its tile.
std::vector<std::string> filter_cpu_defines(int samples, Format format, DepthRange range, int layers, bool array,
                                            TileSize tile, WarpExponents exponents) {
    CpuTiling tiling = cpu_tiling(DeviceInfo{});
    if (tile.width > 0) tiling.width = tile.width;
    if (tile.height > 0) tiling.height = tile.height;
    std::vector<std::string> defines = filter_defines(samples, format, range, layers, array, exponents);
    defines.push_back("CPU_TILE_W=" + std::to_string(tiling.width));
    defines.push_back("CPU_TILE_H=" + std::to_string(tiling.height));
    return defines;
}

} // namespace detail

std::array<float, 9> gaussian_taps(float sigma) {
    if (!std::isfinite(sigma) || sigma < 0.0f)
        throw input_error("filter: sigma must be finite and >= 0, got " + std::to_string(sigma));
    std::array<float, 9> taps{};
    // sigma 0: a unit impulse, no blur.
    if (sigma == 0.0f) {
        taps[4] = 1.0f;
        return taps;
    }
    // Weights in double, normalized, rounded once to float (symmetric by construction).
    double weights[5];
    double total = 0.0;
    for (int i = 0; i <= 4; ++i) {
        weights[i] = std::exp(-double(i * i) / (2.0 * double(sigma) * double(sigma)));
        total += i == 0 ? weights[i] : 2.0 * weights[i];
    }
    for (int i = 0; i <= 4; ++i) {
        taps[4 + i] = static_cast<float>(weights[i] / total);
        taps[4 - i] = taps[4 + i];
    }
    return taps;
}

bool is_supported_sample_count(int samples) noexcept {
    return samples == 1 || samples == 2 || samples == 4 || samples == 8 || samples == 16;
}

Texture filter(Context& context, const DepthImage& depth, const FilterOptions& options) {
    return filter(context, depth, std::vector<TranslucentLayer>{}, options);
}

Texture filter(Context& context, const DepthImage& depth, const std::vector<TranslucentLayer>& layers,
               const FilterOptions& options) {
    // Validate everything before touching the device.
    validate_shape(depth.width, depth.height, depth.samples);
    detail::validate_array_layers("filter", depth.layers);
    const std::size_t values =
        detail::texel_count(depth.width, depth.height) * depth.samples * static_cast<std::size_t>(depth.layers);
    if (depth.depth.size() != values) {
        throw input_error("filter: depth map " + describe_size(depth.width, depth.height, depth.samples) +
                          layers_text(depth.layers) + " needs " + std::to_string(values) + " values, got " +
                          std::to_string(depth.depth.size()));
    }
    gaussian_taps(options.sigma); // throws input_error for a bad sigma
    const WarpExponents exponents = effective_exponents(options.format, options.exponents, "filter");
    detail::validate_depth_values("filter", depth, options.depth_range);
    detail::validate_layers("filter", depth, layers, options.depth_range);
    detail::ContextImpl& impl = context.impl();
    validate_device_sizes(impl.info, depth.width, depth.height, depth.samples, options.format,
                          choose_kernel(impl.info, options.kernel), static_cast<int>(layers.size()), depth.layers);

    // Upload (the translucent layers one after the other), run on the Context's queue, read back.
    detail::StageTimer stages(impl, options.on_stage);
    Texture texture;
    texture.format = options.format;
    texture.width = depth.width;
    texture.height = depth.height;
    texture.layers = depth.layers;
    texture.exponents = exponents;
    texture.words.resize(detail::texel_count(depth.width, depth.height) * texel_words(options.format) *
                         static_cast<std::size_t>(depth.layers));
    const cl::Buffer depth_buffer =
        detail::upload_in_place(impl, depth.depth.data(), values * sizeof(float), "clCreateBuffer(depth)");
    LayerBuffers layer_buffers;
    if (!layers.empty()) {
        const std::vector<float> layer_depth = detail::concatenated_depths(layers, depth.layers);
        const std::vector<float> layer_opacity = detail::concatenated_opacities(layers, depth.layers);
        layer_buffers.depth = detail::upload(impl, layer_depth.data(), layer_depth.size() * sizeof(float),
                                             "clCreateBuffer(layer depth)");
        layer_buffers.opacity = detail::upload(impl, layer_opacity.data(), layer_opacity.size() * sizeof(float),
                                               "clCreateBuffer(layer opacity)");
        layer_buffers.count = static_cast<int>(layers.size());
    }
    stages.uploaded({&depth_buffer, &layer_buffers.depth, &layer_buffers.opacity});
    const std::size_t texture_bytes = texture.words.size() * sizeof(std::uint32_t);
    const cl::Buffer texture_buffer =
        detail::result_buffer(impl, texture.words.data(), texture_bytes, "clCreateBuffer(texture)");
    const cl::Event done = enqueue_filter(impl, impl.queue, {}, depth_buffer, depth.width, depth.height, depth.samples,
                                          texture_buffer, options, layer_buffers, depth.layers);
    stages.computed("filter");
    detail::read_result(impl, texture_buffer, texture_bytes, texture.words.data(), done, "clEnqueueReadBuffer(texture)");
    stages.downloaded(texture_buffer, texture_bytes);
    return texture;
}

void filter(Context& context, const DeviceDepth& depth, cl_mem texture, const FilterOptions& options,
            const Enqueue& enqueue) {
    filter(context, depth, DeviceLayers{}, texture, options, enqueue);
}

void filter(Context& context, const DeviceDepth& depth, const DeviceLayers& layers, cl_mem texture,
            const FilterOptions& options, const Enqueue& enqueue) {
    validate_shape(depth.width, depth.height, depth.samples);
    detail::validate_array_layers("filter", depth.layers);
    if (!depth.buffer) throw input_error("filter: DeviceDepth::buffer is null");
    if (!texture) throw input_error("filter: the texture buffer is null");
    gaussian_taps(options.sigma); // throws input_error for a bad sigma
    detail::validate_layer_count("filter", layers.count);
    // The caller's buffers must hold the whole depth map, the layers and the texture (every array layer).
    const cl_ulong array_layers = static_cast<cl_ulong>(depth.layers);
    const cl_ulong depth_bytes =
        detail::texel_count(depth.width, depth.height) * depth.samples * sizeof(float) * array_layers;
    const cl_ulong texture_bytes = detail::texel_count(depth.width, depth.height) * texel_bytes(options.format) *
                                   array_layers;
    if (detail::buffer_size(depth.buffer) < depth_bytes) {
        throw input_error("filter: the depth buffer holds " + std::to_string(detail::buffer_size(depth.buffer)) +
                          " bytes, a " + describe_size(depth.width, depth.height, depth.samples) +
                          layers_text(depth.layers) + " map needs " + std::to_string(depth_bytes));
    }
    if (detail::buffer_size(texture) < texture_bytes) {
        throw input_error("filter: the texture buffer holds " + std::to_string(detail::buffer_size(texture)) +
                          " bytes, a " + std::to_string(depth.width) + "x" + std::to_string(depth.height) + " " +
                          format_name(options.format) + " texture" + layers_text(depth.layers) + " needs " +
                          std::to_string(texture_bytes));
    }
    LayerBuffers layer_buffers;
    if (layers.count > 0) {
        const cl_ulong layer_bytes = depth_bytes * static_cast<cl_ulong>(layers.count);
        for (const auto& [buffer, what] : {std::pair<cl_mem, const char*>{layers.depth, "depth"},
                                           std::pair<cl_mem, const char*>{layers.opacity, "opacity"}}) {
            if (!buffer) throw input_error(std::string("filter: the layer ") + what + " buffer is null");
            if (detail::buffer_size(buffer) < layer_bytes)
                throw input_error(std::string("filter: the layer ") + what + " buffer holds " +
                                  std::to_string(detail::buffer_size(buffer)) + " bytes, " +
                                  std::to_string(layers.count) + " layers of a " +
                                  describe_size(depth.width, depth.height, depth.samples) +
                                  " map need " + std::to_string(layer_bytes));
        }
        layer_buffers = LayerBuffers{cl::Buffer(layers.depth, true), cl::Buffer(layers.opacity, true), layers.count};
    }
    detail::ContextImpl& impl = context.impl();
    const cl::CommandQueue queue = impl.queue_for(enqueue);
    const cl::Event last = enqueue_filter(impl, queue, detail::wait_list(enqueue), cl::Buffer(depth.buffer, true),
                                          depth.width, depth.height, depth.samples, cl::Buffer(texture, true), options,
                                          layer_buffers, depth.layers);
    detail::complete(enqueue, queue, last);
}

} // namespace msmcl
