// msmcl-vulkan (examples/vulkan) against msmcl's own commands: KTX2 textures uploaded into
// VkImages of the formats in docs/shaders.md and sampled by shaders/msm.glsl and shaders/msm.hlsl on
// a Vulkan device (lavapipe in CI), compared with `msmcl shade`, `msmcl soft` and
// `msmcl scatter` (OpenCL, PoCL in CI) on the same inputs (shade and soft read the very same
// KTX2 files): every format, every lookup, both shading languages, the summed-area table
// and the prefiltered scattering maps.
//
// Inputs: the shipped railing map and view, and a map no other test uses: random boxes
// over a sloped ground at 97 x 71 texels, 2 samples, with random receivers (some outside
// the map, to check clamp-to-edge) and random screen pixels for the dithered lookup.
// Seed: MSMCL_TEST_SEED (default 14), printed.
//
// Skips only when the machine has no Vulkan device; with MSMCL_REQUIRE_VULKAN=1 (CI) that
// is a failure instead.
#include "io/exr_io.hpp"
#include "io/ktx2.hpp"
#include "io/sat_exr.hpp"
#include "kernels/msm_scatter.clh"
#include "kernels/msm_shading.clh"
#include "tests/seeded_test.hpp"

#include <msmcl/device_math.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <random>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;

// The run's seed (tests/seeded_test.hpp: MSMCL_TEST_SEED, else 14; printed once), recorded
// per test. The random map is the same for every test of a run.
unsigned test_seed() {
    const auto seed = static_cast<unsigned>(msmcl::testing::run_seed(14));
    testing::Test::RecordProperty("seed", std::to_string(seed));
    return seed;
}

std::string quoted(const std::string& text) { return "'" + text + "'"; }

// Runs a command line; its exit code (-1 when it did not exit normally).
int run(const std::string& command) {
    const int status = std::system((command + " > /dev/null").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void run_ok(const std::string& command) { ASSERT_EQ(run(command), 0) << command; }

std::string cli() { return quoted(MSMCL_CLI_PATH); }
std::string vulkan(bool hlsl) { return quoted(MSMCL_VULKAN_PATH) + (hlsl ? " --hlsl" : ""); }

// Whether a Vulkan device exists: msmcl-vulkan devices exits 3 when there is none.
bool vulkan_device_present() {
    static const int code = run(quoted(MSMCL_VULKAN_PATH) + " devices 2> /dev/null");
    return code == 0;
}

#define REQUIRE_VULKAN_DEVICE()                                                                                  \
    do {                                                                                                         \
        if (!vulkan_device_present()) {                                                                          \
            const char* required = std::getenv("MSMCL_REQUIRE_VULKAN");                                          \
            if (required && std::string(required) == "1") FAIL() << "MSMCL_REQUIRE_VULKAN=1 but no Vulkan device"; \
            GTEST_SKIP() << "no Vulkan device (Debian: mesa-vulkan-drivers installs lavapipe)";                 \
        }                                                                                                        \
    } while (0)

std::vector<float> read_y(const std::string& path) {
    const msmcl::io::ExrImage image = msmcl::io::read_exr(path);
    const msmcl::io::ExrChannel* y = image.find_channel("Y");
    return y ? y->values : std::vector<float>{};
}

// Differences of b against a: largest, root mean square, count above a threshold.
struct Difference {
    double largest = 0, rms = 0;
    std::size_t above_1e3 = 0, above_1e2 = 0, count = 0;
};
Difference difference(const std::vector<float>& a, const std::vector<float>& b) {
    Difference d;
    d.count = a.size();
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
        const double e = std::fabs(static_cast<double>(b[i]) - a[i]);
        d.largest = std::isnan(e) ? INFINITY : std::max(d.largest, e);
        d.rms += e * e;
        d.above_1e3 += e > 1e-3;
        d.above_1e2 += e > 1e-2;
    }
    d.rms = a.empty() ? 0 : std::sqrt(d.rms / a.size());
    return d;
}
void print(const std::string& what, const Difference& d) {
    std::printf("  %-44s max %.3g  rms %.3g  > 1e-3: %zu  > 1e-2: %zu  (of %zu)\n", what.c_str(), d.largest, d.rms,
                d.above_1e3, d.above_1e2, d.count);
}

// A scratch folder per test.
struct Scratch {
    fs::path dir;
    Scratch() {
        const testing::TestInfo* info = testing::UnitTest::GetInstance()->current_test_info();
        std::string name = std::string(info->test_suite_name()) + "_" + info->name();
        std::replace(name.begin(), name.end(), '/', '_');
        dir = fs::temp_directory_path() / ("msmcl-vulkan-" + std::to_string(::getpid()) + "-" + name);
        fs::create_directories(dir);
    }
    ~Scratch() { fs::remove_all(dir); }
    std::string operator/(const std::string& file) const { return (dir / file).string(); }
};

// ---- Inputs.
struct Inputs {
    std::string depth, receivers;
};

// Random boxes above a sloped ground, receivers on the ground (a map no other test uses).
Inputs random_scene(const Scratch& scratch) {
    std::mt19937 random(test_seed());
    const int width = 97, height = 71, samples = 2;
    msmcl::DepthImage depth{width, height, samples, {}};
    depth.depth.resize(static_cast<std::size_t>(width) * height * samples);
    const auto ground = [&](double x, double y) { return 0.80 + 0.12 * x / width - 0.05 * y / height; };
    struct Box {
        double x0, y0, x1, y1, z;
    };
    std::vector<Box> boxes;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int b = 0; b < 9; ++b) {
        const double x = unit(random) * width, y = unit(random) * height;
        boxes.push_back({x, y, x + 4 + unit(random) * 18, y + 4 + unit(random) * 14, 0.15 + 0.55 * unit(random)});
    }
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int s = 0; s < samples; ++s) {
                // Sample positions of a 2x pattern: (0.25, 0.25), (0.75, 0.75) in the texel.
                const double px = x + 0.25 + 0.5 * s, py = y + 0.25 + 0.5 * s;
                double z = ground(px, py);
                for (const Box& box : boxes)
                    if (px >= box.x0 && px < box.x1 && py >= box.y0 && py < box.y1) z = std::min(z, box.z);
                depth.depth[(static_cast<std::size_t>(y) * width + x) * samples + s] = static_cast<float>(z);
            }
    Inputs inputs{scratch / "random_depth.exr", scratch / "random_receivers.exr"};
    msmcl::io::write_depth_exr(inputs.depth, depth);

    msmcl::io::ReceiverGrid grid;
    grid.width = 64;
    grid.height = 48;
    std::uniform_int_distribution<std::uint32_t> pixel(0, 511);
    for (int i = 0; i < grid.width * grid.height; ++i) {
        const float u = static_cast<float>(-3.0 + unit(random) * (width + 6)),
                    v = static_cast<float>(-3.0 + unit(random) * (height + 6));
        grid.points.u.push_back(u);
        grid.points.v.push_back(v);
        grid.points.z.push_back(static_cast<float>(ground(u, v)));
        grid.pixels.x.push_back(pixel(random));
        grid.pixels.y.push_back(pixel(random));
    }
    msmcl::io::write_receivers_exr(inputs.receivers, grid);
    return inputs;
}

