// `msmcl` under faults, run as a child process: a signal while the output is written, an
// output folder it cannot write, a full disk (the file size limit of the child), a damaged
// binary cache, a map too large for the device, and a driver that cannot write its own
// files. Each ends with the documented exit code, one clear line, and no output or
// temporary file left behind.
#include "io/atomic_file.hpp"
#include "io/exr_io.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

extern char** environ;

namespace {

namespace fs = std::filesystem;

#ifdef MSMCL_CLI_PATH
const std::string cli_path = MSMCL_CLI_PATH;
#else
const std::string cli_path;
#endif
const std::string railing = MSMCL_SOURCE_DIR "/data/railing_256x256_4x.exr";

struct ProcessResult {
    int exit_code = -1;   ///< -1 when ended by a signal
    int signal = 0;       ///< the signal that ended it, else 0
    std::string err;
};

/// How a child runs besides its arguments.
struct ChildSetup {
    std::map<std::string, std::string> environment; ///< added or replaced variables
    std::vector<std::string> unset;                 ///< removed variables
    rlim_t file_size_limit = RLIM_INFINITY;         ///< RLIMIT_FSIZE (ulimit -f) of the child
};

bool have_device() {
    try {
        return !msmcl::list_devices().empty();
    } catch (const msmcl::error&) {
        return false;
    }
}

bool default_device_is_pocl() {
    try {
        const msmcl::Context context;
        return context.device().platform_name.find("Portable Computing Language") != std::string::npos;
    } catch (const msmcl::error&) {
        return false;
    }
}

/// The full path of `program` on PATH, else empty.
std::string find_program(const std::string& program) {
    const char* path = std::getenv("PATH");
    std::string directories = path ? path : "/usr/bin:/bin";
    for (std::size_t start = 0; start <= directories.size();) {
        const std::size_t end = std::min(directories.find(':', start), directories.size());
        const std::string candidate = directories.substr(start, end - start) + "/" + program;
        if (::access(candidate.c_str(), X_OK) == 0) return candidate;
        start = end + 1;
    }
    return {};
}

class Faults : public ::testing::Test {
protected:
    void SetUp() override {
        if (cli_path.empty()) GTEST_SKIP() << "built without the msmcl CLI (MSMCL_BUILD_TOOLS=OFF)";
        if (!have_device()) GTEST_SKIP() << "no OpenCL device";
        std::string pattern = (fs::temp_directory_path() / "msmcl-faults-test-XXXXXX").string();
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        root_ = pattern;
        fs::create_directory(root_ / "out");
    }
    void TearDown() override {
        if (!root_.empty()) {
            std::error_code ignored;
            fs::permissions(root_ / "out", fs::perms::owner_all, ignored);
            fs::remove_all(root_, ignored);
        }
    }

    std::string out(const std::string& name) const { return (root_ / "out" / name).string(); }
    std::vector<std::string> outputs() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(root_ / "out")) names.push_back(entry.path().filename().string());
        return names;
    }
    std::string left_behind() const {
        std::string text;
        for (const std::string& name : outputs()) text += " " + name;
        return text;
    }

    /// Runs `arguments` (no shell) with stderr captured, stdout discarded.
    ProcessResult run(std::vector<std::string> arguments, const ChildSetup& setup = {}) {
        const std::string err_log = (root_ / "stderr.log").string();
        // Everything the child needs is prepared before fork: after it, only system calls.
        std::map<std::string, std::string> variables;
        for (char** entry = environ; *entry; ++entry) {
            const std::string text = *entry;
            const std::size_t equals = text.find('=');
            if (equals != std::string::npos) variables[text.substr(0, equals)] = text.substr(equals + 1);
        }
        for (const std::string& name : setup.unset) variables.erase(name);
        for (const auto& [name, value] : setup.environment) variables[name] = value;
        std::vector<std::string> environment_text;
        for (const auto& [name, value] : variables) environment_text.push_back(name + "=" + value);
        std::vector<char*> envp, argv;
        for (std::string& text : environment_text) envp.push_back(text.data());
        envp.push_back(nullptr);
        for (std::string& argument : arguments) argv.push_back(argument.data());
        argv.push_back(nullptr);
        const rlimit limit{setup.file_size_limit, setup.file_size_limit};

        const pid_t pid = ::fork();
        if (pid == 0) {
            const int err = ::open(err_log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            const int null = ::open("/dev/null", O_WRONLY);
            if (err < 0 || null < 0 || ::dup2(null, 1) < 0 || ::dup2(err, 2) < 0) ::_exit(126);
            if (setup.file_size_limit != RLIM_INFINITY && ::setrlimit(RLIMIT_FSIZE, &limit) != 0) ::_exit(126);
            ::execve(argv[0], argv.data(), envp.data());
            ::_exit(127);
        }
        ProcessResult result;
        if (pid < 0) {
            ADD_FAILURE() << "fork failed";
            return result;
        }
        int status = 0;
        ::waitpid(pid, &status, 0);
        result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        result.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
        result.err = msmcl::io::read_whole_file(err_log);
        return result;
    }
    ProcessResult msmcl_cli(std::vector<std::string> arguments, const ChildSetup& setup = {}) {
        arguments.insert(arguments.begin(), cli_path);
        return run(std::move(arguments), setup);
    }

    /// One line "msmcl: ...<problem>..." on stderr.
    static void expect_one_line(const ProcessResult& result, const std::string& problem) {
        EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
        EXPECT_EQ(result.err.rfind("msmcl: ", 0), 0u) << result.err;
        EXPECT_NE(result.err.find(problem), std::string::npos) << result.err << "  expected: " << problem;
    }

    fs::path root_;
};

