// The batch form of msmcl filter and msmcl sat (docs/batch.md), run as processes:
//  - a batch writes byte for byte what single-file runs write (formats, containers, sat,
//    translucent layers);
//  - --list reads one input per line or a JSON manifest with per-file options;
//  - --shard I/N: the shards of a list are disjoint, cover it and are the same every run;
//  - a bad file among good ones: the others are written, one line names it, exit 2, no
//    output (and no temporary file) for it;
//  - --json: the summary per file; --device all; the progress line on a terminal only,
//    --verbose a line per file.
#include "io/atomic_file.hpp"
#include "io/exr_io.hpp"
#include "cli_folder_test.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using msmcl::testing::CliRun;

class BatchCli : public msmcl::testing::CliFolderTest {
protected:
    /// The names of the files in a folder of the test, sorted.
    std::vector<std::string> files_in(const std::string& folder) const {
        std::vector<std::string> names;
        if (!fs::exists(path(folder))) return names;
        for (const auto& entry : fs::directory_iterator(path(folder))) names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }

    void write_text(const std::string& name, const std::string& text) { std::ofstream(path(name)) << text; }
};

std::string lines(const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& name : names) text += name + "\n";
    return text;
}

TEST_F(BatchCli, FilterBatchWritesTheBytesOfSingleRunsInEveryFormat) {
    const std::vector<std::string> inputs = {write_depth("a.exr", 67, 41, 4), write_depth("b.exr", 32, 32, 1),
                                             write_depth("c.exr", 50, 70, 2)};
    for (const char* format : {"moments128", "msm64", "nlq64", "nlq32"}) {
        SCOPED_TRACE(format);
        const std::string folder = std::string("batch_") + format;
        std::vector<std::string> arguments = {"filter"};
        arguments.insert(arguments.end(), inputs.begin(), inputs.end());
        arguments.insert(arguments.end(), {"-o", folder, "--format", format, "--sigma", "1.7"});
        const CliRun batch = cli(arguments);
        ASSERT_EQ(batch.exit_code, 0) << batch.err;
        EXPECT_NE(batch.err.find("msmcl: filter: 3 files, 3 written, 0 bad input, 0 failed"), std::string::npos)
            << batch.err;
        EXPECT_EQ(files_in(folder), (std::vector<std::string>{"a.exr", "b.exr", "c.exr"}));
        for (const std::string& input : inputs) {
            const std::string single = std::string("single_") + format + "_" + input;
            const CliRun one = cli({"filter", input, single, "--format", format, "--sigma", "1.7"});
            ASSERT_EQ(one.exit_code, 0) << one.err;
            EXPECT_EQ(one.err, "");
            EXPECT_EQ(bytes(folder + "/" + input), bytes(single)) << input;
        }
    }
    // Another container: the derived names take its extension.
    const CliRun ktx = cli({"filter", inputs[0], inputs[1], "-o", "ktx", "--format", "nlq64", "--out-container", "ktx2"});
    ASSERT_EQ(ktx.exit_code, 0) << ktx.err;
    EXPECT_EQ(files_in("ktx"), (std::vector<std::string>{"a.ktx2", "b.ktx2"}));
    ASSERT_EQ(cli({"filter", inputs[0], "single_a.ktx2", "--format", "nlq64"}).exit_code, 0);
    EXPECT_EQ(bytes("ktx/a.ktx2"), bytes("single_a.ktx2"));
}

