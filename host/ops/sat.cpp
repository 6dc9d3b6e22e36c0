// sat: depth map -> integer modular summed-area table (kernels/sat_build.cl), and the
// table queries on host (kernels/msm_sat.clh compiled as C++) and device (sat_query.cl).
#include "ops/kernel_variants.hpp"
#include "ops/transfer.hpp"
#include "ops/translucent_layers.hpp"
#include "ops/validation.hpp"
#include "runtime/context_impl.hpp"
#include "runtime/enum_names.hpp"
#include "runtime/work_distribution.hpp"

#include "kernels/msm_sat.clh"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/sat.hpp>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace msmcl {

namespace {

// The GPU distribution of the tiled scan: kernels/sat_build.cl, 32x32 tiles in local
// memory, 32 work-items per tile, kernels/sat_carries.cl in between.
constexpr int kGpuTile = 32;
// The CPU distribution: kernels/sat_build_cpu.cl, one work-item per band of full rows in
// 16-lane vectors (band totals, sat_column_carries, band scan). Bands of 32 rows: the
// carries pass costs 0.3 ms at 2048^2 against 0.8 ms with 16 (PoCL, 2 cores).
constexpr int kCpuLanes = 16;
constexpr int kCpuBandHeight = 32;
// From this many samples a texel the CPU build resolves the depths once, writing the integer
// texels into the table for the band scan to read back (2048^2, PoCL, 2 cores, the three
// kernels timed by profiling events: S = 2 8.5 against 10.5 ms; S = 1 7.9 against 7.0).
constexpr int kCpuTexelPassSamples = 2;

using detail::size_text;
using detail::texel_count;

void validate_table_shape(const char* call, int width, int height) {
    detail::validate_map_size(std::string(call) + ": size", width, height);
}

// ", 4 array layers" for texture arrays, nothing for one map.
std::string layers_text(int layers) {
    return layers == 1 ? std::string() : ", " + std::to_string(layers) + " array layers";
}

void validate_samples(int samples) {
    if (!is_supported_sample_count(samples))
        throw input_error("sat: unsupported sample count " + std::to_string(samples) + " (supported: 1, 2, 4, 8, 16)");
}

// Buffers of a call against the device's largest allocation.
void validate_device_bytes(const DeviceInfo& device, unsigned long long bytes, const std::string& what) {
    if (device.max_alloc_bytes != 0 && bytes > device.max_alloc_bytes)
        throw device_error("sat: " + what + " needs " + std::to_string(bytes) + " bytes, more than the device's " +
                          "largest buffer (" + std::to_string(device.max_alloc_bytes) + " bytes)");
}

void require_buffer_bytes(cl_mem buffer, cl_ulong bytes, const std::string& what) {
    if (!buffer) throw input_error("sat: the " + what + " buffer is null");
    const cl_ulong held = detail::buffer_size(buffer);
    if (held < bytes)
        throw input_error("sat: the " + what + " buffer holds " + std::to_string(held) + " bytes, " +
                          std::to_string(bytes) + " are needed");
}

// What the table is built from.
struct SatSource {
    bool is_depth = true; // depth map (else ready integer texels)
    int samples = 1;
    DepthRange depth_range = DepthRange::zero_one;
    std::uint32_t scale = 0;
    int layers = 1; // array layers (texture arrays): every buffer holds layer after layer
};

// Compile-time variant: input kind, sample count, depth convention, tile or band size.
// `step1_texels`: ready texels in the layout step 1 of the CPU build leaves (MSM_SAT_SOURCE 2).
std::vector<std::string> build_defines(const SatSource& source, SatKernel kernel, bool step1_texels = false) {
    return detail::sat_build_defines(source.is_depth, source.samples, source.depth_range, kernel, step1_texels,
                                     source.layers > 1);
}

cl::Buffer scratch_buffer(detail::ContextImpl& impl, std::size_t words, const char* what) {
    cl_int status = CL_SUCCESS;
    cl::Buffer buffer(impl.context, CL_MEM_READ_WRITE, words * sizeof(cl_uint), nullptr, &status);
    detail::check(status, what);
    return buffer;
}

// `range` (1D or 2D) with the array layers as a third dimension (`fill` in it: the layer
// count for the global range, 1 for a work-group); unchanged for one map or no range.
cl::NDRange over_layers(const cl::NDRange& range, int layers, std::size_t fill) {
    if (layers == 1 || range.dimensions() == 0) return range;
    return cl::NDRange(range.get()[0], range.dimensions() > 1 ? range.get()[1] : 1, fill);
}

// One launch of `kernel` over every array layer of `layers`.
void launch(const cl::CommandQueue& queue, cl::Kernel& kernel, const cl::NDRange& global, const cl::NDRange& local,
            const std::vector<cl::Event>& waits, cl::Event& done, const char* call, int layers = 1) {
    detail::check(queue.enqueueNDRangeKernel(kernel, cl::NullRange,
                                             over_layers(global, layers, static_cast<std::size_t>(layers)),
                                             over_layers(local, layers, 1), waits.empty() ? nullptr : &waits, &done),
                  call);
}

// Sets the common arguments (source, width, height, scale) of a build kernel.
void set_source_arguments(cl::Kernel& kernel, const cl::Buffer& source, int width, int height, std::uint32_t scale) {
    detail::set_arg(kernel, 0, source);
    detail::set_arg(kernel, 1, static_cast<cl_int>(width));
    detail::set_arg(kernel, 2, static_cast<cl_int>(height));
    detail::set_arg(kernel, 3, static_cast<cl_uint>(scale));
}

// The baseline of the papers: one work-item per row, then one per column in place.
cl::Event enqueue_rows_per_thread(detail::ContextImpl& impl, const cl::CommandQueue& queue,
                                  const std::vector<cl::Event>& waits, const cl::Buffer& source,
                                  const SatSource& what, int width, int height, const cl::Buffer& table) {
    const std::vector<std::string> defines = build_defines(what, SatKernel::row_per_thread);
    cl::Kernel& rows = impl.kernel("sat_build.cl", defines, "sat_rows_per_thread");
    set_source_arguments(rows, source, width, height, what.scale);
    detail::set_arg(rows, 4, table);
    cl::Event rows_done;
    launch(queue, rows, cl::NDRange(static_cast<std::size_t>(height)), cl::NullRange, waits, rows_done,
           "clEnqueueNDRangeKernel(sat_rows_per_thread)", what.layers);
    cl::Kernel& columns = impl.kernel("sat_build.cl", defines, "sat_columns_per_thread");
    detail::set_arg(columns, 0, table);
    detail::set_arg(columns, 1, static_cast<cl_int>(width));
    detail::set_arg(columns, 2, static_cast<cl_int>(height));
    cl::Event last;
    launch(queue, columns, cl::NDRange(static_cast<std::size_t>(width)), cl::NullRange, {rows_done}, last,
           "clEnqueueNDRangeKernel(sat_columns_per_thread)", what.layers);
    return last;
}

// CPU: bands of full rows (kernels/sat_build_cpu.cl); the only carries are the column sums
// above each band.
cl::Event enqueue_band_scan(detail::ContextImpl& impl, const cl::CommandQueue& queue,
                            std::vector<cl::Event> waits, const cl::Buffer& source, const SatSource& what,
                            int width, int height, const cl::Buffer& table) {
    const std::vector<std::string> defines = build_defines(what, SatKernel::tiled_cpu);
    const int bands = (height + kCpuBandHeight - 1) / kCpuBandHeight;
    const int padded_width = (width + kCpuLanes - 1) / kCpuLanes * kCpuLanes;
    const char* const carries_scratch = "sat band totals";
    cl::Buffer column_carries = impl.scratch(carries_scratch, 16 * texel_count(padded_width, bands) * what.layers, waits);
    // Groups of one work-item: the bands share nothing, and a fixed size means one
    // compilation for every map size.
    const cl::NDRange band_grid(static_cast<std::size_t>(bands));
    const cl::NDRange one_item(1);

    // Depth maps of many samples: step 1 also writes the integer texels into the table and
    // step 3 scans them in place, instead of resolving every depth twice.
    const bool texel_pass = what.is_depth && what.samples >= kCpuTexelPassSamples;

    // 1. Column sums of each band.
    cl::Kernel& totals =
        impl.kernel("sat_build_cpu.cl", defines, texel_pass ? "sat_band_totals_texels_cpu" : "sat_band_totals_cpu");
    set_source_arguments(totals, source, width, height, what.scale);
    detail::set_arg(totals, 4, column_carries);
    if (texel_pass) detail::set_arg(totals, 5, table);
    cl::Event totals_done;
    launch(queue, totals, band_grid, one_item, waits, totals_done, "clEnqueueNDRangeKernel(sat_band_totals_cpu)",
           what.layers);

    // 2. Down the bands: the sums of each column above every band, in place.
    cl::Kernel& carries = impl.kernel("sat_carries.cl", detail::sat_carries_defines(what.layers > 1),
                                      "sat_column_carries");
    detail::set_arg(carries, 0, column_carries);
    detail::set_arg(carries, 1, static_cast<cl_int>(padded_width));
    detail::set_arg(carries, 2, static_cast<cl_int>(bands));
    cl::Event carries_done;
    launch(queue, carries, cl::NDRange(static_cast<std::size_t>(padded_width)), cl::NullRange, {totals_done},
           carries_done, "clEnqueueNDRangeKernel(sat_column_carries)", what.layers);

    // 3. Each band scanned from its carries, written once.
    SatSource texels = what;
    texels.is_depth = false;
    cl::Kernel& scan =
        impl.kernel("sat_build_cpu.cl", texel_pass ? build_defines(texels, SatKernel::tiled_cpu, true) : defines,
                    "sat_band_scan_cpu");
    set_source_arguments(scan, texel_pass ? table : source, width, height, what.scale);
    detail::set_arg(scan, 4, column_carries);
    detail::set_arg(scan, 5, table);
    cl::Event last;
    launch(queue, scan, band_grid, one_item, {carries_done}, last, "clEnqueueNDRangeKernel(sat_band_scan_cpu)",
           what.layers);
    impl.scratch_used(carries_scratch, last);
    return last;
}

// GPU: 32x32 tiles in local memory (kernels/sat_build.cl), carries between tiles in
// columns, rows and corners.
cl::Event enqueue_tiled_gpu(detail::ContextImpl& impl, const cl::CommandQueue& queue,
                            std::vector<cl::Event> waits, const cl::Buffer& source, const SatSource& what,
                            int width, int height, const cl::Buffer& table) {
    const std::vector<std::string> defines = build_defines(what, SatKernel::tiled_gpu);
    const int tiles_x = (width + kGpuTile - 1) / kGpuTile;
    const int tiles_y = (height + kGpuTile - 1) / kGpuTile;
    const int padded_width = tiles_x * kGpuTile;
    const int padded_height = tiles_y * kGpuTile;
    const char* const scratch_names[] = {"sat column carries", "sat row carries", "sat tile totals",
                                         "sat corner carries"};
    // Carries of every array layer, layer after layer.
    const std::size_t layers = static_cast<std::size_t>(what.layers);
    cl::Buffer column_carries = impl.scratch(scratch_names[0], 16 * texel_count(padded_width, tiles_y) * layers, waits);
    cl::Buffer row_carries = impl.scratch(scratch_names[1], 16 * texel_count(tiles_x, padded_height) * layers, waits);
    cl::Buffer tile_totals = impl.scratch(scratch_names[2], 16 * texel_count(tiles_x, tiles_y) * layers, waits);
    cl::Buffer corner_carries = impl.scratch(scratch_names[3], 16 * texel_count(tiles_x, tiles_y) * layers, waits);
    const std::vector<std::string> carries_defines = detail::sat_carries_defines(what.layers > 1);
    const cl::NDRange tile_grid(static_cast<std::size_t>(padded_width), static_cast<std::size_t>(tiles_y));
    const cl::NDRange tile_group(static_cast<std::size_t>(kGpuTile), 1);

    // 1. Totals per tile.
    cl::Kernel& totals = impl.kernel("sat_build.cl", defines, "sat_tile_totals");
    // The tiles need kGpuTile work-items per group; the built kernel may allow fewer.
    const std::size_t limit = totals.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(impl.device);
    if (limit < static_cast<std::size_t>(kGpuTile))
        throw device_error("sat: device '" + impl.info.name + "' runs the tiled_gpu kernels with at most " +
                           std::to_string(limit) + " work-items per group, they need " + std::to_string(kGpuTile) +
                           " (use SatKernel::tiled_cpu)");
    set_source_arguments(totals, source, width, height, what.scale);
    detail::set_arg(totals, 4, column_carries);
    detail::set_arg(totals, 5, row_carries);
    detail::set_arg(totals, 6, tile_totals);
    cl::Event totals_done;
    launch(queue, totals, tile_grid, tile_group, waits, totals_done, "clEnqueueNDRangeKernel(sat_tile_totals)",
           what.layers);

    // 2. Carries across tiles: columns, rows, corners (independent of each other).
    const std::vector<cl::Event> after_totals{totals_done};
    cl::Kernel& columns = impl.kernel("sat_carries.cl", carries_defines, "sat_column_carries");
    detail::set_arg(columns, 0, column_carries);
    detail::set_arg(columns, 1, static_cast<cl_int>(padded_width));
    detail::set_arg(columns, 2, static_cast<cl_int>(tiles_y));
    cl::Event columns_done;
    launch(queue, columns, cl::NDRange(static_cast<std::size_t>(padded_width)), cl::NullRange, after_totals,
           columns_done, "clEnqueueNDRangeKernel(sat_column_carries)", what.layers);
    cl::Kernel& rows = impl.kernel("sat_carries.cl", carries_defines, "sat_row_carries");
    detail::set_arg(rows, 0, row_carries);
    detail::set_arg(rows, 1, static_cast<cl_int>(padded_height));
    detail::set_arg(rows, 2, static_cast<cl_int>(tiles_x));
    cl::Event rows_done;
    launch(queue, rows, cl::NDRange(static_cast<std::size_t>(padded_height)), cl::NullRange, after_totals, rows_done,
           "clEnqueueNDRangeKernel(sat_row_carries)", what.layers);
    cl::Kernel& corners = impl.kernel("sat_carries.cl", carries_defines, "sat_corner_carries");
    detail::set_arg(corners, 0, tile_totals);
    detail::set_arg(corners, 1, static_cast<cl_int>(tiles_x));
    detail::set_arg(corners, 2, static_cast<cl_int>(tiles_y));
    detail::set_arg(corners, 3, corner_carries);
    cl::Event corners_done;
    launch(queue, corners, cl::NDRange(static_cast<std::size_t>(tiles_x)), cl::NullRange, after_totals, corners_done,
           "clEnqueueNDRangeKernel(sat_corner_carries)", what.layers);

    // 3. Each tile scanned from its carries, written once.
    cl::Kernel& tile_scan = impl.kernel("sat_build.cl", defines, "sat_tile_scan");
    set_source_arguments(tile_scan, source, width, height, what.scale);
    detail::set_arg(tile_scan, 4, column_carries);
    detail::set_arg(tile_scan, 5, row_carries);
    detail::set_arg(tile_scan, 6, corner_carries);
    detail::set_arg(tile_scan, 7, table);
    cl::Event last;
    launch(queue, tile_scan, tile_grid, tile_group, {columns_done, rows_done, corners_done}, last,
           "clEnqueueNDRangeKernel(sat_tile_scan)", what.layers);
    for (const char* name : scratch_names) impl.scratch_used(name, last);
    return last;
}

// Enqueues the whole build on `queue` with the given distribution; returns the event of
// its last command.
cl::Event enqueue_build(detail::ContextImpl& impl, const cl::CommandQueue& queue, const std::vector<cl::Event>& waits,
                        const cl::Buffer& source, const SatSource& what, int width, int height,
                        const cl::Buffer& table, SatKernel kernel) {
    validate_device_bytes(impl.info, 16ull * texel_count(width, height) * what.layers,
                          "the " + size_text(width, height) + " table" + layers_text(what.layers));
    // Scratch held by this call is released even when an enqueue throws.
    const detail::ContextImpl::ScratchSession scratch_session(impl);
    switch (kernel) {
    case SatKernel::row_per_thread:
        return enqueue_rows_per_thread(impl, queue, waits, source, what, width, height, table);
    case SatKernel::tiled_cpu: return enqueue_band_scan(impl, queue, waits, source, what, width, height, table);
    default: return enqueue_tiled_gpu(impl, queue, waits, source, what, width, height, table);
    }
}

// Translucent layers (kernels/sat_translucent.cl): the composited texels into a scratch
// buffer, then the prefix sums of ready texels.
cl::Event enqueue_translucent_build(detail::ContextImpl& impl, const cl::CommandQueue& queue,
                                    const std::vector<cl::Event>& waits, const cl::Buffer& depth,
                                    const cl::Buffer& layer_depth, const cl::Buffer& layer_opacity, int layers,
                                    const SatSource& what, int width, int height, const cl::Buffer& table,
                                    SatKernel kernel) {
    validate_device_bytes(impl.info, 16ull * texel_count(width, height) * what.layers,
                          "the " + size_text(width, height) + " texels" + layers_text(what.layers));
    cl::Buffer texels = scratch_buffer(impl, 4 * texel_count(width, height) * what.layers,
                                       "clCreateBuffer(sat translucent texels)");
    cl::Kernel& composite = impl.kernel(
        "sat_translucent.cl", detail::sat_translucent_defines(what.samples, layers, what.depth_range, what.layers > 1),
        "sat_translucent_texels");
    detail::set_arg(composite, 0, depth);
    detail::set_arg(composite, 1, layer_depth);
    detail::set_arg(composite, 2, layer_opacity);
    detail::set_arg(composite, 3, static_cast<cl_int>(width));
    detail::set_arg(composite, 4, static_cast<cl_int>(height));
    detail::set_arg(composite, 5, static_cast<cl_uint>(what.scale));
    detail::set_arg(composite, 6, texels);
    cl::Event composited;
    launch(queue, composite, cl::NDRange(static_cast<std::size_t>(width), static_cast<std::size_t>(height)),
           cl::NullRange, waits, composited, "clEnqueueNDRangeKernel(sat_translucent_texels)", what.layers);
    // The texels buffer is released here; OpenCL keeps it until the prefix sums are done.
    return enqueue_build(impl, queue, {composited}, texels, SatSource{false, 1, DepthRange::zero_one, 0, what.layers},
                         width, height, table, kernel);
}

SatKernel resolve_kernel(const DeviceInfo& device, SatKernel kernel) { return detail::sat_kernel_for(device, kernel); }

// A host table must be what build_sat produces.
void validate_table(const SatTable& table, const char* call) {
    validate_table_shape(call, table.width, table.height);
    detail::require_single_layer(call, "the table", table.layers);
    sat_scale(table.max_kernel_texels);
    if (table.scale != msm_sat_scale(table.max_kernel_texels))
        throw input_error(std::string(call) + ": table scale " + std::to_string(table.scale) +
                          " does not match N = " + std::to_string(table.max_kernel_texels) + " (expected " +
                          std::to_string(msm_sat_scale(table.max_kernel_texels)) + ")");
    if (table.words.size() != 4 * texel_count(table.width, table.height))
        throw input_error(std::string(call) + ": table holds " + std::to_string(table.words.size()) + " words, a " +
                          size_text(table.width, table.height) + " table needs " +
                          std::to_string(4 * texel_count(table.width, table.height)));
}

std::string rectangle_text(int x0, int y0, int x1, int y1) {
    return "[" + std::to_string(x0) + ", " + std::to_string(x1) + "] x [" + std::to_string(y0) + ", " +
           std::to_string(y1) + "]";
}

Moments4 moments_of_basis(const msm_sat_basis& mean) {
    const msm_moments m = msm_sat_moments_of_basis(mean);
    return {m.b1, m.b2, m.b3, m.b4};
}

} // namespace

