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

    /// Records the work distribution `operation` ("filter") runs with and why, for
    /// Context::kernel_choices (the CLI's --verbose).
    void note_choice(const std::string& operation, const std::string& choice);
    std::vector<std::string> kernel_choices() const;
    /// The choice recorded for `operation`; empty if none.
    std::string kernel_choice(const std::string& operation) const;

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

    mutable std::mutex mutex_; ///< guards extra_build_options_, scratch_ and choices_
    std::condition_variable scratch_released_;
    std::string extra_build_options_;
    std::map<std::string, Scratch> scratch_;
    std::vector<std::pair<std::string, std::string>> choices_;
};

/// What a built kernel allows on its device: CL_KERNEL_WORK_GROUP_SIZE (never above the
/// device's maximum; GPU drivers lower it for kernels heavy in registers, Mesa's llvmpipe
/// reports 32 for every kernel) and the local memory it takes (CL_KERNEL_LOCAL_MEM_SIZE)
/// against the device's. Only the work-items decide whether a group runs: llvmpipe reports
/// twice the local memory a kernel declares (41184 bytes for the fused kernel's 20720), so
/// the operations check their declared local memory against the device's themselves.
struct KernelFit {
    std::size_t work_items = 0;
    unsigned long long local_bytes = 0;
    unsigned long long device_local_bytes = 0;

    bool runs(std::size_t group) const { return group <= work_items; }
    /// "at most 32 work-items per group, 20720 of 32768 bytes of local memory"
    std::string limits() const {
        return "at most " + std::to_string(work_items) + " work-items per group, " + std::to_string(local_bytes) +
               " of " + std::to_string(device_local_bytes) + " bytes of local memory";
    }
};
KernelFit kernel_fit(const ContextImpl& impl, const cl::Kernel& kernel);
/// The largest power-of-two fraction of `preferred` (a power of two) that `fit` allows: the
/// group of kernels whose work-items are independent (shade, soft, queries).
std::size_t fitting_group(const KernelFit& fit, std::size_t preferred);

/// Wait list of an Enqueue as the bindings want it (retains the events).
std::vector<cl::Event> wait_list(const Enqueue& enqueue);

/// Hands the last event of a call to the caller (Enqueue::done) and blocks if asked.
void complete(const Enqueue& enqueue, const cl::CommandQueue& queue, const cl::Event& last);

/// A call with nothing to do still honours the event contract: a marker after the
/// Enqueue's wait list is its last event.
void complete_without_work(const Enqueue& enqueue, const cl::CommandQueue& queue);

} // namespace msmcl::detail
