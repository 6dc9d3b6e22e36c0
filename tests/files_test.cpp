// File safety of msmcl (docs/files.md), run as a hostile pipeline would: outputs that are
// devices, FIFOs, symlinks or spellings of an input; inputs that are FIFOs or devices;
// program-cache entries that are no files; NUL in list paths; malformed containers;
// refusals that must come before any work and create nothing; `-` through a pipe.
// Device nodes are made with mknod in the test's folder (root only), never under /dev.
#include "cli_folder_test.hpp"

#include "io/atomic_file.hpp"
#include "io/dds.hpp"
#include "io/gpu_image.hpp"
#include "io/ktx2.hpp"
#include "io/texture_metadata.hpp"

#include <msmcl/errors.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;
using msmcl::testing::CliFolderTest;
using msmcl::testing::CliRun;

class Files : public CliFolderTest {
protected:
    /// `text` as the file `name` in the test's folder.
    void write_text(const std::string& name, const std::string& text) {
        std::ofstream(path(name), std::ios::binary) << text;
    }
    /// `command` run by /bin/sh in the test's folder (for pipes); its exit code.
    int shell(const std::string& command) {
        const std::string line = "cd '" + root_.string() + "' && " + command;
        const int status = std::system(line.c_str());
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    static std::string cli_path() { return std::string("'") + MSMCL_CLI_PATH + "'"; }
    /// Exit 2, one line on stderr containing `message`.
    static void expect_refused(const CliRun& run, const std::string& message) {
        EXPECT_EQ(run.exit_code, 2) << run.err;
        EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
        EXPECT_NE(run.err.find(message), std::string::npos) << run.err;
    }
    /// The names in the test's folder (recursively), for "nothing else was written".
    std::vector<std::string> listing() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::recursive_directory_iterator(root_))
            names.push_back(fs::relative(entry.path(), root_).string());
        std::sort(names.begin(), names.end());
        return names;
    }
};

// ---- 1. Outputs: devices, FIFOs and standard output are written, never replaced; symlinks
// are written through.

TEST_F(Files, OutputDeviceNodeIsWrittenNotReplaced) {
    if (::geteuid() != 0) GTEST_SKIP() << "mknod of a character device needs root";
    write_depth("d.exr", 16, 16, 1);
    // A null device of our own (major 1, minor 3), in the test's folder.
    ASSERT_EQ(::mknod(path("null").c_str(), S_IFCHR | 0666, makedev(1, 3)), 0) << std::strerror(errno);
    const CliRun run = cli({"filter", "d.exr", "null", "--out-container", "exr", "--format", "msm64"});
    EXPECT_EQ(run.exit_code, 0) << run.err;
    struct stat status {};
    ASSERT_EQ(::stat(path("null").c_str(), &status), 0);
    EXPECT_TRUE(S_ISCHR(status.st_mode)) << "the device node was replaced";
    EXPECT_EQ(status.st_rdev, makedev(1, 3));
}

TEST_F(Files, DevStdoutIntoAPipeGetsTheBytes) {
    write_depth("d.exr", 16, 16, 1);
    ASSERT_EQ(cli({"filter", "d.exr", "file.exr", "--format", "msm64"}).exit_code, 0);
    // /dev/stdout is a pipe here: written into, never renamed over.
    ASSERT_EQ(shell(cli_path() + " filter d.exr /dev/stdout --out-container exr --format msm64 | cat > piped.exr"), 0);
    EXPECT_EQ(bytes("piped.exr"), bytes("file.exr"));
}

