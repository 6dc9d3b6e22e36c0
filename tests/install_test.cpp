// The installed package: `cmake --install` of this build tree into a temporary, non-system
// prefix, then what an engine's build sees there: files in place (license and docs too), a
// shared library that exports the public API only under its SONAME, find_package(msmcl
// CONFIG) from a fresh consumer project (examples/, C++ and C, shared and static) whose
// variables and targets all point into the prefix and whose configure step prints no
// warning, pkg-config without the static library's dependencies, and the installed CLI
// finding its libraries without LD_LIBRARY_PATH. Consumers pick their own OpenCL version:
// the CMake project at 3.0, pkg-config shared at 3.0 and 1.2, pkg-config static as the
// one-line command docs/integration-build.md prints; every public header compiles
// warning-free with any version.
// Needs cmake, a C compiler, nm, readelf and pkg-config (paths from CMakeLists.txt).
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <iterator>
#include <string>
#include <utility>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

struct Outcome {
    int exit_code = -1;
    std::string output; // stdout and stderr
};

// Runs a shell command line, capturing its output.
Outcome run(const std::string& command) {
    Outcome outcome;
    FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    if (!pipe) return outcome;
    std::array<char, 4096> chunk{};
    std::size_t read = 0;
    while ((read = std::fread(chunk.data(), 1, chunk.size(), pipe)) > 0) outcome.output.append(chunk.data(), read);
    const int status = pclose(pipe);
    outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return outcome;
}

std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }

// The install prefix and consumer build, shared by the tests of this file (one install).
class InstallTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        root_ = fs::temp_directory_path() / ("msmcl-install-test-" + std::to_string(getpid()));
        fs::remove_all(root_);
        fs::create_directories(root_);
        prefix_ = root_ / "prefix";
        install_ = run(std::string("'") + MSMCL_CMAKE_COMMAND + "' --install '" + MSMCL_BINARY_DIR + "' --prefix " +
                       quoted(prefix_));
    }
    static void TearDownTestSuite() {
        // Keep the directory for a look when something failed.
        if (!::testing::UnitTest::GetInstance()->Failed()) fs::remove_all(root_);
    }
    void SetUp() override { ASSERT_EQ(install_.exit_code, 0) << install_.output; }

    static fs::path libdir() { return prefix_ / MSMCL_INSTALL_LIBDIR; }
    /// pkg-config with the installed .pc files first on its search path.
    static std::string pkg_config() {
        return "PKG_CONFIG_PATH=" + quoted(libdir() / "pkgconfig") + " '" + MSMCL_PKG_CONFIG_COMMAND + "' ";
    }
    /// Compiles `program` with `command` (which names the source and flags), runs it and
    /// expects exit 0 and `ok_line` in its output.
    static void build_and_run(const std::string& command, const fs::path& program, const std::string& ok_line) {
        const Outcome compile = run(command + " -o " + quoted(program));
        ASSERT_EQ(compile.exit_code, 0) << compile.output;
        const Outcome result = run(quoted(program));
        EXPECT_EQ(result.exit_code, 0) << result.output;
        EXPECT_NE(result.output.find(ok_line), std::string::npos) << result.output;
    }

    static fs::path root_;
    static fs::path prefix_;
    static Outcome install_;
};

fs::path InstallTest::root_;
fs::path InstallTest::prefix_;
Outcome InstallTest::install_;

