// Texture arrays: filter and build_sat of a layered depth map (N maps of one size, layer
// after layer) give, layer for layer, the bits of N single-map calls, on the host and the
// device paths, with every filter kernel, format and table distribution, translucent
// layers included; bad layer counts and buffers are input_error. The single-map calls
// themselves are checked against the double-precision reference in filter_test, sat_test
// and translucent_test, so bit equality here carries that check over to the arrays.
#include "filter_fixtures.hpp"
#include "io/gpu_image.hpp"
#include "io/ktx2.hpp"
#include "process.hpp"
#include "seeded_test.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/interop.hpp>
#include <msmcl/msmcl.h>
#include <msmcl/sat.hpp>
#include <msmcl/shade.hpp>

#include <gtest/gtest.h>

#include <climits>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace {

using msmcl::Context;
using msmcl::DepthImage;
using msmcl::DepthRange;
using msmcl::DeviceDepth;
using msmcl::DeviceLayers;
using msmcl::FilterKernel;
using msmcl::FilterOptions;
using msmcl::Format;
using msmcl::SatKernel;
using msmcl::SatOptions;
using msmcl::SatTable;
using msmcl::Texture;
using msmcl::TranslucentLayer;

// Odd sizes: no multiple of any tile, block or band.
constexpr int kWidth = 45;
constexpr int kHeight = 37;

// `count` different depth maps of one size, and the texture array holding them.
struct Stack {
    std::vector<DepthImage> maps;
    DepthImage layered;
};

Stack make_stack(int width, int height, int samples, int count, DepthRange range, std::uint32_t seed) {
    Stack stack;
    stack.layered = DepthImage{width, height, samples, {}, count};
    for (int i = 0; i < count; ++i) {
        stack.maps.push_back(filter_fixtures::make_depth(width, height, samples, range, seed + 7919u * i));
        const std::vector<float>& depth = stack.maps.back().depth;
        stack.layered.depth.insert(stack.layered.depth.end(), depth.begin(), depth.end());
    }
    return stack;
}

// `count` translucent layers over each map of `stack`: random depths in the range and
// opacities in [0, 1] (a quarter of them 0: no surface); per map, and the same stacked
// into layered TranslucentLayers (each holding every array layer's slice).
struct TranslucentStack {
    std::vector<std::vector<TranslucentLayer>> per_map;
    std::vector<TranslucentLayer> layered;
};

TranslucentStack make_translucent(const Stack& stack, int count, DepthRange range, std::uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> depth(range == DepthRange::zero_one ? 0.0f : -1.0f, 1.0f);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    TranslucentStack out;
    out.layered.resize(static_cast<std::size_t>(count));
    for (const DepthImage& map : stack.maps) {
        std::vector<TranslucentLayer> layers(static_cast<std::size_t>(count));
        for (int k = 0; k < count; ++k) {
            TranslucentLayer& layer = layers[static_cast<std::size_t>(k)];
            for (std::size_t i = 0; i < map.depth.size(); ++i) {
                layer.depth.push_back(depth(random));
                const float a = unit(random);
                layer.opacity.push_back(a < 0.25f ? 0.0f : a);
            }
            TranslucentLayer& all = out.layered[static_cast<std::size_t>(k)];
            all.depth.insert(all.depth.end(), layer.depth.begin(), layer.depth.end());
            all.opacity.insert(all.opacity.end(), layer.opacity.begin(), layer.opacity.end());
        }
        out.per_map.push_back(std::move(layers));
    }
    return out;
}

// Layer i of the texture array equals `single` word for word (first difference reported).
void expect_layer_equal(const std::vector<std::uint32_t>& array_words, std::size_t layer_words, int layer,
                        const std::vector<std::uint32_t>& single, const std::string& what) {
    ASSERT_EQ(single.size(), layer_words) << what;
    for (std::size_t i = 0; i < layer_words; ++i) {
        const std::uint32_t got = array_words[static_cast<std::size_t>(layer) * layer_words + i];
        ASSERT_EQ(got, single[i]) << what << ": array layer " << layer << " word " << i << " differs";
    }
}

// One Context for the suite (PoCL builds programs per Context).
class ArrayTest : public msmcl::testing::DeviceSuite<ArrayTest, 20160216u> {};

