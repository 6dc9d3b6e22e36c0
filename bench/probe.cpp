// Probe mode: the first filter() call of a process, timed.
#include "probe.hpp"

#include "harness.hpp"
#include "scene.hpp"

#include <msmcl/context.hpp>
#include <msmcl/filter.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>

namespace msmcl::bench {

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

int run_first_call_probe(int size, int samples, Format format, const std::string& device,
                         const std::string& json_path) {
    // Context (device selection; the caches come from the environment).
    auto start = std::chrono::steady_clock::now();
    DeviceSelection selection;
    selection.device = device;
    selection.strict = !device.empty();
    Context context(selection);
    const double context_ms = ms_since(start);

    // Data on the device before anything is timed.
    const DepthImage depth = make_scene(size, samples);
    cl_int status = CL_SUCCESS;
    cl_mem depth_buffer = clCreateBuffer(context.cl_context_handle(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                         depth.depth.size() * sizeof(float), const_cast<float*>(depth.depth.data()),
                                         &status);
    check_cl(status, "clCreateBuffer(depth)");
    cl_mem texture = clCreateBuffer(context.cl_context_handle(), CL_MEM_WRITE_ONLY,
                                    static_cast<std::size_t>(size) * size * texel_bytes(format), nullptr, &status);
    check_cl(status, "clCreateBuffer(texture)");
    FilterOptions options;
    options.format = format;
    const DeviceDepth device_depth{depth_buffer, size, size, samples};
    const auto call = [&] {
        filter(context, device_depth, texture, options);
        context.finish();
    };

    // The first call, then steady ones.
    start = std::chrono::steady_clock::now();
    call();
    const double first_ms = ms_since(start);
    const std::vector<double> steady = time_runs(call, 0, 3).wall_ms;
    clReleaseMemObject(texture);
    clReleaseMemObject(depth_buffer);

    // The steady cost: the fastest of the calls after the first (the least disturbed by
    // whatever else runs on the machine).
    nlohmann::json report{{"first_ms", first_ms},
                          {"steady_ms", minimum(steady)},
                          {"context_ms", context_ms},
                          {"programs_built", context.programs_built()}};
    std::ofstream(json_path) << report.dump() << '\n';
    return 0;
}

} // namespace msmcl::bench
