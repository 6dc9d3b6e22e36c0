/* msmcl from C (include/msmcl/msmcl.h): filter a small depth map into an nlq32 moment shadow
 * map and evaluate two receivers. Exits 0 when the receiver outside the occluder's shadow is
 * lit and the one inside is shadowed. */
#include <msmcl/msmcl.h>

#include <stdio.h>

enum { SIZE = 64 };

static int failed(msmcl_status status) {
    if (status == MSMCL_SUCCESS) return 0;
    fprintf(stderr, "example_c: %s: %s\n", msmcl_status_name(status), msmcl_last_error_message());
    return 1;
}

int main(void) {
    static float depth[SIZE * SIZE];
    static unsigned int map[SIZE * SIZE];
    const float u[2] = {8.0f, 32.0f}, v[2] = {8.0f, 32.0f}, z[2] = {0.8f, 0.8f};
    float intensity[2] = {-1.0f, -1.0f};
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
        failed(msmcl_shade(context, MSMCL_FORMAT_NLQ32, SIZE, SIZE, map, sizeof map, u, v, z, 2, NULL, intensity))) {
        msmcl_context_destroy(context);
        return 1;
    }
    printf("example_c: msmcl %s on %s, lit %.3f, shadowed %.3f\n", msmcl_version_string(),
           msmcl_context_device_name(context), intensity[0], intensity[1]);
    msmcl_context_destroy(context);
    ok = intensity[0] < 0.05f && intensity[1] > 0.95f;
    printf("example_c: %s\n", ok ? "ok" : "unexpected intensities");
    return ok ? 0 : 1;
}
