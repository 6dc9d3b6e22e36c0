/* The C API (include/msmcl/msmcl.h) compiled as C (C11, -Wpedantic) and linked against the
 * shared library alone, so that only exported symbols resolve: every entry point is called
 * once from C with structs built in C, and each call that has work to do succeeds (each
 * failing call's status is printed). That the results equal the C++ API's, and the error
 * mapping, is tests/capi_test.cpp. Exit code 0 when every call behaves. */
#include <msmcl/msmcl.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;

/* A call that must return `expected`; prints the call and its message otherwise. */
static void expect_status(msmcl_status status, msmcl_status expected, const char* call) {
    if (status == expected) return;
    ++failures;
    fprintf(stderr, "capi_c_test: %s returned %s, expected %s: %s\n", call, msmcl_status_name(status),
            msmcl_status_name(expected), msmcl_last_error_message());
}
#define EXPECT_OK(call) expect_status((call), MSMCL_SUCCESS, #call)

enum { WIDTH = 9, HEIGHT = 7, SAMPLES = 2, TEXELS = WIDTH * HEIGHT, VALUES = TEXELS * SAMPLES, RECEIVERS = 5 };

static cl_mem buffer_of(msmcl_context* context, size_t bytes, const void* data) {
    cl_int error = CL_SUCCESS;
    cl_mem buffer = clCreateBuffer(msmcl_context_cl_context(context),
                                   CL_MEM_READ_WRITE | (data ? CL_MEM_COPY_HOST_PTR : 0), bytes, (void*)data, &error);
    if (error != CL_SUCCESS) {
        ++failures;
        fprintf(stderr, "capi_c_test: clCreateBuffer: %d\n", error);
    }
    return buffer;
}

