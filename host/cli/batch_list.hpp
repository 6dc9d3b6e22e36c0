// Which files a batch of `msmcl filter` or `msmcl sat` runs (docs/batch.md): the positional
// inputs, then those of --list (one per line, or a JSON manifest with per-file options),
// each made a checked job with its output named (-o DIR/<input name>.<container>, or the
// manifest's); --shard keeps every N-th of them. Every mistake is found here, before any
// file is read or written.
#pragma once

#include "cli/batch.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace msmcl::cli {

/// --shard I/N: this run's index and the number of shards.
struct Shard {
    std::size_t index = 0;
    std::size_t count = 1;
    std::string text() const; ///< "I/N"
};

/// "I/N" with 0 <= I < N; usage_error otherwise.
Shard parse_shard(const std::string& text);

/// Every file of the batch, in list order, as a job of `command`: options checked, output
/// named. Throws usage_error (bad option values, no output, two files writing one output,
/// an output, the --json summary or the list being an input or another of them) or
/// input_error (an unreadable list, a bad manifest, a NUL in a path).
std::vector<MapJob> batch_jobs(const BatchArguments& batch, const MapCommand& command);

/// The jobs at positions p with p % N == I, in list order.
std::vector<MapJob> shard_jobs(std::vector<MapJob> jobs, Shard shard);

/// Refuses (input_error naming the output) an output or --json file of `jobs` that could not
/// be written: a directory or block device, a symlink loop, a folder that cannot be created
/// or written. Creates nothing.
void check_output_folders(const BatchArguments& batch, const std::vector<MapJob>& jobs);

/// Creates -o DIR (when given), the folder of every output and of the --json file;
/// input_error naming the folder that cannot be made.
void create_output_folders(const BatchArguments& batch, const std::vector<MapJob>& jobs);

} // namespace msmcl::cli