TEST_F(InstallTest, PutsLibrariesHeadersPackageAndToolsInPlace) {
    const fs::path include = prefix_ / MSMCL_INSTALL_INCLUDEDIR / "msmcl";
    for (const char* header : {"msmcl.hpp", "msmcl.h", "version.hpp", "context.hpp", "filter.hpp", "interop.hpp",
                               "formats.hpp", "errors.hpp", "enqueue.hpp", "shade.hpp", "device_math.hpp", "types.hpp",
                               "vector3.hpp"})
        EXPECT_TRUE(fs::is_regular_file(include / header)) << header;
    const std::string so = "libmsmcl.so";
    EXPECT_TRUE(fs::is_regular_file(libdir() / (so + "." + MSMCL_VERSION)));
    EXPECT_TRUE(fs::is_symlink(libdir() / (so + "." + MSMCL_SOVERSION)));
    EXPECT_TRUE(fs::is_symlink(libdir() / so));
    EXPECT_TRUE(fs::is_regular_file(libdir() / "libmsmcl.a"));
    for (const char* file : {"msmclConfig.cmake", "msmclConfigVersion.cmake", "msmclTargets.cmake",
                             "msmclStaticTargets.cmake"})
        EXPECT_TRUE(fs::is_regular_file(libdir() / "cmake" / "msmcl" / file)) << file;
    EXPECT_TRUE(fs::is_regular_file(libdir() / "pkgconfig" / "msmcl.pc"));
    EXPECT_TRUE(fs::is_regular_file(libdir() / "pkgconfig" / "msmcl-static.pc"));
    const fs::path doc = prefix_ / MSMCL_INSTALL_DOCDIR;
    for (const char* file : {"README.md", "LICENSE", "docs/README.md", "docs/formats.md", "docs/math.md",
                             "docs/kernels.md", "docs/devices.md", "docs/methods.md", "examples/engine.c",
                             "examples/engine.cpp", "examples/CMakeLists.txt"})
        EXPECT_TRUE(fs::is_regular_file(doc / file)) << file;
    const fs::path data = prefix_ / MSMCL_INSTALL_DATADIR / "msmcl";
    EXPECT_TRUE(fs::is_regular_file(data / "kernels" / "msm_shading.clh"));
    EXPECT_TRUE(fs::is_regular_file(data / "kernels" / "msm_portable.clh"));
    if (fs::exists(fs::path(MSMCL_SOURCE_DIR) / "shaders" / "msm.glsl.in")) {
        EXPECT_TRUE(fs::is_regular_file(data / "shaders" / "msm.glsl"));
        EXPECT_TRUE(fs::is_regular_file(data / "shaders" / "msm.hlsl"));
    }
    EXPECT_TRUE(fs::is_regular_file(prefix_ / MSMCL_INSTALL_BINDIR / "msmcl"));
}

TEST_F(InstallTest, SharedLibraryHasSonameAndExportsThePublicApiOnly) {
    const fs::path library = libdir() / (std::string("libmsmcl.so.") + MSMCL_VERSION);
    const Outcome dynamic = run(std::string("'") + MSMCL_READELF_COMMAND + "' -d " + quoted(library));
    ASSERT_EQ(dynamic.exit_code, 0) << dynamic.output;
    EXPECT_NE(dynamic.output.find(std::string("Library soname: [libmsmcl.so.") + MSMCL_SOVERSION + "]"),
              std::string::npos)
        << dynamic.output;

    const Outcome symbols = run(std::string("'") + MSMCL_NM_COMMAND + "' -D -C --defined-only " + quoted(library));
    ASSERT_EQ(symbols.exit_code, 0) << symbols.output;
    std::istringstream lines(symbols.output);
    std::string line;
    int public_cpp = 0, public_c = 0;
    while (std::getline(lines, line)) {
        // "<address> <type> <name>": the name starts after the second blank.
        const std::size_t first = line.find(' ');
        const std::size_t second = first == std::string::npos ? first : line.find(' ', first + 1);
        if (second == std::string::npos) continue;
        const std::string name = line.substr(second + 1);
        const bool version_node = name.rfind("MSMCL_", 0) == 0;
        const bool cpp_api = name.rfind("msmcl::", 0) == 0 || name.find(" for msmcl::") != std::string::npos;
        const bool c_api = name.rfind("msmcl_", 0) == 0;
        EXPECT_TRUE(version_node || cpp_api || c_api) << "exported: " << name;
        EXPECT_EQ(name.find("msmcl::detail::"), std::string::npos) << "exported: " << name;
        public_cpp += name.rfind("msmcl::filter(", 0) == 0;
        public_c += name.rfind("msmcl_filter@", 0) == 0;
    }
    EXPECT_GE(public_cpp, 2) << symbols.output; // host and device overloads
    EXPECT_EQ(public_c, 1) << symbols.output;
}

