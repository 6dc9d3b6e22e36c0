#include "cli/batch.hpp"
#include "cli/batch_list.hpp"
#include "cli/file_checks.hpp"
#include "cli/progress.hpp"
#include "cli/texture_files.hpp"

#include "io/atomic_file.hpp"
#include "runtime/enum_names.hpp"

#include <msmcl/errors.hpp>

#include <boost/asio/post.hpp>
#include <boost/asio/thread_pool.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <deque>
#include <cstdio>
#include <filesystem>
#include <future>
#include <iostream>
#include <memory>
#include <mutex>
#include <new>
#include <thread>

namespace msmcl::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

/// Results of one device waiting to be written, in bytes (one larger result still goes).
constexpr std::size_t pending_write_bytes = 64u << 20;

double milliseconds_between(Clock::time_point start, Clock::time_point end) {
    return std::chrono::duration<double, std::milli>(end - start).count();
}

/// Every device for --device all, else the one the selection picks.
std::vector<DeviceSelection> device_selections(const GlobalArguments& global) {
    if (global.device != "all") return {global.selection()};
    std::vector<DeviceSelection> selections;
    for (const DeviceInfo& device : list_devices()) {
        DeviceSelection selection;
        selection.use_environment = false;
        selection.strict = true;
        selection.filter = DeviceFilter::platform_index(device.platform_index) &&
                           DeviceFilter::device_index(device.device_index);
        selections.push_back(std::move(selection));
    }
    if (selections.empty()) throw device_error("no OpenCL device found (is an ICD such as pocl-opencl-icd installed?)");
    return selections;
}

/// Runs `work` on the pool; its result (or exception) comes back through the future.
template <class Work>
auto post_task(boost::asio::thread_pool& pool, Work work) -> std::future<decltype(work())> {
    auto task = std::make_shared<std::packaged_task<decltype(work())()>>(std::move(work));
    std::future<decltype(work())> result = task->get_future();
    boost::asio::post(pool, [task] { (*task)(); });
    return result;
}

enum class Outcome { pending, written, bad_input, failed };

/// The outcomes' names in the JSON summary ("status" of a file).
constexpr detail::EnumNames<Outcome> outcome_names[] = {
    {Outcome::pending, "pending"},
    {Outcome::written, "written"},
    {Outcome::bad_input, "bad_input"},
    {Outcome::failed, "failed"},
};

/// What became of one file of a batch.
struct FileReport {
    Outcome outcome = Outcome::pending;
    std::string error;
    std::string device;
    std::uintmax_t input_bytes = 0, output_bytes = 0;
    double read_ms = 0, device_ms = 0, write_ms = 0, total_ms = 0;
    Clock::time_point start;
};

/// The failure of a step as a report: bad input (exit 2) or a run-time failure (exit 1).
/// Library input errors do not know the file: `input` goes in front unless named already.
void record_failure(FileReport& report, const std::string& input) {
    try {
        throw;
    } catch (const usage_error& e) {
        report.outcome = Outcome::bad_input;
        report.error = e.what();
    } catch (const input_error& e) {
        report.outcome = Outcome::bad_input;
        report.error = e.what();
    } catch (const unfit_kernel_error& e) { // an explicit --kernel the device cannot run: a usage choice
        report.outcome = Outcome::bad_input;
        report.error = e.what();
    } catch (const std::bad_alloc&) {
        report.outcome = Outcome::failed;
        report.error = "out of memory";
    } catch (const std::exception& e) {
        report.outcome = Outcome::failed;
        report.error = e.what();
    }
    if (report.error.rfind(input + ": ", 0) != 0) report.error = input + ": " + report.error;
}

/// A batch run: the jobs, one worker per device, the pool, the reports and the progress.
class Batch {
public:
    Batch(const std::string& command, std::vector<MapJob> jobs, bool verbose)
        : command_(command), jobs_(std::move(jobs)), reports_(jobs_.size()), verbose_(verbose) {
        for (std::size_t i = 0; i < jobs_.size(); ++i) {
            std::error_code error;
            const std::uintmax_t bytes = fs::file_size(jobs_[i].input, error);
            reports_[i].input_bytes = error ? 0 : bytes;
            total_bytes_ += reports_[i].input_bytes;
        }
    }

