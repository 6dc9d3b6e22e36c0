/* msmcl C API: the C++ API (msmcl.hpp) for engines written in C or bound from other
 * languages. Opaque context handle, plain structs, status codes; no exception crosses it.
 *
 * Errors: every function returning msmcl_status returns MSMCL_SUCCESS or an error code.
 * After an error, msmcl_last_error_message() reads what went wrong (one line, or the
 * OpenCL build log for MSMCL_ERROR_BUILD) and msmcl_last_opencl_error() the cl_int of a
 * failed OpenCL call. Both are per thread, reset by each call that returns a status, and
 * valid until the next such call on the same thread.
 *
 * Versions: before 1.0 every 0.x minor version may break the ABI (SONAME libmsmcl.so.0.1).
 * The option structs grew in 0.1 (msmcl_shade_options: frame, screen_width, then
 * min_variance, light_bleed_reduction, exponent_positive, exponent_negative;
 * msmcl_sat_options: kernel); new fields
 * only ever go at the end, so callers that fill a struct with its *_init function and
 * then set fields stay source compatible, but must be rebuilt.
 *
 * Threads: any number of threads may share a context and call operations on it at once
 * (as msmcl::Context, context.hpp); destroying it while another thread uses it is not safe.
 * Memory: the library never keeps the caller's pointers past a call; it retains the
 * OpenCL objects of msmcl_context_create_from_cl and releases only what it retained.
 *
 * Layouts (as the C++ API):
 *  - host depth maps: float depth[(y * width + x) * samples + s], rows top to bottom;
 *  - textures: row-major, msmcl_texel_bytes(format) bytes per texel, little-endian:
 *    moments128 = 4 floats b1..b4; msm64/nlq64 = 4 uint16 codes (R, G, B, A);
 *    nlq32 = 1 uint32;
 *  - summed-area tables: 4 uint32 per texel (R, G, B, A);
 *  - device receivers: 3 * count floats, planar (all u, all v, all z);
 *  - translucent layers: per layer a depth and an opacity array, each as the depth map
 *    (host: one array per layer; device: the layers one after the other in one buffer);
 *  - receivers' screen pixels (dither): host: two arrays x, y of count uint32; device:
 *    2 * count uint32, planar (all x, all y).
 */
#ifndef MSMCL_MSMCL_H
#define MSMCL_MSMCL_H

#include <CL/cl.h>

#include <stddef.h>
#include <stdint.h>

#if defined(_WIN32)
#define MSMCL_C_API
#else
#define MSMCL_C_API __attribute__((visibility("default")))
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Status codes */

typedef enum msmcl_status {
    MSMCL_SUCCESS = 0,
    MSMCL_ERROR_INVALID_ARGUMENT = 1, /* null handle or pointer, unknown enum value, output too small */
    MSMCL_ERROR_INPUT = 2,            /* unusable data: bad size, NaN depth, wrong image format... */
    MSMCL_ERROR_OPENCL = 3,           /* an OpenCL call failed: see msmcl_last_opencl_error() */
    MSMCL_ERROR_BUILD = 4,            /* a kernel did not build: the message holds the build log */
    MSMCL_ERROR_DEVICE = 5,           /* no OpenCL device matches, or the device cannot run a kernel */
    MSMCL_ERROR_OUT_OF_MEMORY = 6,    /* host allocation failed */
    MSMCL_ERROR_INTERNAL = 7          /* anything else */
} msmcl_status;

/* "MSMCL_SUCCESS", "MSMCL_ERROR_INPUT", ...; "MSMCL_UNKNOWN_STATUS" for other values. */
MSMCL_C_API const char* msmcl_status_name(msmcl_status status);
/* The message of the last failed call on this thread ("" after a success). */
MSMCL_C_API const char* msmcl_last_error_message(void);
/* The cl_int of the last failed OpenCL call on this thread (CL_SUCCESS if none). */
MSMCL_C_API cl_int msmcl_last_opencl_error(void);

/* "0.1.0", and its parts. Any pointer may be null. */
MSMCL_C_API const char* msmcl_version_string(void);
MSMCL_C_API void msmcl_version(int* major, int* minor, int* patch);

/* ---- Enumerations (the order of the C++ enums) */