Inputs inputs_of(const std::string& scene, const Scratch& scratch) {
    if (scene == "railing")
        return {std::string(MSMCL_SOURCE_DIR) + "/data/railing_256x256_4x.exr",
                std::string(MSMCL_SOURCE_DIR) + "/data/railing_view_160x120.exr"};
    return random_scene(scratch);
}

// ---- The float32 fast 4MSM of msm.glsl's linear formats, run on the host (the functions
// of kernels/msm_shading.clh compiled as C++): what the shaders compute, in exact IEEE
// float32, for every receiver and lookup (hardware filtering aside).
// weight_bits > 0: the bilinear weights rounded to that many fractional bits, as a sampler
// with subTexelPrecisionBits = weight_bits blends.
std::vector<float> host_fast_path(const msmcl::Texture& map, const msmcl::io::ReceiverGrid& grid, int lookup,
                                  std::uint32_t frame, float depth_bias, int weight_bits = 0) {
    const auto texel = [&](int x, int y) {
        const std::uint32_t* w = map.words.data() + msmcl::texel_words(map.format) * (static_cast<std::size_t>(y) * map.width + x);
        if (map.format == msmcl::Format::msm64) return msm_decode_msm64(msm_word2{w[0], w[1]});
        msm_moments m;
        std::memcpy(&m, w, sizeof m);
        return m;
    };
    const auto shade = [&](msm_moments m, float zf) {
        return map.format == msmcl::Format::msm64 ? msm_shadow_msm64_decoded_fast(m, zf)
                                                  : msm_shadow_moments128_fast(m, zf);
    };
    std::vector<float> out(grid.points.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
        const float u = grid.points.u[i], v = grid.points.v[i];
        const float zf = msm_internal_depth(grid.points.z[i], 1) - depth_bias;
        if (lookup == 1) {
            msm_bilinear_taps k = msm_bilinear_taps_at(u, v, map.width, map.height);
            if (weight_bits > 0) {
                const float steps = std::ldexp(1.0f, weight_bits);
                k.tx = std::nearbyint(k.tx * steps) / steps;
                k.ty = std::nearbyint(k.ty * steps) / steps;
            }
            out[i] = shade(msm_moments_bilinear(texel(k.x0, k.y0), texel(k.x1, k.y0), texel(k.x0, k.y1),
                                                texel(k.x1, k.y1), k.tx, k.ty),
                           zf);
        } else if (lookup == 2) {
            const std::uint32_t px = grid.pixels.x.empty() ? static_cast<std::uint32_t>(i % grid.width) : grid.pixels.x[i];
            const std::uint32_t py = grid.pixels.y.empty() ? static_cast<std::uint32_t>(i / grid.width) : grid.pixels.y[i];
            const msmcl::DitherNoise noise = msmcl::blue_noise_at(frame, px, py);
            out[i] = shade(texel(msm_dither_index(u, noise.x, map.width), msm_dither_index(v, noise.y, map.height)), zf);
        } else {
            out[i] = shade(texel(msm_texel_index(u, map.width), msm_texel_index(v, map.height)), zf);
        }
    }
    return out;
}

