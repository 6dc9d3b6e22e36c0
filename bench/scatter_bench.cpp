// msmcl-scatter-bench: cost of prefiltered single scattering on one OpenCL device, per
// rectified texel (resampling + prefix sums, filtered and unfiltered, 4 and 6 moments) and
// per output pixel (evaluation), against ray marching the shadow map with 32 and 128 samples
// per pixel on the same device (Peters et al., i3D 2016, Figure 8; Peters, GDC Europe 2016, "Results").
//   msmcl-scatter-bench [--scene data/scatter/pergola.json] [--map-size 1024] [--rectified 1024]
//                       [--width 1920] [--height 1080] [--reps 7] [--device D] [--json FILE]
// Every timed call ends with clFinish; two untimed warm-up calls first (program builds,
// first-launch compilation). Wall-clock medians and minima in milliseconds, and the median
// CPU time of the process (all threads): on a shared machine the steadier figure of the work.
#include "tools/scatter_geometry.hpp"
#include "io/scene_json.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/scatter.hpp>

#include <CL/cl.h>
#include <sys/resource.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace msmcl;

struct Timing {
    double median_ms = 0, min_ms = 0;
    double cpu_median_ms = 0; ///< CPU time of the whole process (all threads): the work done
};

/// User + system time of this process so far, all threads (the OpenCL runtime's included).
double process_cpu_ms() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return (usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) * 1e3 +
           (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) * 1e-3;
}

