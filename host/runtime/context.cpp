// Context: owns or borrows the OpenCL objects; builds and caches programs on demand.
#include "runtime/context_impl.hpp"
#include "runtime/device_selection.hpp"
#include "runtime/kernel_sources.hpp"
#include "runtime/quirks.hpp"

#include <algorithm>
#include <cstdlib>

namespace msmcl {

namespace detail {

cl::Kernel& ContextImpl::kernel(const std::string& source_file, const std::vector<std::string>& defines,
                                const std::string& kernel_name) {
    // The assembled source is cached per (file, defines): no assembly or hashing per launch.
    const KernelSource& source = kernel_source(source_file, defines);
    std::string options = base_build_options;
    if (const std::string quirk = device_build_options(info, source_file); !quirk.empty()) options += ' ' + quirk;
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (!extra_build_options_.empty()) options += ' ' + extra_build_options_;
    }
    return programs.kernel(context, device, source_file, source, options, kernel_name);
}

void ContextImpl::set_extra_build_options(const std::string& options) {
    const std::lock_guard<std::mutex> lock(mutex_);
    extra_build_options_ = options;
}

cl::CommandQueue ContextImpl::queue_for(const Enqueue& enqueue) const {
    return enqueue.queue ? cl::CommandQueue(enqueue.queue, true) : queue;
}

cl::Buffer ContextImpl::scratch(const std::string& purpose, std::size_t bytes, std::vector<cl::Event>& waits) {
    std::unique_lock<std::mutex> lock(mutex_);
    Scratch& held = scratch_[purpose];
    // Wait while another thread is between its scratch and scratch_used of this purpose.
    // (A hold of this very thread is left over from a call that threw: take it over.)
    const std::thread::id self = std::this_thread::get_id();
    scratch_released_.wait(lock, [&] { return !held.held || held.holder == self; });
    held.held = true;
    held.holder = self;
    if (held.bytes < bytes) {
        // The old buffer lives on until its last user is done (OpenCL reference counts).
        cl_int status = CL_SUCCESS;
        cl::Buffer grown(context, CL_MEM_READ_WRITE, bytes, nullptr, &status);
        if (status != CL_SUCCESS) {
            held.held = false;
            scratch_released_.notify_all();
            check(status, ("clCreateBuffer(" + purpose + ")").c_str());
        }
        held.buffer = grown;
        held.bytes = bytes;
        held.last_use = cl::Event();
        return held.buffer;
    }
    if (held.last_use()) waits.push_back(held.last_use);
    return held.buffer;
}

void ContextImpl::scratch_used(const std::string& purpose, const cl::Event& last) {
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        Scratch& held = scratch_[purpose];
        held.last_use = last;
        held.held = false;
    }
    scratch_released_.notify_all();
}

void ContextImpl::release_abandoned_scratch() {
    bool released = false;
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        const std::thread::id self = std::this_thread::get_id();
        for (auto& [purpose, held] : scratch_)
            if (held.held && held.holder == self) {
                held = Scratch();
                released = true;
            }
    }
    if (released) scratch_released_.notify_all();
}

std::vector<cl::Event> wait_list(const Enqueue& enqueue) {
    std::vector<cl::Event> events;
    for (cl_event e : enqueue.wait_for) events.emplace_back(e, true);
    return events;
}

void complete(const Enqueue& enqueue, const cl::CommandQueue& queue, const cl::Event& last) {
    if (enqueue.done) {
        *enqueue.done = last();
        if (last()) check(clRetainEvent(last()), "clRetainEvent");
    }
    if (enqueue.blocking) check(queue.finish(), "clFinish");
}

void complete_without_work(const Enqueue& enqueue, const cl::CommandQueue& queue) {
    std::vector<cl::Event> waits = wait_list(enqueue);
    cl::Event marker;
    check(queue.enqueueMarkerWithWaitList(waits.empty() ? nullptr : &waits, &marker), "clEnqueueMarkerWithWaitList");
    complete(enqueue, queue, marker);
}

} // namespace detail

