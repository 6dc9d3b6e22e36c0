// Host data in and out of the device for the host versions of the operations: each host
// call uploads its inputs, runs the device version on the Context's queue and reads the
// result back. Errors are opencl_error naming the call ("clCreateBuffer(receivers)").
#pragma once

#include "runtime/context_impl.hpp"

#include <msmcl/types.hpp>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

namespace msmcl::detail {

/// A read-only buffer holding a copy of `bytes` bytes at `data`; `what` names the
/// clCreateBuffer call in errors.
cl::Buffer upload(ContextImpl& impl, const void* data, std::size_t bytes, const char* what);
/// A read-only buffer over `bytes` bytes at `data` that the kernels may read in place
/// (CL_MEM_USE_HOST_PTR on devices that share host memory, memory_strategy.hpp), else a
/// copy: `data` must stay unchanged and alive until the buffer is released.
cl::Buffer upload_in_place(ContextImpl& impl, const void* data, std::size_t bytes, const char* what);
/// A buffer for a result of `bytes` bytes that lands in `out`: on devices that
/// share host memory the kernels write `out` itself (CL_MEM_USE_HOST_PTR), else a device
/// buffer (kernels may also read it back). `out` must stay alive until the buffer is released; read_result makes its
/// content valid.
cl::Buffer result_buffer(ContextImpl& impl, void* out, std::size_t bytes, const char* what);
/// Once `after` has completed, the `bytes` bytes of a result_buffer in `out`, blocking: a
/// map and unmap of the buffer on devices that share host memory (no copy where the driver
/// aliases `out`), else a read.
void read_result(ContextImpl& impl, const cl::Buffer& buffer, std::size_t bytes, void* out, const cl::Event& after,
                 const char* what);
/// The receivers planar (all u, then all v, then all z), as the device calls take them.
cl::Buffer upload_receivers(ContextImpl& impl, const Receivers& receivers);
/// A device buffer of at least `bytes` bytes (at least 4: OpenCL refuses empty buffers).
cl::Buffer device_buffer(ContextImpl& impl, cl_mem_flags flags, std::size_t bytes, const char* what);
/// `count` floats (or 32-bit words) read from the start of `buffer`, blocking.
std::vector<float> read_floats(ContextImpl& impl, const cl::Buffer& buffer, std::size_t count,
                               const char* what = "clEnqueueReadBuffer");
/// `bytes` bytes from the start of `buffer` into `out` once `after` has completed, blocking.
void read_after(ContextImpl& impl, const cl::Buffer& buffer, std::size_t bytes, void* out, const cl::Event& after,
                const char* what);
std::vector<std::uint32_t> read_words(ContextImpl& impl, const cl::Buffer& buffer, std::size_t count,
                                      const char* what = "clEnqueueReadBuffer");

/// The stages of a host call, timed for its StageObserver (types.hpp): upload, program,
/// kernel, download. Without an observer it measures nothing and waits for nothing.
class StageTimer {
public:
    StageTimer(ContextImpl& impl, const StageObserver& observer);
    /// Ends the upload of `inputs` (the note counts their bytes and those used in place).
    void uploaded(std::initializer_list<const cl::Buffer*> inputs);
    /// Ends the computation once the queue is idle: "program" (the Context's time building
    /// or loading programs since the upload) and "kernel" (the rest), noting the work
    /// distribution recorded for `operation` ("filter"), if any.
    void computed(const char* operation = nullptr);
    /// Ends the read of `bytes` bytes of `result` (in place where the device shares host memory).
    void downloaded(const cl::Buffer& result, std::size_t bytes);

private:
    void report(const char* stage, double milliseconds, std::string note);
    double elapsed_ms() const;

    ContextImpl& impl_;
    const StageObserver& observer_;
    std::chrono::steady_clock::time_point start_;
    double build_ms_ = 0;
    std::size_t built_ = 0;
};

} // namespace msmcl::detail
