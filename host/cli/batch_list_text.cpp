#include "cli/batch_list_text.hpp"

#include "io/atomic_file.hpp"

#include <msmcl/errors.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>

namespace msmcl::cli {
namespace {

using nlohmann::json;

/// Refuses a path of a list with a NUL in it, which no file name holds: cut there, it would
/// name another file.
void refuse_nul(const std::string& path, const std::string& where) {
    if (path.find('\0') != std::string::npos) throw input_error(where + " holds a NUL character, which no file name may");
}

/// A manifest value as option text: strings as written, numbers as JSON writes them
/// (the shortest text that reads back to the same number).
std::string option_text(const json& value, const std::string& where) {
    if (value.is_string()) return value.get<std::string>();
    if (value.is_number()) return value.dump();
    throw input_error(where + " must be a string or a number");
}

/// A JSON manifest: an array of entries, each an input path or an object with "input",
/// optionally "output" and the command's options.
std::vector<BatchEntry> parse_manifest(const std::string& name, const std::string& text,
                                       const std::vector<std::string>& manifest_keys, const std::string& command_name) {
    json manifest;
    try {
        manifest = json::parse(text);
    } catch (const json::exception& e) { // parse_error, or out_of_range for a number past double
        throw input_error(name + ": not a valid JSON manifest: " + e.what());
    }
    if (!manifest.is_array()) throw input_error(name + ": a manifest is a JSON array of entries");
    std::vector<BatchEntry> entries;
    for (std::size_t i = 0; i < manifest.size(); ++i) {
        const json& item = manifest[i];
        const std::string where = name + ": entry " + std::to_string(i);
        BatchEntry entry;
        if (item.is_string()) {
            entry.input = item.get<std::string>();
        } else if (item.is_object()) {
            for (auto it = item.begin(); it != item.end(); ++it) {
                const std::string& key = it.key();
                if (key == "input") entry.input = option_text(it.value(), where + " \"input\"");
                else if (key == "output") entry.output = option_text(it.value(), where + " \"output\"");
                else if (key == "samples") entry.options[key] = option_text(it.value(), where + " \"samples\"");
                else if (std::find(manifest_keys.begin(), manifest_keys.end(), key) != manifest_keys.end())
                    entry.options[key] = option_text(it.value(), where + " \"" + key + "\"");
                else {
                    std::string known = "input, output, samples";
                    for (const std::string& option : manifest_keys) known += ", " + option;
                    throw input_error(where + ": unknown key \"" + io::display_name(key) + "\" for msmcl " +
                                      command_name + " (keys: " + known + ")");
                }
            }
        } else {
            throw input_error(where + ": an entry is an input path or an object with \"input\"");
        }
        if (entry.input.empty()) throw input_error(where + ": no \"input\"");
        refuse_nul(entry.input, where + " \"input\"");
        refuse_nul(entry.output, where + " \"output\"");
        entries.push_back(std::move(entry));
    }
    return entries;
}

} // namespace

std::vector<BatchEntry> parse_batch_list(const std::string& path, const std::string& text,
                                         const std::vector<std::string>& manifest_keys,
                                         const std::string& command_name) {
    const std::string name = io::display_name(path);
    const std::size_t first = text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && text[first] == '[') return parse_manifest(name, text, manifest_keys, command_name);
    std::vector<BatchEntry> entries;
    for (std::size_t start = 0, line_number = 1; start < text.size(); ++line_number) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        std::string line = text.substr(start, end - start);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        refuse_nul(line, name + ": line " + std::to_string(line_number));
        if (!line.empty() && line[0] != '#') entries.push_back(BatchEntry{line, "", {}});
        start = end + 1;
    }
    return entries;
}

} // namespace msmcl::cli
