// Host data in and out of the device (transfer.hpp).
#include "ops/transfer.hpp"

#include "runtime/memory_strategy.hpp"

#include <algorithm>

namespace msmcl::detail {

namespace {

bool in_place(const cl::Buffer& buffer) { return (buffer.getInfo<CL_MEM_FLAGS>() & CL_MEM_USE_HOST_PTR) != 0; }

} // namespace

StageTimer::StageTimer(ContextImpl& impl, const StageObserver& observer)
    : impl_(impl), observer_(observer), start_(std::chrono::steady_clock::now()) {}

double StageTimer::elapsed_ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
}

void StageTimer::report(const char* stage, double milliseconds, std::string note) {
    observer_(StageTime{stage, milliseconds, std::move(note)});
    start_ = std::chrono::steady_clock::now();
}

void StageTimer::uploaded(std::initializer_list<const cl::Buffer*> inputs) {
    if (!observer_) return;
    check(impl_.queue.finish(), "clFinish");
    std::size_t bytes = 0, kept = 0;
    for (const cl::Buffer* input : inputs) {
        if (!input || !(*input)()) continue;
        const std::size_t size = input->getInfo<CL_MEM_SIZE>();
        bytes += size;
        if (in_place(*input)) kept += size;
    }
    const double ms = elapsed_ms();
    build_ms_ = impl_.programs.build_milliseconds();
    built_ = impl_.programs.programs_built();
    report("upload", ms, std::to_string(bytes) + " bytes" + (kept > 0 ? ", " + std::to_string(kept) + " in place" : ""));
}

void StageTimer::computed(const char* operation) {
    if (!observer_) return;
    check(impl_.queue.finish(), "clFinish");
    const double total = elapsed_ms();
    const double build = impl_.programs.build_milliseconds() - build_ms_;
    const std::size_t built = impl_.programs.programs_built() - built_;
    observer_(StageTime{"program", build,
                        built == 0 ? std::string("cache hit")
                                   : std::to_string(built) + (built == 1 ? " program built" : " programs built")});
    // The work distribution the operation's kernels were fitted to (docs/devices.md).
    report("kernel", std::max(0.0, total - build), operation ? impl_.kernel_choice(operation) : std::string());
}

void StageTimer::downloaded(const cl::Buffer& result, std::size_t bytes) {
    if (!observer_) return;
    report("download", elapsed_ms(), std::to_string(bytes) + " bytes" + (in_place(result) ? " in place" : ""));
}

cl::Buffer upload(ContextImpl& impl, const void* data, std::size_t bytes, const char* what) {
    cl_int status = CL_SUCCESS;
    cl::Buffer buffer(impl.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, const_cast<void*>(data), &status);
    check(status, what);
    return buffer;
}

cl::Buffer upload_in_place(ContextImpl& impl, const void* data, std::size_t bytes, const char* what) {
    if (!shares_host_memory(impl.info) || bytes == 0) return upload(impl, data, bytes, what);
    cl_int status = CL_SUCCESS;
    cl::Buffer buffer(impl.context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, bytes, const_cast<void*>(data), &status);
    check(status, what);
    return buffer;
}

cl::Buffer result_buffer(ContextImpl& impl, void* out, std::size_t bytes, const char* what) {
    if (!shares_host_memory(impl.info) || bytes == 0) return device_buffer(impl, CL_MEM_READ_WRITE, bytes, what);
    cl_int status = CL_SUCCESS;
    cl::Buffer buffer(impl.context, CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, bytes, out, &status);
    check(status, what);
    return buffer;
}

void read_result(ContextImpl& impl, const cl::Buffer& buffer, std::size_t bytes, void* out, const cl::Event& after,
                 const char* what) {
    if (bytes == 0) return;
    if ((buffer.getInfo<CL_MEM_FLAGS>() & CL_MEM_USE_HOST_PTR) == 0) {
        read_after(impl, buffer, bytes, out, after, what);
        return;
    }
    // Mapping a CL_MEM_USE_HOST_PTR buffer makes `out` hold the result (the spec's
    // synchronization point); unmapping hands the buffer back.
    const std::vector<cl::Event> waits{after};
    cl_int status = CL_SUCCESS;
    void* mapped = impl.queue.enqueueMapBuffer(buffer, CL_TRUE, CL_MAP_READ, 0, bytes, &waits, nullptr, &status);
    check(status, what);
    cl::Event unmapped;
    check(impl.queue.enqueueUnmapMemObject(buffer, mapped, nullptr, &unmapped), what);
    check(unmapped.wait(), what);
}

cl::Buffer upload_receivers(ContextImpl& impl, const Receivers& receivers) {
    const std::size_t count = receivers.size();
    std::vector<float> uvz(3 * count);
    std::copy(receivers.u.begin(), receivers.u.end(), uvz.begin());
    std::copy(receivers.v.begin(), receivers.v.end(), uvz.begin() + count);
    std::copy(receivers.z.begin(), receivers.z.end(), uvz.begin() + 2 * count);
    return upload(impl, uvz.data(), uvz.size() * sizeof(float), "clCreateBuffer(receivers)");
}

cl::Buffer device_buffer(ContextImpl& impl, cl_mem_flags flags, std::size_t bytes, const char* what) {
    cl_int status = CL_SUCCESS;
    cl::Buffer buffer(impl.context, flags, std::max<std::size_t>(bytes, 4), nullptr, &status);
    check(status, what);
    return buffer;
}

std::vector<float> read_floats(ContextImpl& impl, const cl::Buffer& buffer, std::size_t count, const char* what) {
    std::vector<float> values(count);
    check(impl.queue.enqueueReadBuffer(buffer, CL_TRUE, 0, count * sizeof(float), values.data()), what);
    return values;
}

void read_after(ContextImpl& impl, const cl::Buffer& buffer, std::size_t bytes, void* out, const cl::Event& after,
                const char* what) {
    const std::vector<cl::Event> waits{after};
    check(impl.queue.enqueueReadBuffer(buffer, CL_TRUE, 0, bytes, out, &waits), what);
}

std::vector<std::uint32_t> read_words(ContextImpl& impl, const cl::Buffer& buffer, std::size_t count,
                                      const char* what) {
    std::vector<std::uint32_t> words(count);
    check(impl.queue.enqueueReadBuffer(buffer, CL_TRUE, 0, count * sizeof(std::uint32_t), words.data()), what);
    return words;
}

} // namespace msmcl::detail