typedef enum msmcl_format {
    MSMCL_FORMAT_MOMENTS128 = 0, /* 16 bytes: float b1..b4;            CL_RGBA/CL_FLOAT */
    MSMCL_FORMAT_MSM64 = 1,      /* 8 bytes: unorm16 affine basis;      CL_RGBA/CL_UNORM_INT16 */
    MSMCL_FORMAT_NLQ64 = 2,      /* 8 bytes: unorm16 y1, y2, v2, Psi4;  CL_RGBA/CL_UNORM_INT16 */
    MSMCL_FORMAT_NLQ32 = 3,      /* 4 bytes: packed uint32;             CL_R/CL_UNSIGNED_INT32 */
    /* The other filterable representations (docs/formats.md, "Filterable representations"). */
    MSMCL_FORMAT_VSM32 = 4,      /* 4 bytes: unorm16 t, t^2;             CL_RG/CL_UNORM_INT16 */
    MSMCL_FORMAT_VSM64 = 5,      /* 8 bytes: float t, t^2;               CL_RG/CL_FLOAT */
    MSMCL_FORMAT_EVSM2_32 = 6,   /* 4 bytes: half p, p^2;                CL_RG/CL_HALF_FLOAT */
    MSMCL_FORMAT_EVSM4_64 = 7,   /* 8 bytes: half p, p^2, n, n^2;        CL_RGBA/CL_HALF_FLOAT */
    MSMCL_FORMAT_EVSM4_128 = 8,  /* 16 bytes: float p, p^2, n, n^2;      CL_RGBA/CL_FLOAT */
    MSMCL_FORMAT_ESM32 = 9       /* 4 bytes: float exp(c (t - 1));       CL_R/CL_FLOAT */
} msmcl_format;

typedef enum msmcl_depth_range {
    MSMCL_DEPTH_RANGE_ZERO_ONE = 0,     /* d in [0,1] (D3D, Vulkan) */
    MSMCL_DEPTH_RANGE_MINUS_ONE_ONE = 1 /* d in [-1,1] (OpenGL) */
} msmcl_depth_range;

typedef enum msmcl_filter_kernel {
    MSMCL_FILTER_KERNEL_AUTOMATIC = 0,
    MSMCL_FILTER_KERNEL_FUSED_PAPER = 1,
    MSMCL_FILTER_KERNEL_THREE_PASS = 2,
    MSMCL_FILTER_KERNEL_FUSED_CPU = 3
} msmcl_filter_kernel;

typedef enum msmcl_lookup {
    MSMCL_LOOKUP_NEAREST = 0,  /* texel floor(u), floor(v) */
    MSMCL_LOOKUP_BILINEAR = 1, /* between the texel centres around (u - 0.5, v - 0.5) */
    MSMCL_LOOKUP_DITHER = 2    /* one texel floor(u - 0.5 + nx), floor(v - 0.5 + ny), blue noise (nx, ny)
                                  of the receiver's screen pixel and the frame; averaged over
                                  frames, the bilinear blend of the shaded texels (since 0.1) */
} msmcl_lookup;

/* How the samples of a depth image lie (include/msmcl/interop.hpp, SampleLayout). */
typedef enum msmcl_sample_layout {
    MSMCL_SAMPLE_LAYOUT_SIDE_BY_SIDE = 0, /* 2D image (width * samples) x height */
    MSMCL_SAMPLE_LAYOUT_LAYERS = 1        /* 2D image array, layer s = sample s */
} msmcl_sample_layout;

/* Bytes per texel of a format (16, 8, 8, 4); 0 for an unknown value. */
MSMCL_C_API size_t msmcl_texel_bytes(msmcl_format format);
/* "moments128", "msm64", "nlq64", "nlq32", "vsm32", "vsm64", "evsm2_32", "evsm4_64",
 * "evsm4_128", "esm32"; NULL for an unknown value. */
MSMCL_C_API const char* msmcl_format_name(msmcl_format format);
/* Inverse of msmcl_format_name: MSMCL_ERROR_INVALID_ARGUMENT for an unknown name. */
MSMCL_C_API msmcl_status msmcl_parse_format(const char* name, msmcl_format* format);
/* The natural image format of a texture, and of a summed-area table (CL_RGBA/CL_UNSIGNED_INT32). */
MSMCL_C_API msmcl_status msmcl_texture_image_format(msmcl_format format, cl_image_format* image_format);
MSMCL_C_API cl_image_format msmcl_sat_image_format(void);

/* ---- Context */

typedef struct msmcl_context msmcl_context;

typedef struct msmcl_context_options {
    const char* device;   /* "gpu", "cpu", an index, "P:D" or a name substring; NULL = not given */
    const char* platform; /* a platform index or name substring; NULL = not given */
    int strict;           /* nonzero: a spec that matches nothing is an error, not a fallback */
    int use_environment;  /* nonzero: MSMCL_DEVICE / MSMCL_PLATFORM apply when no spec is given */
} msmcl_context_options;

