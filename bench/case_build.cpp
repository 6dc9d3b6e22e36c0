// Rows build_cold, build_warm and first_call: what the first filter() call of a process
// costs. Each measurement is a fresh process (this executable in probe mode, see
// probe.hpp) so that nothing is cached in memory; PoCL's kernel cache (POCL_CACHE_DIR)
// and msmcl's binary cache (MSMCL_CACHE_DIR) point into a directory that is empty
// (cold) or filled by an earlier probe (warm).
//  - build_cold: first call minus a steady call (the fastest of 3), empty caches (compile
//    + JIT);
//  - build_warm: the same with the caches filled (load binaries + JIT from cache);
//  - first_call: the whole first call with warm caches, as an application sees it.
#include "harness.hpp"
#include "probe.hpp"
#include "tests/process.hpp"

#include <msmcl/errors.hpp>

#include <nlohmann/json.hpp>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace msmcl::bench {

namespace {

namespace fs = std::filesystem;

// Runs the probe in a child process with the caches under `cache_root`; returns its JSON.
nlohmann::json run_probe(const BenchEnv& env, const Workload& work, const fs::path& cache_root) {
    const fs::path report = cache_root / "probe.json";
    std::vector<std::string> arguments = {env.self_path, kProbeFlag,
                                          "--size", std::to_string(work.size),
                                          "--samples", std::to_string(work.samples),
                                          "--format", format_name(work.format),
                                          "--json", report.string()};
    if (!env.device.empty()) {
        arguments.push_back("--device");
        arguments.push_back(env.device);
    }
    // The environment with both cache directories replaced.
    std::vector<std::string> variables;
    for (char** entry = environ; *entry; ++entry) {
        const std::string variable = *entry;
        if (variable.rfind("POCL_CACHE_DIR=", 0) == 0 || variable.rfind("MSMCL_CACHE_DIR=", 0) == 0 ||
            variable.rfind("POCL_KERNEL_CACHE=", 0) == 0)
            continue;
        variables.push_back(variable);
    }
    fs::create_directories(cache_root / "pocl");
    fs::create_directories(cache_root / "msmcl");
    variables.push_back("POCL_CACHE_DIR=" + (cache_root / "pocl").string());
    variables.push_back("MSMCL_CACHE_DIR=" + (cache_root / "msmcl").string());
    const int exit_code = msmcl::testing::run_process(arguments, "", "", &variables);
    if (exit_code == msmcl::testing::process_not_started)
        throw error("msmcl-bench: cannot start the first-call probe " + env.self_path);
    if (exit_code != 0)
        throw error("msmcl-bench: the first-call probe failed (exit code " + std::to_string(exit_code) + ")");
    std::ifstream in(report);
    return nlohmann::json::parse(in);
}

std::vector<CaseResult> run_build_rows(BenchEnv& env, const Workload& work) {
    if (env.build_reps <= 0 || env.self_path.empty()) return {};
    CaseResult cold, warm, first;
    cold.name = "build_cold";
    warm.name = "build_warm";
    first.name = "first_call";
    for (CaseResult* row : {&cold, &warm, &first}) row->has_throughput = false;
    first.bytes = work.bytes();
    std::vector<double> steady;
    for (int rep = 0; rep < env.build_reps; ++rep) {
        // A fresh, empty cache directory per repetition.
        std::string pattern = (fs::temp_directory_path() / "msmcl-bench-XXXXXX").string();
        if (!mkdtemp(pattern.data())) throw error("msmcl-bench: cannot create a temporary directory");
        const fs::path root = pattern;
        const nlohmann::json cold_probe = run_probe(env, work, root);
        const nlohmann::json warm_probe = run_probe(env, work, root);
        std::error_code ignored;
        fs::remove_all(root, ignored);
        cold.ms.push_back(cold_probe["first_ms"].get<double>() - cold_probe["steady_ms"].get<double>());
        warm.ms.push_back(warm_probe["first_ms"].get<double>() - warm_probe["steady_ms"].get<double>());
        first.ms.push_back(warm_probe["first_ms"].get<double>());
        steady.push_back(warm_probe["steady_ms"].get<double>());
        cold.extra["programs_built"] = cold_probe["programs_built"];
        warm.extra["programs_built"] = warm_probe["programs_built"];
    }
    first.extra["steady_ms_median"] = median(steady); // of the probes' fastest steady calls
    for (CaseResult* row : {&cold, &warm, &first}) row->extra["kernel"] = "automatic";
    return {cold, warm, first};
}

MSMCL_BENCH_CASE({"build", 100, run_build_rows});

} // namespace

} // namespace msmcl::bench