TEST_F(Files, OutputFifoIsWrittenIntoNotReplaced) {
    write_depth("d.exr", 8, 8, 1);
    ASSERT_EQ(cli({"filter", "d.exr", "file.ktx2", "--format", "msm64"}).exit_code, 0);
    ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0666), 0);
    // The reader is there first (a FIFO without one is refused, not waited on); 8x8 msm64
    // fits in the pipe's buffer.
    const int reader = ::open(path("fifo").c_str(), O_RDONLY | O_NONBLOCK);
    ASSERT_GE(reader, 0);
    const CliRun run = cli({"filter", "d.exr", "fifo", "--out-container", "ktx2", "--format", "msm64"});
    EXPECT_EQ(run.exit_code, 0) << run.err;
    std::string got(1 << 16, '\0');
    const ssize_t count = ::read(reader, got.data(), got.size());
    ::close(reader);
    got.resize(count > 0 ? static_cast<std::size_t>(count) : 0);
    EXPECT_EQ(got, bytes("file.ktx2"));
    struct stat status {};
    ASSERT_EQ(::lstat(path("fifo").c_str(), &status), 0);
    EXPECT_TRUE(S_ISFIFO(status.st_mode));
    // Nobody reading: refused at once, the FIFO left as it is.
    const CliRun unread = cli({"filter", "d.exr", "fifo", "--out-container", "ktx2", "--format", "msm64"});
    expect_refused(unread, "fifo: cannot write: no process reads from it");
}

TEST_F(Files, OutputSymlinkIsWrittenThroughToItsTarget) {
    write_depth("d.exr", 16, 16, 1);
    ASSERT_EQ(cli({"filter", "d.exr", "file.exr", "--format", "msm64"}).exit_code, 0);
    fs::create_directory(path("targets"));
    write_text("targets/old.exr", "old content");
    fs::create_symlink("targets/old.exr", path("link.exr"));
    // A chain of links to a name that does not exist yet.
    fs::create_symlink("targets/new.exr", path("dangling.exr"));
    fs::create_symlink("dangling.exr", path("chain.exr"));
    for (const std::string link : {"link.exr", "chain.exr"}) {
        SCOPED_TRACE(link);
        const CliRun run = cli({"filter", "d.exr", link, "--format", "msm64"});
        EXPECT_EQ(run.exit_code, 0) << run.err;
        EXPECT_TRUE(fs::is_symlink(path(link)));
    }
    EXPECT_EQ(bytes("targets/old.exr"), bytes("file.exr"));
    EXPECT_EQ(bytes("targets/new.exr"), bytes("file.exr"));
    EXPECT_TRUE(fs::is_symlink(path("dangling.exr")));
}

TEST_F(Files, JsonSummarySymlinkIsWrittenThrough) {
    write_depth("d.exr", 8, 8, 1);
    write_text("summary_target.json", "old");
    fs::create_symlink("summary_target.json", path("summary.json"));
    const CliRun run = cli({"filter", "d.exr", "-o", "out", "--format", "msm64", "--json", "summary.json"});
    EXPECT_EQ(run.exit_code, 0) << run.err;
    EXPECT_TRUE(fs::is_symlink(path("summary.json")));
    EXPECT_NE(bytes("summary_target.json").find("\"written\": 1"), std::string::npos) << bytes("summary_target.json");
}

TEST_F(Files, OutputThatIsADirectoryOrASymlinkLoopIsRefused) {
    write_depth("d.exr", 8, 8, 1);
    fs::create_directory(path("folder.exr"));
    fs::create_symlink("loop_b.exr", path("loop_a.exr"));
    fs::create_symlink("loop_a.exr", path("loop_b.exr"));
    expect_refused(cli({"filter", "d.exr", "folder.exr", "--format", "msm64"}), "folder.exr: cannot write: is a directory");
    expect_refused(cli({"filter", "d.exr", "loop_a.exr", "--format", "msm64"}),
                   "loop_a.exr: cannot write: Too many levels of symbolic links");
    EXPECT_TRUE(fs::is_directory(path("folder.exr")));
    EXPECT_TRUE(fs::is_symlink(path("loop_a.exr")));
}

// ---- 2. --json never replaces an input, an output or the list.

TEST_F(Files, JsonSummaryMayNotReplaceAnInputAnOutputOrTheList) {
    write_depth("a.exr", 8, 8, 1);
    write_depth("b.exr", 8, 8, 1);
    write_text("l.json", "[\"a.exr\"]");
    const std::string a = bytes("a.exr"), list = bytes("l.json");
    expect_refused(cli({"filter", "a.exr", "b.exr", "-o", "out", "--format", "msm64", "--json", "a.exr"}),
                   "a.exr: the --json summary would replace the input a.exr");
    expect_refused(cli({"filter", "a.exr", "b.exr", "-o", "out", "--format", "msm64", "--json", "out/b.exr"}),
                   "out/b.exr: the --json summary is the same file as the output out/b.exr");
    expect_refused(cli({"filter", "--list", "l.json", "-o", "out", "--format", "msm64", "--json", "l.json"}),
                   "l.json: the --json summary would replace the --list file l.json");
    EXPECT_EQ(bytes("a.exr"), a);
    EXPECT_EQ(bytes("l.json"), list);
    EXPECT_FALSE(fs::exists(path("out")));
}

