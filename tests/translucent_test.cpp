// Translucent occluders (docs/math.md, Peters et al., i3D 2016, section 4) on PoCL: every filter kernel and
// the SAT build with translucent layers against the double-precision reference
// (tests/reference/translucent_reference: sort, alpha blending front to back), bit-identity
// with the opaque path for no layers and for layers of opacity 0, opacity 1 acting as an
// opaque surface, plausible partial shadow against the exact transmittance, the EXR layers
// and the CLI.
#include "filter_fixtures.hpp"
#include "runtime/quirks.hpp"

#include "io/exr_io.hpp"
#include "reference/sat_reference.hpp"
#include "reference/translucent_reference.hpp"
#include "process.hpp"

#include <msmcl/sat.hpp>
#include <msmcl/shade.hpp>

#include <fcntl.h>
#include <filesystem>
#include <spawn.h>
#include <sys/wait.h>

extern char** environ;

#ifndef MSMCL_CLI_PATH // configured with MSMCL_BUILD_TOOLS=OFF: the CLI test skips
#define MSMCL_CLI_PATH ""
#endif

namespace {

using namespace filter_fixtures;
using msmcl::TranslucentLayer;

std::uint32_t seed() {
    static const std::uint32_t value = [] {
        const std::uint32_t s = test_seed() + 505;
        std::printf("translucent_test seed %u (set MSMCL_TEST_SEED to change)\n", s);
        return s;
    }();
    return value;
}

constexpr FilterKernel kKernels[] = {FilterKernel::fused_paper, FilterKernel::fused_cpu, FilterKernel::three_pass};

// Whether the device runs fused_cpu with translucent layers: not where it stops long loops
// (llvmpipe, runtime/quirks.hpp; FusedCpuWithLayersIsUnfitWhereLoopsAreLimited checks the
// refusal). Said once on stdout, so that a run shows what it left out.
bool runs_cpu_layers(const msmcl::Context& context) {
    static const bool runs = [&] {
        const bool limited = msmcl::detail::loop_iteration_limit(context.device()).has_value();
        if (limited) std::printf("fused_cpu with translucent layers: left out, the device limits loop iterations\n");
        return !limited;
    }();
    return runs;
}
constexpr Format kFormats[] = {Format::moments128, Format::msm64, Format::nlq64, Format::nlq32};

const char* kernel_name(FilterKernel kernel) {
    return kernel == FilterKernel::fused_paper ? "fused_paper" : kernel == FilterKernel::fused_cpu ? "fused_cpu" : "three_pass";
}

// Hidden layer stacks: `count` layers of smoke-like patches over the map. Each sample's
// layer depth is random in [0, 1] (so some lie behind the opaque surface), its opacity 0 off
// the layer's blobs, else random in (0, 1) with some exact 0 and 1.
std::vector<TranslucentLayer> hidden_layers(const DepthImage& depth, int count, DepthRange range, std::uint32_t s) {
    std::mt19937 random(s);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<TranslucentLayer> layers(count);
    for (TranslucentLayer& layer : layers) {
        const double cx = unit(random) * depth.width, cy = unit(random) * depth.height;
        const double radius = 3.0 + unit(random) * std::max(depth.width, depth.height) / 2.0;
        const double plane = unit(random);
        for (int y = 0; y < depth.height; ++y)
            for (int x = 0; x < depth.width; ++x)
                for (int k = 0; k < depth.samples; ++k) {
                    const bool inside = std::hypot(x + 0.5 - cx, y + 0.5 - cy) < radius;
                    // Mostly one plane per layer, sometimes a sample elsewhere.
                    const double d = unit(random) < 0.8 ? plane : unit(random);
                    const double pick = unit(random);
                    const double a = !inside ? 0.0 : pick < 0.1 ? 0.0 : pick < 0.2 ? 1.0 : unit(random);
                    layer.depth.push_back(static_cast<float>(range == DepthRange::zero_one ? d : 2.0 * d - 1.0));
                    layer.opacity.push_back(static_cast<float>(a));
                }
    }
    return layers;
}

std::vector<ref::LayerMap> to_reference(const std::vector<TranslucentLayer>& layers) {
    std::vector<ref::LayerMap> maps;
    for (const TranslucentLayer& layer : layers) maps.push_back({layer.depth, layer.opacity});
    return maps;
}

class Translucent : public FilterTest {
protected:
    static Texture run_layers(const DepthImage& depth, const std::vector<TranslucentLayer>& layers, Format format,
                              FilterKernel kernel, float sigma = 2.4f, DepthRange range = DepthRange::zero_one) {
        msmcl::FilterOptions options;
        options.format = format;
        options.sigma = sigma;
        options.depth_range = range;
        options.kernel = kernel;
        return msmcl::filter(*context_, depth, layers, options);
    }
};

TEST_F(Translucent, NoLayersAndTransparentLayersGiveTheOpaqueBits) {
    // Opaque inputs run the opaque program; layers of opacity 0 run the compositing one and
    // must not change a bit (0 * b(z) adds +-0, every transmittance stays 1).
    const DepthImage depth = make_depth(150, 70, 4, DepthRange::zero_one, seed());
    std::vector<TranslucentLayer> clear = hidden_layers(depth, 2, DepthRange::zero_one, seed() + 1);
    for (TranslucentLayer& layer : clear) std::fill(layer.opacity.begin(), layer.opacity.end(), 0.0f);
    for (FilterKernel kernel : kKernels)
        for (Format format : kFormats) {
            if (kernel == FilterKernel::fused_cpu && !runs_cpu_layers(*context_)) continue;
            const Texture opaque = run(depth, format, 2.4f, DepthRange::zero_one, kernel);
            EXPECT_EQ(run_layers(depth, {}, format, kernel).words, opaque.words) << kernel_name(kernel) << " "
                                                                                  << msmcl::format_name(format);
            EXPECT_EQ(run_layers(depth, clear, format, kernel).words, opaque.words)
                << kernel_name(kernel) << " " << msmcl::format_name(format) << ", seed " << seed();
        }
}

TEST_F(Translucent, OpacityOneActsAsAnOpaqueSurface) {
    // A layer of opacity 1 on random samples (0 elsewhere) at random depths: the same bits as
    // the opaque map with the nearer of the two depths there. (nlq formats of the fused
    // kernels shift by the opaque depth of their block's centre, which the nearer depth may
    // change: those are compared by three_pass, which does not shift.)
    const DepthImage depth = make_depth(150, 70, 4, DepthRange::zero_one, seed() + 2);
    std::mt19937 random(seed() + 3);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    // (A second, clear layer: the test runs the two-layer programs the other tests build.)
    TranslucentLayer wall, clear;
    DepthImage nearer = depth;
    for (std::size_t i = 0; i < depth.depth.size(); ++i) {
        wall.depth.push_back(unit(random));
        wall.opacity.push_back(unit(random) < 0.5f ? 1.0f : 0.0f);
        if (wall.opacity.back() == 1.0f) nearer.depth[i] = std::min(nearer.depth[i], wall.depth.back());
        clear.depth.push_back(unit(random));
        clear.opacity.push_back(0.0f);
    }
    for (FilterKernel kernel : kKernels)
        for (Format format : kFormats) {
            if (kernel != FilterKernel::three_pass && (format == Format::nlq64 || format == Format::nlq32)) continue;
            if (kernel == FilterKernel::fused_cpu && !runs_cpu_layers(*context_)) continue;
            EXPECT_EQ(run_layers(depth, {clear, wall}, format, kernel).words,
                      run(nearer, format, 2.4f, DepthRange::zero_one, kernel).words)
                << kernel_name(kernel) << " " << msmcl::format_name(format) << ", seed " << seed();
        }
}

// On a device that stops long loops, an explicit fused_cpu with layers is refused with the
// limit named (the CLI's exit 2), and automatic takes three_pass and says why.
TEST_F(Translucent, FusedCpuWithLayersIsUnfitWhereLoopsAreLimited) {
    if (runs_cpu_layers(*context_)) GTEST_SKIP() << "the device does not limit loop iterations";
    const DepthImage depth = make_depth(20, 10, 1, DepthRange::zero_one, seed() + 4);
    const std::vector<TranslucentLayer> layers = hidden_layers(depth, 1, DepthRange::zero_one, seed() + 5);
    try {
        run_layers(depth, layers, Format::msm64, FilterKernel::fused_cpu);
        ADD_FAILURE() << "fused_cpu with layers ran on a device that limits loops";
    } catch (const msmcl::unfit_kernel_error& e) {
        EXPECT_NE(std::string(e.what()).find("65535 loop iterations"), std::string::npos) << e.what();
    }
    msmcl::FilterOptions options;
    options.format = Format::msm64;
    msmcl::filter(*context_, depth, layers, options);
    EXPECT_EQ(context_->kernel_choices().back().rfind("filter: three_pass (fused_cpu with translucent layers", 0), 0u)
        << context_->kernel_choices().back();
}

TEST_F(Translucent, HiddenLayerStacksMatchTheDoubleReference) {
    // float32: the opaque filter's ~20 roundings (kMomentTolerance) plus the composite's: up
    // to 3 transmittance factors, the weight, 4 layer terms summed and the division by their
    // total, ~10 more roundings of values <= 1: 3e-6 in all.
    const double tolerance = 3e-6;
    // Every format on the first case; moments128 (and one nlq format) on the others, which
    // vary samples, layer count, sigma and range (each variant is a program to build).
    struct Case {
        int width, height, samples, layers;
        float sigma;
        DepthRange range;
        bool all_formats;
    };
    const Case cases[] = {{70, 50, 4, 2, 2.4f, DepthRange::zero_one, true},
                          {45, 37, 1, 3, 0.0f, DepthRange::zero_one, false},
                          {33, 25, 8, 1, 2.4f, DepthRange::minus_one_one, false},
                          {64, 40, 2, 8, 1.0f, DepthRange::zero_one, false}};
    for (const Case& c : cases) {
        const DepthImage depth = make_depth(c.width, c.height, c.samples, c.range, seed() + 10 * c.layers);
        const std::vector<TranslucentLayer> layers = hidden_layers(depth, c.layers, c.range, seed() + 11 * c.layers);
        const std::vector<ref::Moments> expected =
            ref::filter_moments_translucent(filter_fixtures::to_reference(depth, c.range), to_reference(layers), c.sigma);
        const std::string what = std::to_string(c.width) + "x" + std::to_string(c.height) + " S=" +
                                 std::to_string(c.samples) + ", " + std::to_string(c.layers) + " layers";
        for (FilterKernel kernel : kKernels) {
            if (kernel == FilterKernel::fused_cpu && !runs_cpu_layers(*context_)) continue;
            // moments128: every moment within the float32 tolerance.
            const Texture moments = run_layers(depth, layers, Format::moments128, kernel, c.sigma, c.range);
            expect_moments_close(moments, expected, tolerance, what + " " + kernel_name(kernel));
            if (!c.all_formats) continue;
            // msm64: the same bits from every kernel (no shift), checked once below.
            EXPECT_EQ(run_layers(depth, layers, Format::msm64, kernel, c.sigma, c.range).words,
                      run_layers(depth, layers, Format::msm64, FilterKernel::three_pass, c.sigma, c.range).words)
                << what << " " << kernel_name(kernel);
            // nlq formats: moments rebuilt from the texels, codes where well conditioned.
            for (Format format : {Format::nlq64, Format::nlq32})
                check_nlq_against_reference(run_layers(depth, layers, format, kernel, c.sigma, c.range), depth, kernel,
                                            expected, what + " " + msmcl::format_name(format) + " " + kernel_name(kernel));
        }
        if (!c.all_formats) {
            // The CPU distribution's nlq64 (the most intricate kernel, shifted per tile).
            if (c.range == DepthRange::zero_one && runs_cpu_layers(*context_))
                check_nlq_against_reference(run_layers(depth, layers, Format::nlq64, FilterKernel::fused_cpu, c.sigma),
                                            depth, FilterKernel::fused_cpu, expected, what + " nlq64 fused_cpu");
            continue;
        }
        // msm64 codes against the reference moments encoded in double: within 2 codes
        // (tests/filter_test.cpp: float moments are off by < 3e-6, G scales that by 8).
        const Texture msm64 = run_layers(depth, layers, Format::msm64, FilterKernel::three_pass, c.sigma, c.range);
        unsigned worst = 0;
        for (int y = 0; y < depth.height; ++y)
            for (int x = 0; x < depth.width; ++x) {
                const ref::Codes16 want = ref::encode_msm64(expected[std::size_t(y) * depth.width + x]);
                for (int ch = 0; ch < 4; ++ch)
                    worst = std::max(worst, static_cast<unsigned>(std::abs(int(msm64.code16(x, y, ch)) - int(want[ch]))));
            }
        std::printf("%s: msm64 codes within %u of the reference\n", what.c_str(), worst);
        EXPECT_LE(worst, 2u) << what;
    }
}

TEST_F(Translucent, PartialShadowIsPlausible) {
    // Unblurred single-sample maps of random smoke stacks over a receiver plane: the shadow a
    // nearest lookup gives at points on the plane and between the layers, against the exact
    // transmittance 1 - prod (1 - a) of the layers in front (reference composite, double).
    // One layer: Z has two points (layer, opaque surface), which four moments pin down, so
    // the 4MSM is exact up to the bias (moments128: alpha = 3e-7; nlq64: its quantization).
    // More layers: the 4MSM is a lower bound (Peters, HPG 2017, section 3): never more shadow than
    // exact beyond that tolerance; the error is reported.
    const int width = 48, height = 40;
    std::mt19937 random(seed() + 20);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int count : {1, 3}) {
        DepthImage plane;
        plane.width = width, plane.height = height, plane.samples = 1;
        plane.depth.assign(std::size_t(width) * height, 0.9f);
        // Layers at distinct depths in front of the plane, smooth opacities.
        std::vector<TranslucentLayer> layers(count);
        for (int k = 0; k < count; ++k) {
            const float d = static_cast<float>(0.2 + 0.6 * (k + unit(random) * 0.5) / count);
            const double fx = 0.05 + 0.2 * unit(random), fy = 0.05 + 0.2 * unit(random), phase = 6.3 * unit(random);
            for (int y = 0; y < height; ++y)
                for (int x = 0; x < width; ++x) {
                    layers[k].depth.push_back(d);
                    layers[k].opacity.push_back(static_cast<float>(0.5 + 0.45 * std::sin(fx * x + phase) * std::cos(fy * y)));
                }
        }
        const ref::DepthMap reference_map{width, height, 1, plane.depth, true};
        for (Format format : {Format::moments128, Format::nlq64}) {
            const Texture map = run_layers(plane, layers, format, FilterKernel::automatic, 0.0f);
            msmcl::Receivers receivers;
            std::vector<double> exact;
            for (int y = 0; y < height; ++y)
                for (int x = 0; x < width; ++x)
                    for (double d : {0.9, 0.5 * (layers[0].depth[0] + 0.9), 0.9 * layers[0].depth[0]}) {
                        receivers.u.push_back(x + 0.5f);
                        receivers.v.push_back(y + 0.5f);
                        receivers.z.push_back(static_cast<float>(d));
                        // The receiver's internal depth minus the shading's depth bias.
                        exact.push_back(ref::transmittance_shadow(reference_map, to_reference(layers),
                                                                  std::size_t(y) * width + x, 2.0 * d - 1.0 - 1e-3));
                    }
            msmcl::ShadeOptions options;
            options.lookup = msmcl::Lookup::nearest;
            const std::vector<float> shadow = msmcl::shade(*context_, map, receivers, options);
            // Also the double 4MSM lower bound of the reference's composited moments: what the
            // shading of an exact moments128 texel gives.
            const std::vector<ref::Moments> moments = ref::resolve_translucent(reference_map, to_reference(layers));
            double sum = 0, worst = 0, worst_above = 0, worst_vs_4msm = 0;
            for (std::size_t i = 0; i < shadow.size(); ++i) {
                sum += std::abs(shadow[i] - exact[i]);
                worst = std::max(worst, std::abs(shadow[i] - exact[i]));
                worst_above = std::max(worst_above, shadow[i] - exact[i]);
                const double zf = 2.0 * receivers.z[i] - 1.0 - 1e-3;
                const double bound = ref::hamburger4(ref::bias(moments[i / 3], ref::alpha_float, ref::bstar_float), zf).lower;
                worst_vs_4msm = std::max(worst_vs_4msm, std::abs(shadow[i] - bound));
            }
            std::printf("%d layer(s), %s: |shadow - exact transmittance| mean %.4f, max %.4f; most above exact %.4f; "
                        "vs double 4MSM of the reference moments max %.2g\n",
                        count, msmcl::format_name(format), sum / shadow.size(), worst, worst_above, worst_vs_4msm);
            // The device's shadow is the 4MSM of the composited moments (moments128: to 1e-3
            // near the steps of nearly singular texels; nlq64 adds its quantization, 1e-2).
            EXPECT_LE(worst_vs_4msm, format == Format::moments128 ? 1e-3 : 1e-2) << count << " layers";
            // Two-point Z: exact up to the bias and quantization (moments128 1e-3; nlq64 codes
            // move each depth by 1.5e-5 and v2 by 7.6e-6: 1e-2 covers the weight's sensitivity).
            if (count == 1) EXPECT_LE(worst, format == Format::moments128 ? 1e-3 : 1e-2) << msmcl::format_name(format);
            // Lower bound: not above the exact shadow beyond that tolerance.
            EXPECT_LE(worst_above, format == Format::moments128 ? 1e-3 : 1e-2) << count << " layers";
        }
    }
}