namespace detail {

// automatic: the CPU distribution on CPUs that are not GPUs, the GPU one elsewhere
// (runtime/work_distribution.hpp).
SatKernel sat_kernel_for(const DeviceInfo& device, SatKernel requested) {
    if (requested != SatKernel::automatic) return requested;
    return prefers_gpu_distribution(device) ? SatKernel::tiled_gpu : SatKernel::tiled_cpu;
}

// Compile-time variant: input kind, sample count, depth convention, tile or band size.
// `step1_texels`: ready texels in the layout step 1 of the CPU build leaves (MSM_SAT_SOURCE 2).
std::vector<std::string> sat_build_defines(bool is_depth, int samples, DepthRange range, SatKernel kernel,
                                           bool step1_texels, bool array) {
    const bool zero_one = !is_depth || range == DepthRange::zero_one;
    std::vector<std::string> defines = {
        "MSM_SAT_SOURCE=" + std::string(is_depth ? "0" : step1_texels ? "2" : "1"),
        "MSM_SAMPLES=" + std::to_string(is_depth ? samples : 1),
        "MSM_DEPTH_ZERO_ONE=" + std::string(zero_one ? "1" : "0"),
        kernel == SatKernel::tiled_cpu ? "MSM_SAT_BAND_H=" + std::to_string(kCpuBandHeight)
                                       : "MSM_SAT_TILE=" + std::to_string(kGpuTile)};
    // Texture arrays: the layer-slicing program (single maps keep the plain one).
    if (array) defines.push_back("MSM_ARRAY=1");
    return defines;
}

std::vector<std::string> sat_translucent_defines(int samples, int layers, DepthRange range, bool array) {
    std::vector<std::string> defines = {"MSM_SAMPLES=" + std::to_string(samples), "MSM_LAYERS=" + std::to_string(layers),
                                        "MSM_DEPTH_ZERO_ONE=" + std::string(range == DepthRange::zero_one ? "1" : "0")};
    if (array) defines.push_back("MSM_ARRAY=1");
    return defines;
}

std::vector<std::string> sat_carries_defines(bool array) {
    return array ? std::vector<std::string>{"MSM_ARRAY=1"} : std::vector<std::string>{};
}

} // namespace detail

