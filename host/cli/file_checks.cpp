#include "cli/file_checks.hpp"

#include "cli/commands.hpp"

#include "io/atomic_file.hpp"

#include <msmcl/errors.hpp>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <sys/stat.h>
#include <unistd.h>

namespace msmcl::cli {
namespace {

namespace fs = std::filesystem;

const char* role_name(NamedFile::Role role) {
    switch (role) {
    case NamedFile::Role::input: return "the input";
    case NamedFile::Role::output: return "the output";
    case NamedFile::Role::summary: return "the --json summary";
    case NamedFile::Role::list: return "the --list file";
    }
    return "the file";
}

std::string device_and_inode(const struct stat& status) {
    return "inode " + std::to_string(status.st_dev) + ":" + std::to_string(status.st_ino);
}

/// What `file` is, as a key equal for every spelling of one file.
std::string identity(const NamedFile& file) {
    struct stat status {};
    // `-`: the stream itself (what the shell connected it to).
    if (file.path == "-") {
        const int descriptor = file.role == NamedFile::Role::input || file.role == NamedFile::Role::list ? 0 : 1;
        // Two writes to standard output would mix their bytes, whatever it is.
        if (::fstat(descriptor, &status) == 0 && !S_ISCHR(status.st_mode)) return device_and_inode(status);
        return descriptor == 0 ? "" : "standard output";
    }
    if (::stat(file.path.c_str(), &status) == 0) {
        // A terminal or /dev/null may be read and written by many: never replaced.
        if (S_ISCHR(status.st_mode)) return "";
        return device_and_inode(status);
    }
    // A new name: where a symlink to it points, in its folder resolved (symlinked folders,
    // "..") as far as that exists.
    std::string final_path = file.path;
    if (file.role != NamedFile::Role::input) {
        try {
            final_path = io::resolve_output(file.path).final_path;
        } catch (const input_error&) {
            // Refused when written; compared as spelled meanwhile.
        }
    }
    std::error_code error;
    const fs::path resolved = fs::weakly_canonical(fs::absolute(final_path, error), error);
    return "path " + (error ? fs::absolute(final_path).lexically_normal().string() : resolved.string());
}

} // namespace

void check_distinct_files(const std::vector<NamedFile>& files) {
    const auto writes = [](const NamedFile& file) {
        return file.role == NamedFile::Role::output || file.role == NamedFile::Role::summary;
    };
    // "an output would replace the input a.exr", naming both as given.
    const auto clash = [&](const NamedFile& file, const NamedFile& other) -> std::string {
        const std::string name = io::display_name(file.path), other_name = io::display_name(other.path);
        if (writes(file) && writes(other) && !file.written_for.empty() && !other.written_for.empty())
            return name + ": written for both " + io::display_name(other.written_for) + " and " +
                   io::display_name(file.written_for) +
                   (file.path == other.path ? std::string() : " (the same file as " + other_name + ")") +
                   " (give one of them an \"output\" in a manifest)";
        const std::string role = file.role == NamedFile::Role::output ? "an output" : role_name(file.role);
        if (writes(file) != writes(other)) {
            const NamedFile& writer = writes(file) ? file : other;
            const NamedFile& reader = writes(file) ? other : file;
            const std::string writer_role = writer.role == NamedFile::Role::output ? "an output" : role_name(writer.role);
            return io::display_name(writer.path) + ": " + writer_role + " would replace " + role_name(reader.role) + " " +
                   io::display_name(reader.path);
        }
        return name + ": " + role + " is the same file as " + role_name(other.role) + " " + other_name;
    };
    std::map<std::string, const NamedFile*> seen;
    // The writes first, outputs before the summary: a later file is compared with all of them.
    for (int pass = 0; pass < 3; ++pass)
        for (const NamedFile& file : files) {
            const int file_pass = file.role == NamedFile::Role::output ? 0 : writes(file) ? 1 : 2;
            if (file_pass != pass) continue;
            const std::string key = identity(file);
            if (key.empty()) continue;
            const auto [where, fresh] = seen.emplace(key, &file);
            if (fresh) continue;
            const NamedFile& other = *where->second;
            if (other.role == NamedFile::Role::input && file.role == NamedFile::Role::input) continue;
            throw usage_error(clash(file, other) + "; nothing was written");
        }
}

void check_output_path(const std::string& path, bool creatable) {
    if (!creatable) {
        io::check_output_writable(path);
        return;
    }
    // What the name is now (a directory, a symlink loop: refused), then its folder.
    const io::OutputTarget target = io::resolve_output(path);
    if (target.kind == io::OutputKind::direct) {
        io::check_output_writable(path);
        return;
    }
    fs::path folder = fs::path(target.final_path).parent_path();
    if (folder.empty()) folder = ".";
    // The nearest folder that exists must be a writable folder: the rest is created in it.
    fs::path existing = folder;
    struct stat status {};
    while (::stat(existing.c_str(), &status) != 0 && errno == ENOENT && existing.has_relative_path() &&
           existing.has_parent_path() && existing.parent_path() != existing)
        existing = existing.parent_path();
    if (::stat(existing.c_str(), &status) != 0) existing = ".";
    const auto refuse = [&](const std::string& problem) {
        throw input_error(io::display_name(path) + ": cannot write: " + problem);
    };
    if (::stat(existing.c_str(), &status) != 0) refuse(std::strerror(errno));
    if (!S_ISDIR(status.st_mode))
        refuse(io::display_name(existing.string()) + " is not a folder: cannot create the output folder " +
               io::display_name(folder.string()));
    if (::access(existing.c_str(), W_OK | X_OK) != 0) refuse(std::strerror(errno));
}

} // namespace msmcl::cli
