// What an operation (host/ops/*.cpp) sees of a Context: the OpenCL objects and the
// program/kernel cache.
#pragma once

#include "runtime/opencl.hpp"
#include "runtime/program_cache.hpp"

#include <msmcl/context.hpp>
#include <msmcl/enqueue.hpp>

#include <condition_variable>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace msmcl::detail {

struct ContextImpl {
    cl::Context context;
    cl::Device device;
    cl::CommandQueue queue;
    DeviceInfo info;
    ProgramCache programs;

    /// A kernel of the embedded program `source_file` ("filter_fused_gpu.cl"), built for
    /// this device with `defines` ("MSM_FORMAT=2", "MSM_TILE_W=32"; each becomes a
    /// `#define NAME VALUE` line prepended to the source). Programs are cached and shared;
    /// the kernel object is the calling thread's own (the same reference for the same
    /// arguments on the same thread), so threads sharing a Context never set arguments on
    /// one kernel at once.
    cl::Kernel& kernel(const std::string& source_file, const std::vector<std::string>& defines,
                       const std::string& kernel_name);

    void set_extra_build_options(const std::string& options);

    /// The queue a call should use: the Enqueue's own, else the Context's.
    cl::CommandQueue queue_for(const Enqueue& enqueue) const;

    /// A device buffer of at least `bytes` for the scratch a call's kernels use while they
    /// run, kept between calls per `purpose` and grown as needed (a fresh buffer per call
    /// costs page faults and zeroing on CPU devices: 2 MiB for a 2048^2 table). `waits`
    /// gains the last event of the previous user, so calls on different queues take turns;
    /// the caller hands its own last event back with scratch_used.
    /// Between the two, the calling thread holds the purpose: another thread asking for it
    /// waits until scratch_used (the enqueues in between do not block), so two threads
    /// never enqueue work on one scratch buffer without an event ordering them. A
    /// ScratchSession around the call releases what an exception left held.
    cl::Buffer scratch(const std::string& purpose, std::size_t bytes, std::vector<cl::Event>& waits);
    void scratch_used(const std::string& purpose, const cl::Event& last);

    /// Releases, when it ends, the scratch purposes its thread still holds (a call that
    /// threw between scratch and scratch_used); their buffers are dropped, since work
    /// enqueued on them may still run.
    class ScratchSession {
      public:
        explicit ScratchSession(ContextImpl& impl) : impl_(impl) {}
        ~ScratchSession() { impl_.release_abandoned_scratch(); }
        ScratchSession(const ScratchSession&) = delete;
        ScratchSession& operator=(const ScratchSession&) = delete;

      private:
        ContextImpl& impl_;
    };

  private:
    struct Scratch {
        cl::Buffer buffer;
        std::size_t bytes = 0;
        cl::Event last_use;
        bool held = false;
        std::thread::id holder;
    };
    void release_abandoned_scratch();

    std::mutex mutex_; ///< guards extra_build_options_ and scratch_
    std::condition_variable scratch_released_;
    std::string extra_build_options_;
    std::map<std::string, Scratch> scratch_;
};

/// Wait list of an Enqueue as the bindings want it (retains the events).
std::vector<cl::Event> wait_list(const Enqueue& enqueue);

/// Hands the last event of a call to the caller (Enqueue::done) and blocks if asked.
void complete(const Enqueue& enqueue, const cl::CommandQueue& queue, const cl::Event& last);

/// A call with nothing to do still honours the event contract: a marker after the
/// Enqueue's wait list is its last event.
void complete_without_work(const Enqueue& enqueue, const cl::CommandQueue& queue);

} // namespace msmcl::detail
