// Built programs and kernel objects, cached in memory per (context, device, options,
// source hash), optionally also on disk as binaries keyed by the driver too.
#pragma once

#include "runtime/opencl.hpp"

#include <cstdint>
#include <map>
#include <string>
#include <tuple>

namespace msmcl::detail {

/// 64-bit FNV-1a of a byte string (stable across runs and platforms).
std::uint64_t fnv1a64(const std::string& bytes, std::uint64_t seed = 0xcbf29ce484222325ull);

class ProgramCache {
public:
    /// The program for `source` built with `options`: from memory, else from the disk
    /// cache, else compiled (build failures throw build_error with the log).
    /// `label` names the program in errors ("filter_fused_gpu.cl").
    const cl::Program& program(const cl::Context& context, const cl::Device& device,
                               const std::string& label, const std::string& source,
                               const std::string& options);
    /// A kernel object of such a program, created once.
    cl::Kernel& kernel(const cl::Context& context, const cl::Device& device,
                       const std::string& label, const std::string& source,
                       const std::string& options, const std::string& kernel_name);

    void set_disk_directory(std::string directory) { disk_directory_ = std::move(directory); }
    const std::string& disk_directory() const { return disk_directory_; }
    std::size_t programs_built() const { return programs_built_; }

private:
    using Key = std::tuple<cl_context, cl_device_id, std::string /*options*/, std::uint64_t /*source*/>;
    cl::Program build(const cl::Context& context, const cl::Device& device, const std::string& label,
                      const std::string& source, const std::string& options);
    std::string disk_path(const cl::Device& device, const std::string& source,
                          const std::string& options) const;

    std::map<Key, cl::Program> programs_;
    std::map<std::tuple<Key, std::string>, cl::Kernel> kernels_;
    std::string disk_directory_;
    std::size_t programs_built_ = 0;
};

} // namespace msmcl::detail
