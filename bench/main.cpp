// msmcl-bench: the filter's cost on one OpenCL device against its peers (a plain C++ loop,
// OpenCV where installed, a copy of the same bytes) as JSON rows; scripts/plot_bench.py
// plots them.
//   msmcl-bench --size N --samples S --format F [--device D] [--reps R] --json FILE
// Without --size: the full sweep (512^2 .. 4096^2, S = 1, 4, 8, every format; --samples
// and --format restrict it).
#include "harness.hpp"
#include "probe.hpp"
#include "scene.hpp"

#include "runtime/texture_kinds.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace {

using namespace msmcl;
using namespace msmcl::bench;

// Repetitions when --reps is not given: fewer for the big maps (a full sweep in minutes).
int default_reps(int size) { return size <= 512 ? 10 : size <= 1024 ? 7 : size <= 2048 ? 5 : 2; }

std::string executable_path(const char* argv0) {
    std::error_code error;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
    return error ? std::string(argv0) : self.string();
}

// One JSON row of a measured case, with the derived figures.
nlohmann::json make_row(const CaseResult& result, const Workload& work, const std::string& device,
                        const std::string& device_type) {
    nlohmann::json row;
    row["case"] = result.name;
    row["size"] = work.size;
    row["samples"] = work.samples;
    row["format"] = format_name(work.format);
    row["device"] = device;
    row["device_type"] = device_type;
    row["reps"] = static_cast<int>(result.ms.size());
    row["ms_min"] = minimum(result.ms);
    row["ms_median"] = median(result.ms);
    row["ms"] = result.ms;
    row["cpu_ms_median"] = result.cpu_ms.empty() ? nlohmann::json(nullptr) : nlohmann::json(median(result.cpu_ms));
    row["bytes"] = result.bytes;
    const double seconds = median(result.ms) * 1e-3;
    if (result.has_throughput && seconds > 0.0) {
        // Rows of several maps (texture arrays) say how many in "layers".
        const double maps = result.extra.contains("layers") ? result.extra["layers"].get<double>() : 1.0;
        row["mtexels_per_s"] = double(work.texels()) * maps / seconds * 1e-6;
        row["gb_per_s"] = double(result.bytes) / seconds * 1e-9;
    } else {
        row["mtexels_per_s"] = nullptr;
        row["gb_per_s"] = nullptr;
    }
    for (auto& [key, value] : result.extra.items()) row[key] = value;
    return row;
}

// Fraction of the copy roof: copy's median time, scaled to the case's bytes (several maps
// per row move a multiple of copy's), over the case's.
void add_roof_fractions(std::vector<nlohmann::json>& rows) {
    for (nlohmann::json& row : rows) {
        row["copy_roof_fraction"] = nullptr;
        if (row["gb_per_s"].is_null()) continue;
        for (const nlohmann::json& copy : rows)
            if (copy["case"] == "copy" && copy["size"] == row["size"] && copy["samples"] == row["samples"] &&
                copy["format"] == row["format"])
                row["copy_roof_fraction"] = copy["ms_median"].get<double>() *
                                            (row["bytes"].get<double>() / copy["bytes"].get<double>()) /
                                            row["ms_median"].get<double>();
    }
}