// ---- Shading: every format, lookup and language.
//
// Tolerances, each with its reason:
//  - kDeviceRounding (nlq64, nlq32 against msmcl shade; moments128, msm64 against the same
//    fast path on the host): the shaders run the same float32 operations in the same order
//    as msmcl's kernels (tests/shaders_test.cpp: bit-identical on the CPU), and the UNORM16
//    and integer fetches return the codes exactly; what remains is the Vulkan device's float
//    arithmetic (Vulkan allows 2.5 ULP for division, approximate exp/log, and fused
//    multiply-adds wherever the compiler likes). Measured on lavapipe: at most 2.1e-6 for
//    nlq64/nlq32. The moments128 fast path amplifies those ULPs where its biased variance is
//    ill-conditioned (contact shadows), hence the separate kFastPathRounding.
//  - kMsm64FastPath (msm64 against msmcl shade): the shaders use the float32 Hamburger 4MSM
//    (HLSL has no exact fused multiply-add for float-float); msmcl's kernel shades in
//    float-float. The float32 decode and pivots are off by up to ~1e-3 (measured 3.3e-4).
//  - moments128 against msmcl shade: the fast path's bias (3e-7) is below float32 rounding,
//    and contact shadows come out up to 0.49 off (kernels/msm_shading.clh documents it); the
//    test asserts only the share of receivers off by more than 1e-2 and prints the figures.
//    The shaders' accurate path (msm_lookup_moments128_accurate: float-float with Dekker's
//    TwoProd and `precise`) must then agree within kDeviceRounding (measured: 2.7e-7).
//  - kHardwareBilinear (lookup `hardware`, one textureLod through the linear sampler,
//    against the texelFetch bilinear of the same shader): Vulkan lets the sampler's
//    bilinear weights carry as few as 8 fractional bits (lavapipe: subTexelPrecisionBits 8),
//    so the moments blend differs from the float32 weights by up to 2^-9 of the texels'
//    difference; the shadow follows smoothly except at depth discontinuities. The same
//    bounds hold for weights rounded to 8 bits on the host (what a GPU with the minimum
//    precision gives), checked here too. moments128's ill-conditioned fast path amplifies
//    the weights' rounding: measured max 0.031 / rms 6.4e-4 on lavapipe and 0.054 / 3.0e-3
//    with 8-bit weights (railing); msm64: 2.3e-4 / 9.3e-6 and 8.2e-4 / 9.2e-5.
constexpr double kDeviceRounding = 1e-4;
constexpr double kFastPathRounding = 2e-3;
constexpr double kMsm64FastPath = 2e-3;
constexpr double kMoments128ShareAbove1e2 = 0.03;
constexpr double kHardwareBilinearMax[2] = {0.1, 2e-3}; // moments128, msm64
constexpr double kHardwareBilinearRms[2] = {5e-3, 2e-4};

struct ShadeCase {
    const char* scene;
    const char* format;
};
void PrintTo(const ShadeCase& shade_case, std::ostream* out) { *out << shade_case.scene << ' ' << shade_case.format; }
std::string shade_case_name(const testing::TestParamInfo<ShadeCase>& info) {
    return std::string(info.param.scene) + "_" + info.param.format;
}

class VulkanShade : public testing::TestWithParam<ShadeCase> {};