// ---- filter, host path: every kernel and format, per-layer calls bit for bit.

class ArrayFilter : public ArrayTest, public ::testing::WithParamInterface<std::tuple<FilterKernel, Format>> {};

TEST_P(ArrayFilter, HostArrayMatchesPerLayerCalls) {
    const auto [kernel, format] = GetParam();
    try {
        msmcl::filter_kernel_for(context(), kernel);
    } catch (const msmcl::device_error& e) {
        GTEST_SKIP() << "the device cannot run " << msmcl::filter_kernel_name(kernel) << ": " << e.what();
    }
    // The other depth convention for the unshifted formats, S = 4 (S = 1 for three_pass, whose
    // resolve is per texel and needs no second sample count to be covered).
    const DepthRange range = format == Format::msm64 ? DepthRange::minus_one_one : DepthRange::zero_one;
    const int samples = kernel == FilterKernel::three_pass ? 1 : 4;
    const Stack stack = make_stack(kWidth, kHeight, samples, 3, range, seed_);
    const FilterOptions options{format, 2.4f, range, kernel};
    const Texture array = msmcl::filter(context(), stack.layered, options);
    ASSERT_EQ(array.layers, 3);
    ASSERT_EQ(array.width, kWidth);
    ASSERT_EQ(array.height, kHeight);
    const std::size_t layer_words = static_cast<std::size_t>(kWidth) * kHeight * msmcl::texel_words(format);
    ASSERT_EQ(array.words.size(), 3 * layer_words);
    for (int i = 0; i < 3; ++i) {
        const Texture single = msmcl::filter(context(), stack.maps[static_cast<std::size_t>(i)], options);
        expect_layer_equal(array.words, layer_words, i, single.words, "filter");
        EXPECT_EQ(array.layer(i).words, single.words);
    }
}

INSTANTIATE_TEST_SUITE_P(
    EveryKernelAndFormat, ArrayFilter,
    ::testing::Combine(::testing::Values(FilterKernel::fused_paper, FilterKernel::fused_cpu, FilterKernel::three_pass),
                       ::testing::Values(Format::moments128, Format::msm64, Format::nlq64, Format::nlq32)),
    [](const ::testing::TestParamInfo<ArrayFilter::ParamType>& info) {
        return std::string(msmcl::filter_kernel_name(std::get<0>(info.param))) + "_" +
               msmcl::format_name(std::get<1>(info.param));
    });

// ---- filter: translucent layers over an array, and the device path.

TEST_F(ArrayTest, TranslucentArrayMatchesPerLayerCalls) {
    const Stack stack = make_stack(kWidth, kHeight, 2, 3, DepthRange::zero_one, seed_);
    const TranslucentStack translucent = make_translucent(stack, 2, DepthRange::zero_one, seed_ + 1u);
    for (FilterKernel kernel : {FilterKernel::automatic, FilterKernel::three_pass}) {
        const FilterOptions options{Format::nlq64, 2.4f, DepthRange::zero_one, kernel};
        const Texture array = msmcl::filter(context(), stack.layered, translucent.layered, options);
        const std::size_t layer_words = static_cast<std::size_t>(kWidth) * kHeight * 2;
        for (int i = 0; i < 3; ++i) {
            const Texture single = msmcl::filter(context(), stack.maps[static_cast<std::size_t>(i)],
                                                 translucent.per_map[static_cast<std::size_t>(i)], options);
            expect_layer_equal(array.words, layer_words, i, single.words,
                               std::string("translucent filter ") + msmcl::filter_kernel_name(kernel));
        }
    }
}

