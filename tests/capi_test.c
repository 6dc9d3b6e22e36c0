/* The C API (include/msmcl/msmcl.h) from C, linked against the shared library: status codes
 * and messages, host filter against a double-precision reference, device paths (buffers and
 * images, no host access to the caller's objects) against the host path, shade, SAT.
 * Seed: MSMCL_TEST_SEED (default 6), printed. Exit code 0 when every check passes. */
#include <msmcl/msmcl.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int checks_failed = 0;
static int checks_passed = 0;

#define CHECK(condition, ...)                                                 \
    do {                                                                      \
        if (condition) {                                                      \
            ++checks_passed;                                                  \
        } else {                                                              \
            ++checks_failed;                                                  \
            fprintf(stderr, "%s:%d: check failed: %s: ", __FILE__, __LINE__, #condition); \
            fprintf(stderr, __VA_ARGS__);                                     \
            fprintf(stderr, "\n");                                            \
        }                                                                     \
    } while (0)

#define CHECK_OK(call)                                                                            \
    do {                                                                                          \
        msmcl_status status_ = (call);                                                            \
        CHECK(status_ == MSMCL_SUCCESS, "%s: %s", msmcl_status_name(status_), msmcl_last_error_message()); \
    } while (0)

/* xorshift32: the test's only source of randomness. */
static unsigned int rng_state = 6u;
static float random_unit(void) {
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 17;
    rng_state ^= rng_state << 5;
    return (float)(rng_state >> 8) / 16777216.0f;
}

enum { WIDTH = 37, HEIGHT = 29, SAMPLES = 4 };

/* A random depth map with a few plateaus (flat regions) and edges. */
static void make_depth(float* depth) {
    for (int y = 0; y < HEIGHT; ++y)
        for (int x = 0; x < WIDTH; ++x)
            for (int s = 0; s < SAMPLES; ++s) {
                float d = (x / 8 + y / 8) % 2 ? 0.25f + 0.01f * random_unit() : 0.5f + 0.4f * random_unit();
                depth[(y * WIDTH + x) * SAMPLES + s] = d;
            }
}

static void test_status_and_errors(void) {
    msmcl_context* context = NULL;
    int major = -1, minor = -1, patch = -1;
    msmcl_format format = MSMCL_FORMAT_MOMENTS128;
    cl_image_format image_format;
    msmcl_status status;

    msmcl_version(&major, &minor, &patch);
    CHECK(major >= 0 && minor >= 0 && patch >= 0, "version %d.%d.%d", major, minor, patch);
    CHECK(strlen(msmcl_version_string()) >= 5, "version string '%s'", msmcl_version_string());
    CHECK(strcmp(msmcl_status_name(MSMCL_ERROR_INPUT), "MSMCL_ERROR_INPUT") == 0, "%s",
          msmcl_status_name(MSMCL_ERROR_INPUT));
    CHECK(strcmp(msmcl_status_name((msmcl_status)99), "MSMCL_UNKNOWN_STATUS") == 0, "unknown status name");
    CHECK(msmcl_texel_bytes(MSMCL_FORMAT_MOMENTS128) == 16 && msmcl_texel_bytes(MSMCL_FORMAT_MSM64) == 8 &&
              msmcl_texel_bytes(MSMCL_FORMAT_NLQ64) == 8 && msmcl_texel_bytes(MSMCL_FORMAT_NLQ32) == 4 &&
              msmcl_texel_bytes((msmcl_format)7) == 0,
          "texel bytes");
    CHECK(strcmp(msmcl_format_name(MSMCL_FORMAT_NLQ32), "nlq32") == 0, "format name");
    CHECK(msmcl_format_name((msmcl_format)7) == NULL, "unknown format name");
    CHECK_OK(msmcl_parse_format("msm64", &format));
    CHECK(format == MSMCL_FORMAT_MSM64, "parsed %d", (int)format);
    status = msmcl_parse_format("msm65", &format);
    CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT && strstr(msmcl_last_error_message(), "msm65"), "%s: %s",
          msmcl_status_name(status), msmcl_last_error_message());
    CHECK_OK(msmcl_texture_image_format(MSMCL_FORMAT_NLQ32, &image_format));
    CHECK(image_format.image_channel_order == CL_R && image_format.image_channel_data_type == CL_UNSIGNED_INT32,
          "nlq32 image format");
    image_format = msmcl_sat_image_format();
    CHECK(image_format.image_channel_order == CL_RGBA && image_format.image_channel_data_type == CL_UNSIGNED_INT32,
          "sat image format");

    /* Null pointers are reported, not crashed on; a success clears the message. */
    status = msmcl_context_create(NULL, NULL);
    CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT, "%s", msmcl_status_name(status));
    CHECK(strstr(msmcl_last_error_message(), "NULL") != NULL, "message '%s'", msmcl_last_error_message());
    status = msmcl_filter(NULL, NULL, 1, 1, 1, NULL, NULL, 0);
    CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT, "%s", msmcl_status_name(status));
    CHECK_OK(msmcl_parse_format("nlq64", &format));
    CHECK(msmcl_last_error_message()[0] == '\0', "message after success '%s'", msmcl_last_error_message());
    CHECK(msmcl_context_cl_context(NULL) == NULL && strcmp(msmcl_context_device_name(NULL), "") == 0,
          "null context accessors");
    msmcl_context_destroy(NULL);

    /* A strict device spec that matches nothing is a device error. */
    {
        msmcl_context_options options;
        msmcl_context_options_init(&options);
        options.device = "no-such-device-name-xyz";
        options.strict = 1;
        options.use_environment = 0;
        status = msmcl_context_create(&options, &context);
        CHECK(status == MSMCL_ERROR_DEVICE && context == NULL, "%s: %s", msmcl_status_name(status),
              msmcl_last_error_message());
    }
}

