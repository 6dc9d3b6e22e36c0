// shade kernel on PoCL against (a) the independent double-precision reconstruction of the
// same stored texture and (b) the host build of the same consumer math.
#include "io/exr_io.hpp"
#include "reference/moment_math.hpp"

#include <msmcl/filter.hpp>

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/shade.hpp>
#include <msmcl/device_math.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>

namespace ref = msmcl::reference;

#include "random_textures.hpp"
#include "seeded_test.hpp"

namespace {

using msmcl::testing::random_texture;

std::uint32_t test_seed() { return static_cast<std::uint32_t>(msmcl::testing::run_seed(20171122u)); }

class ShadeTest : public msmcl::testing::DeviceSuite<ShadeTest, 20171122u> {};

// A texel's depth distribution: what a filtered shadow map holds near silhouettes (two

// Algorithm 3 exactly as docs/math.md writes it (clamps 1e-6), in long double.
double reference_algorithm3(const ref::Nlq& t, double zf_in) {
    using real = long double;
    const real zf = zf_in, y1 = t.y1, y2 = t.y2;
    if (zf <= y1) return 0;
    const real dy = std::max(y2 - y1, real(1e-6));
    const real v2 = std::clamp(real(t.v2), real(1e-6), real(1) - real(1e-6));
    const real z = (zf - y1) / dy, x = real(t.xi4) / (dy * dy * dy * dy);
    real zl = z;
    if (zf <= y2) {
        const real q0 = -x / ((1 - v2) * z);
        const real q1 = -q0 * (v2 - z) / (v2 - v2 * z) - 1;
        zl = -q1 / 2 - std::sqrt(q1 * q1 / 4 - q0);
    }
    const real wl = 1 / ((1 - zl) * (1 - zl) / (1 - v2) + zl * zl / v2 + (1 - zl) * (1 - zl) * zl * zl / x);
    return static_cast<double>(zf <= y2 ? wl : 1 - wl);
}

// Double-precision shadow of one stored texel at internal depth zf: the format's decode,
// bias and reconstruction (generic 4MSM, or Algorithm 3 for the nlq formats).
double reference_texel_shadow(const msmcl::Texture& t, int x, int y, double zf) {
    const std::uint32_t* w = t.texel(x, y);
    switch (t.format) {
        case msmcl::Format::moments128: {
            const ref::Moments b{t.moment(x, y, 1), t.moment(x, y, 2), t.moment(x, y, 3), t.moment(x, y, 4)};
            return ref::hamburger4(ref::bias(b, ref::alpha_float, ref::bstar_float), zf).lower;
        }
        case msmcl::Format::msm64: {
            const ref::Moments b = ref::decode_msm64(ref::unpack_codes16({w[0], w[1]}));
            return ref::hamburger4(ref::bias(b, ref::alpha_msm64, ref::bstar_msm64), zf).lower;
        }
        case msmcl::Format::nlq64:
            return reference_algorithm3(ref::decode_nlq64(ref::unpack_codes16({w[0], w[1]})), zf);
        case msmcl::Format::nlq32:
            return reference_algorithm3(ref::decode_nlq32(w[0]), zf);
    }
    return 0;
}

// Reference moments a bilinear lookup interpolates (linear formats).
ref::Moments reference_linear_moments(const msmcl::Texture& t, int x, int y) {
    if (t.format == msmcl::Format::moments128)
        return {t.moment(x, y, 1), t.moment(x, y, 2), t.moment(x, y, 3), t.moment(x, y, 4)};
    const std::uint32_t* w = t.texel(x, y);
    return ref::decode_msm64(ref::unpack_codes16({w[0], w[1]}));
}

// The lookup of docs/math.md (Lookups), in double, written out independently of msm_shading.clh.
double reference_shade(const msmcl::Texture& t, double u, double v, double z, const msmcl::ShadeOptions& o) {
    const double zf = ref::internal_depth(z, o.depth_range == msmcl::DepthRange::zero_one) - o.depth_bias;
    auto clamp_index = [](double c, int size) {
        return static_cast<int>(std::clamp(std::floor(std::clamp(c, -1.0, double(size))), 0.0, double(size - 1)));
    };
    if (o.lookup == msmcl::Lookup::nearest)
        return reference_texel_shadow(t, clamp_index(u, t.width), clamp_index(v, t.height), zf);
    const double fx = std::clamp(u - 0.5, -1.0, double(t.width)), fy = std::clamp(v - 0.5, -1.0, double(t.height));
    const double tx = fx - std::floor(fx), ty = fy - std::floor(fy);
    const int x0 = clamp_index(fx, t.width), x1 = clamp_index(std::floor(fx) + 1, t.width);
    const int y0 = clamp_index(fy, t.height), y1 = clamp_index(std::floor(fy) + 1, t.height);
    const double w00 = (1 - tx) * (1 - ty), w10 = tx * (1 - ty), w01 = (1 - tx) * ty, w11 = tx * ty;
    if (t.format == msmcl::Format::moments128 || t.format == msmcl::Format::msm64) {
        const ref::Moments m[4] = {reference_linear_moments(t, x0, y0), reference_linear_moments(t, x1, y0),
                                   reference_linear_moments(t, x0, y1), reference_linear_moments(t, x1, y1)};
        const double w[4] = {w00, w10, w01, w11};
        ref::Moments b;
        for (int k = 0; k < 4; ++k) {
            b.b1 += w[k] * m[k].b1;
            b.b2 += w[k] * m[k].b2;
            b.b3 += w[k] * m[k].b3;
            b.b4 += w[k] * m[k].b4;
        }
        const bool f128 = t.format == msmcl::Format::moments128;
        return ref::hamburger4(ref::bias(b, f128 ? ref::alpha_float : ref::alpha_msm64,
                                         f128 ? ref::bstar_float : ref::bstar_msm64),
                               zf)
            .lower;
    }
    return w00 * reference_texel_shadow(t, x0, y0, zf) + w10 * reference_texel_shadow(t, x1, y0, zf) +
           w01 * reference_texel_shadow(t, x0, y1, zf) + w11 * reference_texel_shadow(t, x1, y1, zf);
}

struct ErrorStats {
    double max = 0;
    std::size_t above_1e4 = 0;
    std::size_t count = 0;
    void add(double e) {
        max = std::max(max, e);
        above_1e4 += e > 1e-4;
        ++count;
    }
    double share_above_1e4() const { return count ? double(above_1e4) / count : 0; }
};

struct ShadeCase {
    msmcl::Format format;
    msmcl::Lookup lookup;
    msmcl::DepthRange range;
};

class ShadeAgainstReference : public ShadeTest, public ::testing::WithParamInterface<ShadeCase> {};

TEST_P(ShadeAgainstReference, MatchesDoubleReconstructionAndHostMath) {
    const ShadeCase c = GetParam();
    std::mt19937 rng(test_seed() + static_cast<unsigned>(c.format) * 7 + static_cast<unsigned>(c.lookup));
    const int width = 37, height = 29;
    const msmcl::Texture map = random_texture(c.format, width, height, rng);

    // Receivers all over the map, a margin outside it (clamp to edge), depths through the range.
    msmcl::Receivers receivers;
    std::uniform_real_distribution<float> u(-3.0f, width + 3.0f), v(-3.0f, height + 3.0f), z01(0.0f, 1.0f);
    const std::size_t count = 20000;
    for (std::size_t i = 0; i < count; ++i) {
        receivers.u.push_back(u(rng));
        receivers.v.push_back(v(rng));
        const float d = z01(rng);
        receivers.z.push_back(c.range == msmcl::DepthRange::zero_one ? d : 2 * d - 1);
    }
    msmcl::ShadeOptions options;
    options.lookup = c.lookup;
    options.depth_range = c.range;
    const std::vector<float> device = msmcl::shade(*context_, map, receivers, options);
    ASSERT_EQ(device.size(), count);

    ErrorStats vs_reference, vs_host;
    std::size_t worst = 0;
    for (std::size_t i = 0; i < count; ++i) {
        ASSERT_TRUE(device[i] >= 0.0f && device[i] <= 1.0f) << "receiver " << i << " gave " << device[i];
        const double error = std::abs(device[i] - reference_shade(map, receivers.u[i], receivers.v[i], receivers.z[i], options));
        if (error > vs_reference.max) worst = i;
        vs_reference.add(error);
        vs_host.add(std::abs(device[i] - msmcl::shade_receiver(map, receivers.u[i], receivers.v[i], receivers.z[i], options)));
    }
    {
        // Where the largest difference is, for a person reading a failure.
        const int x = std::clamp(static_cast<int>(std::floor(receivers.u[worst])), 0, width - 1);
        const int y = std::clamp(static_cast<int>(std::floor(receivers.v[worst])), 0, height - 1);
        const double zf = ref::internal_depth(receivers.z[worst], c.range == msmcl::DepthRange::zero_one) - options.depth_bias;
        std::printf("worst receiver %zu at (%.3f, %.3f) zf %.6f: device %.6f, reference %.6f; texel (%d,%d) words",
                    worst, receivers.u[worst], receivers.v[worst], zf, device[worst],
                    reference_shade(map, receivers.u[worst], receivers.v[worst], receivers.z[worst], options), x, y);
        for (std::size_t k = 0; k < msmcl::texel_words(c.format); ++k) std::printf(" %08x", map.texel(x, y)[k]);
        std::printf("\n");
    }
    std::printf("%s/%s: vs double reference max %.3g, share > 1e-4 %.4f%%; vs host float max %.3g\n",
                msmcl::format_name(c.format), msmcl::lookup_name(c.lookup), vs_reference.max,
                100 * vs_reference.share_above_1e4(), vs_host.max);
    // Acceptance bound of the shade kernel: within 1e-4 for 99.9% of receivers, 1e-2 for all. The
    // float32 Cholesky of nearly singular (two-point) moments is where the rest comes from.
    EXPECT_LE(vs_reference.share_above_1e4(), 0.001);
    EXPECT_LE(vs_reference.max, 1e-2);
    // Same source on host and device: only libm ulps and contraction differ.
    EXPECT_LE(vs_host.share_above_1e4(), 0.001);
    EXPECT_LE(vs_host.max, 1e-2);
}

std::vector<ShadeCase> all_cases() {
    std::vector<ShadeCase> cases;
    for (auto f : {msmcl::Format::moments128, msmcl::Format::msm64, msmcl::Format::nlq64, msmcl::Format::nlq32})
        for (auto l : {msmcl::Lookup::nearest, msmcl::Lookup::bilinear})
            cases.push_back({f, l, l == msmcl::Lookup::nearest ? msmcl::DepthRange::zero_one
                                                               : msmcl::DepthRange::minus_one_one});
    return cases;
}

INSTANTIATE_TEST_SUITE_P(AllFormats, ShadeAgainstReference, ::testing::ValuesIn(all_cases()),
                         [](const auto& info) {
                             return std::string(msmcl::format_name(info.param.format)) + "_" +
                                    msmcl::lookup_name(info.param.lookup);
                         });

// The shipped sample scenes: real filtered maps (sigma 2.4), the receivers of a view.
class ShadeSampleScene : public ShadeTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(ShadeSampleScene, EveryFormatAndLookupMatchesTheDoubleReconstruction) {
    const std::string scene = GetParam();
    const msmcl::DepthImage depth =
        msmcl::io::read_depth_exr(std::string(MSMCL_SOURCE_DIR "/data/") + scene + "_256x256_4x.exr",
                                  msmcl::DepthRange::zero_one);
    const msmcl::io::ReceiverGrid view =
        msmcl::io::read_receivers_exr(std::string(MSMCL_SOURCE_DIR "/data/") + scene + "_view_160x120.exr");
    for (auto format : {msmcl::Format::moments128, msmcl::Format::msm64, msmcl::Format::nlq64, msmcl::Format::nlq32}) {
        msmcl::FilterOptions filter_options;
        filter_options.format = format;
        const msmcl::Texture map = msmcl::filter(*context_, depth, filter_options);
        for (auto lookup : {msmcl::Lookup::nearest, msmcl::Lookup::bilinear}) {
            msmcl::ShadeOptions options;
            options.lookup = lookup;
            const std::vector<float> device = msmcl::shade(*context_, map, view.points, options);
            ErrorStats stats;
            for (std::size_t i = 0; i < device.size(); ++i)
                stats.add(std::abs(device[i] - reference_shade(map, view.points.u[i], view.points.v[i],
                                                               view.points.z[i], options)));
            std::printf("%s %s/%s: %zu receivers, max error %.3g, share > 1e-4 %.4f%%\n", scene.c_str(),
                        msmcl::format_name(format), msmcl::lookup_name(lookup), stats.count, stats.max,
                        100 * stats.share_above_1e4());
            // Acceptance bound of the shade kernel (see the random-texel test above).
            EXPECT_LE(stats.share_above_1e4(), 0.001) << msmcl::format_name(format) << "/" << msmcl::lookup_name(lookup);
            EXPECT_LE(stats.max, 1e-2) << msmcl::format_name(format) << "/" << msmcl::lookup_name(lookup);
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Shipped, ShadeSampleScene, ::testing::Values("railing", "wuson"));

TEST_F(ShadeTest, RejectsBadInput) {
    std::mt19937 rng(test_seed());
    msmcl::Texture map = random_texture(msmcl::Format::nlq64, 4, 4, rng);
    msmcl::Receivers r{{1.0f}, {1.0f}, {0.5f}};
    msmcl::ShadeOptions o;
    EXPECT_NO_THROW(msmcl::shade(*context_, map, r, o));
    msmcl::Receivers nan_receiver{{1.0f}, {std::nanf("")}, {0.5f}};
    EXPECT_THROW(msmcl::shade(*context_, map, nan_receiver, o), msmcl::input_error);
    msmcl::Receivers ragged{{1.0f, 2.0f}, {1.0f}, {0.5f}};
    EXPECT_THROW(msmcl::shade(*context_, map, ragged, o), msmcl::input_error);
    msmcl::Texture short_map = map;
    short_map.words.pop_back();
    EXPECT_THROW(msmcl::shade(*context_, short_map, r, o), msmcl::input_error);
    msmcl::Texture empty_map = map;
    empty_map.width = 0;
    EXPECT_THROW(msmcl::shade(*context_, empty_map, r, o), msmcl::input_error);
    EXPECT_TRUE(msmcl::shade(*context_, map, msmcl::Receivers{}, o).empty());
}

TEST_F(ShadeTest, DevicePathWithEventsEqualsHostPath) {
    std::mt19937 rng(test_seed() + 99);
    const msmcl::Texture map = random_texture(msmcl::Format::nlq32, 16, 8, rng);
    msmcl::Receivers r;
    for (int i = 0; i < 300; ++i) {
        r.u.push_back(0.07f * i);
        r.v.push_back(0.03f * i);
        r.z.push_back(0.5f + 0.001f * i);
    }
    msmcl::ShadeOptions o;
    const std::vector<float> host = msmcl::shade(*context_, map, r, o);

    // Same call on caller-owned buffers, chained on an event, result read by the caller.
    cl_int status = CL_SUCCESS;
    cl_context ctx = context_->cl_context_handle();
    cl_command_queue q = context_->cl_queue_handle();
    cl_mem map_buffer = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, map.words.size() * 4,
                                       const_cast<std::uint32_t*>(map.words.data()), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    std::vector<float> uvz(r.u);
    uvz.insert(uvz.end(), r.v.begin(), r.v.end());
    uvz.insert(uvz.end(), r.z.begin(), r.z.end());
    cl_mem uvz_buffer = clCreateBuffer(ctx, CL_MEM_READ_ONLY, uvz.size() * 4, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_event uploaded = nullptr;
    ASSERT_EQ(clEnqueueWriteBuffer(q, uvz_buffer, CL_FALSE, 0, uvz.size() * 4, uvz.data(), 0, nullptr, &uploaded),
              CL_SUCCESS);
    cl_mem out = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, r.size() * 4, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_event done = nullptr;
    msmcl::Enqueue e;
    e.queue = q;
    e.wait_for = {uploaded};
    e.done = &done;
    msmcl::shade(*context_, msmcl::DeviceTexture{map_buffer, map.format, map.width, map.height}, uvz_buffer,
                 r.size(), out, o, e);
    ASSERT_NE(done, nullptr);
    std::vector<float> device(r.size());
    ASSERT_EQ(clEnqueueReadBuffer(q, out, CL_TRUE, 0, device.size() * 4, device.data(), 1, &done, nullptr),
              CL_SUCCESS);
    EXPECT_EQ(device, host);
    clReleaseEvent(done);
    clReleaseEvent(uploaded);
    for (cl_mem m : {map_buffer, uvz_buffer, out}) clReleaseMemObject(m);
}

} // namespace
