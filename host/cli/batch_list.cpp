#include "cli/batch_list.hpp"

#include "cli/option_values.hpp"

#include "io/atomic_file.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

namespace msmcl::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// Largest list or manifest read (a line per file: millions of files).
constexpr std::uint64_t max_list_bytes = 256ull << 20;

/// A manifest value as option text: strings as written, numbers as JSON writes them
/// (the shortest text that reads back to the same number).
std::string option_text(const json& value, const std::string& where) {
    if (value.is_string()) return value.get<std::string>();
    if (value.is_number()) return value.dump();
    throw input_error(where + " must be a string or a number");
}

/// A JSON manifest: an array of entries, each an input path or an object with "input",
/// optionally "output" and the command's options.
std::vector<BatchEntry> parse_manifest(const std::string& path, const std::string& text, const MapCommand& command) {
    json manifest;
    try {
        manifest = json::parse(text);
    } catch (const json::parse_error& e) {
        throw input_error(path + ": not a valid JSON manifest: " + e.what());
    }
    if (!manifest.is_array()) throw input_error(path + ": a manifest is a JSON array of entries");
    std::vector<BatchEntry> entries;
    for (std::size_t i = 0; i < manifest.size(); ++i) {
        const json& item = manifest[i];
        const std::string where = path + ": entry " + std::to_string(i);
        BatchEntry entry;
        if (item.is_string()) {
            entry.input = item.get<std::string>();
        } else if (item.is_object()) {
            for (auto it = item.begin(); it != item.end(); ++it) {
                const std::string& key = it.key();
                if (key == "input") entry.input = option_text(it.value(), where + " \"input\"");
                else if (key == "output") entry.output = option_text(it.value(), where + " \"output\"");
                else if (key == "samples") entry.options[key] = option_text(it.value(), where + " \"samples\"");
                else if (std::find(command.manifest_keys.begin(), command.manifest_keys.end(), key) !=
                         command.manifest_keys.end())
                    entry.options[key] = option_text(it.value(), where + " \"" + key + "\"");
                else {
                    std::string known = "input, output, samples";
                    for (const std::string& name : command.manifest_keys) known += ", " + name;
                    throw input_error(where + ": unknown key \"" + key + "\" for msmcl " + command.name + " (keys: " +
                                      known + ")");
                }
            }
        } else {
            throw input_error(where + ": an entry is an input path or an object with \"input\"");
        }
        if (entry.input.empty()) throw input_error(where + ": no \"input\"");
        entries.push_back(std::move(entry));
    }
    return entries;
}

/// --list FILE: a JSON manifest when its first non-blank character is '[', else one input
/// per line (blank lines and lines starting with '#' skipped).
std::vector<BatchEntry> read_list(const std::string& path, const MapCommand& command) {
    const std::string text = io::read_whole_file(path, max_list_bytes);
    const std::size_t first = text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && text[first] == '[') return parse_manifest(path, text, command);
    std::vector<BatchEntry> entries;
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        std::string line = text.substr(start, end - start);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (!line.empty() && line[0] != '#') entries.push_back(BatchEntry{line, "", {}});
        start = end + 1;
    }
    return entries;
}

/// DIR/<the input's file name, its extension replaced by the output container's>.
std::string derived_output(const std::string& directory, const BatchEntry& entry, const MapCommand& command) {
    const std::string container = entry_option(entry, "out-container", command.out_container);
    const std::string stem = fs::path(entry.input).stem().string();
    if (stem.empty() || stem == "." || stem == "..")
        throw usage_error(entry.input + ": cannot name an output after this input (give it an \"output\" in a manifest)");
    return (fs::path(directory) / (stem + "." + (container.empty() ? std::string("exr") : container))).string();
}

/// A path as a key for comparing files: absolute and without "." and "..".
std::string path_key(const std::string& path) { return fs::absolute(path).lexically_normal().string(); }

/// Refuses a batch where two files would write one output, or an output would replace an input.
void check_outputs(const std::vector<MapJob>& jobs) {
    std::map<std::string, const MapJob*> writer_of, inputs;
    for (const MapJob& job : jobs) inputs.emplace(path_key(job.input), &job);
    for (const MapJob& job : jobs) {
        const std::string key = path_key(job.output);
        const auto [where, fresh] = writer_of.emplace(key, &job);
        if (!fresh)
            throw usage_error(job.output + ": written for both " + where->second->input + " and " + job.input +
                              " (give one of them an \"output\" in a manifest)");
        if (inputs.count(key)) throw usage_error(job.output + ": an output would replace the input of the batch");
    }
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
    check_outputs(jobs);
    return jobs;
}

std::vector<MapJob> shard_jobs(std::vector<MapJob> jobs, Shard shard) {
    std::vector<MapJob> mine;
    for (std::size_t p = shard.index; p < jobs.size(); p += shard.count) mine.push_back(std::move(jobs[p]));
    return mine;
}

void create_output_folders(const std::string& output_dir, const std::vector<MapJob>& jobs) {
    std::set<fs::path> folders;
    if (!output_dir.empty()) folders.insert(output_dir);
    for (const MapJob& job : jobs) folders.insert(fs::path(job.output).parent_path());
    for (const fs::path& folder : folders) {
        if (folder.empty()) continue;
        std::error_code error;
        fs::create_directories(folder, error);
        if (!fs::is_directory(folder))
            throw input_error(folder.string() + ": cannot create the output folder" +
                              (error ? ": " + error.message() : std::string()));
    }
}

} // namespace msmcl::cli