std::uint32_t sat_scale(std::uint32_t max_kernel_texels) {
    if (max_kernel_texels < sat_min_kernel_texels || max_kernel_texels > sat_max_kernel_texels)
        throw input_error("sat: the largest kernel N = " + std::to_string(max_kernel_texels) + " texels is outside [" +
                          std::to_string(sat_min_kernel_texels) + ", " + std::to_string(sat_max_kernel_texels) + "]");
    return msm_sat_scale(max_kernel_texels);
}

SatTable build_sat(Context& context, const DepthImage& depth, const SatOptions& options) {
    return build_sat(context, depth, std::vector<TranslucentLayer>{}, options);
}

SatTable build_sat(Context& context, const DepthImage& depth, const std::vector<TranslucentLayer>& layers,
                   const SatOptions& options) {
    // Validate everything before touching the device.
    validate_table_shape("sat: depth map", depth.width, depth.height);
    validate_samples(depth.samples);
    detail::validate_array_layers("sat", depth.layers);
    const std::size_t layers_in_depth = static_cast<std::size_t>(depth.layers);
    const std::size_t values = texel_count(depth.width, depth.height) * depth.samples * layers_in_depth;
    if (depth.depth.size() != values)
        throw input_error("sat: depth map " + size_text(depth.width, depth.height) + " with " +
                          std::to_string(depth.samples) + " samples" + layers_text(depth.layers) + " needs " +
                          std::to_string(values) + " values, got " + std::to_string(depth.depth.size()));
    const std::uint32_t scale = sat_scale(options.max_kernel_texels);
    detail::validate_depth_values("sat", depth, options.depth_range);
    detail::validate_layers("sat", depth, layers, options.depth_range);
    detail::ContextImpl& impl = context.impl();
    validate_device_bytes(impl.info, values * sizeof(float), "the depth buffer");
    validate_device_bytes(impl.info, layers.size() * values * sizeof(float), "the translucent layers");

    // Upload (the translucent layers one after the other), build on the Context's queue, read back.
    detail::StageTimer stages(impl, options.on_stage);
    SatTable table;
    table.width = depth.width;
    table.height = depth.height;
    table.max_kernel_texels = options.max_kernel_texels;
    table.scale = scale;
    table.layers = depth.layers;
    table.words.resize(4 * texel_count(depth.width, depth.height) * layers_in_depth);
    const cl::Buffer depth_buffer =
        detail::upload_in_place(impl, depth.depth.data(), values * sizeof(float), "clCreateBuffer(depth)");
    const std::size_t table_bytes = table.words.size() * sizeof(std::uint32_t);
    const cl::Buffer table_buffer =
        detail::result_buffer(impl, table.words.data(), table_bytes, "clCreateBuffer(sat table)");
    const SatSource source{true, depth.samples, options.depth_range, scale, depth.layers};
    const SatKernel kernel = resolve_kernel(impl.info, options.kernel);
    cl::Buffer depth_layers, opacity_layers;
    if (!layers.empty()) {
        std::vector<float> layer_depth = detail::concatenated_depths(layers, depth.layers);
        std::vector<float> layer_opacity = detail::concatenated_opacities(layers, depth.layers);
        depth_layers = detail::upload(impl, layer_depth.data(), layer_depth.size() * sizeof(float),
                                      "clCreateBuffer(layer depth)");
        opacity_layers = detail::upload(impl, layer_opacity.data(), layer_opacity.size() * sizeof(float),
                                        "clCreateBuffer(layer opacity)");
    }
    stages.uploaded({&depth_buffer, &depth_layers, &opacity_layers});
    const cl::Event done =
        layers.empty()
            ? enqueue_build(impl, impl.queue, {}, depth_buffer, source, depth.width, depth.height, table_buffer, kernel)
            : enqueue_translucent_build(impl, impl.queue, {}, depth_buffer, depth_layers, opacity_layers,
                                        static_cast<int>(layers.size()), source, depth.width, depth.height,
                                        table_buffer, kernel);
    stages.computed();
    detail::read_result(impl, table_buffer, table_bytes, table.words.data(), done, "clEnqueueReadBuffer(sat table)");
    stages.downloaded(table_buffer, table_bytes);
    return table;
}

