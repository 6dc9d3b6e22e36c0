// Moment soft shadow mapping (Peters et al., i3D 2016, section 3) and its refinements
// (docs/soft_shadows.md) on the OpenCL device (PoCL in CI):
// against the same method evaluated by direct sums in long double, against brute-force
// percentage-closer soft shadows (PCSS) on the sample scenes (error statistics printed,
// bounds asserted), contact hardening, umbra and lit limits, the host build of the same
// device code, the device API with events, and bad input.
#include "reference/sat_reference.hpp"
#include "reference/soft_analysis.hpp"

#include "io/exr_io.hpp"
#include "io/sat_exr.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/sat.hpp>

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#ifndef MSMCL_CLI_PATH // built without the CLI: the CLI test skips
#define MSMCL_CLI_PATH ""
#endif

#include "seeded_test.hpp"

namespace {

namespace ref = msmcl::reference;
using msmcl::DepthImage;
using msmcl::DepthRange;
using msmcl::SatTable;
using msmcl::SoftShadowOptions;

class SoftTest : public msmcl::testing::DeviceSuite<SoftTest> {};

constexpr std::uint32_t kMaxKernel = 27 * 27;

ref::DepthMap reference_map(const DepthImage& depth) {
    ref::DepthMap map;
    map.width = depth.width;
    map.height = depth.height;
    map.samples = depth.samples;
    map.depth = depth.depth;
    map.zero_one = true;
    return map;
}

// The integer texels the device quantized, recovered from the table by exact 1x1 queries.
ref::SatTexels texels_of(const SatTable& table) {
    ref::SatTexels texels;
    texels.width = table.width;
    texels.height = table.height;
    for (int y = 0; y < table.height; ++y)
        for (int x = 0; x < table.width; ++x)
            for (std::uint32_t v : msmcl::sat_rectangle_sum(table, x, y, x, y)) texels.values.push_back(v);
    return texels;
}

ref::SoftParams reference_params(const SoftShadowOptions& options) {
    const msmcl::SoftShadowLimits limits = msmcl::soft_shadow_limits(kMaxKernel, options);
    ref::SoftParams p;
    p.search_size = limits.search_size;
    p.light_size = options.light_size;
    p.min_filter_size = options.min_filter_size;
    p.max_filter_size = limits.max_filter_size;
    return p;
}

ref::SoftVariant reference_variant(const SoftShadowOptions& options) {
    ref::SoftVariant variant;
    variant.receiver_weight = options.receiver_blocker_weight;
    variant.parts = options.filter_parts;
    return variant;
}

// The method as published: no receiver weight, one filter query.
SoftShadowOptions published(SoftShadowOptions options) {
    options.receiver_blocker_weight = 0.0f;
    options.filter_parts = 1;
    return options;
}

struct ErrorStats {
    double mean = 0, p99 = 0, max = 0;
    double share_above(double) const;
    std::vector<double> errors;
};

ErrorStats error_stats(const std::vector<float>& actual, const std::vector<double>& expected) {
    ErrorStats s;
    for (std::size_t i = 0; i < actual.size(); ++i) s.errors.push_back(std::fabs(actual[i] - expected[i]));
    std::vector<double> sorted = s.errors;
    std::sort(sorted.begin(), sorted.end());
    for (double e : sorted) s.mean += e;
    s.mean /= sorted.size();
    s.p99 = sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(0.99 * sorted.size()))];
    s.max = sorted.back();
    return s;
}

double ErrorStats::share_above(double threshold) const {
    return double(std::count_if(errors.begin(), errors.end(), [&](double e) { return e > threshold; })) / errors.size();
}

// A sample scene: its depth map, table and receivers (with their internal depths).
struct Scene {
    DepthImage depth;
    SatTable table;
    msmcl::Receivers receivers;
};

Scene load_scene(msmcl::Context& context, const std::string& name) {
    const std::string data = MSMCL_SOURCE_DIR "/data/";
    Scene scene;
    scene.depth = msmcl::io::read_depth_exr(data + name + "_256x256_4x.exr", DepthRange::zero_one);
    scene.receivers = msmcl::io::read_receivers_exr(data + name + "_view_160x120.exr").points;
    msmcl::SatOptions options;
    options.max_kernel_texels = kMaxKernel;
    scene.table = msmcl::build_sat(context, scene.depth, options);
    return scene;
}

