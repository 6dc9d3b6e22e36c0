// Cases of the summed-area table work (docs/kernels.md), all on the workload's device and depth map,
// measured once per (size, samples) (the rows carry format msm64, the basis the table uses):
//   sat_copy            a kernel moving the table's minimum bytes (the S depths in, 16 bytes
//                       out per texel): the memory roof of the SAT rows, the faster of a copy
//                       per texel and one per 16 texels in vectors (extra.copy_kernel)
//   sat                 build_sat with the kernel the library picks for the device
//   sat_tiled_gpu       the local-memory tiled scan (the GPU distribution)
//   sat_tiled_cpu       bands of 32 full rows in 16-lane vectors (the CPU distribution)
//   sat_row_per_thread  the papers' one-thread-per-row scan, then one thread per column
//   soft_msm_published  soft_shade as published (receiver weight 0, one filter query): moment
//                       soft shadows of 2^18 receivers on the map's surface
//   soft_msm            the same with the library's default refinements, timed in turns with it
//   pcss_15, pcss_27    brute-force PCSS of the same receivers with a 15x15 / 27x27 search
// The copies and the builds are timed in turns (copy, copy, baseline, sat, ...; repeated,
// each timed run right after an untimed one of its own), so a slow phase of the machine
// hits them alike. Every SAT row reports `bytes` = the minimum (depths once, table once), so GB/s
// compare; `sat_copy_roof_fraction` is sat_copy's time over the row's and
// `speedup_over_row_per_thread` the median of the per-turn ratios. Table rows record whether
// they equal the baseline's table bit for bit; soft rows the cost per receiver.
#include "harness.hpp"
#include "scene.hpp"
#include "runtime/context_impl.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/sat.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <tuple>

namespace msmcl::bench {

namespace {

constexpr std::uint32_t kMaxKernel = 27 * 27;

// Kernels that are not part of the library: the copy roof and brute-force PCSS.
const char* const kSatBenchSource = R"CLC(
// Every texel: the sum of its samples (no load can be dropped), written as 4 words.
__kernel void sat_copy(__global const float* depth, __global uint* table, uint texels) {
    const size_t t = get_global_id(0);
    if (t >= texels) return;
    float sum = 0.0f;
    for (int s = 0; s < SAMPLES; ++s) sum += depth[t * SAMPLES + s];
    table[4 * t + 0] = as_uint(sum);
    table[4 * t + 1] = as_uint(sum) + 1u;
    table[4 * t + 2] = as_uint(sum) + 2u;
    table[4 * t + 3] = as_uint(sum) + 3u;
}

// The same bytes, 16 texels a work-item as 16-lane vectors: the contiguous streams a CPU
// reads fastest (the per-texel copy reads S-strided floats across work-items).
__kernel void sat_copy_blocks(__global const float16* depth, __global uint16* table, uint blocks) {
    const size_t b = get_global_id(0);
    if (b >= blocks) return;
    float16 sum = depth[b * SAMPLES];
    for (int s = 1; s < SAMPLES; ++s) sum += depth[b * SAMPLES + s];
    const uint16 words = as_uint16(sum);
    table[4 * b + 0] = words;
    table[4 * b + 1] = words + 1u;
    table[4 * b + 2] = words + 2u;
    table[4 * b + 3] = words + 3u;
}

// Percentage-closer soft shadows by brute force (tests/reference/sat_reference.cpp
// pcss_shadow): every sample of the SEARCH x SEARCH texel square in front of zf is a
// blocker; filter side light_size * (zf - mean blocker depth), clamped; area-weighted share
// of the samples in front of zf over the filter square, clipped to the map.
__kernel void pcss(__global const float* depth, int width, int height, __global const float* uvz, uint count,
                   float depth_bias, float light_size, float min_filter, float max_filter,
                   __global float* intensity) {
    const size_t i = get_global_id(0);
    if (i >= count) return;
    const float u = clamp(uvz[i], 0.0f, (float)width);
    const float v = clamp(uvz[count + i], 0.0f, (float)height);
    const float zf = 2.0f * uvz[2 * (size_t)count + i] - 1.0f - depth_bias;
    const int sx = (int)floor(u + 0.5f - 0.5f * SEARCH), sy = (int)floor(v + 0.5f - 0.5f * SEARCH);
    const int x0 = max(sx, 0), y0 = max(sy, 0);
    const int x1 = min(sx + SEARCH - 1, width - 1), y1 = min(sy + SEARCH - 1, height - 1);
    float blockers = 0.0f, depth_sum = 0.0f;
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x)
            for (int s = 0; s < SAMPLES; ++s) {
                const float z = 2.0f * depth[((size_t)y * width + x) * SAMPLES + s] - 1.0f;
                if (z < zf) {
                    blockers += 1.0f;
                    depth_sum += z;
                }
            }
    if (blockers == 0.0f) {
        intensity[i] = 0.0f;
        return;
    }
    const float side = clamp(light_size * (zf - depth_sum / blockers), min_filter, max_filter);
    const float left = max(u - 0.5f * side, 0.0f), right = min(u + 0.5f * side, (float)width);
    const float top = max(v - 0.5f * side, 0.0f), bottom = min(v + 0.5f * side, (float)height);
    float shadow = 0.0f;
    for (int y = (int)floor(top); y < (int)ceil(bottom); ++y) {
        const float wy = min(bottom, y + 1.0f) - max(top, (float)y);
        for (int x = (int)floor(left); x < (int)ceil(right); ++x) {
            const float w = wy * (min(right, x + 1.0f) - max(left, (float)x));
            float in_front = 0.0f;
            for (int s = 0; s < SAMPLES; ++s)
                in_front += 2.0f * depth[((size_t)y * width + x) * SAMPLES + s] - 1.0f < zf ? 1.0f : 0.0f;
            shadow += w * in_front;
        }
    }
    intensity[i] = shadow / (SAMPLES * (right - left) * (bottom - top));
}
)CLC";