// Device buffers in, one call for the whole array, the texture array out: the host path's bits.
TEST_F(ArrayTest, DeviceArrayMatchesHostArray) {
    const Stack stack = make_stack(kWidth, kHeight, 4, 4, DepthRange::zero_one, seed_);
    const TranslucentStack translucent = make_translucent(stack, 1, DepthRange::zero_one, seed_ + 2u);
    const cl_context cl = context().cl_context_handle();
    cl_int status = CL_SUCCESS;
    const std::size_t depth_bytes = stack.layered.depth.size() * sizeof(float);
    cl_mem depth = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, depth_bytes,
                                  const_cast<float*>(stack.layered.depth.data()), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    // The translucent layer in the device order: array layer after array layer (one each here).
    cl_mem layer_depth = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, depth_bytes,
                                        const_cast<float*>(translucent.layered[0].depth.data()), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_mem layer_opacity = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, depth_bytes,
                                          const_cast<float*>(translucent.layered[0].opacity.data()), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    for (Format format : {Format::msm64, Format::nlq32}) {
        const FilterOptions options{format};
        const std::size_t bytes = stack.layered.depth.size() / 4 * msmcl::texel_bytes(format);
        cl_mem texture = clCreateBuffer(cl, CL_MEM_WRITE_ONLY, bytes, nullptr, &status);
        ASSERT_EQ(status, CL_SUCCESS);
        const DeviceDepth device{depth, kWidth, kHeight, 4, 4};
        for (bool with_layers : {false, true}) {
            const DeviceLayers layers = with_layers ? DeviceLayers{layer_depth, layer_opacity, 1} : DeviceLayers{};
            msmcl::filter(context(), device, layers, texture, options, msmcl::Enqueue{nullptr, {}, nullptr, true});
            std::vector<std::uint32_t> words(bytes / 4);
            ASSERT_EQ(clEnqueueReadBuffer(context().cl_queue_handle(), texture, CL_TRUE, 0, bytes, words.data(), 0, nullptr,
                                          nullptr),
                      CL_SUCCESS);
            const Texture host = with_layers
                                     ? msmcl::filter(context(), stack.layered, translucent.layered, options)
                                     : msmcl::filter(context(), stack.layered, options);
            EXPECT_EQ(words, host.words) << msmcl::format_name(format) << (with_layers ? " with a translucent layer" : "");
        }
        clReleaseMemObject(texture);
    }
    clReleaseMemObject(layer_opacity);
    clReleaseMemObject(layer_depth);
    clReleaseMemObject(depth);
}

// One layer is a plain map: the same bits and a texture of one layer.
TEST_F(ArrayTest, OneLayerIsThePlainCall) {
    const Stack stack = make_stack(kWidth, kHeight, 4, 1, DepthRange::zero_one, seed_);
    const Texture array = msmcl::filter(context(), stack.layered, FilterOptions{Format::nlq32});
    const Texture single = msmcl::filter(context(), stack.maps[0], FilterOptions{Format::nlq32});
    EXPECT_EQ(array.layers, 1);
    EXPECT_EQ(array.words, single.words);
    const SatTable table = msmcl::build_sat(context(), stack.layered, SatOptions{});
    EXPECT_EQ(table.layers, 1);
    EXPECT_EQ(table.words, msmcl::build_sat(context(), stack.maps[0], SatOptions{}).words);
}

// ---- build_sat: every distribution, per-layer calls bit for bit, host and device.

class ArraySat : public ArrayTest, public ::testing::WithParamInterface<std::tuple<SatKernel, int>> {};