// ---- 3. Identity, not spelling: symlinked folders, hard links, "..".

TEST_F(Files, OutputsAreComparedByIdentityNotSpelling) {
    write_depth("d.exr", 8, 8, 1);
    const std::string depth = bytes("d.exr");
    fs::create_directory_symlink(".", path("self"));
    write_text("self.json", R"([{"input": "d.exr", "output": "self/d.exr"}])");
    expect_refused(cli({"filter", "--list", "self.json", "--format", "msm64"}),
                   "self/d.exr: an output would replace the input d.exr");
    // Two spellings of one new output.
    fs::create_directory(path("o"));
    fs::create_directory_symlink("o", path("olink"));
    write_depth("e.exr", 8, 8, 1);
    write_text("two.json", R"([{"input": "d.exr", "output": "o/a.exr"}, {"input": "e.exr", "output": "olink/a.exr"}])");
    expect_refused(cli({"filter", "--list", "two.json", "--format", "msm64"}),
                   "olink/a.exr: written for both d.exr and e.exr (the same file as o/a.exr)");
    // The single-file form refuses what a batch refuses.
    expect_refused(cli({"filter", "d.exr", "d.exr", "--format", "msm64"}), "d.exr: an output would replace the input d.exr");
    EXPECT_EQ(bytes("d.exr"), depth);
    EXPECT_TRUE(fs::is_empty(path("o")));
}

TEST_F(Files, HardLinkDotDotAndArrayOutputsOfAnInputAreRefused) {
    write_depth("d.exr", 8, 8, 1);
    const std::string depth = bytes("d.exr");
    fs::create_hard_link(path("d.exr"), path("hard.exr"));
    fs::create_directory(path("sub"));
    expect_refused(cli({"filter", "d.exr", "hard.exr", "--format", "msm64"}),
                   "hard.exr: an output would replace the input d.exr");
    expect_refused(cli({"filter", "d.exr", "sub/../d.exr", "--format", "msm64"}),
                   "sub/../d.exr: an output would replace the input d.exr");
    expect_refused(cli({"filter", "d.exr", "-o", "sub/..", "--format", "msm64"}), "an output would replace the input d.exr");
    // An array output that is a hard link of a layer's input, spelled through "..".
    fs::create_hard_link(path("d.exr"), path("hard.ktx2"));
    expect_refused(cli({"filter", "d.exr", "hard.exr", "--array", "sub/../hard.ktx2", "--format", "msm64"}),
                   "sub/../hard.ktx2: an output would replace the input d.exr");
    EXPECT_EQ(bytes("d.exr"), depth);
    EXPECT_TRUE(fs::is_empty(path("sub")));
}

// ---- 4. A FIFO input is refused at once, wherever it is named.

TEST_F(Files, FifoInputIsRefusedAtOnceAndTheOtherFilesAreWritten) {
    write_depth("a.exr", 8, 8, 1);
    ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0666), 0);
    write_text("maps.json", R"(["fifo", "a.exr"])");
    const CliRun batch = cli({"filter", "--list", "maps.json", "-o", "out", "--format", "msm64"});
    EXPECT_EQ(batch.exit_code, 2) << batch.err;
    EXPECT_NE(batch.err.find("fifo: cannot read: is a FIFO"), std::string::npos) << batch.err;
    EXPECT_TRUE(fs::exists(path("out/a.exr")));
    expect_refused(cli({"filter", "--list", "fifo", "-o", "out2", "--format", "msm64"}), "fifo: cannot read: is a FIFO");
    expect_refused(cli({"info", "fifo"}), "fifo: cannot read: is a FIFO");
    expect_refused(cli({"shade", "fifo", "a.exr", "y.exr"}), "fifo: cannot read: is a FIFO");
    expect_refused(cli({"filter", "fifo", "t.exr", "--format", "msm64"}), "fifo: cannot read: is a FIFO");
    EXPECT_FALSE(fs::exists(path("out2")));
}

