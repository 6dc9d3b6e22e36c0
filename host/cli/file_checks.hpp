// Checks on every file a call names, made before any map is read (docs/files.md): no output,
// --json summary or list may be the same file as another, or as an input, however it is
// spelled (hard links, symlinked folders, `..`); and every output can be written.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace msmcl::cli {

/// One file a call names, and what it is to the call.
struct NamedFile {
    enum class Role { input, output, summary, list };
    NamedFile(std::string path_, Role role_, std::string written_for_ = {})
        : path(std::move(path_)), role(role_), written_for(std::move(written_for_)) {}
    std::string path;
    Role role = Role::input;
    std::string written_for; ///< an output of a batch: its input
};

/// Refuses (usage_error, one line naming both paths) two files of `files` that are one
/// file, unless both are inputs. Compares by identity: device and inode of an existing
/// file (symlinks followed; `-` is standard input for an input, standard output else), the
/// resolved folder and name of a new one.
void check_distinct_files(const std::vector<NamedFile>& files);

/// Refuses (input_error naming the output) an output that could not be written: one that
/// may never be (a directory, a block device, a symlink loop), or whose folder is missing
/// or not writable. `creatable`: the folder may be missing when the nearest folder above it
/// that exists is writable (a batch creates it). Creates nothing.
void check_output_path(const std::string& path, bool creatable);

} // namespace msmcl::cli