static void run(msmcl_context* context) {
    float depth[VALUES], layer_depth[VALUES], layer_opacity[VALUES];
    float moments[4 * TEXELS], intensity[RECEIVERS];
    float u[RECEIVERS] = {0.5f, 2.5f, 4.0f, 6.2f, 8.9f}, v[RECEIVERS] = {0.5f, 1.5f, 3.0f, 5.2f, 6.9f};
    float z[RECEIVERS] = {0.1f, 0.3f, 0.5f, 0.7f, 0.9f}, uvz[3 * RECEIVERS];
    uint32_t pixel_x[RECEIVERS] = {0, 1, 2, 3, 4}, pixel_y[RECEIVERS] = {4, 3, 2, 1, 0}, pixels[2 * RECEIVERS];
    uint32_t table[4 * TEXELS], scale = 0;
    msmcl_translucent_layer layer;
    msmcl_filter_options filter_options;
    msmcl_shade_options shade_options;
    msmcl_sat_options sat_options;
    msmcl_soft_options soft_options;
    msmcl_enqueue blocking;
    msmcl_device_depth device_depth;
    msmcl_device_layers device_layers;
    cl_mem depth_buffer, layer_depth_buffer, layer_opacity_buffer, texture, receivers, receiver_pixels, out, sat_table;
    for (int i = 0; i < VALUES; ++i) {
        depth[i] = (float)((i * 37) % 101) / 100.0f;
        layer_depth[i] = (float)((i * 53) % 97) / 96.0f;
        layer_opacity[i] = (float)(i % 5) / 4.0f;
    }
    layer.depth = layer_depth;
    layer.opacity = layer_opacity;
    memcpy(uvz, u, sizeof u);
    memcpy(uvz + RECEIVERS, v, sizeof v);
    memcpy(uvz + 2 * RECEIVERS, z, sizeof z);
    memcpy(pixels, pixel_x, sizeof pixel_x);
    memcpy(pixels + RECEIVERS, pixel_y, sizeof pixel_y);

    /* Host calls. */
    msmcl_filter_options_init(&filter_options);
    filter_options.format = MSMCL_FORMAT_MOMENTS128;
    EXPECT_OK(msmcl_filter(context, depth, WIDTH, HEIGHT, SAMPLES, &filter_options, moments, sizeof moments));
    EXPECT_OK(msmcl_filter_layered(context, depth, WIDTH, HEIGHT, SAMPLES, &layer, 1, &filter_options, moments,
                                   sizeof moments));
    msmcl_shade_options_init(&shade_options);
    shade_options.lookup = MSMCL_LOOKUP_DITHER;
    EXPECT_OK(msmcl_shade(context, MSMCL_FORMAT_MOMENTS128, WIDTH, HEIGHT, moments, sizeof moments, u, v, z, RECEIVERS,
                          &shade_options, intensity));
    EXPECT_OK(msmcl_shade_with_pixels(context, MSMCL_FORMAT_MOMENTS128, WIDTH, HEIGHT, moments, sizeof moments, u, v,
                                      z, pixel_x, pixel_y, RECEIVERS, &shade_options, intensity));
    msmcl_sat_options_init(&sat_options);
    EXPECT_OK(msmcl_sat_scale(sat_options.max_kernel_texels, &scale));
    EXPECT_OK(msmcl_build_sat(context, depth, WIDTH, HEIGHT, SAMPLES, &sat_options, table, 4 * TEXELS));
    msmcl_soft_options_init(&soft_options);
    EXPECT_OK(msmcl_soft_shade(context, table, WIDTH, HEIGHT, sat_options.max_kernel_texels, u, v, z, RECEIVERS,
                               &soft_options, intensity));
    EXPECT_OK(msmcl_build_sat_layered(context, depth, WIDTH, HEIGHT, SAMPLES, &layer, 1, &sat_options, table,
                                      4 * TEXELS));

    /* Device calls, on buffers. */
    depth_buffer = buffer_of(context, sizeof depth, depth);
    layer_depth_buffer = buffer_of(context, sizeof layer_depth, layer_depth);
    layer_opacity_buffer = buffer_of(context, sizeof layer_opacity, layer_opacity);
    texture = buffer_of(context, sizeof moments, NULL);
    receivers = buffer_of(context, sizeof uvz, uvz);
    receiver_pixels = buffer_of(context, sizeof pixels, pixels);
    out = buffer_of(context, sizeof intensity, NULL);
    sat_table = buffer_of(context, sizeof table, NULL);
    device_depth.memory = depth_buffer;
    device_depth.width = WIDTH;
    device_depth.height = HEIGHT;
    device_depth.samples = SAMPLES;
    device_depth.layout = MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE;
    device_layers.depth = layer_depth_buffer;
    device_layers.opacity = layer_opacity_buffer;
    device_layers.count = 1;
    memset(&blocking, 0, sizeof blocking);
    blocking.blocking = 1;
    EXPECT_OK(msmcl_filter_device(context, &device_depth, texture, &filter_options, &blocking));
    EXPECT_OK(msmcl_filter_layered_device(context, &device_depth, &device_layers, texture, &filter_options, &blocking));
    EXPECT_OK(msmcl_shade_device(context, MSMCL_FORMAT_MOMENTS128, WIDTH, HEIGHT, texture, receivers, RECEIVERS, out,
                                 &shade_options, &blocking));
    EXPECT_OK(msmcl_shade_with_pixels_device(context, MSMCL_FORMAT_MOMENTS128, WIDTH, HEIGHT, texture, receivers,
                                             receiver_pixels, RECEIVERS, out, &shade_options, &blocking));
    EXPECT_OK(msmcl_build_sat_device(context, &device_depth, sat_table, &sat_options, &blocking));
    EXPECT_OK(msmcl_build_sat_layered_device(context, &device_depth, &device_layers, sat_table, &sat_options,
                                             &blocking));
    EXPECT_OK(msmcl_build_sat_device(context, &device_depth, sat_table, &sat_options, &blocking));
    EXPECT_OK(msmcl_soft_shade_device(context, sat_table, WIDTH, HEIGHT, sat_options.max_kernel_texels, receivers,
                                      RECEIVERS, out, &soft_options, &blocking));
    clReleaseMemObject(sat_table);
    clReleaseMemObject(out);
    clReleaseMemObject(receiver_pixels);
    clReleaseMemObject(receivers);
    clReleaseMemObject(texture);
    clReleaseMemObject(layer_opacity_buffer);
    clReleaseMemObject(layer_depth_buffer);
    clReleaseMemObject(depth_buffer);
}

