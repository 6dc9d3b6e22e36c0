#include "cli/batch_list.hpp"
#include "cli/batch_list_text.hpp"

#include "cli/file_checks.hpp"
#include "cli/option_values.hpp"

#include "io/atomic_file.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

namespace msmcl::cli {
namespace {

namespace fs = std::filesystem;

/// Largest list or manifest read (a line per file: millions of files), fixed.
constexpr std::uint64_t max_list_bytes = 256ull << 20;

/// --list FILE (`-`: standard input), parsed by parse_batch_list.
std::vector<BatchEntry> read_list(const std::string& path, const MapCommand& command) {
    // The limit is fixed: longer lists are split (or sharded).
    const std::string text =
        io::read_input_file(path, {max_list_bytes, "fixed for lists: split a longer one", "", ""});
    return parse_batch_list(path, text, command.manifest_keys, command.name);
}

/// DIR/<the input's file name, its extension replaced by the output container's>.
std::string derived_output(const std::string& directory, const BatchEntry& entry, const MapCommand& command) {
    const std::string container = entry_option(entry, "out-container", command.out_container);
    const std::string stem = fs::path(entry.input).stem().string();
    if (stem.empty() || stem == "." || stem == "..")
        throw usage_error(entry.input + ": cannot name an output after this input (give it an \"output\" in a manifest)");
    return (fs::path(directory) / (stem + "." + (container.empty() ? std::string("exr") : container))).string();
}

/// Refuses a batch where two files would write one output, or where an output, the
/// summary or the list is one of the inputs or another of them (by identity, not spelling).
void check_outputs(const BatchArguments& batch, const std::vector<MapJob>& jobs) {
    std::vector<NamedFile> files;
    for (const MapJob& job : jobs) files.push_back({job.input, NamedFile::Role::input});
    for (const MapJob& job : jobs) files.push_back({job.output, NamedFile::Role::output, job.input});
    if (!batch.json.empty()) files.push_back({batch.json, NamedFile::Role::summary});
    if (!batch.list.empty()) files.push_back({batch.list, NamedFile::Role::list});
    check_distinct_files(files);
}

/// The files of a batch in list order: the positional inputs, then the list's entries.
std::vector<BatchEntry> batch_entries(const BatchArguments& batch, const MapCommand& command) {
    std::vector<BatchEntry> entries;
    for (const std::string& input : batch.paths) entries.push_back(BatchEntry{input, "", {}});
    if (!batch.list.empty()) {
        std::vector<BatchEntry> listed = read_list(batch.list, command);
        entries.insert(entries.end(), std::make_move_iterator(listed.begin()), std::make_move_iterator(listed.end()));
    }
    return entries;
}

} // namespace

Shard parse_shard(const std::string& text) {
    const std::size_t slash = text.find('/');
    const auto bad = [&] { return usage_error("--shard must be I/N with 0 <= I < N, got '" + text + "'"); };
    if (slash == std::string::npos) throw bad();
    const auto whole = [&](const std::string& part) {
        if (part.empty() || part.size() > 9 || part.find_first_not_of("0123456789") != std::string::npos) throw bad();
        return static_cast<std::size_t>(std::stoul(part));
    };
    Shard shard{whole(text.substr(0, slash)), whole(text.substr(slash + 1))};
    if (shard.count == 0 || shard.index >= shard.count) throw bad();
    return shard;
}

std::string Shard::text() const { return std::to_string(index) + "/" + std::to_string(count); }

std::vector<MapJob> batch_jobs(const BatchArguments& batch, const MapCommand& command) {
    std::vector<BatchEntry> entries = batch_entries(batch, command);
    std::vector<MapJob> jobs;
    for (BatchEntry& entry : entries) {
        if (entry.output.empty()) {
            if (batch.output_dir.empty())
                throw usage_error(entry.input + ": no output: give -o DIR (or an \"output\" in a manifest)");
            entry.output = derived_output(batch.output_dir, entry, command);
        }
        try {
            jobs.push_back(command.make_job(entry));
            // "samples": what the file must hold (the count itself is the file's).
            const std::string samples = entry_option(entry, "samples", "");
            if (!samples.empty()) {
                jobs.back().expected_samples = static_cast<int>(parse_integer("\"samples\"", samples, 1, 16));
                if (!is_supported_sample_count(jobs.back().expected_samples))
                    throw usage_error("\"samples\" must be 1, 2, 4, 8 or 16, got '" + samples + "'");
            }
        } catch (const usage_error& e) {
            // A manifest sets options per file: say which file's are wrong.
            throw usage_error(entry.options.empty() ? e.what() : entry.input + ": " + e.what());
        }
    }
    check_outputs(batch, jobs);
    return jobs;
}

std::vector<MapJob> shard_jobs(std::vector<MapJob> jobs, Shard shard) {
    std::vector<MapJob> mine;
    for (std::size_t p = shard.index; p < jobs.size(); p += shard.count) mine.push_back(std::move(jobs[p]));
    return mine;
}

void check_output_folders(const BatchArguments& batch, const std::vector<MapJob>& jobs) {
    for (const MapJob& job : jobs) check_output_path(job.output, true);
    if (!batch.json.empty() && batch.json != "-") check_output_path(batch.json, true);
}

void create_output_folders(const BatchArguments& batch, const std::vector<MapJob>& jobs) {
    std::set<fs::path> folders;
    if (!batch.output_dir.empty()) folders.insert(batch.output_dir);
    for (const MapJob& job : jobs) folders.insert(fs::path(job.output).parent_path());
    if (!batch.json.empty() && batch.json != "-") folders.insert(fs::path(batch.json).parent_path());
    for (const fs::path& folder : folders) {
        if (folder.empty()) continue;
        std::error_code error;
        fs::create_directories(folder, error);
        if (!fs::is_directory(folder))
            throw input_error(io::display_name(folder.string()) + ": cannot create the output folder" +
                              (error ? ": " + error.message() : std::string()));
    }
}

} // namespace msmcl::cli