// A fresh project (examples/) finds the installed package and builds against it, from C++
// and C, shared and static, with OpenCL 3.0 as its own version (no "redefined" warning, which
// -Werror would turn into a failure; the C++ example creates its queue with the 2.0 call);
// the examples check their own results.
TEST_F(InstallTest, ConsumerProjectFindsThePackageAndRuns) {
    // The exported targets leave the OpenCL version to the consumer.
    for (const char* file : {"msmclTargets.cmake", "msmclStaticTargets.cmake"}) {
        std::ifstream targets(libdir() / "cmake" / "msmcl" / file);
        const std::string text((std::istreambuf_iterator<char>(targets)), std::istreambuf_iterator<char>());
        EXPECT_EQ(text.find("OPENCL_VERSION"), std::string::npos) << file << "\n" << text;
    }
    const fs::path build = root_ / "consumer";
    const Outcome configure = run(std::string("'") + MSMCL_CMAKE_COMMAND + "' -S '" + MSMCL_SOURCE_DIR +
                                  "/examples' -B " + quoted(build) + " -DCMAKE_BUILD_TYPE=Release" +
                                  " -DMSMCL_EXAMPLES_OPENCL_VERSION=300 -DCMAKE_C_FLAGS=-Werror" +
                                  " -DCMAKE_CXX_FLAGS=-Werror" +
                                  " -DCMAKE_PREFIX_PATH=" + quoted(prefix_) +
                                  " -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON -DCMAKE_C_COMPILER='" +
                                  MSMCL_C_COMPILER + "' -DCMAKE_CXX_COMPILER='" + MSMCL_CXX_COMPILER + "'");
    ASSERT_EQ(configure.exit_code, 0) << configure.output;
    // Nothing to warn about: no dependency's config file speaks, no path is missing.
    for (const char* noise : {"Warning", "WARNING", "does not exist", "Imath"})
        EXPECT_EQ(configure.output.find(noise), std::string::npos) << noise << "\n" << configure.output;
    // It found the installed package, not this build tree.
    std::ifstream cache(build / "CMakeCache.txt");
    const std::string cache_text((std::istreambuf_iterator<char>(cache)), std::istreambuf_iterator<char>());
    EXPECT_NE(cache_text.find("msmcl_DIR:PATH=" + (libdir() / "cmake" / "msmcl").string()), std::string::npos);

    const Outcome compile = run(std::string("'") + MSMCL_CMAKE_COMMAND + "' --build " + quoted(build) + " -j2");
    ASSERT_EQ(compile.exit_code, 0) << compile.output;
    for (const char* example : {"msmcl_example_engine", "msmcl_example_c", "msmcl_example_c_static"}) {
        SCOPED_TRACE(example);
        ASSERT_TRUE(fs::is_regular_file(build / example));
        const Outcome result = run(quoted(build / example));
        EXPECT_EQ(result.exit_code, 0) << result.output;
        EXPECT_NE(result.output.find(": ok"), std::string::npos) << result.output;
    }
    // The shared examples load the installed library (through the build RPATH).
    const Outcome needed = run(std::string("'") + MSMCL_READELF_COMMAND + "' -d " + quoted(build / "msmcl_example_c"));
    EXPECT_NE(needed.output.find(std::string("libmsmcl.so.") + MSMCL_SOVERSION), std::string::npos) << needed.output;
}

