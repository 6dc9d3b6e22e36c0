// Built programs and kernel objects, cached in memory per (context, device, options,
// source hash), optionally also on disk as binaries keyed by the driver too.
// Thread-safe: the maps are locked, a program is built once even when several threads
// ask for it at once (other programs build meanwhile), and every thread gets kernel
// objects of its own, since clSetKernelArg on one kernel from two threads races.
#pragma once

#include "runtime/kernel_sources.hpp"
#include "runtime/opencl.hpp"

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <tuple>

namespace msmcl::detail {

/// 64-bit FNV-1a of a byte string (stable across runs and platforms).
std::uint64_t fnv1a64(const std::string& bytes, std::uint64_t seed = 0xcbf29ce484222325ull);

class ProgramCache {
public:
    /// The program for `source` built with `options`: from memory, else from the disk
    /// cache, else compiled (build failures throw build_error with the log).
    /// `label` names the program in errors ("filter_fused_gpu.cl").
    cl::Program program(const cl::Context& context, const cl::Device& device, const std::string& label,
                        const KernelSource& source, const std::string& options);
    cl::Program program(const cl::Context& context, const cl::Device& device, const std::string& label,
                        const std::string& source, const std::string& options);
    /// The calling thread's kernel object of such a program, created once per thread and
    /// kept until the cache is destroyed. Only the calling thread may set its arguments.
    cl::Kernel& kernel(const cl::Context& context, const cl::Device& device, const std::string& label,
                       const KernelSource& source, const std::string& options, const std::string& kernel_name);
    cl::Kernel& kernel(const cl::Context& context, const cl::Device& device, const std::string& label,
                       const std::string& source, const std::string& options, const std::string& kernel_name);

    /// Stores binaries in `directory` from now on (empty: no disk cache). The directory is
    /// created when missing; one that cannot be created or written is an input_error
    /// naming it (`what` says where the path came from: "MSMCL_CACHE_DIR").
    void set_disk_directory(const std::string& directory, const std::string& what = "binary cache directory");
    std::string disk_directory() const;
    std::size_t programs_built() const { return programs_built_.load(); }
    /// Time spent building programs or loading them from the disk cache, all threads together.
    double build_milliseconds() const { return static_cast<double>(build_nanoseconds_.load()) * 1e-6; }

private:
    using Key = std::tuple<cl_context, cl_device_id, std::string /*options*/, std::uint64_t /*source*/>;
    /// One program: built at most once, under its own lock, so that different programs
    /// build in parallel while threads wanting the same one wait for it.
    struct Entry {
        std::mutex build;
        cl::Program program;
        bool built = false;
    };
    cl::Program build(const cl::Context& context, const cl::Device& device, const std::string& label,
                      const std::string& source, const std::string& options, const std::string& disk_directory);
    static std::string disk_path(const std::string& directory, const cl::Device& device, const std::string& source,
                                 const std::string& options);

    mutable std::mutex mutex_; ///< guards the maps and disk_directory_
    std::map<Key, std::unique_ptr<Entry>> programs_;
    std::map<std::tuple<Key, std::string /*kernel*/, std::thread::id>, cl::Kernel> kernels_;
    std::string disk_directory_;
    std::atomic<std::size_t> programs_built_{0};
    std::atomic<std::uint64_t> build_nanoseconds_{0};
};

} // namespace msmcl::detail