namespace {

std::unique_ptr<detail::ContextImpl> make_impl(const cl::Device& device, const DeviceInfo& info) {
    auto impl = std::make_unique<detail::ContextImpl>();
    cl_int status = CL_SUCCESS;
    impl->device = device;
    impl->info = info;
    impl->context = cl::Context(device, nullptr, nullptr, nullptr, &status);
    detail::check(status, "clCreateContext");
    impl->queue = cl::CommandQueue(impl->context, device, 0, &status);
    detail::check(status, "clCreateCommandQueue");
    return impl;
}

void apply_environment(detail::ContextImpl& impl) {
    if (const char* dir = std::getenv("MSMCL_CACHE_DIR"); dir && *dir)
        impl.programs.set_disk_directory(dir, "MSMCL_CACHE_DIR");
}

} // namespace

Context::Context(const DeviceSelection& selection) {
    detail::DeviceCandidate chosen = detail::select_device(selection);
    impl_ = make_impl(chosen.device, chosen.info);
    apply_environment(*impl_);
}

Context::Context(cl_context context, cl_device_id device, cl_command_queue queue) {
    if (!context || !device) throw input_error("msmcl::Context: null cl_context or cl_device_id");
    impl_ = std::make_unique<detail::ContextImpl>();
    impl_->context = cl::Context(context, true);
    impl_->device = cl::Device(device, true);
    // Describe the borrowed device like an enumerated one.
    cl::Platform platform(impl_->device.getInfo<CL_DEVICE_PLATFORM>(), true);
    std::string platform_name;
    platform.getInfo(CL_PLATFORM_NAME, &platform_name);
    while (!platform_name.empty() && platform_name.back() == '\0') platform_name.pop_back();
    impl_->info = detail::describe_device(impl_->device, -1, -1, platform_name);
    if (queue) {
        impl_->queue = cl::CommandQueue(queue, true);
    } else {
        cl_int status = CL_SUCCESS;
        impl_->queue = cl::CommandQueue(impl_->context, impl_->device, 0, &status);
        detail::check(status, "clCreateCommandQueue");
    }
    apply_environment(*impl_);
}

Context::~Context() = default;
Context::Context(Context&&) noexcept = default;
Context& Context::operator=(Context&&) noexcept = default;

const DeviceInfo& Context::device() const { return impl_->info; }
cl_context Context::cl_context_handle() const { return impl_->context(); }
cl_device_id Context::cl_device_handle() const { return impl_->device(); }
cl_command_queue Context::cl_queue_handle() const { return impl_->queue(); }
void Context::finish() { detail::check(impl_->queue.finish(), "clFinish"); }
void Context::set_binary_cache_dir(const std::string& directory) { impl_->programs.set_disk_directory(directory); }
void Context::set_extra_build_options(const std::string& options) { impl_->set_extra_build_options(options); }
std::size_t Context::programs_built() const { return impl_->programs.programs_built(); }
std::vector<std::string> Context::kernel_choices() const { return impl_->kernel_choices(); }

namespace detail {

void ContextImpl::note_choice(const std::string& operation, const std::string& choice) {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (std::pair<std::string, std::string>& entry : choices_) {
        if (entry.first == operation) {
            entry.second = choice;
            return;
        }
    }
    choices_.emplace_back(operation, choice);
}

std::vector<std::string> ContextImpl::kernel_choices() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::string> lines;
    for (const std::pair<std::string, std::string>& entry : choices_) lines.push_back(entry.first + ": " + entry.second);
    return lines;
}

std::string ContextImpl::kernel_choice(const std::string& operation) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const std::pair<std::string, std::string>& entry : choices_)
        if (entry.first == operation) return entry.second;
    return {};
}

KernelFit kernel_fit(const ContextImpl& impl, const cl::Kernel& kernel) {
    KernelFit fit;
    fit.work_items = std::min(impl.info.max_work_group_size,
                              kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(impl.device));
    fit.local_bytes = kernel.getWorkGroupInfo<CL_KERNEL_LOCAL_MEM_SIZE>(impl.device);
    fit.device_local_bytes = impl.info.local_mem_bytes;
    return fit;
}

std::size_t fitting_group(const KernelFit& fit, std::size_t preferred) {
    std::size_t group = preferred;
    while (group > 1 && group > fit.work_items) group /= 2;
    return group;
}

} // namespace detail

} // namespace msmcl