TEST_P(ArraySat, HostAndDeviceArraysMatchPerLayerCalls) {
    const auto [kernel, samples] = GetParam();
    const Stack stack = make_stack(kWidth, kHeight, samples, 3, DepthRange::zero_one, seed_);
    const SatOptions options{27 * 27, DepthRange::zero_one, kernel};
    const SatTable array = msmcl::build_sat(context(), stack.layered, options);
    ASSERT_EQ(array.layers, 3);
    const std::size_t layer_words = 4 * static_cast<std::size_t>(kWidth) * kHeight;
    ASSERT_EQ(array.words.size(), 3 * layer_words);
    for (int i = 0; i < 3; ++i) {
        const SatTable single = msmcl::build_sat(context(), stack.maps[static_cast<std::size_t>(i)], options);
        expect_layer_equal(array.words, layer_words, i, single.words, "build_sat");
        EXPECT_EQ(array.layer(i).words, single.words);
    }

    // Translucent layers over the array.
    const TranslucentStack translucent = make_translucent(stack, 2, DepthRange::zero_one, seed_ + 3u);
    const SatTable translucent_array = msmcl::build_sat(context(), stack.layered, translucent.layered, options);
    for (int i = 0; i < 3; ++i) {
        const SatTable single = msmcl::build_sat(context(), stack.maps[static_cast<std::size_t>(i)],
                                                 translucent.per_map[static_cast<std::size_t>(i)], options);
        expect_layer_equal(translucent_array.words, layer_words, i, single.words, "translucent build_sat");
    }

    // The device path: the host path's bits.
    const cl_context cl = context().cl_context_handle();
    cl_int status = CL_SUCCESS;
    cl_mem depth = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, stack.layered.depth.size() * sizeof(float),
                                  const_cast<float*>(stack.layered.depth.data()), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_mem table = clCreateBuffer(cl, CL_MEM_READ_WRITE, 3 * layer_words * 4, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    msmcl::build_sat(context(), DeviceDepth{depth, kWidth, kHeight, samples, 3}, table, options,
                     msmcl::Enqueue{nullptr, {}, nullptr, true});
    std::vector<std::uint32_t> words(3 * layer_words);
    ASSERT_EQ(clEnqueueReadBuffer(context().cl_queue_handle(), table, CL_TRUE, 0, words.size() * 4, words.data(), 0, nullptr,
                                  nullptr),
              CL_SUCCESS);
    EXPECT_EQ(words, array.words);
    clReleaseMemObject(table);
    clReleaseMemObject(depth);
}

INSTANTIATE_TEST_SUITE_P(
    EveryDistribution, ArraySat,
    ::testing::Combine(::testing::Values(SatKernel::tiled_gpu, SatKernel::tiled_cpu, SatKernel::row_per_thread),
                       ::testing::Values(1, 4)),
    [](const ::testing::TestParamInfo<ArraySat::ParamType>& info) {
        return std::string(msmcl::sat_kernel_name(std::get<0>(info.param))) + "_S" +
               std::to_string(std::get<1>(info.param));
    });

// ---- bad input: one input_error naming the problem, before any device work.

TEST_F(ArrayTest, BadLayerCountsAndSizesAreInputErrors) {
    const Stack stack = make_stack(9, 7, 1, 2, DepthRange::zero_one, seed_);
    for (int layers : {0, -1, msmcl::max_array_layers + 1, INT_MAX}) {
        DepthImage bad = stack.layered;
        bad.layers = layers;
        EXPECT_THROW(msmcl::filter(context(), bad, FilterOptions{}), msmcl::input_error) << layers;
        EXPECT_THROW(msmcl::build_sat(context(), bad, SatOptions{}), msmcl::input_error) << layers;
    }
    // Values for two layers declared as three, and as one.
    for (int layers : {1, 3}) {
        DepthImage bad = stack.layered;
        bad.layers = layers;
        EXPECT_THROW(msmcl::filter(context(), bad, FilterOptions{}), msmcl::input_error) << layers;
        EXPECT_THROW(msmcl::build_sat(context(), bad, SatOptions{}), msmcl::input_error) << layers;
    }
    // Absurd sizes.
    DepthImage huge{70000, 2, 1, std::vector<float>(140000 * 2, 0.5f), 2};
    EXPECT_THROW(msmcl::filter(context(), huge, FilterOptions{}), msmcl::input_error);
    EXPECT_THROW(msmcl::build_sat(context(), huge, SatOptions{}), msmcl::input_error);

    // A translucent layer holding one array layer's values instead of both.
    std::vector<TranslucentLayer> short_layer{{stack.maps[0].depth, stack.maps[0].depth}};
    EXPECT_THROW(msmcl::filter(context(), stack.layered, short_layer, FilterOptions{}), msmcl::input_error);

    // Device buffers too small for the layers they declare.
    const cl_context cl = context().cl_context_handle();
    cl_int status = CL_SUCCESS;
    const std::size_t one_map = 9 * 7 * sizeof(float);
    cl_mem depth = clCreateBuffer(cl, CL_MEM_READ_WRITE, 2 * one_map, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_mem output = clCreateBuffer(cl, CL_MEM_READ_WRITE, 2 * 9 * 7 * 16, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    EXPECT_THROW(msmcl::filter(context(), DeviceDepth{depth, 9, 7, 1, 3}, output, FilterOptions{}), msmcl::input_error);
    EXPECT_THROW(msmcl::build_sat(context(), DeviceDepth{depth, 9, 7, 1, 3}, output, SatOptions{}), msmcl::input_error);
    EXPECT_THROW(msmcl::filter(context(), DeviceDepth{depth, 9, 7, 1, 0}, output, FilterOptions{}), msmcl::input_error);
    EXPECT_THROW(msmcl::build_sat(context(), DeviceDepth{depth, 9, 7, 1, -2}, output, SatOptions{}),
                 msmcl::input_error);
    // Two layers fit the depth buffer, but not a texture of 2 x 16 bytes a texel in half of it.
    cl_mem small = clCreateBuffer(cl, CL_MEM_READ_WRITE, 9 * 7 * 16, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    EXPECT_THROW(msmcl::filter(context(), DeviceDepth{depth, 9, 7, 1, 2}, small, FilterOptions{Format::moments128}),
                 msmcl::input_error);
    EXPECT_THROW(msmcl::build_sat(context(), DeviceDepth{depth, 9, 7, 1, 2}, small, SatOptions{}), msmcl::input_error);
    clReleaseMemObject(small);
    clReleaseMemObject(output);
    clReleaseMemObject(depth);
}

// Calls that take one map refuse an array; layer(i) takes one out.
TEST_F(ArrayTest, SingleMapCallsRefuseArrays) {
    const Stack stack = make_stack(9, 7, 1, 2, DepthRange::zero_one, seed_);
    const Texture array = msmcl::filter(context(), stack.layered, FilterOptions{Format::msm64});
    const msmcl::Receivers receivers{{1.0f}, {1.0f}, {0.5f}};
    EXPECT_THROW(msmcl::shade(context(), array, receivers, msmcl::ShadeOptions{}), msmcl::input_error);
    EXPECT_NO_THROW(msmcl::shade(context(), array.layer(1), receivers, msmcl::ShadeOptions{}));
    EXPECT_THROW(array.layer(2), msmcl::input_error);
    EXPECT_THROW(array.layer(-1), msmcl::input_error);
    const SatTable table = msmcl::build_sat(context(), stack.layered, SatOptions{});
    EXPECT_THROW(msmcl::sat_rectangle_sum(table, 0, 0, 1, 1), msmcl::input_error);
    EXPECT_NO_THROW(msmcl::sat_rectangle_sum(table.layer(1), 0, 0, 1, 1));
    EXPECT_THROW(table.layer(2), msmcl::input_error);
}

// ---- Image arrays in and out (the interop path): the buffer path's bits.

// A 2D image array of `layers` layers holding `values` (rows packed, layer after layer), or
// null when the device cannot make one of `format`.
cl_mem image_array(Context& context, cl_image_format format, std::size_t width, std::size_t height, std::size_t layers,
                   const void* values) {
    cl_image_desc description{};
    description.image_type = CL_MEM_OBJECT_IMAGE2D_ARRAY;
    description.image_width = width;
    description.image_height = height;
    description.image_array_size = layers;
    cl_int status = CL_SUCCESS;
    cl_mem image = clCreateImage(context.cl_context_handle(),
                                 CL_MEM_READ_WRITE | (values ? CL_MEM_COPY_HOST_PTR : cl_mem_flags{0}), &format,
                                 &description, const_cast<void*>(values), &status);
    return status == CL_SUCCESS ? image : nullptr;
}

std::vector<std::uint32_t> read_image_array(Context& context, cl_mem image, std::size_t width, std::size_t height,
                                            std::size_t layers, std::size_t texel_bytes) {
    std::vector<std::uint32_t> words(width * height * layers * texel_bytes / 4);
    const std::size_t origin[3] = {0, 0, 0};
    const std::size_t region[3] = {width, height, layers};
    EXPECT_EQ(clEnqueueReadImage(context.cl_queue_handle(), image, CL_TRUE, origin, region, 0, 0, words.data(), 0,
                                 nullptr, nullptr),
              CL_SUCCESS);
    return words;
}

std::vector<std::uint32_t> read_buffer(Context& context, cl_mem buffer, std::size_t words) {
    std::vector<std::uint32_t> result(words);
    EXPECT_EQ(clEnqueueReadBuffer(context.cl_queue_handle(), buffer, CL_TRUE, 0, words * 4, result.data(), 0, nullptr,
                                  nullptr),
              CL_SUCCESS);
    return result;
}

TEST_F(ArrayTest, ImageArraysMatchTheHostArray) {
    constexpr int kMaps = 3, kSamples = 2;
    const Stack stack = make_stack(kWidth, kHeight, kSamples, kMaps, DepthRange::zero_one, seed_);
    const std::size_t texels = static_cast<std::size_t>(kWidth) * kHeight;
    // Side by side: map a in array layer a, its rows of width * S floats (the buffer layout).
    cl_mem side_by_side = image_array(context(), cl_image_format{CL_R, CL_FLOAT}, kWidth * kSamples, kHeight, kMaps,
                                      stack.layered.depth.data());
    if (!side_by_side) GTEST_SKIP() << "the device makes no CL_R/CL_FLOAT 2D image arrays";
    // Samples as layers: sample s of map a in array layer a * S + s.
    std::vector<float> planes;
    for (const DepthImage& map : stack.maps)
        for (int s = 0; s < kSamples; ++s)
            for (std::size_t t = 0; t < texels; ++t) planes.push_back(map.depth[t * kSamples + s]);
    cl_mem sample_layers =
        image_array(context(), cl_image_format{CL_R, CL_FLOAT}, kWidth, kHeight, kMaps * kSamples, planes.data());
    ASSERT_NE(sample_layers, nullptr);

    const FilterOptions options{Format::nlq32};
    const Texture expected = msmcl::filter(context(), stack.layered, options);
    const SatTable expected_table = msmcl::build_sat(context(), stack.layered, SatOptions{});
    cl_int status = CL_SUCCESS;
    cl_mem table = clCreateBuffer(context().cl_context_handle(), CL_MEM_READ_WRITE, expected_table.words.size() * 4,
                                  nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_mem texture_image = image_array(context(), msmcl::texture_image_format(Format::nlq32), kWidth, kHeight, kMaps,
                                       nullptr);
    cl_mem table_image = image_array(context(), msmcl::sat_image_format(), kWidth, kHeight, kMaps, nullptr);
    ASSERT_NE(texture_image, nullptr);
    ASSERT_NE(table_image, nullptr);
    const msmcl::Enqueue blocking{nullptr, {}, nullptr, true};
    for (const auto& [image, layout] : {std::pair{side_by_side, msmcl::SampleLayout::side_by_side},
                                        std::pair{sample_layers, msmcl::SampleLayout::layers}}) {
        const msmcl::DeviceDepthImage depth{image, kWidth, kHeight, kSamples, layout, kMaps};
        const std::string what = layout == msmcl::SampleLayout::layers ? "samples as layers" : "side by side";
        msmcl::filter(context(), depth, table, options, blocking);
        EXPECT_EQ(read_buffer(context(), table, expected.words.size()), expected.words) << what;
        msmcl::filter_to_image(context(), depth, texture_image, options, blocking);
        EXPECT_EQ(read_image_array(context(), texture_image, kWidth, kHeight, kMaps, 4), expected.words) << what;
        msmcl::build_sat(context(), depth, table, SatOptions{}, blocking);
        EXPECT_EQ(read_buffer(context(), table, expected_table.words.size()), expected_table.words) << what;
        msmcl::build_sat_to_image(context(), depth, table_image, SatOptions{}, blocking);
        EXPECT_EQ(read_image_array(context(), table_image, kWidth, kHeight, kMaps, 16), expected_table.words) << what;
    }
    // Too few layers in the depth image or the output image.
    EXPECT_THROW(msmcl::filter(context(), msmcl::DeviceDepthImage{side_by_side, kWidth, kHeight, kSamples,
                                                                  msmcl::SampleLayout::side_by_side, kMaps + 1},
                               table, options),
                 msmcl::input_error);
    EXPECT_THROW(msmcl::filter_to_image(context(), msmcl::DeviceDepthImage{sample_layers, kWidth, kHeight, kSamples,
                                                                           msmcl::SampleLayout::layers, kMaps + 1},
                                        texture_image, options),
                 msmcl::input_error);
    for (cl_mem object : {side_by_side, sample_layers, table, texture_image, table_image}) clReleaseMemObject(object);
}

// ---- KTX2: a texture array is one file of layerCount layers; read back, the same words.

TEST_F(ArrayTest, Ktx2WritesAndReadsLayers) {
    const Stack stack = make_stack(kWidth, kHeight, 1, 3, DepthRange::zero_one, seed_);
    for (Format format : {Format::msm64, Format::nlq32}) {
        const Texture array = msmcl::filter(context(), stack.layered, FilterOptions{format});
        const std::vector<std::uint8_t> bytes = msmcl::io::encode_ktx2(msmcl::io::gpu_image_of(array));
        // layerCount at byte 32 of the header.
        EXPECT_EQ(bytes[32] | bytes[33] << 8 | bytes[34] << 16 | bytes[35] << 24, 3);
        const msmcl::io::GpuImage image = msmcl::io::decode_ktx2(bytes, "array.ktx2");
        EXPECT_TRUE(image.array);
        EXPECT_EQ(image.layers, 3);
        const Texture back = msmcl::io::texture_of(image, format, "array.ktx2");
        EXPECT_EQ(back.layers, 3);
        EXPECT_EQ(back.words, array.words);
    }
    // A table array, and one layer stays a plain 2D texture (layerCount 0).
    const SatTable tables = msmcl::build_sat(context(), stack.layered, SatOptions{});
    const msmcl::io::GpuImage table_image = msmcl::io::decode_ktx2(
        msmcl::io::encode_ktx2(msmcl::io::gpu_image_of(tables)), "tables.ktx2");
    EXPECT_EQ(table_image.layers, 3);
    const std::vector<std::uint8_t> single =
        msmcl::io::encode_ktx2(msmcl::io::gpu_image_of(msmcl::filter(context(), stack.maps[0], FilterOptions{})));
    EXPECT_EQ(single[32] | single[33] << 8 | single[34] << 16 | single[35] << 24, 0);
}

#ifdef MSMCL_CLI_PATH
// `msmcl info` names the layer count of an array file; commands that read one map refuse it.
TEST_F(ArrayTest, CliInfoShowsLayersAndShadeRefusesArrays) {
    const Stack stack = make_stack(9, 7, 1, 4, DepthRange::zero_one, seed_);
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("msmcl_array_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string map = (dir / "array.ktx2").string();
    msmcl::io::write_ktx2(map, msmcl::io::gpu_image_of(msmcl::filter(context(), stack.layered, FilterOptions{})));
    const std::string out = (dir / "info.txt").string();
    ASSERT_EQ(msmcl::testing::run_process({MSMCL_CLI_PATH, "info", map}, out, "/dev/null"), 0);
    std::ifstream text(out);
    std::stringstream content;
    content << text.rdbuf();
    EXPECT_NE(content.str().find("layers 4"), std::string::npos) << content.str();
    const std::string err = (dir / "err.txt").string();
    EXPECT_EQ(msmcl::testing::run_process({MSMCL_CLI_PATH, "shade", map, map, (dir / "y.exr").string()}, "/dev/null", err), 2);
    std::ifstream err_text(err);
    std::stringstream err_content;
    err_content << err_text.rdbuf();
    EXPECT_NE(err_content.str().find("texture array of 4 layers"), std::string::npos) << err_content.str();
    std::filesystem::remove_all(dir);
}
#endif

// ---- The C API binding: the C++ result, and its errors.

TEST_F(ArrayTest, CApiArraysMatchTheCppCalls) {
    msmcl_context* c_context = nullptr;
    ASSERT_EQ(msmcl_context_create(nullptr, &c_context), MSMCL_SUCCESS);
    const Stack stack = make_stack(kWidth, kHeight, 2, 3, DepthRange::zero_one, seed_);
    msmcl_filter_options options;
    msmcl_filter_options_init(&options);
    options.format = MSMCL_FORMAT_NLQ64;
    const Texture expected = msmcl::filter(context(), stack.layered, FilterOptions{Format::nlq64});
    std::vector<std::uint32_t> texture(expected.words.size());
    EXPECT_EQ(msmcl_filter_array(c_context, stack.layered.depth.data(), kWidth, kHeight, 2, 3, &options, texture.data(),
                                 texture.size() * 4),
              MSMCL_SUCCESS);
    EXPECT_EQ(texture, expected.words);
    const SatTable expected_table = msmcl::build_sat(context(), stack.layered, SatOptions{});
    std::vector<std::uint32_t> table(expected_table.words.size());
    EXPECT_EQ(msmcl_build_sat_array(c_context, stack.layered.depth.data(), kWidth, kHeight, 2, 3, nullptr, table.data(),
                                    table.size()),
              MSMCL_SUCCESS);
    EXPECT_EQ(table, expected_table.words);

    // Device buffers.
    const cl_context cl = msmcl_context_cl_context(c_context);
    cl_int status = CL_SUCCESS;
    cl_mem depth = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, stack.layered.depth.size() * 4,
                                  const_cast<float*>(stack.layered.depth.data()), &status);
    ASSERT_EQ(status, CL_SUCCESS);
    cl_mem output = clCreateBuffer(cl, CL_MEM_READ_WRITE, table.size() * 4, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    const msmcl_device_depth device{depth, kWidth, kHeight, 2, MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
    msmcl_enqueue blocking{};
    blocking.blocking = 1;
    ASSERT_EQ(msmcl_filter_array_device(c_context, &device, 3, output, &options, &blocking), MSMCL_SUCCESS);
    std::vector<std::uint32_t> words(texture.size());
    ASSERT_EQ(clEnqueueReadBuffer(msmcl_context_cl_queue(c_context), output, CL_TRUE, 0, words.size() * 4, words.data(),
                                  0, nullptr, nullptr),
              CL_SUCCESS);
    EXPECT_EQ(words, expected.words);
    ASSERT_EQ(msmcl_build_sat_array_device(c_context, &device, 3, output, nullptr, &blocking), MSMCL_SUCCESS);
    words.resize(table.size());
    ASSERT_EQ(clEnqueueReadBuffer(msmcl_context_cl_queue(c_context), output, CL_TRUE, 0, words.size() * 4, words.data(),
                                  0, nullptr, nullptr),
              CL_SUCCESS);
    EXPECT_EQ(words, expected_table.words);

    // Bad layer counts and short outputs.
    EXPECT_EQ(msmcl_filter_array(c_context, stack.layered.depth.data(), kWidth, kHeight, 2, 0, &options, texture.data(),
                                 texture.size() * 4),
              MSMCL_ERROR_INPUT);
    EXPECT_EQ(msmcl_build_sat_array(c_context, stack.layered.depth.data(), kWidth, kHeight, 2, -3, nullptr,
                                    table.data(), table.size()),
              MSMCL_ERROR_INPUT);
    EXPECT_EQ(msmcl_filter_array(c_context, stack.layered.depth.data(), kWidth, kHeight, 2, 3, &options, texture.data(),
                                 texture.size() * 4 - 1),
              MSMCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(msmcl_filter_array_device(c_context, &device, 4, output, &options, &blocking), MSMCL_ERROR_INPUT);

    // A 2D image array in (the maps side by side), the buffer's bits out.
    cl_image_desc description{};
    description.image_type = CL_MEM_OBJECT_IMAGE2D_ARRAY;
    description.image_width = 2 * kWidth;
    description.image_height = kHeight;
    description.image_array_size = 3;
    const cl_image_format depth_format{CL_R, CL_FLOAT};
    cl_mem image = clCreateImage(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, &depth_format, &description,
                                 const_cast<float*>(stack.layered.depth.data()), &status);
    if (status == CL_SUCCESS) {
        const msmcl_device_depth in_image{image, kWidth, kHeight, 2, MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
        ASSERT_EQ(msmcl_filter_array_device(c_context, &in_image, 3, output, &options, &blocking), MSMCL_SUCCESS);
        words.resize(texture.size());
        ASSERT_EQ(clEnqueueReadBuffer(msmcl_context_cl_queue(c_context), output, CL_TRUE, 0, words.size() * 4,
                                      words.data(), 0, nullptr, nullptr),
                  CL_SUCCESS);
        EXPECT_EQ(words, expected.words);
        clReleaseMemObject(image);
    }
    clReleaseMemObject(output);
    clReleaseMemObject(depth);
    msmcl_context_destroy(c_context);
}

} // namespace