// Every variable and target of the package, seen from a consumer project in another prefix:
// each path lies in the install prefix and exists, each target is defined.
TEST_F(InstallTest, PackageVariablesAndTargetsPointIntoThePrefix) {
    const fs::path project = root_ / "variables";
    fs::create_directories(project);
    std::ofstream(project / "CMakeLists.txt") << R"(cmake_minimum_required(VERSION 3.19)
project(variables LANGUAGES C CXX)
find_package(msmcl 0.1 CONFIG REQUIRED)
foreach(variable msmcl_INCLUDE_DIR msmcl_KERNEL_DIR msmcl_SHADER_DIR msmcl_DOC_DIR msmcl_DIR msmcl_VERSION)
  message(STATUS "variable ${variable}=${${variable}}")
endforeach()
foreach(target msmcl::msmcl msmcl::msmcl_static)
  if(TARGET ${target})
    message(STATUS "target ${target}")
  endif()
endforeach()
)";
    const Outcome configure = run(std::string("'") + MSMCL_CMAKE_COMMAND + "' -S " + quoted(project) + " -B " +
                                  quoted(project / "build") + " -DCMAKE_PREFIX_PATH=" + quoted(prefix_) +
                                  " -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON -DCMAKE_C_COMPILER='" +
                                  MSMCL_C_COMPILER + "' -DCMAKE_CXX_COMPILER='" + MSMCL_CXX_COMPILER + "'");
    ASSERT_EQ(configure.exit_code, 0) << configure.output;
    for (const char* noise : {"Warning", "WARNING", "does not exist", "Imath"})
        EXPECT_EQ(configure.output.find(noise), std::string::npos) << noise << "\n" << configure.output;
    const auto value_of = [&](const std::string& name) {
        const std::string key = "variable " + name + "=";
        const std::size_t at = configure.output.find(key);
        if (at == std::string::npos) return std::string("<missing>");
        const std::size_t begin = at + key.size();
        return configure.output.substr(begin, configure.output.find('\n', begin) - begin);
    };
    const fs::path share = prefix_ / MSMCL_INSTALL_DATADIR / "msmcl";
    const std::pair<const char*, fs::path> expected[] = {
        {"msmcl_INCLUDE_DIR", prefix_ / MSMCL_INSTALL_INCLUDEDIR},
        {"msmcl_KERNEL_DIR", share / "kernels"},
        {"msmcl_SHADER_DIR", share / "shaders"},
        {"msmcl_DOC_DIR", prefix_ / MSMCL_INSTALL_DOCDIR},
        {"msmcl_DIR", libdir() / "cmake" / "msmcl"},
    };
    for (const auto& [name, path] : expected) {
        SCOPED_TRACE(name);
        const std::string value = value_of(name);
        EXPECT_EQ(fs::weakly_canonical(value), fs::weakly_canonical(path)) << value;
        if (std::string(name) != "msmcl_SHADER_DIR" || fs::exists(fs::path(MSMCL_SOURCE_DIR) / "shaders"))
            EXPECT_TRUE(fs::is_directory(value)) << value;
    }
    EXPECT_EQ(value_of("msmcl_VERSION"), MSMCL_VERSION);
    EXPECT_NE(configure.output.find("target msmcl::msmcl\n"), std::string::npos) << configure.output;
    EXPECT_NE(configure.output.find("target msmcl::msmcl_static\n"), std::string::npos) << configure.output;
}