TEST_F(BatchCli, SatBatchWritesTheBytesOfSingleRuns) {
    // One map with a translucent layer (layer0.Z, layer0.A) among the opaque ones.
    const std::string opaque = write_depth("t_opaque.exr", 36, 28, 2);
    msmcl::io::TranslucentDepth translucent;
    translucent.depth = msmcl::io::read_depth_exr(path(opaque), msmcl::DepthRange::zero_one);
    msmcl::TranslucentLayer layer;
    for (float depth : translucent.depth.depth) {
        layer.depth.push_back(depth * 0.5f);
        layer.opacity.push_back(0.25f + 0.5f * depth);
    }
    translucent.layers.push_back(layer);
    msmcl::io::write_translucent_depth_exr(path("t.exr"), translucent);
    const std::vector<std::string> inputs = {write_depth("p.exr", 45, 33, 4), write_depth("q.exr", 64, 20, 1), "t.exr"};
    const CliRun batch = cli({"sat", inputs[0], inputs[1], inputs[2], "-o", "tables", "--max-kernel", "400"});
    ASSERT_EQ(batch.exit_code, 0) << batch.err;
    const CliRun dds =
        cli({"sat", inputs[0], inputs[1], inputs[2], "-o", "dds", "--max-kernel", "400", "--out-container", "dds"});
    ASSERT_EQ(dds.exit_code, 0) << dds.err;
    for (const std::string& input : inputs) {
        const std::string stem = input.substr(0, input.size() - 4);
        ASSERT_EQ(cli({"sat", input, "one_" + input, "--max-kernel", "400"}).exit_code, 0);
        EXPECT_EQ(bytes("tables/" + input), bytes("one_" + input)) << input;
        ASSERT_EQ(cli({"sat", input, "one_" + stem + ".dds", "--max-kernel", "400"}).exit_code, 0);
        EXPECT_EQ(bytes("dds/" + stem + ".dds"), bytes("one_" + stem + ".dds")) << input;
    }
}

TEST_F(BatchCli, ListTakesLinesOrAManifestWithPerFileOptions) {
    const std::string a = write_depth("a.exr", 40, 30, 4), b = write_depth("b.exr", 24, 24, 1),
                      c = write_depth("c.exr", 33, 17, 1);
    // One input per line; blank lines and # comments are skipped.
    write_text("maps.txt", "# maps\n" + a + "\n\n" + b + "\r\n");
    const CliRun listed = cli({"filter", "--list", "maps.txt", "-o", "listed", "--format", "msm64"});
    ASSERT_EQ(listed.exit_code, 0) << listed.err;
    EXPECT_EQ(files_in("listed"), (std::vector<std::string>{"a.exr", "b.exr"}));
    ASSERT_EQ(cli({"filter", a, "single_a.exr", "--format", "msm64"}).exit_code, 0);
    EXPECT_EQ(bytes("listed/a.exr"), bytes("single_a.exr"));

    // A manifest: per-file format, sigma, output and container; the rest from the command line.
    write_text("maps.json", R"([ ")" + a + R"(",
        {"input": ")" + b + R"(", "format": "nlq32", "sigma": 0.5},
        {"input": ")" + c + R"(", "output": "elsewhere/c_map.ktx2", "sigma": "3", "depth-range": "0,1"} ])");
    const CliRun manifest = cli({"filter", "--list", "maps.json", "-o", "manifest", "--format", "moments128"});
    ASSERT_EQ(manifest.exit_code, 0) << manifest.err;
    EXPECT_EQ(files_in("manifest"), (std::vector<std::string>{"a.exr", "b.exr"}));
    ASSERT_EQ(cli({"filter", a, "s_a.exr", "--format", "moments128"}).exit_code, 0);
    ASSERT_EQ(cli({"filter", b, "s_b.exr", "--format", "nlq32", "--sigma", "0.5"}).exit_code, 0);
    ASSERT_EQ(cli({"filter", c, "s_c.ktx2", "--format", "moments128", "--sigma", "3"}).exit_code, 0);
    EXPECT_EQ(bytes("manifest/a.exr"), bytes("s_a.exr"));
    EXPECT_EQ(bytes("manifest/b.exr"), bytes("s_b.exr"));
    EXPECT_EQ(bytes("elsewhere/c_map.ktx2"), bytes("s_c.ktx2"));

    // "samples" states what a file must hold: a file that holds another count is bad input.
    write_text("samples.json", R"([{"input": ")" + a + R"(", "samples": 4}, {"input": ")" + b + R"(", "samples": 4}])");
    const CliRun samples = cli({"filter", "--list", "samples.json", "-o", "samples", "--format", "msm64"});
    EXPECT_EQ(samples.exit_code, 2) << samples.err;
    EXPECT_NE(samples.err.find("msmcl: b.exr: 1 samples per texel, the manifest says 4"), std::string::npos)
        << samples.err;
    EXPECT_EQ(files_in("samples"), (std::vector<std::string>{"a.exr"}));

    // sat takes its own keys; a key of another command is refused before any work.
    write_text("tables.json", R"([{"input": ")" + a + R"(", "max-kernel": 100}])");
    ASSERT_EQ(cli({"sat", "--list", "tables.json", "-o", "tables"}).exit_code, 0);
    ASSERT_EQ(cli({"sat", a, "one_table.exr", "--max-kernel", "100"}).exit_code, 0);
    EXPECT_EQ(bytes("tables/a.exr"), bytes("one_table.exr"));
    const CliRun wrong_key = cli({"sat", "--list", "maps.json", "-o", "never"});
    EXPECT_EQ(wrong_key.exit_code, 2);
    EXPECT_EQ(wrong_key.err.rfind("msmcl: maps.json: entry 1: unknown key \"format\" for msmcl sat", 0), 0u)
        << wrong_key.err;
    EXPECT_FALSE(fs::exists(path("never")));
}