TEST_F(Faults, SignalWhileWritingTheOutputLeavesNoTemporaryFile) {
    const std::string strace = find_program("strace");
    if (strace.empty()) GTEST_SKIP() << "strace is not installed (scripts/install-deps.sh installs it)";
    if (run({strace, "-o", "/dev/null", "/bin/true"}).exit_code != 0)
        GTEST_SKIP() << "strace cannot trace here (ptrace not permitted)";
    // A first run fills a binary cache, so that the traced run compiles nothing.
    ChildSetup cached;
    cached.environment["MSMCL_CACHE_DIR"] = (root_ / "cache").string();
    ASSERT_EQ(msmcl_cli({"filter", railing, out("warm.exr"), "--format", "moments128"}, cached).exit_code, 0);
    fs::remove(out("warm.exr"));
    const std::string trace = (root_ / "strace.log").string();
    for (const char* signal_name : {"INT", "TERM"}) {
        SCOPED_TRACE(signal_name);
        // strace delivers the signal at the first fsync, which its log (-y: file names)
        // shows to be the one of the output's temporary file: the file is complete then.
        std::vector<std::string> arguments{strace, "-f", "-qq", "-y", "-o", trace, "-e", "trace=fsync", "-e",
                                           std::string("inject=fsync:signal=") + signal_name + ":when=1",
                                           cli_path, "filter", railing, out("t.exr"), "--format", "moments128"};
        const ProcessResult result = run(arguments, cached);
        EXPECT_EQ(result.signal, std::string(signal_name) == "INT" ? SIGINT : SIGTERM)
            << "exit " << result.exit_code << ": " << result.err;
        const std::string log = msmcl::io::read_whole_file(trace);
        EXPECT_NE(log.find("/.msmcl-"), std::string::npos) << log;
        EXPECT_TRUE(outputs().empty()) << "left behind:" << left_behind();
    }
}

TEST_F(Faults, UnwritableOutputFolderIsBadInputAndWritesNothing) {
    const std::string file_as_folder = (root_ / "plain").string();
    std::ofstream(file_as_folder) << "a file, not a folder\n";
    const struct {
        std::string output, problem;
    } cases[] = {{(root_ / "missing" / "t.exr").string(), "cannot write: No such file or directory"},
                 {file_as_folder + "/t.exr", "cannot write: Not a directory"}};
    for (const auto& c : cases) {
        SCOPED_TRACE(c.output);
        const ProcessResult result = msmcl_cli({"filter", railing, c.output, "--format", "nlq32"});
        EXPECT_EQ(result.exit_code, 2) << result.err;
        expect_one_line(result, c.output + ": " + c.problem);
    }
    // Permissions do not stop root; the check runs for other users.
    if (::geteuid() != 0) {
        fs::permissions(root_ / "out", fs::perms::owner_read | fs::perms::owner_exec);
        const ProcessResult result = msmcl_cli({"filter", railing, out("t.exr"), "--format", "nlq32"});
        EXPECT_EQ(result.exit_code, 2) << result.err;
        expect_one_line(result, "cannot write: Permission denied");
        fs::permissions(root_ / "out", fs::perms::owner_all);
    }
    EXPECT_TRUE(outputs().empty()) << "left behind:" << left_behind();
}

TEST_F(Faults, FullDiskIsARuntimeFailureAndLeavesNothing) {
    // A binary cache filled first: the limited run compiles nothing (PoCL writes every
    // source it compiles to a file, which the limit would stop).
    ChildSetup full;
    full.environment["MSMCL_CACHE_DIR"] = (root_ / "cache").string();
    ASSERT_EQ(msmcl_cli({"filter", railing, out("warm.exr"), "--format", "moments128"}, full).exit_code, 0);
    fs::remove(out("warm.exr"));
    // 64 KiB of file size (ulimit -f): the 1 MiB of moments128 texels do not fit.
    full.file_size_limit = 64 * 1024;
    for (const char* name : {"t.exr", "t.ktx2", "t.dds"}) {
        SCOPED_TRACE(name);
        const ProcessResult result = msmcl_cli({"filter", railing, out(name), "--format", "moments128"}, full);
        EXPECT_EQ(result.exit_code, 1) << result.err;
        expect_one_line(result, out(name) + ": cannot write: File too large");
        EXPECT_TRUE(outputs().empty()) << "left behind:" << left_behind();
    }
}

