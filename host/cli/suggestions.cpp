#include "cli/suggestions.hpp"

#include <algorithm>
#include <cctype>

namespace msmcl::cli {
namespace {

/// Long and short names of an app's options ("--format", "-h") and whether each takes a value.
struct OptionNames {
    std::vector<std::string> names;
    std::vector<std::string> with_value;
};

OptionNames option_names(const CLI::App& app) {
    OptionNames result;
    for (const CLI::Option* option : app.get_options()) {
        std::vector<std::string> names;
        for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
        for (const std::string& name : option->get_snames()) names.push_back("-" + name);
        for (const std::string& name : names) {
            result.names.push_back(name);
            if (option->get_type_size_max() > 0) result.with_value.push_back(name);
        }
    }
    return result;
}

bool contains(const std::vector<std::string>& list, const std::string& word) {
    return std::find(list.begin(), list.end(), word) != list.end();
}

/// An option-looking word: "--x..." or "-x" with a letter (not a negative number).
bool looks_like_option(const std::string& word) {
    if (word.size() < 2 || word[0] != '-') return false;
    if (word[1] == '-') return word.size() > 2;
    return std::isalpha(static_cast<unsigned char>(word[1])) != 0;
}

std::string with_suggestion(std::string message, const std::optional<std::string>& suggestion) {
    if (suggestion) message += " (did you mean '" + *suggestion + "'?)";
    return message;
}

} // namespace

std::size_t edit_distance(const std::string& a, const std::string& b) {
    // One row of the dynamic programme at a time.
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

std::optional<std::string> nearest_name(const std::string& word, const std::vector<std::string>& names) {
    std::optional<std::string> best;
    std::size_t best_distance = 0;
    for (const std::string& name : names) {
        const std::size_t distance = edit_distance(word, name);
        if (!best || distance < best_distance) best = name, best_distance = distance;
    }
    // A typo: at most a third of the word wrong (at least 2 edits allowed, so swaps count).
    const std::size_t allowed = std::max<std::size_t>(2, word.size() / 3);
    if (!best || best_distance > allowed) return std::nullopt;
    return best;
}

std::optional<std::string> unknown_word_message(CLI::App& app, const std::vector<std::string>& arguments) {
    const OptionNames global = option_names(app);
    std::vector<std::string> commands;
    for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; }))
        commands.push_back(command->get_name());

    // Walk the words: global options (and their values) up to the subcommand, then the
    // subcommand's words; "--" ends the options.
    CLI::App* command = nullptr;
    OptionNames local;
    for (std::size_t i = 0; i < arguments.size(); ++i) {
        const std::string& word = arguments[i];
        if (word == "--") break;
        if (looks_like_option(word)) {
            const std::string name = word.substr(0, word.find('='));
            const bool known_global = contains(global.names, name);
            const bool known_local = command && contains(local.names, name);
            if (!known_global && !known_local) {
                std::vector<std::string> candidates = global.names;
                candidates.insert(candidates.end(), local.names.begin(), local.names.end());
                const std::string where = command ? "msmcl " + command->get_name() : std::string("msmcl");
                return with_suggestion("unknown option '" + name + "' for " + where, nearest_name(name, candidates));
            }
            // Skip the value of an option that takes one, unless it came with '='.
            const bool takes_value = contains(global.with_value, name) || (command && contains(local.with_value, name));
            if (takes_value && word.find('=') == std::string::npos) ++i;
            continue;
        }
        if (!command) {
            // The first plain word is the subcommand.
            if (!contains(commands, word)) {
                const std::optional<std::string> suggestion = nearest_name(word, commands);
                if (suggestion) return with_suggestion("unknown command '" + word + "'", suggestion);
                std::string list;
                for (const std::string& name : commands) list += (list.empty() ? "" : ", ") + name;
                return "unknown command '" + word + "' (commands: " + list + ")";
            }
            command = app.get_subcommand(word);
            local = option_names(*command);
        }
    }
    return std::nullopt;
}

} // namespace msmcl::cli
