// The C API (include/msmcl/msmcl.h) as a binding of the C++ API: every C entry point gives
// the C++ call's result bit for bit (on the same device: the C context is made from the
// C++ one's OpenCL handles), its defaults are the C++ defaults, and what the C++ call
// throws arrives as the status code, message and OpenCL code the header documents. What
// the results mean (references, tolerances) is the C++ suites' subject. That the header is
// C and links against the shared library alone: tests/capi_c_test.c.
#include "seeded_test.hpp"

#include <msmcl/msmcl.h>

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/interop.hpp>
#include <msmcl/sat.hpp>
#include <msmcl/scatter.hpp>
#include <msmcl/shade.hpp>
#include <msmcl/version.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

namespace {

constexpr int width = 37, height = 29, samples = 4;
constexpr std::size_t texels = std::size_t(width) * height, values = texels * samples;

// The status, message and OpenCL code the C API owes for what a C++ call throws.
struct Outcome {
    msmcl_status status = MSMCL_SUCCESS;
    std::string message;
    cl_int opencl_code = CL_SUCCESS;
};

bool operator==(const Outcome& a, const Outcome& b) {
    return a.status == b.status && a.message == b.message && a.opencl_code == b.opencl_code;
}

std::ostream& operator<<(std::ostream& out, const Outcome& o) {
    return out << msmcl_status_name(o.status) << " '" << o.message << "' (OpenCL " << o.opencl_code << ")";
}

Outcome cpp_outcome(const std::function<void()>& call) {
    try {
        call();
        return {};
    } catch (const msmcl::build_error& e) {
        return {MSMCL_ERROR_BUILD, std::string(e.what()) + "\n" + e.log(), e.code()};
    } catch (const msmcl::opencl_error& e) {
        return {MSMCL_ERROR_OPENCL, e.what(), e.code()};
    } catch (const msmcl::input_error& e) {
        return {MSMCL_ERROR_INPUT, e.what()};
    } catch (const msmcl::device_error& e) {
        return {MSMCL_ERROR_DEVICE, e.what()};
    }
}

Outcome c_outcome(msmcl_status status) { return {status, msmcl_last_error_message(), msmcl_last_opencl_error()}; }

// The C enumerators of the C++ enums, as the header documents them.
msmcl_format c_format(msmcl::Format format) {
    switch (format) {
    case msmcl::Format::moments128: return MSMCL_FORMAT_MOMENTS128;
    case msmcl::Format::msm64: return MSMCL_FORMAT_MSM64;
    case msmcl::Format::nlq64: return MSMCL_FORMAT_NLQ64;
    case msmcl::Format::nlq32: break;
    }
    return MSMCL_FORMAT_NLQ32;
}

const std::vector<msmcl::Format> formats{msmcl::Format::moments128, msmcl::Format::msm64, msmcl::Format::nlq64,
                                         msmcl::Format::nlq32};

template <class T>
std::vector<T> read_buffer(cl_command_queue queue, cl_mem buffer, std::size_t count) {
    std::vector<T> out(count);
    EXPECT_EQ(clEnqueueReadBuffer(queue, buffer, CL_TRUE, 0, count * sizeof(T), out.data(), 0, nullptr, nullptr),
              CL_SUCCESS);
    return out;
}

std::vector<std::uint32_t> read_image(cl_command_queue queue, cl_mem image, std::size_t texel_words) {
    std::vector<std::uint32_t> out(texels * texel_words);
    const std::size_t origin[3] = {0, 0, 0}, region[3] = {width, height, 1};
    EXPECT_EQ(clEnqueueReadImage(queue, image, CL_TRUE, origin, region, 0, 0, out.data(), 0, nullptr, nullptr),
              CL_SUCCESS);
    return out;
}

class Capi : public msmcl::testing::DeviceSuite<Capi, 6u> {
protected:
    static void SetUpTestSuite() {
        DeviceSuite::SetUpTestSuite();
        if (!context_) return;
        ASSERT_EQ(msmcl_context_create_from_cl(context_->cl_context_handle(), context_->cl_device_handle(),
                                               context_->cl_queue_handle(), &c_context_),
                  MSMCL_SUCCESS)
            << msmcl_last_error_message();
    }
    static void TearDownTestSuite() {
        msmcl_context_destroy(c_context_);
        c_context_ = nullptr;
        DeviceSuite::TearDownTestSuite();
    }
    void SetUp() override {
        DeviceSuite::SetUp();
        std::mt19937 random(seed_);
        std::uniform_real_distribution<float> unit(0.0f, 1.0f);
        depth_.width = width, depth_.height = height, depth_.samples = samples;
        depth_.depth.resize(values);
        for (float& d : depth_.depth) d = unit(random);
        // Two layers: opacities a quarter 0, a quarter 1, the rest in (0, 1).
        layers_.assign(2, {});
        for (msmcl::TranslucentLayer& layer : layers_)
            for (std::size_t i = 0; i < values; ++i) {
                const float pick = unit(random);
                layer.depth.push_back(unit(random));
                layer.opacity.push_back(pick < 0.25f ? 0.0f : pick < 0.5f ? 1.0f : unit(random));
            }
    }

    cl_mem buffer(std::size_t bytes, const void* data = nullptr) {
        cl_int status = CL_SUCCESS;
        cl_mem memory = clCreateBuffer(context_->cl_context_handle(),
                                       CL_MEM_READ_WRITE | (data ? CL_MEM_COPY_HOST_PTR : 0), bytes,
                                       const_cast<void*>(data), &status);
        EXPECT_EQ(status, CL_SUCCESS);
        owned_.push_back(memory);
        return memory;
    }
    cl_mem image(cl_image_format format) {
        cl_image_desc description{};
        description.image_type = CL_MEM_OBJECT_IMAGE2D;
        description.image_width = width;
        description.image_height = height;
        cl_int status = CL_SUCCESS;
        cl_mem memory = clCreateImage(context_->cl_context_handle(), CL_MEM_READ_WRITE, &format, &description, nullptr,
                                      &status);
        EXPECT_EQ(status, CL_SUCCESS);
        owned_.push_back(memory);
        return memory;
    }
    void TearDown() override {
        for (cl_mem memory : owned_) clReleaseMemObject(memory);
    }
    cl_command_queue queue() const { return context_->cl_queue_handle(); }
    std::vector<msmcl_translucent_layer> c_layers() const {
        std::vector<msmcl_translucent_layer> out;
        for (const msmcl::TranslucentLayer& layer : layers_) out.push_back({layer.depth.data(), layer.opacity.data()});
        return out;
    }
    // The layers one after the other, as device buffers hold them.
    std::vector<float> stacked(std::vector<float> msmcl::TranslucentLayer::*field) const {
        std::vector<float> out;
        for (const msmcl::TranslucentLayer& layer : layers_)
            out.insert(out.end(), (layer.*field).begin(), (layer.*field).end());
        return out;
    }