void build_sat(Context& context, const DeviceDepth& depth, cl_mem table, const SatOptions& options,
               const Enqueue& enqueue) {
    build_sat(context, depth, DeviceLayers{}, table, options, enqueue);
}

void build_sat(Context& context, const DeviceDepth& depth, const DeviceLayers& layers, cl_mem table,
               const SatOptions& options, const Enqueue& enqueue) {
    validate_table_shape("sat: depth map", depth.width, depth.height);
    validate_samples(depth.samples);
    detail::validate_array_layers("sat", depth.layers);
    detail::validate_layer_count("sat", layers.count);
    const std::uint32_t scale = sat_scale(options.max_kernel_texels);
    // The caller's buffers hold every array layer.
    const cl_ulong array_layers = static_cast<cl_ulong>(depth.layers);
    const cl_ulong depth_bytes = texel_count(depth.width, depth.height) * depth.samples * sizeof(float) * array_layers;
    require_buffer_bytes(depth.buffer, depth_bytes, "depth");
    require_buffer_bytes(table, 16ull * texel_count(depth.width, depth.height) * array_layers, "table");
    if (layers.count > 0) {
        require_buffer_bytes(layers.depth, depth_bytes * static_cast<cl_ulong>(layers.count), "layer depth");
        require_buffer_bytes(layers.opacity, depth_bytes * static_cast<cl_ulong>(layers.count), "layer opacity");
    }
    detail::ContextImpl& impl = context.impl();
    const cl::CommandQueue queue = impl.queue_for(enqueue);
    const SatSource source{true, depth.samples, options.depth_range, scale, depth.layers};
    const SatKernel kernel = resolve_kernel(impl.info, options.kernel);
    const cl::Event last =
        layers.count == 0
            ? enqueue_build(impl, queue, detail::wait_list(enqueue), cl::Buffer(depth.buffer, true), source, depth.width,
                            depth.height, cl::Buffer(table, true), kernel)
            : enqueue_translucent_build(impl, queue, detail::wait_list(enqueue), cl::Buffer(depth.buffer, true),
                                        cl::Buffer(layers.depth, true), cl::Buffer(layers.opacity, true), layers.count,
                                        source, depth.width, depth.height, cl::Buffer(table, true), kernel);
    detail::complete(enqueue, queue, last);
}

