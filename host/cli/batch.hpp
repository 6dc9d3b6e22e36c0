// The map commands of msmcl (filter, sat): one depth map in, one texture file out, for one
// file (`msmcl filter IN OUT`) or for a batch (`msmcl filter IN... -o DIR/`, `--list FILE`).
// The command says what it does to one map (a MapJob); this driver reads, runs and writes,
// for a batch with one Context per device and the EXR reads and writes on a thread pool
// overlapping the device work (docs/batch.md has the rules: output names, list and
// manifest formats, --shard, --device all, the summary and exit codes).
#pragma once

#include "cli/commands.hpp"
#include "cli/stages.hpp"

#include "io/exr_io.hpp"

#include <msmcl/context.hpp>

#include <CLI/CLI.hpp>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace msmcl::cli {

/// What a map command takes besides its own options.
struct BatchArguments {
    std::vector<std::string> paths; ///< IN OUT (one file), or the inputs of a batch with -o DIR
    std::string output_dir;         ///< -o DIR: outputs named after the inputs (a batch)
    std::string list;               ///< --list FILE: inputs one per line, or a JSON manifest (a batch)
    std::string shard;              ///< --shard I/N: this run takes every N-th file from the I-th
    std::string json;               ///< --json FILE or -: a machine-readable summary
    std::string array;              ///< --array FILE: every input a layer of one texture array in FILE
    bool is_batch() const { return !output_dir.empty() || !list.empty(); }
};

/// Adds the positionals and -o, --list, --shard, --json, --array to `command`.
void add_batch_options(CLI::App& command, BatchArguments& batch);

/// One file of a batch as listed: its input, its output (empty: named after the input in
/// -o DIR) and the options a manifest sets for it (option name without dashes -> value).
struct BatchEntry {
    std::string input;
    std::string output;
    std::map<std::string, std::string> options;
    bool array = false; ///< --array: the output is a texture array (also of one layer)
};

/// The result of a map's device work, waiting to be written.
struct MapResult {
    std::function<void()> write; ///< writes the file (atomically)
    std::size_t bytes = 0;       ///< host memory the result holds until written
};

/// One depth map to turn into one file, its option values checked.
struct MapJob {
    std::string input;
    std::string output;
    DepthRange depth_range = DepthRange::zero_one;
    int expected_samples = 0; ///< a manifest's "samples": the file must hold that many (0: any)
    /// The device work on `context`; returns the write of its result, which the driver runs
    /// later (on another thread in a batch). With `stages` (one file) the work is timed
    /// stage by stage for --verbose.
    std::function<MapResult(Context&, const io::TranslucentDepth&, Stages*)> run;
};

/// The job of `entry` whose device work is `compute(context, layered, on_stage)` (a library
/// call that reports its stages to `on_stage` for --verbose), timed as the stage `stage`
/// otherwise; `publish(result, samples)` writes its result (a Texture or SatTable: its words
/// are what it holds).
template <class Compute, class Publish>
MapJob map_job(const BatchEntry& entry, DepthRange range, const char* stage, Compute compute, Publish publish) {
    MapJob job;
    job.input = entry.input;
    job.output = entry.output;
    job.depth_range = range;
    job.run = [=](Context& context, const io::TranslucentDepth& layered, Stages* stages) -> MapResult {
        auto result = stages ? stages->run_call(stage, [&](const StageObserver& on_stage) {
            return compute(context, layered, on_stage);
        })
                             : compute(context, layered, StageObserver{});
        const std::size_t bytes = result.words.size() * sizeof(result.words[0]);
        return {[result = std::move(result), publish, samples = layered.depth.samples] { publish(result, samples); },
                bytes};
    };
    return job;
}

/// What differs between filter and sat.
struct MapCommand {
    std::string name;                       ///< "filter" or "sat"
    std::vector<std::string> manifest_keys; ///< options a manifest entry may set ("format", "depth-range", ...)
    std::string out_container;              ///< --out-container of the command line (names derived outputs)
    /// The job of one entry; throws usage_error for a bad option value or output name.
    std::function<MapJob(const BatchEntry&)> make_job;
};

/// Runs the single-file form, a batch or the array form (--array: all inputs as the layers
/// of one texture array, in one library call); returns the exit code (0, 2 if any input was bad,
/// else 1 if anything failed at run time). Usage errors and a failure of the single-file
/// form are thrown as from every other command.
int run_map_command(const GlobalArguments& global, const BatchArguments& batch, const MapCommand& command);

/// The value of option `key` for `entry`: the manifest's, else `fallback`.
std::string entry_option(const BatchEntry& entry, const std::string& key, const std::string& fallback);

} // namespace msmcl::cli