    /// Runs every job; device i takes the files at positions i, i + D, i + 2D, ... so that a
    /// file goes to the same device on every run (kernels may differ between device types).
    void run(std::vector<Context>& contexts) {
        start_ = Clock::now();
        ProgressLine progress(!verbose_, [this](double elapsed_s) { return progress_text(elapsed_s); });
        progress_ = &progress;
        // Per device: one read ahead of the map on the device, and the writes behind it.
        boost::asio::thread_pool pool(std::max<std::size_t>(1, contexts.size() * (1 + writes_in_flight())));
        std::vector<std::thread> workers;
        std::vector<std::string> failures(contexts.size());
        for (std::size_t d = 0; d < contexts.size(); ++d) {
            std::vector<std::size_t> mine;
            for (std::size_t i = d; i < jobs_.size(); i += contexts.size()) mine.push_back(i);
            workers.emplace_back([this, &pool, &context = contexts[d], mine, &failure = failures[d]] {
                try {
                    work(pool, context, mine);
                } catch (const std::exception& e) {
                    failure = e.what();
                }
            });
        }
        for (std::thread& worker : workers) worker.join();
        pool.join();
        // A worker stopped by a failure outside any one file's steps (out of memory in the
        // pipeline itself): its files not yet done failed with it.
        for (std::size_t i = 0; i < jobs_.size(); ++i)
            if (reports_[i].outcome == Outcome::pending) {
                reports_[i].outcome = Outcome::failed;
                reports_[i].error = jobs_[i].input + ": not processed: " + failures[i % contexts.size()];
                std::fprintf(stderr, "msmcl: %s\n", io::shorten_long_names(reports_[i].error).c_str());
            }
        progress_ = nullptr;
        seconds_ = milliseconds_between(start_, Clock::now()) / 1000.0;
    }

    std::size_t count(Outcome outcome) const {
        return static_cast<std::size_t>(std::count_if(reports_.begin(), reports_.end(),
                                                      [&](const FileReport& r) { return r.outcome == outcome; }));
    }

    /// "msmcl: filter: 24 files, 23 written, 1 bad input, 0 failed; 96.1 MB in 3.20 s (30.0 MB/s)".
    std::string summary_line(std::size_t devices) const {
        char text[512];
        std::snprintf(text, sizeof text,
                      "msmcl: %s: %zu files, %zu written, %zu bad input, %zu failed; %.1f MB read in %.2f s (%.1f MB/s) "
                      "on %zu device%s",
                      command_.c_str(), jobs_.size(), count(Outcome::written), count(Outcome::bad_input),
                      count(Outcome::failed), total_bytes_ / 1e6, seconds_,
                      seconds_ > 0 ? total_bytes_ / 1e6 / seconds_ : 0.0, devices, devices == 1 ? "" : "s");
        return text;
    }

    json summary_json(const std::string& shard, std::size_t devices) const {
        json files = json::array();
        for (std::size_t i = 0; i < jobs_.size(); ++i) {
            const FileReport& r = reports_[i];
            json file = {{"input", jobs_[i].input},
                         {"output", jobs_[i].output},
                         {"status", detail::name_in(outcome_names, r.outcome)},
                         {"error", r.error.empty() ? json(nullptr) : json(r.error)},
                         {"device", r.device.empty() ? json(nullptr) : json(r.device)},
                         {"input_bytes", r.input_bytes},
                         {"output_bytes", r.output_bytes},
                         {"ms", r.total_ms},
                         {"read_ms", r.read_ms},
                         {"device_ms", r.device_ms},
                         {"write_ms", r.write_ms}};
            files.push_back(std::move(file));
        }
        // The layout's version: docs/schemas/msmcl-batch-1.schema.json.
        return {{"schema", "msmcl-batch/1"},
                {"command", command_},
                {"shard", shard},
                {"devices", devices},
                {"files", std::move(files)},
                {"written", count(Outcome::written)},
                {"bad_input", count(Outcome::bad_input)},
                {"failed", count(Outcome::failed)},
                {"input_bytes", total_bytes_},
                {"seconds", seconds_}};
    }

private:
    /// A map read on the pool: the depth or the failure of the read.
    struct Loaded {
        io::TranslucentDepth depth;
        bool ok = false;
    };

