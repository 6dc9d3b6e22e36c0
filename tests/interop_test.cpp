// Device data in and out (include/msmcl/interop.hpp): depth buffers and images in, caller
// images out, for every format and sample layout, bit-identical to the host path (which
// filter_test and sat_test check against double references). Every object the library sees
// is created with CL_MEM_HOST_NO_ACCESS, so a host read, write or map of it by the library
// would fail: the calls pass without a host round trip. Seed: MSMCL_TEST_SEED (default 6).
#include "runtime/opencl.hpp"

#include <msmcl/filter.hpp>
#include <msmcl/interop.hpp>
#include <msmcl/sat.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#ifndef CL_DEPTH
#define CL_DEPTH 0x10BD
#endif

namespace {

unsigned test_seed() {
    const char* text = std::getenv("MSMCL_TEST_SEED");
    const unsigned seed = text ? static_cast<unsigned>(std::strtoul(text, nullptr, 10)) : 6u;
    std::printf("interop_test: seed %u (MSMCL_TEST_SEED overrides)\n", seed);
    return seed;
}

// A depth map that is neither tile-aligned nor flat: random depths over steps.
msmcl::DepthImage random_depth(int width, int height, int samples, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> jitter(0.0f, 1.0f);
    msmcl::DepthImage depth;
    depth.width = width;
    depth.height = height;
    depth.samples = samples;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int s = 0; s < samples; ++s)
                depth.depth.push_back(((x / 7 + y / 5) % 3 == 0) ? 0.2f + 0.001f * jitter(random)
                                                                 : 0.3f + 0.6f * jitter(random));
    return depth;
}

class InteropTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        seed_ = test_seed();
        context_ = new msmcl::Context();
    }
    static void TearDownTestSuite() {
        delete context_;
        context_ = nullptr;
    }

    cl_context cl() const { return context_->cl_context_handle(); }
    cl_command_queue queue() const { return context_->cl_queue_handle(); }

    bool supports(cl_mem_object_type type, cl_image_format format) const {
        cl_uint count = 0;
        clGetSupportedImageFormats(cl(), CL_MEM_READ_WRITE, type, 0, nullptr, &count);
        std::vector<cl_image_format> formats(count);
        clGetSupportedImageFormats(cl(), CL_MEM_READ_WRITE, type, count, formats.data(), nullptr);
        for (const cl_image_format& f : formats)
            if (f.image_channel_order == format.image_channel_order &&
                f.image_channel_data_type == format.image_channel_data_type)
                return true;
        return false;
    }

    // A device-only buffer filled through a host-readable staging buffer and a device copy.
    cl::Buffer device_buffer(const void* data, std::size_t bytes) const {
        cl_int status = CL_SUCCESS;
        cl::Buffer buffer(cl::Context(cl(), true), CL_MEM_READ_WRITE | CL_MEM_HOST_NO_ACCESS, bytes, nullptr, &status);
        EXPECT_EQ(status, CL_SUCCESS);
        if (data) {
            cl::Buffer staging(cl::Context(cl(), true), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes,
                               const_cast<void*>(data), &status);
            EXPECT_EQ(clEnqueueCopyBuffer(queue(), staging(), buffer(), 0, 0, bytes, 0, nullptr, nullptr), CL_SUCCESS);
            EXPECT_EQ(clFinish(queue()), CL_SUCCESS);
        }
        return buffer;
    }

    // A device-only image (2D, or 2D array with `layers`), optionally filled from `data`
    // (rows packed, layers after each other).
    cl_mem device_image(cl_image_format format, std::size_t width, std::size_t height, std::size_t layers,
                        const void* data, std::size_t texel_bytes) const {
        cl_image_desc description{};
        description.image_type = layers > 0 ? CL_MEM_OBJECT_IMAGE2D_ARRAY : CL_MEM_OBJECT_IMAGE2D;
        description.image_width = width;
        description.image_height = height;
        description.image_array_size = layers;
        cl_int status = CL_SUCCESS;
        cl_mem image = clCreateImage(cl(), CL_MEM_READ_WRITE | CL_MEM_HOST_NO_ACCESS, &format, &description, nullptr,
                                     &status);
        EXPECT_EQ(status, CL_SUCCESS);
        if (data) {
            const std::size_t bytes = width * height * std::max<std::size_t>(layers, 1) * texel_bytes;
            cl::Buffer staging(cl::Context(cl(), true), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes,
                               const_cast<void*>(data), &status);
            const std::size_t origin[3] = {0, 0, 0};
            const std::size_t region[3] = {width, height, std::max<std::size_t>(layers, 1)};
            EXPECT_EQ(clEnqueueCopyBufferToImage(queue(), staging(), image, 0, origin, region, 0, nullptr, nullptr),
                      CL_SUCCESS);
            EXPECT_EQ(clFinish(queue()), CL_SUCCESS);
        }
        return image;
    }

    // The top-left width x height texels of a device-only image, through a device copy.
    std::vector<std::uint32_t> read_image(cl_mem image, int width, int height, std::size_t texel_bytes,
                                          cl_event after = nullptr) const {
        std::vector<std::uint32_t> words(static_cast<std::size_t>(width) * height * texel_bytes / 4);
        cl_int status = CL_SUCCESS;
        cl::Buffer readable(cl::Context(cl(), true), CL_MEM_READ_WRITE, words.size() * 4, nullptr, &status);
        const std::size_t origin[3] = {0, 0, 0};
        const std::size_t region[3] = {static_cast<std::size_t>(width), static_cast<std::size_t>(height), 1};
        EXPECT_EQ(clEnqueueCopyImageToBuffer(queue(), image, readable(), origin, region, 0, after ? 1 : 0,
                                             after ? &after : nullptr, nullptr),
                  CL_SUCCESS);
        EXPECT_EQ(clEnqueueReadBuffer(queue(), readable(), CL_TRUE, 0, words.size() * 4, words.data(), 0, nullptr,
                                      nullptr),
                  CL_SUCCESS);
        return words;
    }

    std::vector<std::uint32_t> read_buffer(const cl::Buffer& buffer, std::size_t words) const {
        std::vector<std::uint32_t> result(words);
        cl_int status = CL_SUCCESS;
        cl::Buffer readable(cl::Context(cl(), true), CL_MEM_READ_WRITE, words * 4, nullptr, &status);
        EXPECT_EQ(clEnqueueCopyBuffer(queue(), buffer(), readable(), 0, 0, words * 4, 0, nullptr, nullptr), CL_SUCCESS);
        EXPECT_EQ(clEnqueueReadBuffer(queue(), readable(), CL_TRUE, 0, words * 4, result.data(), 0, nullptr, nullptr),
                  CL_SUCCESS);
        return result;
    }

    // The depth map's samples as S planes (the layered layout).
    static std::vector<float> planes_of(const msmcl::DepthImage& depth) {
        const std::size_t texels = static_cast<std::size_t>(depth.width) * depth.height;
        std::vector<float> planes(texels * depth.samples);
        for (std::size_t t = 0; t < texels; ++t)
            for (int s = 0; s < depth.samples; ++s) planes[s * texels + t] = depth.depth[t * depth.samples + s];
        return planes;
    }

    static unsigned seed_;
    static msmcl::Context* context_;
};

unsigned InteropTest::seed_ = 0;
msmcl::Context* InteropTest::context_ = nullptr;

constexpr cl_image_format kDepthR{CL_R, CL_FLOAT};

TEST_F(InteropTest, ImageFormatsAreTheNaturalOnes) {
    using msmcl::Format;
    EXPECT_EQ(msmcl::texture_image_format(Format::moments128).image_channel_order, static_cast<cl_uint>(CL_RGBA));
    EXPECT_EQ(msmcl::texture_image_format(Format::moments128).image_channel_data_type, static_cast<cl_uint>(CL_FLOAT));
    EXPECT_EQ(msmcl::texture_image_format(Format::msm64).image_channel_data_type, static_cast<cl_uint>(CL_UNORM_INT16));
    EXPECT_EQ(msmcl::texture_image_format(Format::nlq64).image_channel_data_type, static_cast<cl_uint>(CL_UNORM_INT16));
    EXPECT_EQ(msmcl::texture_image_format(Format::nlq32).image_channel_order, static_cast<cl_uint>(CL_R));
    EXPECT_EQ(msmcl::texture_image_format(Format::nlq32).image_channel_data_type,
              static_cast<cl_uint>(CL_UNSIGNED_INT32));
    EXPECT_TRUE(msmcl::image_format_matches(Format::nlq64, cl_image_format{CL_RGBA, CL_UNSIGNED_INT16}));
    EXPECT_FALSE(msmcl::image_format_matches(Format::moments128, cl_image_format{CL_RGBA, CL_UNSIGNED_INT16}));
    EXPECT_FALSE(msmcl::image_format_matches(Format::nlq32, cl_image_format{CL_RGBA, CL_UNSIGNED_INT32}));
    EXPECT_EQ(msmcl::sat_image_format().image_channel_data_type, static_cast<cl_uint>(CL_UNSIGNED_INT32));
}