std::vector<std::uint32_t> sat_prefix_sums(Context& context, const std::vector<std::uint32_t>& texels, int width,
                                           int height, SatKernel kernel) {
    validate_table_shape("sat: texels", width, height);
    const std::size_t words = 4 * texel_count(width, height);
    if (texels.size() != words)
        throw input_error("sat: " + size_text(width, height) + " texels need " + std::to_string(words) +
                          " words, got " + std::to_string(texels.size()));
    detail::ContextImpl& impl = context.impl();
    cl_int status = CL_SUCCESS;
    cl::Buffer input(impl.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, words * sizeof(std::uint32_t),
                     const_cast<std::uint32_t*>(texels.data()), &status);
    detail::check(status, "clCreateBuffer(sat texels)");
    cl::Buffer output(impl.context, CL_MEM_READ_WRITE, words * sizeof(std::uint32_t), nullptr, &status);
    detail::check(status, "clCreateBuffer(sat table)");
    const cl::Event done = enqueue_build(impl, impl.queue, {}, input, SatSource{false, 1, DepthRange::zero_one, 0},
                                         width, height, output, resolve_kernel(impl.info, kernel));
    std::vector<std::uint32_t> table(words);
    const std::vector<cl::Event> after_build{done};
    detail::check(impl.queue.enqueueReadBuffer(output, CL_TRUE, 0, words * sizeof(std::uint32_t), table.data(),
                                               &after_build),
                  "clEnqueueReadBuffer(sat table)");
    return table;
}