    /// Writes queued at once per device: as many as the machine has threads (encoding is
    /// the longest step of a small map), at most 4.
    static std::size_t writes_in_flight() {
        return std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, 4);
    }

    /// One device's files in order: the next one read while this one is on the device, the
    /// previous ones written meanwhile. Memory: two maps, and the results waiting to be
    /// written, at most writes_in_flight() of them and no more than pending_write_bytes
    /// unless a single one is larger.
    void work(boost::asio::thread_pool& pool, Context& context, const std::vector<std::size_t>& mine) {
        const auto read = [&](std::size_t i) { return post_task(pool, [this, i] { return load(i); }); };
        std::future<Loaded> next;
        if (!mine.empty()) next = read(mine[0]);
        std::deque<std::pair<std::future<void>, std::size_t>> writing; // and the bytes each holds
        std::size_t writing_bytes = 0;
        for (std::size_t k = 0; k < mine.size(); ++k) {
            const std::size_t i = mine[k];
            MapResult result;
            {
                Loaded current = next.get();
                if (k + 1 < mine.size()) next = read(mine[k + 1]);
                if (!current.ok) {
                    finish(i);
                    continue;
                }
                // The device work of this map while the next one is read.
                FileReport& report = reports_[i];
                report.device = context.device().name;
                const Clock::time_point device_start = Clock::now();
                try {
                    result = jobs_[i].run(context, current.depth, nullptr);
                } catch (...) {
                    record_failure(report, jobs_[i].input);
                }
                report.device_ms = milliseconds_between(device_start, Clock::now());
                if (!result.write) {
                    finish(i);
                    continue;
                }
            }
            // Wait for earlier writes while too many, or too many bytes, are queued.
            while (!writing.empty() && (writing.size() >= writes_in_flight() ||
                                        writing_bytes + result.bytes > pending_write_bytes)) {
                writing.front().first.get();
                writing_bytes -= writing.front().second;
                writing.pop_front();
            }
            writing_bytes += result.bytes;
            writing.emplace_back(post_task(pool, [this, i, write = std::move(result.write)] { store(i, write); }),
                                 result.bytes);
        }
        for (auto& [pending, bytes] : writing) pending.get();
    }

    Loaded load(std::size_t i) {
        FileReport& report = reports_[i];
        report.start = Clock::now();
        Loaded loaded;
        try {
            loaded.depth = io::read_translucent_depth_exr(jobs_[i].input, jobs_[i].depth_range);
            const int samples = loaded.depth.depth.samples, expected = jobs_[i].expected_samples;
            if (expected != 0 && samples != expected)
                throw input_error(jobs_[i].input + ": " + std::to_string(samples) +
                                  " samples per texel, the manifest says " + std::to_string(expected));
            loaded.ok = true;
        } catch (...) {
            record_failure(report, jobs_[i].input);
        }
        report.read_ms = milliseconds_between(report.start, Clock::now());
        return loaded;
    }

    void store(std::size_t i, const std::function<void()>& write) {
        FileReport& report = reports_[i];
        const Clock::time_point write_start = Clock::now();
        try {
            write();
            report.outcome = Outcome::written;
            std::error_code error;
            const std::uintmax_t bytes = fs::file_size(jobs_[i].output, error);
            report.output_bytes = error ? 0 : bytes;
        } catch (...) {
            record_failure(report, jobs_[i].input);
        }
        report.write_ms = milliseconds_between(write_start, Clock::now());
        finish(i);
    }

    /// A file is done: its failure on stderr at once, its bytes in the progress.
    void finish(std::size_t i) {
        FileReport& report = reports_[i];
        report.total_ms = milliseconds_between(report.start, Clock::now());
        std::string line;
        if (report.outcome != Outcome::written) {
            line = "msmcl: " + report.error;
        } else if (verbose_) {
            char text[256];
            std::snprintf(text, sizeof text, ": read %.1f ms, %s %.1f ms, write %.1f ms", report.read_ms,
                          report.device.c_str(), report.device_ms, report.write_ms);
            line = "msmcl: " + jobs_[i].input + " -> " + jobs_[i].output + text;
        }
        {
            std::lock_guard<std::mutex> lock(mutex_);
            ++done_;
            done_bytes_ += report.input_bytes;
        }
        if (line.empty()) return;
        // No newline may stay inside the line (build logs): one line per file. Printed
        // without holding mutex_, which the progress line's text takes.
        std::replace(line.begin(), line.end(), '\n', ' ');
        progress_->print(io::shorten_long_names(line));
    }

    /// "msmcl: filter [#####...............] 6/24 files, 31.5 MB/s, ETA 9 s".
    std::string progress_text(double elapsed_s) {
        std::lock_guard<std::mutex> lock(mutex_);
        const double rate = elapsed_s > 0 ? done_bytes_ / 1e6 / elapsed_s : 0.0;
        char text[256];
        std::snprintf(text, sizeof text, "msmcl: %s %s %zu/%zu files, %.1f MB/s", command_.c_str(),
                      progress_bar(done_, jobs_.size()).c_str(), done_, jobs_.size(), rate);
        std::string line = text;
        if (done_ > 0 && done_ < jobs_.size()) {
            // Time left at the rate so far: by the bytes still to read, or by the files
            // while only empty or missing ones are done.
            const double bytes_left = double(total_bytes_ - std::min(done_bytes_, total_bytes_));
            const double left_s = done_bytes_ > 0 ? elapsed_s * bytes_left / double(done_bytes_)
                                                  : elapsed_s * double(jobs_.size() - done_) / double(done_);
            std::snprintf(text, sizeof text, ", ETA %.0f s", left_s);
            line += text;
        }
        return line;
    }

    std::string command_;
    std::vector<MapJob> jobs_;
    std::vector<FileReport> reports_;
    bool verbose_ = false;
    std::uintmax_t total_bytes_ = 0;
    Clock::time_point start_;
    double seconds_ = 0;

    std::mutex mutex_; ///< guards what the progress line reads
    std::size_t done_ = 0;
    std::uintmax_t done_bytes_ = 0;
    ProgressLine* progress_ = nullptr;
};

