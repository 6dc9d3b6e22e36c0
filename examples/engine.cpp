// msmcl inside an engine: the engine owns the OpenCL context and queue, renders its shadow
// map into a depth image, and gets back an nlq32 moment shadow map in an image of its own,
// all on the device, ordered by events. Prints two shadow intensities; exits 0 when they
// are as expected (lit outside the occluder's shadow, shadowed inside).
#include <msmcl/msmcl.hpp>
#include <msmcl/interop.hpp>

#include <CL/cl.h>

#include <cstdio>
#include <vector>

int main() try {
    // The engine's OpenCL objects (here simply the first device of the first platform).
    cl_platform_id platform = nullptr;
    cl_device_id device = nullptr;
    if (clGetPlatformIDs(1, &platform, nullptr) != CL_SUCCESS ||
        clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, 1, &device, nullptr) != CL_SUCCESS) {
        std::fprintf(stderr, "example: no OpenCL device\n");
        return 1;
    }
    cl_int status = CL_SUCCESS;
    cl_context engine_context = clCreateContext(nullptr, 1, &device, nullptr, nullptr, &status);
    // The engine's own OpenCL version decides its calls (msmcl's headers need 1.2 only).
#if CL_TARGET_OPENCL_VERSION >= 200
    cl_command_queue engine_queue = clCreateCommandQueueWithProperties(engine_context, device, nullptr, &status);
#else
    cl_command_queue engine_queue = clCreateCommandQueue(engine_context, device, 0, &status);
#endif

    // msmcl borrows them (and retains what it keeps).
    msmcl::Context msm(engine_context, device, engine_queue);

    // The "rendered" shadow map: a floor at depth 0.8 and a box at 0.3 over texels 24..39.
    const int size = 64;
    std::vector<float> depth(size * size, 0.8f);
    for (int y = 24; y < 40; ++y)
        for (int x = 24; x < 40; ++x) depth[y * size + x] = 0.3f;
    const cl_image_format depth_format{CL_R, CL_FLOAT};
    cl_image_desc description{};
    description.image_type = CL_MEM_OBJECT_IMAGE2D;
    description.image_width = size;
    description.image_height = size;
    cl_mem depth_image = clCreateImage(engine_context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, &depth_format,
                                       &description, depth.data(), &status);

    // The engine's texture for the result: the natural image format of nlq32.
    msmcl::FilterOptions options;
    options.format = msmcl::Format::nlq32;
    const cl_image_format map_format = msmcl::texture_image_format(options.format);
    cl_mem shadow_map = clCreateImage(engine_context, CL_MEM_READ_WRITE, &map_format, &description, nullptr, &status);
    if (status != CL_SUCCESS) {
        std::fprintf(stderr, "example: clCreateImage failed (%d)\n", status);
        return 1;
    }

    // Filter on the engine's queue; `done` orders the engine's next use of the map.
    cl_event done = nullptr;
    msmcl::Enqueue enqueue;
    enqueue.queue = engine_queue;
    enqueue.done = &done;
    msmcl::filter_to_image(msm, msmcl::DeviceDepthImage{depth_image, size, size, 1}, shadow_map, options, enqueue);

    // A renderer would now sample shadow_map in a shader (shaders/msm.glsl). Here: read it
    // back after `done` and evaluate two receivers on the floor with the host functions.
    msmcl::Texture map;
    map.format = options.format;
    map.width = map.height = size;
    map.words.resize(size * size);
    const size_t origin[3] = {0, 0, 0};
    const size_t region[3] = {static_cast<size_t>(size), static_cast<size_t>(size), 1};
    clEnqueueReadImage(engine_queue, shadow_map, CL_TRUE, origin, region, 0, 0, map.words.data(), 1, &done, nullptr);
    const msmcl::ShadeOptions shade_options; // bilinear, bias 1e-3, depth in [0,1]
    const float lit = msmcl::shade_receiver(map, 8.0f, 8.0f, 0.8f, shade_options);
    const float shadowed = msmcl::shade_receiver(map, 32.0f, 32.0f, 0.8f, shade_options);
    std::printf("example: device %s, lit %.3f, shadowed %.3f\n", msm.device().name.c_str(), lit, shadowed);

    clReleaseEvent(done);
    clReleaseMemObject(shadow_map);
    clReleaseMemObject(depth_image);
    clReleaseCommandQueue(engine_queue);
    clReleaseContext(engine_context);
    const bool expected = lit < 0.05f && shadowed > 0.95f;
    std::printf("example: %s\n", expected ? "ok" : "unexpected intensities");
    return expected ? 0 : 1;
} catch (const msmcl::error& e) {
    std::fprintf(stderr, "example: %s\n", e.what());
    return 1;
}
