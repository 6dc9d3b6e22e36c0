// Case copy: a kernel that moves the filter's bytes and does nothing else (reads the S
// samples of each texel, writes texel_bytes), the memory-bandwidth roof of the device.
// The best of a few work-group sizes counts (a roof, not a kernel to compare).
#include "harness.hpp"

#include <msmcl/errors.hpp>

#include <limits>
#include <map>
#include <string>
#include <tuple>

namespace msmcl::bench {

namespace {

// Every texel: the sum of its samples (so no load can be dropped), written as its words.
const char* const kCopySource = R"CLC(
__kernel void copy_texels(__global const float* depth, __global uint* texture, uint texels) {
    const size_t t = get_global_id(0);
    if (t >= texels) return;
    float sum = 0.0f;
    for (int s = 0; s < SAMPLES; ++s) sum += depth[t * SAMPLES + s];
    for (int w = 0; w < WORDS; ++w) texture[t * WORDS + w] = as_uint(sum) + (uint)w;
}
)CLC";

// Built copy kernels per (context, samples, words), kept for the process.
cl_kernel copy_kernel(Context& context, int samples, int words) {
    static std::map<std::tuple<cl_context, int, int>, cl_kernel> kernels;
    const auto key = std::make_tuple(context.cl_context_handle(), samples, words);
    if (auto found = kernels.find(key); found != kernels.end()) return found->second;
    cl_int status = CL_SUCCESS;
    const char* sources[] = {kCopySource};
    cl_program program = clCreateProgramWithSource(context.cl_context_handle(), 1, sources, nullptr, &status);
    check_cl(status, "clCreateProgramWithSource(copy)");
    const std::string options = "-cl-std=CL1.2 -DSAMPLES=" + std::to_string(samples) + " -DWORDS=" + std::to_string(words);
    cl_device_id device = context.cl_device_handle();
    check_cl(clBuildProgram(program, 1, &device, options.c_str(), nullptr, nullptr), "clBuildProgram(copy)");
    cl_kernel kernel = clCreateKernel(program, "copy_texels", &status);
    check_cl(status, "clCreateKernel(copy_texels)");
    clReleaseProgram(program);
    kernels.emplace(key, kernel);
    return kernel;
}

std::vector<CaseResult> run_copy(BenchEnv& env, const Workload& work) {
    cl_kernel kernel = copy_kernel(*env.context, work.samples, static_cast<int>(texel_words(work.format)));
    const cl_uint texels = static_cast<cl_uint>(work.texels());
    check_cl(clSetKernelArg(kernel, 0, sizeof(cl_mem), &work.depth_buffer), "clSetKernelArg");
    check_cl(clSetKernelArg(kernel, 1, sizeof(cl_mem), &work.texture_buffer), "clSetKernelArg");
    check_cl(clSetKernelArg(kernel, 2, sizeof texels, &texels), "clSetKernelArg");
    // The work-group size that copies fastest (one run each after a warm-up), then timed.
    const auto run_with = [&](std::size_t group) {
        const std::size_t global = (work.texels() + group - 1) / group * group;
        return [&, group, global] {
            check_cl(clEnqueueNDRangeKernel(env.context->cl_queue_handle(), kernel, 1, nullptr, &global, &group, 0,
                                            nullptr, nullptr),
                     "clEnqueueNDRangeKernel(copy_texels)");
            env.context->finish();
        };
    };
    std::size_t best_group = 0;
    double best_ms = std::numeric_limits<double>::infinity();
    for (std::size_t group : {64, 256, 1024}) {
        if (group > env.context->device().max_work_group_size) continue;
        const double ms = minimum(time_runs(run_with(group), 1, 1).wall_ms);
        if (ms < best_ms) best_ms = ms, best_group = group;
    }
    CaseResult best;
    best.name = "copy";
    best.bytes = work.bytes();
    best.take(time_runs(run_with(best_group), 0, env.reps));
    best.extra["work_group"] = best_group;
    return {best};
}

MSMCL_BENCH_CASE({"copy", 90, run_copy});

} // namespace

} // namespace msmcl::bench