TEST_F(BatchCli, ListAndOptionMistakesAreRefusedBeforeAnyWork) {
    const std::string a = write_depth("a.exr", 16, 16, 1);
    fs::create_directory(path("sub"));
    const std::string b = "sub/a.exr";
    fs::copy_file(path(a), path(b));
    struct Case {
        std::vector<std::string> arguments;
        std::string message;
    };
    write_text("broken.json", "[ {\"input\": \"a.exr\", ");
    write_text("bad_format.json", R"([{"input": "a.exr", "format": "nlq16"}])");
    const std::vector<Case> cases = {
        {{"filter", a, b, "-o", "out", "--format", "msm64"}, "out/a.exr: written for both a.exr and sub/a.exr"},
        {{"filter", a, "-o", ".", "--format", "msm64"}, "an output would replace the input"},
        {{"filter", "--list", "broken.json", "-o", "out", "--format", "msm64"}, "broken.json: not a valid JSON manifest"},
        {{"filter", "--list", "bad_format.json", "-o", "out"}, "a.exr: unknown --format 'nlq16'"},
        {{"filter", "--list", "missing.txt", "-o", "out", "--format", "msm64"}, "missing.txt: cannot open"},
        {{"filter", a, "-o", "out"}, "--format is required"},
        {{"filter", a, "-o", "out", "--format", "msm64", "--shard", "2/2"}, "--shard must be I/N"},
        {{"filter", a, "-o", "out", "--format", "msm64", "--shard", "x"}, "--shard must be I/N"},
        {{"filter", a, "t.exr", "--format", "msm64", "--json", "-"}, "apply to a batch"},
        {{"filter", a, "t.exr", "u.exr", "--format", "msm64"}, "several inputs only with -o DIR"},
        {{"filter", "-o", "out", "--format", "msm64"}, "needs inputs"},
        {{"--device", "all", "shade", "m.exr", "r.exr", "y.exr"}, "only filter and sat take it"},
    };
    for (const Case& c : cases) {
        std::string command;
        for (const std::string& argument : c.arguments) command += argument + " ";
        SCOPED_TRACE(command);
        const CliRun run = cli(c.arguments);
        EXPECT_EQ(run.exit_code, 2) << run.err;
        EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
        EXPECT_NE(run.err.find(c.message), std::string::npos) << run.err;
        EXPECT_FALSE(fs::exists(path("out")));
        EXPECT_FALSE(fs::exists(path("t.exr")));
    }
}