/* Host filter against a double reference: sigma 0 makes a texel the mean of b(z) over its samples. */
static void test_host_filter(msmcl_context* context, const float* depth) {
    msmcl_filter_options options;
    float* moments = malloc(sizeof(float) * 4 * WIDTH * HEIGHT);
    unsigned short* codes = malloc(sizeof(unsigned short) * 4 * WIDTH * HEIGHT);
    double worst_moment = 0.0;
    int worst_code = 0;
    msmcl_status status;

    msmcl_filter_options_init(&options);
    CHECK(options.format == MSMCL_FORMAT_NLQ64 && fabsf(options.sigma - 2.4f) < 1e-6f, "filter defaults");
    options.sigma = 0.0f;
    options.format = MSMCL_FORMAT_MOMENTS128;
    CHECK_OK(msmcl_filter(context, depth, WIDTH, HEIGHT, SAMPLES, &options, moments, sizeof(float) * 4 * WIDTH * HEIGHT));
    options.format = MSMCL_FORMAT_MSM64;
    CHECK_OK(msmcl_filter(context, depth, WIDTH, HEIGHT, SAMPLES, &options, codes,
                          sizeof(unsigned short) * 4 * WIDTH * HEIGHT));
    for (int t = 0; t < WIDTH * HEIGHT; ++t) {
        double b[4] = {0, 0, 0, 0};
        for (int s = 0; s < SAMPLES; ++s) {
            double z = 2.0 * depth[t * SAMPLES + s] - 1.0;
            b[0] += z / SAMPLES;
            b[1] += z * z / SAMPLES;
            b[2] += z * z * z / SAMPLES;
            b[3] += z * z * z * z / SAMPLES;
        }
        /* msm64 affine basis (SPEC section 3), rounded to nearest unorm16. */
        double channel[4] = {1.5 * b[0] - 2.0 * b[2] + 0.5, 4.0 * b[1] - 4.0 * b[3],
                             sqrt(3.0) * (0.5 * b[0] - 2.0 * b[2] / 9.0) + 0.5, 0.5 * b[1] + 0.5 * b[3]};
        for (int j = 0; j < 4; ++j) {
            double error = fabs(moments[4 * t + j] - b[j]);
            int expected = (int)floor(channel[j] * 65535.0 + 0.5);
            int difference = abs((int)codes[4 * t + j] - expected);
            if (error > worst_moment) worst_moment = error;
            if (difference > worst_code) worst_code = difference;
        }
    }
    /* float32 sums of 4 samples of |b| <= 1: a few ulps of 1 (1.2e-7 each). */
    CHECK(worst_moment <= 1e-6, "moments128 off by %g", worst_moment);
    /* A code may land one step off where float32 channels sit at a rounding boundary. */
    CHECK(worst_code <= 1, "msm64 codes off by %d", worst_code);

    /* Errors: a NaN depth names its texel; a short output is the caller's mistake. */
    {
        float* bad = malloc(sizeof(float) * WIDTH * HEIGHT * SAMPLES);
        memcpy(bad, depth, sizeof(float) * WIDTH * HEIGHT * SAMPLES);
        bad[(3 * WIDTH + 5) * SAMPLES + 1] = NAN;
        status = msmcl_filter(context, bad, WIDTH, HEIGHT, SAMPLES, &options, codes,
                              sizeof(unsigned short) * 4 * WIDTH * HEIGHT);
        CHECK(status == MSMCL_ERROR_INPUT && strstr(msmcl_last_error_message(), "(5, 3)"), "%s: %s",
              msmcl_status_name(status), msmcl_last_error_message());
        status = msmcl_filter(context, depth, WIDTH, HEIGHT, SAMPLES, &options, codes, 8);
        CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT, "%s: %s", msmcl_status_name(status), msmcl_last_error_message());
        status = msmcl_filter(context, depth, WIDTH, HEIGHT, 3, &options, codes, sizeof(unsigned short) * 4 * WIDTH * HEIGHT);
        CHECK(status == MSMCL_ERROR_INPUT, "%s: %s", msmcl_status_name(status), msmcl_last_error_message());
        options.format = (msmcl_format)9;
        status = msmcl_filter(context, depth, WIDTH, HEIGHT, SAMPLES, &options, codes, 8);
        CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT, "%s: %s", msmcl_status_name(status), msmcl_last_error_message());
        free(bad);
    }
    free(moments);
    free(codes);
}