    static inline msmcl_context* c_context_ = nullptr;
    msmcl::DepthImage depth_;
    std::vector<msmcl::TranslucentLayer> layers_;
    std::vector<cl_mem> owned_;
};

TEST(CapiPlain, VersionNamesAndFormatsAreTheCppOnes) {
    int major = -1, minor = -1, patch = -1;
    msmcl_version(&major, &minor, &patch);
    EXPECT_EQ(major, msmcl::version_major);
    EXPECT_EQ(minor, msmcl::version_minor);
    EXPECT_EQ(patch, msmcl::version_patch);
    EXPECT_STREQ(msmcl_version_string(), msmcl::version_string);
    EXPECT_STREQ(msmcl_status_name(MSMCL_ERROR_INPUT), "MSMCL_ERROR_INPUT");
    EXPECT_STREQ(msmcl_status_name(static_cast<msmcl_status>(99)), "MSMCL_UNKNOWN_STATUS");
    for (msmcl::Format format : formats) {
        const msmcl_format c = c_format(format);
        EXPECT_EQ(msmcl_texel_bytes(c), msmcl::texel_bytes(format));
        EXPECT_STREQ(msmcl_format_name(c), msmcl::format_name(format));
        msmcl_format parsed = static_cast<msmcl_format>(-1);
        EXPECT_EQ(msmcl_parse_format(msmcl::format_name(format), &parsed), MSMCL_SUCCESS);
        EXPECT_EQ(parsed, c);
        cl_image_format image_format{};
        EXPECT_EQ(msmcl_texture_image_format(c, &image_format), MSMCL_SUCCESS);
        const cl_image_format expected = msmcl::texture_image_format(format);
        EXPECT_EQ(image_format.image_channel_order, expected.image_channel_order);
        EXPECT_EQ(image_format.image_channel_data_type, expected.image_channel_data_type);
    }
    // Outside the enumerators (any int can come from C): no bytes, no name.
    EXPECT_EQ(msmcl_texel_bytes(static_cast<msmcl_format>(10)), 0u);
    EXPECT_EQ(msmcl_texel_bytes(static_cast<msmcl_format>(-1)), 0u);
    EXPECT_EQ(msmcl_format_name(static_cast<msmcl_format>(1 << 20)), nullptr);
    const cl_image_format sat = msmcl_sat_image_format(), sat_expected = msmcl::sat_image_format();
    EXPECT_EQ(sat.image_channel_order, sat_expected.image_channel_order);
    EXPECT_EQ(sat.image_channel_data_type, sat_expected.image_channel_data_type);
    for (std::uint32_t n : {2u, 27u * 27u, 4096u}) {
        std::uint32_t scale = 0;
        EXPECT_EQ(msmcl_sat_scale(n, &scale), MSMCL_SUCCESS);
        EXPECT_EQ(scale, msmcl::sat_scale(n)) << n;
    }
    std::uint32_t scale = 0;
    EXPECT_EQ(c_outcome(msmcl_sat_scale(1, &scale)), cpp_outcome([] { msmcl::sat_scale(1); }));
}

TEST(CapiPlain, OptionDefaultsAreTheCppDefaults) {
    msmcl_context_options context_options;
    msmcl_context_options_init(&context_options);
    const msmcl::DeviceSelection selection;
    EXPECT_EQ(context_options.device, nullptr);
    EXPECT_EQ(context_options.platform, nullptr);
    EXPECT_EQ(context_options.strict != 0, selection.strict);
    EXPECT_EQ(context_options.use_environment != 0, selection.use_environment);

    msmcl_filter_options filter;
    msmcl_filter_options_init(&filter);
    const msmcl::FilterOptions filter_cpp;
    EXPECT_EQ(filter.format, c_format(filter_cpp.format));
    EXPECT_EQ(filter.sigma, filter_cpp.sigma);
    EXPECT_EQ(filter.depth_range, MSMCL_DEPTH_RANGE_ZERO_ONE);
    EXPECT_EQ(filter_cpp.depth_range, msmcl::DepthRange::zero_one);
    EXPECT_EQ(filter.kernel, MSMCL_FILTER_KERNEL_AUTOMATIC);
    EXPECT_EQ(filter_cpp.kernel, msmcl::FilterKernel::automatic);

    msmcl_shade_options shade;
    msmcl_shade_options_init(&shade);
    const msmcl::ShadeOptions shade_cpp;
    EXPECT_EQ(shade.lookup, MSMCL_LOOKUP_BILINEAR);
    EXPECT_EQ(shade_cpp.lookup, msmcl::Lookup::bilinear);
    EXPECT_EQ(shade.depth_bias, shade_cpp.depth_bias);
    EXPECT_EQ(shade.depth_range, MSMCL_DEPTH_RANGE_ZERO_ONE);
    EXPECT_EQ(shade.frame, shade_cpp.frame);
    EXPECT_EQ(shade.screen_width, shade_cpp.screen_width);

    msmcl_sat_options sat;
    msmcl_sat_options_init(&sat);
    const msmcl::SatOptions sat_cpp;
    EXPECT_EQ(sat.max_kernel_texels, sat_cpp.max_kernel_texels);
    EXPECT_EQ(sat.depth_range, MSMCL_DEPTH_RANGE_ZERO_ONE);
    EXPECT_EQ(sat.kernel, MSMCL_SAT_KERNEL_AUTOMATIC);
    EXPECT_EQ(sat_cpp.kernel, msmcl::SatKernel::automatic);
    EXPECT_EQ(MSMCL_MAX_TRANSLUCENT_LAYERS, msmcl::max_translucent_layers);

    msmcl_soft_options soft;
    msmcl_soft_options_init(&soft);
    const msmcl::SoftShadowOptions soft_cpp;
    EXPECT_EQ(soft.light_size, soft_cpp.light_size);
    EXPECT_EQ(soft.search_size, soft_cpp.search_size);
    EXPECT_EQ(soft.min_filter_size, soft_cpp.min_filter_size);
    EXPECT_EQ(soft.depth_bias, soft_cpp.depth_bias);
    EXPECT_EQ(soft.depth_range, MSMCL_DEPTH_RANGE_ZERO_ONE);
    EXPECT_EQ(soft.receiver_blocker_weight, soft_cpp.receiver_blocker_weight);
    EXPECT_EQ(soft.filter_parts, soft_cpp.filter_parts);

    msmcl_scatter_scene scene;
    msmcl_scatter_scene_init(&scene);
    const msmcl::ScatterScene scene_cpp;
    const auto same_vector = [](const double (&c)[3], const msmcl::Vector3& cpp) {
        return c[0] == cpp[0] && c[1] == cpp[1] && c[2] == cpp[2];
    };
    EXPECT_TRUE(same_vector(scene.light.direction, scene_cpp.light.direction));
    EXPECT_TRUE(same_vector(scene.light.up, scene_cpp.light.up));
    EXPECT_TRUE(same_vector(scene.light.center, scene_cpp.light.center));
    EXPECT_EQ(scene.light.width, scene_cpp.light.width);
    EXPECT_EQ(scene.light.height, scene_cpp.light.height);
    EXPECT_EQ(scene.light.near_plane, scene_cpp.light.near);
    EXPECT_EQ(scene.light.far_plane, scene_cpp.light.far);
    EXPECT_EQ(scene.light.depth_range, MSMCL_DEPTH_RANGE_ZERO_ONE);
    EXPECT_EQ(scene_cpp.light.depth_range, msmcl::DepthRange::zero_one);
    EXPECT_TRUE(same_vector(scene.camera.position, scene_cpp.camera.position));
    EXPECT_TRUE(same_vector(scene.camera.forward, scene_cpp.camera.forward));
    EXPECT_TRUE(same_vector(scene.camera.up, scene_cpp.camera.up));
    EXPECT_EQ(scene.camera.vertical_fov_degrees, scene_cpp.camera.vertical_fov_degrees);
    EXPECT_EQ(scene.camera.near_plane, scene_cpp.camera.near);
    EXPECT_EQ(scene.camera.far_plane, scene_cpp.camera.far);
    EXPECT_EQ(scene.camera.width, scene_cpp.camera.width);
    EXPECT_EQ(scene.camera.height, scene_cpp.camera.height);
    EXPECT_EQ(scene.camera.depth, MSMCL_CAMERA_DEPTH_ZERO_ONE);
    EXPECT_EQ(scene_cpp.camera.depth, msmcl::CameraDepth::zero_one);
    EXPECT_EQ(scene.medium.extinction, scene_cpp.medium.extinction);
    EXPECT_EQ(scene.medium.phase_g, scene_cpp.medium.phase_g);
    EXPECT_EQ(scene.medium.irradiance, scene_cpp.medium.irradiance);
    EXPECT_EQ(scene.rectified_width, scene_cpp.rectified_width);
    EXPECT_EQ(scene.rectified_height, scene_cpp.rectified_height);
    EXPECT_EQ(scene.guard_band, scene_cpp.guard_band);
    EXPECT_EQ(msmcl_scatter_map_bytes(&scene), msmcl::scatter_map_bytes(scene_cpp));
    EXPECT_EQ(msmcl_scatter_map_bytes(nullptr), 0u);

    msmcl_scatter_options scatter;
    msmcl_scatter_options_init(&scatter);
    const msmcl::ScatterOptions scatter_cpp;
    EXPECT_EQ(scatter.moments, scatter_cpp.moments);
    EXPECT_EQ(scatter.filtered != 0, scatter_cpp.filtered);
    EXPECT_EQ(scatter.filter_sigma, scatter_cpp.filter_sigma);
    EXPECT_EQ(scatter.beta, scatter_cpp.beta);
    EXPECT_EQ(scatter.kernel, MSMCL_SCATTER_KERNEL_AUTOMATIC);
    EXPECT_EQ(scatter_cpp.kernel, msmcl::ScatterKernel::automatic);
    EXPECT_EQ(scatter.filter_kernel, MSMCL_FILTER_KERNEL_AUTOMATIC);
    EXPECT_EQ(scatter_cpp.filter_kernel, msmcl::FilterKernel::automatic);
}

TEST_F(Capi, ContextsAreTheCppContexts) {
    // Made from the C++ context's handles: the same objects.
    EXPECT_EQ(msmcl_context_cl_context(c_context_), context_->cl_context_handle());
    EXPECT_EQ(msmcl_context_cl_device(c_context_), context_->cl_device_handle());
    EXPECT_EQ(msmcl_context_cl_queue(c_context_), context_->cl_queue_handle());
    EXPECT_EQ(std::string(msmcl_context_device_name(c_context_)), context_->device().name);
    EXPECT_EQ(msmcl_context_set_binary_cache_dir(c_context_, nullptr), MSMCL_SUCCESS);
    EXPECT_EQ(msmcl_context_finish(c_context_), MSMCL_SUCCESS);
    EXPECT_GE(msmcl_context_programs_built(c_context_), 0u);
    // The default device, as msmcl::Context picks it.
    msmcl_context* chosen = nullptr;
    ASSERT_EQ(msmcl_context_create(nullptr, &chosen), MSMCL_SUCCESS) << msmcl_last_error_message();
    EXPECT_EQ(std::string(msmcl_context_device_name(chosen)), msmcl::Context().device().name);
    msmcl_context_destroy(chosen);
    // A strict spec that matches nothing: the C++ device_error.
    msmcl_context_options options;
    msmcl_context_options_init(&options);
    options.device = "no-such-device-name-xyz";
    options.strict = 1;
    options.use_environment = 0;
    msmcl::DeviceSelection selection;
    selection.device = options.device;
    selection.strict = true;
    selection.use_environment = false;
    msmcl_context* none = nullptr;
    EXPECT_EQ(c_outcome(msmcl_context_create(&options, &none)), cpp_outcome([&] { msmcl::Context{selection}; }));
    EXPECT_EQ(none, nullptr);
}

TEST_F(Capi, FilterEqualsCpp) {
    for (msmcl::Format format : formats)
        for (auto [c_kernel, kernel] : {std::pair{MSMCL_FILTER_KERNEL_AUTOMATIC, msmcl::FilterKernel::automatic},
                                        std::pair{MSMCL_FILTER_KERNEL_FUSED_PAPER, msmcl::FilterKernel::fused_paper},
                                        std::pair{MSMCL_FILTER_KERNEL_THREE_PASS, msmcl::FilterKernel::three_pass},
                                        std::pair{MSMCL_FILTER_KERNEL_FUSED_CPU, msmcl::FilterKernel::fused_cpu}}) {
            msmcl_filter_options options;
            msmcl_filter_options_init(&options);
            options.format = c_format(format);
            options.kernel = c_kernel;
            msmcl::FilterOptions cpp;
            cpp.format = format;
            cpp.kernel = kernel;
            const msmcl::Texture expected = msmcl::filter(*context_, depth_, cpp);
            std::vector<std::uint32_t> words(expected.words.size());
            ASSERT_EQ(msmcl_filter(c_context_, depth_.depth.data(), width, height, samples, &options, words.data(),
                                   words.size() * 4),
                      MSMCL_SUCCESS)
                << msmcl_last_error_message();
            EXPECT_EQ(words, expected.words) << msmcl::format_name(format) << " " << msmcl::filter_kernel_name(kernel);
        }
    // sigma and the depth range reach the C++ options.
    msmcl_filter_options options;
    msmcl_filter_options_init(&options);
    options.sigma = 0.5f;
    options.depth_range = MSMCL_DEPTH_RANGE_MINUS_ONE_ONE;
    msmcl::FilterOptions cpp;
    cpp.sigma = 0.5f;
    cpp.depth_range = msmcl::DepthRange::minus_one_one;
    const msmcl::Texture expected = msmcl::filter(*context_, depth_, cpp);
    std::vector<std::uint32_t> words(expected.words.size());
    ASSERT_EQ(msmcl_filter(c_context_, depth_.depth.data(), width, height, samples, &options, words.data(),
                           words.size() * 4),
              MSMCL_SUCCESS);
    EXPECT_EQ(words, expected.words);
    // NULL options are the defaults.
    ASSERT_EQ(msmcl_filter(c_context_, depth_.depth.data(), width, height, samples, nullptr, words.data(),
                           words.size() * 4),
              MSMCL_SUCCESS);
    EXPECT_EQ(words, msmcl::filter(*context_, depth_, msmcl::FilterOptions{}).words);
}

TEST_F(Capi, FilterDeviceEqualsCpp) {
    msmcl_filter_options options;
    msmcl_filter_options_init(&options);
    options.format = MSMCL_FORMAT_NLQ32;
    msmcl::FilterOptions cpp;
    cpp.format = msmcl::Format::nlq32;
    cl_mem depth = buffer(values * 4, depth_.depth.data());
    const msmcl_device_depth c_depth{depth, width, height, samples, MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
    const msmcl::DeviceDepth cpp_depth{depth, width, height, samples};

    // buffer -> buffer, with the enqueue plumbing: a wait list and a done event.
    cl_mem c_texture = buffer(texels * 4), cpp_texture = buffer(texels * 4);
    cl_int status = CL_SUCCESS;
    cl_event gate = clCreateUserEvent(context_->cl_context_handle(), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_event done = nullptr;
    msmcl_enqueue enqueue{nullptr, &gate, 1, &done, 0};
    ASSERT_EQ(msmcl_filter_device(c_context_, &c_depth, c_texture, &options, &enqueue), MSMCL_SUCCESS)
        << msmcl_last_error_message();
    ASSERT_NE(done, nullptr);
    clSetUserEventStatus(gate, CL_COMPLETE);
    clWaitForEvents(1, &done);
    clReleaseEvent(done);
    clReleaseEvent(gate);
    msmcl::filter(*context_, cpp_depth, cpp_texture, cpp);
    EXPECT_EQ(read_buffer<std::uint32_t>(queue(), c_texture, texels), read_buffer<std::uint32_t>(queue(), cpp_texture, texels));

    // buffer -> image.
    cl_image_format nlq32{};
    ASSERT_EQ(msmcl_texture_image_format(MSMCL_FORMAT_NLQ32, &nlq32), MSMCL_SUCCESS);
    cl_mem c_image = image(nlq32), cpp_image = image(nlq32);
    ASSERT_EQ(msmcl_filter_device(c_context_, &c_depth, c_image, &options, nullptr), MSMCL_SUCCESS);
    msmcl::filter_to_image(*context_, cpp_depth, cpp_image, cpp);
    EXPECT_EQ(read_image(queue(), c_image, 1), read_image(queue(), cpp_image, 1));

    // image (samples side by side) -> buffer and -> image.
    cl_image_desc description{};
    description.image_type = CL_MEM_OBJECT_IMAGE2D;
    description.image_width = std::size_t(width) * samples;
    description.image_height = height;
    const cl_image_format r_float{CL_R, CL_FLOAT};
    cl_mem depth_image = clCreateImage(context_->cl_context_handle(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, &r_float,
                                       &description, depth_.depth.data(), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    owned_.push_back(depth_image);
    const msmcl_device_depth c_depth_image{depth_image, width, height, samples, MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
    msmcl::DeviceDepthImage cpp_depth_image;
    cpp_depth_image.image = depth_image;
    cpp_depth_image.width = width, cpp_depth_image.height = height, cpp_depth_image.samples = samples;
    ASSERT_EQ(msmcl_filter_device(c_context_, &c_depth_image, c_texture, &options, nullptr), MSMCL_SUCCESS)
        << msmcl_last_error_message();
    msmcl::filter(*context_, cpp_depth_image, cpp_texture, cpp);
    EXPECT_EQ(read_buffer<std::uint32_t>(queue(), c_texture, texels), read_buffer<std::uint32_t>(queue(), cpp_texture, texels));
    ASSERT_EQ(msmcl_filter_device(c_context_, &c_depth_image, c_image, &options, nullptr), MSMCL_SUCCESS);
    msmcl::filter_to_image(*context_, cpp_depth_image, cpp_image, cpp);
    EXPECT_EQ(read_image(queue(), c_image, 1), read_image(queue(), cpp_image, 1));
    // A sample layout outside the enum names itself.
    msmcl_device_depth unknown_layout = c_depth_image;
    unknown_layout.layout = static_cast<msmcl_sample_layout>(5);
    EXPECT_EQ(msmcl_filter_device(c_context_, &unknown_layout, c_texture, &options, nullptr),
              MSMCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(msmcl_last_error_message()).find("sample layout 5"), std::string::npos)
        << msmcl_last_error_message();

    // The layered versions with no layers are the plain ones; with layers, buffers.
    ASSERT_EQ(msmcl_filter_layered_device(c_context_, &c_depth, nullptr, c_image, &options, nullptr), MSMCL_SUCCESS);
    EXPECT_EQ(read_image(queue(), c_image, 1), read_image(queue(), cpp_image, 1));
    const std::vector<float> layer_depth = stacked(&msmcl::TranslucentLayer::depth);
    const std::vector<float> layer_opacity = stacked(&msmcl::TranslucentLayer::opacity);
    cl_mem depth_layers = buffer(layer_depth.size() * 4, layer_depth.data());
    cl_mem opacity_layers = buffer(layer_opacity.size() * 4, layer_opacity.data());
    const msmcl_device_layers c_layers{depth_layers, opacity_layers, 2};
    ASSERT_EQ(msmcl_filter_layered_device(c_context_, &c_depth, &c_layers, c_texture, &options, nullptr),
              MSMCL_SUCCESS)
        << msmcl_last_error_message();
    msmcl::filter(*context_, cpp_depth, msmcl::DeviceLayers{depth_layers, opacity_layers, 2}, cpp_texture, cpp);
    EXPECT_EQ(read_buffer<std::uint32_t>(queue(), c_texture, texels), read_buffer<std::uint32_t>(queue(), cpp_texture, texels));
    // Buffers too small for the count: the C++ input error.
    const msmcl_device_layers too_many{depth_layers, opacity_layers, 3};
    EXPECT_EQ(c_outcome(msmcl_filter_layered_device(c_context_, &c_depth, &too_many, c_texture, &options, nullptr)),
              cpp_outcome([&] {
                  msmcl::filter(*context_, cpp_depth, msmcl::DeviceLayers{depth_layers, opacity_layers, 3},
                                cpp_texture, cpp);
              }));
}

TEST_F(Capi, FilterLayeredEqualsCpp) {
    const std::vector<msmcl_translucent_layer> layers = c_layers();
    for (msmcl::Format format : {msmcl::Format::moments128, msmcl::Format::nlq64}) {
        msmcl_filter_options options;
        msmcl_filter_options_init(&options);
        options.format = c_format(format);
        msmcl::FilterOptions cpp;
        cpp.format = format;
        const msmcl::Texture expected = msmcl::filter(*context_, depth_, layers_, cpp);
        std::vector<std::uint32_t> words(expected.words.size());
        ASSERT_EQ(msmcl_filter_layered(c_context_, depth_.depth.data(), width, height, samples, layers.data(),
                                       layers.size(), &options, words.data(), words.size() * 4),
                  MSMCL_SUCCESS)
            << msmcl_last_error_message();
        EXPECT_EQ(words, expected.words) << msmcl::format_name(format);
    }
}

TEST_F(Capi, ShadeEqualsCpp) {
    const msmcl::Texture map = msmcl::filter(*context_, depth_, msmcl::FilterOptions{});
    constexpr std::size_t count = 300;
    std::mt19937 random(seed_ + 1);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    msmcl::Receivers receivers;
    msmcl::ReceiverPixels pixels;
    for (std::size_t i = 0; i < count; ++i) {
        receivers.u.push_back(-2.0f + (width + 4) * unit(random));
        receivers.v.push_back(-2.0f + (height + 4) * unit(random));
        receivers.z.push_back(unit(random));
        pixels.x.push_back(std::uint32_t(1920 * unit(random)));
        pixels.y.push_back(std::uint32_t(1080 * unit(random)));
    }
    std::vector<float> uvz = receivers.u;
    uvz.insert(uvz.end(), receivers.v.begin(), receivers.v.end());
    uvz.insert(uvz.end(), receivers.z.begin(), receivers.z.end());
    std::vector<std::uint32_t> xy = pixels.x;
    xy.insert(xy.end(), pixels.y.begin(), pixels.y.end());
    cl_mem map_buffer = buffer(map.words.size() * 4, map.words.data());
    cl_mem uvz_buffer = buffer(uvz.size() * 4, uvz.data());
    cl_mem xy_buffer = buffer(xy.size() * 4, xy.data());
    cl_mem c_out = buffer(count * 4), cpp_out = buffer(count * 4);
    const msmcl::DeviceTexture device_map{map_buffer, map.format, width, height};
    for (auto [c_lookup, lookup] : {std::pair{MSMCL_LOOKUP_NEAREST, msmcl::Lookup::nearest},
                                    std::pair{MSMCL_LOOKUP_BILINEAR, msmcl::Lookup::bilinear},
                                    std::pair{MSMCL_LOOKUP_DITHER, msmcl::Lookup::dither}}) {
        msmcl_shade_options options;
        msmcl_shade_options_init(&options);
        options.lookup = c_lookup;
        options.depth_bias = 2e-3f;
        options.frame = 5;
        options.screen_width = 41;
        msmcl::ShadeOptions cpp;
        cpp.lookup = lookup;
        cpp.depth_bias = 2e-3f;
        cpp.frame = 5;
        cpp.screen_width = 41;
        const std::string name = msmcl::lookup_name(lookup);
        std::vector<float> intensity(count, -1.0f);
        ASSERT_EQ(msmcl_shade(c_context_, MSMCL_FORMAT_NLQ64, width, height, map.words.data(), map.words.size() * 4,
                              receivers.u.data(), receivers.v.data(), receivers.z.data(), count, &options,
                              intensity.data()),
                  MSMCL_SUCCESS)
            << msmcl_last_error_message();
        EXPECT_EQ(intensity, msmcl::shade(*context_, map, receivers, cpp)) << name;
        ASSERT_EQ(msmcl_shade_with_pixels(c_context_, MSMCL_FORMAT_NLQ64, width, height, map.words.data(),
                                          map.words.size() * 4, receivers.u.data(), receivers.v.data(),
                                          receivers.z.data(), pixels.x.data(), pixels.y.data(), count, &options,
                                          intensity.data()),
                  MSMCL_SUCCESS);
        EXPECT_EQ(intensity, msmcl::shade(*context_, map, receivers, pixels, cpp)) << name;
        // Device versions: row-major pixels, and a pixel buffer.
        msmcl_enqueue blocking{nullptr, nullptr, 0, nullptr, 1};
        ASSERT_EQ(msmcl_shade_device(c_context_, MSMCL_FORMAT_NLQ64, width, height, map_buffer, uvz_buffer, count,
                                     c_out, &options, &blocking),
                  MSMCL_SUCCESS);
        msmcl::shade(*context_, device_map, uvz_buffer, count, cpp_out, cpp);
        EXPECT_EQ(read_buffer<float>(queue(), c_out, count), read_buffer<float>(queue(), cpp_out, count)) << name;
        ASSERT_EQ(msmcl_shade_with_pixels_device(c_context_, MSMCL_FORMAT_NLQ64, width, height, map_buffer, uvz_buffer,
                                                 xy_buffer, count, c_out, &options, &blocking),
                  MSMCL_SUCCESS);
        msmcl::shade(*context_, device_map, uvz_buffer, xy_buffer, count, cpp_out, cpp);
        EXPECT_EQ(read_buffer<float>(queue(), c_out, count), read_buffer<float>(queue(), cpp_out, count)) << name;
    }
}

TEST_F(Capi, BuildSatEqualsCpp) {
    for (auto [c_kernel, kernel] : {std::pair{MSMCL_SAT_KERNEL_AUTOMATIC, msmcl::SatKernel::automatic},
                                    std::pair{MSMCL_SAT_KERNEL_TILED_GPU, msmcl::SatKernel::tiled_gpu},
                                    std::pair{MSMCL_SAT_KERNEL_TILED_CPU, msmcl::SatKernel::tiled_cpu},
                                    std::pair{MSMCL_SAT_KERNEL_ROW_PER_THREAD, msmcl::SatKernel::row_per_thread}}) {
        msmcl_sat_options options;
        msmcl_sat_options_init(&options);
        options.kernel = c_kernel;
        options.max_kernel_texels = 15 * 15;
        msmcl::SatOptions cpp;
        cpp.kernel = kernel;
        cpp.max_kernel_texels = 15 * 15;
        std::vector<std::uint32_t> table(4 * texels);
        ASSERT_EQ(msmcl_build_sat(c_context_, depth_.depth.data(), width, height, samples, &options, table.data(),
                                  table.size()),
                  MSMCL_SUCCESS)
            << msmcl_last_error_message();
        EXPECT_EQ(table, msmcl::build_sat(*context_, depth_, cpp).words) << msmcl::sat_kernel_name(kernel);
    }
    // Layered, host and device.
    const std::vector<msmcl_translucent_layer> layers = c_layers();
    std::vector<std::uint32_t> table(4 * texels);
    ASSERT_EQ(msmcl_build_sat_layered(c_context_, depth_.depth.data(), width, height, samples, layers.data(),
                                      layers.size(), nullptr, table.data(), table.size()),
              MSMCL_SUCCESS)
        << msmcl_last_error_message();
    EXPECT_EQ(table, msmcl::build_sat(*context_, depth_, layers_, msmcl::SatOptions{}).words);
    cl_mem depth = buffer(values * 4, depth_.depth.data());
    const msmcl_device_depth c_depth{depth, width, height, samples, MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
    const msmcl::DeviceDepth cpp_depth{depth, width, height, samples};
    const std::vector<float> layer_depth = stacked(&msmcl::TranslucentLayer::depth);
    const std::vector<float> layer_opacity = stacked(&msmcl::TranslucentLayer::opacity);
    cl_mem depth_layers = buffer(layer_depth.size() * 4, layer_depth.data());
    cl_mem opacity_layers = buffer(layer_opacity.size() * 4, layer_opacity.data());
    const msmcl_device_layers c_layers{depth_layers, opacity_layers, 2};
    cl_mem c_table = buffer(16 * texels), cpp_table = buffer(16 * texels);
    ASSERT_EQ(msmcl_build_sat_layered_device(c_context_, &c_depth, &c_layers, c_table, nullptr, nullptr),
              MSMCL_SUCCESS)
        << msmcl_last_error_message();
    msmcl::build_sat(*context_, cpp_depth, msmcl::DeviceLayers{depth_layers, opacity_layers, 2}, cpp_table,
                     msmcl::SatOptions{});
    EXPECT_EQ(read_buffer<std::uint32_t>(queue(), c_table, 4 * texels),
              read_buffer<std::uint32_t>(queue(), cpp_table, 4 * texels));
    // Device, into a buffer and into an image.
    ASSERT_EQ(msmcl_build_sat_device(c_context_, &c_depth, c_table, nullptr, nullptr), MSMCL_SUCCESS);
    msmcl::build_sat(*context_, cpp_depth, cpp_table, msmcl::SatOptions{});
    EXPECT_EQ(read_buffer<std::uint32_t>(queue(), c_table, 4 * texels),
              read_buffer<std::uint32_t>(queue(), cpp_table, 4 * texels));
    cl_mem c_image = image(msmcl_sat_image_format()), cpp_image = image(msmcl::sat_image_format());
    ASSERT_EQ(msmcl_build_sat_device(c_context_, &c_depth, c_image, nullptr, nullptr), MSMCL_SUCCESS);
    msmcl::build_sat_to_image(*context_, cpp_depth, cpp_image, msmcl::SatOptions{});
    EXPECT_EQ(read_image(queue(), c_image, 4), read_image(queue(), cpp_image, 4));
}

// What the C++ API throws arrives as its status, with its message (and OpenCL code).
// Soft shadows with the defaults, the published method and other values of every option.
TEST_F(Capi, SoftShadeEqualsCpp) {
    msmcl::SatOptions sat;
    sat.max_kernel_texels = 100;
    const msmcl::SatTable table = msmcl::build_sat(*context_, depth_, sat);
    std::mt19937 random(seed_ + 2);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    msmcl::Receivers receivers;
    for (int i = 0; i < 200; ++i) {
        receivers.u.push_back(-2.0f + (width + 4) * unit(random));
        receivers.v.push_back(-2.0f + (height + 4) * unit(random));
        receivers.z.push_back(unit(random));
    }
    for (int variant = 0; variant < 3; ++variant) {
        msmcl_soft_options options;
        msmcl_soft_options_init(&options);
        msmcl::SoftShadowOptions cpp;
        options.light_size = cpp.light_size = 20.0f;
        if (variant == 1) { // as published
            options.receiver_blocker_weight = cpp.receiver_blocker_weight = 0.0f;
            options.filter_parts = cpp.filter_parts = 1;
        } else if (variant == 2) {
            options.search_size = cpp.search_size = 7;
            options.min_filter_size = cpp.min_filter_size = 2.0f;
            options.depth_bias = cpp.depth_bias = 0.02f;
            options.depth_range = MSMCL_DEPTH_RANGE_MINUS_ONE_ONE;
            cpp.depth_range = msmcl::DepthRange::minus_one_one;
            options.receiver_blocker_weight = cpp.receiver_blocker_weight = 0.3f;
            options.filter_parts = cpp.filter_parts = 3;
        }
        std::vector<float> intensity(receivers.size(), -1.0f);
        ASSERT_EQ(msmcl_soft_shade(c_context_, table.words.data(), width, height, 100, receivers.u.data(),
                                   receivers.v.data(), receivers.z.data(), receivers.size(), &options,
                                   intensity.data()),
                  MSMCL_SUCCESS)
            << msmcl_last_error_message();
        EXPECT_EQ(intensity, msmcl::soft_shade(*context_, table, receivers, cpp)) << variant;
    }
    // Errors: the C++ API's, and NULL arguments named.
    msmcl_soft_options bad;
    msmcl_soft_options_init(&bad);
    bad.filter_parts = 5;
    msmcl::SoftShadowOptions bad_cpp;
    bad_cpp.filter_parts = 5;
    std::vector<float> intensity(receivers.size());
    EXPECT_EQ(c_outcome(msmcl_soft_shade(c_context_, table.words.data(), width, height, 100, receivers.u.data(),
                                         receivers.v.data(), receivers.z.data(), receivers.size(), &bad,
                                         intensity.data())),
              cpp_outcome([&] { msmcl::soft_shade(*context_, table, receivers, bad_cpp); }));
    EXPECT_EQ(msmcl_soft_shade(c_context_, nullptr, width, height, 100, receivers.u.data(), receivers.v.data(),
                               receivers.z.data(), receivers.size(), nullptr, intensity.data()),
              MSMCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(msmcl_last_error_message()).find("table"), std::string::npos) << msmcl_last_error_message();
}

// The device version reads the table from a buffer or an image and keeps the queue and
// event semantics of the other device calls (wait list, done event).
TEST_F(Capi, SoftShadeDeviceEqualsCpp) {
    msmcl::SatOptions sat;
    sat.max_kernel_texels = 100;
    const msmcl::SatTable table = msmcl::build_sat(*context_, depth_, sat);
    std::mt19937 random(seed_ + 3);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    constexpr std::size_t count = 150;
    msmcl::Receivers receivers;
    for (std::size_t i = 0; i < count; ++i) {
        receivers.u.push_back(-2.0f + (width + 4) * unit(random));
        receivers.v.push_back(-2.0f + (height + 4) * unit(random));
        receivers.z.push_back(unit(random));
    }
    std::vector<float> uvz = receivers.u;
    uvz.insert(uvz.end(), receivers.v.begin(), receivers.v.end());
    uvz.insert(uvz.end(), receivers.z.begin(), receivers.z.end());
    cl_mem c_table = buffer(table.words.size() * 4, table.words.data());
    cl_mem c_receivers = buffer(uvz.size() * 4, uvz.data());
    cl_mem c_intensity = buffer(count * 4);
    msmcl_soft_options options;
    msmcl_soft_options_init(&options);
    msmcl::SoftShadowOptions cpp;
    options.light_size = cpp.light_size = 20.0f;
    options.filter_parts = cpp.filter_parts = 3;
    options.depth_range = MSMCL_DEPTH_RANGE_MINUS_ONE_ONE;
    cpp.depth_range = msmcl::DepthRange::minus_one_one;
    // After a user event, with a done event: nothing runs before the event completes.
    cl_int status = CL_SUCCESS;
    cl_event gate = clCreateUserEvent(context_->cl_context_handle(), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_event done = nullptr;
    const msmcl_enqueue chained{nullptr, &gate, 1, &done, 0};
    ASSERT_EQ(msmcl_soft_shade_device(c_context_, c_table, width, height, 100, c_receivers, count, c_intensity,
                                      &options, &chained),
              MSMCL_SUCCESS)
        << msmcl_last_error_message();
    ASSERT_NE(done, nullptr);
    ASSERT_EQ(clSetUserEventStatus(gate, CL_COMPLETE), CL_SUCCESS);
    ASSERT_EQ(clWaitForEvents(1, &done), CL_SUCCESS);
    clReleaseEvent(done);
    clReleaseEvent(gate);
    EXPECT_EQ(read_buffer<float>(queue(), c_intensity, count), msmcl::soft_shade(*context_, table, receivers, cpp));

    // The table in an image, as msmcl_build_sat_device writes one.
    cl_mem image_table = image(msmcl_sat_image_format());
    msmcl_sat_options c_sat;
    msmcl_sat_options_init(&c_sat);
    c_sat.max_kernel_texels = 100;
    const msmcl_device_depth c_depth{buffer(values * 4, depth_.depth.data()), width, height, samples,
                                     MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
    ASSERT_EQ(msmcl_build_sat_device(c_context_, &c_depth, image_table, &c_sat, nullptr), MSMCL_SUCCESS);
    const msmcl_enqueue blocking{nullptr, nullptr, 0, nullptr, 1};
    ASSERT_EQ(msmcl_soft_shade_device(c_context_, image_table, width, height, 100, c_receivers, count, c_intensity,
                                      &options, &blocking),
              MSMCL_SUCCESS)
        << msmcl_last_error_message();
    EXPECT_EQ(read_buffer<float>(queue(), c_intensity, count), msmcl::soft_shade(*context_, table, receivers, cpp));

    // Errors: the C++ API's (buffer and image), NULL arguments named.
    const msmcl::DeviceSat cpp_table{c_table, width, height, 100};
    msmcl_soft_options bad = options;
    bad.search_size = 11;
    msmcl::SoftShadowOptions bad_cpp = cpp;
    bad_cpp.search_size = 11;
    EXPECT_EQ(c_outcome(msmcl_soft_shade_device(c_context_, c_table, width, height, 100, c_receivers, count,
                                                c_intensity, &bad, nullptr)),
              cpp_outcome([&] { msmcl::soft_shade(*context_, cpp_table, c_receivers, count, c_intensity, bad_cpp); }));
    EXPECT_EQ(c_outcome(msmcl_soft_shade_device(c_context_, c_table, width, height, 1, c_receivers, count,
                                                c_intensity, nullptr, nullptr)),
              cpp_outcome([&] {
                  msmcl::soft_shade(*context_, msmcl::DeviceSat{c_table, width, height, 1}, c_receivers, count,
                                    c_intensity, msmcl::SoftShadowOptions{});
              }));
    EXPECT_EQ(c_outcome(msmcl_soft_shade_device(c_context_, image_table, width + 1, height, 100, c_receivers, count,
                                                c_intensity, nullptr, nullptr)),
              cpp_outcome([&] {
                  msmcl::soft_shade(*context_, msmcl::DeviceSatImage{image_table, width + 1, height, 100}, c_receivers,
                                    count, c_intensity, msmcl::SoftShadowOptions{});
              }));
    EXPECT_EQ(msmcl_last_error_message(), std::string("soft: the table image is 37x29, smaller than the 38x29 table"));
    EXPECT_EQ(msmcl_soft_shade_device(c_context_, c_table, width, height, 100, nullptr, count, c_intensity, nullptr,
                                      nullptr),
              MSMCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(msmcl_last_error_message()).find("receivers_uvz"), std::string::npos)
        << msmcl_last_error_message();
}

// Texture arrays of translucent shadow maps: three array layers under two translucent
// layers, host and device, filter and SAT.
TEST_F(Capi, ArraysWithTranslucentLayersEqualCpp) {
    constexpr int array_layers = 3;
    std::mt19937 random(seed_ + 4);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    msmcl::DepthImage stack = depth_;
    stack.layers = array_layers;
    stack.depth.resize(values * array_layers);
    for (float& d : stack.depth) d = unit(random);
    std::vector<msmcl::TranslucentLayer> translucent(2);
    for (msmcl::TranslucentLayer& layer : translucent)
        for (std::size_t i = 0; i < values * array_layers; ++i) {
            const float pick = unit(random);
            layer.depth.push_back(unit(random));
            layer.opacity.push_back(pick < 0.25f ? 0.0f : pick < 0.5f ? 1.0f : unit(random));
        }
    std::vector<msmcl_translucent_layer> c_translucent;
    for (const msmcl::TranslucentLayer& layer : translucent)
        c_translucent.push_back({layer.depth.data(), layer.opacity.data()});
    // Device layout: translucent layer k of array layer a at a * 2 + k.
    std::vector<float> device_depth, device_opacity;
    for (int a = 0; a < array_layers; ++a)
        for (const msmcl::TranslucentLayer& layer : translucent) {
            device_depth.insert(device_depth.end(), layer.depth.begin() + a * values,
                                layer.depth.begin() + (a + 1) * values);
            device_opacity.insert(device_opacity.end(), layer.opacity.begin() + a * values,
                                  layer.opacity.begin() + (a + 1) * values);
        }
    cl_mem depth = buffer(stack.depth.size() * 4, stack.depth.data());
    cl_mem layer_depth = buffer(device_depth.size() * 4, device_depth.data());
    cl_mem layer_opacity = buffer(device_opacity.size() * 4, device_opacity.data());
    const msmcl_device_depth c_depth{depth, width, height, samples, MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
    const msmcl::DeviceDepth cpp_depth{depth, width, height, samples, array_layers};
    const msmcl_device_layers c_layers{layer_depth, layer_opacity, 2};
    const msmcl::DeviceLayers cpp_layers{layer_depth, layer_opacity, 2};

    for (msmcl::Format format : {msmcl::Format::moments128, msmcl::Format::nlq32}) {
        msmcl_filter_options options;
        msmcl_filter_options_init(&options);
        options.format = c_format(format);
        msmcl::FilterOptions cpp;
        cpp.format = format;
        const std::size_t bytes = texels * array_layers * msmcl::texel_bytes(format);
        std::vector<std::uint32_t> texture(bytes / 4);
        ASSERT_EQ(msmcl_filter_array_layered(c_context_, stack.depth.data(), width, height, samples, array_layers,
                                             c_translucent.data(), c_translucent.size(), &options, texture.data(),
                                             bytes),
                  MSMCL_SUCCESS)
            << msmcl_last_error_message();
        const msmcl::Texture expected = msmcl::filter(*context_, stack, translucent, cpp);
        EXPECT_EQ(texture, expected.words) << msmcl::format_name(format);
        cl_mem c_texture = buffer(bytes), cpp_texture = buffer(bytes);
        ASSERT_EQ(msmcl_filter_array_layered_device(c_context_, &c_depth, array_layers, &c_layers, c_texture, &options,
                                                    nullptr),
                  MSMCL_SUCCESS)
            << msmcl_last_error_message();
        msmcl::filter(*context_, cpp_depth, cpp_layers, cpp_texture, cpp);
        EXPECT_EQ(read_buffer<std::uint32_t>(queue(), c_texture, bytes / 4),
                  read_buffer<std::uint32_t>(queue(), cpp_texture, bytes / 4))
            << msmcl::format_name(format);
    }

    std::vector<std::uint32_t> table(4 * texels * array_layers);
    ASSERT_EQ(msmcl_build_sat_array_layered(c_context_, stack.depth.data(), width, height, samples, array_layers,
                                            c_translucent.data(), c_translucent.size(), nullptr, table.data(),
                                            table.size()),
              MSMCL_SUCCESS)
        << msmcl_last_error_message();
    EXPECT_EQ(table, msmcl::build_sat(*context_, stack, translucent, msmcl::SatOptions{}).words);
    cl_mem c_table = buffer(table.size() * 4), cpp_table = buffer(table.size() * 4);
    ASSERT_EQ(msmcl_build_sat_array_layered_device(c_context_, &c_depth, array_layers, &c_layers, c_table, nullptr,
                                                   nullptr),
              MSMCL_SUCCESS)
        << msmcl_last_error_message();
    msmcl::build_sat(*context_, cpp_depth, cpp_layers, cpp_table, msmcl::SatOptions{});
    EXPECT_EQ(read_buffer<std::uint32_t>(queue(), c_table, table.size()),
              read_buffer<std::uint32_t>(queue(), cpp_table, table.size()));

    // Errors: a bad value names its array layer as the C++ API does; too few table words;
    // an image with layers.
    std::vector<msmcl::TranslucentLayer> bad = translucent;
    bad[1].opacity[2 * values + 7] = 2.0f;
    const std::vector<msmcl_translucent_layer> c_bad{{bad[0].depth.data(), bad[0].opacity.data()},
                                                     {bad[1].depth.data(), bad[1].opacity.data()}};
    EXPECT_EQ(c_outcome(msmcl_build_sat_array_layered(c_context_, stack.depth.data(), width, height, samples,
                                                      array_layers, c_bad.data(), c_bad.size(), nullptr, table.data(),
                                                      table.size())),
              cpp_outcome([&] { msmcl::build_sat(*context_, stack, bad, msmcl::SatOptions{}); }));
    EXPECT_EQ(msmcl_build_sat_array_layered(c_context_, stack.depth.data(), width, height, samples, array_layers,
                                            c_translucent.data(), c_translucent.size(), nullptr, table.data(),
                                            table.size() - 1),
              MSMCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(msmcl_last_error_message()).find("table_words"), std::string::npos);
    cl_mem table_image = image(msmcl_sat_image_format());
    EXPECT_EQ(msmcl_build_sat_array_layered_device(c_context_, &c_depth, array_layers, &c_layers, table_image, nullptr,
                                                   nullptr),
              MSMCL_ERROR_INPUT);
}

// A light from above, a camera looking down the street; the shadow map and camera depth
// random values in range (the binding is the subject, not the picture).
struct ScatterCase {
    msmcl_scatter_scene c;
    msmcl::ScatterScene cpp;
    std::vector<float> camera_depth;
};

ScatterCase scatter_case(std::uint32_t seed) {
    ScatterCase s;
    msmcl_scatter_scene_init(&s.c);
    const double direction[3] = {0.2, -1.0, 0.1}, center[3] = {0.0, 0.0, -5.0};
    const double forward[3] = {0.3, -0.2, -1.0}, position[3] = {0.5, 1.0, 4.0};
    std::copy(direction, direction + 3, s.c.light.direction);
    std::copy(center, center + 3, s.c.light.center);
    s.c.light.width = s.c.light.height = 20.0;
    s.c.light.near_plane = -10.0;
    s.c.light.far_plane = 10.0;
    std::copy(forward, forward + 3, s.c.camera.forward);
    std::copy(position, position + 3, s.c.camera.position);
    s.c.camera.vertical_fov_degrees = 50.0;
    s.c.camera.near_plane = 0.1;
    s.c.camera.far_plane = 30.0;
    s.c.camera.width = 40;
    s.c.camera.height = 30;
    s.c.medium.extinction = 0.15;
    s.c.medium.phase_g = 0.3;
    s.c.medium.irradiance = 2.0;
    s.c.rectified_width = 64;
    s.c.rectified_height = 48;
    s.cpp.light.direction = {0.2, -1.0, 0.1};
    s.cpp.light.center = {0.0, 0.0, -5.0};
    s.cpp.light.width = s.cpp.light.height = 20.0;
    s.cpp.light.near = -10.0;
    s.cpp.light.far = 10.0;
    s.cpp.camera.forward = {0.3, -0.2, -1.0};
    s.cpp.camera.position = {0.5, 1.0, 4.0};
    s.cpp.camera.vertical_fov_degrees = 50.0;
    s.cpp.camera.near = 0.1;
    s.cpp.camera.far = 30.0;
    s.cpp.camera.width = 40;
    s.cpp.camera.height = 30;
    s.cpp.medium.extinction = 0.15;
    s.cpp.medium.phase_g = 0.3;
    s.cpp.medium.irradiance = 2.0;
    s.cpp.rectified_width = 64;
    s.cpp.rectified_height = 48;
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> far_half(0.5f, 1.0f);
    s.camera_depth.resize(40 * 30);
    for (float& d : s.camera_depth) d = far_half(random);
    return s;
}

TEST_F(Capi, ScatterEqualsCpp) {
    const ScatterCase s = scatter_case(seed_ + 5);
    const std::size_t pixels = s.camera_depth.size();
    for (int variant = 0; variant < 3; ++variant) {
        msmcl_scatter_options options;
        msmcl_scatter_options_init(&options);
        msmcl::ScatterOptions cpp;
        if (variant == 1) {
            options.moments = cpp.moments = 4;
            options.filter_sigma = cpp.filter_sigma = 2.0f;
            options.beta = cpp.beta = 0.25f;
            options.kernel = MSMCL_SCATTER_KERNEL_ROWS_GPU;
            cpp.kernel = msmcl::ScatterKernel::rows_gpu;
        } else if (variant == 2) {
            options.filtered = 0;
            cpp.filtered = false;
            options.kernel = MSMCL_SCATTER_KERNEL_ROWS_CPU;
            cpp.kernel = msmcl::ScatterKernel::rows_cpu;
            options.filter_kernel = MSMCL_FILTER_KERNEL_THREE_PASS;
            cpp.filter_kernel = msmcl::FilterKernel::three_pass;
        }
        const std::vector<float> expected = msmcl::scatter(*context_, s.cpp, depth_, s.camera_depth, cpp);
        // Some light and some shadow: the comparison is not of constants.
        const auto [darkest, brightest] = std::minmax_element(expected.begin(), expected.end());
        EXPECT_LT(*darkest, *brightest) << variant;
        EXPECT_GT(*brightest, 0.0f) << variant;
        std::vector<float> radiance(pixels, -1.0f);
        ASSERT_EQ(msmcl_scatter(c_context_, &s.c, depth_.depth.data(), width, height, samples, s.camera_depth.data(),
                                &options, radiance.data()),
                  MSMCL_SUCCESS)
            << msmcl_last_error_message();
        EXPECT_EQ(radiance, expected) << variant;
        // The two halves.
        const msmcl::ScatterMap map = msmcl::scatter_prefilter(*context_, s.cpp, depth_, cpp);
        std::vector<std::uint32_t> words(msmcl_scatter_map_bytes(&s.c) / 4);
        ASSERT_EQ(msmcl_scatter_prefilter(c_context_, &s.c, depth_.depth.data(), width, height, samples, &options,
                                          words.data(), words.size() * 4),
                  MSMCL_SUCCESS)
            << msmcl_last_error_message();
        EXPECT_EQ(words, map.words) << variant;
        std::fill(radiance.begin(), radiance.end(), -1.0f);
        ASSERT_EQ(msmcl_scatter_evaluate(c_context_, &s.c, words.data(), words.size() * 4, s.camera_depth.data(),
                                         &options, radiance.data()),
                  MSMCL_SUCCESS)
            << msmcl_last_error_message();
        EXPECT_EQ(radiance, msmcl::scatter_evaluate(*context_, s.cpp, map, s.camera_depth, cpp)) << variant;
    }
}

// The device path an engine runs (its moments128 map or depth buffer, its camera depth):
// the host call's bytes.
TEST_F(Capi, ScatterDeviceEqualsHost) {
    const ScatterCase s = scatter_case(seed_ + 6);
    const std::size_t pixels = s.camera_depth.size();
    cl_mem depth = buffer(values * 4, depth_.depth.data());
    cl_mem camera_depth = buffer(pixels * 4, s.camera_depth.data());
    cl_mem map = buffer(msmcl_scatter_map_bytes(&s.c));
    cl_mem radiance = buffer(pixels * 4);
    const msmcl_device_depth c_depth{depth, width, height, samples, MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
    for (int moments : {4, 6}) {
        msmcl::ScatterOptions cpp;
        cpp.moments = moments;
        // Filtered: the moments128 map of the C filter call, then prefilter and evaluate.
        msmcl_filter_options filter;
        msmcl_filter_options_init(&filter);
        filter.format = MSMCL_FORMAT_MOMENTS128;
        filter.sigma = cpp.filter_sigma;
        cl_mem moment_map = buffer(texels * 16);
        ASSERT_EQ(msmcl_filter_device(c_context_, &c_depth, moment_map, &filter, nullptr), MSMCL_SUCCESS);
        ASSERT_EQ(msmcl_scatter_prefilter_device(c_context_, &s.c, moment_map, width, height, moments, map, nullptr),
                  MSMCL_SUCCESS)
            << msmcl_last_error_message();
        cl_event done = nullptr;
        const msmcl_enqueue finished{nullptr, nullptr, 0, &done, 0};
        ASSERT_EQ(msmcl_scatter_evaluate_device(c_context_, &s.c, map, moments, camera_depth, radiance, cpp.beta,
                                                &finished),
                  MSMCL_SUCCESS)
            << msmcl_last_error_message();
        ASSERT_NE(done, nullptr);
        ASSERT_EQ(clWaitForEvents(1, &done), CL_SUCCESS);
        clReleaseEvent(done);
        EXPECT_EQ(read_buffer<float>(queue(), radiance, pixels),
                  msmcl::scatter(*context_, s.cpp, depth_, s.camera_depth, cpp))
            << moments;
        // Unfiltered, from the depth buffer.
        cpp.filtered = false;
        ASSERT_EQ(msmcl_scatter_prefilter_depth_device(c_context_, &s.c, &c_depth, moments, map, nullptr),
                  MSMCL_SUCCESS)
            << msmcl_last_error_message();
        ASSERT_EQ(msmcl_scatter_evaluate_device(c_context_, &s.c, map, moments, camera_depth, radiance, cpp.beta,
                                                nullptr),
                  MSMCL_SUCCESS)
            << msmcl_last_error_message();
        EXPECT_EQ(read_buffer<float>(queue(), radiance, pixels),
                  msmcl::scatter(*context_, s.cpp, depth_, s.camera_depth, cpp))
            << moments;
    }
}

// The C++ API's errors arrive as its status and message; C misuse names the argument.
TEST_F(Capi, ScatterErrors) {
    ScatterCase s = scatter_case(seed_ + 7);
    std::vector<float> radiance(s.camera_depth.size());
    std::vector<std::uint32_t> words(msmcl_scatter_map_bytes(&s.c) / 4);
    const float* depth = depth_.depth.data();
    // A medium without extinction, a camera inside geometry, 5 moments, beta 2.
    s.c.medium.extinction = 0.0;
    s.cpp.medium.extinction = 0.0;
    EXPECT_EQ(c_outcome(msmcl_scatter(c_context_, &s.c, depth, width, height, samples, s.camera_depth.data(), nullptr,
                                      radiance.data())),
              cpp_outcome([&] { msmcl::scatter(*context_, s.cpp, depth_, s.camera_depth, msmcl::ScatterOptions{}); }));
    s.c.medium.extinction = s.cpp.medium.extinction = 0.15;
    std::vector<float> inside(s.camera_depth.size(), 0.0f);
    EXPECT_EQ(c_outcome(msmcl_scatter(c_context_, &s.c, depth, width, height, samples, inside.data(), nullptr,
                                      radiance.data())),
              cpp_outcome([&] { msmcl::scatter(*context_, s.cpp, depth_, inside, msmcl::ScatterOptions{}); }));
    msmcl_scatter_options options;
    msmcl_scatter_options_init(&options);
    options.moments = 5;
    msmcl::ScatterOptions cpp;
    cpp.moments = 5;
    EXPECT_EQ(c_outcome(msmcl_scatter_prefilter(c_context_, &s.c, depth, width, height, samples, &options,
                                                words.data(), words.size() * 4)),
              cpp_outcome([&] { msmcl::scatter_prefilter(*context_, s.cpp, depth_, cpp); }));
    cl_mem map = buffer(words.size() * 4), camera_depth = buffer(radiance.size() * 4, s.camera_depth.data());
    cl_mem out = buffer(radiance.size() * 4);
    EXPECT_EQ(c_outcome(msmcl_scatter_evaluate_device(c_context_, &s.c, map, 6, camera_depth, out, 2.0f, nullptr)),
              cpp_outcome([&] { msmcl::scatter_evaluate(*context_, s.cpp, map, 6, camera_depth, out, 2.0f); }));
    cl_mem moments128 = buffer(texels * 16);
    EXPECT_EQ(c_outcome(msmcl_scatter_prefilter_device(c_context_, &s.c, moments128, width, height, 3, map, nullptr)),
              cpp_outcome([&] {
                  msmcl::scatter_prefilter(*context_, s.cpp,
                                           msmcl::DeviceTexture{moments128, msmcl::Format::moments128, width, height},
                                           map, 3);
              }));

    const auto expect_invalid = [](msmcl_status status, const std::string& needle) {
        EXPECT_EQ(status, MSMCL_ERROR_INVALID_ARGUMENT) << msmcl_status_name(status) << ": " << msmcl_last_error_message();
        EXPECT_NE(std::string(msmcl_last_error_message()).find(needle), std::string::npos)
            << "'" << msmcl_last_error_message() << "' lacks '" << needle << "'";
    };
    expect_invalid(msmcl_scatter(c_context_, nullptr, depth, width, height, samples, s.camera_depth.data(), nullptr,
                                 radiance.data()),
                   "scene");
    expect_invalid(msmcl_scatter(c_context_, &s.c, depth, width, height, samples, nullptr, nullptr, radiance.data()),
                   "camera_depth");
    expect_invalid(msmcl_scatter_prefilter(c_context_, &s.c, depth, width, height, samples, nullptr, words.data(),
                                           words.size() * 4 - 1),
                   "map_bytes");
    msmcl_scatter_scene odd = s.c;
    odd.camera.depth = static_cast<msmcl_camera_depth>(3);
    expect_invalid(msmcl_scatter_evaluate(c_context_, &odd, words.data(), words.size() * 4, s.camera_depth.data(),
                                          nullptr, radiance.data()),
                   "camera depth 3");
    options.moments = 6;
    options.kernel = static_cast<msmcl_scatter_kernel>(-1);
    expect_invalid(msmcl_scatter(c_context_, &s.c, depth, width, height, samples, s.camera_depth.data(), &options,
                                 radiance.data()),
                   "scatter kernel -1");
    options.kernel = MSMCL_SCATTER_KERNEL_AUTOMATIC;
    options.filter_kernel = static_cast<msmcl_filter_kernel>(8);
    expect_invalid(msmcl_scatter(c_context_, &s.c, depth, width, height, samples, s.camera_depth.data(), &options,
                                 radiance.data()),
                   "filter kernel 8");
    expect_invalid(msmcl_scatter_evaluate_device(c_context_, &s.c, map, 6, nullptr, out, -1.0f, nullptr),
                   "camera_depth");
    const msmcl_device_depth no_memory{nullptr, width, height, samples, MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
    expect_invalid(msmcl_scatter_prefilter_depth_device(c_context_, &s.c, &no_memory, 6, map, nullptr),
                   "shadow_map->memory");
    // A depth image: the C++ API resamples buffers only.
    cl_image_format depth_format{CL_R, CL_FLOAT};
    const msmcl_device_depth in_image{image(depth_format), width, height, 1, MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
    EXPECT_EQ(msmcl_scatter_prefilter_depth_device(c_context_, &s.c, &in_image, 6, map, nullptr), MSMCL_ERROR_INPUT);
}

TEST_F(Capi, CppErrorsBecomeStatusAndMessage) {
    msmcl::DepthImage bad = depth_;
    bad.depth[(3 * width + 5) * samples + 1] = NAN;
    msmcl_filter_options options;
    msmcl_filter_options_init(&options);
    std::vector<std::uint32_t> words(2 * texels);
    EXPECT_EQ(c_outcome(msmcl_filter(c_context_, bad.depth.data(), width, height, samples, &options, words.data(),
                                     words.size() * 4)),
              cpp_outcome([&] { msmcl::filter(*context_, bad, msmcl::FilterOptions{}); }));
    EXPECT_NE(std::string(msmcl_last_error_message()).find("(5, 3)"), std::string::npos) << msmcl_last_error_message();

    std::vector<msmcl::TranslucentLayer> layers = layers_;
    layers[1].opacity[11] = -0.25f;
    std::vector<msmcl_translucent_layer> c_layers;
    for (const msmcl::TranslucentLayer& layer : layers) c_layers.push_back({layer.depth.data(), layer.opacity.data()});
    EXPECT_EQ(c_outcome(msmcl_filter_layered(c_context_, depth_.depth.data(), width, height, samples, c_layers.data(),
                                             c_layers.size(), &options, words.data(), words.size() * 4)),
              cpp_outcome([&] { msmcl::filter(*context_, depth_, layers, msmcl::FilterOptions{}); }));
    std::vector<std::uint32_t> table(4 * texels);
    EXPECT_EQ(c_outcome(msmcl_build_sat_layered(c_context_, depth_.depth.data(), width, height, samples,
                                                c_layers.data(), c_layers.size(), nullptr, table.data(), table.size())),
              cpp_outcome([&] { msmcl::build_sat(*context_, depth_, layers, msmcl::SatOptions{}); }));

    const msmcl::Texture map = msmcl::filter(*context_, depth_, msmcl::FilterOptions{});
    msmcl::Receivers receivers{{1.5f, 2.5f}, {1.5f, 2.5f}, {0.5f, NAN}};
    float intensity[2];
    EXPECT_EQ(c_outcome(msmcl_shade(c_context_, MSMCL_FORMAT_NLQ64, width, height, map.words.data(),
                                    map.words.size() * 4, receivers.u.data(), receivers.v.data(), receivers.z.data(),
                                    2, nullptr, intensity)),
              cpp_outcome([&] { msmcl::shade(*context_, map, receivers, msmcl::ShadeOptions{}); }));

    // A wrong image format for the texture, refused before anything is enqueued.
    cl_mem depth = buffer(values * 4, depth_.depth.data());
    cl_image_format nlq32{};
    ASSERT_EQ(msmcl_texture_image_format(MSMCL_FORMAT_NLQ32, &nlq32), MSMCL_SUCCESS);
    cl_mem texture = image(nlq32);
    const msmcl_device_depth c_depth{depth, width, height, samples, MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
    options.format = MSMCL_FORMAT_MSM64;
    msmcl::FilterOptions msm64;
    msm64.format = msmcl::Format::msm64;
    EXPECT_EQ(c_outcome(msmcl_filter_device(c_context_, &c_depth, texture, &options, nullptr)),
              cpp_outcome([&] {
                  msmcl::filter_to_image(*context_, msmcl::DeviceDepth{depth, width, height, samples}, texture, msm64);
              }));
    EXPECT_EQ(msmcl_last_error_message()[0] != '\0', true);

    // A success clears the message.
    msmcl_format format;
    EXPECT_EQ(msmcl_parse_format("nlq64", &format), MSMCL_SUCCESS);
    EXPECT_STREQ(msmcl_last_error_message(), "");
    EXPECT_EQ(msmcl_last_opencl_error(), CL_SUCCESS);
}

// Misuse the C layer finds itself (NULL pointers, values outside the enums, outputs too
// small, a lone pixel array): MSMCL_ERROR_INVALID_ARGUMENT naming the argument.
TEST_F(Capi, CArgumentErrorsNameTheArgument) {
    const auto expect_invalid = [](msmcl_status status, const std::string& needle) {
        EXPECT_EQ(status, MSMCL_ERROR_INVALID_ARGUMENT) << msmcl_status_name(status) << ": " << msmcl_last_error_message();
        EXPECT_NE(std::string(msmcl_last_error_message()).find(needle), std::string::npos)
            << "'" << msmcl_last_error_message() << "' lacks '" << needle << "'";
    };
    std::vector<std::uint32_t> words(4 * texels);
    const std::size_t bytes = words.size() * 4;
    const float* depth = depth_.depth.data();
    msmcl_filter_options options;
    msmcl_filter_options_init(&options);
    msmcl_format format;

    expect_invalid(msmcl_context_create(nullptr, nullptr), "NULL");
    expect_invalid(msmcl_filter(nullptr, nullptr, 1, 1, 1, nullptr, nullptr, 0), "NULL");
    expect_invalid(msmcl_parse_format("msm65", &format), "msm65");
    EXPECT_EQ(msmcl_context_cl_context(nullptr), nullptr);
    EXPECT_STREQ(msmcl_context_device_name(nullptr), "");
    msmcl_context_destroy(nullptr);

    expect_invalid(msmcl_filter(c_context_, depth, width, height, samples, &options, words.data(), 8), "texture_bytes");
    msmcl_filter_options bad = options;
    bad.format = static_cast<msmcl_format>(19);
    expect_invalid(msmcl_filter(c_context_, depth, width, height, samples, &bad, words.data(), bytes), "format 19");
    bad = options;
    bad.kernel = static_cast<msmcl_filter_kernel>(-7);
    expect_invalid(msmcl_filter(c_context_, depth, width, height, samples, &bad, words.data(), bytes), "filter kernel -7");
    bad = options;
    bad.depth_range = static_cast<msmcl_depth_range>(1000);
    expect_invalid(msmcl_filter(c_context_, depth, width, height, samples, &bad, words.data(), bytes), "depth range 1000");
    EXPECT_EQ(msmcl_filter(c_context_, depth, width, height, 3, &options, words.data(), bytes), MSMCL_ERROR_INPUT);

    // Layers: NULL with a count, a NULL array, device buffers missing.
    expect_invalid(msmcl_filter_layered(c_context_, depth, width, height, samples, nullptr, 2, &options, words.data(),
                                        bytes),
                   "layers is NULL");
    std::vector<msmcl_translucent_layer> layers = c_layers();
    layers[1].opacity = nullptr;
    expect_invalid(msmcl_filter_layered(c_context_, depth, width, height, samples, layers.data(), layers.size(),
                                        &options, words.data(), bytes),
                   "layers[1].opacity");
    cl_mem depth_buffer = buffer(values * 4, depth);
    cl_mem texture = buffer(bytes);
    const msmcl_device_depth c_depth{depth_buffer, width, height, samples, MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
    const msmcl_device_layers missing{depth_buffer, nullptr, 1};
    expect_invalid(msmcl_filter_layered_device(c_context_, &c_depth, &missing, texture, &options, nullptr), "opacity");
    const msmcl_enqueue no_events{nullptr, nullptr, 2, nullptr, 0};
    expect_invalid(msmcl_filter_device(c_context_, &c_depth, texture, &options, &no_events), "wait_for");

    // Shade: an unknown lookup, a lone pixel array; SAT: an unknown kernel.
    const float u[1] = {1.5f}, v[1] = {1.5f}, z[1] = {0.5f};
    const std::uint32_t pixel_x[1] = {0};
    float intensity[1];
    msmcl_shade_options shade;
    msmcl_shade_options_init(&shade);
    shade.lookup = static_cast<msmcl_lookup>(3);
    expect_invalid(msmcl_shade(c_context_, MSMCL_FORMAT_NLQ64, width, height, words.data(), bytes, u, v, z, 1, &shade,
                               intensity),
                   "unknown lookup 3");
    shade.lookup = MSMCL_LOOKUP_DITHER;
    expect_invalid(msmcl_shade_with_pixels(c_context_, MSMCL_FORMAT_NLQ64, width, height, words.data(), bytes, u, v, z,
                                           pixel_x, nullptr, 1, &shade, intensity),
                   "pixel_y");
    msmcl_sat_options sat;
    msmcl_sat_options_init(&sat);
    sat.kernel = static_cast<msmcl_sat_kernel>(9);
    expect_invalid(msmcl_build_sat(c_context_, depth, width, height, samples, &sat, words.data(), words.size()),
                   "SAT kernel 9");
}

} // namespace