// Neither .pc file requires more than OpenCL (file I/O lives in msmcl_io, which is not
// installed): a machine without the OpenEXR and libpng development packages gets the flags of
// both. Shown with a pkg-config search path that holds the installed .pc files and OpenCL's alone.
TEST_F(InstallTest, PkgConfigNeedsNoFileFormatPackages) {
    for (const char* name : {"msmcl.pc", "msmcl-static.pc"}) {
        std::ifstream pc(libdir() / "pkgconfig" / name);
        const std::string pc_text((std::istreambuf_iterator<char>(pc)), std::istreambuf_iterator<char>());
        for (const char* dependency : {"OpenEXR", "libpng", "Imath"})
            EXPECT_EQ(pc_text.find(dependency), std::string::npos) << name << ": " << dependency << "\n" << pc_text;
        EXPECT_NE(pc_text.find("License: MIT"), std::string::npos) << pc_text;
    }

    // A search path with OpenCL.pc only, besides msmcl's own.
    const fs::path system_pc = root_ / "opencl-only-pkgconfig";
    fs::create_directories(system_pc);
    const Outcome opencl_pc = run(std::string("'") + MSMCL_PKG_CONFIG_COMMAND + "' --variable=pcfiledir OpenCL");
    ASSERT_EQ(opencl_pc.exit_code, 0) << opencl_pc.output;
    const fs::path opencl_dir = opencl_pc.output.substr(0, opencl_pc.output.find('\n'));
    fs::copy_file(opencl_dir / "OpenCL.pc", system_pc / "OpenCL.pc", fs::copy_options::overwrite_existing);
    const std::string pkg_config = "PKG_CONFIG_PATH= PKG_CONFIG_LIBDIR=" + quoted(libdir() / "pkgconfig") + ":" +
                                   quoted(system_pc) + " '" + MSMCL_PKG_CONFIG_COMMAND + "' ";
    EXPECT_NE(run(pkg_config + "--exists OpenEXR").exit_code, 0) << "the search path still sees OpenEXR";
    const Outcome flags = run(pkg_config + "--cflags --libs msmcl");
    ASSERT_EQ(flags.exit_code, 0) << flags.output;
    build_and_run(std::string("'") + MSMCL_C_COMPILER + "' -std=c99 '" + MSMCL_SOURCE_DIR + "/examples/engine.c' $(" +
                      pkg_config + "--cflags --libs msmcl) -Wl,-rpath," + quoted(libdir()),
                  root_ / "example_c_pkgconfig_minimal", "example_c: ok");
    // The static variant resolves there too.
    EXPECT_EQ(run(pkg_config + "--cflags --libs msmcl-static").exit_code, 0);
}

// The installed CLI finds its libraries from its own RPATH, in any prefix, with no
// LD_LIBRARY_PATH.
TEST_F(InstallTest, InstalledCliRunsFromItsPrefix) {
    const fs::path cli = prefix_ / MSMCL_INSTALL_BINDIR / "msmcl";
    if (!fs::exists(cli)) GTEST_SKIP() << "the CLI is not built (MSMCL_BUILD_TOOLS=OFF)";
    const Outcome dynamic = run(std::string("'") + MSMCL_READELF_COMMAND + "' -d " + quoted(cli));
    EXPECT_NE(dynamic.output.find("$ORIGIN/"), std::string::npos) << dynamic.output;
    const Outcome version = run("env -u LD_LIBRARY_PATH " + quoted(cli) + " --version");
    EXPECT_EQ(version.exit_code, 0) << version.output;
    EXPECT_NE(version.output.find(std::string("msmcl ") + MSMCL_VERSION), std::string::npos) << version.output;
}