// Every format, from a depth buffer into a caller's image of the natural format.
TEST_F(InteropTest, BufferToImageMatchesHostForEveryFormat) {
    const msmcl::DepthImage depth = random_depth(45, 31, 4, seed_);
    const cl::Buffer depth_buffer = device_buffer(depth.depth.data(), depth.depth.size() * sizeof(float));
    for (msmcl::Format format : {msmcl::Format::moments128, msmcl::Format::msm64, msmcl::Format::nlq64,
                                 msmcl::Format::nlq32}) {
        SCOPED_TRACE(msmcl::format_name(format));
        msmcl::FilterOptions options;
        options.format = format;
        const msmcl::Texture host = msmcl::filter(*context_, depth, options);
        const cl_mem image =
            device_image(msmcl::texture_image_format(format), depth.width, depth.height, 0, nullptr, 0);
        cl_event done = nullptr;
        msmcl::Enqueue enqueue;
        enqueue.done = &done;
        msmcl::filter_to_image(*context_, msmcl::DeviceDepth{depth_buffer(), depth.width, depth.height, depth.samples},
                               image, options, enqueue);
        ASSERT_NE(done, nullptr);
        cl_command_type type = 0;
        clGetEventInfo(done, CL_EVENT_COMMAND_TYPE, sizeof type, &type, nullptr);
        EXPECT_EQ(type, static_cast<cl_command_type>(CL_COMMAND_COPY_BUFFER_TO_IMAGE));
        EXPECT_EQ(read_image(image, depth.width, depth.height, msmcl::texel_bytes(format), done), host.words);
        clReleaseEvent(done);
        clReleaseMemObject(image);
    }
}

// Depth images in both sample layouts; outputs: an image larger than the map (raw-code
// CL_UNSIGNED_INT16 alternative) and a buffer.
TEST_F(InteropTest, DepthImagesInBothLayouts) {
    const msmcl::DepthImage depth = random_depth(40, 26, 4, seed_ + 1);
    msmcl::FilterOptions options;
    options.format = msmcl::Format::nlq64;
    const msmcl::Texture host = msmcl::filter(*context_, depth, options);

    const cl_mem side_by_side = device_image(kDepthR, depth.width * depth.samples, depth.height, 0,
                                             depth.depth.data(), sizeof(float));
    const std::vector<float> planes = planes_of(depth);
    const cl_mem layers = device_image(kDepthR, depth.width, depth.height, depth.samples, planes.data(), sizeof(float));
    const cl_mem bigger = device_image(cl_image_format{CL_RGBA, CL_UNSIGNED_INT16}, depth.width + 5, depth.height + 3,
                                       0, nullptr, 0);
    const cl::Buffer texture = device_buffer(nullptr, host.words.size() * 4);

    msmcl::DeviceDepthImage input{side_by_side, depth.width, depth.height, depth.samples,
                                  msmcl::SampleLayout::side_by_side};
    msmcl::filter_to_image(*context_, input, bigger, options);
    EXPECT_EQ(read_image(bigger, depth.width, depth.height, 8), host.words) << "side_by_side -> image";

    input.image = layers;
    input.layout = msmcl::SampleLayout::layers;
    msmcl::filter(*context_, input, texture(), options);
    EXPECT_EQ(read_buffer(texture, host.words.size()), host.words) << "layers -> buffer";

    msmcl::filter_to_image(*context_, input, bigger, options);
    EXPECT_EQ(read_image(bigger, depth.width, depth.height, 8), host.words) << "layers -> image";

    clReleaseMemObject(side_by_side);
    clReleaseMemObject(layers);
    clReleaseMemObject(bigger);
}