/// The single-file form: read, device setup, the command's stages, write; errors thrown.
void run_one(const GlobalArguments& global, const MapJob& job) {
    // The output is no spelling of the input, and can be written, before any work.
    check_distinct_files({{job.input, NamedFile::Role::input}, {job.output, NamedFile::Role::output}});
    check_output_path(job.output, false);
    Stages stages(global.verbose, global.verbose ? 7 : 4);
    // Read and validate the depth map and its translucent layers (layer<k>.Z, layer<k>.A).
    const io::TranslucentDepth layered =
        stages.run("read", [&] { return io::read_translucent_depth_exr(job.input, job.depth_range); });
    Context context = stages.run("device setup", [&] { return Context(device_selections(global).front()); });
    MapResult result;
    try {
        result = job.run(context, layered, &stages);
    } catch (const input_error& e) {
        // Library input errors do not know the file; put it in front.
        throw input_error(job.input + ": " + e.what());
    }
    stages.run("write", result.write);
}

/// The inputs of --array as one layered depth map: map i in array layer i, each map's
/// translucent layers beside it. All maps must share width, height and samples (input_error
/// naming the first that does not). A map with fewer translucent layers than another gets
/// layers of opacity 0, which give the bits of no layer (include/msmcl/filter.hpp).
io::TranslucentDepth stack_array_layers(const std::vector<std::string>& paths, DepthRange range) {
    std::vector<io::TranslucentDepth> maps;
    maps.reserve(paths.size());
    std::size_t most_translucent = 0;
    // "256x256, 4 samples per texel"
    const auto shape = [](const DepthImage& d) {
        return std::to_string(d.width) + "x" + std::to_string(d.height) + ", " + std::to_string(d.samples) +
               (d.samples == 1 ? " sample" : " samples") + " per texel";
    };
    for (const std::string& path : paths) {
        maps.push_back(io::read_translucent_depth_exr(path, range));
        const DepthImage &first = maps.front().depth, &map = maps.back().depth;
        if (map.width != first.width || map.height != first.height || map.samples != first.samples)
            throw input_error(path + ": " + shape(map) + ", but the array's layer 0 (" + paths.front() + ") is " +
                              shape(first) + ": every layer of a texture array has one size and sample count");
        most_translucent = std::max(most_translucent, maps.back().layers.size());
    }
    // The depths layer after layer; translucent layer k of array layer a after those of a - 1.
    io::TranslucentDepth stacked;
    const DepthImage& first = maps.front().depth;
    stacked.depth.width = first.width;
    stacked.depth.height = first.height;
    stacked.depth.samples = first.samples;
    stacked.depth.layers = static_cast<int>(maps.size());
    stacked.depth.depth.reserve(first.depth.size() * maps.size());
    stacked.layers.resize(most_translucent);
    for (io::TranslucentDepth& map : maps) {
        stacked.depth.depth.insert(stacked.depth.depth.end(), map.depth.depth.begin(), map.depth.depth.end());
        for (std::size_t k = 0; k < most_translucent; ++k) {
            TranslucentLayer& slices = stacked.layers[k];
            if (k < map.layers.size()) {
                slices.depth.insert(slices.depth.end(), map.layers[k].depth.begin(), map.layers[k].depth.end());
                slices.opacity.insert(slices.opacity.end(), map.layers[k].opacity.begin(), map.layers[k].opacity.end());
            } else {
                // No surface: the opaque depth (always valid) at opacity 0.
                slices.depth.insert(slices.depth.end(), map.depth.depth.begin(), map.depth.depth.end());
                slices.opacity.insert(slices.opacity.end(), map.depth.depth.size(), 0.0f);
            }
        }
        map = {}; // the stacked copy is all that is kept
    }
    return stacked;
}