// The scenes' light: penumbrae up to the full 27 texels for blockers 0.34 away in internal
// depth. Depth bias 0.02: the receivers are the visible surfaces, many of them steep; with
// less, brute-force PCSS finds the receiver's own slope inside the 27 x 27 search square and
// shadows it (acne on 90% of the Wuson receivers at 1e-3), which is no ground truth.
SoftShadowOptions scene_options() {
    SoftShadowOptions options;
    options.light_size = 40.0f;
    options.depth_bias = 0.02f;
    return options;
}

TEST_F(SoftTest, DeviceEqualsItsHostBuild) {
    // The kernel and kernels/msm_sat.clh compiled as C++: the same float32 code, so equal up
    // to the compilers' instruction choices (contraction); a handful of receivers sit on a
    // decision edge (umbra threshold, blocker classification) and may flip.
    const Scene scene = load_scene(context(), "railing");
    const SoftShadowOptions options = scene_options();
    const std::vector<float> device = msmcl::soft_shade(context(), scene.table, scene.receivers, options);
    std::vector<double> host;
    for (std::size_t i = 0; i < scene.receivers.size(); ++i)
        host.push_back(msmcl::soft_shadow_at(scene.table, scene.receivers.u[i], scene.receivers.v[i],
                                             scene.receivers.z[i], options));
    const ErrorStats stats = error_stats(device, host);
    std::printf("  device vs host build: mean %.2e, p99 %.2e, max %.2e, share > 1e-3: %.4f\n", stats.mean, stats.p99,
                stats.max, stats.share_above(1e-3));
    // PoCL fuses multiply-adds, GCC does not: the 4MSM solve amplifies those last bits near
    // the bound's steep parts.
    EXPECT_LT(stats.mean, 1e-4);
    EXPECT_LT(stats.share_above(1e-3), 0.01);
    EXPECT_LT(stats.max, 0.05);
}

// Device soft shadows of a scene against (a) the same method by direct sums in long double
// (sat_reference's moment_soft_shadow for the published method, soft_analysis' MomentTable
// for the refined one, both from the texels the device quantized) and (b) brute-force PCSS
// on the depth samples. Returns the device's shares lighter than PCSS by more than 0.3.
struct PcssComparison {
    ErrorStats vs_pcss;
    double lighter = 0; // share of receivers lighter than PCSS by more than 0.3
    double darker = 0;  // share darker by more than 0.3
};
PcssComparison compare_with_references(msmcl::Context& context, const std::string& name,
                                       const SoftShadowOptions& options, double method_mean_bound,
                                       double method_p99_bound, double pcss_mean_bound, double pcss_p99_bound) {
    const Scene scene = load_scene(context, name);
    const std::vector<float> device = msmcl::soft_shade(context, scene.table, scene.receivers, options);

    const ref::SatTexels texels = texels_of(scene.table);
    const ref::DepthMap map = reference_map(scene.depth);
    const ref::SoftParams params = reference_params(options);
    const ref::PcssMap pcss_map(map);
    const ref::MomentTable moment_table(texels, scene.table.scale);
    const bool is_published = options.receiver_blocker_weight == 0.0f && options.filter_parts == 1;
    std::vector<double> method, pcss;
    int shadowed = 0;
    PcssComparison result;
    for (std::size_t i = 0; i < scene.receivers.size(); ++i) {
        const double u = scene.receivers.u[i], v = scene.receivers.v[i];
        const double zf = ref::internal_depth(scene.receivers.z[i], true) - options.depth_bias;
        method.push_back(is_published
                             ? ref::moment_soft_shadow(texels, scene.table.scale, u, v, zf, params).shadow
                             : moment_table.soft_shadow(pcss_map, u, v, zf, params, {}, reference_variant(options)).shadow);
        pcss.push_back(ref::pcss_shadow(map, u, v, zf, params).shadow);
        shadowed += pcss.back() > 0.5;
        result.lighter += device[i] < pcss.back() - 0.3;
        result.darker += device[i] > pcss.back() + 0.3;
    }
    result.lighter /= device.size();
    result.darker /= device.size();
    const ErrorStats vs_method = error_stats(device, method);
    result.vs_pcss = error_stats(device, pcss);
    const ErrorStats& vs_pcss = result.vs_pcss;
    std::printf("  %s (%s): %zu receivers, %d in shadow (PCSS > 0.5)\n", name.c_str(),
                is_published ? "published" : "refined", device.size(), shadowed);
    std::printf("  %s vs same method in long double: mean %.5f, p99 %.5f, max %.4f\n", name.c_str(), vs_method.mean,
                vs_method.p99, vs_method.max);
    std::printf("  %s vs brute-force PCSS: mean %.4f, p99 %.4f, max %.4f, share > 0.1: %.4f, lighter by > 0.3: "
                "%.4f, darker by > 0.3: %.4f\n",
                name.c_str(), vs_pcss.mean, vs_pcss.p99, vs_pcss.max, vs_pcss.share_above(0.1), result.lighter,
                result.darker);
    EXPECT_GT(shadowed, 100);
    EXPECT_LT(vs_method.mean, method_mean_bound);
    EXPECT_LT(vs_method.p99, method_p99_bound);
    EXPECT_LT(vs_pcss.mean, pcss_mean_bound);
    EXPECT_LT(vs_pcss.p99, pcss_p99_bound);
    return result;
}

