// Program and kernel caching; binaries on disk when a cache directory is set.
#include "runtime/program_cache.hpp"

#include <chrono>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <sstream>
#include <atomic>
#include <chrono>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
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

/// A failed build whose log names no error in the source failed in the driver itself;
/// drivers that compile through files (PoCL) fail so when they cannot write them. Says
/// so, and names the file size limit when one is set.
std::string explain_silent_build_failure(const std::string& log) {
    std::string lower = log;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
    if (lower.find("error") != std::string::npos) return log;
    std::string note = "the log reports no error in the source: the driver itself failed, e.g. it could not write "
                       "its compiled files (disk full, no permission on its cache directory";
    rlimit limit{};
    if (::getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
        note += ", or the file size limit of " + std::to_string(static_cast<unsigned long long>(limit.rlim_cur)) +
                " bytes set by ulimit -f";
    note += ")";
    return log.empty() ? note : log + "\n" + note;
}

// Disk cache files: a header that lets a damaged or foreign file be told from a binary
// before the driver sees it, then the binary.
constexpr char kMagic[8] = {'M', 'S', 'M', 'C', 'L', 'B', 'I', 'N'};
constexpr std::size_t kHeaderBytes = sizeof kMagic + 16; // magic, byte count, FNV-1a of the bytes

/// Largest cache entry read: compiled programs are a few MiB; anything larger is no entry.
constexpr std::uint64_t kMaxEntryBytes = 256ull << 20;

/// What a cache name holds.
enum class EntryState { absent, regular, other };

/// Looks at `path` without following a symlink or opening it.
EntryState entry_state(const std::string& path) {
    struct stat status {};
    if (::lstat(path.c_str(), &status) != 0) return errno == ENOENT ? EntryState::absent : EntryState::other;
    return S_ISREG(status.st_mode) && static_cast<std::uint64_t>(status.st_size) <= kMaxEntryBytes ? EntryState::regular
                                                                                                   : EntryState::other;
}

// A cached binary; empty when absent, not a regular file (a folder, a symlink, a FIFO), too
// large, unreadable, truncated or damaged. Never waits on what the name holds.
std::vector<unsigned char> read_binary(const std::string& path) {
    const int descriptor = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (descriptor < 0) return {};
    std::string content;
    struct stat status {};
    if (::fstat(descriptor, &status) == 0 && S_ISREG(status.st_mode) &&
        static_cast<std::uint64_t>(status.st_size) <= kMaxEntryBytes) {
        // At most the size it had when opened.
        content.resize(static_cast<std::size_t>(status.st_size));
        std::size_t got = 0;
        while (got < content.size()) {
            const ssize_t count = ::read(descriptor, content.data() + got, content.size() - got);
            if (count < 0 && errno == EINTR) continue;
            if (count <= 0) break;
            got += static_cast<std::size_t>(count);
        }
        content.resize(got);
    }
    ::close(descriptor);
    if (content.size() < kHeaderBytes || content.compare(0, sizeof kMagic, kMagic, sizeof kMagic) != 0) return {};
    std::uint64_t size = 0, hash = 0;
    std::memcpy(&size, content.data() + sizeof kMagic, 8);
    std::memcpy(&hash, content.data() + sizeof kMagic + 8, 8);
    const std::string bytes = content.substr(kHeaderBytes);
    if (bytes.size() != size || bytes.empty() || fnv1a64(bytes) != hash) return {};
    return {bytes.begin(), bytes.end()};
}

/// A temporary name in `directory` of one short length (random per process and call).
std::string temporary_entry_name(const std::string& directory) {
    static std::atomic<std::uint64_t> counter{0};
    std::uint64_t bits = fnv1a64(std::to_string(::getpid()) + ':' + std::to_string(counter++) + ':' +
                                 std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    static const char digits[] = "0123456789abcdefghijklmnopqrstuv";
    std::string name = directory + "/.msmcl-";
    for (int i = 0; i < 10; ++i, bits >>= 5) name += digits[bits & 31];
    return name + ".tmp";
}

// Stores a binary atomically (a temporary file of its own, then rename); a failure only
// loses the cache entry, never the call.
void write_binary(const std::string& path, const std::vector<unsigned char>& binary) {
    const std::string directory = path.substr(0, path.find_last_of('/'));
    const std::string temporary = temporary_entry_name(directory);
    const std::string bytes(binary.begin(), binary.end());
    const std::uint64_t size = bytes.size(), hash = fnv1a64(bytes);
    std::string content(kMagic, sizeof kMagic);
    content.append(reinterpret_cast<const char*>(&size), 8);
    content.append(reinterpret_cast<const char*>(&hash), 8);
    content += bytes;
    const int descriptor = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (descriptor < 0) return;
    std::size_t written = 0;
    while (written < content.size()) {
        const ssize_t count = ::write(descriptor, content.data() + written, content.size() - written);
        if (count < 0 && errno == EINTR) continue;
        if (count <= 0) break;
        written += static_cast<std::size_t>(count);
    }
    const bool complete = ::close(descriptor) == 0 && written == content.size();
    if (!complete || std::rename(temporary.c_str(), path.c_str()) != 0) std::remove(temporary.c_str());
}

/// The names an entry may have: `path`, then fresh ones for when a name holds something that
/// is no cache entry (a folder, a symlink, a FIFO), which is left alone.
std::vector<std::string> entry_names(const std::string& path) {
    const std::string stem = path.substr(0, path.size() - 4); // without ".bin"
    return {path, stem + "-1.bin", stem + "-2.bin", stem + "-3.bin"};
}

} // namespace

std::string ProgramCache::disk_path(const std::string& directory, const cl::Device& device, const std::string& source,
                                    const std::string& options) {
    // The binary depends on the device, its driver and the platform, besides the inputs.
    cl::Platform platform(device.getInfo<CL_DEVICE_PLATFORM>());
    std::string platform_version;
    platform.getInfo(CL_PLATFORM_VERSION, &platform_version);
    const std::string identity = device_string(device, CL_DEVICE_NAME) + '\n' +
                                 device_string(device, CL_DEVICE_VENDOR) + '\n' +
                                 device_string(device, CL_DRIVER_VERSION) + '\n' + platform_version +
                                 '\n' + options + '\n';
    std::ostringstream name;
    name << directory << "/msmcl-" << std::hex << fnv1a64(source, fnv1a64(identity)) << ".bin";
    return name.str();
}

void ProgramCache::set_disk_directory(const std::string& directory, const std::string& what) {
    if (!directory.empty()) {
        // Create it when missing; refuse one msmcl could not store binaries in.
        std::error_code failure;
        std::filesystem::create_directories(directory, failure);
        const auto refuse = [&](const std::string& problem) {
            throw input_error(what + " '" + directory + "': " + problem);
        };
        if (failure) refuse("cannot create it: " + failure.message());
        if (!std::filesystem::is_directory(directory, failure)) refuse("not a directory");
        if (::access(directory.c_str(), W_OK | X_OK) != 0) refuse(std::string("cannot write into it: ") + std::strerror(errno));
    }
    const std::lock_guard<std::mutex> lock(mutex_);
    disk_directory_ = directory;
}

std::string ProgramCache::disk_directory() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return disk_directory_;
}

