/* The C API (include/msmcl/msmcl.h) from C, linked against the shared library: status codes
 * and messages, host filter against a double-precision reference, device paths (buffers and
 * images, no host access to the caller's objects) against the host path, shade, SAT, soft shadows;
 * translucent layers (filter and SAT against a double reference and the bits the C++ API
 * guarantees: no or clear layers give the opaque bits, opacity 1 acts as opaque, device
 * equals host) and the dithered lookup (each result one of its texels shaded as nearest,
 * pixels / screen width / frame reach the kernel, device equals host, the mean over frames
 * is the bilinear blend).
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
        /* msm64 affine basis (docs/math.md), rounded to nearest unorm16. */
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
        /* Values outside every enum (any int can come from C) are argument errors; the library
           reads them as integers (an ASan+UBSan build checks that no enum load sees them). */
        options.format = MSMCL_FORMAT_NLQ64;
        options.kernel = (msmcl_filter_kernel)-7;
        status = msmcl_filter(context, depth, WIDTH, HEIGHT, SAMPLES, &options, codes, 8);
        CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT && strstr(msmcl_last_error_message(), "filter kernel -7"), "%s: %s",
              msmcl_status_name(status), msmcl_last_error_message());
        options.kernel = MSMCL_FILTER_KERNEL_AUTOMATIC;
        options.depth_range = (msmcl_depth_range)1000;
        status = msmcl_filter(context, depth, WIDTH, HEIGHT, SAMPLES, &options, codes, 8);
        CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT && strstr(msmcl_last_error_message(), "depth range 1000"), "%s: %s",
              msmcl_status_name(status), msmcl_last_error_message());
        CHECK(msmcl_texel_bytes((msmcl_format)-1) == 0 && msmcl_format_name((msmcl_format)1 << 20) == NULL,
              "out-of-range formats");
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
    CHECK(options.kernel == MSMCL_SAT_KERNEL_AUTOMATIC, "sat kernel default");
    CHECK_OK(msmcl_build_sat(context, depth, WIDTH, HEIGHT, SAMPLES, &options, host, 4 * texels));
    /* Every distribution gives the same bits; an unknown one is refused. */
    for (int kernel = MSMCL_SAT_KERNEL_TILED_GPU; kernel <= MSMCL_SAT_KERNEL_ROW_PER_THREAD; ++kernel) {
        msmcl_sat_options chosen = options;
        chosen.kernel = (msmcl_sat_kernel)kernel;
        CHECK_OK(msmcl_build_sat(context, depth, WIDTH, HEIGHT, SAMPLES, &chosen, device, 4 * texels));
        CHECK(memcmp(host, device, sizeof(unsigned int) * 4 * texels) == 0, "SAT kernel %d differs", kernel);
    }
    {
        msmcl_sat_options unknown = options;
        unknown.kernel = (msmcl_sat_kernel)9;
        CHECK(msmcl_build_sat(context, depth, WIDTH, HEIGHT, SAMPLES, &unknown, device, 4 * texels) ==
                  MSMCL_ERROR_INVALID_ARGUMENT,
              "unknown SAT kernel accepted");
    }

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

/* msmcl_soft_shade: the options reach the kernel (defaults, the published method, bad
 * values refused), a receiver in front of everything is lit, one far behind a plateau of
 * the map (depth 0.25, a receiver at 0.95, every depth around it in front) is shadowed. */
static void test_soft(msmcl_context* context, const float* depth) {
    enum { RECEIVERS = 64 };
    const size_t texels = WIDTH * HEIGHT;
    unsigned int* table = malloc(sizeof(unsigned int) * 4 * texels);
    float u[RECEIVERS], v[RECEIVERS], z[RECEIVERS], refined[RECEIVERS], published[RECEIVERS];
    msmcl_sat_options sat_options;
    msmcl_soft_options options, published_options, bad;
    int differ = 0;

    msmcl_sat_options_init(&sat_options);
    sat_options.max_kernel_texels = 100;
    CHECK_OK(msmcl_build_sat(context, depth, WIDTH, HEIGHT, SAMPLES, &sat_options, table, 4 * texels));
    msmcl_soft_options_init(&options);
    CHECK(options.light_size == 64.0f && options.search_size == 0 && options.min_filter_size == 1.0f &&
              options.receiver_blocker_weight == 0.1f && options.filter_parts == 2 &&
              options.depth_range == MSMCL_DEPTH_RANGE_ZERO_ONE,
          "soft defaults");
    options.light_size = 20.0f;
    for (int i = 0; i < RECEIVERS; ++i) {
        u[i] = random_unit() * WIDTH;
        v[i] = random_unit() * HEIGHT;
        z[i] = 0.3f + 0.7f * random_unit();
    }
    u[0] = 4.0f, v[0] = 4.0f, z[0] = 0.01f; /* in front of everything */
    u[1] = 4.0f, v[1] = 12.0f, z[1] = 0.95f; /* a plateau (x / 8 + y / 8 odd) at 0.25 */
    CHECK_OK(msmcl_soft_shade(context, table, WIDTH, HEIGHT, 100, u, v, z, RECEIVERS, &options, refined));
    published_options = options;
    published_options.receiver_blocker_weight = 0.0f;
    published_options.filter_parts = 1;
    CHECK_OK(msmcl_soft_shade(context, table, WIDTH, HEIGHT, 100, u, v, z, RECEIVERS, &published_options, published));
    CHECK(refined[0] == 0.0f && published[0] == 0.0f, "lit receiver: %g, %g", refined[0], published[0]);
    CHECK(refined[1] > 0.9f && published[1] > 0.9f, "shadowed receiver: %g, %g", refined[1], published[1]);
    for (int i = 0; i < RECEIVERS; ++i) {
        CHECK(refined[i] >= 0.0f && refined[i] <= 1.0f, "receiver %d: %g", i, refined[i]);
        differ += refined[i] != published[i];
    }
    CHECK(differ > 0, "the refinements changed no receiver");
    bad = options;
    bad.filter_parts = 5;
    CHECK(msmcl_soft_shade(context, table, WIDTH, HEIGHT, 100, u, v, z, RECEIVERS, &bad, refined) == MSMCL_ERROR_INPUT,
          "5 filter parts accepted");
    bad = options;
    bad.receiver_blocker_weight = -1.0f;
    CHECK(msmcl_soft_shade(context, table, WIDTH, HEIGHT, 100, u, v, z, RECEIVERS, &bad, refined) == MSMCL_ERROR_INPUT,
          "negative receiver weight accepted");
    CHECK(msmcl_soft_shade(context, NULL, WIDTH, HEIGHT, 100, u, v, z, RECEIVERS, &options, refined) ==
              MSMCL_ERROR_INVALID_ARGUMENT,
          "NULL table accepted");
    free(table);
}