/// The array form: every input one layer of a texture array, filtered (or tabled) by one
/// library call on the layered map and written as one KTX2 or DDS file; errors thrown.
void run_array(const GlobalArguments& global, const BatchArguments& batch, const MapCommand& command) {
    // Check the form and the output before touching any file.
    if (batch.is_batch() || !batch.shard.empty() || !batch.json.empty())
        throw usage_error("--array writes one file from the inputs IN...; -o, --list, --shard and --json are for a batch");
    if (batch.paths.empty()) throw usage_error("msmcl " + command.name + " --array OUT needs inputs IN...");
    if (batch.paths.size() > static_cast<std::size_t>(max_array_layers))
        throw usage_error("--array takes at most " + std::to_string(max_array_layers) + " inputs, got " +
                          std::to_string(batch.paths.size()));
    if (output_container(command.out_container, batch.array) == Container::exr)
        throw usage_error(batch.array +
                          ": an OpenEXR texture holds one map; write a texture array as .ktx2 (layerCount) or .dds "
                          "(arraySize)");
    const MapJob job = command.make_job(BatchEntry{batch.paths.front(), batch.array, {}, true});
    std::vector<NamedFile> files{{batch.array, NamedFile::Role::output}};
    for (const std::string& input : batch.paths) files.push_back({input, NamedFile::Role::input});
    check_distinct_files(files);
    check_output_path(batch.array, false);

    Stages stages(global.verbose, global.verbose ? 7 : 4);
    // Read every input and stack them as the layers of one depth map.
    const io::TranslucentDepth layered =
        stages.run("read", [&] { return stack_array_layers(batch.paths, job.depth_range); });
    Context context = stages.run("device setup", [&] { return Context(device_selections(global).front()); });
    MapResult result;
    try {
        result = job.run(context, layered, &stages);
    } catch (const input_error& e) {
        // Library input errors do not know the files; name the array's.
        throw input_error(batch.array + " (array of " + std::to_string(batch.paths.size()) + " inputs): " + e.what());
    }
    stages.run("write", result.write);
}

} // namespace