cl::Program ProgramCache::build(const cl::Context& context, const cl::Device& device, const std::string& label,
                                const std::string& source, const std::string& options,
                                const std::string& disk_directory) {
    const std::vector<cl::Device> devices{device};
    cl_int status = CL_SUCCESS;
    // A binary from the disk cache, if one was stored for this very device and driver.
    const std::string path = disk_directory.empty() ? std::string() : disk_path(disk_directory, device, source, options);
    // The first of its names that is a regular file is the entry; names holding anything
    // else are passed over (and the binary is stored under the next free one).
    std::string entry;
    if (!path.empty())
        for (const std::string& name : entry_names(path)) {
            const EntryState state = entry_state(name);
            if (state == EntryState::other) continue;
            entry = name;
            break;
        }
    if (!entry.empty()) {
        std::vector<unsigned char> binary = read_binary(entry);
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
            throw build_error(status, label, options, explain_silent_build_failure(build_log(program, device)));
        throw opencl_error(status, "clBuildProgram", label);
    }
    ++programs_built_;
    if (!entry.empty()) {
        std::vector<std::vector<unsigned char>> binaries;
        if (program.getInfo(CL_PROGRAM_BINARIES, &binaries) == CL_SUCCESS && binaries.size() == 1 &&
            !binaries[0].empty())
            write_binary(entry, binaries[0]);
    }
    return program;
}

cl::Program ProgramCache::program(const cl::Context& context, const cl::Device& device, const std::string& label,
                                  const KernelSource& source, const std::string& options) {
    // Find or add the entry under the cache's lock, build it under its own.
    Entry* entry = nullptr;
    std::string disk_directory;
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        std::unique_ptr<Entry>& slot = programs_[Key{context(), device(), options, source.hash}];
        if (!slot) slot = std::make_unique<Entry>();
        entry = slot.get();
        disk_directory = disk_directory_;
    }
    const std::lock_guard<std::mutex> building(entry->build);
    if (!entry->built) {
        const auto start = std::chrono::steady_clock::now();
        entry->program = build(context, device, label, source.text, options, disk_directory);
        entry->built = true;
        build_nanoseconds_ += static_cast<std::uint64_t>(
            std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count());
    }
    return entry->program;
}

cl::Program ProgramCache::program(const cl::Context& context, const cl::Device& device, const std::string& label,
                                  const std::string& source, const std::string& options) {
    return program(context, device, label, KernelSource{source, fnv1a64(source)}, options);
}

cl::Kernel& ProgramCache::kernel(const cl::Context& context, const cl::Device& device, const std::string& label,
                                 const KernelSource& source, const std::string& options,
                                 const std::string& kernel_name) {
    auto id = std::make_tuple(Key{context(), device(), options, source.hash}, kernel_name, std::this_thread::get_id());
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        auto found = kernels_.find(id);
        if (found != kernels_.end()) return found->second;
    }
    // This thread's first use: a kernel object of its own from the shared program.
    const cl::Program built = program(context, device, label, source, options);
    cl_int status = CL_SUCCESS;
    cl::Kernel kernel(built, kernel_name.c_str(), &status);
    check(status, ("clCreateKernel(" + kernel_name + ")").c_str());
    const std::lock_guard<std::mutex> lock(mutex_);
    return kernels_.emplace(std::move(id), std::move(kernel)).first->second;
}

cl::Kernel& ProgramCache::kernel(const cl::Context& context, const cl::Device& device, const std::string& label,
                                 const std::string& source, const std::string& options,
                                 const std::string& kernel_name) {
    return kernel(context, device, label, KernelSource{source, fnv1a64(source)}, options, kernel_name);
}

} // namespace msmcl::detail
