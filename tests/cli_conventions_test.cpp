// Command-line conventions of msmcl, run as processes: an unknown subcommand, option or option
// value is named with a "did you mean" suggestion (exit 2, one line); a bare `msmcl` prints
// the usage and the commands (exit 2); -v/--verbose prints a timing line per stage and
// changes no output byte; -q/--quiet leaves only errors on stderr; the progress line appears
// on a terminal only (a pseudo-terminal the test opens with forkpty), never in a pipe or
// file; `msmcl --help` ends with the table of every environment variable msmcl reads.
#include "io/atomic_file.hpp"
#include "process.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <cerrno>
#include <sys/wait.h>
#include <unistd.h>
#include <utility>
#include <vector>

#ifndef MSMCL_CLI_PATH
#define MSMCL_CLI_PATH ""
#endif

namespace {

namespace fs = std::filesystem;

bool have_device() {
    try {
        return !msmcl::list_devices().empty();
    } catch (const msmcl::error&) {
        return false;
    }
}

class CliConventions : public ::testing::Test {
protected:
    void SetUp() override {
        if (std::string(MSMCL_CLI_PATH).empty()) GTEST_SKIP() << "built without the msmcl CLI";
        directory_ = fs::temp_directory_path() / ("msmcl-conventions-" + std::to_string(::getpid()));
        fs::create_directories(directory_);
    }
    void TearDown() override {
        if (!directory_.empty()) fs::remove_all(directory_);
    }
    std::string path(const std::string& name) const { return (directory_ / name).string(); }
    std::string q(const std::string& name) const { return "'" + path(name) + "'"; }
    static std::string data(const std::string& name) { return "'" + std::string(MSMCL_SOURCE_DIR) + "/data/" + name + "'"; }
    // Runs `msmcl <arguments>` with stdout and stderr in files; the exit code (-1: signal).
    int cli(const std::string& arguments, const std::string& environment = "") {
        const int status = std::system((environment + " '" + MSMCL_CLI_PATH + "' " + arguments + " >" + q("stdout.txt") +
                                        " 2>" + q("stderr.txt"))
                                           .c_str());
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    std::string out() const { return msmcl::io::read_whole_file(path("stdout.txt")); }
    std::string err() const { return msmcl::io::read_whole_file(path("stderr.txt")); }
    // Exit 2 and exactly the one line `expected` on stderr.
    void expect_usage(const std::string& arguments, const std::string& expected) {
        SCOPED_TRACE(arguments);
        EXPECT_EQ(cli(arguments), 2);
        EXPECT_EQ(err(), "msmcl: " + expected + "\n");
    }

    fs::path directory_;
};

TEST_F(CliConventions, UnknownWordsAreNamedWithASuggestion) {
    expect_usage("fitler a.exr b.exr --format nlq64", "unknown command 'fitler' (did you mean 'filter'?)");
    expect_usage("shdae", "unknown command 'shdae' (did you mean 'shade'?)");
    // Nothing near: the list of commands.
    EXPECT_EQ(cli("frobnicate"), 2);
    const std::string message = err();
    EXPECT_EQ(message.rfind("msmcl: unknown command 'frobnicate' (commands: filter, shade, ", 0), 0u) << message;
    EXPECT_NE(message.find("info"), std::string::npos) << message;
    EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 1);
    // Options of the subcommand, global options before and after it, values skipped.
    expect_usage("filter a.exr b.exr --fromat nlq64", "unknown option '--fromat' for msmcl filter (did you mean '--format'?)");
    expect_usage("--devcie cpu devices", "unknown option '--devcie' for msmcl (did you mean '--device'?)");
    expect_usage("--device cpu shade m.exr r.exr y.exr --lokup nearest",
                 "unknown option '--lokup' for msmcl shade (did you mean '--lookup'?)");
    expect_usage("filter a.exr b.exr --format nlq64 --depth-range -1,1 --sigam 2",
                 "unknown option '--sigam' for msmcl filter (did you mean '--sigma'?)");
    expect_usage("sat a.exr b.exr --max-kernal=100", "unknown option '--max-kernal' for msmcl sat (did you mean '--max-kernel'?)");
    expect_usage("filter a.exr b.exr --format nlq64 --qqqqqqqq", "unknown option '--qqqqqqqq' for msmcl filter");
    // Known words still get CLI11's own messages.
    expect_usage("filter a.exr b.exr", "--format is required");
}

TEST_F(CliConventions, MistypedValuesAreNamedWithTheNearestValue) {
    expect_usage("shade m.exr r.exr y.exr --lookup bilnear",
                 "unknown --lookup 'bilnear' (did you mean 'bilinear'? expected nearest, bilinear or dither)");
    expect_usage("filter a.exr b.exr --format nlq46",
                 "unknown --format 'nlq46' (did you mean 'nlq64'? expected moments128, msm64, nlq64, nlq32, vsm32, "
                 "vsm64, evsm2_32, evsm4_64, evsm4_128 or esm32)");
    expect_usage("filter a.exr b.exr --format msm64 --kernel fused_gpu",
                 "unknown --kernel 'fused_gpu' (did you mean 'fused_cpu'? expected automatic, fused_paper, fused_cpu "
                 "or three_pass)");
    expect_usage("filter a.exr b.exr --format msm64 --out-container kxt2",
                 "unknown --out-container 'kxt2' (did you mean 'ktx2'? expected exr, ktx2 or dds)");
    // Nothing near: the valid values alone.
    expect_usage("shade m.exr r.exr y.exr --lookup cubic", "unknown --lookup 'cubic' (expected nearest, bilinear or dither)");
}

TEST_F(CliConventions, BareMsmclPrintsTheUsageAndTheCommands) {
    for (const char* arguments : {"", "--device cpu", "-q"}) {
        SCOPED_TRACE(arguments);
        EXPECT_EQ(cli(arguments), 2);
        const std::string usage = err();
        EXPECT_EQ(usage.rfind("usage: msmcl [OPTIONS] COMMAND", 0), 0u) << usage;
        for (const char* command : {"filter", "shade", "sat", "soft", "scatter", "devices", "info"})
            EXPECT_NE(usage.find(std::string("\n  ") + command + " "), std::string::npos) << command << "\n" << usage;
        EXPECT_EQ(out(), "");
    }
    EXPECT_EQ(cli("-q -v devices"), 2); // quiet and verbose exclude each other
}

// The table closing `msmcl --help` (and so the man page) and docs/environment.md name every
// MSMCL_* variable that host/ reads (getenv, or its wrappers environment and environment_limit).
TEST_F(CliConventions, EnvironmentTableNamesEveryVariable) {
    ASSERT_EQ(cli("--help"), 0) << err();
    const std::string help = out();
    const std::string environment = help.substr(std::min(help.find("\nEnvironment:\n"), help.size()));
    ASSERT_FALSE(environment.empty()) << help;
    const std::string docs = msmcl::io::read_whole_file(std::string(MSMCL_SOURCE_DIR) + "/docs/environment.md");
    const std::regex read_call(R"re((getenv|environment|environment_limit)\("(MSMCL_[A-Z_]+)")re");
    std::set<std::string> names;
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(fs::path(MSMCL_SOURCE_DIR) / "host")) {
        if (!entry.is_regular_file()) continue;
        const std::string text = msmcl::io::read_whole_file(entry.path().string());
        for (auto match = std::sregex_iterator(text.begin(), text.end(), read_call); match != std::sregex_iterator(); ++match)
            names.insert((*match)[2]);
    }
    for (const char* known : {"MSMCL_DEVICE", "MSMCL_PLATFORM", "MSMCL_STRICT", "MSMCL_CACHE_DIR", "MSMCL_MAX_TEXELS",
                              "MSMCL_MAX_BYTES", "MSMCL_CPU_TILE", "MSMCL_PROGRESS_AFTER_MS"})
        EXPECT_EQ(names.count(known), 1u) << known << ": the source scan missed it";
    for (const std::string& name : names) {
        EXPECT_NE(environment.find("\n  " + name + " "), std::string::npos) << name << " missing from --help:\n" << help;
        EXPECT_NE(docs.find("| `" + name + "` |"), std::string::npos) << name << " missing from docs/environment.md";
    }
}