void add_batch_options(CLI::App& command, BatchArguments& batch) {
    // An empty value is a mistake (an unset shell variable), never "not given".
    const auto not_empty = [](const char* what) {
        return CLI::Validator(
            [what](const std::string& value) {
                return value.empty() ? std::string(what) + ", got an empty value" : std::string();
            },
            "", "NOT_EMPTY");
    };
    command.add_option("paths", batch.paths,
                       "IN OUT (one file), or the inputs IN... of a batch with -o DIR; - is standard input or output");
    command.add_option("-o,--output-dir", batch.output_dir,
                       "batch: write DIR/<input name>.<container> for each input (DIR is created)")
        ->type_name("DIR")
        ->check(not_empty("-o needs a folder"));
    command.add_option("--list", batch.list,
                       "batch: inputs from FILE (- for standard input), one per line, or a JSON manifest (an array "
                       "of inputs or of objects with \"input\", \"output\" and per-file options)")
        ->type_name("FILE")
        ->check(not_empty("--list needs a file or -"));
    command.add_option("--shard", batch.shard,
                       "batch: take only the files at positions p with p % N == I (0 <= I < N), for job arrays")
        ->type_name("I/N")
        ->check(not_empty("--shard must be I/N with 0 <= I < N"));
    command.add_option("--json", batch.json, "batch: write a JSON summary (per file: status, error, bytes, ms) to FILE, "
                                             "or - for stdout")
        ->type_name("FILE")
        ->check(not_empty("--json needs a file or -"));
    command.add_option("--array", batch.array,
                       "write the inputs IN... as the layers of one texture array (KTX2 or DDS), in one call; all "
                       "inputs of one size and sample count")
        ->type_name("FILE")
        ->check(not_empty("--array needs a file"));
}

std::string entry_option(const BatchEntry& entry, const std::string& key, const std::string& fallback) {
    const auto it = entry.options.find(key);
    return it == entry.options.end() ? fallback : it->second;
}

int run_map_command(const GlobalArguments& global, const BatchArguments& batch, const MapCommand& command) {
    // The array form: the inputs are the layers of one file.
    if (!batch.array.empty()) {
        run_array(global, batch, command);
        return 0;
    }
    // The single-file form: exactly IN OUT, errors thrown as from every command.
    if (!batch.is_batch()) {
        if (!batch.shard.empty() || !batch.json.empty())
            throw usage_error("--shard and --json apply to a batch (-o DIR or --list FILE)");
        if (batch.paths.size() != 2)
            throw usage_error(batch.paths.size() < 2
                                  ? "msmcl " + command.name + " needs IN OUT, or inputs with -o DIR or --list FILE"
                                  : "msmcl " + command.name + " takes several inputs only with -o DIR");
        run_one(global, command.make_job(BatchEntry{batch.paths[0], batch.paths[1], {}}));
        return 0;
    }

    // Check every entry's options and name every output before touching a file.
    if (batch.paths.empty() && batch.list.empty())
        throw usage_error("msmcl " + command.name + " -o DIR needs inputs: IN... or --list FILE");
    const Shard shard = batch.shard.empty() ? Shard{} : parse_shard(batch.shard);
    if (!batch.json.empty() && batch.json != "-" && !fs::path(batch.json).has_filename())
        throw usage_error("--json needs a file name or -, got '" + batch.json + "'");
    std::vector<MapJob> all = batch_jobs(batch, command);
    check_output_folders(batch, all);
    std::vector<MapJob> mine = shard_jobs(std::move(all), shard);

    // One Context per device (one program build each), then the output folders: a run
    // refused before any map is read creates nothing.
    std::vector<Context> contexts;
    // An empty shard sets up no device.
    const std::vector<DeviceSelection> selections =
        mine.empty() ? std::vector<DeviceSelection>{} : device_selections(global);
    for (std::size_t d = 0; d < selections.size(); ++d) {
        try {
            contexts.emplace_back(selections[d]);
        } catch (const error& e) {
            // --device all: a device that cannot be set up leaves its files to the others.
            if (selections.size() == 1 || (d + 1 == selections.size() && contexts.empty())) throw;
            if (!global.quiet)
                std::fprintf(stderr, "msmcl: device %zu of %zu skipped: %s\n", d, selections.size(), e.what());
        }
    }

    create_output_folders(batch, mine);
    Batch run(command.name, std::move(mine), global.verbose);
    run.run(contexts);

    // The summary: a line on stderr, and the JSON where asked for.
    if (!global.quiet) {
        std::fprintf(stderr, "%s\n", run.summary_line(contexts.size()).c_str());
        std::fflush(stderr);
    }
    if (!batch.json.empty()) {
        const std::string text = run.summary_json(shard.text(), contexts.size()).dump(2) + "\n";
        if (batch.json == "-") {
            std::cout << text;
            std::cout.flush();
        } else {
            io::write_file_atomically(batch.json, text.data(), text.size());
        }
    }
    if (run.count(Outcome::bad_input) > 0) return 2;
    return run.count(Outcome::failed) > 0 ? 1 : 0;
}

} // namespace msmcl::cli
