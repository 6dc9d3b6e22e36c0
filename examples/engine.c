/* msmcl from C (include/msmcl/msmcl.h): filter a small depth map into an nlq32 moment shadow
 * map and evaluate two receivers on the host; then, with the data in device buffers as an
 * engine holds it, build a summed-area table and shade the same receivers with moment soft
 * shadows. Exits 0 when the receiver outside the occluder's shadow is lit and the one inside
 * is shadowed, both times. */
#include <msmcl/msmcl.h>

#include <stdio.h>

enum { SIZE = 64 };

static int failed(msmcl_status status) {
    if (status == MSMCL_SUCCESS) return 0;
    fprintf(stderr, "example_c: %s: %s\n", msmcl_status_name(status), msmcl_last_error_message());
    return 1;
}

/* Soft shadows on the device: the depth map and receivers in buffers, the table and the
 * intensities written into buffers, one blocking read at the end. */
static int soft_shadows_on_device(msmcl_context* context, const float* depth, const float* uvz, float* intensity) {
    cl_context cl = msmcl_context_cl_context(context);
    cl_int error = CL_SUCCESS;
    cl_mem depth_buffer = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, SIZE * SIZE * sizeof(float),
                                         (void*)depth, &error);
    cl_mem receivers = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, 6 * sizeof(float), (void*)uvz,
                                      &error);
    cl_mem table = clCreateBuffer(cl, CL_MEM_READ_WRITE, 16 * SIZE * SIZE, NULL, &error);
    cl_mem out = clCreateBuffer(cl, CL_MEM_WRITE_ONLY, 2 * sizeof(float), NULL, &error);
    msmcl_device_depth device_depth = {NULL, SIZE, SIZE, 1, MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE};
    msmcl_sat_options sat;
    msmcl_soft_options soft;
    int result = 1;
    device_depth.memory = depth_buffer;
    msmcl_sat_options_init(&sat);
    msmcl_soft_options_init(&soft);
    soft.light_size = 8.0f; /* penumbrae narrower than the box */
    if (depth_buffer && receivers && table && out && !failed(msmcl_build_sat_device(context, &device_depth, table, &sat, NULL)) &&
        !failed(msmcl_soft_shade_device(context, table, SIZE, SIZE, sat.max_kernel_texels, receivers, 2, out, &soft,
                                        NULL)))
        result = clEnqueueReadBuffer(msmcl_context_cl_queue(context), out, CL_TRUE, 0, 2 * sizeof(float), intensity,
                                     0, NULL, NULL) != CL_SUCCESS;
    /* clCreateBuffer returns NULL when it fails: release what exists. */
    if (out) clReleaseMemObject(out);
    if (table) clReleaseMemObject(table);
    if (receivers) clReleaseMemObject(receivers);
    if (depth_buffer) clReleaseMemObject(depth_buffer);
    return result;
}

int main(void) {
    static float depth[SIZE * SIZE];
    static unsigned int map[SIZE * SIZE];
    const float u[2] = {8.0f, 32.0f}, v[2] = {8.0f, 32.0f}, z[2] = {0.8f, 0.8f};
    const float uvz[6] = {8.0f, 32.0f, 8.0f, 32.0f, 0.8f, 0.8f}; /* planar: all u, all v, all z */
    float intensity[2] = {-1.0f, -1.0f}, soft[2] = {-1.0f, -1.0f};
    msmcl_context* context = NULL;
    msmcl_filter_options options;
    int x, y, ok;

    /* A floor at depth 0.8 and a box at 0.3 over texels 24..39. */
    for (y = 0; y < SIZE; ++y)
        for (x = 0; x < SIZE; ++x) depth[y * SIZE + x] = (x >= 24 && x < 40 && y >= 24 && y < 40) ? 0.3f : 0.8f;

    if (failed(msmcl_context_create(NULL, &context))) return 1;
    msmcl_filter_options_init(&options);
    options.format = MSMCL_FORMAT_NLQ32;
    if (failed(msmcl_filter(context, depth, SIZE, SIZE, 1, &options, map, sizeof map)) ||
        failed(msmcl_shade(context, MSMCL_FORMAT_NLQ32, SIZE, SIZE, map, sizeof map, u, v, z, 2, NULL, intensity)) ||
        soft_shadows_on_device(context, depth, uvz, soft)) {
        msmcl_context_destroy(context);
        return 1;
    }
    printf("example_c: msmcl %s on %s, lit %.3f, shadowed %.3f; soft: lit %.3f, shadowed %.3f\n",
           msmcl_version_string(), msmcl_context_device_name(context), intensity[0], intensity[1], soft[0], soft[1]);
    msmcl_context_destroy(context);
    ok = intensity[0] < 0.05f && intensity[1] > 0.95f && soft[0] < 0.05f && soft[1] > 0.95f;
    printf("example_c: %s\n", ok ? "ok" : "unexpected intensities");
    return ok ? 0 : 1;
}