TEST_F(CliConventions, VerbosePrintsATimingLinePerStageAndChangesNoByte) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    const std::string depth = data("railing_256x256_4x.exr"), view = data("railing_view_160x120.exr");
    ASSERT_EQ(cli("filter " + depth + " " + q("quiet.exr") + " --format nlq32"), 0) << err();
    EXPECT_EQ(err(), ""); // not a terminal: no progress, no timing
    ASSERT_EQ(cli("--verbose filter " + depth + " " + q("verbose.exr") + " --format nlq32"), 0) << err();
    const std::string filter_log = err();
    EXPECT_EQ(out(), "");
    EXPECT_EQ(msmcl::io::read_whole_file(path("verbose.exr")), msmcl::io::read_whole_file(path("quiet.exr")));
    for (const char* stage : {"read", "device setup", "program", "upload", "kernel", "download", "write"})
        EXPECT_NE(filter_log.find(std::string("msmcl: ") + stage + ": "), std::string::npos) << stage << "\n" << filter_log;
    EXPECT_EQ(std::count(filter_log.begin(), filter_log.end(), '\n'), 7) << filter_log;
    // The program stage says whether it built or found the program.
    EXPECT_TRUE(filter_log.find("cache hit") != std::string::npos || filter_log.find("built") != std::string::npos)
        << filter_log;

    ASSERT_EQ(cli("shade " + q("quiet.exr") + " " + view + " " + q("y_quiet.exr")), 0) << err();
    ASSERT_EQ(cli("shade " + q("quiet.exr") + " " + view + " " + q("y_verbose.exr") + " --verbose"), 0) << err();
    const std::string shade_log = err();
    EXPECT_EQ(msmcl::io::read_whole_file(path("y_verbose.exr")), msmcl::io::read_whole_file(path("y_quiet.exr")));
    for (const char* stage : {"read map", "read receivers", "device setup", "program", "upload", "kernel", "download",
                              "write"})
        EXPECT_NE(shade_log.find(std::string("msmcl: ") + stage + ": "), std::string::npos) << stage << "\n" << shade_log;

    ASSERT_EQ(cli("sat " + depth + " " + q("sat_quiet.exr")), 0) << err();
    ASSERT_EQ(cli("sat " + depth + " " + q("sat.exr") + " -v"), 0) << err(); // -v is --verbose
    const std::string sat_log = err();
    EXPECT_EQ(msmcl::io::read_whole_file(path("sat.exr")), msmcl::io::read_whole_file(path("sat_quiet.exr")));
    for (const char* stage : {"read", "device setup", "program", "upload", "kernel", "download", "write"})
        EXPECT_NE(sat_log.find(std::string("msmcl: ") + stage + ": "), std::string::npos) << stage << "\n" << sat_log;

    ASSERT_EQ(cli("soft " + q("sat.exr") + " " + view + " " + q("s_quiet.exr") + " --light-size 8"), 0) << err();
    ASSERT_EQ(cli("soft " + q("sat.exr") + " " + view + " " + q("s_verbose.exr") + " --light-size 8 --verbose"), 0)
        << err();
    const std::string soft_log = err();
    EXPECT_EQ(msmcl::io::read_whole_file(path("s_verbose.exr")), msmcl::io::read_whole_file(path("s_quiet.exr")));
    for (const char* stage : {"read table", "read receivers", "device setup", "program", "upload", "kernel",
                              "download", "write"})
        EXPECT_NE(soft_log.find(std::string("msmcl: ") + stage + ": "), std::string::npos) << stage << "\n" << soft_log;
}