/* Defaults: no specs, not strict, environment used. */
MSMCL_C_API void msmcl_context_options_init(msmcl_context_options* options);
/* Picks a device and creates its context and queue. `options` may be NULL (defaults). */
MSMCL_C_API msmcl_status msmcl_context_create(const msmcl_context_options* options, msmcl_context** context);
/* Works inside an engine's OpenCL context; `queue` may be NULL (msmcl creates one). */
MSMCL_C_API msmcl_status msmcl_context_create_from_cl(cl_context opencl_context, cl_device_id device,
                                                      cl_command_queue queue, msmcl_context** context);
/* Releases the context (NULL is ignored). */
MSMCL_C_API void msmcl_context_destroy(msmcl_context* context);

/* The OpenCL objects (owned by the context: retain them to keep them longer); NULL for a NULL context. */
MSMCL_C_API cl_context msmcl_context_cl_context(const msmcl_context* context);
MSMCL_C_API cl_device_id msmcl_context_cl_device(const msmcl_context* context);
MSMCL_C_API cl_command_queue msmcl_context_cl_queue(const msmcl_context* context);
/* The device's name, valid as long as the context; "" for a NULL context. */
MSMCL_C_API const char* msmcl_context_device_name(const msmcl_context* context);
/* Blocks until the context's own queue is idle. */
MSMCL_C_API msmcl_status msmcl_context_finish(msmcl_context* context);
/* Directory of the on-disk program binary cache; NULL or "" disables it. */
MSMCL_C_API msmcl_status msmcl_context_set_binary_cache_dir(msmcl_context* context, const char* directory);
/* Programs built (not found in a cache) since the context was created. */
MSMCL_C_API size_t msmcl_context_programs_built(const msmcl_context* context);

/* ---- Command plumbing of the device calls (include/msmcl/enqueue.hpp).
 * queue NULL = the context's queue. The call waits for `wait_for` (wait_count events);
 * if `done` is non-NULL it receives a new event of the call's last command, which the
 * caller releases. Nothing blocks unless `blocking` is nonzero. A NULL msmcl_enqueue
 * pointer means all of these defaults. */
typedef struct msmcl_enqueue {
    cl_command_queue queue;
    const cl_event* wait_for;
    cl_uint wait_count;
    cl_event* done;
    int blocking;
} msmcl_enqueue;

/* ---- Filter: depth map -> moment shadow map */

typedef struct msmcl_filter_options {
    msmcl_format format;           /* default MSMCL_FORMAT_NLQ64 */
    float sigma;                   /* Gaussian sigma in texels, default 2.4; 0 = no blur */
    msmcl_depth_range depth_range; /* default MSMCL_DEPTH_RANGE_ZERO_ONE */
    msmcl_filter_kernel kernel;    /* default MSMCL_FILTER_KERNEL_AUTOMATIC */
    /* EVSM's c+ and c-, ESM's c (in exponent_positive); default 0 = the format's default;
     * only for the formats with a warp (include/msmcl/formats.hpp, effective_exponents). */
    float exponent_positive;
    float exponent_negative;
} msmcl_filter_options;

MSMCL_C_API void msmcl_filter_options_init(msmcl_filter_options* options);

/* Host depth map in, host texture out: `texture` receives width * height *
 * msmcl_texel_bytes(format) bytes (texture_bytes must be at least that). Depths are
 * validated (MSMCL_ERROR_INPUT names the first bad texel). `options` may be NULL. */
MSMCL_C_API msmcl_status msmcl_filter(msmcl_context* context, const float* depth, int width, int height,
                                      int samples, const msmcl_filter_options* options, void* texture,
                                      size_t texture_bytes);

/* A depth map on the device. `memory` is either
 *  - a buffer of width * height * samples floats, texel-major (as the host layout), or
 *  - a 2D image or 2D image array, CL_R or CL_DEPTH / CL_FLOAT, samples as `layout` says.
 * Values are not validated on the device (out of range clamps, NaN = near plane). */
typedef struct msmcl_device_depth {
    cl_mem memory;
    int width;
    int height;
    int samples;
    msmcl_sample_layout layout; /* images only */
} msmcl_device_depth;

/* Device depth in, device texture out, no host copy. `texture` is either a buffer of at
 * least width * height * msmcl_texel_bytes(format) bytes (layout as the host texture), or
 * a 2D image of at least width x height of msmcl_texture_image_format(format) (for msm64
 * and nlq64 also CL_RGBA/CL_UNSIGNED_INT16). `options` and `enqueue` may be NULL. */
MSMCL_C_API msmcl_status msmcl_filter_device(msmcl_context* context, const msmcl_device_depth* depth,
                                             cl_mem texture, const msmcl_filter_options* options,
                                             const msmcl_enqueue* enqueue);