// ---- 5. Program-cache entries that are not regular files are passed over.

TEST_F(Files, ProgramCacheEntriesThatAreNotFilesAreIgnoredAndRebuilt) {
    write_depth("d.exr", 16, 16, 1);
    const std::vector<std::string> cache = {"MSMCL_CACHE_DIR=" + path("cache")};
    std::vector<std::string> environment = cache;
    for (char** variable = environ; *variable; ++variable)
        if (std::string(*variable).rfind("MSMCL_CACHE_DIR=", 0) != 0) environment.emplace_back(*variable);
    ASSERT_EQ(cli({"filter", "d.exr", "first.exr", "--format", "nlq64"}, &environment).exit_code, 0);
    std::vector<fs::path> entries;
    for (const auto& entry : fs::directory_iterator(path("cache")))
        if (entry.path().extension() == ".bin") entries.push_back(entry.path());
    ASSERT_FALSE(entries.empty());
    const std::string first = bytes("first.exr");
    for (const std::string kind : {"folder", "symlink to /dev/zero", "FIFO"}) {
        SCOPED_TRACE(kind);
        // Every entry's name holds something else; nothing else is in the folder.
        fs::remove_all(path("cache"));
        fs::create_directory(path("cache"));
        for (const fs::path& entry : entries) {
            if (kind == "folder") fs::create_directory(entry);
            else if (kind == "FIFO") ASSERT_EQ(::mkfifo(entry.c_str(), 0666), 0);
            else fs::create_symlink("/dev/zero", entry);
        }
        const CliRun run = cli({"filter", "d.exr", "again.exr", "--format", "nlq64"}, &environment);
        ASSERT_EQ(run.exit_code, 0) << run.err;
        EXPECT_EQ(bytes("again.exr"), first);
        // Left alone, and the binary stored under a fresh name beside it.
        for (const fs::path& entry : entries) {
            EXPECT_FALSE(fs::is_regular_file(fs::symlink_status(entry))) << entry;
            const fs::path fresh = entry.parent_path() / (entry.stem().string() + "-1.bin");
            EXPECT_EQ(msmcl::io::read_whole_file(fresh.string()).rfind("MSMCLBIN", 0), 0u) << fresh;
            fs::remove(fresh);
        }
        fs::remove(path("again.exr"));
    }
}

// ---- 6. Any name the file system takes works (the temporary name is short).

TEST_F(Files, LongOutputNamesAreWritten) {
    write_depth("d.exr", 8, 8, 1);
    for (const std::size_t length : {237u, 250u, 255u}) {
        const std::string name = std::string(length - 4, 'n') + ".exr";
        SCOPED_TRACE(length);
        const CliRun run = cli({"filter", "d.exr", name, "--format", "msm64"});
        EXPECT_EQ(run.exit_code, 0) << run.err;
        EXPECT_TRUE(fs::exists(path(name)));
    }
}

// ---- 7. NUL in list and manifest paths.

TEST_F(Files, NulInListPathsIsRefusedWithItsPosition) {
    write_depth("d.exr", 8, 8, 1);
    write_text("input.json", R"(["a.exr", {"input": "d.exr\u0000zzz"}])");
    write_text("output.json", R"([{"input": "d.exr", "output": "a.exr\u0000../../x.exr"}])");
    write_text("raw.txt", std::string("d.exr\nd.exr\0zzz\n", 17));
    expect_refused(cli({"filter", "--list", "input.json", "-o", "out", "--format", "msm64"}),
                   "input.json: entry 1 \"input\" holds a NUL character");
    expect_refused(cli({"filter", "--list", "output.json", "--format", "msm64"}),
                   "output.json: entry 0 \"output\" holds a NUL character");
    expect_refused(cli({"filter", "--list", "raw.txt", "-o", "out", "--format", "msm64"}),
                   "raw.txt: line 2 holds a NUL character");
    EXPECT_FALSE(fs::exists(path("out")));
    EXPECT_FALSE(fs::exists(path("a.exr")));
}