TEST_P(VulkanShade, EveryLookupAndLanguageAgreesWithMsmclShade) {
    REQUIRE_VULKAN_DEVICE();
    test_seed();
    const Scratch scratch;
    const Inputs inputs = inputs_of(GetParam().scene, scratch);
    const std::string format = GetParam().format;
    const bool linear = format == "moments128" || format == "msm64";
    // One KTX2 file, read by msmcl shade and by the Vulkan consumer alike.
    const std::string ktx2 = scratch / "map.ktx2";
    run_ok(cli() + " filter " + quoted(inputs.depth) + " " + quoted(ktx2) + " --format " + format);
    if (HasFatalFailure()) return;
    const msmcl::Texture texture =
        msmcl::io::texture_of(msmcl::io::read_ktx2(ktx2), *msmcl::parse_format(format), ktx2);
    const msmcl::io::ReceiverGrid grid = msmcl::io::read_receivers_exr(inputs.receivers);
    std::printf("%s %s: %zu receivers\n", GetParam().scene, format.c_str(), grid.points.size());

    const char* lookups[] = {"nearest", "bilinear", "dither"};
    const std::string frame = "5";
    for (int lookup = 0; lookup < 3; ++lookup) {
        const std::string options = std::string(" --lookup ") + lookups[lookup] + " --frame " + frame;
        const std::string reference = scratch / (std::string("cl_") + lookups[lookup] + ".exr");
        run_ok(cli() + " shade " + quoted(ktx2) + " " + quoted(inputs.receivers) + " " + quoted(reference) + options);
        if (HasFatalFailure()) return;
        const std::vector<float> expected = read_y(reference);
        ASSERT_EQ(expected.size(), grid.points.size());
        for (bool hlsl : {false, true}) {
            const std::string what = std::string(hlsl ? "hlsl " : "glsl ") + lookups[lookup];
            const std::string out = scratch / (std::string(hlsl ? "hlsl_" : "glsl_") + lookups[lookup] + ".exr");
            run_ok(vulkan(hlsl) + " shade " + quoted(ktx2) + " " + quoted(inputs.receivers) + " " + quoted(out) + options);
            if (HasFatalFailure()) return;
            const std::vector<float> shadow = read_y(out);
            ASSERT_EQ(shadow.size(), expected.size()) << what;
            const Difference against_msmcl = difference(expected, shadow);
            print(what + " vs msmcl shade", against_msmcl);
            if (!linear) {
                EXPECT_LE(against_msmcl.largest, kDeviceRounding) << what;
                continue;
            }
            // The linear formats: the shader's fast path reproduced on the host, then msmcl's.
            const Difference against_fast = difference(host_fast_path(texture, grid, lookup, 5, 1e-3f), shadow);
            print(what + " vs float32 fast path (host)", against_fast);
            EXPECT_LE(against_fast.rms, kDeviceRounding) << what;
            EXPECT_LE(against_fast.largest, kFastPathRounding) << what;
            if (format == "msm64") {
                EXPECT_LE(against_msmcl.largest, kMsm64FastPath) << what;
                continue;
            }
            EXPECT_LE(against_msmcl.above_1e2, kMoments128ShareAbove1e2 * against_msmcl.count) << what;
            // The fix the shaders offer: msm_lookup_moments128_accurate, float-float as msmcl.
            const std::string accurate = scratch / "accurate.exr";
            run_ok(vulkan(hlsl) + " shade " + quoted(ktx2) + " " + quoted(inputs.receivers) + " " + quoted(accurate) +
                   options + " --accurate");
            if (HasFatalFailure()) return;
            const Difference fixed = difference(expected, read_y(accurate));
            print(what + " accurate vs msmcl shade", fixed);
            EXPECT_LE(fixed.largest, kDeviceRounding) << what;
        }
    }
    if (!linear) return;
    // Bilinear weights of 8 fractional bits, emulated on the host, against float32 weights.
    const Difference quantized = difference(host_fast_path(texture, grid, 1, 0, 1e-3f),
                                            host_fast_path(texture, grid, 1, 0, 1e-3f, 8));
    print("host: 8-bit vs float32 bilinear weights", quantized);
    const int linear_index = format == "moments128" ? 0 : 1;
    EXPECT_LE(quantized.largest, kHardwareBilinearMax[linear_index]);
    EXPECT_LE(quantized.rms, kHardwareBilinearRms[linear_index]);
    // The engine's bilinear: one hardware-filtered textureLod / SampleLevel through the
    // linear sampler, against the same shader's texelFetch bilinear.
    for (bool hlsl : {false, true}) {
        const std::string fetched = scratch / "fetched.exr", filtered = scratch / "filtered.exr";
        run_ok(vulkan(hlsl) + " shade " + quoted(ktx2) + " " + quoted(inputs.receivers) + " " + quoted(fetched) +
               " --lookup bilinear");
        run_ok(vulkan(hlsl) + " shade " + quoted(ktx2) + " " + quoted(inputs.receivers) + " " + quoted(filtered) +
               " --lookup hardware");
        if (HasFatalFailure()) return;
        const Difference d = difference(read_y(fetched), read_y(filtered));
        print(std::string(hlsl ? "hlsl" : "glsl") + " hardware vs texelFetch bilinear", d);
        EXPECT_LE(d.largest, kHardwareBilinearMax[linear_index]);
        EXPECT_LE(d.rms, kHardwareBilinearRms[linear_index]);
    }
}