/* Reads `bytes` of a device-only buffer through a device copy into a readable buffer. */
static void read_device_buffer(cl_context cl, cl_command_queue queue, cl_mem buffer, size_t bytes, void* out) {
    cl_int error = CL_SUCCESS;
    cl_mem readable = clCreateBuffer(cl, CL_MEM_READ_WRITE, bytes, NULL, &error);
    CHECK(error == CL_SUCCESS, "clCreateBuffer %d", error);
    CHECK(clEnqueueCopyBuffer(queue, buffer, readable, 0, 0, bytes, 0, NULL, NULL) == CL_SUCCESS, "copy");
    CHECK(clEnqueueReadBuffer(queue, readable, CL_TRUE, 0, bytes, out, 0, NULL, NULL) == CL_SUCCESS, "read");
    clReleaseMemObject(readable);
}

/* Reads a width x height device-only image through a device copy into a readable buffer. */
static void read_device_image(cl_context cl, cl_command_queue queue, cl_mem image, size_t texel_bytes, void* out,
                              const cl_event* after) {
    cl_int error = CL_SUCCESS;
    size_t origin[3] = {0, 0, 0};
    size_t region[3] = {WIDTH, HEIGHT, 1};
    cl_mem readable = clCreateBuffer(cl, CL_MEM_READ_WRITE, texel_bytes * WIDTH * HEIGHT, NULL, &error);
    CHECK(error == CL_SUCCESS, "clCreateBuffer %d", error);
    CHECK(clEnqueueCopyImageToBuffer(queue, image, readable, origin, region, 0, after ? 1 : 0, after, NULL) ==
              CL_SUCCESS,
          "copy image");
    CHECK(clEnqueueReadBuffer(queue, readable, CL_TRUE, 0, texel_bytes * WIDTH * HEIGHT, out, 0, NULL, NULL) ==
              CL_SUCCESS,
          "read");
    clReleaseMemObject(readable);
}