// Bounds: against the same method, float32 and the 22.5-bit table move the 4MSM results by
// ~1e-3 on average, a few receivers on a decision edge (umbra threshold, blocker
// classification) by more. Against PCSS, the method's own error: four moments of a 27 x 27
// region hold more than two surfaces near contact points, the blocker search's lower bound
// then finds too little blocker mass and the filter leaks light (Peters et al., i3D 2016, Fig. 12); 1% of
// the receivers differ by up to ~0.45.
// The refinements (receiver blocker weight 0.1, 2 x 2 filter parts): against their own
// long double evaluation the same float32 and table errors as above (each part is a query
// like the published one's); against PCSS less light leaks than the published method on both
// scenes (railing: 1.2% lighter by > 0.3 instead of 3.2%, p99 0.32 instead of 0.45; Wuson:
// 0.3% instead of 2.4%, p99 0.21 instead of 0.39). Darker than PCSS by > 0.3: 2 of the
// 19,200 railing receivers (at 256^2 a bar's shadow is a few texels wide and the 2 x 2 parts'
// bounds, each tighter, can overshoot PCSS's box filter there); bound 0.1%. On the larger
// unseen scenes of docs/soft_shadows.md none is.
TEST_F(SoftTest, PublishedAndRefinedMethodsAgreeWithReferences) {
    for (const char* name : {"railing", "wuson"}) {
        const PcssComparison before =
            compare_with_references(context(), name, published(scene_options()), 0.005, 0.05, 0.06, 0.6);
        const PcssComparison after = compare_with_references(context(), name, scene_options(), 0.005, 0.05, 0.03, 0.4);
        EXPECT_LT(after.vs_pcss.mean, before.vs_pcss.mean) << name;
        EXPECT_LT(after.vs_pcss.p99, before.vs_pcss.p99) << name;
        EXPECT_LT(after.lighter, 0.5 * before.lighter) << name;
        EXPECT_LE(after.darker, 0.001) << name;
    }
}