INSTANTIATE_TEST_SUITE_P(Maps, VulkanShade,
                         testing::Values(ShadeCase{"railing", "moments128"}, ShadeCase{"railing", "msm64"},
                                         ShadeCase{"railing", "nlq64"}, ShadeCase{"railing", "nlq32"},
                                         ShadeCase{"random", "moments128"}, ShadeCase{"random", "msm64"},
                                         ShadeCase{"random", "nlq64"}, ShadeCase{"random", "nlq32"}),
                         shade_case_name);

// ---- Texture arrays: `msmcl filter A B --array arr.ktx2` shaded layer by layer through a
// sampler2DArray (Texture2DArray in HLSL) against the 2D shaders on `msmcl filter A a.ktx2`.
// Same texels, same functions (tests/shaders_test.cpp: the array lookups equal the 2D ones of
// the layer bit for bit on the CPU), so the tolerances are those of the Vulkan device's
// rounding above: kDeviceRounding (largest) for nlq64/nlq32, and for the fast 4MSM of
// moments128/msm64 kDeviceRounding as rms and kFastPathRounding as the largest difference.
// Measured on lavapipe: GLSL array against GLSL 2D 0 for every format and lookup; HLSL
// array against the GLSL 2D map at most 2.5e-6 (nlq32; the two languages compile apart).
class VulkanShadeArray : public testing::TestWithParam<const char*> {};

TEST_P(VulkanShadeArray, EveryLayerAgreesWithThe2DMapOfItsInput) {
    REQUIRE_VULKAN_DEVICE();
    const Scratch scratch;
    const std::string format = GetParam();
    const bool linear = format == "moments128" || format == "msm64";
    const std::string data = std::string(MSMCL_SOURCE_DIR) + "/data/";
    const std::vector<std::string> inputs = {data + "railing_256x256_4x.exr", data + "wuson_256x256_4x.exr"};
    const std::string receivers = data + "railing_view_160x120.exr";
    // One array of both maps, and each map alone.
    const std::string array = scratch / "array.ktx2";
    run_ok(cli() + " filter " + quoted(inputs[0]) + " " + quoted(inputs[1]) + " --array " + quoted(array) + " --format " +
           format);
    std::vector<std::string> singles;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        singles.push_back(scratch / ("map" + std::to_string(i) + ".ktx2"));
        run_ok(cli() + " filter " + quoted(inputs[i]) + " " + quoted(std::as_const(singles).back()) + " --format " + format);
    }
    if (HasFatalFailure()) return;
    ASSERT_EQ(msmcl::io::read_ktx2(array).layers, 2);

    std::vector<std::string> options = {" --lookup nearest", " --lookup bilinear", " --lookup dither --frame 5"};
    if (linear) options.push_back(" --lookup hardware");
    if (format == "moments128") options.push_back(" --lookup bilinear --accurate");
    for (const std::string& option : options) {
        // The 2D shader on each map alone.
        std::vector<std::vector<float>> expected;
        for (std::size_t i = 0; i < singles.size(); ++i) {
            const std::string out = scratch / ("single" + std::to_string(i) + ".exr");
            run_ok(vulkan(false) + " shade " + quoted(std::as_const(singles)[i]) + " " + quoted(receivers) + " " + quoted(out) + option);
            if (HasFatalFailure()) return;
            expected.push_back(read_y(out));
        }
        for (bool hlsl : {false, true}) {
            // Every layer in one call: channels layer<i>.Y.
            const std::string out = scratch / "layers.exr";
            run_ok(vulkan(hlsl) + " shade " + quoted(array) + " " + quoted(receivers) + " " + quoted(out) + option);
            if (HasFatalFailure()) return;
            const msmcl::io::ExrImage shaded = msmcl::io::read_exr(out);
            for (std::size_t i = 0; i < singles.size(); ++i) {
                const std::string what = format + (hlsl ? " hlsl" : " glsl") + option + ", layer " + std::to_string(i);
                const msmcl::io::ExrChannel* layer = shaded.find_channel("layer" + std::to_string(i) + ".Y");
                ASSERT_NE(layer, nullptr) << what;
                ASSERT_EQ(layer->values.size(), expected[i].size()) << what;
                const Difference d = difference(expected[i], layer->values);
                print(what + " vs 2D", d);
                if (linear) {
                    EXPECT_LE(d.rms, kDeviceRounding) << what;
                    EXPECT_LE(d.largest, kFastPathRounding) << what;
                } else {
                    EXPECT_LE(d.largest, kDeviceRounding) << what;
                }
            }
        }
    }
    // One chosen layer: channel Y, the same values as in the all-layers file (same run, same bits).
    const std::string one = scratch / "one.exr", all = scratch / "all.exr";
    run_ok(vulkan(false) + " shade " + quoted(array) + " " + quoted(receivers) + " " + quoted(one) + " --layer 1");
    run_ok(vulkan(false) + " shade " + quoted(array) + " " + quoted(receivers) + " " + quoted(all) + " --layer all");
    if (HasFatalFailure()) return;
    const msmcl::io::ExrImage all_layers = msmcl::io::read_exr(all);
    const msmcl::io::ExrChannel* layer1 = all_layers.find_channel("layer1.Y");
    ASSERT_NE(layer1, nullptr);
    EXPECT_TRUE(read_y(one) == layer1->values);
}