TEST_F(InteropTest, DepthChannelOrderWhereSupported) {
    const cl_image_format depth_format{CL_DEPTH, CL_FLOAT};
    if (!supports(CL_MEM_OBJECT_IMAGE2D, depth_format))
        GTEST_SKIP() << "the device has no CL_DEPTH/CL_FLOAT images";
    const msmcl::DepthImage depth = random_depth(33, 17, 1, seed_ + 2);
    msmcl::FilterOptions options;
    options.format = msmcl::Format::msm64;
    const msmcl::Texture host = msmcl::filter(*context_, depth, options);
    const cl_mem input = device_image(depth_format, depth.width, depth.height, 0, depth.depth.data(), sizeof(float));
    const cl_mem output = device_image(msmcl::texture_image_format(options.format), depth.width, depth.height, 0,
                                       nullptr, 0);
    msmcl::filter_to_image(*context_, msmcl::DeviceDepthImage{input, depth.width, depth.height, 1}, output, options);
    EXPECT_EQ(read_image(output, depth.width, depth.height, 8), host.words);
    clReleaseMemObject(input);
    clReleaseMemObject(output);
}

TEST_F(InteropTest, SatIntoImageFromBufferAndLayeredImage) {
    const msmcl::DepthImage depth = random_depth(50, 21, 2, seed_ + 3);
    msmcl::SatOptions options;
    options.max_kernel_texels = 19 * 19;
    const msmcl::SatTable host = msmcl::build_sat(*context_, depth, options);
    const cl::Buffer depth_buffer = device_buffer(depth.depth.data(), depth.depth.size() * sizeof(float));
    const cl_mem table = device_image(msmcl::sat_image_format(), depth.width, depth.height, 0, nullptr, 0);

    msmcl::build_sat_to_image(*context_, msmcl::DeviceDepth{depth_buffer(), depth.width, depth.height, depth.samples},
                              table, options);
    EXPECT_EQ(read_image(table, depth.width, depth.height, 16), host.words) << "buffer -> image";

    const std::vector<float> planes = planes_of(depth);
    const cl_mem layers = device_image(kDepthR, depth.width, depth.height, depth.samples, planes.data(), sizeof(float));
    const msmcl::DeviceDepthImage input{layers, depth.width, depth.height, depth.samples, msmcl::SampleLayout::layers};
    msmcl::build_sat_to_image(*context_, input, table, options);
    EXPECT_EQ(read_image(table, depth.width, depth.height, 16), host.words) << "layers -> image";
    const cl::Buffer table_buffer = device_buffer(nullptr, host.words.size() * 4);
    msmcl::build_sat(*context_, input, table_buffer(), options);
    EXPECT_EQ(read_buffer(table_buffer, host.words.size()), host.words) << "layers -> buffer";
    clReleaseMemObject(layers);
    clReleaseMemObject(table);
}

