// Writing a file so that it is either complete under its final name or absent.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace msmcl::io {

/// Writes `size` bytes to a temporary file in the directory of `path`, flushes it to
/// disk, then renames it to `path`. On any failure the temporary file is removed and
/// nothing appears under `path` (an existing file there is left untouched).
/// Throws input_error when `path` cannot be created (missing directory, no permission)
/// and msmcl::error when writing fails midway (disk full, I/O error).
void write_file_atomically(const std::string& path, const void* data, std::size_t size);

class TemporaryFile;

/// A file written in pieces (and seeks) under a temporary name in the directory of
/// `path`, published by commit() as write_file_atomically publishes it; destroyed
/// without commit(), it leaves nothing behind. The same errors as write_file_atomically.
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
    std::unique_ptr<TemporaryFile> temporary_;
    std::uint64_t position_ = 0;
};

/// Makes SIGINT, SIGTERM and SIGHUP remove the temporary files of writes in progress
/// before the process ends by the signal as it would have (the handler unlinks, restores
/// the default action and raises the signal again). For programs (the CLI); a library
/// leaves signal dispositions to its host. A disposition set to ignore stays ignored.
void remove_temporary_files_on_signals();

/// The whole content of a file. Throws input_error naming the file when it cannot be read,
/// or when it is larger than `max_bytes` (checked before reading).
std::string read_whole_file(const std::string& path, std::uint64_t max_bytes = UINT64_MAX);

} // namespace msmcl::io
