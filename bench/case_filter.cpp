// Cases fused (the kernel the library picks for the device), fused_paper (the paper's
// 40x32 kernel) and three_pass: msmcl::filter on device buffers, no host copies timed.
#include "harness.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>

namespace msmcl::bench {

namespace {

const char* kernel_label(FilterKernel kernel) {
    switch (kernel) {
    case FilterKernel::automatic: return "automatic";
    case FilterKernel::fused_paper: return "fused_paper";
    case FilterKernel::three_pass: return "three_pass";
    case FilterKernel::fused_cpu: return "fused_cpu";
    }
    return "?";
}

std::vector<CaseResult> run_filter(BenchEnv& env, const Workload& work, const char* name, FilterKernel kernel) {
    FilterOptions options = work.filter_options();
    options.kernel = kernel;
    const DeviceDepth depth = work.device_depth();
    const auto run = [&] {
        filter(*env.context, depth, work.texture_buffer, options);
        env.context->finish();
    };
    CaseResult result;
    result.name = name;
    result.bytes = work.bytes();
    try {
        result.take(time_runs(run, env.warmups, env.reps));
    } catch (const device_error& e) {
        return {}; // the device cannot run this kernel
    }
    result.extra["kernel"] = kernel_label(kernel); // automatic: fused_cpu on CPU devices, else fused_paper
    if (!env.three_pass_words.empty())
        result.extra["equal_to_three_pass"] =
            equal_share(read_texture(*env.context, work.texture_buffer, work.texture_bytes()), env.three_pass_words);
    return {result};
}

MSMCL_BENCH_CASE({"fused", 10, [](BenchEnv& env, const Workload& work) {
                      return run_filter(env, work, "fused", FilterKernel::automatic);
                  }});
MSMCL_BENCH_CASE({"fused_paper", 20, [](BenchEnv& env, const Workload& work) {
                      return run_filter(env, work, "fused_paper", FilterKernel::fused_paper);
                  }});
MSMCL_BENCH_CASE({"three_pass", 30, [](BenchEnv& env, const Workload& work) {
                      return run_filter(env, work, "three_pass", FilterKernel::three_pass);
                  }});

} // namespace

} // namespace msmcl::bench