// The whole-view references the tools use: PcssMap (min/max quadtree) is pcss_shadow, and
// MomentTable (64-bit prefix sums) with no stage swapped is moment_soft_shadow, up to the
// order of summation (1e-9), on random receivers in and around both scenes' maps.
TEST_F(SoftTest, WholeViewReferencesEqualTheDirectOnes) {
    for (const char* name : {"railing", "wuson"}) {
        const Scene scene = load_scene(context(), name);
        const ref::DepthMap map = reference_map(scene.depth);
        const ref::SatTexels texels = texels_of(scene.table);
        const ref::PcssMap pcss_map(map);
        const ref::MomentTable moment_table(texels, scene.table.scale);
        ref::SoftParams params = reference_params(scene_options());
        std::mt19937 rng(seed_ + 3);
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        double worst_pcss = 0, worst_method = 0;
        for (int i = 0; i < 400; ++i) {
            const double u = unit(rng) * (map.width + 8) - 4, v = unit(rng) * (map.height + 8) - 4;
            const double zf = 2 * unit(rng) - 1;
            params.search_size = i % 2 ? 27 : 1 + i % 27;
            const ref::SoftResult direct = ref::pcss_shadow(map, u, v, zf, params);
            const ref::SoftResult fast = pcss_map.pcss(u, v, zf, params);
            worst_pcss = std::max({worst_pcss, std::abs(direct.shadow - fast.shadow),
                                   std::abs(direct.blocker_depth - fast.blocker_depth),
                                   std::abs(direct.blocker_shadow - fast.blocker_shadow)});
            worst_method = std::max(
                worst_method, std::abs(ref::moment_soft_shadow(texels, scene.table.scale, u, v, zf, params).shadow -
                                       moment_table.soft_shadow(pcss_map, u, v, zf, params).shadow));
        }
        std::printf("  %s: PcssMap vs pcss_shadow max %.2e, MomentTable vs moment_soft_shadow max %.2e\n", name,
                    worst_pcss, worst_method);
        EXPECT_LT(worst_pcss, 1e-9) << name;
        EXPECT_LT(worst_method, 1e-9) << name;
    }
}

// Every stage swapped for its exact counterpart at once is PCSS itself: the classification
// of docs/soft_shadows.md always ends.
TEST_F(SoftTest, AllStagesSwappedIsPcss) {
    const Scene scene = load_scene(context(), "railing");
    const ref::DepthMap map = reference_map(scene.depth);
    const ref::PcssMap pcss_map(map);
    const ref::MomentTable moment_table(map, kMaxKernel);
    const ref::SoftParams params = reference_params(scene_options());
    ref::SoftSwaps all;
    all.unquantized_table = all.exact_blockers = all.plain_average = all.no_umbra_early_out = true;
    all.pcss_filter_size = all.exact_filter = true;
    double worst = 0;
    for (std::size_t i = 0; i < scene.receivers.size(); i += 7) {
        const double zf = ref::internal_depth(scene.receivers.z[i], true) - scene_options().depth_bias;
        const double u = scene.receivers.u[i], v = scene.receivers.v[i];
        worst = std::max(worst, std::abs(moment_table.soft_shadow(pcss_map, u, v, zf, params, all).shadow -
                                         pcss_map.pcss(u, v, zf, params).shadow));
    }
    EXPECT_LT(worst, 1e-9);
}

// Ground at depth 0.9 everywhere; for y < edge a bar whose depth falls from 0.9 at x = 0
// to 0.4 at the right edge (4 samples per texel at random positions).
DepthImage sloped_bar(int width, int height, int edge, std::mt19937& rng) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    DepthImage depth;
    depth.width = width;
    depth.height = height;
    depth.samples = 4;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int s = 0; s < 4; ++s) {
                const double px = x + unit(rng), py = y + unit(rng);
                depth.depth.push_back(static_cast<float>(py < edge ? 0.9 - 0.5 * px / width : 0.9));
            }
    return depth;
}

// 10%..90% width of the shadow's fall-off across the bar's edge at column u.
double penumbra_width(const std::vector<float>& profile, double step) {
    int first = -1, last = -1;
    for (std::size_t i = 0; i < profile.size(); ++i) {
        if (profile[i] < 0.9f && first < 0) first = static_cast<int>(i);
        if (profile[i] > 0.1f) last = static_cast<int>(i);
    }
    return (last - first + 1) * step;
}