/* ---- Translucent occluders (docs/math.md; include/msmcl/filter.hpp, TranslucentLayer) */

/* Most translucent layers one call composites. */
#define MSMCL_MAX_TRANSLUCENT_LAYERS 8

/* A translucent layer over a host depth map: `depth` (as rendered, in the map's depth
 * range) and `opacity` (in [0, 1]; 0 where the layer has no surface) each hold width *
 * height * samples floats laid out as the depth map. Per sample, the opaque surface
 * (opacity 1) and the layers are alpha-blended nearest first, whatever the order of the
 * layers: the texel stores the moments of sum_i prod_{j<i} (1 - a_j) a_i b(z_i). Neither
 * pointer may be NULL; the library copies both during the call. */
typedef struct msmcl_translucent_layer {
    const float* depth;
    const float* opacity;
} msmcl_translucent_layer;

/* msmcl_filter with `layer_count` translucent layers (at most MSMCL_MAX_TRANSLUCENT_LAYERS,
 * more is MSMCL_ERROR_INPUT). `layers` may be NULL only when layer_count is 0 (then the
 * result is msmcl_filter's); layers of opacity 0 give the same bits as none. Every layer
 * value is validated (MSMCL_ERROR_INPUT names the first bad layer, texel and sample).
 * `options` may be NULL. */
MSMCL_C_API msmcl_status msmcl_filter_layered(msmcl_context* context, const float* depth, int width, int height,
                                              int samples, const msmcl_translucent_layer* layers, size_t layer_count,
                                              const msmcl_filter_options* options, void* texture,
                                              size_t texture_bytes);

/* Translucent layers on the device (include/msmcl/filter.hpp, DeviceLayers): buffers
 * `depth` and `opacity` each hold count * width * height * samples floats, layer after
 * layer, each layer laid out as a depth buffer. count 0: no layers (the buffers may be NULL). */
typedef struct msmcl_device_layers {
    cl_mem depth;
    cl_mem opacity;
    int count;
} msmcl_device_layers;

/* msmcl_filter_device with translucent layers. With layers, `depth->memory` and `texture`
 * must be buffers (an image is MSMCL_ERROR_INPUT); `layers` NULL or count 0 is exactly
 * msmcl_filter_device (images allowed). Values are not validated on the device: depths
 * clamp to the range (NaN = near plane), opacities clamp to [0, 1] (NaN = 0). `layers`,
 * `options` and `enqueue` may be NULL. */
MSMCL_C_API msmcl_status msmcl_filter_layered_device(msmcl_context* context, const msmcl_device_depth* depth,
                                                     const msmcl_device_layers* layers, cl_mem texture,
                                                     const msmcl_filter_options* options,
                                                     const msmcl_enqueue* enqueue);

/* ---- Shade: shadow intensity (0 lit, 1 shadowed) of receivers */

typedef struct msmcl_shade_options {
    msmcl_lookup lookup;           /* default MSMCL_LOOKUP_BILINEAR */
    float depth_bias;              /* subtracted from the receiver's internal depth; default 1e-3 */
    msmcl_depth_range depth_range; /* convention of the receivers' z; default zero_one */
    /* Since 0.1; read by MSMCL_LOOKUP_DITHER only. */
    uint32_t frame;        /* the frame number: its hash picks the blue-noise texture and shift; default 0 */
    uint32_t screen_width; /* receivers without pixels: receiver i is pixel (i % screen_width,
                              i / screen_width) of a row-major image; 0 = one row (pixel (i, 0)); default 0 */
    /* VSM and EVSM maps only (docs/math.md, "Shading VSM, EVSM and ESM"). */
    float min_variance;          /* least variance of the depth in [0,1], in [0, 0.25]; negative
                                    (the default, -1) = the format's (docs/formats.md) */
    float light_bleed_reduction; /* R in [0, 1): the bound rescaled from [R,1] to [0,1]; default 0 */
    /* EVSM and ESM maps: the exponents the texture was made with (EVSM's c+ and c-,
     * ESM's c in exponent_positive; as msmcl_filter_options); default 0 = the format's default. */
    float exponent_positive;
    float exponent_negative;
} msmcl_shade_options;

MSMCL_C_API void msmcl_shade_options_init(msmcl_shade_options* options);

/* Host texture and receivers in, host intensities out (count floats). u, v in texels of
 * the map, z as rendered. `options` may be NULL. */
MSMCL_C_API msmcl_status msmcl_shade(msmcl_context* context, msmcl_format format, int width, int height,
                                     const void* texture, size_t texture_bytes, const float* u, const float* v,
                                     const float* z, size_t count, const msmcl_shade_options* options,
                                     float* intensity);

