#include "io/atomic_file.hpp"

#include <msmcl/errors.hpp>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <csignal>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace msmcl::io {
namespace {

std::string system_message(int error_number) { return std::strerror(error_number); }

/// A temporary name next to `path`: hidden, unique per process and call, ends in .tmp.
std::string temporary_name_for(const std::string& path) {
    static std::atomic<unsigned> counter{0};
    const std::size_t slash = path.find_last_of('/');
    const std::string directory = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
    const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
    return directory + "." + name + "." + std::to_string(static_cast<long>(::getpid())) + "." +
           std::to_string(counter.fetch_add(1)) + ".tmp";
}

/// Names of the temporary files being written, where a signal handler can read them:
/// fixed slots, each free, being filled, or holding a name to remove.
enum SlotState : int { slot_free, slot_filling, slot_live };
struct LiveTemporary {
    std::atomic<int> state{slot_free};
    char name[4096];
};
constexpr int live_slots = 64;
LiveTemporary live_temporaries[live_slots];

/// Records `name` for the signal handler; -1 when every slot is taken or the name is too
/// long (the file is then only removed on the normal paths).
int register_temporary(const std::string& name) {
    if (name.size() >= sizeof live_temporaries[0].name) return -1;
    for (int i = 0; i < live_slots; ++i) {
        int expected = slot_free;
        if (live_temporaries[i].state.compare_exchange_strong(expected, slot_filling)) {
            std::memcpy(live_temporaries[i].name, name.c_str(), name.size() + 1);
            live_temporaries[i].state.store(slot_live, std::memory_order_release);
            return i;
        }
    }
    return -1;
}

void unregister_temporary(int slot) {
    if (slot >= 0) live_temporaries[slot].state.store(slot_free, std::memory_order_release);
}

/// Async-signal-safe: unlink() the live temporary files, then end by the signal.
extern "C" void remove_temporaries_and_reraise(int signal_number) {
    for (LiveTemporary& slot : live_temporaries)
        if (slot.state.load(std::memory_order_acquire) == slot_live) ::unlink(slot.name);
    std::signal(signal_number, SIG_DFL);
    std::raise(signal_number);
}

} // namespace