TEST_F(SoftTest, PenumbraGrowsWithBlockerDistance) {
    // Contact hardening: a box filter of side w over a straight edge falls from 0.9 to 0.1 over
    // 0.8 w, with w = light_size * (z_receiver - z_blocker) = light_size * 2 (d_g - d_o).
    std::mt19937 rng(seed_);
    const int width = 256, height = 128, edge = 64;
    const DepthImage depth = sloped_bar(width, height, edge, rng);
    msmcl::SatOptions sat_options;
    sat_options.max_kernel_texels = kMaxKernel;
    const SatTable table = msmcl::build_sat(context(), depth, sat_options);
    SoftShadowOptions refined;
    refined.light_size = 40.0f;
    const ref::DepthMap map = reference_map(depth);
    const ref::SoftParams params = reference_params(refined);
    const double step = 0.25;
    // The published method, each refinement alone, both (the default).
    SoftShadowOptions weight_only = published(refined), parts_only = published(refined);
    weight_only.receiver_blocker_weight = refined.receiver_blocker_weight;
    parts_only.filter_parts = refined.filter_parts;
    for (const SoftShadowOptions& options : {published(refined), weight_only, parts_only, refined}) {
        std::printf("  receiver weight %.2f, %dx%d filter parts:\n", options.receiver_blocker_weight,
                    options.filter_parts, options.filter_parts);
        std::vector<double> widths, expected;
        for (double u : {24.5, 64.5, 128.5}) {
            msmcl::Receivers line;
            std::vector<float> pcss;
            for (double v = edge - 20; v <= edge + 20; v += step) {
                line.u.push_back(static_cast<float>(u));
                line.v.push_back(static_cast<float>(v));
                line.z.push_back(0.9f);
                pcss.push_back(
                    static_cast<float>(ref::pcss_shadow(map, u, v, 2 * 0.9 - 1 - options.depth_bias, params).shadow));
            }
            const std::vector<float> shadow = msmcl::soft_shade(context(), table, line, options);
            const double blocker = 0.9 - 0.5 * u / width;
            const double filter = std::clamp(options.light_size * 2 * (0.9 - blocker), 1.0, 27.0);
            widths.push_back(penumbra_width(shadow, step));
            expected.push_back(0.8 * filter);
            std::printf("    column %.1f: blocker %.3f, filter side %.1f -> penumbra %.2f texels (expected %.2f, PCSS %.2f)\n",
                        u, blocker, filter, widths.back(), expected.back(), penumbra_width(pcss, step));
            // Under the bar, lit far from it (up to the bias's leak; the bar slopes, so its
            // search square is not a single depth and the umbra test may not cut in).
            EXPECT_GT(shadow.front(), 0.99f);
            EXPECT_LT(shadow.back(), 1e-4f);
        }
        EXPECT_GT(widths[1], 1.5 * widths[0]);
        EXPECT_GT(widths[2], 1.5 * widths[1]);
        for (std::size_t i = 0; i < widths.size(); ++i) EXPECT_NEAR(widths[i], expected[i], 0.3 * expected[i] + 1.0);
    }
}

TEST_F(SoftTest, DeviceApiHonoursEventsAndMatchesHostApi) {
    const Scene scene = load_scene(context(), "wuson");
    const SoftShadowOptions options = scene_options();
    const std::vector<float> expected = msmcl::soft_shade(context(), scene.table, scene.receivers, options);
    const std::size_t count = scene.receivers.size();
    std::vector<float> uvz(scene.receivers.u);
    uvz.insert(uvz.end(), scene.receivers.v.begin(), scene.receivers.v.end());
    uvz.insert(uvz.end(), scene.receivers.z.begin(), scene.receivers.z.end());
    cl_int status = CL_SUCCESS;
    cl_context cl = context().cl_context_handle();
    cl_mem table = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, scene.table.words.size() * 4,
                                  const_cast<std::uint32_t*>(scene.table.words.data()), &status);
    cl_mem receivers = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, uvz.size() * 4, uvz.data(), &status);
    cl_mem intensity = clCreateBuffer(cl, CL_MEM_WRITE_ONLY, count * 4, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_event done = nullptr;
    msmcl::Enqueue enqueue;
    enqueue.done = &done;
    msmcl::soft_shade(context(), msmcl::DeviceSat{table, scene.table.width, scene.table.height, kMaxKernel}, receivers,
                      count, intensity, options, enqueue);
    ASSERT_NE(done, nullptr);
    std::vector<float> result(count);
    ASSERT_EQ(clEnqueueReadBuffer(context().cl_queue_handle(), intensity, CL_TRUE, 0, count * 4, result.data(), 1,
                                  &done, nullptr),
              CL_SUCCESS);
    clReleaseEvent(done);
    EXPECT_EQ(result, expected);
    // No receivers: still an event.
    done = nullptr;
    msmcl::soft_shade(context(), msmcl::DeviceSat{table, scene.table.width, scene.table.height, kMaxKernel}, receivers, 0,
                      intensity, options, enqueue);
    ASSERT_NE(done, nullptr);
    EXPECT_EQ(clWaitForEvents(1, &done), CL_SUCCESS);
    clReleaseEvent(done);
    clReleaseMemObject(intensity);
    clReleaseMemObject(receivers);
    clReleaseMemObject(table);
}