TEST_F(CliConventions, ProgressOnlyOnATerminal) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    const std::string depth = std::string(MSMCL_SOURCE_DIR) + "/data/railing_256x256_4x.exr";
    // On a pseudo-terminal, with the delay set to 0: the bar is drawn, then erased.
    const auto [terminal, code] = msmcl::testing::run_on_terminal(
        {MSMCL_CLI_PATH, "filter", depth, path("tty.exr"), "--format", "msm64"}, "MSMCL_PROGRESS_AFTER_MS=0");
    ASSERT_EQ(code, 0) << terminal;
    EXPECT_NE(terminal.find("msmcl: ["), std::string::npos) << terminal;
    ASSERT_GE(terminal.size(), 4u);
    EXPECT_EQ(terminal.substr(terminal.size() - 4), "\r\033[K") << terminal;
    EXPECT_TRUE(fs::exists(path("tty.exr")));
    // The same into a file: nothing at all.
    ASSERT_EQ(cli("filter " + depth + " " + q("file.exr") + " --format msm64", "MSMCL_PROGRESS_AFTER_MS=0"), 0);
    EXPECT_EQ(err(), "");
    EXPECT_EQ(msmcl::io::read_whole_file(path("file.exr")), msmcl::io::read_whole_file(path("tty.exr")));
}

TEST_F(CliConventions, QuietLeavesOnlyErrorsOnStderr) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    const std::string depth = std::string(MSMCL_SOURCE_DIR) + "/data/railing_256x256_4x.exr";
    // On a terminal: no progress line.
    const auto [terminal, code] = msmcl::testing::run_on_terminal(
        {MSMCL_CLI_PATH, "-q", "filter", depth, path("tty.exr"), "--format", "msm64"}, "MSMCL_PROGRESS_AFTER_MS=0");
    ASSERT_EQ(code, 0) << terminal;
    EXPECT_EQ(terminal, "");
    // A batch: no summary line, but each bad file still named; the same bytes as without -q.
    ASSERT_EQ(cli("filter '" + depth + "' -o " + q("loud") + " --format msm64"), 0) << err();
    EXPECT_NE(err().find("msmcl: filter: 1 file"), std::string::npos) << err();
    ASSERT_EQ(cli("--quiet filter '" + depth + "' -o " + q("quiet") + " --format msm64"), 0) << err();
    EXPECT_EQ(err(), "");
    EXPECT_EQ(msmcl::io::read_whole_file(path("quiet/railing_256x256_4x.exr")),
              msmcl::io::read_whole_file(path("loud/railing_256x256_4x.exr")));
    EXPECT_EQ(cli("filter '" + depth + "' " + q("missing.exr") + " -o " + q("quiet") + " --format msm64 -q"), 2);
    const std::string errors = err();
    EXPECT_NE(errors.find(path("missing.exr") + ": cannot open"), std::string::npos) << errors;
    EXPECT_EQ(std::count(errors.begin(), errors.end(), '\n'), 1) << errors;
}

} // namespace
