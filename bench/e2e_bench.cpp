// msmcl-e2e-bench: the whole CLI path against the floor of any EXR-to-EXR tool, in one
// run. Each repetition runs, as child processes, `msmcl filter IN OUT --format F` and
// msmcl-exr-peer (a plain OpenEXR read of the same file and write of an EXR with the
// same channels and size), in alternating order so that a slow phase of a shared machine
// hits both. Reports wall times (median, min, max), their ratio (median of the per-
// repetition ratios), the same for CPU time (user + system of all threads, the steadier
// figure on a shared machine), and each child's peak resident memory (wait4's ru_maxrss) against
// the data a filter must hold: the input as floats plus the output texture.
//   msmcl-e2e-bench [--input D.exr | --size 4096 --samples 4] [--formats msm64,nlq32]
//                   [--reps 5] [--json FILE] [--msmcl PATH]
#include <msmcl/formats.hpp>

#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

extern char** environ;

namespace {

/// Wall time, CPU time (user + system, all threads) and peak resident memory of one
/// child process.
struct ChildRun {
    double ms = 0.0;
    double cpu_ms = 0.0;
    long max_rss_kb = 0;
};

/// Runs `arguments` (the program first) with stdout and stderr as the bench's; throws
/// when it cannot start or exits with a failure.
ChildRun run_child(const std::vector<std::string>& arguments) {
    std::vector<char*> argv;
    for (const std::string& argument : arguments) argv.push_back(const_cast<char*>(argument.c_str()));
    argv.push_back(nullptr);
    const auto start = std::chrono::steady_clock::now();
    pid_t pid = 0;
    if (const int error = posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ); error != 0)
        throw std::runtime_error("cannot start " + arguments[0] + ": " + std::strerror(error));
    int status = 0;
    struct rusage usage {};
    if (wait4(pid, &status, 0, &usage) != pid) throw std::runtime_error("wait4 failed for " + arguments[0]);
    const auto end = std::chrono::steady_clock::now();
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::string command;
        for (const std::string& argument : arguments) command += (command.empty() ? "" : " ") + argument;
        throw std::runtime_error("failed: " + command);
    }
    const auto milliseconds = [](const timeval& time) { return time.tv_sec * 1e3 + time.tv_usec * 1e-3; };
    return {std::chrono::duration<double, std::milli>(end - start).count(),
            milliseconds(usage.ru_utime) + milliseconds(usage.ru_stime), usage.ru_maxrss};
}

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