INSTANTIATE_TEST_SUITE_P(Formats, VulkanShadeArray, testing::Values("moments128", "msm64", "nlq64", "nlq32"),
                         [](const testing::TestParamInfo<const char*>& info) { return std::string(info.param); });

// ---- Soft shadows from the R32G32B32A32_UINT summed-area table.
//
// kSoftRounding: the same float32 operations as msmcl's sat_soft_shade kernel (texelFetch of
// exact integers, wrapping uint32 sums); the 4MSM with alpha 5e-6 amplifies the Vulkan
// device's rounding (fused multiply-adds, division within 2.5 ULP) in the penumbrae.
// Measured on lavapipe: at most 4.0e-3 (railing), rms 1.7e-4.
constexpr double kSoftMax = 2e-2;
constexpr double kSoftRms = 1e-3;

class VulkanSoft : public testing::TestWithParam<const char*> {};

TEST_P(VulkanSoft, SatSoftShadowsAgreeWithMsmclSoft) {
    REQUIRE_VULKAN_DEVICE();
    test_seed();
    const Scratch scratch;
    const Inputs inputs = inputs_of(GetParam(), scratch);
    // One KTX2 table, read by msmcl soft and by the Vulkan consumer alike.
    const std::string ktx2 = scratch / "sat.ktx2", reference = scratch / "cl.exr";
    const std::string options = " --light-size 40 --depth-bias 0.02";
    run_ok(cli() + " sat " + quoted(inputs.depth) + " " + quoted(ktx2) + " --max-kernel 729");
    run_ok(cli() + " soft " + quoted(ktx2) + " " + quoted(inputs.receivers) + " " + quoted(reference) + options);
    if (HasFatalFailure()) return;
    const msmcl::io::GpuImage table = msmcl::io::read_ktx2(ktx2);
    EXPECT_EQ(table.format, msmcl::io::GpuFormat::r32g32b32a32_uint);
    const std::vector<float> expected = read_y(reference);
    for (bool hlsl : {false, true}) {
        const std::string out = scratch / "vk.exr";
        run_ok(vulkan(hlsl) + " soft " + quoted(ktx2) + " " + quoted(inputs.receivers) + " " + quoted(out) + options);
        if (HasFatalFailure()) return;
        const std::vector<float> shadow = read_y(out);
        ASSERT_EQ(shadow.size(), expected.size());
        const Difference d = difference(expected, shadow);
        print(std::string(GetParam()) + (hlsl ? " hlsl" : " glsl") + " soft vs msmcl soft", d);
        EXPECT_LE(d.largest, kSoftMax);
        EXPECT_LE(d.rms, kSoftRms);
    }
}

std::string text_name(const testing::TestParamInfo<const char*>& info) { return info.param; }

INSTANTIATE_TEST_SUITE_P(Maps, VulkanSoft, testing::Values("railing", "random"), text_name);

// ---- Single scattering from the prefiltered map: six moments in two
// A2B10G10R10_UNORM_PACK32 layers, four in one R16G16B16A16_UNORM image.
//
// kScatterRelative (of the image's largest radiance): msmcl's kernel blends the decoded
// moments of four texels with float32 weights; the shader lets the sampler blend the UNORM10
// (UNORM16) channels (decoding is affine, so only the weights' precision differs: at least 8
// fractional bits) and runs the same float32 bounds. Measured on lavapipe: 9.5e-6 absolute
// at radiances up to 3.6 (six moments).
constexpr double kScatterRelative = 2e-3;