void sat_prefix_sums(Context& context, cl_mem texels, cl_mem table, int width, int height, SatKernel kernel,
                     const Enqueue& enqueue) {
    validate_table_shape("sat: texels", width, height);
    const cl_ulong bytes = 16ull * texel_count(width, height);
    require_buffer_bytes(texels, bytes, "texels");
    require_buffer_bytes(table, bytes, "table");
    if (texels == table) throw input_error("sat: the texels and table buffers must be distinct");
    detail::ContextImpl& impl = context.impl();
    const cl::CommandQueue queue = impl.queue_for(enqueue);
    const cl::Event last = enqueue_build(impl, queue, detail::wait_list(enqueue), cl::Buffer(texels, true),
                                         SatSource{false, 1, DepthRange::zero_one, 0}, width, height,
                                         cl::Buffer(table, true), resolve_kernel(impl.info, kernel));
    detail::complete(enqueue, queue, last);
}

std::array<std::uint32_t, 4> sat_rectangle_sum(const SatTable& table, int x0, int y0, int x1, int y1) {
    validate_table(table, "sat query");
    if (x0 > x1 || y0 > y1 || x0 < 0 || y0 < 0 || x1 >= table.width || y1 >= table.height)
        throw input_error("sat query: rectangle " + rectangle_text(x0, y0, x1, y1) + " is empty or leaves the " +
                          size_text(table.width, table.height) + " table");
    const unsigned long long texels = static_cast<unsigned long long>(x1 - x0 + 1) * (y1 - y0 + 1);
    if (texels > table.max_kernel_texels)
        throw input_error("sat query: rectangle " + rectangle_text(x0, y0, x1, y1) + " holds " +
                          std::to_string(texels) + " texels, more than N = " +
                          std::to_string(table.max_kernel_texels));
    const msm_sat_sum s = msm_sat_rectangle_sum(table.words.data(), table.width, x0, y0, x1, y1);
    return {s.c0, s.c1, s.c2, s.c3};
}

