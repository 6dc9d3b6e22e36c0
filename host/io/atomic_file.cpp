#include "io/atomic_file.hpp"

#include <msmcl/errors.hpp>

#include "io/image_limits.hpp"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <mutex>
#include <cstdio>
#include <cstring>
#include <csignal>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace msmcl::io {
namespace {

std::string system_message(int error_number) { return std::strerror(error_number); }

[[noreturn]] void refuse_output(const std::string& path, const std::string& problem) {
    throw input_error(display_name(path) + ": cannot write: " + problem);
}

/// The folder of `path` as a prefix to put a name in ("" for a bare name).
std::string folder_prefix(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

/// The folder of `path` ("." for a bare name).
std::string folder_of(const std::string& path) {
    const std::string prefix = folder_prefix(path);
    return prefix.empty() ? "." : prefix;
}

/// A temporary name beside `path`: hidden, of one short length whatever the final name
/// (so that any name the file system takes works), random per process and call.
std::string temporary_name_for(const std::string& path) {
    static std::atomic<std::uint64_t> counter{0};
    const std::uint64_t clock = static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
    std::uint64_t bits = (static_cast<std::uint64_t>(::getpid()) << 32) ^ clock ^ (counter.fetch_add(1) * 0x9e3779b97f4a7c15ull);
    // splitmix64's finalizer: every input bit moves every name character.
    bits = (bits ^ (bits >> 30)) * 0xbf58476d1ce4e5b9ull;
    bits = (bits ^ (bits >> 27)) * 0x94d049bb133111ebull;
    bits ^= bits >> 31;
    static const char digits[] = "0123456789abcdefghijklmnopqrstuv";
    std::string name = ".msmcl-";
    for (int i = 0; i < 10; ++i, bits >>= 5) name += digits[bits & 31];
    return folder_prefix(path) + name + ".tmp";
}

/// The last name of the symlink chain that starts at `path` (`path` itself when it is no
/// symlink); the chain may end at a name that does not exist yet.
std::string final_link_target(const std::string& path) {
    std::string current = path;
    for (int hop = 0; hop < 40; ++hop) {
        struct stat status {};
        if (::lstat(current.c_str(), &status) != 0 || !S_ISLNK(status.st_mode)) return current;
        std::string target(4096, '\0');
        const ssize_t length = ::readlink(current.c_str(), target.data(), target.size());
        if (length < 0 || static_cast<std::size_t>(length) >= target.size()) refuse_output(path, "cannot read the symlink");
        target.resize(static_cast<std::size_t>(length));
        current = target[0] == '/' ? target : folder_prefix(current) + target;
    }
    refuse_output(path, system_message(ELOOP));
}

std::string mode_kind(mode_t mode) {
    if (S_ISREG(mode)) return "";
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
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


OutputTarget resolve_output(const std::string& path) {
    if (path.empty()) throw input_error("empty output file name");
    if (path == "-") return {OutputKind::direct, "-"};
    struct stat status {};
    if (::stat(path.c_str(), &status) == 0) {
        // Written in place: what renaming over would replace (a device, a pipe's end).
        if (S_ISCHR(status.st_mode) || S_ISFIFO(status.st_mode) || S_ISSOCK(status.st_mode))
            return {OutputKind::direct, path};
        if (!S_ISREG(status.st_mode))
            refuse_output(path, "is " + mode_kind(status.st_mode) +
                                    " (msmcl writes regular files, character devices, FIFOs and sockets)");
        // A regular file, through its symlinks: the link stays, its target gets the bytes.
        return {OutputKind::replace, final_link_target(path)};
    }
    const int error_number = errno;
    if (error_number != ENOENT) refuse_output(path, system_message(error_number));
    // A new name, or a symlink to one (written where the link points).
    return {OutputKind::replace, final_link_target(path)};
}

void check_output_writable(const std::string& path) {
    const OutputTarget target = resolve_output(path);
    if (target.kind == OutputKind::direct) {
        if (path == "-") {
            if (::fcntl(1, F_GETFL) < 0) refuse_output(path, "standard output is closed");
        } else if (::access(target.final_path.c_str(), W_OK) != 0) {
            refuse_output(path, system_message(errno));
        }
        return;
    }
    // The temporary file is created in the final name's folder, then renamed.
    const std::string folder = folder_of(target.final_path);
    struct stat status {};
    if (::stat(folder.c_str(), &status) != 0) refuse_output(path, system_message(errno));
    if (!S_ISDIR(status.st_mode)) refuse_output(path, system_message(ENOTDIR));
    if (::access(folder.c_str(), W_OK | X_OK) != 0) refuse_output(path, system_message(errno));
}

AtomicFile::AtomicFile(const std::string& path) : path_(path), target_(resolve_output(path)) {
    if (target_.kind == OutputKind::direct) {
        // Opened now, so that a write that cannot happen fails before any work; without
        // waiting for a FIFO's reader (none: refused).
        if (path == "-") {
            direct_descriptor_ = 1;
            return;
        }
        direct_descriptor_ = ::open(target_.final_path.c_str(), O_WRONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
        if (direct_descriptor_ < 0)
            refuse_output(path, errno == ENXIO ? std::string("no process reads from it") : system_message(errno));
        ::fcntl(direct_descriptor_, F_SETFL, ::fcntl(direct_descriptor_, F_GETFL) & ~O_NONBLOCK);
        return;
    }
    // Create the temporary file beside the final one, so rename stays on one file system.
    for (int attempt = 0; attempt < 16; ++attempt) {
        temporary_ = std::make_unique<TemporaryFile>(temporary_name_for(target_.final_path));
        if (temporary_->open_error() != EEXIST) break;
    }
    if (temporary_->open_error() != 0) refuse_output(path, system_message(temporary_->open_error()));
}

AtomicFile::~AtomicFile() {
    if (direct_descriptor_ > 2) ::close(direct_descriptor_);
}

namespace {

/// Writes all of `size` bytes to `descriptor`, retrying short writes; errno, or 0.
int write_all(int descriptor, const char* bytes, std::size_t size) {
    std::size_t written = 0;
    while (written < size) {
        const ssize_t result = ::write(descriptor, bytes + written, size - written);
        if (result < 0) {
            if (errno == EINTR) continue;
            return errno;
        }
        written += static_cast<std::size_t>(result);
    }
    return 0;
}

} // namespace

void AtomicFile::write(const void* data, std::size_t size) {
    const char* bytes = static_cast<const char*>(data);
    if (direct_descriptor_ >= 0) {
        // Kept until commit(): the container may still seek back.
        if (direct_bytes_.size() < position_ + size) direct_bytes_.resize(position_ + size);
        std::copy(bytes, bytes + size, direct_bytes_.begin() + static_cast<std::ptrdiff_t>(position_));
        position_ += size;
        return;
    }
    if (const int error_number = write_all(temporary_->descriptor(), bytes, size); error_number != 0)
        throw error(display_name(path_) + ": cannot write: " + system_message(error_number));
    position_ += size;
}

void AtomicFile::seek(std::uint64_t position) {
    if (direct_descriptor_ < 0 && ::lseek(temporary_->descriptor(), static_cast<off_t>(position), SEEK_SET) < 0) {
        const int error_number = errno;
        throw error(display_name(path_) + ": cannot write: " + system_message(error_number));
    }
    position_ = position;
}

void AtomicFile::commit() {
    if (direct_descriptor_ >= 0) {
        // A device or pipe gets the bytes in one pass, nothing renamed over it.
        if (const int error_number = write_all(direct_descriptor_, direct_bytes_.data(), direct_bytes_.size());
            error_number != 0)
            throw error(display_name(path_) + ": cannot write: " + system_message(error_number));
        direct_bytes_.clear();
        direct_bytes_.shrink_to_fit();
        return;
    }
    // Flush to disk before the rename makes the file visible.
    if (::fsync(temporary_->descriptor()) != 0 && errno != EINVAL && errno != EROFS) {
        const int error_number = errno;
        throw error(display_name(path_) + ": cannot write: " + system_message(error_number));
    }
    if (const int close_error = temporary_->close(); close_error != 0)
        throw error(display_name(path_) + ": cannot write: " + system_message(close_error));

    // Publish under the final name in one step (a symlink's target: the link stays).
    if (::rename(temporary_->name().c_str(), target_.final_path.c_str()) != 0) {
        const int error_number = errno;
        throw error(display_name(path_) + ": cannot write: " + system_message(error_number));
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

namespace {

[[noreturn]] void refuse_input(const std::string& path, const std::string& problem) {
    throw input_error(display_name(path) + ": " + problem);
}

/// Standard input, read to its end once (bounded by MSMCL_MAX_BYTES), then kept: the
/// container is sniffed from its first bytes and then read whole.
const std::string& standard_input() {
    static std::once_flag once;
    static std::string content;
    static std::string problem;
    std::call_once(once, [] {
        const std::uint64_t limit = image_limits().max_bytes;
        char buffer[1 << 16];
        for (;;) {
            const ssize_t count = ::read(0, buffer, sizeof buffer);
            if (count < 0 && errno == EINTR) continue;
            if (count < 0) {
                problem = "cannot read standard input: " + system_message(errno);
                break;
            }
            if (count == 0) break;
            if (content.size() + static_cast<std::size_t>(count) > limit) {
                problem = "standard input exceeds the limit of " + std::to_string(limit) + " bytes (MSMCL_MAX_BYTES)";
                content.clear();
                break;
            }
            content.append(buffer, static_cast<std::size_t>(count));
        }
    });
    if (!problem.empty()) throw input_error("-: " + problem);
    return content;
}

/// Reads up to `size` bytes at the current position of `descriptor` into `out`; stops
/// early at the end of the file.
void read_up_to(int descriptor, std::string& out, std::uint64_t size, const std::string& path) {
    char buffer[1 << 16];
    while (size > 0) {
        const ssize_t count = ::read(descriptor, buffer, static_cast<std::size_t>(std::min<std::uint64_t>(size, sizeof buffer)));
        if (count < 0 && errno == EINTR) continue;
        if (count < 0) refuse_input(path, "cannot read: " + system_message(errno));
        if (count == 0) return;
        out.append(buffer, static_cast<std::size_t>(count));
        size -= static_cast<std::uint64_t>(count);
    }
}

/// A regular input opened for reading, never waiting on what it names; its size in `size`.
class InputDescriptor {
public:
    explicit InputDescriptor(const std::string& path) {
        struct stat status {};
        // Looked at before it is opened: opening a FIFO or a device may wait or act.
        if (::stat(path.c_str(), &status) != 0) refuse_input(path, "cannot open: " + system_message(errno));
        if (!S_ISREG(status.st_mode))
            refuse_input(path, "cannot read: is " + mode_kind(status.st_mode) +
                                   " (msmcl reads regular files, or standard input as -)");
        descriptor_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
        if (descriptor_ < 0) refuse_input(path, "cannot open: " + system_message(errno));
        // What was opened is what was looked at (not swapped since).
        if (::fstat(descriptor_, &status) != 0 || !S_ISREG(status.st_mode))
            refuse_input(path, "cannot read: not a regular file");
        size = static_cast<std::uint64_t>(status.st_size);
    }
    ~InputDescriptor() {
        if (descriptor_ >= 0) ::close(descriptor_);
    }
    InputDescriptor(const InputDescriptor&) = delete;
    InputDescriptor& operator=(const InputDescriptor&) = delete;
    int descriptor() const { return descriptor_; }
    std::uint64_t size = 0;

private:
    int descriptor_ = -1;
};

std::string limit_message(std::uint64_t bytes, const ReadRules& rules) {
    return "the file's " + std::to_string(bytes) + " bytes exceed the limit of " + std::to_string(rules.max_bytes) +
           " bytes" + (rules.limit_note.empty() ? std::string() : " (" + rules.limit_note + ")");
}

void check_magic(const std::string& path, const std::string& head, const ReadRules& rules) {
    if (head.compare(0, rules.magic.size(), rules.magic) != 0) refuse_input(path, "not " + rules.kind);
}

} // namespace

std::string read_input_file(const std::string& path, const ReadRules& rules) {
    if (path.empty()) throw input_error("empty input file name");
    if (path == "-") {
        const std::string& content = standard_input();
        if (content.size() > rules.max_bytes) refuse_input(path, limit_message(content.size(), rules));
        check_magic(path, content.substr(0, rules.magic.size()), rules);
        return content;
    }
    InputDescriptor input(path);
    if (input.size > rules.max_bytes) refuse_input(path, limit_message(input.size, rules));
    // The first bytes before the rest: a file of another kind is refused unread.
    std::string content;
    read_up_to(input.descriptor(), content, std::min<std::uint64_t>(rules.magic.size(), input.size), path);
    check_magic(path, content, rules);
    content.reserve(static_cast<std::size_t>(input.size));
    read_up_to(input.descriptor(), content, input.size - content.size(), path);
    return content;
}

std::string read_whole_file(const std::string& path, std::uint64_t max_bytes) {
    ReadRules rules;
    rules.max_bytes = max_bytes;
    if (max_bytes != UINT64_MAX) rules.limit_note = "MSMCL_MAX_BYTES";
    return read_input_file(path, rules);
}

std::string read_file_head(const std::string& path, std::size_t count) {
    if (path == "-") return standard_input().substr(0, count);
    InputDescriptor input(path);
    std::string head;
    read_up_to(input.descriptor(), head, std::min<std::uint64_t>(count, input.size), path);
    return head;
}

std::string special_file_kind(const std::string& path) {
    struct stat status {};
    if (::stat(path.c_str(), &status) != 0) return "";
    return mode_kind(status.st_mode);
}

std::string display_name(const std::string& name, std::size_t longest) {
    if (name.size() <= longest || longest < 8) return name;
    // The start names the folder, the end the file: keep both.
    const std::size_t tail = (longest - 3) / 3, head = longest - 3 - tail;
    return name.substr(0, head) + "..." + name.substr(name.size() - tail);
}

std::string shorten_long_names(const std::string& message, std::size_t longest) {
    std::string shortened;
    std::size_t start = 0;
    while (start < message.size()) {
        std::size_t end = message.find(' ', start);
        if (end == std::string::npos) end = message.size();
        shortened += display_name(message.substr(start, end - start), longest);
        if (end < message.size()) shortened += ' ';
        start = end + 1;
    }
    return shortened;
}

} // namespace msmcl::io