/* Device paths, every input and output object without host access, against the host path. */
static void test_device_paths(msmcl_context* context, const float* depth) {
    cl_context cl = msmcl_context_cl_context(context);
    cl_command_queue queue = msmcl_context_cl_queue(context);
    cl_int error = CL_SUCCESS;
    const size_t texels = WIDTH * HEIGHT;
    msmcl_filter_options options;
    msmcl_device_depth device_depth;
    msmcl_enqueue enqueue;
    cl_event done = NULL;
    cl_image_format nlq32_format;
    cl_image_desc description;
    unsigned int* host = malloc(sizeof(unsigned int) * texels);
    unsigned int* device = malloc(sizeof(unsigned int) * texels);
    cl_mem depth_buffer, staging, texture_buffer, texture_image;

    msmcl_filter_options_init(&options);
    options.format = MSMCL_FORMAT_NLQ32;
    CHECK_OK(msmcl_filter(context, depth, WIDTH, HEIGHT, SAMPLES, &options, host, sizeof(unsigned int) * texels));

    /* The depth reaches the device through a host-readable staging buffer and a device copy. */
    staging = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(float) * texels * SAMPLES,
                             (void*)depth, &error);
    depth_buffer = clCreateBuffer(cl, CL_MEM_READ_WRITE | CL_MEM_HOST_NO_ACCESS, sizeof(float) * texels * SAMPLES,
                                  NULL, &error);
    CHECK(error == CL_SUCCESS, "clCreateBuffer %d", error);
    clEnqueueCopyBuffer(queue, staging, depth_buffer, 0, 0, sizeof(float) * texels * SAMPLES, 0, NULL, NULL);
    texture_buffer = clCreateBuffer(cl, CL_MEM_READ_WRITE | CL_MEM_HOST_NO_ACCESS, sizeof(unsigned int) * texels,
                                    NULL, &error);
    CHECK(error == CL_SUCCESS, "clCreateBuffer %d", error);

    device_depth.memory = depth_buffer;
    device_depth.width = WIDTH;
    device_depth.height = HEIGHT;
    device_depth.samples = SAMPLES;
    device_depth.layout = MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE;

    /* buffer -> buffer */
    CHECK_OK(msmcl_filter_device(context, &device_depth, texture_buffer, &options, NULL));
    read_device_buffer(cl, queue, texture_buffer, sizeof(unsigned int) * texels, device);
    CHECK(memcmp(host, device, sizeof(unsigned int) * texels) == 0, "buffer -> buffer differs from the host path");

    /* buffer -> image of the natural format, chained by the returned event */
    CHECK_OK(msmcl_texture_image_format(MSMCL_FORMAT_NLQ32, &nlq32_format));
    memset(&description, 0, sizeof description);
    description.image_type = CL_MEM_OBJECT_IMAGE2D;
    description.image_width = WIDTH;
    description.image_height = HEIGHT;
    texture_image = clCreateImage(cl, CL_MEM_READ_WRITE | CL_MEM_HOST_NO_ACCESS, &nlq32_format, &description, NULL,
                                  &error);
    CHECK(error == CL_SUCCESS, "clCreateImage %d", error);
    memset(&enqueue, 0, sizeof enqueue);
    enqueue.done = &done;
    memset(device, 0, sizeof(unsigned int) * texels);
    CHECK_OK(msmcl_filter_device(context, &device_depth, texture_image, &options, &enqueue));
    CHECK(done != NULL, "no done event");
    read_device_image(cl, queue, texture_image, sizeof(unsigned int), device, &done);
    CHECK(memcmp(host, device, sizeof(unsigned int) * texels) == 0, "buffer -> image differs from the host path");
    if (done) clReleaseEvent(done);

    /* A wrong image format is refused before anything is enqueued. */
    options.format = MSMCL_FORMAT_MSM64;
    {
        msmcl_status status = msmcl_filter_device(context, &device_depth, texture_image, &options, NULL);
        CHECK(status == MSMCL_ERROR_INPUT && strstr(msmcl_last_error_message(), "CL_UNORM_INT16"), "%s: %s",
              msmcl_status_name(status), msmcl_last_error_message());
    }

    clReleaseMemObject(texture_image);
    clReleaseMemObject(texture_buffer);
    clReleaseMemObject(depth_buffer);
    clReleaseMemObject(staging);
    free(host);
    free(device);
}

/* A plane at d = 0.5: receivers in front are lit, behind it shadowed. */
static void test_shade(msmcl_context* context) {
    enum { N = 8 };
    float depth[N * N];
    float moments[4 * N * N];
    float u[4] = {1.5f, 4.0f, 6.2f, 3.3f}, v[4] = {2.5f, 4.0f, 1.1f, 7.9f};
    float z[4] = {0.3f, 0.45f, 0.6f, 0.9f};
    float intensity[4] = {-1, -1, -1, -1};
    msmcl_filter_options filter_options;
    msmcl_shade_options shade_options;
    for (int i = 0; i < N * N; ++i) depth[i] = 0.5f;
    msmcl_filter_options_init(&filter_options);
    filter_options.format = MSMCL_FORMAT_MOMENTS128;
    CHECK_OK(msmcl_filter(context, depth, N, N, 1, &filter_options, moments, sizeof moments));
    msmcl_shade_options_init(&shade_options);
    CHECK(shade_options.lookup == MSMCL_LOOKUP_BILINEAR && fabsf(shade_options.depth_bias - 1e-3f) < 1e-9f,
          "shade defaults");
    CHECK_OK(msmcl_shade(context, MSMCL_FORMAT_MOMENTS128, N, N, moments, sizeof moments, u, v, z, 4, &shade_options,
                         intensity));
    CHECK(intensity[0] < 0.02f && intensity[1] < 0.02f, "in front: %g %g", intensity[0], intensity[1]);
    /* 4MSM lower bound of a single depth behind the receiver: close to 1 (the bias leaves a little light). */
    CHECK(intensity[2] > 0.9f && intensity[3] > 0.9f, "behind: %g %g", intensity[2], intensity[3]);
    {
        float nan_z[1] = {NAN};
        msmcl_status status = msmcl_shade(context, MSMCL_FORMAT_MOMENTS128, N, N, moments, sizeof moments, u, v, nan_z,
                                          1, &shade_options, intensity);
        CHECK(status == MSMCL_ERROR_INPUT, "%s: %s", msmcl_status_name(status), msmcl_last_error_message());
    }
}

