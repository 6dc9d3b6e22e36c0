// A GoogleTest fixture for tests that run the msmcl CLI as a process in a folder of their
// own: skipped without the CLI or an OpenCL device, a fresh temporary folder per test
// (removed after it), `cli(...)` runs msmcl there, and random depth maps are written there.
#pragma once

#include "io/atomic_file.hpp"
#include "io/exr_io.hpp"
#include "process.hpp"
#include "seeded_test.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/types.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#ifndef MSMCL_CLI_PATH
#define MSMCL_CLI_PATH ""
#endif

namespace msmcl::testing {

/// A finished msmcl run: its exit code and what it printed.
struct CliRun {
    int exit_code = -1;
    std::string out, err;
};

class CliFolderTest : public SeededTest {
protected:
    void SetUp() override {
        SeededTest::SetUp();
        if (std::string(MSMCL_CLI_PATH).empty()) GTEST_SKIP() << "built without the msmcl CLI";
        if (!have_device()) GTEST_SKIP() << "no OpenCL device";
        std::string pattern = (std::filesystem::temp_directory_path() / "msmcl-cli-test-XXXXXX").string();
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        root_ = pattern;
    }
    void TearDown() override {
        if (!root_.empty()) std::filesystem::remove_all(root_);
    }

    /// The path of `name` in the test's folder.
    std::string path(const std::string& name) const { return (root_ / name).string(); }

    /// msmcl <arguments>, run in the test's folder (relative paths are the test's files);
    /// `environment`: "NAME=VALUE" strings, or null for this process's environment. What it
    /// prints is read back and its logs removed, so the folder holds only what msmcl wrote.
    CliRun cli(std::vector<std::string> arguments, const std::vector<std::string>* environment = nullptr) {
        arguments.insert(arguments.begin(), MSMCL_CLI_PATH);
        const std::string out = path("stdout.txt"), err = path("stderr.txt");
        const std::filesystem::path here = std::filesystem::current_path();
        std::filesystem::current_path(root_);
        const int code = run_process(arguments, out, err, environment);
        std::filesystem::current_path(here);
        CliRun run;
        run.exit_code = code;
        run.out = msmcl::io::read_whole_file(out);
        run.err = msmcl::io::read_whole_file(err);
        std::filesystem::remove(out);
        std::filesystem::remove(err);
        return run;
    }

    /// A random depth map in [0, 1] (a slope, a box, noise) of `width` x `height` x `samples`.
    DepthImage random_depth(int width, int height, int samples) {
        std::uniform_real_distribution<float> noise(-0.02f, 0.02f);
        std::uniform_int_distribution<int> corner(0, std::max(width, height));
        DepthImage depth;
        depth.width = width;
        depth.height = height;
        depth.samples = samples;
        const int bx = corner(rng_), by = corner(rng_);
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                for (int s = 0; s < samples; ++s) {
                    const bool box = std::abs(x - bx) < width / 4 && std::abs(y - by) < height / 4;
                    const float base = box ? 0.3f : 0.5f + 0.3f * float(x + y) / float(width + height);
                    depth.depth.push_back(std::clamp(base + noise(rng_), 0.0f, 1.0f));
                }
        return depth;
    }

    /// random_depth written as `name` in the test's folder; returns `name`.
    std::string write_depth(const std::string& name, int width, int height, int samples) {
        msmcl::io::write_depth_exr(path(name), random_depth(width, height, samples));
        return name;
    }

    /// The bytes of `name` in the test's folder.
    std::string bytes(const std::string& name) const { return msmcl::io::read_whole_file(path(name)); }

    std::filesystem::path root_;

private:
    static bool have_device() {
        try {
            return !msmcl::list_devices().empty();
        } catch (const msmcl::error&) {
            return false;
        }
    }
};

} // namespace msmcl::testing