/* Device version: `texture` a buffer (layout as the host texture), `receivers_uvz` 3 *
 * count floats planar, `intensity` count floats. */
MSMCL_C_API msmcl_status msmcl_shade_device(msmcl_context* context, msmcl_format format, int width, int height,
                                            cl_mem texture, cl_mem receivers_uvz, size_t count, cl_mem intensity,
                                            const msmcl_shade_options* options, const msmcl_enqueue* enqueue);

/* msmcl_shade with the receivers' screen pixels, which the dithered lookup indexes the blue
 * noise by (the other lookups ignore them): `pixel_x`, `pixel_y` count uint32 each, or both
 * NULL (receivers are the pixels of a row-major image, see screen_width; one NULL alone is
 * MSMCL_ERROR_INVALID_ARGUMENT). `options` may be NULL. */
MSMCL_C_API msmcl_status msmcl_shade_with_pixels(msmcl_context* context, msmcl_format format, int width, int height,
                                                 const void* texture, size_t texture_bytes, const float* u,
                                                 const float* v, const float* z, const uint32_t* pixel_x,
                                                 const uint32_t* pixel_y, size_t count,
                                                 const msmcl_shade_options* options, float* intensity);

/* Device version: `receiver_pixels` a buffer of 2 * count uint32, planar (all x, all y), or
 * NULL (row-major, see screen_width); the rest as msmcl_shade_device. `options` and
 * `enqueue` may be NULL. */
MSMCL_C_API msmcl_status msmcl_shade_with_pixels_device(msmcl_context* context, msmcl_format format, int width,
                                                        int height, cl_mem texture, cl_mem receivers_uvz,
                                                        cl_mem receiver_pixels, size_t count, cl_mem intensity,
                                                        const msmcl_shade_options* options,
                                                        const msmcl_enqueue* enqueue);

/* ---- Summed-area tables of moments (soft shadows; include/msmcl/sat.hpp) */

/* Which kernels build a table (include/msmcl/sat.hpp, SatKernel); all give the same bits. */
typedef enum msmcl_sat_kernel {
    MSMCL_SAT_KERNEL_AUTOMATIC = 0,     /* tiled GPU scan on GPUs, the CPU band scan elsewhere */
    MSMCL_SAT_KERNEL_TILED_GPU = 1,     /* 32x32 tiles in local memory */
    MSMCL_SAT_KERNEL_TILED_CPU = 2,     /* bands of 32 rows in 16-lane vectors */
    MSMCL_SAT_KERNEL_ROW_PER_THREAD = 3 /* the papers' baseline: one work-item per row, then per column */
} msmcl_sat_kernel;

typedef struct msmcl_sat_options {
    uint32_t max_kernel_texels;    /* N: texels of the largest rectangle ever queried; default 27 * 27 */
    msmcl_depth_range depth_range; /* default zero_one */
    msmcl_sat_kernel kernel;       /* since 0.1; default MSMCL_SAT_KERNEL_AUTOMATIC */
} msmcl_sat_options;

MSMCL_C_API void msmcl_sat_options_init(msmcl_sat_options* options);
/* floor((2^32 - 1) / N), the integer scale of the table's channels. */
MSMCL_C_API msmcl_status msmcl_sat_scale(uint32_t max_kernel_texels, uint32_t* scale);

/* Host depth map in, host table out: `table` receives 4 * width * height uint32
 * (table_words at least that). `options` may be NULL. */
MSMCL_C_API msmcl_status msmcl_build_sat(msmcl_context* context, const float* depth, int width, int height,
                                         int samples, const msmcl_sat_options* options, uint32_t* table,
                                         size_t table_words);

/* Device depth in, device table out: `table` a buffer of at least 16 * width * height
 * bytes, or a 2D image of CL_RGBA/CL_UNSIGNED_INT32 of at least width x height. */
MSMCL_C_API msmcl_status msmcl_build_sat_device(msmcl_context* context, const msmcl_device_depth* depth,
                                                cl_mem table, const msmcl_sat_options* options,
                                                const msmcl_enqueue* enqueue);

/* The table of a translucent shadow map: each sample's surfaces composited as
 * msmcl_filter_layered composites them, the texel the mean over its samples. `layers` and
 * `layer_count` as for msmcl_filter_layered (NULL only with count 0: msmcl_build_sat's
 * bits; layers of opacity 0 give the same bits as none). `options` may be NULL. */
MSMCL_C_API msmcl_status msmcl_build_sat_layered(msmcl_context* context, const float* depth, int width, int height,
                                                 int samples, const msmcl_translucent_layer* layers,
                                                 size_t layer_count, const msmcl_sat_options* options,
                                                 uint32_t* table, size_t table_words);