Moments4 sat_rectangle_moments(const SatTable& table, int x0, int y0, int x1, int y1) {
    const std::array<std::uint32_t, 4> sums = sat_rectangle_sum(table, x0, y0, x1, y1);
    msm_sat_sum s;
    s.c0 = sums[0];
    s.c1 = sums[1];
    s.c2 = sums[2];
    s.c3 = sums[3];
    const float texels = static_cast<float>(static_cast<long long>(x1 - x0 + 1) * (y1 - y0 + 1));
    return moments_of_basis(msm_sat_mean_of_sum(s, table.scale, texels));
}

Moments4 sat_interpolated_moments(const SatTable& table, const SatRectangle& r) {
    validate_table(table, "sat query");
    const bool finite = std::isfinite(r.left) && std::isfinite(r.top) && std::isfinite(r.right) && std::isfinite(r.bottom);
    if (!finite || !(r.left < r.right) || !(r.top < r.bottom) || r.left < 0.0f || r.top < 0.0f ||
        r.right > static_cast<float>(table.width) || r.bottom > static_cast<float>(table.height)) {
        std::ostringstream text;
        text << "sat query: rectangle [" << r.left << ", " << r.right << ") x [" << r.top << ", " << r.bottom
             << ") is empty, not finite or leaves the " << size_text(table.width, table.height) << " table";
        throw input_error(text.str());
    }
    if (!msm_sat_interpolation_fits(r.left, r.top, r.right, r.bottom, table.max_kernel_texels)) {
        std::ostringstream text;
        text << "sat query: rectangle [" << r.left << ", " << r.right << ") x [" << r.top << ", " << r.bottom
             << ") needs sums over more than N = " << table.max_kernel_texels << " texels";
        throw input_error(text.str());
    }
    return moments_of_basis(
        msm_sat_interpolated_mean(table.words.data(), table.width, table.scale, r.left, r.top, r.right, r.bottom));
}

