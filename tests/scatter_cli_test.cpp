// `msmcl scatter` and `msmcl-scatter-scene` run as processes: results equal the library's,
// inspection maps, and bad input (malformed JSON, zero extinction, a camera inside geometry,
// wrong sizes, bad options) gives exit 2 with one line naming the file and the problem.
#include "tools/scatter_geometry.hpp"
#include "io/atomic_file.hpp"
#include "io/exr_io.hpp"
#include "io/scene_json.hpp"
#include "captured_process.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/scatter.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <spawn.h>
#include <sstream>
#include <sys/wait.h>

extern char** environ;

#ifndef MSMCL_CLI_PATH
#define MSMCL_CLI_PATH ""
#endif

namespace {

namespace fs = std::filesystem;

const std::string cli_path = MSMCL_CLI_PATH;
const std::string scene_tool = std::string(MSMCL_TOOLS_BUILD_DIR) + "/msmcl-scatter-scene";

std::string read_text(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    std::ostringstream text;
    text << file.rdbuf();
    return text.str();
}

using msmcl::testing::ProcessResult;

class ScatterCli : public ::testing::Test {
protected:
    void SetUp() override {
        if (cli_path.empty()) GTEST_SKIP() << "built without the msmcl CLI (MSMCL_BUILD_TOOLS=OFF)";
        if (msmcl::list_devices().empty()) GTEST_SKIP() << "no OpenCL device";
        std::string pattern = (fs::temp_directory_path() / "msmcl-scatter-cli-XXXXXX").string();
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        root_ = pattern;
        fs::create_directory(root_ / "in");
        fs::create_directory(root_ / "out");
        fs::create_directory(root_ / "log");
        // The hall at test size: 128^2 shadow map, 128 x 96 view, 64^2 rectified map.
        text_ = read_text(std::string(MSMCL_SOURCE_DIR) + "/data/scatter/hall.json");
        nlohmann::json document = nlohmann::json::parse(text_);
        document["rectified"]["width"] = 64;
        document["rectified"]["height"] = 64;
        text_ = document.dump(2);
        write_scene("scene.json", text_);
        scene_ = msmcl::parse_scatter_scene(text_);
        geometry_ = msmcl::scatter_data::parse_geometry(text_);
        shadow_ = msmcl::scatter_data::render_shadow_map(scene_, geometry_, 128, 128);
        camera_ = msmcl::scatter_data::render_camera_depth(scene_, geometry_);
        msmcl::io::write_depth_exr(in("shadow.exr"), shadow_);
        write_camera(in("camera.exr"), camera_, scene_.camera.width, scene_.camera.height);
    }
    void TearDown() override {
        if (!root_.empty()) fs::remove_all(root_);
    }

    std::string in(const std::string& name) const { return (root_ / "in" / name).string(); }
    std::string out(const std::string& name) const { return (root_ / "out" / name).string(); }
    bool out_empty() const { return fs::is_empty(root_ / "out"); }

    void write_scene(const std::string& name, const std::string& text) const { std::ofstream(in(name)) << text; }
    static void write_camera(const std::string& path, const std::vector<float>& depth, int width, int height) {
        msmcl::io::ExrImage image;
        image.width = width;
        image.height = height;
        image.channels = {{"Z", msmcl::io::SampleType::float32, depth, {}}};
        msmcl::io::write_exr(path, image);
    }

    ProcessResult run(std::vector<std::string> arguments) {
        return msmcl::testing::run_captured(std::move(arguments), (root_ / "log" / "stdout").string(),
                                            (root_ / "log" / "stderr").string());
    }

    ProcessResult scatter(std::vector<std::string> arguments) {
        arguments.insert(arguments.begin(), {cli_path, "scatter"});
        return run(std::move(arguments));
    }

    /// Exit 2, one line "msmcl: <file>: ...<problem>...", nothing written.
    void expect_bad_input(const std::vector<std::string>& arguments, const std::string& file, const std::string& problem) {
        std::string command = "msmcl scatter";
        for (const std::string& a : arguments) command += " " + a;
        SCOPED_TRACE(command);
        const ProcessResult result = scatter(arguments);
        EXPECT_EQ(result.exit_code, 2) << result.err;
        EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
        const std::string prefix = "msmcl: " + (file.empty() ? std::string() : file + ": ");
        EXPECT_EQ(result.err.rfind(prefix, 0), 0u) << result.err << "  expected prefix: " << prefix;
        EXPECT_NE(result.err.find(problem), std::string::npos) << result.err << "  expected: " << problem;
        EXPECT_TRUE(out_empty());
    }

    static std::vector<float> channel(const std::string& path, const std::string& name) {
        const msmcl::io::ExrImage image = msmcl::io::read_exr(path);
        const msmcl::io::ExrChannel* c = image.find_channel(name);
        EXPECT_NE(c, nullptr) << path << " has no channel " << name;
        return c ? c->values : std::vector<float>{};
    }