// Found by fuzz/fuzz_batch_list.cpp: a number past double in a manifest is bad input (exit 2),
// not an uncaught JSON exception (exit 1).
TEST_F(Files, ManifestNumberPastDoubleIsBadInput) {
    write_text("big.json", R"([{"input": "d.exr", "sigma": 1E999999}])");
    expect_refused(cli({"filter", "--list", "big.json", "-o", "out", "--format", "msm64"}),
                   "big.json: not a valid JSON manifest");
    EXPECT_FALSE(fs::exists(path("out")));
}

// ---- 8. Malformed containers.

TEST_F(Files, MalformedContainersAreRefused) {
    write_depth("d.exr", 8, 8, 1);
    ASSERT_EQ(cli({"filter", "d.exr", "t.ktx2", "--format", "msm64"}).exit_code, 0);
    ASSERT_EQ(cli({"filter", "d.exr", "t.dds", "--format", "msm64"}).exit_code, 0);
    // KTX2: level 0 at byte 0, over the header.
    std::string ktx2 = bytes("t.ktx2");
    std::fill(ktx2.begin() + 80, ktx2.begin() + 88, '\0');
    write_text("overlap.ktx2", ktx2);
    expect_refused(cli({"info", "overlap.ktx2"}), "overlap.ktx2: level 0 starts at byte 0, inside the header");
    // DDS: the header says 4 rows, the data holds 8.
    std::string dds = bytes("t.dds");
    dds[12] = 4;
    write_text("short.dds", dds);
    expect_refused(cli({"info", "short.dds"}), "short.dds: DDS file of the wrong size");
    // A KTX2 value msmcl refuses: msmcl-vulkan reads the record with the same code
    // (io::texture_info_of, io::sat_max_kernel_of).
    msmcl::io::GpuImage image = msmcl::io::read_ktx2(path("t.ktx2"));
    for (auto& [key, value] : image.metadata)
        if (key == "msmcl:sigma") value = "-1";
    EXPECT_THROW(msmcl::io::texture_info_of(image, "bad_sigma.ktx2"), msmcl::input_error);
}

// ---- 9. Problems are found before the work; a refused run creates nothing.

TEST_F(Files, RefusedRunsFailBeforeAnyWorkAndCreateNothing) {
    write_depth("d.exr", 8, 8, 1);
    write_text("plain", "a file, not a folder");
    const std::vector<std::string> before = listing();
    // The --json folder cannot be made: refused before any map is written.
    expect_refused(cli({"filter", "d.exr", "-o", "out", "--format", "msm64", "--json", "plain/s.json"}),
                   "plain/s.json: cannot write: Not a directory");
    // One output into a missing folder: refused before the filter runs.
    expect_refused(cli({"filter", "d.exr", "nodir/t.exr", "--format", "msm64"}),
                   "nodir/t.exr: cannot write: No such file or directory");
    // A device that does not exist: the output folders are not made.
    const CliRun no_device = cli({"--device", "no such device", "filter", "d.exr", "-o", "out/deep", "--format", "msm64"});
    EXPECT_NE(no_device.exit_code, 0);
    EXPECT_EQ(listing(), before);
    // A --json folder that can be made is made with the outputs'.
    const CliRun made = cli({"filter", "d.exr", "-o", "out", "--format", "msm64", "--json", "reports/s.json"});
    EXPECT_EQ(made.exit_code, 0) << made.err;
    EXPECT_TRUE(fs::exists(path("reports/s.json")));
}

// ---- 10. Smaller issues.

TEST_F(Files, DeviceInputIsRefusedUnread) {
    // A character device as input: refused from its type, not after 1 GiB of zeros.
    expect_refused(cli({"filter", "/dev/zero", "t.exr", "--format", "msm64"}),
                   "/dev/zero: cannot read: is a character device");
    expect_refused(cli({"info", "/dev/zero"}), "/dev/zero: cannot read: is a character device");
}

TEST_F(Files, ListLimitMessageSaysTheLimitIsFixed) {
    // A sparse file of 300 MiB: refused from its size before it is read.
    {
        std::ofstream(path("huge.txt"));
    }
    fs::resize_file(path("huge.txt"), 300ull << 20);
    const CliRun run = cli({"filter", "--list", "huge.txt", "-o", "out", "--format", "msm64"});
    expect_refused(run, "exceed the limit of 268435456 bytes (fixed for lists");
    EXPECT_EQ(run.err.find("MSMCL_MAX_BYTES"), std::string::npos) << run.err;
}