/* Texture arrays of two layers, plain and under one translucent layer, host and device. */
static void run_arrays(msmcl_context* context) {
    enum { LAYERS = 2 };
    float depth[LAYERS * VALUES], layer_depth[LAYERS * VALUES], layer_opacity[LAYERS * VALUES];
    uint16_t texture[LAYERS * 4 * TEXELS];
    uint32_t table[LAYERS * 4 * TEXELS];
    msmcl_translucent_layer layer;
    msmcl_filter_options filter_options;
    msmcl_enqueue blocking;
    msmcl_device_depth device_depth;
    msmcl_device_layers device_layers;
    cl_mem depth_buffer, layer_depth_buffer, layer_opacity_buffer, texture_buffer, table_buffer;
    for (int i = 0; i < LAYERS * VALUES; ++i) {
        depth[i] = (float)((i * 41) % 103) / 102.0f;
        layer_depth[i] = (float)((i * 29) % 89) / 88.0f;
        layer_opacity[i] = (float)(i % 3) / 2.0f;
    }
    layer.depth = layer_depth;
    layer.opacity = layer_opacity;
    msmcl_filter_options_init(&filter_options);
    EXPECT_OK(msmcl_filter_array(context, depth, WIDTH, HEIGHT, SAMPLES, LAYERS, &filter_options, texture,
                                 sizeof texture));
    EXPECT_OK(msmcl_build_sat_array(context, depth, WIDTH, HEIGHT, SAMPLES, LAYERS, NULL, table, LAYERS * 4 * TEXELS));
    EXPECT_OK(msmcl_filter_array_layered(context, depth, WIDTH, HEIGHT, SAMPLES, LAYERS, &layer, 1, &filter_options,
                                         texture, sizeof texture));
    EXPECT_OK(msmcl_build_sat_array_layered(context, depth, WIDTH, HEIGHT, SAMPLES, LAYERS, &layer, 1, NULL, table,
                                            LAYERS * 4 * TEXELS));
    /* One translucent layer per array layer: the host arrays are already the device layout. */
    depth_buffer = buffer_of(context, sizeof depth, depth);
    layer_depth_buffer = buffer_of(context, sizeof layer_depth, layer_depth);
    layer_opacity_buffer = buffer_of(context, sizeof layer_opacity, layer_opacity);
    texture_buffer = buffer_of(context, sizeof texture, NULL);
    table_buffer = buffer_of(context, sizeof table, NULL);
    device_depth.memory = depth_buffer;
    device_depth.width = WIDTH;
    device_depth.height = HEIGHT;
    device_depth.samples = SAMPLES;
    device_depth.layout = MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE;
    device_layers.depth = layer_depth_buffer;
    device_layers.opacity = layer_opacity_buffer;
    device_layers.count = 1;
    memset(&blocking, 0, sizeof blocking);
    blocking.blocking = 1;
    EXPECT_OK(msmcl_filter_array_device(context, &device_depth, LAYERS, texture_buffer, &filter_options, &blocking));
    EXPECT_OK(msmcl_build_sat_array_device(context, &device_depth, LAYERS, table_buffer, NULL, &blocking));
    EXPECT_OK(msmcl_filter_array_layered_device(context, &device_depth, LAYERS, &device_layers, texture_buffer,
                                                &filter_options, &blocking));
    EXPECT_OK(msmcl_build_sat_array_layered_device(context, &device_depth, LAYERS, &device_layers, table_buffer, NULL,
                                                   &blocking));
    clReleaseMemObject(table_buffer);
    clReleaseMemObject(texture_buffer);
    clReleaseMemObject(layer_opacity_buffer);
    clReleaseMemObject(layer_depth_buffer);
    clReleaseMemObject(depth_buffer);
}