// The bench's kernels per (samples, search size), built and kept by the Context's program
// cache like the library's own (in memory and, with MSMCL_CACHE_DIR, on disk).
cl_kernel bench_kernel(Context& context, const char* name, int samples, int search) {
    detail::ContextImpl& impl = context.impl();
    const std::string options =
        "-cl-std=CL1.2 -DSAMPLES=" + std::to_string(samples) + " -DSEARCH=" + std::to_string(search);
    return impl.programs.kernel(impl.context, impl.device, "sat bench", kSatBenchSource, options, name)();
}

void set_arg(cl_kernel kernel, cl_uint index, std::size_t size, const void* value) {
    check_cl(clSetKernelArg(kernel, index, size, value), "clSetKernelArg(sat bench)");
}

// Table bytes every build must move at least: the depths once, the table once.
std::size_t sat_bytes(const Workload& work) { return work.texels() * (work.samples * sizeof(float) + 16); }

std::vector<CaseResult> run_sat(BenchEnv& env, const Workload& work) {
    if (work.format != Format::msm64) return {}; // once per (size, samples)
    Context& context = *env.context;
    const std::size_t table_bytes = 16 * work.texels();
    Buffer table(context, table_bytes);
    std::vector<CaseResult> rows;

    // The roof: the same bytes, no arithmetic; the faster of a copy per texel and one per 16
    // texels in vectors (the latter needs whole blocks of 16).
    struct Copy {
        const char* kernel_name;
        const char* label;
        std::size_t items;
        std::size_t group; // 0: the device picks
    };
    std::vector<Copy> copies = {{"sat_copy", "per_texel", work.texels(),
                                 std::min<std::size_t>(256, context.device().max_work_group_size)}};
    if (work.texels() % 16 == 0) copies.push_back({"sat_copy_blocks", "blocks_of_16", work.texels() / 16, 0});
    std::vector<std::function<void()>> runs;
    for (const Copy& c : copies) {
        cl_kernel kernel = bench_kernel(context, c.kernel_name, work.samples, 1);
        const cl_uint count = static_cast<cl_uint>(c.items);
        set_arg(kernel, 0, sizeof(cl_mem), &work.depth_buffer);
        set_arg(kernel, 1, sizeof(cl_mem), &table.mem);
        set_arg(kernel, 2, sizeof count, &count);
        runs.push_back([&context, kernel, c] {
            const std::size_t global = c.group ? (c.items + c.group - 1) / c.group * c.group : c.items;
            check_cl(clEnqueueNDRangeKernel(context.cl_queue_handle(), kernel, 1, nullptr, &global,
                                            c.group ? &c.group : nullptr, 0, nullptr, nullptr),
                     "clEnqueueNDRangeKernel(sat_copy)");
            context.finish();
        });
    }

    // The builds, the baseline first (its table is the reference of the others).
    // The distribution meant for the other kind of device runs last, out of the turns: on a
    // CPU, the tiled_gpu kernel slows whatever runs next for a while (PoCL, measured).
    const bool gpu = context.device().is_gpu;
    const std::tuple<const char*, SatKernel> builds[] = {
        {"sat_row_per_thread", SatKernel::row_per_thread},
        {"sat", SatKernel::automatic},
        {gpu ? "sat_tiled_gpu" : "sat_tiled_cpu", gpu ? SatKernel::tiled_gpu : SatKernel::tiled_cpu},
        {gpu ? "sat_tiled_cpu" : "sat_tiled_gpu", gpu ? SatKernel::tiled_cpu : SatKernel::tiled_gpu}};
    const std::size_t builds_in_turns = std::size(builds) - 1;
    const DeviceDepth depth = work.device_depth();
    const auto options_of = [](SatKernel kernel) {
        SatOptions options;
        options.max_kernel_texels = kMaxKernel;
        options.kernel = kernel;
        return options;
    };
    for (const auto& build : builds) {
        const SatOptions options = options_of(std::get<1>(build));
        runs.push_back([&context, &depth, &table, options] {
            build_sat(context, depth, table.mem, options);
            context.finish();
        });
    }

    // Every run but the last in turns, so that the ratios compare like with like on a noisy
    // machine; the last on its own.
    std::function<void()> outsider = runs.back();
    runs.pop_back();
    std::vector<Timings> timings = time_interleaved(runs, env.warmups, env.reps);
    timings.push_back(time_runs(outsider, env.warmups, env.reps));

    CaseResult copy;
    copy.name = "sat_copy";
    copy.bytes = sat_bytes(work);
    std::size_t fastest = 0;
    for (std::size_t c = 1; c < copies.size(); ++c)
        if (median(timings[c].wall_ms) < median(timings[fastest].wall_ms)) fastest = c;
    copy.take(timings[fastest]);
    copy.extra["copy_kernel"] = copies[fastest].label;
    rows.push_back(copy);

    std::vector<std::uint32_t> baseline;
    const std::vector<double>& baseline_ms = timings[copies.size()].wall_ms;
    for (std::size_t b = 0; b < std::size(builds); ++b) {
        CaseResult row;
        row.name = std::get<0>(builds[b]);
        row.bytes = sat_bytes(work);
        row.take(timings[copies.size() + b]);
        // The table each build leaves, against the baseline's.
        build_sat(context, depth, table.mem, options_of(std::get<1>(builds[b])));
        const std::vector<std::uint32_t> words = read_texture(context, table.mem, table_bytes);
        if (baseline.empty()) baseline = words;
        row.extra["equal_to_row_per_thread"] = equal_share(words, baseline);
        // Paired per turn where the row ran in the turns, else the ratio of medians.
        row.extra["speedup_over_row_per_thread"] =
            b < builds_in_turns ? median_ratio(baseline_ms, row.ms) : median(baseline_ms) / median(row.ms);
        rows.push_back(row);
    }
    for (CaseResult& row : rows) {
        row.extra["roof_case"] = "sat_copy";
        row.extra["sat_copy_roof_fraction"] = median(copy.ms) / median(row.ms);
        row.extra["max_kernel_texels"] = kMaxKernel;
    }
    return rows;
}