TEST_F(Translucent, SatOfTranslucentMapsMatchesTheReference) {
    // Texels recovered from the table by exact 1x1 queries against round(c * scale) of the
    // double channels of the composited moments (tolerance as tests/sat_test.cpp, with the
    // composite's roundings: 3e-6 * scale + 1); no layers and transparent layers: the
    // opaque table's bits.
    const DepthImage depth = make_depth(45, 37, 4, DepthRange::zero_one, seed() + 30);
    const std::vector<TranslucentLayer> layers = hidden_layers(depth, 2, DepthRange::zero_one, seed() + 31);
    msmcl::SatOptions options;
    options.max_kernel_texels = 729;
    for (msmcl::SatKernel kernel : {msmcl::SatKernel::tiled_cpu, msmcl::SatKernel::tiled_gpu}) {
        options.kernel = kernel;
        const msmcl::SatTable opaque = msmcl::build_sat(*context_, depth, options);
        EXPECT_EQ(msmcl::build_sat(*context_, depth, {}, options).words, opaque.words);
        std::vector<TranslucentLayer> clear = layers;
        for (TranslucentLayer& layer : clear) std::fill(layer.opacity.begin(), layer.opacity.end(), 0.0f);
        EXPECT_EQ(msmcl::build_sat(*context_, depth, clear, options).words, opaque.words);

        const msmcl::SatTable table = msmcl::build_sat(*context_, depth, layers, options);
        const std::vector<ref::Moments> moments =
            ref::resolve_translucent(filter_fixtures::to_reference(depth, DepthRange::zero_one), to_reference(layers));
        const double tolerance = 3e-6 * table.scale + 1.0;
        double worst = 0;
        for (int y = 0; y < depth.height; ++y)
            for (int x = 0; x < depth.width; ++x) {
                const auto texel = msmcl::sat_rectangle_sum(table, x, y, x, y);
                const std::array<double, 4> channels = ref::msm64_affine(moments[std::size_t(y) * depth.width + x]);
                for (int ch = 0; ch < 4; ++ch)
                    worst = std::max(worst, std::fabs(texel[ch] - channels[ch] * table.scale));
            }
        std::printf("sat with 2 layers: worst texel error %.3f units (tolerance %.1f)\n", worst, tolerance);
        EXPECT_LE(worst, tolerance);
    }
}