// The man page msmcl(1) renders from the prefix (`man -l`, and `man msmcl` with the prefix's
// share/man on MANPATH) with the commands and the environment variables; the bash completion
// offers the subcommands and the options of the command on the line.
TEST_F(InstallTest, ManPageAndCompletionWorkFromThePrefix) {
    const fs::path cli = prefix_ / MSMCL_INSTALL_BINDIR / "msmcl";
    if (!fs::exists(cli)) GTEST_SKIP() << "the CLI is not built (MSMCL_BUILD_TOOLS=OFF)";
    const fs::path completion = prefix_ / MSMCL_INSTALL_DATADIR / "bash-completion" / "completions" / "msmcl";
    ASSERT_TRUE(fs::is_regular_file(completion));
    const auto complete = [&](const std::string& words, int current) {
        return run("bash -c 'source " + completion.string() + "; COMP_WORDS=(" + words + "); COMP_CWORD=" +
                   std::to_string(current) + "; _msmcl; echo \"${COMPREPLY[*]}\"'");
    };
    const Outcome commands = complete("msmcl \"\"", 1);
    EXPECT_EQ(commands.exit_code, 0) << commands.output;
    const std::string offered = " " + commands.output.substr(0, commands.output.find('\n')) + " ";
    for (const char* command : {"filter", "shade", "sat", "soft", "scatter", "devices", "info"})
        EXPECT_NE(offered.find(std::string(" ") + command + " "), std::string::npos) << command << ": " << offered;
    EXPECT_EQ(complete("msmcl fi", 1).output, "filter\n");
    EXPECT_EQ(complete("msmcl shade map.exr --lo", 3).output, "--lookup\n");
    EXPECT_EQ(complete("msmcl --qu", 1).output, "--quiet\n");

#ifndef MSMCL_HAS_MAN_PAGE
    GTEST_SKIP() << "no man page (help2man was not found at configure time)";
#else
    const fs::path page = prefix_ / MSMCL_INSTALL_MANDIR / "man1" / "msmcl.1";
    ASSERT_TRUE(fs::is_regular_file(page));
    for (const std::string& command : {"man -l " + quoted(page), "MANPATH=" + quoted(prefix_ / MSMCL_INSTALL_MANDIR) + " man msmcl"}) {
        SCOPED_TRACE(command);
        const Outcome rendered = run("MANWIDTH=100 MANPAGER=cat PAGER=cat " + command);
        EXPECT_EQ(rendered.exit_code, 0) << rendered.output;
        for (const char* text : {"NAME", "msmcl - moment shadow maps", "--quiet", "msmcl filter", "msmcl info",
                                 "MSMCL_STRICT", "MSMCL_CACHE_DIR", "Exit codes"})
            EXPECT_NE(rendered.output.find(text), std::string::npos) << text << "\n" << rendered.output;
        EXPECT_EQ(rendered.output.find("warning"), std::string::npos) << rendered.output;
    }
#endif
}

TEST_F(InstallTest, PkgConfigReportsTheLibrary) {
    const std::string pkg_config = InstallTest::pkg_config();
    const Outcome version = run(pkg_config + "--modversion msmcl");
    ASSERT_EQ(version.exit_code, 0) << version.output;
    EXPECT_EQ(version.output, std::string(MSMCL_VERSION) + "\n");
    const Outcome flags = run(pkg_config + "--cflags --libs msmcl");
    ASSERT_EQ(flags.exit_code, 0) << flags.output;
    EXPECT_NE(flags.output.find("-lmsmcl"), std::string::npos) << flags.output;
    const Outcome static_flags = run(pkg_config + "--static --libs msmcl");
    EXPECT_EQ(static_flags.exit_code, 0) << static_flags.output;
}

// pkg-config builds the examples against the shared library, and leaves the OpenCL version
// to the consumer: the C++ example at 3.0 (its queue from the 2.0 call) and the C example at
// 1.2, each warning-free, each running.
TEST_F(InstallTest, PkgConfigConsumersPickTheirOpenClVersion) {
    const std::string pkg_config = InstallTest::pkg_config();
    for (const char* package : {"msmcl", "msmcl-static"}) {
        const Outcome flags = run(pkg_config + "--cflags " + package);
        ASSERT_EQ(flags.exit_code, 0) << flags.output;
        EXPECT_EQ(flags.output.find("OPENCL_VERSION"), std::string::npos) << package << ": " << flags.output;
    }
    const std::pair<std::string, std::string> consumers[] = {
        {std::string("'") + MSMCL_CXX_COMPILER + "' -std=c++17 -DCL_TARGET_OPENCL_VERSION=300", "engine.cpp"},
        {std::string("'") + MSMCL_C_COMPILER + "' -std=c99 -DCL_TARGET_OPENCL_VERSION=120", "engine.c"},
    };
    for (const auto& [compiler, source] : consumers) {
        SCOPED_TRACE(source);
        build_and_run(compiler + " -Wall -Wextra -Werror '" + MSMCL_SOURCE_DIR + "/examples/" + source + "' $(" +
                          pkg_config + "--cflags --libs msmcl) -Wl,-rpath," + quoted(libdir()),
                      root_ / ("pkgconfig_version_" + source), ": ok");
    }
}