TEST_F(Faults, DamagedBinaryCacheIsRebuiltAndAnUnusableOneRefused) {
    // MSMCL_CACHE_DIR is created when missing, then filled.
    const fs::path cache = root_ / "cache" / "msmcl";
    ChildSetup cached;
    cached.environment["MSMCL_CACHE_DIR"] = cache.string();
    ASSERT_EQ(msmcl_cli({"filter", railing, out("first.exr"), "--format", "nlq64"}, cached).exit_code, 0);
    std::vector<fs::path> binaries;
    for (const auto& entry : fs::directory_iterator(cache))
        if (entry.path().extension() == ".bin") binaries.push_back(entry.path());
    ASSERT_FALSE(binaries.empty()) << "nothing cached in " << cache;
    const std::string first = msmcl::io::read_whole_file(out("first.exr"));

    // Every kind of damage: cut short, bytes flipped, emptied, another file's content.
    const auto damage = [&](int kind) {
        for (const fs::path& binary : binaries) {
            std::string bytes = msmcl::io::read_whole_file(binary.string());
            if (kind == 0) bytes.resize(bytes.size() / 2);
            if (kind == 1)
                for (std::size_t i = 0; i < bytes.size(); i += 97) bytes[i] = static_cast<char>(~bytes[i]);
            if (kind == 2) bytes.clear();
            if (kind == 3) bytes = "\x7f" "ELF not a program binary at all";
            std::ofstream(binary, std::ios::binary | std::ios::trunc) << bytes;
        }
    };
    for (int kind = 0; kind < 4; ++kind) {
        SCOPED_TRACE("damage " + std::to_string(kind));
        damage(kind);
        const ProcessResult result = msmcl_cli({"filter", railing, out("again.exr"), "--format", "nlq64"}, cached);
        ASSERT_EQ(result.exit_code, 0) << result.err;
        EXPECT_EQ(msmcl::io::read_whole_file(out("again.exr")), first);
        // Rebuilt: every cache file is whole again (it starts with its header).
        for (const fs::path& binary : binaries)
            EXPECT_EQ(msmcl::io::read_whole_file(binary.string()).rfind("MSMCLBIN", 0), 0u) << binary;
        fs::remove(out("again.exr"));
    }

    // A cache path that cannot be a directory is refused, naming the variable.
    cached.environment["MSMCL_CACHE_DIR"] = (root_ / "out" / "first.exr" / "cache").string();
    const ProcessResult result = msmcl_cli({"filter", railing, out("no.exr"), "--format", "nlq64"}, cached);
    EXPECT_EQ(result.exit_code, 2) << result.err;
    expect_one_line(result, "MSMCL_CACHE_DIR '" + cached.environment["MSMCL_CACHE_DIR"] + "': cannot create it");
    EXPECT_FALSE(fs::exists(out("no.exr")));
}

TEST_F(Faults, MapTooLargeForTheDeviceIsARuntimeFailure) {
    if (!default_device_is_pocl()) GTEST_SKIP() << "needs PoCL's POCL_MEMORY_LIMIT to shrink the device";
    // A 4096 x 4097 depth map, constant (a small file); as moments128 its texture needs
    // 268500992 bytes, just over the 256 MiB largest buffer of a PoCL device limited to 1 GiB.
    msmcl::DepthImage depth{4096, 4097, 1, std::vector<float>(std::size_t(4096) * 4097, 0.5f)};
    const std::string input = (root_ / "big.exr").string();
    msmcl::io::write_depth_exr(input, depth, msmcl::io::SampleType::half);
    ChildSetup small_device;
    small_device.environment["POCL_MEMORY_LIMIT"] = "1";
    const ProcessResult result = msmcl_cli({"filter", input, out("t.exr"), "--format", "moments128"}, small_device);
    EXPECT_EQ(result.exit_code, 1) << result.err;
    expect_one_line(result, "needs 268500992 bytes, more than the device's largest buffer (268435456 bytes)");
    EXPECT_TRUE(outputs().empty()) << "left behind:" << left_behind();
}

TEST_F(Faults, DriverThatCannotWriteItsFilesIsNamedAsTheCause) {
    if (!default_device_is_pocl()) GTEST_SKIP() << "PoCL compiles through files in POCL_CACHE_DIR";
    // A fresh driver cache and 16 KiB of file size: PoCL cannot write the compiled kernel.
    ChildSetup limited;
    limited.environment["POCL_CACHE_DIR"] = (root_ / "pocl").string();
    limited.unset.push_back("MSMCL_CACHE_DIR");
    limited.file_size_limit = 16 * 1024;
    const ProcessResult result = msmcl_cli({"filter", railing, out("t.exr"), "--format", "msm64"}, limited);
    EXPECT_EQ(result.exit_code, 1) << result.err;
    // Either the build fails and says why, or (a driver that needs no files) the output does.
    if (result.err.find("clBuildProgram") != std::string::npos)
        expect_one_line(result, "the file size limit of 16384 bytes set by ulimit -f");
    else
        expect_one_line(result, "cannot write: File too large");
    EXPECT_TRUE(outputs().empty()) << "left behind:" << left_behind();
}

} // namespace