TEST_F(SoftTest, LitAndUmbraLimits) {
    std::mt19937 rng(seed_ + 1);
    const DepthImage depth = sloped_bar(128, 128, 64, rng);
    msmcl::SatOptions sat_options;
    sat_options.max_kernel_texels = kMaxKernel;
    const SatTable table = msmcl::build_sat(context(), depth, sat_options);
    msmcl::Receivers r;
    // In front of everything; on the lit ground far from the bar; deep under the bar's far
    // end (umbra early-out: exactly 1); off the map (clamped to the corner (128, 0), under it).
    r.u = {30.0f, 64.0f, 110.0f, 300.0f};
    r.v = {30.0f, 120.0f, 10.0f, -50.0f};
    r.z = {0.05f, 0.9f, 0.9f, 0.9f};
    const std::vector<float> shadow = msmcl::soft_shade(context(), table, r, SoftShadowOptions{});
    EXPECT_EQ(shadow[0], 0.0f);
    EXPECT_LT(shadow[1], 1e-4f);
    EXPECT_EQ(shadow[2], 1.0f);
    EXPECT_EQ(shadow[3], 1.0f);
}

TEST_F(SoftTest, BadInputIsRejected) {
    std::mt19937 rng(seed_ + 2);
    const DepthImage depth = sloped_bar(32, 32, 16, rng);
    msmcl::SatOptions sat_options;
    sat_options.max_kernel_texels = 100;
    const SatTable table = msmcl::build_sat(context(), depth, sat_options);
    msmcl::Receivers r;
    r.u = {1.0f};
    r.v = {1.0f};
    r.z = {0.5f};
    const auto rejects = [&](const SoftShadowOptions& options) {
        EXPECT_THROW(msmcl::soft_shade(context(), table, r, options), msmcl::input_error);
    };
    SoftShadowOptions o;
    o.light_size = -1.0f;
    rejects(o);
    o.light_size = std::numeric_limits<float>::quiet_NaN();
    rejects(o);
    o = {};
    o.search_size = 11; // 121 > N = 100
    rejects(o);
    o.search_size = -1;
    rejects(o);
    o = {};
    o.min_filter_size = 0.0f;
    rejects(o);
    o.min_filter_size = 10.5f; // > floor(sqrt(100))
    rejects(o);
    o = {};
    o.depth_bias = std::numeric_limits<float>::infinity();
    rejects(o);
    o = {};
    o.receiver_blocker_weight = 1.5f;
    rejects(o);
    o.receiver_blocker_weight = std::numeric_limits<float>::quiet_NaN();
    rejects(o);
    o = {};
    o.filter_parts = 0;
    rejects(o);
    o.filter_parts = 5;
    rejects(o);
    o = {};
    o.search_size = 10;
    EXPECT_NO_THROW(msmcl::soft_shade(context(), table, r, o));
    EXPECT_EQ(msmcl::soft_shadow_limits(100, SoftShadowOptions{}).search_size, 10);
    EXPECT_EQ(msmcl::soft_shadow_limits(100, SoftShadowOptions{}).max_filter_size, 10.0f);

    // Receivers: non-finite, mismatched arrays.
    msmcl::Receivers bad = r;
    bad.z[0] = std::nanf("");
    EXPECT_THROW(msmcl::soft_shade(context(), table, bad, SoftShadowOptions{}), msmcl::input_error);
    bad = r;
    bad.u.push_back(2.0f);
    EXPECT_THROW(msmcl::soft_shade(context(), table, bad, SoftShadowOptions{}), msmcl::input_error);
    // Tables: scale that does not match N, wrong word count, N out of range.
    SatTable broken = table;
    broken.scale -= 1;
    EXPECT_THROW(msmcl::soft_shade(context(), broken, r, SoftShadowOptions{}), msmcl::input_error);
    broken = table;
    broken.words.resize(8);
    EXPECT_THROW(msmcl::soft_shade(context(), broken, r, SoftShadowOptions{}), msmcl::input_error);
    broken = table;
    broken.max_kernel_texels = 1;
    EXPECT_THROW(msmcl::soft_shadow_at(broken, 1, 1, 0.5f, SoftShadowOptions{}), msmcl::input_error);
    // Device call: null buffers.
    EXPECT_THROW(msmcl::soft_shade(context(), msmcl::DeviceSat{nullptr, 32, 32, 100}, nullptr, 1, nullptr,
                                   SoftShadowOptions{}),
                 msmcl::input_error);
}