/* SAT: host table against the device table written into an image. */
static void test_sat(msmcl_context* context, const float* depth) {
    cl_context cl = msmcl_context_cl_context(context);
    cl_command_queue queue = msmcl_context_cl_queue(context);
    const size_t texels = WIDTH * HEIGHT;
    unsigned int* host = malloc(sizeof(unsigned int) * 4 * texels);
    unsigned int* device = malloc(sizeof(unsigned int) * 4 * texels);
    msmcl_sat_options options;
    uint32_t scale = 0;
    cl_int error = CL_SUCCESS;
    cl_image_format format = msmcl_sat_image_format();
    cl_image_desc description;
    cl_mem depth_buffer, table_image;
    msmcl_device_depth device_depth;

    msmcl_sat_options_init(&options);
    CHECK(options.max_kernel_texels == 27 * 27, "sat defaults");
    CHECK_OK(msmcl_sat_scale(options.max_kernel_texels, &scale));
    CHECK(scale == 0xffffffffu / (27u * 27u), "scale %u", scale);
    CHECK(msmcl_sat_scale(1, &scale) == MSMCL_ERROR_INPUT, "N = 1 accepted");
    CHECK_OK(msmcl_build_sat(context, depth, WIDTH, HEIGHT, SAMPLES, &options, host, 4 * texels));

    depth_buffer = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(float) * texels * SAMPLES,
                                  (void*)depth, &error);
    memset(&description, 0, sizeof description);
    description.image_type = CL_MEM_OBJECT_IMAGE2D;
    description.image_width = WIDTH;
    description.image_height = HEIGHT;
    table_image = clCreateImage(cl, CL_MEM_READ_WRITE | CL_MEM_HOST_NO_ACCESS, &format, &description, NULL, &error);
    CHECK(error == CL_SUCCESS, "clCreateImage %d", error);
    device_depth.memory = depth_buffer;
    device_depth.width = WIDTH;
    device_depth.height = HEIGHT;
    device_depth.samples = SAMPLES;
    device_depth.layout = MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE;
    CHECK_OK(msmcl_build_sat_device(context, &device_depth, table_image, &options, NULL));
    read_device_image(cl, queue, table_image, 16, device, NULL);
    CHECK(memcmp(host, device, sizeof(unsigned int) * 4 * texels) == 0, "device SAT image differs from the host table");
    clReleaseMemObject(table_image);
    clReleaseMemObject(depth_buffer);
    free(host);
    free(device);
}

int main(void) {
    const char* seed_text = getenv("MSMCL_TEST_SEED");
    unsigned int seed = seed_text ? (unsigned int)strtoul(seed_text, NULL, 10) : 6u;
    msmcl_context* context = NULL;
    float* depth = malloc(sizeof(float) * WIDTH * HEIGHT * SAMPLES);

    rng_state = seed ? seed : 6u;
    printf("capi_test: seed %u (MSMCL_TEST_SEED overrides)\n", seed);
    make_depth(depth);
    test_status_and_errors();
    CHECK_OK(msmcl_context_create(NULL, &context));
    if (context) {
        printf("capi_test: device %s\n", msmcl_context_device_name(context));
        test_host_filter(context, depth);
        test_device_paths(context, depth);
        test_shade(context);
        test_sat(context, depth);
        CHECK_OK(msmcl_context_finish(context));
        msmcl_context_destroy(context);
    }
    free(depth);
    printf("%d passed, %d failed\n", checks_passed, checks_failed);
    return checks_failed == 0 ? 0 : 1;
}