TEST_F(BatchCli, ShardsAreDisjointCoverTheListAndAreTheSameEveryRun) {
    std::vector<std::string> inputs;
    for (int i = 0; i < 7; ++i) inputs.push_back(write_depth("m" + std::to_string(i) + ".exr", 8, 8, 1));
    write_text("maps.txt", lines(inputs));
    const std::size_t shards = 3;
    std::vector<std::string> union_of_shards;
    for (std::size_t index = 0; index < shards; ++index) {
        const std::string shard = std::to_string(index) + "/" + std::to_string(shards);
        std::vector<std::vector<std::string>> runs;
        for (int repeat = 0; repeat < 2; ++repeat) {
            const CliRun run = cli({"filter", "--list", "maps.txt", "--shard", shard, "-o", "out", "--format", "nlq32",
                                 "--json", "-"});
            ASSERT_EQ(run.exit_code, 0) << run.err;
            const json summary = json::parse(run.out);
            EXPECT_EQ(summary["shard"], shard);
            std::vector<std::string> taken;
            for (const json& file : summary["files"]) taken.push_back(file["input"].get<std::string>());
            runs.push_back(taken);
        }
        // The rule: positions p with p % N == I, in list order; the same on every run.
        std::vector<std::string> expected;
        for (std::size_t p = index; p < inputs.size(); p += shards) expected.push_back(inputs[p]);
        EXPECT_EQ(runs[0], expected) << shard;
        EXPECT_EQ(runs[1], runs[0]) << shard;
        union_of_shards.insert(union_of_shards.end(), runs[0].begin(), runs[0].end());
    }
    // Disjoint and complete: every input exactly once over the shards, every output written.
    std::sort(union_of_shards.begin(), union_of_shards.end());
    std::vector<std::string> all = inputs;
    std::sort(all.begin(), all.end());
    EXPECT_EQ(union_of_shards, all);
    EXPECT_EQ(files_in("out"), all);
    // More shards than files: the empty ones succeed with nothing to do.
    const CliRun empty = cli({"filter", "--list", "maps.txt", "--shard", "9/10", "-o", "more", "--format", "nlq32"});
    EXPECT_EQ(empty.exit_code, 0) << empty.err;
    EXPECT_NE(empty.err.find("msmcl: filter: 0 files, 0 written"), std::string::npos) << empty.err;
}

TEST_F(BatchCli, ABadFileIsReportedAndSkippedAndTheOthersAreWritten) {
    const std::string good1 = write_depth("good1.exr", 40, 40, 4), good2 = write_depth("good2.exr", 30, 20, 4);
    // A truncated file, a file without a depth channel, a missing file.
    const std::string whole = bytes(write_depth("whole.exr", 64, 64, 4));
    write_text("truncated.exr", whole.substr(0, whole.size() / 2));
    msmcl::io::ExrImage no_depth;
    no_depth.width = no_depth.height = 8;
    no_depth.channels.push_back({"Y", msmcl::io::SampleType::float32, std::vector<float>(64, 0.5f), {}, 1, 1});
    msmcl::io::write_exr(path("no_depth.exr"), no_depth);
    write_text("maps.txt", lines({good1, "truncated.exr", "no_depth.exr", "missing.exr", good2}));
    const CliRun run = cli({"filter", "--list", "maps.txt", "-o", "out", "--format", "msm64", "--json", "summary.json"});
    EXPECT_EQ(run.exit_code, 2) << run.err;
    // One line per bad file, naming it, then the summary line.
    for (const char* bad : {"truncated.exr", "no_depth.exr", "missing.exr"})
        EXPECT_NE(run.err.find(std::string("msmcl: ") + bad + ": "), std::string::npos) << bad << "\n" << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 4) << run.err;
    EXPECT_NE(run.err.find("msmcl: filter: 5 files, 2 written, 3 bad input, 0 failed"), std::string::npos) << run.err;
    // The good files are written as alone; nothing else in the folder (no temporary files).
    EXPECT_EQ(files_in("out"), (std::vector<std::string>{"good1.exr", "good2.exr"}));
    for (const std::string& good : {good1, good2}) {
        ASSERT_EQ(cli({"filter", good, "one_" + good, "--format", "msm64"}).exit_code, 0);
        EXPECT_EQ(bytes("out/" + good), bytes("one_" + good));
    }
    const json summary = json::parse(bytes("summary.json"));
    ASSERT_EQ(summary["files"].size(), 5u);
    EXPECT_EQ(summary["files"][1]["status"], "bad_input");
    EXPECT_EQ(summary["files"][1]["error"].get<std::string>().rfind("truncated.exr: ", 0), 0u);
    EXPECT_EQ(summary["files"][2]["status"], "bad_input");
    EXPECT_EQ(summary["files"][3]["status"], "bad_input");
}