TEST_F(Translucent, DevicePathEqualsHostPath) {
    const DepthImage depth = make_depth(70, 50, 4, DepthRange::zero_one, seed() + 40);
    const std::vector<TranslucentLayer> layers = hidden_layers(depth, 2, DepthRange::zero_one, seed() + 41);
    msmcl::FilterOptions options;
    options.format = Format::nlq32;
    const Texture host = msmcl::filter(*context_, depth, layers, options);

    // Caller-owned buffers: depth, the layers one after the other, the texture.
    cl_context ctx = context_->cl_context_handle();
    cl_int status = CL_SUCCESS;
    std::vector<float> layer_depth, layer_opacity;
    for (const TranslucentLayer& layer : layers) {
        layer_depth.insert(layer_depth.end(), layer.depth.begin(), layer.depth.end());
        layer_opacity.insert(layer_opacity.end(), layer.opacity.begin(), layer.opacity.end());
    }
    const auto upload = [&](const std::vector<float>& values) {
        cl_mem buffer = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, values.size() * 4,
                                       const_cast<float*>(values.data()), &status);
        EXPECT_EQ(status, CL_SUCCESS);
        return buffer;
    };
    cl_mem depth_buffer = upload(depth.depth), z_buffer = upload(layer_depth), a_buffer = upload(layer_opacity);
    cl_mem texture = clCreateBuffer(ctx, CL_MEM_READ_WRITE, host.words.size() * 4, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    msmcl::Enqueue e;
    e.blocking = true;
    msmcl::filter(*context_, msmcl::DeviceDepth{depth_buffer, depth.width, depth.height, depth.samples},
                  msmcl::DeviceLayers{z_buffer, a_buffer, 2}, texture, options, e);
    std::vector<std::uint32_t> words(host.words.size());
    ASSERT_EQ(clEnqueueReadBuffer(context_->cl_queue_handle(), texture, CL_TRUE, 0, words.size() * 4, words.data(), 0,
                                  nullptr, nullptr),
              CL_SUCCESS);
    EXPECT_EQ(words, host.words);
    // Too small a layer buffer, too many layers, a null buffer: input_error.
    EXPECT_THROW(msmcl::filter(*context_, msmcl::DeviceDepth{depth_buffer, depth.width, depth.height, depth.samples},
                               msmcl::DeviceLayers{z_buffer, a_buffer, 3}, texture, options),
                 msmcl::input_error);
    EXPECT_THROW(msmcl::filter(*context_, msmcl::DeviceDepth{depth_buffer, depth.width, depth.height, depth.samples},
                               msmcl::DeviceLayers{z_buffer, nullptr, 1}, texture, options),
                 msmcl::input_error);
    EXPECT_THROW(msmcl::filter(*context_, msmcl::DeviceDepth{depth_buffer, depth.width, depth.height, depth.samples},
                               msmcl::DeviceLayers{z_buffer, a_buffer, 9}, texture, options),
                 msmcl::input_error);
    for (cl_mem m : {depth_buffer, z_buffer, a_buffer, texture}) clReleaseMemObject(m);
}