void print_row(const nlohmann::json& row) {
    const auto number = [](const nlohmann::json& value, const char* format) {
        if (value.is_null()) return std::string("-");
        char text[32];
        std::snprintf(text, sizeof text, format, value.get<double>());
        return std::string(text);
    };
    std::printf("%-12s %5d^2 S=%-2d %-10s  min %9s ms  median %9s ms  cpu %9s ms  %8s Mtex/s  %6s GB/s  roof %5s\n",
                row["case"].get<std::string>().c_str(), row["size"].get<int>(), row["samples"].get<int>(),
                row["format"].get<std::string>().c_str(), number(row["ms_min"], "%.2f").c_str(),
                number(row["ms_median"], "%.2f").c_str(), number(row["cpu_ms_median"], "%.1f").c_str(),
                number(row["mtexels_per_s"], "%.1f").c_str(),
                number(row["gb_per_s"], "%.2f").c_str(), number(row["copy_roof_fraction"], "%.2f").c_str());
    std::fflush(stdout);
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"msmcl-bench: cost of the moment shadow map filter on an OpenCL device against its peers",
                 "msmcl-bench"};
    int size = 0, samples = 0, reps = 0, build_reps = -1;
    std::string format_text, device, json_path;
    std::vector<std::string> only_cases;
    bool probe = false;
    app.add_option("--size", size, "map width = height in texels; without it the full sweep 512..4096")
        ->check(CLI::Range(1, 16384));
    app.add_option("--samples", samples, "samples per texel (1, 2, 4, 8, 16); default: sweep 1, 4, 8");
    std::string format_list;
    for (Format format : detail::filter_formats())
        format_list += (format_list.empty() ? "" : "|") + std::string(format_name(format));
    app.add_option("--format", format_text, format_list + "; default: the four moment formats");
    app.add_option("--device", device, "OpenCL device spec (gpu, cpu, index, P:D or a name substring)");
    app.add_option("--reps", reps, "timed repetitions per case (default 10, 7, 5, 2 from 512^2 to 4096^2)")
        ->check(CLI::Range(1, 10000));
    app.add_option("--json", json_path, "where the JSON array of rows goes")->required();
    app.add_option("--case", only_cases, "run only these cases (repeatable; build = the build/first-call rows)");
    app.add_option("--build-reps", build_reps,
                   "probe processes per build row (default 2 for one configuration, 1 at 2048^2 S=4 in a sweep)");
    std::string cli_path;
    app.add_option("--msmcl", cli_path, "the msmcl executable the batch case runs (default: the one built with this bench)");
    std::string build_options;
    app.add_option("--build-options", build_options, "extra OpenCL build options for every program (experiments)");
    app.add_flag(kProbeFlag, probe)->group("");
    CLI11_PARSE(app, argc, argv);

    try {
        std::optional<Format> only_format;
        if (!format_text.empty()) {
            only_format = parse_format(format_text);
            if (!only_format) throw input_error("unknown format '" + format_text + "'");
        }
        if (samples != 0 && !is_supported_sample_count(samples))
            throw input_error("unsupported sample count " + std::to_string(samples));
        if (probe) {
            if (size == 0 || samples == 0 || !only_format) throw input_error("the probe needs --size, --samples, --format");
            return run_first_call_probe(size, samples, *only_format, device, json_path);
        }

        // The sweep: sizes x samples x formats, or the one configuration asked for.
        const bool sweep = size == 0;
        const std::vector<int> sizes = sweep ? std::vector<int>{512, 1024, 2048, 4096} : std::vector<int>{size};
        const std::vector<int> sample_counts = samples ? std::vector<int>{samples} : std::vector<int>{1, 4, 8};
        std::vector<Format> formats{Format::moments128, Format::msm64, Format::nlq64, Format::nlq32};
        if (only_format) formats = {*only_format};

        DeviceSelection selection;
        selection.device = device;
        selection.strict = !device.empty();
        Context context(selection);
        if (!build_options.empty()) context.set_extra_build_options(build_options);
        const std::string device_name = context.device().name;
        const std::string device_type = context.device().is_gpu ? "gpu" : context.device().is_cpu ? "cpu" : "other";
        std::cout << "device: " << device_name << " (" << context.device().platform_name << ")\n";

        BenchEnv env;
        env.context = &context;
        env.device = device;
        env.self_path = executable_path(argv[0]);
        env.cli_path = cli_path;
        const std::set<std::string> wanted(only_cases.begin(), only_cases.end());
        std::vector<BenchCase> cases;
        for (const BenchCase& c : registered_cases())
            if (wanted.empty() || wanted.count(c.name)) cases.push_back(c);

        std::vector<nlohmann::json> rows;
        for (int map_size : sizes) {
            for (int sample_count : sample_counts) {
                // Data once per size and sample count, on the host and the device.
                const DepthImage depth = make_scene(map_size, sample_count);
                cl_int status = CL_SUCCESS;
                cl_mem depth_buffer =
                    clCreateBuffer(context.cl_context_handle(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                   depth.depth.size() * sizeof(float), const_cast<float*>(depth.depth.data()), &status);
                check_cl(status, "clCreateBuffer(depth)");
                for (Format format : formats) {
                    Workload work;
                    work.size = map_size;
                    work.samples = sample_count;
                    work.format = format;
                    work.depth = &depth;
                    work.depth_buffer = depth_buffer;
                    work.texture_buffer = clCreateBuffer(context.cl_context_handle(), CL_MEM_READ_WRITE,
                                                         work.texture_bytes(), nullptr, &status);
                    check_cl(status, "clCreateBuffer(texture)");
                    env.reps = reps ? reps : default_reps(map_size);
                    // Warm-up: the first run builds and JIT-compiles and touches the buffers;
                    // small maps get a second one (their runs are short and jittery).
                    env.warmups = map_size <= 512 ? 2 : 1;
                    env.build_reps = build_reps >= 0 ? build_reps
                                     : !sweep      ? 2
                                     : (map_size == 2048 && sample_count == 4) ? 1
                                                                               : 0;
                    // The three-pass texture: what every case's output is compared with.
                    FilterOptions reference_options;
                    reference_options.format = format;
                    reference_options.kernel = FilterKernel::three_pass;
                    filter(context, DeviceDepth{depth_buffer, map_size, map_size, sample_count}, work.texture_buffer,
                           reference_options);
                    env.three_pass_words = read_texture(context, work.texture_buffer, work.texture_bytes());
                    std::vector<nlohmann::json> config_rows;
                    for (const BenchCase& c : cases)
                        for (const CaseResult& result : c.run(env, work))
                            config_rows.push_back(make_row(result, work, device_name, device_type));
                    add_roof_fractions(config_rows);
                    for (const nlohmann::json& row : config_rows) {
                        print_row(row);
                        rows.push_back(row);
                    }
                    clReleaseMemObject(work.texture_buffer);
                }
                clReleaseMemObject(depth_buffer);
            }
        }

        std::ofstream out(json_path);
        out << nlohmann::json(rows).dump(2) << '\n';
        if (!out) throw error("msmcl-bench: cannot write " + json_path);
        // Plots: scripts/plot_bench.py (matplotlib) reads these rows.
        std::cout << "wrote " << json_path << " (plot: python3 scripts/plot_bench.py " << json_path << ")\n";
        return 0;
    } catch (const input_error& e) {
        std::cerr << "msmcl-bench: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "msmcl-bench: " << e.what() << "\n";
        return 1;
    }
}