TEST_F(BatchCli, JsonSummaryDescribesEveryFile) {
    const std::vector<std::string> inputs = {write_depth("a.exr", 40, 40, 4), write_depth("b.exr", 20, 30, 1)};
    const CliRun run = cli({"sat", inputs[0], "missing.exr", inputs[1], "-o", "out", "--json", "summary.json"});
    EXPECT_EQ(run.exit_code, 2) << run.err;
    const json summary = json::parse(bytes("summary.json"));
    EXPECT_EQ(summary["schema"], "msmcl-batch/1");
    EXPECT_EQ(summary["command"], "sat");
    EXPECT_EQ(summary["shard"], "0/1");
    EXPECT_EQ(summary["written"], 2);
    EXPECT_EQ(summary["bad_input"], 1);
    EXPECT_EQ(summary["failed"], 0);
    ASSERT_EQ(summary["files"].size(), 3u);
    const std::vector<std::string> listed = {inputs[0], "missing.exr", inputs[1]};
    for (std::size_t i = 0; i < listed.size(); ++i) {
        const json& file = summary["files"][i];
        SCOPED_TRACE(listed[i]);
        EXPECT_EQ(file["input"], listed[i]);
        EXPECT_EQ(file["output"], "out/" + listed[i]);
        EXPECT_GE(file["ms"].get<double>(), 0.0);
        if (i == 1) {
            EXPECT_EQ(file["status"], "bad_input");
            EXPECT_EQ(file["error"].get<std::string>().rfind("missing.exr: cannot open", 0), 0u) << file["error"];
            EXPECT_EQ(file["output_bytes"], 0);
        } else {
            EXPECT_EQ(file["status"], "written");
            EXPECT_TRUE(file["error"].is_null());
            EXPECT_EQ(file["input_bytes"].get<std::uintmax_t>(), fs::file_size(path(listed[i])));
            EXPECT_EQ(file["output_bytes"].get<std::uintmax_t>(), fs::file_size(path("out/" + listed[i])));
            EXPECT_FALSE(file["device"].get<std::string>().empty());
        }
    }
}

TEST_F(BatchCli, DeviceAllSpreadsTheFilesOverEveryDevice) {
    std::vector<std::string> inputs;
    for (int i = 0; i < 4; ++i) inputs.push_back(write_depth("d" + std::to_string(i) + ".exr", 24, 24, 4));
    std::vector<std::string> arguments = {"--device", "all", "filter"};
    arguments.insert(arguments.end(), inputs.begin(), inputs.end());
    arguments.insert(arguments.end(), {"-o", "out", "--format", "nlq64", "--json", "-"});
    const CliRun run = cli(arguments);
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const json summary = json::parse(run.out);
    const std::vector<msmcl::DeviceInfo> devices = msmcl::list_devices();
    EXPECT_EQ(summary["devices"].get<std::size_t>(), devices.size());
    // File p goes to device p % D; with one device (PoCL) the bytes are the default device's.
    for (std::size_t p = 0; p < inputs.size(); ++p)
        EXPECT_EQ(summary["files"][p]["device"], devices[p % devices.size()].name) << inputs[p];
    if (devices.size() == 1)
        for (const std::string& input : inputs) {
            ASSERT_EQ(cli({"filter", input, "one_" + input, "--format", "nlq64"}).exit_code, 0);
            EXPECT_EQ(bytes("out/" + input), bytes("one_" + input));
        }
}