// The static library links with the one-line command of docs/integration-build.md, as
// printed: `cc r.c $(pkg-config --cflags --libs msmcl-static)`, no --static needed; the
// program needs no libmsmcl.so at run time.
TEST_F(InstallTest, StaticPkgConfigLinksAsPrinted) {
    const fs::path program = root_ / "example_c_pkgconfig_static";
    build_and_run(std::string("'") + MSMCL_C_COMPILER + "' '" + MSMCL_SOURCE_DIR + "/examples/engine.c' $(" + pkg_config() +
                      "--cflags --libs msmcl-static)",
                  program, "example_c: ok");
    const Outcome needed = run(std::string("'") + MSMCL_READELF_COMMAND + "' -d " + quoted(program));
    EXPECT_EQ(needed.output.find("libmsmcl"), std::string::npos) << needed.output;
}

// Every installed public header on its own, included with -I (not as a system header, which
// would hide its warnings), compiles without a warning under the strictest common flags, at
// each OpenCL version a consumer may pick, and beside the Khronos C++ bindings at theirs.
TEST_F(InstallTest, PublicHeadersCompileWarningFreeWithAnyOpenClVersion) {
    const fs::path include = prefix_ / MSMCL_INSTALL_INCLUDEDIR;
    const fs::path sources = root_ / "headers";
    fs::create_directories(sources);
    std::string cpp_sources;
    for (const fs::directory_entry& entry : fs::directory_iterator(include / "msmcl")) {
        const std::string name = entry.path().filename().string();
        const fs::path source = sources / (entry.path().stem().string() + (entry.path().extension() == ".h" ? "_h.cpp" : ".cpp"));
        std::ofstream(source) << "#include <msmcl/" << name << ">\n";
        cpp_sources += " " + quoted(source);
    }
    ASSERT_FALSE(cpp_sources.empty());
    std::ofstream(sources / "c_api.c") << "#include <msmcl/msmcl.h>\n";
    std::ofstream(sources / "with_bindings.cpp") << "#include <CL/opencl.hpp>\n#include <msmcl/msmcl.hpp>\n";
    const std::string warnings = " -fsyntax-only -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow -Werror -I" +
                                 quoted(include);
    for (const char* version : {"120", "200", "300"}) {
        SCOPED_TRACE(version);
        const std::string define = std::string(" -DCL_TARGET_OPENCL_VERSION=") + version;
        const Outcome cpp = run(std::string("'") + MSMCL_CXX_COMPILER + "' -std=c++17" + warnings + define + cpp_sources);
        EXPECT_EQ(cpp.exit_code, 0) << cpp.output;
        EXPECT_EQ(cpp.output, "");
        const Outcome c = run(std::string("'") + MSMCL_C_COMPILER + "' -std=c99" + warnings + define + " " + quoted(sources / "c_api.c"));
        EXPECT_EQ(c.exit_code, 0) << c.output;
        EXPECT_EQ(c.output, "");
        const Outcome bindings = run(std::string("'") + MSMCL_CXX_COMPILER + "' -std=c++17" + warnings + define +
                                     " -DCL_HPP_TARGET_OPENCL_VERSION=" + version + " -DCL_HPP_MINIMUM_OPENCL_VERSION=" +
                                     version + " " + quoted(sources / "with_bindings.cpp"));
        EXPECT_EQ(bindings.exit_code, 0) << bindings.output;
    }
}

} // namespace