TEST_F(Translucent, BadLayersThrowInputError) {
    const DepthImage depth = make_depth(20, 10, 2, DepthRange::zero_one, seed() + 50);
    const std::vector<TranslucentLayer> good = hidden_layers(depth, 1, DepthRange::zero_one, seed() + 51);
    msmcl::FilterOptions options;
    const auto expect_error = [&](std::vector<TranslucentLayer> layers, const std::string& text) {
        try {
            msmcl::filter(*context_, depth, layers, options);
            ADD_FAILURE() << "no error for: " << text;
        } catch (const msmcl::input_error& e) {
            EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
        }
        msmcl::SatOptions sat_options;
        EXPECT_THROW(msmcl::build_sat(*context_, depth, layers, sat_options), msmcl::input_error) << text;
    };
    std::vector<TranslucentLayer> layers = good;
    layers[0].opacity[7] = 1.5f;
    expect_error(layers, "translucent layer 0 opacity at texel (3, 0) sample 1 is 1.5, outside [0, 1]");
    layers = good;
    layers[0].opacity[7] = std::nanf("");
    expect_error(layers, "translucent layer 0 opacity at texel (3, 0) sample 1 is nan");
    layers = good;
    layers[0].depth[41] = -0.25f;
    expect_error(layers, "translucent layer 0 depth at texel (0, 1) sample 1 is -0.25, outside the depth range [0,1]");
    layers = good;
    layers[0].depth.pop_back();
    expect_error(layers, "translucent layer 0 holds 399 depths");
    expect_error(std::vector<TranslucentLayer>(9, good[0]), "9 translucent layers (at most 8)");
}