    fs::path root_;
    std::string text_;
    msmcl::ScatterScene scene_;
    msmcl::scatter_data::Geometry geometry_;
    msmcl::DepthImage shadow_;
    std::vector<float> camera_;
};

TEST_F(ScatterCli, RadianceEqualsTheLibrary) {
    msmcl::Context context;
    const struct {
        std::vector<std::string> options;
        int moments;
        bool filtered;
        float beta;
        msmcl::ScatterKernel kernel = msmcl::ScatterKernel::automatic;
        msmcl::FilterKernel filter_kernel = msmcl::FilterKernel::automatic;
    } cases[] = {{{}, 6, true, -1.0f},
                 {{"--moments", "4", "--no-filter", "--beta", "0.5"}, 4, false, 0.5f},
                 {{"--kernel", "rows_gpu", "--filter-kernel", "fused_paper"}, 6, true, -1.0f,
                  msmcl::ScatterKernel::rows_gpu, msmcl::FilterKernel::fused_paper},
                 {{"--kernel", "rows_cpu", "--filter-kernel", "three_pass", "--moments", "4"}, 4, true, -1.0f,
                  msmcl::ScatterKernel::rows_cpu, msmcl::FilterKernel::three_pass}};
    for (const auto& c : cases) {
        std::vector<std::string> arguments{in("scene.json"), in("shadow.exr"), in("camera.exr"), out("radiance.exr")};
        arguments.insert(arguments.end(), c.options.begin(), c.options.end());
        const ProcessResult result = scatter(arguments);
        ASSERT_EQ(result.exit_code, 0) << result.err;
        EXPECT_TRUE(result.err.empty()) << result.err;
        msmcl::ScatterOptions options;
        options.moments = c.moments;
        options.filtered = c.filtered;
        options.beta = c.beta;
        options.kernel = c.kernel;
        options.filter_kernel = c.filter_kernel;
        const std::vector<float> expected = msmcl::scatter(context, scene_, shadow_, camera_, options);
        const std::vector<float> got = channel(out("radiance.exr"), "Y");
        ASSERT_EQ(got.size(), expected.size());
        EXPECT_EQ(0, std::memcmp(got.data(), expected.data(), got.size() * sizeof(float)));
        fs::remove(out("radiance.exr"));
    }
}

TEST_F(ScatterCli, RayMarchingAndInspectionMaps) {
    msmcl::Context context;
    ProcessResult result =
        scatter({in("scene.json"), in("shadow.exr"), in("camera.exr"), out("marched.exr"), "--ray-march", "32"});
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const std::vector<float> expected = msmcl::scatter_ray_march(context, scene_, shadow_, camera_, 32);
    const std::vector<float> got = channel(out("marched.exr"), "Y");
    ASSERT_EQ(got.size(), expected.size());
    EXPECT_EQ(0, std::memcmp(got.data(), expected.data(), got.size() * sizeof(float)));

    result = scatter({in("scene.json"), in("shadow.exr"), in("camera.exr"), out("radiance.exr"), "--moments", "4",
                      "--rectified", out("rectified.exr"), "--prefix-sums", out("sums.exr")});
    ASSERT_EQ(result.exit_code, 0) << result.err;
    for (const char* file : {"rectified.exr", "sums.exr"}) {
        const msmcl::io::ExrImage image = msmcl::io::read_exr(out(file));
        EXPECT_EQ(image.width, 64);
        EXPECT_EQ(image.height, 64);
        EXPECT_EQ(image.channels.size(), 4u) << file;
        EXPECT_NE(image.find_channel("b4"), nullptr) << file;
    }
    // The prefix sums of a row start with its first resampled texel.
    const std::vector<float> b1 = channel(out("rectified.exr"), "b1"), s1 = channel(out("sums.exr"), "b1");
    for (int row = 0; row < 64; row += 7) EXPECT_NEAR(s1[row * 64], b1[row * 64], 2e-5);
}

TEST_F(ScatterCli, MalformedJsonAndZeroExtinction) {
    write_scene("broken.json", text_.substr(0, text_.size() / 3));
    expect_bad_input({in("broken.json"), in("shadow.exr"), in("camera.exr"), out("r.exr")}, in("broken.json"),
                     "malformed JSON: parse error at line");
    nlohmann::json document = nlohmann::json::parse(text_);
    document["medium"]["extinction"] = 0;
    write_scene("clear.json", document.dump());
    expect_bad_input({in("clear.json"), in("shadow.exr"), in("camera.exr"), out("r.exr")}, in("clear.json"),
                     "medium.extinction: must be > 0");
    document = nlohmann::json::parse(text_);
    document["camera"].erase("near");
    write_scene("no_near.json", document.dump());
    expect_bad_input({in("no_near.json"), in("shadow.exr"), in("camera.exr"), out("r.exr")}, in("no_near.json"),
                     "camera: missing key \"near\"");
}

TEST_F(ScatterCli, HostileJsonIsBadInputNamingTheFile) {
    const std::vector<std::string> rest{in("shadow.exr"), in("camera.exr"), out("r.exr")};
    const auto arguments = [&](const std::string& scene) {
        std::vector<std::string> a{in(scene)};
        a.insert(a.end(), rest.begin(), rest.end());
        return a;
    };
    // 100000 nested arrays in a key's value: refused at the depth limit, no stack overflow
    // (neither while parsing nor while describing the value in a message).
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    write_scene("deep.json", "{\"medium\": " + deep + "}");
    expect_bad_input(arguments("deep.json"), in("deep.json"), "nested deeper than 64 levels");
    // Just under the limit: parsed, then refused for its type with a short message.
    nlohmann::json document = nlohmann::json::parse(text_);
    document["medium"] = nlohmann::json::parse(std::string(60, '[') + std::string(60, ']'));
    write_scene("nested.json", document.dump());
    expect_bad_input(arguments("nested.json"), in("nested.json"), "medium: expected an object, got an array of 1");
    // A number beyond double's range is a parse error of the file, not a runtime failure.
    document = nlohmann::json::parse(text_);
    std::string text = document.dump();
    const std::string extinction = "\"extinction\":";
    text.insert(text.find(extinction) + extinction.size(), "1e400");
    text.erase(text.find(extinction) + extinction.size() + 5, text.find_first_of(",}", text.find(extinction)) -
                                                                  (text.find(extinction) + extinction.size() + 5));
    write_scene("overflow.json", text);
    expect_bad_input(arguments("overflow.json"), in("overflow.json"), "number overflow");
    // Wrong types deep inside an object (a string where an integer goes; an out-of-range
    // integer) keep the file name and exit 2.
    document = nlohmann::json::parse(text_);
    document["rectified"]["width"] = 18446744073709551615ull;
    write_scene("huge.json", document.dump());
    expect_bad_input(arguments("huge.json"), in("huge.json"), "rectified.width");
}

TEST_F(ScatterCli, CameraInsideGeometry) {
    // The camera moved into a pillar: the rendered depth buffer lies on the near plane.
    nlohmann::json document = nlohmann::json::parse(text_);
    document["camera"]["position"] = {-2.1, 1.5, -1.3};
    write_scene("inside.json", document.dump());
    const msmcl::ScatterScene inside = msmcl::parse_scatter_scene(document.dump());
    write_camera(in("inside.exr"), msmcl::scatter_data::render_camera_depth(inside, geometry_), inside.camera.width,
                 inside.camera.height);
    expect_bad_input({in("inside.json"), in("shadow.exr"), in("inside.exr"), out("r.exr")}, in("inside.exr"),
                     "the camera is inside geometry");
}

TEST_F(ScatterCli, WrongSizesAndOptions) {
    write_camera(in("small.exr"), std::vector<float>(64 * 48, 0.99f), 64, 48);
    expect_bad_input({in("scene.json"), in("shadow.exr"), in("small.exr"), out("r.exr")}, in("small.exr"),
                     "the depth buffer is 64x48, the scene's camera 128x96");
    const std::vector<std::string> files{in("scene.json"), in("shadow.exr"), in("camera.exr"), out("r.exr")};
    const auto with = [&](std::vector<std::string> extra) {
        std::vector<std::string> a = files;
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    };
    expect_bad_input(with({"--moments", "5"}), "", "--moments must be 4 or 6");
    expect_bad_input(with({"--beta", "1.5"}), "", "--beta must be adaptive or in [0, 1]");
    expect_bad_input(with({"--sigma", "-1"}), "", "--sigma must be >= 0");
    expect_bad_input(with({"--ray-march", "0"}), "", "--ray-march must be an integer");
    expect_bad_input(with({"--ray-march", "16", "--rectified", out("x.exr")}), "", "need the prefiltered method");
    expect_bad_input(with({"--kernel", "rows"}), "", "unknown --kernel 'rows' (expected automatic, rows_gpu or rows_cpu)");
    expect_bad_input(with({"--filter-kernel", "gpu"}), "", "unknown --filter-kernel 'gpu'");
    expect_bad_input({in("scene.json"), in("missing.exr"), in("camera.exr"), out("r.exr")}, in("missing.exr"), "");
}

TEST_F(ScatterCli, SceneToolIsDeterministic) {
    if (!fs::exists(scene_tool)) GTEST_SKIP() << scene_tool << " not built";
    for (const char* name : {"a", "b"}) {
        const ProcessResult result = run({scene_tool, in("scene.json"), "--map-size", "64", "--shadow-map",
                                          out(std::string(name) + "_shadow.exr"), "--camera-depth",
                                          out(std::string(name) + "_camera.exr")});
        ASSERT_EQ(result.exit_code, 0) << result.err;
    }
    EXPECT_EQ(msmcl::io::read_whole_file(out("a_shadow.exr")), msmcl::io::read_whole_file(out("b_shadow.exr")));
    EXPECT_EQ(msmcl::io::read_whole_file(out("a_camera.exr")), msmcl::io::read_whole_file(out("b_camera.exr")));
    // The camera depth it writes is the one the tests render.
    EXPECT_EQ(channel(out("a_camera.exr"), "Z"), camera_);
    write_scene("broken.json", "{");
    const ProcessResult bad = run({scene_tool, in("broken.json"), "--shadow-map", out("x.exr")});
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find("malformed JSON"), std::string::npos) << bad.err;
}

} // namespace