nlohmann::json summary(const std::vector<double>& values) {
    return {{"median", median(values)},
            {"min", *std::min_element(values.begin(), values.end())},
            {"max", *std::max_element(values.begin(), values.end())},
            {"all", values}};
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"msmcl-e2e-bench: msmcl filter end to end against a plain OpenEXR read + write"};
    std::string input, json_path, formats_text = "msm64,nlq32", cli = MSMCL_E2E_CLI;
    int size = 4096, samples = 4, reps = 5;
    app.add_option("--input", input, "depth EXR (default: the railing scene made by msmcl-scene)");
    app.add_option("--size", size, "side of the generated depth map")->check(CLI::Range(8, 16384));
    app.add_option("--samples", samples, "samples per texel of the generated depth map")
        ->check(CLI::IsMember({1, 2, 4, 8, 16}));
    app.add_option("--formats", formats_text, "comma-separated texture formats");
    app.add_option("--reps", reps, "timed repetitions of each command")->check(CLI::Range(1, 100));
    app.add_option("--json", json_path, "write the figures as JSON");
    app.add_option("--msmcl", cli, "the msmcl executable to time (default: the one built with this bench)");
    CLI11_PARSE(app, argc, argv);

    try {
        // A scratch folder for the input and the outputs.
        const std::filesystem::path work =
            std::filesystem::temp_directory_path() / ("msmcl-e2e-bench." + std::to_string(getpid()));
        std::filesystem::create_directories(work);
        if (input.empty()) {
            input = (work / "depth.exr").string();
            run_child({MSMCL_E2E_SCENE_TOOL, "--width", std::to_string(size), "--samples", std::to_string(samples),
                       "--depth", input});
        }

        // The data a filter holds: the input as floats (every channel), and the texture.
        Imf::InputFile header_file(input.c_str());
        const Imath::Box2i window = header_file.header().dataWindow();
        const std::uint64_t texels = static_cast<std::uint64_t>(window.max.x - window.min.x + 1) *
                                     static_cast<std::uint64_t>(window.max.y - window.min.y + 1);
        std::uint64_t channels = 0;
        for (auto it = header_file.header().channels().begin(); it != header_file.header().channels().end(); ++it)
            ++channels;
        const std::uint64_t input_float_bytes = texels * channels * sizeof(float);

        nlohmann::json rows = nlohmann::json::array();
        std::stringstream formats_stream(formats_text);
        for (std::string format_text; std::getline(formats_stream, format_text, ',');) {
            const std::optional<msmcl::Format> format = msmcl::parse_format(format_text);
            if (!format || *format == msmcl::Format::moments128)
                throw std::runtime_error("--formats: msm64, nlq64 or nlq32, got '" + format_text + "'");
            const std::uint64_t output_bytes = texels * msmcl::texel_bytes(*format);
            const std::string channel_count = *format == msmcl::Format::nlq32 ? "1" : "4";
            const std::vector<std::string> msmcl_command = {cli, "filter", input,
                                                            (work / ("msmcl_" + format_text + ".exr")).string(),
                                                            "--format", format_text};
            const std::vector<std::string> peer_command = {
                MSMCL_E2E_PEER, input, (work / ("peer_" + format_text + ".exr")).string(), "--channels", channel_count};

            // One untimed run each (program cache, page cache), then alternating pairs.
            run_child(msmcl_command);
            run_child(peer_command);
            std::vector<double> msmcl_ms, peer_ms, ratios, msmcl_cpu_ms, peer_cpu_ms, cpu_ratios, msmcl_rss, peer_rss;
            for (int rep = 0; rep < reps; ++rep) {
                ChildRun ours, peer;
                if (rep % 2 == 0) {
                    ours = run_child(msmcl_command);
                    peer = run_child(peer_command);
                } else {
                    peer = run_child(peer_command);
                    ours = run_child(msmcl_command);
                }
                msmcl_ms.push_back(ours.ms);
                peer_ms.push_back(peer.ms);
                ratios.push_back(ours.ms / peer.ms);
                msmcl_cpu_ms.push_back(ours.cpu_ms);
                peer_cpu_ms.push_back(peer.cpu_ms);
                cpu_ratios.push_back(ours.cpu_ms / peer.cpu_ms);
                msmcl_rss.push_back(static_cast<double>(ours.max_rss_kb) * 1024.0);
                peer_rss.push_back(static_cast<double>(peer.max_rss_kb) * 1024.0);
            }
            const double data_bytes = static_cast<double>(input_float_bytes + output_bytes);
            nlohmann::json row = {{"format", format_text},
                                  {"texels", texels},
                                  {"input_channels", channels},
                                  {"input_float_bytes", input_float_bytes},
                                  {"output_bytes", output_bytes},
                                  {"reps", reps},
                                  {"msmcl_ms", summary(msmcl_ms)},
                                  {"peer_ms", summary(peer_ms)},
                                  {"wall_ratio", summary(ratios)},
                                  {"msmcl_cpu_ms", summary(msmcl_cpu_ms)},
                                  {"peer_cpu_ms", summary(peer_cpu_ms)},
                                  {"cpu_ratio", summary(cpu_ratios)},
                                  {"msmcl_peak_rss_bytes", summary(msmcl_rss)},
                                  {"peer_peak_rss_bytes", summary(peer_rss)},
                                  {"msmcl_rss_over_data", median(msmcl_rss) / data_bytes},
                                  {"peer_rss_over_data", median(peer_rss) / data_bytes}};
            std::printf("%s: msmcl %.0f ms (%.0f-%.0f), peer %.0f ms (%.0f-%.0f), ratio %.2f (%.2f-%.2f); CPU time ratio %.2f; peak RSS msmcl %.0f MB "
                        "= %.2fx data (%.0f MB), peer %.0f MB = %.2fx\n",
                        format_text.c_str(), median(msmcl_ms), row["msmcl_ms"]["min"].get<double>(),
                        row["msmcl_ms"]["max"].get<double>(), median(peer_ms), row["peer_ms"]["min"].get<double>(),
                        row["peer_ms"]["max"].get<double>(), median(ratios), row["wall_ratio"]["min"].get<double>(),
                        row["wall_ratio"]["max"].get<double>(), median(cpu_ratios), median(msmcl_rss) / 1e6, median(msmcl_rss) / data_bytes,
                        data_bytes / 1e6, median(peer_rss) / 1e6, median(peer_rss) / data_bytes);
            std::fflush(stdout);
            rows.push_back(row);
        }
        std::filesystem::remove_all(work);
        if (!json_path.empty()) std::ofstream(json_path) << rows.dump(2) << '\n';
    } catch (const std::exception& e) {
        std::fprintf(stderr, "msmcl-e2e-bench: %s\n", e.what());
        return 1;
    }
    return 0;
}