// Soft shadows from a table image: the buffer call's intensities, after the caller's event;
// a wrong image refused before anything is enqueued.
TEST_F(InteropTest, SoftShadowsFromATableImage) {
    const msmcl::DepthImage depth = random_depth(45, 26, 2, seed_ + 6);
    msmcl::SatOptions options;
    options.max_kernel_texels = 11 * 11;
    const msmcl::SatTable host = msmcl::build_sat(*context_, depth, options);
    const cl_mem table = device_image(msmcl::sat_image_format(), 48, 30, 0, nullptr, 0);
    const cl::Buffer depth_buffer = device_buffer(depth.depth.data(), depth.depth.size() * sizeof(float));
    msmcl::build_sat_to_image(*context_, msmcl::DeviceDepth{depth_buffer(), depth.width, depth.height, depth.samples},
                              table, options);
    std::mt19937 random(seed_ + 7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    msmcl::Receivers receivers;
    for (int i = 0; i < 300; ++i) {
        receivers.u.push_back(depth.width * unit(random));
        receivers.v.push_back(depth.height * unit(random));
        receivers.z.push_back(unit(random));
    }
    std::vector<float> uvz = receivers.u;
    uvz.insert(uvz.end(), receivers.v.begin(), receivers.v.end());
    uvz.insert(uvz.end(), receivers.z.begin(), receivers.z.end());
    const cl::Buffer receiver_buffer = device_buffer(uvz.data(), uvz.size() * sizeof(float));
    const cl::Buffer intensity = device_buffer(nullptr, receivers.size() * sizeof(float));
    msmcl::SoftShadowOptions soft;
    soft.light_size = 12.0f;
    cl_int status = CL_SUCCESS;
    cl_event gate = clCreateUserEvent(cl(), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_event done = nullptr;
    msmcl::Enqueue enqueue;
    enqueue.wait_for = {gate};
    enqueue.done = &done;
    const msmcl::DeviceSatImage in_image{table, depth.width, depth.height, options.max_kernel_texels};
    msmcl::soft_shade(*context_, in_image, receiver_buffer(), receivers.size(), intensity(), soft, enqueue);
    ASSERT_NE(done, nullptr);
    cl_int execution = CL_COMPLETE;
    clGetEventInfo(done, CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof execution, &execution, nullptr);
    EXPECT_NE(execution, CL_COMPLETE);
    ASSERT_EQ(clSetUserEventStatus(gate, CL_COMPLETE), CL_SUCCESS);
    ASSERT_EQ(clWaitForEvents(1, &done), CL_SUCCESS);
    const std::vector<float> expected = msmcl::soft_shade(*context_, host, receivers, soft);
    std::vector<float> got(receivers.size());
    const std::vector<std::uint32_t> words = read_buffer(intensity, got.size());
    std::memcpy(got.data(), words.data(), got.size() * sizeof(float));
    EXPECT_EQ(got, expected);
    clReleaseEvent(done);
    clReleaseEvent(gate);

    const auto message_of = [](auto call) -> std::string {
        try {
            call();
        } catch (const msmcl::input_error& e) {
            return e.what();
        }
        return "no input_error";
    };
    const cl_mem wrong_format = device_image(cl_image_format{CL_RGBA, CL_FLOAT}, 48, 30, 0, nullptr, 0);
    const cl_mem array = device_image(msmcl::sat_image_format(), 48, 30, 2, nullptr, 0);
    const auto shade_from = [&](cl_mem image, int width) {
        return message_of([&] {
            msmcl::soft_shade(*context_, msmcl::DeviceSatImage{image, width, depth.height, options.max_kernel_texels},
                              receiver_buffer(), receivers.size(), intensity(), soft);
        });
    };
    EXPECT_NE(shade_from(wrong_format, depth.width).find("CL_RGBA/CL_FLOAT, expected CL_RGBA/CL_UNSIGNED_INT32"),
              std::string::npos);
    EXPECT_NE(shade_from(array, depth.width).find("array"), std::string::npos);
    EXPECT_NE(shade_from(table, 49).find("48x30, smaller than the 49x26"), std::string::npos);
    EXPECT_NE(shade_from(depth_buffer(), depth.width).find("not a 2D image"), std::string::npos);
    for (cl_mem m : {table, wrong_format, array}) clReleaseMemObject(m);
}

// The call joins the caller's queue: it waits for the caller's event and reports its own.
TEST_F(InteropTest, ChainsIntoTheCallersQueueByEvents) {
    const msmcl::DepthImage depth = random_depth(24, 24, 1, seed_ + 4);
    msmcl::FilterOptions options;
    options.format = msmcl::Format::nlq32;
    const msmcl::Texture host = msmcl::filter(*context_, depth, options);

    cl_int status = CL_SUCCESS;
    cl_command_queue engine_queue = clCreateCommandQueue(cl(), context_->cl_device_handle(), 0, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    const cl_mem input = device_image(kDepthR, depth.width, depth.height, 0, depth.depth.data(), sizeof(float));
    const cl_mem output = device_image(msmcl::texture_image_format(options.format), depth.width, depth.height, 0,
                                       nullptr, 0);
    cl_event gate = clCreateUserEvent(cl(), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_event done = nullptr;
    msmcl::Enqueue enqueue;
    enqueue.queue = engine_queue;
    enqueue.wait_for = {gate};
    enqueue.done = &done;
    msmcl::filter_to_image(*context_, msmcl::DeviceDepthImage{input, depth.width, depth.height, 1}, output, options,
                           enqueue);
    ASSERT_NE(done, nullptr);
    cl_command_queue done_queue = nullptr;
    clGetEventInfo(done, CL_EVENT_COMMAND_QUEUE, sizeof done_queue, &done_queue, nullptr);
    EXPECT_EQ(done_queue, engine_queue);
    // Nothing can have run while the caller's event is open.
    cl_int execution = CL_COMPLETE;
    clGetEventInfo(done, CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof execution, &execution, nullptr);
    EXPECT_NE(execution, CL_COMPLETE);
    ASSERT_EQ(clSetUserEventStatus(gate, CL_COMPLETE), CL_SUCCESS);
    ASSERT_EQ(clWaitForEvents(1, &done), CL_SUCCESS);
    EXPECT_EQ(read_image(output, depth.width, depth.height, 4), host.words);
    clReleaseEvent(done);
    clReleaseEvent(gate);
    clReleaseMemObject(input);
    clReleaseMemObject(output);
    clReleaseCommandQueue(engine_queue);
}

TEST_F(InteropTest, RefusesWrongObjectsBeforeEnqueueing) {
    const msmcl::DepthImage depth = random_depth(16, 16, 2, seed_ + 5);
    const cl::Buffer depth_buffer = device_buffer(depth.depth.data(), depth.depth.size() * sizeof(float));
    const msmcl::DeviceDepth in_buffer{depth_buffer(), 16, 16, 2};
    msmcl::FilterOptions options;
    options.format = msmcl::Format::msm64;
    const cl_mem wrong_format = device_image(cl_image_format{CL_RGBA, CL_FLOAT}, 16, 16, 0, nullptr, 0);
    const cl_mem too_small = device_image(cl_image_format{CL_RGBA, CL_UNORM_INT16}, 15, 16, 0, nullptr, 0);
    const cl_mem array = device_image(cl_image_format{CL_RGBA, CL_UNORM_INT16}, 16, 16, 2, nullptr, 0);
    const cl_mem depth_side_by_side = device_image(kDepthR, 32, 16, 0, depth.depth.data(), sizeof(float));
    const cl_mem rgba_depth = device_image(cl_image_format{CL_RGBA, CL_FLOAT}, 32, 16, 0, nullptr, 0);

    const auto message_of = [](auto call) -> std::string {
        try {
            call();
        } catch (const msmcl::input_error& e) {
            return e.what();
        }
        return "no input_error";
    };
    EXPECT_NE(message_of([&] { msmcl::filter_to_image(*context_, in_buffer, wrong_format, options); })
                  .find("CL_RGBA/CL_FLOAT, expected CL_RGBA/CL_UNORM_INT16"),
              std::string::npos);
    EXPECT_NE(message_of([&] { msmcl::filter_to_image(*context_, in_buffer, too_small, options); }).find("15x16"),
              std::string::npos);
    EXPECT_NE(message_of([&] { msmcl::filter_to_image(*context_, in_buffer, array, options); }).find("array"),
              std::string::npos);
    EXPECT_NE(message_of([&] { msmcl::filter_to_image(*context_, in_buffer, depth_buffer(), options); })
                  .find("not a 2D image"),
              std::string::npos);
    msmcl::DeviceDepthImage image_input{depth_side_by_side, 16, 16, 2, msmcl::SampleLayout::layers};
    EXPECT_NE(message_of([&] { msmcl::filter(*context_, image_input, depth_buffer(), options); }).find("array"),
              std::string::npos);
    image_input.layout = msmcl::SampleLayout::side_by_side;
    image_input.samples = 4; // needs 64 columns
    EXPECT_NE(message_of([&] { msmcl::filter(*context_, image_input, depth_buffer(), options); }).find("64x16"),
              std::string::npos);
    image_input.samples = 3;
    EXPECT_NE(message_of([&] { msmcl::filter(*context_, image_input, depth_buffer(), options); }).find("sample count"),
              std::string::npos);
    image_input = {rgba_depth, 16, 16, 2, msmcl::SampleLayout::side_by_side};
    EXPECT_NE(message_of([&] { msmcl::filter(*context_, image_input, depth_buffer(), options); }).find("CL_R/CL_FLOAT"),
              std::string::npos);
    // An image of another cl_context.
    msmcl::Context other;
    EXPECT_NE(message_of([&] { msmcl::filter_to_image(other, in_buffer, too_small, options); }).find("cl_context"),
              std::string::npos);
    for (cl_mem m : {wrong_format, too_small, array, depth_side_by_side, rgba_depth}) clReleaseMemObject(m);
}

} // namespace
