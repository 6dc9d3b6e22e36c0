// Rows batch_cli and batch_loop: many maps through the msmcl command line, as a baking
// pipeline runs it. The same N depth maps (EXR files on disk) are filtered into msm64
// textures by one batch call (`msmcl filter IN... -o DIR --format msm64`: one Context, one
// program build, reads and writes beside the device work) and by a loop of N single-file
// calls (`msmcl filter IN OUT --format msm64`, a process each, as a shell loop runs them),
// in turns within the same run; both outputs must be byte-identical. `--msmcl PATH` runs
// another build's CLI (before/after comparisons). The row batch_loop
// carries the ratio loop / batch (median over the paired repetitions); the CPU column of
// both rows is the CPU time of the msmcl processes (user + system).
// N: 24 maps at 512^2 and below, 8 at 1024^2, 4 at 2048^2; larger maps are skipped (a
// batch of those is bound by the single-file path, which its own case measures). Only the
// msm64 workloads with S = 4 run it (neither changes what a batch saves): once per size in a
// full sweep, 6.1 minutes for 512^2..2048^2 on the 2-core VM at load average 10 (94 + 94 +
// 163 s with --reps 3, the default cap).
#include "harness.hpp"
#include "scene.hpp"
#include "tests/process.hpp"

#include "io/atomic_file.hpp"
#include "io/exr_io.hpp"

#include <msmcl/errors.hpp>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <filesystem>
#include <string>
#include <vector>

#ifndef MSMCL_CLI_PATH
#define MSMCL_CLI_PATH ""
#endif

namespace msmcl::bench {

namespace {

namespace fs = std::filesystem;

int maps_for(int size) { return size <= 512 ? 24 : size <= 1024 ? 8 : size <= 2048 ? 4 : 0; }

/// CPU time of the finished child processes (user + system), in ms.
double children_cpu_ms() {
    rusage usage{};
    getrusage(RUSAGE_CHILDREN, &usage);
    const auto ms = [](const timeval& t) { return t.tv_sec * 1e3 + t.tv_usec * 1e-3; };
    return ms(usage.ru_utime) + ms(usage.ru_stime);
}

/// Runs msmcl with `arguments` (and --device when the bench has one); throws when it fails.
void run_cli(const BenchEnv& env, std::vector<std::string> arguments) {
    if (!env.device.empty()) arguments.insert(arguments.begin(), {"--device", env.device});
    arguments.insert(arguments.begin(), env.cli_path.empty() ? std::string(MSMCL_CLI_PATH) : env.cli_path);
    const int code = msmcl::testing::run_process(arguments, "/dev/null", "/dev/null");
    if (code != 0)
        throw error("msmcl-bench: batch case: msmcl " + arguments[1] + " ... exited with " + std::to_string(code));
}

/// A temporary folder removed at scope exit.
struct ScratchFolder {
    fs::path path;
    ScratchFolder() {
        std::string pattern = (fs::temp_directory_path() / "msmcl-bench-batch-XXXXXX").string();
        if (!::mkdtemp(pattern.data())) throw error("msmcl-bench: cannot create a temporary folder");
        path = pattern;
    }
    ~ScratchFolder() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
    }
};

std::vector<CaseResult> run_batch_rows(BenchEnv& env, const Workload& work) {
    const int maps = maps_for(work.size);
    if ((std::string(MSMCL_CLI_PATH).empty() && env.cli_path.empty()) || maps == 0 || work.format != Format::msm64 || work.samples != 4)
        return {};
    const std::string format = format_name(work.format);

    // N different maps of the workload's kind, on disk as FLOAT EXR.
    ScratchFolder scratch;
    std::vector<std::string> inputs;
    std::uintmax_t input_bytes = 0;
    fs::create_directories(scratch.path / "in");
    for (int i = 0; i < maps; ++i) {
        const std::string input = (scratch.path / "in" / ("map" + std::to_string(i) + ".exr")).string();
        io::write_depth_exr(input, make_scene(work.size, work.samples, 7u + static_cast<std::uint32_t>(i)));
        input_bytes += fs::file_size(input);
        inputs.push_back(input);
    }
    const fs::path batch_dir = scratch.path / "batch", loop_dir = scratch.path / "loop";
    fs::create_directories(loop_dir);

    // One batch call, and the loop of single-file calls.
    const auto batch = [&] {
        std::vector<std::string> arguments = {"filter"};
        arguments.insert(arguments.end(), inputs.begin(), inputs.end());
        arguments.insert(arguments.end(), {"-o", batch_dir.string(), "--format", format});
        run_cli(env, arguments);
    };
    const auto loop = [&] {
        for (std::size_t i = 0; i < inputs.size(); ++i)
            run_cli(env, {"filter", inputs[i], (loop_dir / fs::path(inputs[i]).filename()).string(), "--format", format});
    };

    // One untimed run each (fills PoCL's kernel cache), then timed in turns, so that a slow
    // phase of a shared machine hits both alike.
    const int reps = std::max(1, std::min(env.reps, 3));
    batch();
    loop();
    Timings batch_timings, loop_timings;
    const std::vector<std::pair<std::function<void()>, Timings*>> turns = {{batch, &batch_timings},
                                                                           {loop, &loop_timings}};
    for (int rep = 0; rep < reps; ++rep)
        for (const auto& [run, timings] : turns) {
            const double cpu_start = children_cpu_ms();
            const auto start = std::chrono::steady_clock::now();
            run();
            timings->wall_ms.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
            timings->cpu_ms.push_back(children_cpu_ms() - cpu_start);
        }

    // The outputs must be the same bytes.
    bool identical = true;
    for (const std::string& input : inputs) {
        const std::string name = fs::path(input).filename().string();
        identical = identical && io::read_whole_file((batch_dir / name).string()) ==
                                     io::read_whole_file((loop_dir / name).string());
    }

    CaseResult batch_row, loop_row;
    batch_row.name = "batch_cli";
    loop_row.name = "batch_loop";
    const double ratio = median_ratio(loop_timings.wall_ms, batch_timings.wall_ms);
    for (CaseResult* row : {&batch_row, &loop_row}) {
        row->has_throughput = false;
        row->bytes = work.bytes() * static_cast<std::size_t>(maps);
        row->extra["maps"] = maps;
        row->extra["input_file_bytes"] = input_bytes;
        row->extra["identical_outputs"] = identical;
        row->extra["loop_over_batch"] = ratio;
    }
    batch_row.take(batch_timings);
    loop_row.take(loop_timings);
    batch_row.extra["ms_per_map"] = median(batch_row.ms) / maps;
    loop_row.extra["ms_per_map"] = median(loop_row.ms) / maps;
    std::printf("batch: %d maps of %d^2 S=%d %s: one call %.0f ms (%.1f ms a map), a loop of calls %.0f ms "
                "(%.1f ms a map): %.2fx; outputs %s\n",
                maps, work.size, work.samples, format.c_str(), median(batch_row.ms), median(batch_row.ms) / maps,
                median(loop_row.ms), median(loop_row.ms) / maps, ratio, identical ? "byte-identical" : "DIFFER");
    if (!identical) throw error("msmcl-bench: batch case: the batch and the loop wrote different bytes");
    return {batch_row, loop_row};
}

} // namespace

MSMCL_BENCH_CASE({"batch", 140, run_batch_rows});

} // namespace msmcl::bench