std::vector<CaseResult> run_soft(BenchEnv& env, const Workload& work) {
    if (work.format != Format::msm64) return {};
    Context& context = *env.context;
    // The table, and 2^18 receivers (a 512 x 512 view) at random spots of the map, on its
    // surface (sample 0 of their texel).
    SatOptions sat_options;
    sat_options.max_kernel_texels = kMaxKernel;
    const SatTable table = build_sat(context, *work.depth, sat_options);
    const std::size_t count = std::size_t(1) << 18;
    const std::vector<float> uvz = surface_receivers(*work.depth, count, 11);
    Buffer table_buffer(context, table.words.size() * 4, table.words.data());
    Buffer receivers(context, uvz.size() * 4, uvz.data());
    Buffer intensity(context, count * 4);
    SoftShadowOptions options;
    options.light_size = 40.0f * work.size / 256.0f; // the same light at every resolution
    options.depth_bias = 0.02f;
    const SoftShadowLimits limits = soft_shadow_limits(kMaxKernel, options);
    std::vector<CaseResult> rows;

    // The published method and the refined default (docs/soft_shadows.md), timed in turns.
    SoftShadowOptions published_options = options;
    published_options.receiver_blocker_weight = 0.0f;
    published_options.filter_parts = 1;
    const DeviceSat device_table{table_buffer.mem, table.width, table.height, kMaxKernel};
    const std::vector<std::pair<const char*, SoftShadowOptions>> methods = {{"soft_msm_published", published_options},
                                                                          {"soft_msm", options}};
    std::vector<std::function<void()>> method_runs;
    for (const auto& method : methods)
        method_runs.push_back([&, method] {
            soft_shade(context, device_table, receivers.mem, count, intensity.mem, method.second);
            context.finish();
        });
    const std::vector<Timings> method_timings = time_interleaved(method_runs, env.warmups, env.reps);
    for (std::size_t m = 0; m < methods.size(); ++m) {
        CaseResult msm;
        msm.name = methods[m].first;
        msm.bytes = 16 * count;
        msm.has_throughput = false;
        msm.take(method_timings[m]);
        msm.extra["receiver_blocker_weight"] = methods[m].second.receiver_blocker_weight;
        msm.extra["filter_parts"] = methods[m].second.filter_parts;
        msm.extra["cost_over_published"] = median_ratio(method_timings[m].wall_ms, method_timings[0].wall_ms);
        rows.push_back(msm);
    }

    for (int search : {15, 27}) {
        cl_kernel kernel = bench_kernel(context, "pcss", work.samples, search);
        const cl_int size = work.size;
        const cl_uint n = static_cast<cl_uint>(count);
        const float min_filter = options.min_filter_size, max_filter = limits.max_filter_size;
        set_arg(kernel, 0, sizeof(cl_mem), &work.depth_buffer);
        set_arg(kernel, 1, sizeof size, &size);
        set_arg(kernel, 2, sizeof size, &size);
        set_arg(kernel, 3, sizeof(cl_mem), &receivers.mem);
        set_arg(kernel, 4, sizeof n, &n);
        set_arg(kernel, 5, sizeof(float), &options.depth_bias);
        set_arg(kernel, 6, sizeof(float), &options.light_size);
        set_arg(kernel, 7, sizeof(float), &min_filter);
        set_arg(kernel, 8, sizeof(float), &max_filter);
        set_arg(kernel, 9, sizeof(cl_mem), &intensity.mem);
        const std::size_t group = std::min<std::size_t>(64, context.device().max_work_group_size);
        const std::size_t global = (count + group - 1) / group * group;
        CaseResult row;
        row.name = "pcss_" + std::to_string(search);
        row.bytes = 16 * count;
        row.has_throughput = false;
        row.take(time_runs(
            [&] {
                check_cl(clEnqueueNDRangeKernel(context.cl_queue_handle(), kernel, 1, nullptr, &global, &group, 0,
                                                nullptr, nullptr),
                         "clEnqueueNDRangeKernel(pcss)");
                context.finish();
            },
            env.warmups, env.reps));
        rows.push_back(row);
    }
    for (CaseResult& row : rows) {
        row.extra["receivers"] = count;
        row.extra["ns_per_receiver"] = median(row.ms) * 1e6 / double(count);
        row.extra["light_size"] = options.light_size;
    }
    return rows;
}

MSMCL_BENCH_CASE({"sat", 100, run_sat});
MSMCL_BENCH_CASE({"soft", 110, run_soft});

} // namespace

} // namespace msmcl::bench