/* Device version: with layers, `depth->memory` and `table` must be buffers (an image is
 * MSMCL_ERROR_INPUT); `layers` NULL or count 0 is exactly msmcl_build_sat_device. Values
 * are not validated on the device (as msmcl_filter_layered_device). `layers`, `options`
 * and `enqueue` may be NULL. */
MSMCL_C_API msmcl_status msmcl_build_sat_layered_device(msmcl_context* context, const msmcl_device_depth* depth,
                                                        const msmcl_device_layers* layers, cl_mem table,
                                                        const msmcl_sat_options* options,
                                                        const msmcl_enqueue* enqueue);

/* Moment soft shadows of a directional light from a table (include/msmcl/sat.hpp,
 * SoftShadowOptions; docs/soft_shadows.md). */
typedef struct msmcl_soft_options {
    float light_size;              /* penumbra texels per unit of internal depth; default 64 */
    int search_size;               /* blocker search side, K^2 <= N; 0 = floor(sqrt(N)); default 0 */
    float min_filter_size;         /* smallest filter side in texels; default 1 */
    float depth_bias;              /* subtracted from the receiver's internal depth; default 1e-3 */
    msmcl_depth_range depth_range; /* convention of the receivers' z; default zero_one */
    /* The refinements of docs/soft_shadows.md; 0 and 1 give the method as published. */
    float receiver_blocker_weight; /* in [0, 1]; default 0.1 */
    int filter_parts;              /* filter square split into P x P parts, P in [1, 4]; default 2 */
} msmcl_soft_options;

MSMCL_C_API void msmcl_soft_options_init(msmcl_soft_options* options);

/* Host table (4 * width * height uint32, as msmcl_build_sat writes it for N =
 * max_kernel_texels) and receivers in, host intensities out (count floats; 0 lit, 1
 * shadowed). u, v in texels, z as rendered. `options` may be NULL. */
MSMCL_C_API msmcl_status msmcl_soft_shade(msmcl_context* context, const uint32_t* table, int width, int height,
                                          uint32_t max_kernel_texels, const float* u, const float* v, const float* z,
                                          size_t count, const msmcl_soft_options* options, float* intensity);

/* Device version: `table` a buffer or image as msmcl_build_sat_device writes it for N =
 * max_kernel_texels, the rest as msmcl_shade_device. `options` and `enqueue` may be NULL. */
MSMCL_C_API msmcl_status msmcl_soft_shade_device(msmcl_context* context, cl_mem table, int width, int height,
                                                 uint32_t max_kernel_texels, cl_mem receivers_uvz, size_t count,
                                                 cl_mem intensity, const msmcl_soft_options* options,
                                                 const msmcl_enqueue* enqueue);

/* ---- Texture arrays: `layers` maps of one size in one call (the cascades of a cascaded
 * shadow map, the maps of several lights; docs/formats.md, "Texture arrays"). Every
 * buffer holds layer after layer, each laid out as for one map; the result equals
 * `layers` single-map calls bit for bit. */

/* Most array layers one call takes. */
#define MSMCL_MAX_ARRAY_LAYERS 2048

/* msmcl_filter of `layers` depth maps: `depth` holds layers * width * height * samples
 * floats, `texture` receives layers * width * height * msmcl_texel_bytes(format) bytes. */
MSMCL_C_API msmcl_status msmcl_filter_array(msmcl_context* context, const float* depth, int width, int height,
                                            int samples, int layers, const msmcl_filter_options* options,
                                            void* texture, size_t texture_bytes);
/* Device version, one launch for all layers. `depth->memory` is a buffer (layer after
 * layer) or a 2D image array: map a in array layer a (side by side), or sample s of map a
 * in array layer a * samples + s (MSMCL_SAMPLE_LAYOUT_LAYERS); `texture` a buffer or a 2D
 * image array of at least `layers` layers. `options` and `enqueue` may be NULL. */
MSMCL_C_API msmcl_status msmcl_filter_array_device(msmcl_context* context, const msmcl_device_depth* depth,
                                                   int layers, cl_mem texture, const msmcl_filter_options* options,
                                                   const msmcl_enqueue* enqueue);
/* msmcl_build_sat of `layers` depth maps: `table` receives 4 * layers * width * height uint32. */
MSMCL_C_API msmcl_status msmcl_build_sat_array(msmcl_context* context, const float* depth, int width, int height,
                                               int samples, int layers, const msmcl_sat_options* options,
                                               uint32_t* table, size_t table_words);
/* Device version: buffers or image arrays, as msmcl_filter_array_device. */
MSMCL_C_API msmcl_status msmcl_build_sat_array_device(msmcl_context* context, const msmcl_device_depth* depth,
                                                      int layers, cl_mem table, const msmcl_sat_options* options,
                                                      const msmcl_enqueue* enqueue);