/* ---- Translucent layers */

enum { LAYERS = 2, VALUES = WIDTH * HEIGHT * SAMPLES };

/* LAYERS layers, one after the other (the device layout): random depths over the whole
 * range; opacities a quarter 0, a quarter 1, the rest in (0, 1). */
static void make_layers(float* layer_depth, float* layer_opacity) {
    for (int i = 0; i < LAYERS * VALUES; ++i) {
        float pick = random_unit();
        layer_depth[i] = random_unit();
        layer_opacity[i] = pick < 0.25f ? 0.0f : pick < 0.5f ? 1.0f : random_unit();
    }
}

/* Host view of layers stored one after the other. */
static void layer_views(const float* layer_depth, const float* layer_opacity, msmcl_translucent_layer* views) {
    for (int k = 0; k < LAYERS; ++k) {
        views[k].depth = layer_depth + (size_t)k * VALUES;
        views[k].opacity = layer_opacity + (size_t)k * VALUES;
    }
}

/* Double reference (docs/math.md): the sample's surfaces sorted nearest first (the
 * translucent ones before the opaque one at equal depth), alpha-blended front to back;
 * adds the blend's moments b1..b4 times `scale` to b. Depths in [0,1]: z = 2d - 1. */
static void add_composite_moments(const float* depth, const float* layer_depth, const float* layer_opacity,
                                  size_t index, double scale, double* b) {
    double z[LAYERS + 1], a[LAYERS + 1], transmitted = 1.0;
    int count = 0;
    for (int k = 0; k <= LAYERS; ++k) {
        /* Insertion sort, stable: the opaque surface (k == LAYERS) goes last among equals. */
        double zk = 2.0 * (k < LAYERS ? layer_depth[(size_t)k * VALUES + index] : depth[index]) - 1.0;
        double ak = k < LAYERS ? layer_opacity[(size_t)k * VALUES + index] : 1.0;
        int at = count++;
        while (at > 0 && z[at - 1] > zk) {
            z[at] = z[at - 1];
            a[at] = a[at - 1];
            --at;
        }
        z[at] = zk;
        a[at] = ak;
    }
    for (int i = 0; i < count; ++i) {
        double weight = transmitted * a[i] * scale;
        transmitted *= 1.0 - a[i];
        b[0] += weight * z[i];
        b[1] += weight * z[i] * z[i];
        b[2] += weight * z[i] * z[i] * z[i];
        b[3] += weight * z[i] * z[i] * z[i] * z[i];
    }
}

/* A device-only buffer (no host access) holding `bytes` of `data`, filled by a device copy. */
static cl_mem device_only_buffer(cl_context cl, cl_command_queue queue, size_t bytes, const void* data) {
    cl_int error = CL_SUCCESS;
    cl_mem staging = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, (void*)data, &error);
    cl_mem buffer = clCreateBuffer(cl, CL_MEM_READ_WRITE | CL_MEM_HOST_NO_ACCESS, bytes, NULL, &error);
    CHECK(error == CL_SUCCESS, "clCreateBuffer %d", error);
    CHECK(clEnqueueCopyBuffer(queue, staging, buffer, 0, 0, bytes, 0, NULL, NULL) == CL_SUCCESS, "copy");
    clFinish(queue);
    clReleaseMemObject(staging);
    return buffer;
}

static cl_mem image_2d(cl_context cl, cl_image_format format) {
    cl_int error = CL_SUCCESS;
    cl_image_desc description;
    cl_mem image;
    memset(&description, 0, sizeof description);
    description.image_type = CL_MEM_OBJECT_IMAGE2D;
    description.image_width = WIDTH;
    description.image_height = HEIGHT;
    image = clCreateImage(cl, CL_MEM_READ_WRITE | CL_MEM_HOST_NO_ACCESS, &format, &description, NULL, &error);
    CHECK(error == CL_SUCCESS, "clCreateImage %d", error);
    return image;
}

