// Cases array4, separate4 (device buffers) and array4_host, separate4_host (host images):
// four maps of the workload's size (the cascades of a cascaded shadow map) filtered by one
// texture-array call against four single-map calls on the same bytes, timed in turns so
// that a noisy machine slows both alike. The separate calls read and write sub-buffers of
// the array's buffers and are enqueued back to back with one wait at the end, the best a
// caller of single-map calls can do. Rows carry the paired ratio separate / array and
// whether the textures are equal.
#include "harness.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>

#include <string>
#include <vector>

namespace msmcl::bench {

namespace {

constexpr int kLayers = 4;

// A sub-buffer of `bytes` bytes at `origin` of `buffer`.
cl_mem sub_buffer(cl_mem buffer, std::size_t origin, std::size_t bytes) {
    cl_buffer_region region{origin, bytes};
    cl_int status = CL_SUCCESS;
    cl_mem sub = clCreateSubBuffer(buffer, 0, CL_BUFFER_CREATE_TYPE_REGION, &region, &status);
    check_cl(status, "clCreateSubBuffer");
    return sub;
}

std::vector<CaseResult> run_array(BenchEnv& env, const Workload& work) {
    Context& context = *env.context;
    const FilterOptions options = work.filter_options();
    const std::size_t depth_bytes = work.texels() * work.samples * sizeof(float);
    const std::size_t texture_bytes = work.texture_bytes();
    // The sub-buffers of the separate calls must start at the device's base alignment.
    cl_uint alignment_bits = 0;
    check_cl(clGetDeviceInfo(context.cl_device_handle(), CL_DEVICE_MEM_BASE_ADDR_ALIGN, sizeof alignment_bits,
                             &alignment_bits, nullptr),
             "clGetDeviceInfo(CL_DEVICE_MEM_BASE_ADDR_ALIGN)");
    const std::size_t alignment = alignment_bits / 8;
    if (alignment == 0 || depth_bytes % alignment != 0 || texture_bytes % alignment != 0) return {};

    // The four layers: the workload's map four times, layer after layer.
    Buffer depth(context, kLayers * depth_bytes);
    for (int i = 0; i < kLayers; ++i)
        check_cl(clEnqueueCopyBuffer(context.cl_queue_handle(), work.depth_buffer, depth.mem, 0, i * depth_bytes,
                                     depth_bytes, 0, nullptr, nullptr),
                 "clEnqueueCopyBuffer(layers)");
    Buffer texture(context, kLayers * texture_bytes);
    std::vector<cl_mem> depth_layers, texture_layers;
    for (int i = 0; i < kLayers; ++i) {
        depth_layers.push_back(sub_buffer(depth.mem, i * depth_bytes, depth_bytes));
        texture_layers.push_back(sub_buffer(texture.mem, i * texture_bytes, texture_bytes));
    }
    const auto array_call = [&] {
        filter(context, DeviceDepth{depth.mem, work.size, work.size, work.samples, kLayers}, texture.mem, options);
        context.finish();
    };
    const auto separate_calls = [&] {
        for (int i = 0; i < kLayers; ++i)
            filter(context, DeviceDepth{depth_layers[i], work.size, work.size, work.samples}, texture_layers[i],
                   options);
        context.finish();
    };
    // The host path: one layered image against four images, uploads and read-backs included.
    DepthImage layered{work.size, work.size, work.samples, {}, kLayers};
    for (int i = 0; i < kLayers; ++i)
        layered.depth.insert(layered.depth.end(), work.depth->depth.begin(), work.depth->depth.end());
    std::vector<std::uint32_t> host_array_words, host_separate_words;
    const auto host_array_call = [&] { host_array_words = filter(context, layered, options).words; };
    const auto host_separate_calls = [&] {
        host_separate_words.clear();
        for (int i = 0; i < kLayers; ++i) {
            const std::vector<std::uint32_t> words = filter(context, *work.depth, options).words;
            host_separate_words.insert(host_separate_words.end(), words.begin(), words.end());
        }
    };

    // Equal bytes first: the array call's texture against the separate calls'.
    array_call();
    const std::vector<std::uint32_t> array_words = read_texture(context, texture.mem, kLayers * texture_bytes);
    separate_calls();
    const double equal = equal_share(array_words, read_texture(context, texture.mem, kLayers * texture_bytes));

    std::vector<Timings> timings = time_interleaved({array_call, separate_calls, host_array_call, host_separate_calls},
                                                    env.warmups, env.reps);
    const double host_equal = equal_share(host_array_words, host_separate_words) * equal_share(host_array_words, array_words);
    for (int i = 0; i < kLayers; ++i) {
        clReleaseMemObject(depth_layers[i]);
        clReleaseMemObject(texture_layers[i]);
    }

    const char* names[] = {"array4", "separate4", "array4_host", "separate4_host"};
    std::vector<CaseResult> rows;
    for (int i = 0; i < 4; ++i) {
        CaseResult row;
        row.name = names[i];
        row.bytes = kLayers * work.bytes();
        row.take(std::move(timings[i]));
        row.extra["layers"] = kLayers;
        row.extra["equal_layers"] = i < 2 ? equal : host_equal;
        rows.push_back(std::move(row));
    }
    // Paired ratios: the separate calls' time over the array call's, per turn, median.
    rows[0].extra["separate_over_array"] = median_ratio(rows[1].ms, rows[0].ms);
    rows[2].extra["separate_over_array"] = median_ratio(rows[3].ms, rows[2].ms);
    return rows;
}

MSMCL_BENCH_CASE({"array", 40, run_array});

} // namespace

} // namespace msmcl::bench