/* msmcl_filter_array under translucent layers (as msmcl_filter_layered), each layer's `depth`
 * and `opacity` laid out as `depth`, all array layers. `options` may be NULL. */
MSMCL_C_API msmcl_status msmcl_filter_array_layered(msmcl_context* context, const float* depth, int width,
                                                    int height, int samples, int layers,
                                                    const msmcl_translucent_layer* translucent,
                                                    size_t layer_count, const msmcl_filter_options* options,
                                                    void* texture, size_t texture_bytes);
/* Device version, buffers only: translucent layer k of array layer a at a * count + k in the
 * layer buffers. `translucent` NULL or count 0 is msmcl_filter_array_device. */
MSMCL_C_API msmcl_status msmcl_filter_array_layered_device(msmcl_context* context, const msmcl_device_depth* depth,
                                                           int layers, const msmcl_device_layers* translucent,
                                                           cl_mem texture, const msmcl_filter_options* options,
                                                           const msmcl_enqueue* enqueue);
/* msmcl_build_sat_array with translucent layers, laid out as for msmcl_filter_array_layered. */
MSMCL_C_API msmcl_status msmcl_build_sat_array_layered(msmcl_context* context, const float* depth, int width,
                                                       int height, int samples, int layers,
                                                       const msmcl_translucent_layer* translucent,
                                                       size_t layer_count, const msmcl_sat_options* options,
                                                       uint32_t* table, size_t table_words);
/* Device version: buffers, laid out as for msmcl_filter_array_layered_device. */
MSMCL_C_API msmcl_status msmcl_build_sat_array_layered_device(msmcl_context* context,
                                                              const msmcl_device_depth* depth, int layers,
                                                              const msmcl_device_layers* translucent, cl_mem table,
                                                              const msmcl_sat_options* options,
                                                              const msmcl_enqueue* enqueue);

/* ---- Prefiltered single scattering (include/msmcl/scatter.hpp; docs/math.md): a
 * directional light with an orthographic shadow map in a homogeneous medium, the
 * in-scattered radiance per camera pixel. Near and far fields are named *_plane (the
 * plain names are macros in some Windows headers). */

/* Convention of the camera's depth buffer (ScatterCamera::depth). */
typedef enum msmcl_camera_depth {
    MSMCL_CAMERA_DEPTH_ZERO_ONE = 0,      /* perspective depth in [0,1] (D3D, Vulkan) */
    MSMCL_CAMERA_DEPTH_MINUS_ONE_ONE = 1, /* perspective depth in [-1,1] (OpenGL) */
    MSMCL_CAMERA_DEPTH_LINEAR = 2         /* eye depth along forward, world units, in [near, far] */
} msmcl_camera_depth;

/* How the prefilter splits a rectified row over work-items (ScatterKernel); same bits. */
typedef enum msmcl_scatter_kernel {
    MSMCL_SCATTER_KERNEL_AUTOMATIC = 0,
    MSMCL_SCATTER_KERNEL_ROWS_GPU = 1,
    MSMCL_SCATTER_KERNEL_ROWS_CPU = 2
} msmcl_scatter_kernel;

/* The light and its orthographic shadow map (ScatterLight: axes, texel and depth mapping). */
typedef struct msmcl_scatter_light {
    double direction[3];           /* the direction the light travels; default (0, -1, 0) */
    double up[3];                  /* hint for the map's up axis; default (0, 0, -1) */
    double center[3];              /* world point at the map's centre; default (0, 0, 0) */
    double width, height;          /* world extent of the map across u and v; default 1, 1 */
    double near_plane, far_plane;  /* depth range along direction from center; default 0, 1 */
    msmcl_depth_range depth_range; /* of the shadow map; default zero_one */
} msmcl_scatter_light;

/* A pinhole camera (ScatterCamera: pixel rays, row 0 at the top). */
typedef struct msmcl_scatter_camera {
    double position[3];            /* default (0, 0, 0) */
    double forward[3];             /* default (0, 0, -1) */
    double up[3];                  /* hint, not parallel to forward; default (0, 1, 0) */
    double vertical_fov_degrees;   /* default 60 */
    double near_plane, far_plane;  /* default 0.1, 100 */
    int width, height;             /* pixels of the camera depth and the radiance; default 128 x 96 */
    msmcl_camera_depth depth;      /* default MSMCL_CAMERA_DEPTH_ZERO_ONE */
} msmcl_scatter_camera;