/* msmcl_filter_layered and msmcl_filter_layered_device. */
static void test_translucent_filter(msmcl_context* context, const float* depth) {
    cl_context cl = msmcl_context_cl_context(context);
    cl_command_queue queue = msmcl_context_cl_queue(context);
    const size_t texels = WIDTH * HEIGHT;
    const size_t code_bytes = sizeof(unsigned short) * 4 * texels;
    float* layer_depth = malloc(sizeof(float) * LAYERS * VALUES);
    float* layer_opacity = malloc(sizeof(float) * LAYERS * VALUES);
    float* clear_opacity = calloc((size_t)LAYERS * VALUES, sizeof(float));
    float* nearer = malloc(sizeof(float) * VALUES);
    float* moments = malloc(sizeof(float) * 4 * texels);
    unsigned short* expected = malloc(code_bytes);
    unsigned short* codes = malloc(code_bytes);
    msmcl_translucent_layer layers[LAYERS], clear[LAYERS], wall[1];
    msmcl_filter_options options;
    msmcl_status status;
    double worst = 0.0;

    make_layers(layer_depth, layer_opacity);
    layer_views(layer_depth, layer_opacity, layers);
    layer_views(layer_depth, clear_opacity, clear);
    msmcl_filter_options_init(&options);

    /* moments128, no blur: each texel the mean over its samples of the composited moments. */
    options.format = MSMCL_FORMAT_MOMENTS128;
    options.sigma = 0.0f;
    CHECK_OK(msmcl_filter_layered(context, depth, WIDTH, HEIGHT, SAMPLES, layers, LAYERS, &options, moments,
                                  sizeof(float) * 4 * texels));
    for (size_t t = 0; t < texels; ++t) {
        double b[4] = {0, 0, 0, 0};
        for (int s = 0; s < SAMPLES; ++s)
            add_composite_moments(depth, layer_depth, layer_opacity, t * SAMPLES + s, 1.0 / SAMPLES, b);
        for (int j = 0; j < 4; ++j)
            if (fabs(moments[4 * t + j] - b[j]) > worst) worst = fabs(moments[4 * t + j] - b[j]);
    }
    printf("capi_test: translucent moments128 vs double reference: worst %.3g\n", worst);
    /* float32: the composite's roundings (transmittances, weights, 3 terms, the division by
     * their total) and the mean of 4 samples, values <= 1 (tests/translucent_test.cpp: 3e-6). */
    CHECK(worst <= 3e-6, "translucent moments128 off by %g", worst);

    /* No layers, and layers of opacity 0: the opaque filter's bits (default nlq64, blurred). */
    msmcl_filter_options_init(&options);
    CHECK_OK(msmcl_filter(context, depth, WIDTH, HEIGHT, SAMPLES, &options, expected, code_bytes));
    CHECK_OK(msmcl_filter_layered(context, depth, WIDTH, HEIGHT, SAMPLES, NULL, 0, &options, codes, code_bytes));
    CHECK(memcmp(codes, expected, code_bytes) == 0, "no layers differs from msmcl_filter");
    memset(codes, 0, code_bytes);
    CHECK_OK(msmcl_filter_layered(context, depth, WIDTH, HEIGHT, SAMPLES, clear, LAYERS, &options, codes, code_bytes));
    CHECK(memcmp(codes, expected, code_bytes) == 0, "layers of opacity 0 differ from msmcl_filter");

    /* Opacity 1 acts as opaque: the opaque map of the nearer depth, bit for bit (msm64: no
     * per-block shift that the nearer depth could move). */
    options.format = MSMCL_FORMAT_MSM64;
    wall[0].depth = layer_depth;
    wall[0].opacity = layer_opacity + VALUES; /* reuse the second layer's opacities, made 0 or 1 */
    for (int i = 0; i < VALUES; ++i) {
        layer_opacity[VALUES + i] = layer_opacity[VALUES + i] >= 0.5f ? 1.0f : 0.0f;
        nearer[i] = layer_opacity[VALUES + i] == 1.0f && layer_depth[i] < depth[i] ? layer_depth[i] : depth[i];
    }
    CHECK_OK(msmcl_filter(context, nearer, WIDTH, HEIGHT, SAMPLES, &options, expected, code_bytes));
    CHECK_OK(msmcl_filter_layered(context, depth, WIDTH, HEIGHT, SAMPLES, wall, 1, &options, codes, code_bytes));
    CHECK(memcmp(codes, expected, code_bytes) == 0, "an opacity-1 layer differs from the opaque nearer depth");

    /* Device: depth, layers and texture in device-only buffers, against the host path. */
    {
        cl_mem depth_buffer = device_only_buffer(cl, queue, sizeof(float) * VALUES, depth);
        cl_mem depth_layers = device_only_buffer(cl, queue, sizeof(float) * LAYERS * VALUES, layer_depth);
        cl_mem opacity_layers = device_only_buffer(cl, queue, sizeof(float) * LAYERS * VALUES, layer_opacity);
        cl_mem texture_buffer = clCreateBuffer(cl, CL_MEM_READ_WRITE | CL_MEM_HOST_NO_ACCESS, code_bytes, NULL, NULL);
        cl_image_format nlq32_format;
        cl_mem texture_image;
        msmcl_device_depth device_depth = {depth_buffer, WIDTH, HEIGHT, SAMPLES, MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
        msmcl_device_layers device_layers = {depth_layers, opacity_layers, LAYERS};
        msmcl_enqueue enqueue;
        cl_event done = NULL;

        /* msm64 with both layers (the first partly translucent, the second 0 or 1). */
        CHECK_OK(msmcl_filter_layered(context, depth, WIDTH, HEIGHT, SAMPLES, layers, LAYERS, &options, expected,
                                      code_bytes));
        memset(&enqueue, 0, sizeof enqueue);
        enqueue.done = &done;
        CHECK_OK(msmcl_filter_layered_device(context, &device_depth, &device_layers, texture_buffer, &options,
                                             &enqueue));
        CHECK(done != NULL, "no done event");
        if (done) {
            clWaitForEvents(1, &done);
            clReleaseEvent(done);
        }
        read_device_buffer(cl, queue, texture_buffer, code_bytes, codes);
        CHECK(memcmp(codes, expected, code_bytes) == 0, "layered device filter differs from the host path");

        /* No layers (count 0, or NULL): msmcl_filter_device, images included. */
        CHECK_OK(msmcl_texture_image_format(MSMCL_FORMAT_NLQ32, &nlq32_format));
        texture_image = image_2d(cl, nlq32_format);
        options.format = MSMCL_FORMAT_NLQ32;
        CHECK_OK(msmcl_filter(context, depth, WIDTH, HEIGHT, SAMPLES, &options, expected, sizeof(unsigned int) * texels));
        device_layers.count = 0;
        CHECK_OK(msmcl_filter_layered_device(context, &device_depth, &device_layers, texture_image, &options, NULL));
        read_device_image(cl, queue, texture_image, sizeof(unsigned int), codes, NULL);
        CHECK(memcmp(codes, expected, sizeof(unsigned int) * texels) == 0, "count 0 into an image differs");
        memset(codes, 0, code_bytes);
        CHECK_OK(msmcl_filter_layered_device(context, &device_depth, NULL, texture_image, &options, NULL));
        read_device_image(cl, queue, texture_image, sizeof(unsigned int), codes, NULL);
        CHECK(memcmp(codes, expected, sizeof(unsigned int) * texels) == 0, "NULL layers into an image differs");

        /* Layers need buffers; NULL layer buffers with a count are the caller's mistake. */
        device_layers.count = LAYERS;
        status = msmcl_filter_layered_device(context, &device_depth, &device_layers, texture_image, &options, NULL);
        CHECK(status == MSMCL_ERROR_INPUT && strstr(msmcl_last_error_message(), "buffer"), "%s: %s",
              msmcl_status_name(status), msmcl_last_error_message());
        device_layers.opacity = NULL;
        status = msmcl_filter_layered_device(context, &device_depth, &device_layers, texture_buffer, &options, NULL);
        CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT && strstr(msmcl_last_error_message(), "opacity"), "%s: %s",
              msmcl_status_name(status), msmcl_last_error_message());
        /* Buffers too small for the count: the C++ API's input error. */
        device_layers.opacity = opacity_layers;
        device_layers.count = LAYERS + 1;
        status = msmcl_filter_layered_device(context, &device_depth, &device_layers, texture_buffer, &options, NULL);
        CHECK(status == MSMCL_ERROR_INPUT && msmcl_last_error_message()[0] != '\0', "%s: %s",
              msmcl_status_name(status), msmcl_last_error_message());

        clReleaseMemObject(texture_image);
        clReleaseMemObject(texture_buffer);
        clReleaseMemObject(opacity_layers);
        clReleaseMemObject(depth_layers);
        clReleaseMemObject(depth_buffer);
    }

    /* Host errors: NULL layers with a count and NULL arrays are argument errors; bad values,
     * too many layers are input errors naming what is wrong. */
    options.format = MSMCL_FORMAT_MSM64;
    status = msmcl_filter_layered(context, depth, WIDTH, HEIGHT, SAMPLES, NULL, 2, &options, codes, code_bytes);
    CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT && strstr(msmcl_last_error_message(), "layers is NULL"), "%s: %s",
          msmcl_status_name(status), msmcl_last_error_message());
    clear[1].opacity = NULL;
    status = msmcl_filter_layered(context, depth, WIDTH, HEIGHT, SAMPLES, clear, LAYERS, &options, codes, code_bytes);
    CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT && strstr(msmcl_last_error_message(), "layers[1].opacity"), "%s: %s",
          msmcl_status_name(status), msmcl_last_error_message());
    clear[1].opacity = clear_opacity + VALUES;
    clear_opacity[VALUES + (3 * WIDTH + 5) * SAMPLES + 2] = 1.5f;
    status = msmcl_filter_layered(context, depth, WIDTH, HEIGHT, SAMPLES, clear, LAYERS, &options, codes, code_bytes);
    CHECK(status == MSMCL_ERROR_INPUT && strstr(msmcl_last_error_message(), "opacity") &&
              strstr(msmcl_last_error_message(), "(5, 3)"),
          "%s: %s", msmcl_status_name(status), msmcl_last_error_message());
    clear_opacity[VALUES + (3 * WIDTH + 5) * SAMPLES + 2] = 0.0f;
    layer_depth[7] = NAN;
    status = msmcl_filter_layered(context, depth, WIDTH, HEIGHT, SAMPLES, clear, LAYERS, &options, codes, code_bytes);
    CHECK(status == MSMCL_ERROR_INPUT && strstr(msmcl_last_error_message(), "depth"), "%s: %s",
          msmcl_status_name(status), msmcl_last_error_message());
    layer_depth[7] = 0.5f;
    {
        msmcl_translucent_layer many[MSMCL_MAX_TRANSLUCENT_LAYERS + 1];
        for (int k = 0; k <= MSMCL_MAX_TRANSLUCENT_LAYERS; ++k) many[k] = clear[0];
        status = msmcl_filter_layered(context, depth, WIDTH, HEIGHT, SAMPLES, many, MSMCL_MAX_TRANSLUCENT_LAYERS + 1,
                                      &options, codes, code_bytes);
        CHECK(status == MSMCL_ERROR_INPUT && strstr(msmcl_last_error_message(), "at most 8"), "%s: %s",
              msmcl_status_name(status), msmcl_last_error_message());
    }
    status = msmcl_filter_layered(NULL, depth, WIDTH, HEIGHT, SAMPLES, clear, LAYERS, &options, codes, code_bytes);
    CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT, "%s: %s", msmcl_status_name(status), msmcl_last_error_message());

    free(layer_depth);
    free(layer_opacity);
    free(clear_opacity);
    free(nearer);
    free(moments);
    free(expected);
    free(codes);
}