TEST_F(Files, LongNamesAreCutInMessages) {
    const std::string name = std::string(1 << 20, 'x') + ".exr";
    write_text("long.txt", name + "\n");
    const CliRun run = cli({"filter", "--list", "long.txt", "-o", "out", "--format", "msm64"});
    EXPECT_EQ(run.exit_code, 2) << run.err.substr(0, 300);
    EXPECT_LT(run.err.size(), 2000u);
    EXPECT_NE(run.err.find("..."), std::string::npos) << run.err;
}

TEST_F(Files, EmptyShardAndOtherEmptyValuesAreRefused) {
    write_depth("d.exr", 8, 8, 1);
    expect_refused(cli({"filter", "d.exr", "-o", "out", "--format", "msm64", "--shard", ""}), "--shard must be I/N");
    expect_refused(cli({"filter", "d.exr", "-o", "out", "--format", "msm64", "--json", ""}), "--json needs a file or -");
    expect_refused(cli({"filter", "d.exr", "-o", "", "--format", "msm64"}), "-o needs a folder");
    EXPECT_FALSE(fs::exists(path("out")));
}

// ---- `-`: standard input and output, through pipes.

TEST_F(Files, StandardInputAndOutputRoundTripThroughAPipe) {
    write_depth("d.exr", 16, 16, 1);
    for (const std::string container : {"ktx2", "exr"}) {
        SCOPED_TRACE(container);
        const std::string file = "file." + container, piped = "piped." + container;
        ASSERT_EQ(cli({"filter", "d.exr", file, "--format", "msm64"}).exit_code, 0);
        ASSERT_EQ(shell("cat d.exr | " + cli_path() + " filter - - --out-container " + container +
                        " --format msm64 | cat > " + piped),
                  0);
        EXPECT_EQ(bytes(piped), bytes(file));
        // And back in: info of the texture from standard input.
        ASSERT_EQ(shell("cat " + piped + " | " + cli_path() + " info - --json > info.json"), 0);
        EXPECT_NE(bytes("info.json").find("msm64"), std::string::npos) << bytes("info.json");
    }
    // --list -: the list from standard input.
    ASSERT_EQ(shell("echo d.exr | " + cli_path() + " filter --list - -o out --format msm64 2>/dev/null"), 0);
    EXPECT_EQ(bytes("out/d.exr"), bytes("file.exr"));
    // Two writes to standard output would mix: refused.
    write_text("stdout.json", R"([{"input": "d.exr", "output": "-", "out-container": "ktx2"}])");
    expect_refused(cli({"filter", "--list", "stdout.json", "--format", "msm64", "--json", "-"}),
                   "-: the --json summary is the same file as the output -");
}

// ---- Unit checks of the readers (no device needed).

TEST(FilesIo, ReadInputFileChecksTheMagicBeforeReadingTheRest) {
    const std::string name = (fs::temp_directory_path() / ("msmcl-files-" + std::to_string(::getpid()))).string();
    std::ofstream(name, std::ios::binary) << "not an EXR at all";
    try {
        msmcl::io::read_input_file(name, {1u << 20, "MSMCL_MAX_BYTES", std::string("\x76\x2f\x31\x01", 4), "an OpenEXR file"});
        ADD_FAILURE() << "accepted";
    } catch (const msmcl::input_error& e) {
        EXPECT_EQ(std::string(e.what()), name + ": not an OpenEXR file");
    }
    fs::remove(name);
}

TEST(FilesIo, DisplayNameKeepsBothEndsOfALongName) {
    const std::string name = std::string(100, 'a') + std::string(100, 'b');
    const std::string cut = msmcl::io::display_name(name, 40);
    EXPECT_EQ(cut.size(), 40u);
    EXPECT_EQ(cut.rfind("aaa", 0), 0u);
    EXPECT_NE(cut.find("..."), std::string::npos);
    EXPECT_EQ(cut.substr(cut.size() - 3), "bbb");
    EXPECT_EQ(msmcl::io::display_name("short.exr"), "short.exr");
}

} // namespace
