// Writing a file so that it is either complete under its final name or absent, and reading
// one without hanging or reading more than it holds (docs/files.md has the rules: what an
// output path may name, what an input may be, standard input and output as `-`).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace msmcl::io {

/// How an output path is written, decided from what it names once symlinks are followed.
enum class OutputKind {
    replace, ///< a regular file or a new name: a temporary file beside it, renamed over it
    direct,  ///< standard output (`-`), a character device, FIFO or socket: written in place
};

/// What writing `path` would do.
struct OutputTarget {
    OutputKind kind = OutputKind::replace;
    /// replace: the name that is replaced (a symlink's final target); direct: what is opened.
    std::string final_path;
};

/// Where the bytes for `path` go: `-` is standard output; a symlink is followed to its final
/// target, which is replaced (the link stays). Throws input_error naming `path` for what is
/// never written (a directory, a block device, a symlink loop, a path that cannot resolve).
OutputTarget resolve_output(const std::string& path);

/// Refuses (input_error "<path>: cannot write: ...") an output that could not be written
/// now: the folder of a replaced file missing, not a folder or not writable; a direct one
/// not writable. Creates nothing.
void check_output_writable(const std::string& path);

/// Writes `size` bytes to a temporary file in the directory of `path` (of its final target
/// when it is a symlink), flushes it to disk, then renames it over that name. On any
/// failure the temporary file is removed and nothing appears under `path` (an existing
/// file there is left untouched). Standard output, devices, FIFOs and sockets are written
/// directly, never renamed over (resolve_output).
/// Throws input_error when `path` cannot be created (missing directory, no permission)
/// and msmcl::error when writing fails midway (disk full, I/O error).
void write_file_atomically(const std::string& path, const void* data, std::size_t size);

class TemporaryFile;

/// A file written in pieces (and seeks) under a temporary name in the directory of
/// `path`, published by commit() as write_file_atomically publishes it; destroyed
/// without commit(), it leaves nothing behind. A direct output (resolve_output) is opened at
/// once and its bytes kept in memory until commit(), so that containers that seek work on
/// pipes too. The same errors as write_file_atomically.
class AtomicFile {
public:
    explicit AtomicFile(const std::string& path);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    void write(const void* data, std::size_t size);
    void seek(std::uint64_t position);
    std::uint64_t position() const { return position_; }
    /// Flushes the bytes to disk and renames the file to `path`.
    void commit();

private:
    std::string path_;
    OutputTarget target_;
    std::unique_ptr<TemporaryFile> temporary_;
    int direct_descriptor_ = -1; ///< a direct output: its descriptor (1 for `-`)
    std::string direct_bytes_;   ///< a direct output: everything written so far
    std::uint64_t position_ = 0;
};

/// Makes SIGINT, SIGTERM and SIGHUP remove the temporary files of writes in progress
/// before the process ends by the signal as it would have (the handler unlinks, restores
/// the default action and raises the signal again). For programs (the CLI); a library
/// leaves signal dispositions to its host. A disposition set to ignore stays ignored.
void remove_temporary_files_on_signals();

/// How an input file is read.
struct ReadRules {
    std::uint64_t max_bytes = UINT64_MAX; ///< a larger file is refused before it is read
    std::string limit_note;               ///< how that limit is set, for the message ("MSMCL_MAX_BYTES")
    std::string magic;                    ///< the first bytes it must hold, checked before the rest is read
    std::string kind;                     ///< what those bytes identify ("an OpenEXR file")
};

/// The whole content of an input: a regular file (symlinks followed) or standard input as
/// `-` (read once, then kept: every read of `-` gets the same bytes). Anything else (a
/// FIFO, device, socket, directory) is refused at once, without waiting on it. Reads at
/// most the size the file had when opened. Throws input_error naming the file.
std::string read_input_file(const std::string& path, const ReadRules& rules);

/// read_input_file with a limit of `max_bytes` set by MSMCL_MAX_BYTES (or none).
std::string read_whole_file(const std::string& path, std::uint64_t max_bytes = UINT64_MAX);

/// The first `count` bytes of an input (fewer when it is shorter), as read_input_file
/// would read them.
std::string read_file_head(const std::string& path, std::size_t count);

/// "<kind>" of what `path` names when it is not a regular file ("a FIFO", "a directory",
/// ...), "" for a regular file or a missing one; symlinks followed.
std::string special_file_kind(const std::string& path);

/// `name` cut to at most `longest` characters for a message: its start and end with an
/// ellipsis between.
std::string display_name(const std::string& name, std::size_t longest = 160);

/// `message` with every run of characters without a space longer than `longest` (a path,
/// mostly) cut as display_name cuts it.
std::string shorten_long_names(const std::string& message, std::size_t longest = 160);

} // namespace msmcl::io