/* A homogeneous medium (ScatterMedium). */
typedef struct msmcl_scatter_medium {
    double extinction; /* sigma_t per world unit, > 0; default 0.1 */
    double phase_g;    /* Henyey-Greenstein asymmetry in (-1, 1); default 0 */
    double irradiance; /* E of the light, >= 0; default 1 */
} msmcl_scatter_medium;

typedef struct msmcl_scatter_scene {
    msmcl_scatter_light light;
    msmcl_scatter_camera camera;
    msmcl_scatter_medium medium;
    int rectified_width;  /* texels along r; default 256 */
    int rectified_height; /* texels along phi; default 256 */
    double guard_band;    /* extra share of the inclination range on each side, in [0, 1]; default 0.05 */
} msmcl_scatter_scene;

/* Defaults: the C++ defaults of ScatterScene. */
MSMCL_C_API void msmcl_scatter_scene_init(msmcl_scatter_scene* scene);

typedef struct msmcl_scatter_options {
    int moments;                       /* 4 or 6; default 6 */
    int filtered;                      /* nonzero: resample a filtered moment map; 0: one depth sample; default 1 */
    float filter_sigma;                /* Gaussian sigma (texels) of that moments128 map; default 1 */
    float beta;                        /* upper-bound weight in [0, 1]; negative = adaptive; default -1 */
    msmcl_scatter_kernel kernel;       /* default MSMCL_SCATTER_KERNEL_AUTOMATIC */
    msmcl_filter_kernel filter_kernel; /* of the moments128 map; default MSMCL_FILTER_KERNEL_AUTOMATIC */
} msmcl_scatter_options;

MSMCL_C_API void msmcl_scatter_options_init(msmcl_scatter_options* options);
/* Bytes of a prefiltered map, 8 * rectified_width * rectified_height (0 for NULL or an empty size). */
MSMCL_C_API size_t msmcl_scatter_map_bytes(const msmcl_scatter_scene* scene);

/* Host shadow map (as a host depth map) and camera depth (camera.width * camera.height floats)
 * in, as many radiances out; all validated. `options` may be NULL. */
MSMCL_C_API msmcl_status msmcl_scatter(msmcl_context* context, const msmcl_scatter_scene* scene,
                                       const float* shadow_depth, int width, int height, int samples,
                                       const float* camera_depth, const msmcl_scatter_options* options,
                                       float* radiance);
/* Its first half: the prefiltered map (layout of ScatterMap::words) into `map` of at least
 * msmcl_scatter_map_bytes(scene) bytes. `options` may be NULL. */
MSMCL_C_API msmcl_status msmcl_scatter_prefilter(msmcl_context* context, const msmcl_scatter_scene* scene,
                                                 const float* shadow_depth, int width, int height, int samples,
                                                 const msmcl_scatter_options* options, void* map, size_t map_bytes);
/* Its second half: radiances from a map msmcl_scatter_prefilter wrote for this scene and
 * options.moments. `options` may be NULL. */
MSMCL_C_API msmcl_status msmcl_scatter_evaluate(msmcl_context* context, const msmcl_scatter_scene* scene,
                                                const void* map, size_t map_bytes, const float* camera_depth,
                                                const msmcl_scatter_options* options, float* radiance);

/* Filtered prefilter on the device: `moment_map` a moments128 buffer (msmcl_filter_device, depth
 * range the light's), `scatter_map` msmcl_scatter_map_bytes(scene). `enqueue` may be NULL. */
MSMCL_C_API msmcl_status msmcl_scatter_prefilter_device(msmcl_context* context, const msmcl_scatter_scene* scene,
                                                        cl_mem moment_map, int map_width, int map_height,
                                                        int moments, cl_mem scatter_map,
                                                        const msmcl_enqueue* enqueue);
/* Unfiltered (sample 0 of the nearest texel): `shadow_map->memory` a buffer (an image is
 * MSMCL_ERROR_INPUT). `enqueue` may be NULL. */
MSMCL_C_API msmcl_status msmcl_scatter_prefilter_depth_device(msmcl_context* context,
                                                              const msmcl_scatter_scene* scene,
                                                              const msmcl_device_depth* shadow_map, int moments,
                                                              cl_mem scatter_map, const msmcl_enqueue* enqueue);
/* Evaluation on the device: `camera_depth` and `radiance` camera.width * camera.height floats
 * (not validated), `beta` as in msmcl_scatter_options. `enqueue` may be NULL. */
MSMCL_C_API msmcl_status msmcl_scatter_evaluate_device(msmcl_context* context, const msmcl_scatter_scene* scene,
                                                       cl_mem scatter_map, int moments, cl_mem camera_depth,
                                                       cl_mem radiance, float beta, const msmcl_enqueue* enqueue);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* MSMCL_MSMCL_H */