double median_of(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

Timing time_call(Context& context, const std::function<void()>& call, int reps) {
    for (int i = 0; i < 2; ++i) {
        call();
        context.finish();
    }
    std::vector<double> ms, cpu;
    for (int i = 0; i < reps; ++i) {
        const double cpu_start = process_cpu_ms();
        const auto start = std::chrono::steady_clock::now();
        call();
        context.finish();
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        cpu.push_back(process_cpu_ms() - cpu_start);
    }
    return {median_of(ms), *std::min_element(ms.begin(), ms.end()), median_of(cpu)};
}

cl_mem make_buffer(Context& context, std::size_t bytes, const void* data) {
    cl_int status = CL_SUCCESS;
    cl_mem buffer = clCreateBuffer(context.cl_context_handle(),
                                   data ? CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR : CL_MEM_READ_WRITE, bytes,
                                   const_cast<void*>(data), &status);
    if (status != CL_SUCCESS) throw opencl_error(status, "clCreateBuffer");
    return buffer;
}

std::string read_text(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw input_error(path + ": cannot open");
    std::ostringstream text;
    text << file.rdbuf();
    return text.str();
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"msmcl-scatter-bench: cost of prefiltered single scattering vs ray marching", "msmcl-scatter-bench"};
    std::string scene_path = "data/scatter/pergola.json", device, json_path;
    int map_size = 1024, rectified = 1024, width = 1920, height = 1080, reps = 7;
    app.add_option("--scene", scene_path, "scene JSON with geometry")->capture_default_str();
    app.add_option("--map-size", map_size, "shadow map side")->capture_default_str()->check(CLI::Range(16, 16384));
    app.add_option("--rectified", rectified, "rectified map side")->capture_default_str()->check(CLI::Range(16, 16384));
    app.add_option("--width", width, "output width")->capture_default_str()->check(CLI::Range(1, 16384));
    app.add_option("--height", height, "output height")->capture_default_str()->check(CLI::Range(1, 16384));
    app.add_option("--reps", reps, "timed repetitions")->capture_default_str()->check(CLI::Range(1, 1000));
    app.add_option("--device", device, "OpenCL device spec (as msmcl --device)");
    app.add_option("--json", json_path, "write the rows as JSON");
    CLI11_PARSE(app, argc, argv);
    try {
        // The scene at the requested sizes, its two depth buffers rendered on the host.
        const std::string text = read_text(scene_path);
        ScatterScene scene = parse_scatter_scene(text);
        const scatter_data::Geometry geometry = scatter_data::parse_geometry(text);
        scene.camera.width = width;
        scene.camera.height = height;
        scene.rectified_width = scene.rectified_height = rectified;
        const DepthImage shadow = scatter_data::render_shadow_map(scene, geometry, map_size, map_size);
        const std::vector<float> camera_depth = scatter_data::render_camera_depth(scene, geometry);

        DeviceSelection selection;
        selection.device = device;
        selection.strict = !device.empty();
        Context context(selection);
        const std::size_t texels = static_cast<std::size_t>(rectified) * rectified;
        const std::size_t pixels = static_cast<std::size_t>(width) * height;
        cl_mem depth_buffer = make_buffer(context, shadow.depth.size() * 4, shadow.depth.data());
        cl_mem moment_buffer = make_buffer(context, static_cast<std::size_t>(map_size) * map_size * 16, nullptr);
        cl_mem map_buffer = make_buffer(context, scatter_map_bytes(scene), nullptr);
        cl_mem camera_buffer = make_buffer(context, pixels * 4, camera_depth.data());
        cl_mem radiance_buffer = make_buffer(context, pixels * 4, nullptr);
        const DeviceDepth device_depth{depth_buffer, map_size, map_size, 1};
        const DeviceTexture moment_map{moment_buffer, Format::moments128, map_size, map_size, {}};
        FilterOptions filter_options;
        filter_options.format = Format::moments128;
        filter_options.sigma = 1.0f;
        filter_options.depth_range = scene.light.depth_range;
        filter(context, device_depth, moment_buffer, filter_options);

        nlohmann::json rows = nlohmann::json::array();
        const auto report = [&](const std::string& name, Timing t, std::size_t items, const char* per) {
            const double ns = t.median_ms * 1e6 / items, cpu_ns = t.cpu_median_ms * 1e6 / items;
            std::printf("%-30s %9.2f ms (min %9.2f, cpu %9.2f)  %8.1f ns (cpu %8.1f ns) per %s\n", name.c_str(),
                        t.median_ms, t.min_ms, t.cpu_median_ms, ns, cpu_ns, per);
            rows.push_back({{"case", name}, {"ms_median", t.median_ms}, {"ms_min", t.min_ms},
                            {"cpu_ms_median", t.cpu_median_ms}, {"items", items}, {"per", per}, {"ns_per_item", ns},
                            {"cpu_ns_per_item", cpu_ns}});
        };
        std::printf("device %s; shadow map %d^2, rectified %d^2, output %dx%d\n", context.device().name.c_str(), map_size,
                    rectified, width, height);
        report("moment map (filter, sigma 1)",
               time_call(context, [&] { filter(context, device_depth, moment_buffer, filter_options); }, reps),
               static_cast<std::size_t>(map_size) * map_size, "shadow texel");
        for (int moments : {4, 6}) {
            report("prefilter " + std::to_string(moments) + " filtered",
                   time_call(context, [&] { scatter_prefilter(context, scene, moment_map, map_buffer, moments); }, reps),
                   texels, "rectified texel");
            report("prefilter " + std::to_string(moments) + " unfiltered",
                   time_call(context, [&] { scatter_prefilter(context, scene, device_depth, map_buffer, moments); }, reps),
                   texels, "rectified texel");
            scatter_prefilter(context, scene, moment_map, map_buffer, moments);
            report("evaluate " + std::to_string(moments),
                   time_call(context,
                             [&] { scatter_evaluate(context, scene, map_buffer, moments, camera_buffer, radiance_buffer); },
                             reps),
                   pixels, "pixel");
        }
        for (int steps : {32, 128})
            report("ray march " + std::to_string(steps),
                   time_call(context,
                             [&] {
                                 scatter_ray_march(context, scene, device_depth, camera_buffer, radiance_buffer, steps);
                             },
                             reps),
                   pixels, "pixel");
        for (cl_mem m : {depth_buffer, moment_buffer, map_buffer, camera_buffer, radiance_buffer}) clReleaseMemObject(m);
        if (!json_path.empty()) {
            nlohmann::json document{{"device", context.device().name}, {"scene", scene_path}, {"map_size", map_size},
                                    {"rectified", rectified}, {"width", width}, {"height", height}, {"rows", rows}};
            std::ofstream(json_path) << document.dump(2) << '\n';
        }
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "msmcl-scatter-bench: " << e.what() << std::endl;
        return dynamic_cast<const input_error*>(&e) ? 2 : 1;
    }
}