/* Single scattering of a small scene, host and device. */
static void run_scatter(msmcl_context* context) {
    enum { CAMERA_WIDTH = 16, CAMERA_HEIGHT = 12, PIXELS = CAMERA_WIDTH * CAMERA_HEIGHT };
    float depth[VALUES], camera_depth[PIXELS], radiance[PIXELS], moments[4 * TEXELS];
    uint32_t map[2 * 32 * 16];
    msmcl_scatter_scene scene;
    msmcl_scatter_options options;
    msmcl_filter_options filter_options;
    msmcl_enqueue blocking;
    msmcl_device_depth device_depth;
    cl_mem depth_buffer, moment_buffer, map_buffer, camera_buffer, radiance_buffer;
    for (int i = 0; i < VALUES; ++i) depth[i] = (float)((i * 37) % 101) / 100.0f;
    for (int i = 0; i < PIXELS; ++i) camera_depth[i] = 0.5f + (float)(i % 7) / 14.0f;
    msmcl_scatter_scene_init(&scene);
    scene.light.width = scene.light.height = 10.0;
    scene.light.near_plane = -5.0;
    scene.light.far_plane = 5.0;
    scene.camera.position[1] = 1.0;
    scene.camera.far_plane = 20.0;
    scene.camera.width = CAMERA_WIDTH;
    scene.camera.height = CAMERA_HEIGHT;
    scene.rectified_width = 32;
    scene.rectified_height = 16;
    msmcl_scatter_options_init(&options);
    if (msmcl_scatter_map_bytes(&scene) != sizeof map) {
        ++failures;
        fprintf(stderr, "capi_c_test: msmcl_scatter_map_bytes is %u, expected %u\n",
                (unsigned)msmcl_scatter_map_bytes(&scene), (unsigned)sizeof map);
    }
    EXPECT_OK(msmcl_scatter(context, &scene, depth, WIDTH, HEIGHT, SAMPLES, camera_depth, &options, radiance));
    EXPECT_OK(msmcl_scatter_prefilter(context, &scene, depth, WIDTH, HEIGHT, SAMPLES, &options, map, sizeof map));
    EXPECT_OK(msmcl_scatter_evaluate(context, &scene, map, sizeof map, camera_depth, &options, radiance));

    /* The device path: moments128 map, prefilter, evaluate; and the unfiltered prefilter. */
    depth_buffer = buffer_of(context, sizeof depth, depth);
    moment_buffer = buffer_of(context, sizeof moments, NULL);
    map_buffer = buffer_of(context, sizeof map, NULL);
    camera_buffer = buffer_of(context, sizeof camera_depth, camera_depth);
    radiance_buffer = buffer_of(context, sizeof radiance, NULL);
    device_depth.memory = depth_buffer;
    device_depth.width = WIDTH;
    device_depth.height = HEIGHT;
    device_depth.samples = SAMPLES;
    device_depth.layout = MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE;
    msmcl_filter_options_init(&filter_options);
    filter_options.format = MSMCL_FORMAT_MOMENTS128;
    filter_options.sigma = options.filter_sigma;
    memset(&blocking, 0, sizeof blocking);
    blocking.blocking = 1;
    EXPECT_OK(msmcl_filter_device(context, &device_depth, moment_buffer, &filter_options, NULL));
    EXPECT_OK(msmcl_scatter_prefilter_device(context, &scene, moment_buffer, WIDTH, HEIGHT, options.moments,
                                             map_buffer, NULL));
    EXPECT_OK(msmcl_scatter_evaluate_device(context, &scene, map_buffer, options.moments, camera_buffer,
                                            radiance_buffer, options.beta, &blocking));
    EXPECT_OK(msmcl_scatter_prefilter_depth_device(context, &scene, &device_depth, 4, map_buffer, &blocking));
    clReleaseMemObject(radiance_buffer);
    clReleaseMemObject(camera_buffer);
    clReleaseMemObject(map_buffer);
    clReleaseMemObject(moment_buffer);
    clReleaseMemObject(depth_buffer);
}

int main(void) {
    msmcl_context_options options;
    msmcl_context* context = NULL;
    msmcl_context* borrowed = NULL;
    msmcl_format format = MSMCL_FORMAT_MOMENTS128;
    cl_image_format image_format;
    int major = 0, minor = 0, patch = 0;

    /* Calls without a device. */
    msmcl_version(&major, &minor, &patch);
    printf("capi_c_test: msmcl %s (%d.%d.%d)\n", msmcl_version_string(), major, minor, patch);
    if (msmcl_texel_bytes(MSMCL_FORMAT_NLQ32) != 4 || strcmp(msmcl_format_name(MSMCL_FORMAT_NLQ32), "nlq32") != 0) {
        ++failures;
        fprintf(stderr, "capi_c_test: nlq32 is not 4 bytes named nlq32\n");
    }
    EXPECT_OK(msmcl_parse_format("msm64", &format));
    EXPECT_OK(msmcl_texture_image_format(format, &image_format));
    image_format = msmcl_sat_image_format();
    expect_status(msmcl_context_create(NULL, NULL), MSMCL_ERROR_INVALID_ARGUMENT, "msmcl_context_create(NULL, NULL)");
    if (msmcl_last_opencl_error() != CL_SUCCESS) ++failures;

    /* A context, and one borrowing its OpenCL objects. */
    msmcl_context_options_init(&options);
    EXPECT_OK(msmcl_context_create(&options, &context));
    if (!context) return 1;
    printf("capi_c_test: device %s\n", msmcl_context_device_name(context));
    EXPECT_OK(msmcl_context_create_from_cl(msmcl_context_cl_context(context), msmcl_context_cl_device(context),
                                           msmcl_context_cl_queue(context), &borrowed));
    EXPECT_OK(msmcl_context_set_binary_cache_dir(borrowed, NULL));
    if (borrowed) {
        run(borrowed);
        run_arrays(borrowed);
        run_scatter(borrowed);
    }
    printf("capi_c_test: %u programs built\n", (unsigned)msmcl_context_programs_built(borrowed));
    EXPECT_OK(msmcl_context_finish(borrowed));
    msmcl_context_destroy(borrowed);
    msmcl_context_destroy(context);
    printf("capi_c_test: %s\n", failures == 0 ? "every call behaved" : "calls failed");
    return failures == 0 ? 0 : 1;
}