/// Closes and deletes the temporary file unless it was handed over by rename.
class TemporaryFile {
public:
    /// Creates the file (exclusively); known to the signal handler from before it exists.
    explicit TemporaryFile(std::string name) : name_(std::move(name)), slot_(register_temporary(name_)) {
        descriptor_ = ::open(name_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        open_error_ = descriptor_ < 0 ? errno : 0;
        if (descriptor_ < 0) renamed_ = true; // not ours: never unlink it
    }
    ~TemporaryFile() {
        if (descriptor_ >= 0) ::close(descriptor_);
        if (!renamed_) ::unlink(name_.c_str());
        unregister_temporary(slot_);
    }
    /// errno of a failed creation, else 0.
    int open_error() const { return open_error_; }
    TemporaryFile(const TemporaryFile&) = delete;
    TemporaryFile& operator=(const TemporaryFile&) = delete;

    int descriptor() const { return descriptor_; }
    const std::string& name() const { return name_; }
    /// Closes the descriptor; returns errno of a failed close (0 on success).
    int close() {
        const int result = ::close(descriptor_);
        descriptor_ = -1;
        return result == 0 ? 0 : errno;
    }
    void mark_renamed() { renamed_ = true; }

private:
    std::string name_;
    int slot_;
    int descriptor_ = -1;
    int open_error_ = 0;
    bool renamed_ = false;
};


AtomicFile::AtomicFile(const std::string& path) : path_(path) {
    if (path.empty()) throw input_error("empty output file name");
    // A directory under the final name would make rename fail late: refuse it up front.
    struct stat existing {};
    if (::stat(path.c_str(), &existing) == 0 && S_ISDIR(existing.st_mode))
        throw input_error(path + ": cannot write: is a directory");

    // Create the temporary file next to the final one, so rename stays on one file system.
    temporary_ = std::make_unique<TemporaryFile>(temporary_name_for(path));
    if (temporary_->open_error() != 0)
        throw input_error(path + ": cannot write: " + system_message(temporary_->open_error()));
}

AtomicFile::~AtomicFile() = default;

void AtomicFile::write(const void* data, std::size_t size) {
    // Write everything at the current position, retrying short writes.
    const char* bytes = static_cast<const char*>(data);
    std::size_t written = 0;
    while (written < size) {
        const ssize_t result = ::write(temporary_->descriptor(), bytes + written, size - written);
        if (result < 0) {
            if (errno == EINTR) continue;
            const int error_number = errno;
            throw error(path_ + ": cannot write: " + system_message(error_number));
        }
        written += static_cast<std::size_t>(result);
    }
    position_ += size;
}

void AtomicFile::seek(std::uint64_t position) {
    if (::lseek(temporary_->descriptor(), static_cast<off_t>(position), SEEK_SET) < 0) {
        const int error_number = errno;
        throw error(path_ + ": cannot write: " + system_message(error_number));
    }
    position_ = position;
}

void AtomicFile::commit() {
    // Flush to disk before the rename makes the file visible.
    if (::fsync(temporary_->descriptor()) != 0 && errno != EINVAL && errno != EROFS) {
        const int error_number = errno;
        throw error(path_ + ": cannot write: " + system_message(error_number));
    }
    if (const int close_error = temporary_->close(); close_error != 0)
        throw error(path_ + ": cannot write: " + system_message(close_error));

    // Publish under the final name in one step.
    if (::rename(temporary_->name().c_str(), path_.c_str()) != 0) {
        const int error_number = errno;
        throw error(path_ + ": cannot write: " + system_message(error_number));
    }
    temporary_->mark_renamed();
}

void write_file_atomically(const std::string& path, const void* data, std::size_t size) {
    AtomicFile file(path);
    file.write(data, size);
    file.commit();
}

void remove_temporary_files_on_signals() {
    for (int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
        struct sigaction action {};
        action.sa_handler = remove_temporaries_and_reraise;
        sigemptyset(&action.sa_mask);
        struct sigaction previous {};
        // Keep a signal its parent chose to ignore (nohup, background jobs) ignored.
        if (::sigaction(signal_number, nullptr, &previous) == 0 && previous.sa_handler == SIG_IGN) continue;
        ::sigaction(signal_number, &action, nullptr);
    }
}

std::string read_whole_file(const std::string& path, std::uint64_t max_bytes) {
    struct stat status {};
    if (::stat(path.c_str(), &status) != 0) {
        const int error_number = errno;
        throw input_error(path + ": cannot open: " + system_message(error_number));
    }
    if (S_ISDIR(status.st_mode)) throw input_error(path + ": cannot open: is a directory");
    if (S_ISREG(status.st_mode) && static_cast<std::uint64_t>(status.st_size) > max_bytes)
        throw input_error(path + ": the file's " + std::to_string(status.st_size) + " bytes exceed the limit of " +
                          std::to_string(max_bytes) + " bytes (MSMCL_MAX_BYTES)");

    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (!file) {
        const int error_number = errno;
        throw input_error(path + ": cannot open: " + system_message(error_number));
    }
    std::string content;
    char buffer[1 << 16];
    std::size_t count = 0;
    while ((count = std::fread(buffer, 1, sizeof buffer, file)) > 0) {
        // A pipe or device has no size up front: stop at the limit while reading.
        if (content.size() + count > max_bytes) {
            std::fclose(file);
            throw input_error(path + ": the file exceeds the limit of " + std::to_string(max_bytes) +
                              " bytes (MSMCL_MAX_BYTES)");
        }
        content.append(buffer, count);
    }
    const bool failed = std::ferror(file) != 0;
    std::fclose(file);
    if (failed) throw input_error(path + ": cannot read: I/O error");
    return content;
}

} // namespace msmcl::io
