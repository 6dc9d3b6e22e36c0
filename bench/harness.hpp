// msmcl-bench harness: workloads, the registry of cases, timing and statistics.
// A case file registers itself with MSMCL_BENCH_CASE; bench/CMakeLists.txt lists the files.
#pragma once

#include <msmcl/context.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/formats.hpp>

#include <nlohmann/json.hpp>

#include <CL/cl.h>

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace msmcl::bench {

/// One configuration of the sweep: a size^2 depth map with `samples` samples per texel,
/// filtered into `format`, on the host and on the device.
struct Workload {
    int size = 0;
    int samples = 1;
    Format format = Format::nlq64;
    float sigma = 2.4f;
    const DepthImage* depth = nullptr; ///< host copy (cpu_loop, opencv)
    cl_mem depth_buffer = nullptr;     ///< the same on the device
    cl_mem texture_buffer = nullptr;   ///< a texture the cases may overwrite

    std::size_t texels() const { return static_cast<std::size_t>(size) * size; }
    /// Bytes every case must move at least: the samples in, the texture out.
    std::size_t bytes() const { return texels() * (samples * sizeof(float) + texel_bytes(format)); }
    std::size_t texture_bytes() const { return texels() * texel_bytes(format); }
    /// The depth on the device, and the filter options of the format and blur.
    DeviceDepth device_depth() const { return {depth_buffer, size, size, samples}; }
    FilterOptions filter_options() const {
        FilterOptions options;
        options.format = format;
        options.sigma = sigma;
        return options;
    }
};

/// What the cases share: the device, repetition counts, the three-pass texture of the
/// workload (to check every case's output against).
struct BenchEnv {
    Context* context = nullptr;
    int reps = 5;
    int warmups = 2;
    std::string device;                         ///< the --device spec (empty: default)
    std::string self_path;                      ///< this executable (cases that spawn probes)
    std::string cli_path;                       ///< --msmcl: the CLI the batch case runs (empty: this build's)
    int build_reps = 0;                         ///< probe processes per build row, 0 = no build rows
    std::vector<std::uint32_t> three_pass_words; ///< reference output of the workload
};

/// Per-repetition times of a case: wall clock, and the CPU time of the whole process (all
/// threads, the OpenCL runtime's included): on a shared machine the second is the steadier
/// figure of the work done, the first what a caller waits.
struct Timings {
    std::vector<double> wall_ms;
    std::vector<double> cpu_ms;
};

/// A measured case: per-repetition wall times and what it moved; `extra` adds fields to
/// the JSON row (checks, notes, parameters).
struct CaseResult {
    std::string name;
    std::vector<double> ms;
    std::vector<double> cpu_ms; ///< process CPU time per repetition (may be empty)
    std::size_t bytes = 0;
    bool has_throughput = true; ///< false for build/latency rows (no texels/s, GB/s)
    nlohmann::json extra = nlohmann::json::object();

    void take(Timings timings) {
        ms = std::move(timings.wall_ms);
        cpu_ms = std::move(timings.cpu_ms);
    }
};

/// A case: `run` returns its rows for a workload (none when it does not apply, e.g. no
/// device support). Cases run in `order`, all on the same device.
struct BenchCase {
    std::string name;
    int order = 0;
    std::function<std::vector<CaseResult>(BenchEnv&, const Workload&)> run;
};

bool register_case(BenchCase bench_case);
/// Every registered case, sorted by order.
std::vector<BenchCase> registered_cases();

#define MSMCL_BENCH_CONCAT2(a, b) a##b
#define MSMCL_BENCH_CONCAT(a, b) MSMCL_BENCH_CONCAT2(a, b)
/// Registers a case at start-up: MSMCL_BENCH_CASE({"name", order, function});
#define MSMCL_BENCH_CASE(...)                                                                                   \
    static const bool MSMCL_BENCH_CONCAT(registered_case_, __LINE__) = ::msmcl::bench::register_case(__VA_ARGS__)

/// Times `run` (which must return only once its work is complete): `warmups` untimed runs
/// (program builds, first-launch JIT, page faults), then `reps` timed ones.
Timings time_runs(const std::function<void()>& run, int warmups, int reps);
/// The same for several runs measured in turns (run 0, 1, ..., then again; each timed run
/// right after an untimed one of its own, so that it starts warm as in time_runs): a slow
/// phase of a noisy machine then hits every run alike, so ratios between them stay fair.
std::vector<Timings> time_interleaved(const std::vector<std::function<void()>>& runs, int warmups, int reps);
/// Median over repetitions of a[i] / b[i] (paired ratio of interleaved timings).
double median_ratio(const std::vector<double>& a, const std::vector<double>& b);

double minimum(const std::vector<double>& values);
double median(std::vector<double> values);

/// Share of equal 32-bit words (1 = identical texture).
double equal_share(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b);

/// Reads a device texture back (blocking, on the context's queue).
std::vector<std::uint32_t> read_texture(Context& context, cl_mem buffer, std::size_t bytes);

/// Throws msmcl::opencl_error for a failed OpenCL call.
void check_cl(cl_int status, const char* call);

/// A device buffer of the Context, released at scope exit: a copy of `data` (read-only) when
/// given, else `bytes` of read-write memory.
struct Buffer {
    cl_mem mem = nullptr;
    Buffer(Context& context, std::size_t bytes, const void* data = nullptr);
    ~Buffer();
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;
};

} // namespace msmcl::bench
