// The OpenCL context msmcl works in: device choice, queue, program cache.
#pragma once

#include <CL/cl.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace msmcl {

/// What a device filter looks at.
struct DeviceInfo {
    int platform_index = 0;
    int device_index = 0;           ///< index within its platform
    std::string platform_name;
    std::string name;
    std::string vendor;
    std::string driver_version;
    std::string opencl_version;
    bool is_gpu = false;
    bool is_cpu = false;
    unsigned compute_units = 0;
    std::size_t max_work_group_size = 0;
    unsigned long long local_mem_bytes = 0;
    unsigned long long global_mem_bytes = 0;
    unsigned long long max_alloc_bytes = 0;
    std::size_t image2d_max_width = 0;
    std::size_t image2d_max_height = 0;
    bool host_unified_memory = false; ///< CL_DEVICE_HOST_UNIFIED_MEMORY: the device works on host memory
};

/// A predicate on devices; compose with &&, || and !.
class DeviceFilter {
public:
    using Predicate = std::function<bool(const DeviceInfo&)>;
    DeviceFilter() : predicate_([](const DeviceInfo&) { return true; }) {}
    explicit DeviceFilter(Predicate p) : predicate_(std::move(p)) {}
    bool operator()(const DeviceInfo& d) const { return predicate_(d); }

    static DeviceFilter any();
    static DeviceFilter gpu();
    static DeviceFilter cpu();
    /// Case-insensitive substring of the device name.
    static DeviceFilter name_contains(std::string text);
    /// Case-insensitive substring of the platform name.
    static DeviceFilter platform_contains(std::string text);
    static DeviceFilter platform_index(int index);
    static DeviceFilter device_index(int index);
    /// Parses a user's device spec: "gpu", "cpu", an index "1", "P:D" (platform:device
    /// indices) or a name substring.
    static DeviceFilter parse(const std::string& device_spec);
    static DeviceFilter parse_platform(const std::string& platform_spec);

private:
    Predicate predicate_;
};
DeviceFilter operator&&(DeviceFilter a, DeviceFilter b);
DeviceFilter operator||(DeviceFilter a, DeviceFilter b);
DeviceFilter operator!(DeviceFilter a);

/// How a Context picks its device.
/// Order: the explicit `device`/`platform` specs, else the environment variables
/// MSMCL_DEVICE / MSMCL_PLATFORM, else the default (first GPU, else first CPU, else first
/// device). With `strict` (or MSMCL_STRICT=1) a spec that matches nothing throws
/// device_error; otherwise it falls back to the default.
struct DeviceSelection {
    std::string device;   ///< spec as in DeviceFilter::parse; empty = not given
    std::string platform; ///< spec as in DeviceFilter::parse_platform; empty = not given
    bool strict = false;
    bool use_environment = true;
    std::optional<DeviceFilter> filter; ///< extra filter ANDed with the specs
};

/// Every OpenCL device of every platform (empty if there is no ICD/platform).
std::vector<DeviceInfo> list_devices();

namespace detail { struct ContextImpl; }

/// Owns (or borrows) an OpenCL context, one device, an in-order queue, and the cache of
/// built programs and kernels. Also keeps the scratch buffers of the table builds between
/// calls (the largest asked for: about 1/32 of a table on CPUs, 1/16 on GPUs), released
/// with the Context.
///
/// Thread safety: any number of threads may call msmcl's operations (filter, shade,
/// build_sat, soft_shade, scatter, ... and the C API) on one Context at once, and each
/// call gives exactly the bytes it gives alone. The program cache is locked and builds
/// each program once; every thread gets kernel objects of its own (kept until the Context
/// is destroyed); a scratch buffer is handed to one call at a time, ordered by events.
/// Calls on the Context's own queue are enqueued in whatever order the threads reach it;
/// a thread that needs its work ordered against another thread's passes events
/// (Enqueue::wait_for / done) or its own queue. set_binary_cache_dir and
/// set_extra_build_options may be called at any time and apply to programs built
/// afterwards. Not thread-safe: moving, assigning or destroying a Context while another
/// thread uses it.
class Context {
public:
    /// Picks a device as DeviceSelection describes and creates context and queue.
    explicit Context(const DeviceSelection& selection = {});
    /// Works inside an engine's context: msmcl retains the handles, never releases more
    /// than it retained. `queue` may be null (msmcl creates one on `device`).
    Context(cl_context context, cl_device_id device, cl_command_queue queue = nullptr);
    ~Context();
    Context(Context&&) noexcept;
    Context& operator=(Context&&) noexcept;
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    const DeviceInfo& device() const;
    cl_context cl_context_handle() const;
    cl_device_id cl_device_handle() const;
    cl_command_queue cl_queue_handle() const;
    /// Blocks until all work msmcl enqueued on its own queue is done.
    void finish();

    /// Optional on-disk cache of program binaries (keyed by device, driver version,
    /// options and source hash). Empty path disables it (the default unless
    /// MSMCL_CACHE_DIR is set). The directory is created when missing; one that cannot
    /// be created or written into throws input_error (so does an unusable
    /// MSMCL_CACHE_DIR, from the constructor). A damaged cache file is rebuilt.
    void set_binary_cache_dir(const std::string& directory);

    /// Extra OpenCL build options appended for every program (e.g. "-cl-fast-relaxed-math").
    void set_extra_build_options(const std::string& options);

    /// Number of programs built (not found in a cache) since the Context was made.
    std::size_t programs_built() const;

    /// The work distribution each operation last ran with on this Context and why, one
    /// line per operation ("filter: fused_cpu, tile 128x64 (one work-item a tile)"), in the
    /// order the operations first ran (docs/devices.md, automatic choice).
    std::vector<std::string> kernel_choices() const;

    detail::ContextImpl& impl() { return *impl_; }

private:
    std::unique_ptr<detail::ContextImpl> impl_;
};

} // namespace msmcl