/* msmcl_build_sat_layered and msmcl_build_sat_layered_device. */
static void test_translucent_sat(msmcl_context* context, const float* depth) {
    cl_context cl = msmcl_context_cl_context(context);
    cl_command_queue queue = msmcl_context_cl_queue(context);
    const size_t texels = WIDTH * HEIGHT;
    const size_t words = 4 * texels;
    float* layer_depth = malloc(sizeof(float) * LAYERS * VALUES);
    float* layer_opacity = malloc(sizeof(float) * LAYERS * VALUES);
    float* clear_opacity = calloc((size_t)LAYERS * VALUES, sizeof(float));
    uint32_t* expected = malloc(sizeof(uint32_t) * words);
    uint32_t* table = malloc(sizeof(uint32_t) * words);
    msmcl_translucent_layer layers[LAYERS], clear[LAYERS];
    msmcl_sat_options options;
    msmcl_status status;
    uint32_t scale = 0;
    double worst = 0.0, tolerance;

    make_layers(layer_depth, layer_opacity);
    layer_views(layer_depth, layer_opacity, layers);
    layer_views(layer_depth, clear_opacity, clear);
    msmcl_sat_options_init(&options);
    CHECK_OK(msmcl_sat_scale(options.max_kernel_texels, &scale));

    /* No layers and clear layers: the opaque table's bits. */
    CHECK_OK(msmcl_build_sat(context, depth, WIDTH, HEIGHT, SAMPLES, &options, expected, words));
    CHECK_OK(msmcl_build_sat_layered(context, depth, WIDTH, HEIGHT, SAMPLES, NULL, 0, &options, table, words));
    CHECK(memcmp(table, expected, sizeof(uint32_t) * words) == 0, "no layers differs from msmcl_build_sat");
    CHECK_OK(msmcl_build_sat_layered(context, depth, WIDTH, HEIGHT, SAMPLES, clear, LAYERS, &options, table, words));
    CHECK(memcmp(table, expected, sizeof(uint32_t) * words) == 0, "clear layers differ from msmcl_build_sat");

    /* Translucent: each texel, recovered by wrapping differences, against round(c * scale) of
     * the double msm64 channels of the composited moments (docs/math.md). */
    CHECK_OK(msmcl_build_sat_layered(context, depth, WIDTH, HEIGHT, SAMPLES, layers, LAYERS, &options, expected, words));
    for (int y = 0; y < HEIGHT; ++y)
        for (int x = 0; x < WIDTH; ++x) {
            double b[4] = {0, 0, 0, 0}, channel[4];
            size_t t = (size_t)y * WIDTH + x;
            for (int s = 0; s < SAMPLES; ++s)
                add_composite_moments(depth, layer_depth, layer_opacity, t * SAMPLES + s, 1.0 / SAMPLES, b);
            channel[0] = 1.5 * b[0] - 2.0 * b[2] + 0.5;
            channel[1] = 4.0 * b[1] - 4.0 * b[3];
            channel[2] = sqrt(3.0) * (0.5 * b[0] - 2.0 * b[2] / 9.0) + 0.5;
            channel[3] = 0.5 * b[1] + 0.5 * b[3];
            for (int c = 0; c < 4; ++c) {
                uint32_t here = expected[4 * t + c];
                uint32_t left = x > 0 ? expected[4 * (t - 1) + c] : 0u;
                uint32_t up = y > 0 ? expected[4 * (t - WIDTH) + c] : 0u;
                uint32_t corner = x > 0 && y > 0 ? expected[4 * (t - WIDTH - 1) + c] : 0u;
                uint32_t texel = here - left - up + corner; /* mod 2^32 */
                double error = fabs((double)texel - channel[c] * scale);
                if (error > worst) worst = error;
            }
        }
    /* float32 composite (3e-6, as for filter) times the channel scale, plus the rounding. */
    tolerance = 3e-6 * scale + 1.0;
    printf("capi_test: translucent SAT texels vs double reference: worst %.1f units (tolerance %.1f)\n", worst,
           tolerance);
    CHECK(worst <= tolerance, "translucent SAT texels off by %.1f units", worst);

    /* Device: buffers without host access, against the host table. */
    {
        cl_mem depth_buffer = device_only_buffer(cl, queue, sizeof(float) * VALUES, depth);
        cl_mem depth_layers = device_only_buffer(cl, queue, sizeof(float) * LAYERS * VALUES, layer_depth);
        cl_mem opacity_layers = device_only_buffer(cl, queue, sizeof(float) * LAYERS * VALUES, layer_opacity);
        cl_mem table_buffer =
            clCreateBuffer(cl, CL_MEM_READ_WRITE | CL_MEM_HOST_NO_ACCESS, sizeof(uint32_t) * words, NULL, NULL);
        cl_mem table_image = image_2d(cl, msmcl_sat_image_format());
        msmcl_device_depth device_depth = {depth_buffer, WIDTH, HEIGHT, SAMPLES, MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
        msmcl_device_layers device_layers = {depth_layers, opacity_layers, LAYERS};
        msmcl_enqueue enqueue;
        memset(&enqueue, 0, sizeof enqueue);
        enqueue.blocking = 1;
        CHECK_OK(msmcl_build_sat_layered_device(context, &device_depth, &device_layers, table_buffer, &options,
                                                &enqueue));
        read_device_buffer(cl, queue, table_buffer, sizeof(uint32_t) * words, table);
        CHECK(memcmp(table, expected, sizeof(uint32_t) * words) == 0, "layered device SAT differs from the host table");

        status = msmcl_build_sat_layered_device(context, &device_depth, &device_layers, table_image, &options, NULL);
        CHECK(status == MSMCL_ERROR_INPUT && strstr(msmcl_last_error_message(), "buffer"), "%s: %s",
              msmcl_status_name(status), msmcl_last_error_message());
        /* No layers: msmcl_build_sat_device, images included. */
        CHECK_OK(msmcl_build_sat(context, depth, WIDTH, HEIGHT, SAMPLES, &options, expected, words));
        CHECK_OK(msmcl_build_sat_layered_device(context, &device_depth, NULL, table_image, &options, NULL));
        read_device_image(cl, queue, table_image, 16, table, NULL);
        CHECK(memcmp(table, expected, sizeof(uint32_t) * words) == 0, "NULL layers into an image differs");
        device_layers.depth = NULL;
        status = msmcl_build_sat_layered_device(context, &device_depth, &device_layers, table_buffer, &options, NULL);
        CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT && strstr(msmcl_last_error_message(), "depth"), "%s: %s",
              msmcl_status_name(status), msmcl_last_error_message());

        clReleaseMemObject(table_image);
        clReleaseMemObject(table_buffer);
        clReleaseMemObject(opacity_layers);
        clReleaseMemObject(depth_layers);
        clReleaseMemObject(depth_buffer);
    }

    /* Host errors. */
    status = msmcl_build_sat_layered(context, depth, WIDTH, HEIGHT, SAMPLES, NULL, 1, &options, table, words);
    CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT && strstr(msmcl_last_error_message(), "layers is NULL"), "%s: %s",
          msmcl_status_name(status), msmcl_last_error_message());
    layer_opacity[11] = -0.25f;
    status = msmcl_build_sat_layered(context, depth, WIDTH, HEIGHT, SAMPLES, layers, LAYERS, &options, table, words);
    CHECK(status == MSMCL_ERROR_INPUT && strstr(msmcl_last_error_message(), "opacity"), "%s: %s",
          msmcl_status_name(status), msmcl_last_error_message());

    free(layer_depth);
    free(layer_opacity);
    free(clear_opacity);
    free(expected);
    free(table);
}

