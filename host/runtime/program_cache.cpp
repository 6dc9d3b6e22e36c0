// Program and kernel caching; binaries on disk when a cache directory is set.
#include "runtime/program_cache.hpp"

#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

namespace msmcl::detail {

std::uint64_t fnv1a64(const std::string& bytes, std::uint64_t seed) {
    std::uint64_t hash = seed;
    for (unsigned char c : bytes) {
        hash ^= c;
        hash *= 0x100000001b3ull;
    }
    return hash;
}

namespace {

std::string device_string(const cl::Device& device, cl_device_info what) {
    std::string value;
    device.getInfo(what, &value);
    while (!value.empty() && value.back() == '\0') value.pop_back();
    return value;
}

std::string build_log(const cl::Program& program, const cl::Device& device) {
    std::string log;
    program.getBuildInfo(device, CL_PROGRAM_BUILD_LOG, &log);
    while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
    return log;
}

// Loads a cached binary; empty when absent or unreadable.
std::vector<unsigned char> read_binary(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return {};
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Stores a binary atomically (temp file + rename); a failure only loses the cache entry.
void write_binary(const std::string& path, const std::vector<unsigned char>& binary) {
    const std::string temporary = path + ".tmp";
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out) return;
        out.write(reinterpret_cast<const char*>(binary.data()), static_cast<std::streamsize>(binary.size()));
        if (!out) {
            out.close();
            std::remove(temporary.c_str());
            return;
        }
    }
    if (std::rename(temporary.c_str(), path.c_str()) != 0) std::remove(temporary.c_str());
}

} // namespace

std::string ProgramCache::disk_path(const cl::Device& device, const std::string& source,
                                    const std::string& options) const {
    // The binary depends on the device, its driver and the platform, besides the inputs.
    cl::Platform platform(device.getInfo<CL_DEVICE_PLATFORM>());
    std::string platform_version;
    platform.getInfo(CL_PLATFORM_VERSION, &platform_version);
    const std::string identity = device_string(device, CL_DEVICE_NAME) + '\n' +
                                 device_string(device, CL_DEVICE_VENDOR) + '\n' +
                                 device_string(device, CL_DRIVER_VERSION) + '\n' + platform_version +
                                 '\n' + options + '\n';
    std::ostringstream name;
    name << disk_directory_ << "/msmcl-" << std::hex << fnv1a64(source, fnv1a64(identity)) << ".bin";
    return name.str();
}

cl::Program ProgramCache::build(const cl::Context& context, const cl::Device& device,
                                const std::string& label, const std::string& source,
                                const std::string& options) {
    const std::vector<cl::Device> devices{device};
    cl_int status = CL_SUCCESS;
    // A binary from the disk cache, if one was stored for this very device and driver.
    const std::string path = disk_directory_.empty() ? std::string() : disk_path(device, source, options);
    if (!path.empty()) {
        std::vector<unsigned char> binary = read_binary(path);
        if (!binary.empty()) {
            cl::Program::Binaries binaries{binary};
            cl::Program cached(context, devices, binaries, nullptr, &status);
            if (status == CL_SUCCESS && cached.build(devices, options.c_str()) == CL_SUCCESS)
                return cached;
        }
    }
    // Compile from source.
    cl::Program program(context, source, false, &status);
    check(status, "clCreateProgramWithSource");
    status = program.build(devices, options.c_str());
    if (status != CL_SUCCESS) {
        if (status == CL_BUILD_PROGRAM_FAILURE || status == CL_INVALID_BUILD_OPTIONS ||
            status == CL_COMPILE_PROGRAM_FAILURE)
            throw build_error(status, label, options, build_log(program, device));
        throw opencl_error(status, "clBuildProgram", label);
    }
    ++programs_built_;
    if (!path.empty()) {
        std::vector<std::vector<unsigned char>> binaries;
        if (program.getInfo(CL_PROGRAM_BINARIES, &binaries) == CL_SUCCESS && binaries.size() == 1 &&
            !binaries[0].empty())
            write_binary(path, binaries[0]);
    }
    return program;
}

const cl::Program& ProgramCache::program(const cl::Context& context, const cl::Device& device,
                                         const std::string& label, const std::string& source,
                                         const std::string& options) {
    Key key{context(), device(), options, fnv1a64(source)};
    auto found = programs_.find(key);
    if (found == programs_.end())
        found = programs_.emplace(key, build(context, device, label, source, options)).first;
    return found->second;
}

cl::Kernel& ProgramCache::kernel(const cl::Context& context, const cl::Device& device,
                                 const std::string& label, const std::string& source,
                                 const std::string& options, const std::string& kernel_name) {
    Key key{context(), device(), options, fnv1a64(source)};
    auto id = std::make_tuple(key, kernel_name);
    auto found = kernels_.find(id);
    if (found != kernels_.end()) return found->second;
    const cl::Program& built = program(context, device, label, source, options);
    cl_int status = CL_SUCCESS;
    cl::Kernel kernel(built, kernel_name.c_str(), &status);
    check(status, ("clCreateKernel(" + kernel_name + ")").c_str());
    return kernels_.emplace(id, std::move(kernel)).first->second;
}

} // namespace msmcl::detail