// Runs the msmcl executable through the shell; returns its exit code, stderr in `err`.
int run_cli(const std::string& arguments, const std::string& directory, std::string& err) {
    const std::string err_path = directory + "/stderr.txt";
    const int status = std::system((std::string(MSMCL_CLI_PATH) + " " + arguments + " 2> " + err_path).c_str());
    std::ifstream in(err_path);
    err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST_F(SoftTest, CliSatAndSoftEqualTheLibrary) {
    if (std::string(MSMCL_CLI_PATH).empty()) GTEST_SKIP() << "built without the msmcl CLI";
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("msmcl_soft_cli_" + std::to_string(seed_));
    fs::create_directories(dir);
    const std::string data = MSMCL_SOURCE_DIR "/data/";
    const std::string depth = data + "railing_256x256_4x.exr", receivers = data + "railing_view_160x120.exr";
    const std::string table_path = (dir / "table.exr").string(), soft_path = (dir / "soft.exr").string();
    std::string err;

    // msmcl sat: the library's table, N and scale in the attributes.
    ASSERT_EQ(run_cli("sat " + depth + " " + table_path + " --max-kernel 729", dir.string(), err), 0) << err;
    const Scene scene = load_scene(context(), "railing");
    const msmcl::io::SatFile file = msmcl::io::read_sat_exr(table_path);
    EXPECT_EQ(file.table.words, scene.table.words);
    EXPECT_EQ(file.table.scale, scene.table.scale);
    EXPECT_EQ(file.info.samples, 4);

    // msmcl soft: the library's intensities as channel Y.
    ASSERT_EQ(run_cli("soft " + table_path + " " + receivers + " " + soft_path + " --light-size 40 --depth-bias 0.02",
                      dir.string(), err),
              0)
        << err;
    const std::vector<float> expected = msmcl::soft_shade(context(), scene.table, scene.receivers, scene_options());
    const msmcl::io::ExrImage image = msmcl::io::read_exr(soft_path);
    ASSERT_NE(image.find_channel("Y"), nullptr);
    EXPECT_EQ(image.find_channel("Y")->values, expected);

    // Bad input: one line on stderr, exit code 2, no output file.
    const std::string bad = (dir / "bad.exr").string();
    const std::string cases[] = {
        "soft " + table_path + " " + receivers + " " + bad + " --light-size 40 --search-size 28", // 28^2 > N
        "soft " + table_path + " " + receivers + " " + bad,                                       // no light size
        "soft " + table_path + " " + receivers + " " + bad + " --light-size -1",
        "soft " + table_path + " " + receivers + " " + bad + " --light-size 40 --filter-parts 5",
        "soft " + table_path + " " + receivers + " " + bad + " --light-size 40 --receiver-weight 2",
        "soft " + table_path + " " + receivers + " " + bad + " --light-size 40 --published --filter-parts 2",
        "soft " + depth + " " + receivers + " " + bad + " --light-size 40", // not a table
        "sat " + depth + " " + bad + " --max-kernel 1",
        "sat " + depth + " " + bad + " --max-kernel 27x27",
        "sat " + (dir / "missing.exr").string() + " " + bad,
    };
    for (const std::string& arguments : cases) {
        EXPECT_EQ(run_cli(arguments, dir.string(), err), 2) << arguments;
        EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
        EXPECT_FALSE(fs::exists(bad)) << arguments;
    }
    fs::remove_all(dir);
}

} // namespace