/* ---- Dithered lookup */

enum { RECEIVERS = 600, DITHER_SCREEN_WIDTH = 41, DITHER_FRAMES = 64 };

static int clamp_index(int i, int size) { return i < 0 ? 0 : i >= size ? size - 1 : i; }

/* msmcl_shade(_with_pixels)(_device) with MSMCL_LOOKUP_DITHER. */
static void test_dither(msmcl_context* context, const float* depth) {
    cl_context cl = msmcl_context_cl_context(context);
    cl_command_queue queue = msmcl_context_cl_queue(context);
    const size_t map_bytes = sizeof(unsigned short) * 4 * WIDTH * HEIGHT;
    unsigned short* map = malloc(map_bytes);
    float u[RECEIVERS], v[RECEIVERS], z[RECEIVERS], dither[RECEIVERS], other[RECEIVERS], mean[RECEIVERS];
    float corner_u[4][RECEIVERS], corner_v[4][RECEIVERS], corner[4][RECEIVERS];
    uint32_t pixel_x[RECEIVERS], pixel_y[RECEIVERS];
    msmcl_filter_options filter_options;
    msmcl_shade_options options;
    msmcl_status status;
    int not_a_texel = 0, frames_differ = 0, spread = 0;
    double z_sum = 0.0, z2_sum = 0.0, rms = 0.0;

    /* An nlq64 map (shades texels, blends intensities) of the test depth; receivers over the
     * map and a margin (clamped to the edge); pixels anywhere on a 1080p screen. */
    msmcl_filter_options_init(&filter_options);
    CHECK_OK(msmcl_filter(context, depth, WIDTH, HEIGHT, SAMPLES, &filter_options, map, map_bytes));
    for (int i = 0; i < RECEIVERS; ++i) {
        u[i] = -2.0f + (WIDTH + 4) * random_unit();
        v[i] = -2.0f + (HEIGHT + 4) * random_unit();
        z[i] = random_unit();
        pixel_x[i] = (uint32_t)(1920 * random_unit());
        pixel_y[i] = (uint32_t)(1080 * random_unit());
    }

    msmcl_shade_options_init(&options);
    CHECK(options.frame == 0 && options.screen_width == 0, "dither defaults %u %u", options.frame,
          options.screen_width);

    /* The four texel centres around (u - 0.5, v - 0.5), each shaded by the nearest lookup. */
    options.lookup = MSMCL_LOOKUP_NEAREST;
    for (int k = 0; k < 4; ++k) {
        for (int i = 0; i < RECEIVERS; ++i) {
            int x0 = (int)floorf(u[i] - 0.5f), y0 = (int)floorf(v[i] - 0.5f);
            corner_u[k][i] = (float)clamp_index(x0 + (k & 1), WIDTH) + 0.5f;
            corner_v[k][i] = (float)clamp_index(y0 + (k >> 1), HEIGHT) + 0.5f;
        }
        CHECK_OK(msmcl_shade(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, corner_u[k], corner_v[k], z,
                             RECEIVERS, &options, corner[k]));
    }

    /* Each dithered result is one of those texels' shadows, bit for bit; frames differ. */
    options.lookup = MSMCL_LOOKUP_DITHER;
    options.frame = 5;
    CHECK_OK(msmcl_shade_with_pixels(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, u, v, z, pixel_x,
                                     pixel_y, RECEIVERS, &options, dither));
    for (int i = 0; i < RECEIVERS; ++i)
        not_a_texel += dither[i] != corner[0][i] && dither[i] != corner[1][i] && dither[i] != corner[2][i] &&
                       dither[i] != corner[3][i];
    CHECK(not_a_texel == 0, "%d dithered receivers are none of their texels", not_a_texel);
    options.frame = 6;
    CHECK_OK(msmcl_shade_with_pixels(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, u, v, z, pixel_x,
                                     pixel_y, RECEIVERS, &options, other));
    for (int i = 0; i < RECEIVERS; ++i) frames_differ += dither[i] != other[i];
    CHECK(frames_differ > 0, "frames 5 and 6 give the same dither");

    /* Row-major pixels: screen_width W equals explicit pixels (i % W, i / W); 0 is one row. */
    options.frame = 9;
    options.screen_width = DITHER_SCREEN_WIDTH;
    {
        uint32_t row_x[RECEIVERS], row_y[RECEIVERS];
        for (int i = 0; i < RECEIVERS; ++i) {
            row_x[i] = (uint32_t)i % DITHER_SCREEN_WIDTH;
            row_y[i] = (uint32_t)i / DITHER_SCREEN_WIDTH;
        }
        CHECK_OK(msmcl_shade(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, u, v, z, RECEIVERS, &options,
                             dither));
        CHECK_OK(msmcl_shade_with_pixels(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, u, v, z, row_x,
                                         row_y, RECEIVERS, &options, other));
        CHECK(memcmp(dither, other, sizeof dither) == 0, "screen_width differs from explicit row-major pixels");
        options.screen_width = 0;
        for (int i = 0; i < RECEIVERS; ++i) {
            row_x[i] = (uint32_t)i;
            row_y[i] = 0;
        }
        CHECK_OK(msmcl_shade(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, u, v, z, RECEIVERS, &options,
                             dither));
        CHECK_OK(msmcl_shade_with_pixels(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, u, v, z, row_x,
                                         row_y, RECEIVERS, &options, other));
        CHECK(memcmp(dither, other, sizeof dither) == 0, "screen_width 0 differs from pixels (i, 0)");
    }

    /* Device: pixel buffer, and row-major pixels, against the host path. */
    {
        float uvz[3 * RECEIVERS];
        uint32_t xy[2 * RECEIVERS];
        cl_mem map_buffer, uvz_buffer, xy_buffer, out;
        cl_int error = CL_SUCCESS;
        msmcl_enqueue enqueue;
        memcpy(uvz, u, sizeof u);
        memcpy(uvz + RECEIVERS, v, sizeof v);
        memcpy(uvz + 2 * RECEIVERS, z, sizeof z);
        memcpy(xy, pixel_x, sizeof pixel_x);
        memcpy(xy + RECEIVERS, pixel_y, sizeof pixel_y);
        map_buffer = device_only_buffer(cl, queue, map_bytes, map);
        uvz_buffer = device_only_buffer(cl, queue, sizeof uvz, uvz);
        xy_buffer = device_only_buffer(cl, queue, sizeof xy, xy);
        out = clCreateBuffer(cl, CL_MEM_READ_WRITE | CL_MEM_HOST_NO_ACCESS, sizeof dither, NULL, &error);
        CHECK(error == CL_SUCCESS, "clCreateBuffer %d", error);
        memset(&enqueue, 0, sizeof enqueue);
        enqueue.blocking = 1;

        options.frame = 12;
        options.screen_width = 0;
        CHECK_OK(msmcl_shade_with_pixels(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, u, v, z, pixel_x,
                                         pixel_y, RECEIVERS, &options, dither));
        CHECK_OK(msmcl_shade_with_pixels_device(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map_buffer, uvz_buffer,
                                                xy_buffer, RECEIVERS, out, &options, &enqueue));
        read_device_buffer(cl, queue, out, sizeof other, other);
        CHECK(memcmp(dither, other, sizeof dither) == 0, "device dither with pixels differs from the host path");

        options.screen_width = DITHER_SCREEN_WIDTH;
        CHECK_OK(msmcl_shade(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, u, v, z, RECEIVERS, &options,
                             dither));
        CHECK_OK(msmcl_shade_device(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map_buffer, uvz_buffer, RECEIVERS, out,
                                    &options, &enqueue));
        read_device_buffer(cl, queue, out, sizeof other, other);
        CHECK(memcmp(dither, other, sizeof dither) == 0, "device dither, row-major, differs from the host path");
        memset(other, 0, sizeof other);
        CHECK_OK(msmcl_shade_with_pixels_device(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map_buffer, uvz_buffer,
                                                NULL, RECEIVERS, out, &options, &enqueue));
        read_device_buffer(cl, queue, out, sizeof other, other);
        CHECK(memcmp(dither, other, sizeof dither) == 0, "device dither, NULL pixels, differs from the host path");

        clReleaseMemObject(out);
        clReleaseMemObject(xy_buffer);
        clReleaseMemObject(uvz_buffer);
        clReleaseMemObject(map_buffer);
    }

    /* The other lookups ignore pixels and frame. */
    options.lookup = MSMCL_LOOKUP_BILINEAR;
    options.frame = 0;
    options.screen_width = 0;
    CHECK_OK(msmcl_shade(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, u, v, z, RECEIVERS, &options,
                         dither));
    options.frame = 3;
    CHECK_OK(msmcl_shade_with_pixels(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, u, v, z, pixel_x,
                                     pixel_y, RECEIVERS, &options, other));
    CHECK(memcmp(dither, other, sizeof dither) == 0, "bilinear depends on pixels or frame");

    /* Over DITHER_FRAMES frames the mean is the bilinear blend sum_k w_k s_k of the shaded
     * texels: per frame texel x0 + 1 is picked with probability tx (a uniform noise level),
     * so mean - blend has variance sum_k w_k (s_k - blend)^2 / F. Standardized errors must
     * have mean ~0 and mean square ~1 (tests/dither_test.cpp runs this with 256 frames). */
    options.lookup = MSMCL_LOOKUP_DITHER;
    memset(mean, 0, sizeof mean);
    for (int f = 0; f < DITHER_FRAMES; ++f) {
        options.frame = (uint32_t)f;
        CHECK_OK(msmcl_shade_with_pixels(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, u, v, z, pixel_x,
                                         pixel_y, RECEIVERS, &options, dither));
        for (int i = 0; i < RECEIVERS; ++i) mean[i] += dither[i] / (float)DITHER_FRAMES;
    }
    for (int i = 0; i < RECEIVERS; ++i) {
        float fx = u[i] - 0.5f < -1.0f ? -1.0f : u[i] - 0.5f > WIDTH ? (float)WIDTH : u[i] - 0.5f;
        float fy = v[i] - 0.5f < -1.0f ? -1.0f : v[i] - 0.5f > HEIGHT ? (float)HEIGHT : v[i] - 0.5f;
        double tx = fx - floorf(fx), ty = fy - floorf(fy);
        double w[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
        double blend = 0.0, variance = 0.0, error;
        for (int k = 0; k < 4; ++k) blend += w[k] * corner[k][i];
        for (int k = 0; k < 4; ++k) variance += w[k] * (corner[k][i] - blend) * (corner[k][i] - blend);
        error = mean[i] - blend;
        rms += error * error / RECEIVERS;
        if (variance < 1e-6) continue; /* the four texels (nearly) alike: nothing to average */
        z_sum += error / sqrt(variance / DITHER_FRAMES);
        z2_sum += error * error / (variance / DITHER_FRAMES);
        ++spread;
    }
    printf("capi_test: dither over %d frames vs bilinear blend: rms %.4f; %d receivers with spread, standardized "
           "mean %.3f, mean square %.3f\n",
           DITHER_FRAMES, sqrt(rms), spread, spread ? z_sum / spread : 0.0, spread ? z2_sum / spread : 0.0);
    CHECK(spread >= RECEIVERS / 3, "only %d receivers with spread", spread);
    if (spread > 0) {
        /* Over n >= 200 receivers the mean of z has sd <= 0.07 and the mean square sd ~0.1
         * for unbiased picks (seeds 1-5: |mean| <= 0.07, mean square 0.97-1.08); a pick
         * shifted by half a texel, or frames that repeat the noise, fail by far. */
        CHECK(fabs(z_sum / spread) < 0.3, "standardized mean %.3f", z_sum / spread);
        CHECK(z2_sum / spread > 0.6 && z2_sum / spread < 1.6, "standardized mean square %.3f", z2_sum / spread);
    }

    /* Errors: an unknown lookup and a lone pixel array are argument errors. */
    options.lookup = (msmcl_lookup)3;
    status = msmcl_shade(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, u, v, z, RECEIVERS, &options,
                         dither);
    CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT && strstr(msmcl_last_error_message(), "unknown lookup 3"), "%s: %s",
          msmcl_status_name(status), msmcl_last_error_message());
    status = msmcl_shade_with_pixels_device(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, NULL, NULL, NULL, 1, NULL,
                                            &options, NULL);
    CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT && strstr(msmcl_last_error_message(), "unknown lookup"), "%s: %s",
          msmcl_status_name(status), msmcl_last_error_message());
    options.lookup = MSMCL_LOOKUP_DITHER;
    status = msmcl_shade_with_pixels(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, u, v, z, pixel_x, NULL,
                                     RECEIVERS, &options, dither);
    CHECK(status == MSMCL_ERROR_INVALID_ARGUMENT && strstr(msmcl_last_error_message(), "pixel_y"), "%s: %s",
          msmcl_status_name(status), msmcl_last_error_message());
    u[17] = NAN;
    status = msmcl_shade_with_pixels(context, MSMCL_FORMAT_NLQ64, WIDTH, HEIGHT, map, map_bytes, u, v, z, pixel_x,
                                     pixel_y, RECEIVERS, &options, dither);
    CHECK(status == MSMCL_ERROR_INPUT && strstr(msmcl_last_error_message(), "receiver 17"), "%s: %s",
          msmcl_status_name(status), msmcl_last_error_message());
    free(map);
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
        test_soft(context, depth);
        test_translucent_filter(context, depth);
        test_translucent_sat(context, depth);
        test_dither(context, depth);
        CHECK_OK(msmcl_context_finish(context));
        msmcl_context_destroy(context);
    }
    free(depth);
    printf("%d passed, %d failed\n", checks_passed, checks_failed);
    return checks_failed == 0 ? 0 : 1;
}
