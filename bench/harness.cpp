// msmcl-bench harness: registry, timing, statistics.
#include "harness.hpp"

#include <msmcl/errors.hpp>

#include <algorithm>
#include <chrono>
#include <ctime>

namespace msmcl::bench {

namespace {

std::vector<BenchCase>& registry() {
    static std::vector<BenchCase> cases;
    return cases;
}

} // namespace

bool register_case(BenchCase bench_case) {
    registry().push_back(std::move(bench_case));
    return true;
}

std::vector<BenchCase> registered_cases() {
    std::vector<BenchCase> cases = registry();
    std::stable_sort(cases.begin(), cases.end(),
                     [](const BenchCase& a, const BenchCase& b) { return a.order < b.order; });
    return cases;
}

namespace {

double process_cpu_ms() {
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return now.tv_sec * 1e3 + now.tv_nsec * 1e-6;
}

} // namespace

Timings time_runs(const std::function<void()>& run, int warmups, int reps) {
    for (int i = 0; i < warmups; ++i) run();
    Timings timings;
    for (int i = 0; i < reps; ++i) {
        const double cpu_start = process_cpu_ms();
        const auto start = std::chrono::steady_clock::now();
        run();
        const auto stop = std::chrono::steady_clock::now();
        timings.cpu_ms.push_back(process_cpu_ms() - cpu_start);
        timings.wall_ms.push_back(std::chrono::duration<double, std::milli>(stop - start).count());
    }
    return timings;
}

std::vector<Timings> time_interleaved(const std::vector<std::function<void()>>& runs, int warmups, int reps) {
    for (const auto& run : runs)
        for (int i = 0; i < warmups; ++i) run();
    std::vector<Timings> timings(runs.size());
    for (int i = 0; i < reps; ++i)
        for (std::size_t r = 0; r < runs.size(); ++r) {
            runs[r](); // untimed: the run finds its own data in the caches, as in time_runs
            const double cpu_start = process_cpu_ms();
            const auto start = std::chrono::steady_clock::now();
            runs[r]();
            const auto stop = std::chrono::steady_clock::now();
            timings[r].cpu_ms.push_back(process_cpu_ms() - cpu_start);
            timings[r].wall_ms.push_back(std::chrono::duration<double, std::milli>(stop - start).count());
        }
    return timings;
}

double median_ratio(const std::vector<double>& a, const std::vector<double>& b) {
    std::vector<double> ratios;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
        if (b[i] > 0) ratios.push_back(a[i] / b[i]);
    return median(ratios);
}

double minimum(const std::vector<double>& values) {
    return values.empty() ? 0.0 : *std::min_element(values.begin(), values.end());
}

double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const std::size_t half = values.size() / 2;
    return values.size() % 2 ? values[half] : 0.5 * (values[half - 1] + values[half]);
}

double equal_share(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
    if (a.size() != b.size() || a.empty()) return 0.0;
    std::size_t equal = 0;
    for (std::size_t i = 0; i < a.size(); ++i) equal += a[i] == b[i];
    return double(equal) / double(a.size());
}

std::vector<std::uint32_t> read_texture(Context& context, cl_mem buffer, std::size_t bytes) {
    std::vector<std::uint32_t> words(bytes / sizeof(std::uint32_t));
    check_cl(clEnqueueReadBuffer(context.cl_queue_handle(), buffer, CL_TRUE, 0, bytes, words.data(), 0, nullptr,
                                 nullptr),
             "clEnqueueReadBuffer");
    return words;
}

void check_cl(cl_int status, const char* call) {
    if (status != CL_SUCCESS) throw opencl_error(status, call);
}

Buffer::Buffer(Context& context, std::size_t bytes, const void* data) {
    cl_int status = CL_SUCCESS;
    mem = clCreateBuffer(context.cl_context_handle(), data ? CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR : CL_MEM_READ_WRITE,
                         bytes, const_cast<void*>(data), &status);
    check_cl(status, "clCreateBuffer(bench)");
}

Buffer::~Buffer() { clReleaseMemObject(mem); }

} // namespace msmcl::bench