void sat_query_moments(Context& context, const DeviceSat& table, cl_mem rectangles, std::size_t count, cl_mem moments,
                       const Enqueue& enqueue) {
    validate_table_shape("sat query", table.width, table.height);
    const std::uint32_t scale = sat_scale(table.max_kernel_texels);
    require_buffer_bytes(table.buffer, 16ull * texel_count(table.width, table.height), "table");
    if (count > std::numeric_limits<cl_uint>::max())
        throw input_error("sat query: too many rectangles in one call (" + std::to_string(count) + ")");
    detail::ContextImpl& impl = context.impl();
    const cl::CommandQueue queue = impl.queue_for(enqueue);
    std::vector<cl::Event> waits = detail::wait_list(enqueue);
    cl::Event done;
    if (count == 0) {
        detail::complete_without_work(enqueue, queue);
        return;
    }
    require_buffer_bytes(rectangles, 16ull * count, "rectangles");
    require_buffer_bytes(moments, 16ull * count, "moments");
    cl::Kernel& kernel = impl.kernel("sat_query.cl", {}, "sat_query_moments");
    detail::set_arg(kernel, 0, table.buffer);
    detail::set_arg(kernel, 1, static_cast<cl_int>(table.width));
    detail::set_arg(kernel, 2, static_cast<cl_int>(table.height));
    detail::set_arg(kernel, 3, static_cast<cl_uint>(scale));
    detail::set_arg(kernel, 4, static_cast<cl_uint>(table.max_kernel_texels));
    detail::set_arg(kernel, 5, rectangles);
    detail::set_arg(kernel, 6, static_cast<cl_uint>(count));
    detail::set_arg(kernel, 7, moments);
    // Groups of 64, or fewer where the built kernel allows fewer (docs/devices.md).
    const std::size_t group = detail::fitting_group(detail::kernel_fit(impl, kernel), 64);
    launch(queue, kernel, cl::NDRange((count + group - 1) / group * group), cl::NDRange(group), waits, done,
           "clEnqueueNDRangeKernel(sat_query_moments)");
    detail::complete(enqueue, queue, done);
}

SatTable SatTable::layer(int index) const {
    if (index < 0 || index >= layers)
        throw input_error("sat: array layer " + std::to_string(index) + " of a table of " + std::to_string(layers) +
                          " layers");
    const std::size_t layer_words = 4 * texel_count(width, height);
    if (words.size() != layer_words * static_cast<std::size_t>(layers))
        throw input_error("sat: the table holds " + std::to_string(words.size()) + " words, " +
                          std::to_string(layers) + " layers need " +
                          std::to_string(layer_words * static_cast<std::size_t>(layers)));
    const auto first = words.begin() + static_cast<std::ptrdiff_t>(layer_words * static_cast<std::size_t>(index));
    return SatTable{width, height, max_kernel_texels, scale,
                    std::vector<std::uint32_t>(first, first + static_cast<std::ptrdiff_t>(layer_words))};
}

// The names of SatKernel values, both ways (sat_kernel_name, parse_sat_kernel).
constexpr detail::EnumNames<SatKernel> sat_kernel_names[] = {
    {SatKernel::automatic, "automatic"},
    {SatKernel::tiled_gpu, "tiled_gpu"},
    {SatKernel::tiled_cpu, "tiled_cpu"},
    {SatKernel::row_per_thread, "row_per_thread"},
};

const char* sat_kernel_name(SatKernel kernel) noexcept { return detail::name_in(sat_kernel_names, kernel); }

std::optional<SatKernel> parse_sat_kernel(std::string_view name) noexcept {
    return detail::parse_in(sat_kernel_names, name);
}

SatKernel sat_kernel_for(const Context& context, SatKernel requested) {
    return resolve_kernel(context.device(), requested);
}

} // namespace msmcl