struct ScatterCase {
    const char* scene;
    int moments;
};
void PrintTo(const ScatterCase& c, std::ostream* out) { *out << c.scene << ' ' << c.moments << " moments"; }
std::string scatter_case_name(const testing::TestParamInfo<ScatterCase>& info) {
    return std::string(info.param.scene) + "_" + std::to_string(info.param.moments);
}

class VulkanScatter : public testing::TestWithParam<ScatterCase> {};

TEST_P(VulkanScatter, PrefilteredScatteringAgreesWithMsmclScatter) {
    REQUIRE_VULKAN_DEVICE();
    const Scratch scratch;
    const std::string name = GetParam().scene;
    const std::string moments = std::to_string(GetParam().moments);
    const std::string scene = scratch / "scene.json", shadow_map = scratch / "shadow.exr",
                      camera = scratch / "camera.exr", map = scratch / "map.ktx2", reference = scratch / "cl.exr";
    run_ok(quoted(MSMCL_SCATTER_SCENE_PATH) + " " + quoted(std::string(MSMCL_SOURCE_DIR) + "/data/scatter/" + name + ".json") +
           " --map-size 256 --camera-width 96 --camera-height 72 --rectified-size 128 --write-scene " + quoted(scene) +
           " --shadow-map " + quoted(shadow_map) + " --camera-depth " + quoted(camera));
    run_ok(cli() + " scatter " + quoted(scene) + " " + quoted(shadow_map) + " " + quoted(camera) + " " +
           quoted(reference) + " --moments " + moments + " --map " + quoted(map));
    if (HasFatalFailure()) return;
    const msmcl::io::GpuImage image = msmcl::io::read_ktx2(map);
    EXPECT_EQ(image.format, GetParam().moments == 6 ? msmcl::io::GpuFormat::a2b10g10r10_unorm_pack32
                                                    : msmcl::io::GpuFormat::r16g16b16a16_unorm);
    EXPECT_EQ(image.layers, GetParam().moments == 6 ? 2 : 1);
    const std::vector<float> expected = read_y(reference);
    const double brightest = *std::max_element(expected.begin(), expected.end());
    ASSERT_GT(brightest, 0.0);
    for (bool hlsl : {false, true}) {
        const std::string out = scratch / "vk.exr";
        run_ok(vulkan(hlsl) + " scatter " + quoted(scene) + " " + quoted(map) + " " + quoted(camera) + " " + quoted(out));
        if (HasFatalFailure()) return;
        const std::vector<float> radiance = read_y(out);
        ASSERT_EQ(radiance.size(), expected.size());
        const Difference d = difference(expected, radiance);
        print(name + " " + moments + (hlsl ? " hlsl" : " glsl") + " scatter vs msmcl scatter (brightest " + std::to_string(brightest) + ")", d);
        EXPECT_LE(d.largest, kScatterRelative * brightest);
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, VulkanScatter,
                         testing::Values(ScatterCase{"hall", 6}, ScatterCase{"pergola", 6}, ScatterCase{"hall", 4}),
                         scatter_case_name);

// ---- The KTX2 outputs the consumer reads hold exactly what msmcl's EXR outputs hold (no
// Vulkan device needed).
TEST(MsmclKtx2Outputs, SatTableIsTheTableOfTheExrFile) {
    const Scratch scratch;
    const std::string depth = std::string(MSMCL_SOURCE_DIR) + "/data/railing_256x256_4x.exr";
    const std::string exr = scratch / "sat.exr", ktx2 = scratch / "sat.ktx2";
    run_ok(cli() + " sat " + quoted(depth) + " " + quoted(exr) + " --max-kernel 1000");
    run_ok(cli() + " sat " + quoted(depth) + " " + quoted(ktx2) + " --max-kernel 1000");
    if (HasFatalFailure()) return;
    const msmcl::io::SatFile table = msmcl::io::read_sat_exr(exr);
    const msmcl::io::GpuImage image = msmcl::io::read_ktx2(ktx2);
    EXPECT_EQ(image.format, msmcl::io::GpuFormat::r32g32b32a32_uint);
    EXPECT_EQ(image.width, table.table.width);
    EXPECT_EQ(image.height, table.table.height);
    EXPECT_EQ(image.find_metadata("msmcl:format"), std::optional<std::string>("sat"));
    EXPECT_EQ(image.find_metadata("msmcl:maxKernelTexels"), std::optional<std::string>("1000"));
    EXPECT_EQ(image.find_metadata("msmcl:scale"), std::optional<std::string>(std::to_string(table.table.scale)));
    EXPECT_EQ(image.find_metadata("msmcl:depthRange"), std::optional<std::string>("0,1"));
    ASSERT_EQ(image.bytes.size(), table.table.words.size() * 4);
    EXPECT_EQ(std::memcmp(image.bytes.data(), table.table.words.data(), image.bytes.size()), 0);
}

TEST(MsmclKtx2Outputs, ScatterMapDecodesToTheStoredPrefixSums) {
    const Scratch scratch;
    const std::string scene = scratch / "scene.json", shadow_map = scratch / "shadow.exr",
                      camera = scratch / "camera.exr", map = scratch / "map.ktx2", sums = scratch / "sums.exr";
    run_ok(quoted(MSMCL_SCATTER_SCENE_PATH) + " " + quoted(std::string(MSMCL_SOURCE_DIR) + "/data/scatter/hall.json") +
           " --map-size 128 --camera-width 32 --camera-height 24 --rectified-size 64 --write-scene " + quoted(scene) +
           " --shadow-map " + quoted(shadow_map) + " --camera-depth " + quoted(camera));
    run_ok(cli() + " scatter " + quoted(scene) + " " + quoted(shadow_map) + " " + quoted(camera) + " " +
           quoted(scratch / "out.exr") + " --moments 6 --map " + quoted(map) + " --prefix-sums " + quoted(sums));
    if (HasFatalFailure()) return;
    const msmcl::io::GpuImage image = msmcl::io::read_ktx2(map);
    const msmcl::io::ExrImage decoded = msmcl::io::read_exr(sums);
    ASSERT_EQ(image.format, msmcl::io::GpuFormat::a2b10g10r10_unorm_pack32);
    ASSERT_TRUE(image.array);
    ASSERT_EQ(image.layers, 2);
    ASSERT_EQ(image.width, decoded.width);
    ASSERT_EQ(image.height, decoded.height);
    // Layer 0 the odd powers, layer 1 the even ones: decoding a texel's two words gives the
    // prefix sums msmcl wrote as floats.
    const std::size_t texels = static_cast<std::size_t>(image.width) * image.height;
    std::vector<std::uint32_t> words(2 * texels);
    std::memcpy(words.data(), image.bytes.data(), image.bytes.size());
    for (std::size_t t = 0; t < texels; ++t) {
        const msm_moments6 m = msm_decode_moments6(msm_word_pair{words[t], words[texels + t]});
        const float expected[6] = {m.b1, m.b2, m.b3, m.b4, m.b5, m.b6};
        for (int k = 0; k < 6; ++k)
            ASSERT_EQ(decoded.find_channel("b" + std::to_string(k + 1))->values[t], expected[k]) << "texel " << t;
    }
}

// ---- Bad input: one line naming the file, exit 2, no output.
TEST(VulkanConsumer, RejectsATextureOfTheWrongKindWithExitCode2) {
    REQUIRE_VULKAN_DEVICE();
    const Scratch scratch;
    const std::string sat = scratch / "sat.ktx2", out = scratch / "out.exr";
    const std::string receivers = std::string(MSMCL_SOURCE_DIR) + "/data/railing_view_160x120.exr";
    run_ok(cli() + " sat " + quoted(std::string(MSMCL_SOURCE_DIR) + "/data/railing_256x256_4x.exr") + " " + quoted(sat));
    EXPECT_EQ(run(vulkan(false) + " shade " + quoted(sat) + " " + quoted(receivers) + " " + quoted(out) + " 2> /dev/null"), 2);
    EXPECT_FALSE(fs::exists(out));
    const std::string missing = scratch / "missing.ktx2";
    EXPECT_EQ(run(vulkan(false) + " shade " + quoted(missing) + " " + quoted(receivers) + " " + quoted(out) + " 2> /dev/null"),
              2);
    EXPECT_FALSE(fs::exists(out));
    // --layer: only for texture arrays, and only one of their layers.
    const std::string depth = std::string(MSMCL_SOURCE_DIR) + "/data/railing_256x256_4x.exr";
    const std::string map = scratch / "map.ktx2", array = scratch / "array.ktx2";
    run_ok(cli() + " filter " + quoted(depth) + " " + quoted(map) + " --format nlq32");
    run_ok(cli() + " filter " + quoted(depth) + " " + quoted(depth) + " --array " + quoted(array) + " --format nlq32");
    for (const std::string& bad : {quoted(map) + " " + quoted(receivers) + " " + quoted(out) + " --layer 0",
                                   quoted(array) + " " + quoted(receivers) + " " + quoted(out) + " --layer 2",
                                   quoted(array) + " " + quoted(receivers) + " " + quoted(out) + " --layer -1"}) {
        EXPECT_EQ(run(vulkan(false) + " shade " + bad + " 2> /dev/null"), 2) << bad;
        EXPECT_FALSE(fs::exists(out)) << bad;
    }
}

} // namespace