TEST_F(Translucent, ExrLayersRoundTripAndFeedTheCli) {
    namespace fs = std::filesystem;
    std::string pattern = (fs::temp_directory_path() / "msmcl-translucent-test-XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    const fs::path root = pattern;
    const auto path = [&](const std::string& name) { return (root / name).string(); };

    // Write and read back, per-sample channels (S = 4) and one channel for all samples.
    msmcl::io::TranslucentDepth layered;
    layered.depth = make_depth(24, 16, 4, DepthRange::zero_one, seed() + 60);
    layered.layers = hidden_layers(layered.depth, 2, DepthRange::zero_one, seed() + 61);
    msmcl::io::write_translucent_depth_exr(path("layers.exr"), layered);
    const msmcl::io::TranslucentDepth back = msmcl::io::read_translucent_depth_exr(path("layers.exr"), DepthRange::zero_one);
    EXPECT_EQ(back.depth.depth, layered.depth.depth);
    ASSERT_EQ(back.layers.size(), 2u);
    for (int k = 0; k < 2; ++k) {
        EXPECT_EQ(back.layers[k].depth, layered.layers[k].depth);
        EXPECT_EQ(back.layers[k].opacity, layered.layers[k].opacity);
    }
    EXPECT_TRUE(msmcl::io::read_translucent_depth_exr(path("layers.exr"), DepthRange::zero_one).layers.size() == 2);
    msmcl::io::ExrImage image = msmcl::io::read_exr(path("layers.exr"));
    msmcl::io::ExrImage shared = image;
    shared.channels.erase(std::remove_if(shared.channels.begin(), shared.channels.end(),
                                         [](const msmcl::io::ExrChannel& c) { return c.name.rfind("layer1.", 0) == 0; }),
                          shared.channels.end());
    std::vector<float> one_per_texel(24 * 16, 0.25f);
    shared.channels.push_back({"layer1.Z", msmcl::io::SampleType::half, one_per_texel, {}});
    shared.channels.push_back({"layer1.A", msmcl::io::SampleType::float32, std::vector<float>(24 * 16, 0.5f), {}});
    msmcl::io::write_exr(path("shared.exr"), shared);
    const msmcl::io::TranslucentDepth broadcast = msmcl::io::read_translucent_depth_exr(path("shared.exr"), DepthRange::zero_one);
    ASSERT_EQ(broadcast.layers.size(), 2u);
    EXPECT_EQ(broadcast.layers[1].depth, std::vector<float>(24 * 16 * 4, 0.25f));
    EXPECT_EQ(broadcast.layers[1].opacity, std::vector<float>(24 * 16 * 4, 0.5f));
    // The opaque reader ignores the layers.
    EXPECT_EQ(msmcl::io::read_depth_exr(path("layers.exr"), DepthRange::zero_one).depth, layered.depth.depth);

    // Broken files: a gap in the numbering, a missing opacity, an opacity out of range.
    const auto expect_bad = [&](msmcl::io::ExrImage broken, const std::string& text) {
        msmcl::io::write_exr(path("bad.exr"), broken);
        try {
            msmcl::io::read_translucent_depth_exr(path("bad.exr"), DepthRange::zero_one);
            ADD_FAILURE() << "no error for: " << text;
        } catch (const msmcl::input_error& e) {
            EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
        }
    };
    msmcl::io::ExrImage gap = image;
    for (msmcl::io::ExrChannel& c : gap.channels)
        if (c.name.rfind("layer1.", 0) == 0) c.name.replace(0, 7, "layer2.");
    expect_bad(gap, "layer1 is missing");
    msmcl::io::ExrImage missing = image;
    missing.channels.erase(std::remove_if(missing.channels.begin(), missing.channels.end(),
                                          [](const msmcl::io::ExrChannel& c) { return c.name == "layer0.sample2.A"; }),
                           missing.channels.end());
    expect_bad(missing, "translucent layer 0 needs layer0.A or layer0.sample0.A .. layer0.sample3.A");
    msmcl::io::ExrImage dense = image;
    for (msmcl::io::ExrChannel& c : dense.channels)
        if (c.name == "layer1.sample3.A") c.values[5] = 2.0f;
    expect_bad(dense, "texel (5, 0) layer1.sample3.A: opacity 2 is outside [0, 1]");

    // msmcl filter and sat read the layers: the same texture and table as the library.
    if (!std::string(MSMCL_CLI_PATH).empty()) {
        const auto run_cli = [&](std::vector<std::string> arguments) {
            arguments.insert(arguments.begin(), MSMCL_CLI_PATH);
            const int exit_code = msmcl::testing::run_process(std::move(arguments), "/dev/null", "/dev/null");
            return exit_code == msmcl::testing::process_not_started ? -1 : exit_code;
        };
        ASSERT_EQ(run_cli({"filter", path("layers.exr"), path("map.exr"), "--format", "nlq64"}), 0);
        msmcl::FilterOptions options;
        EXPECT_EQ(msmcl::io::read_texture_exr(path("map.exr")).texture.words,
                  msmcl::filter(*context_, layered.depth, layered.layers, options).words);
        ASSERT_EQ(run_cli({"sat", path("layers.exr"), path("sat.exr")}), 0);
        msmcl::SatOptions sat_options;
        const msmcl::SatTable table = msmcl::build_sat(*context_, layered.depth, layered.layers, sat_options);
        const msmcl::io::ExrImage sat = msmcl::io::read_exr(path("sat.exr"));
        std::vector<std::uint32_t> words;
        for (std::size_t t = 0; t < table.words.size() / 4; ++t)
            for (const char* name : {"R", "G", "B", "A"}) words.push_back(sat.find_channel(name)->codes[t]);
        EXPECT_EQ(words, table.words);
        EXPECT_EQ(run_cli({"filter", path("bad.exr"), path("never.exr"), "--format", "nlq64"}), 2);
        EXPECT_FALSE(fs::exists(path("never.exr")));
    }
    fs::remove_all(root);
}

} // namespace