TEST_F(BatchCli, DeviceAllOnTwoDevicesGivesTheSingleDeviceBytes) {
    // PoCL makes two CPU devices of one machine when POCL_DEVICES names its driver twice: a
    // real two-device batch (two contexts, two queues, files alternating) on any CI machine.
    const std::vector<msmcl::DeviceInfo> devices = msmcl::list_devices();
    if (devices.empty() || devices.front().platform_name.find("Portable Computing Language") == std::string::npos)
        GTEST_SKIP() << "two devices are made with PoCL's POCL_DEVICES; the first platform is "
                     << (devices.empty() ? "none" : devices.front().platform_name);
    std::vector<std::string> environment;
    for (char** variable = environ; *variable; ++variable)
        if (std::string(*variable).rfind("POCL_DEVICES=", 0) != 0) environment.emplace_back(*variable);
    environment.emplace_back("POCL_DEVICES=pthread pthread");
    const CliRun listed = cli({"devices"}, &environment);
    ASSERT_EQ(listed.exit_code, 0) << listed.err;
    if (std::count(listed.out.begin(), listed.out.end(), '\n') < 2)
        GTEST_SKIP() << "this PoCL does not make two devices: " << listed.out;

    std::vector<std::string> inputs;
    for (int i = 0; i < 6; ++i) inputs.push_back(write_depth("d" + std::to_string(i) + ".exr", 40 + 8 * i, 24, 4));
    for (const char* command : {"filter", "sat"}) {
        std::vector<std::string> arguments = {"--device", "all", command};
        arguments.insert(arguments.end(), inputs.begin(), inputs.end());
        arguments.insert(arguments.end(), {"-o", std::string("all_") + command, "--json", "-"});
        if (std::string(command) == "filter") arguments.insert(arguments.end(), {"--format", "nlq32"});
        else arguments.insert(arguments.end(), {"--max-kernel", "64"});
        const CliRun run = cli(arguments, &environment);
        ASSERT_EQ(run.exit_code, 0) << run.err;
        const json summary = json::parse(run.out);
        EXPECT_EQ(summary["devices"], 2) << run.out;
        EXPECT_EQ(summary["written"], inputs.size()) << run.out;
        // Each output equals the single-file run's on the default device, byte for byte.
        for (const std::string& input : inputs) {
            std::vector<std::string> single = {command, input, std::string("one_") + command + "_" + input};
            if (std::string(command) == "filter") single.insert(single.end(), {"--format", "nlq32"});
            else single.insert(single.end(), {"--max-kernel", "64"});
            ASSERT_EQ(cli(single).exit_code, 0) << input;
            EXPECT_EQ(bytes(std::string("all_") + command + "/" + input), bytes(std::string("one_") + command + "_" + input))
                << command << " " << input;
        }
    }
}

TEST_F(BatchCli, ProgressShowsFilesOnATerminalOnly) {
    const std::string a = write_depth("a.exr", 32, 32, 4), b = write_depth("b.exr", 32, 32, 4);
    const auto [terminal, code] = msmcl::testing::run_on_terminal(
        {MSMCL_CLI_PATH, "filter", path(a), path(b), "-o", path("tty"), "--format", "msm64"},
        "MSMCL_PROGRESS_AFTER_MS=0");
    ASSERT_EQ(code, 0) << terminal;
    EXPECT_NE(terminal.find("msmcl: filter ["), std::string::npos) << terminal;
    EXPECT_NE(terminal.find("/2 files"), std::string::npos) << terminal;
    EXPECT_NE(terminal.find("MB/s"), std::string::npos) << terminal;
    // Erased before the summary line, which is the last thing written.
    EXPECT_NE(terminal.find("\r\033[Kmsmcl: filter: 2 files, 2 written"), std::string::npos) << terminal;
    // Into a file: only the summary line.
    const CliRun file = cli({"filter", a, b, "-o", "file", "--format", "msm64"});
    ASSERT_EQ(file.exit_code, 0);
    EXPECT_EQ(file.err.find('\r'), std::string::npos) << file.err;
    EXPECT_EQ(std::count(file.err.begin(), file.err.end(), '\n'), 1) << file.err;
    EXPECT_EQ(bytes("file/a.exr"), bytes("tty/a.exr"));
    // --verbose: a line per written file (its read, device and write times), then the summary.
    const CliRun verbose = cli({"--verbose", "filter", a, b, "-o", "verbose", "--format", "msm64"});
    ASSERT_EQ(verbose.exit_code, 0) << verbose.err;
    EXPECT_EQ(std::count(verbose.err.begin(), verbose.err.end(), '\n'), 3) << verbose.err;
    for (const std::string& input : {a, b})
        EXPECT_NE(verbose.err.find("msmcl: " + input + " -> verbose/" + input + ": read "), std::string::npos)
            << verbose.err;
    EXPECT_EQ(bytes("verbose/a.exr"), bytes("tty/a.exr"));
}

} // namespace
