// Writing a file so that it is either complete under its final name or absent.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace msmcl::io {

/// Writes `size` bytes to a temporary file in the directory of `path`, flushes it to
/// disk, then renames it to `path`. On any failure the temporary file is removed and
/// nothing appears under `path` (an existing file there is left untouched).
/// Throws input_error when `path` cannot be created (missing directory, no permission)
/// and msmcl::error when writing fails midway (disk full, I/O error).
void write_file_atomically(const std::string& path, const void* data, std::size_t size);

/// Makes SIGINT, SIGTERM and SIGHUP remove the temporary files of writes in progress
/// before the process ends by the signal as it would have (the handler unlinks, restores
/// the default action and raises the signal again). For programs (the CLI); a library
/// leaves signal dispositions to its host. A disposition set to ignore stays ignored.
void remove_temporary_files_on_signals();

/// The whole content of a file. Throws input_error naming the file when it cannot be read,
/// or when it is larger than `max_bytes` (checked before reading).
std::string read_whole_file(const std::string& path, std::uint64_t max_bytes = UINT64_MAX);

} // namespace msmcl::io
