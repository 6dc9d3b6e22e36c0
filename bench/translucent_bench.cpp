// Cases of the translucent-occluder and dithering work (docs/math.md) on the workload's device and depth map:
//   shade_nearest, shade_bilinear, shade_dither
//                         shade 2^18 receivers (a 512 x 512 view of random points on the
//                         map's surface) from the workload's texture with each lookup; the
//                         dither row also reports its error against bilinear: one frame,
//                         and the mean of 64 frames (rms and max over the receivers)
//   filter_opaque, filter_translucent2
//                         the filter the library picks (fused) on the depth map alone and
//                         with two translucent layers (see translucent_layers below); the
//                         translucent row reports its time over the opaque one
// Shade rows report the cost per receiver; filter rows `bytes` = what each must move (the
// layers' depths and opacities included), so GB/s compare.
#include "harness.hpp"
#include "scene.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/shade.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace msmcl::bench {

namespace {

std::vector<float> read_floats(Context& context, cl_mem buffer, std::size_t count) {
    std::vector<float> values(count);
    check_cl(clEnqueueReadBuffer(context.cl_queue_handle(), buffer, CL_TRUE, 0, count * sizeof(float), values.data(), 0,
                                 nullptr, nullptr),
             "clEnqueueReadBuffer(translucent bench)");
    return values;
}

std::vector<CaseResult> run_lookups(BenchEnv& env, const Workload& work) {
    Context& context = *env.context;
    // The workload's map in its format, filtered into the workload's texture.
    filter(context, work.device_depth(), work.texture_buffer, work.filter_options());
    const DeviceTexture map{work.texture_buffer, work.format, work.size, work.size, work.filter_options().exponents};

    // 2^18 receivers at random spots on the map's surface (sample 0 of their texel), the
    // pixels of a 512 x 512 view (row-major).
    const std::uint32_t view = 512;
    const std::size_t count = std::size_t(view) * view;
    const std::vector<float> uvz = surface_receivers(*work.depth, count, 5);
    Buffer receivers(context, uvz.size() * sizeof(float), uvz.data());
    Buffer intensity(context, count * sizeof(float));

    std::vector<CaseResult> rows;
    std::vector<float> bilinear;
    for (Lookup lookup : {Lookup::nearest, Lookup::bilinear, Lookup::dither}) {
        ShadeOptions options;
        options.lookup = lookup;
        options.screen_width = view;
        CaseResult row;
        row.name = std::string("shade_") + lookup_name(lookup);
        row.bytes = count * (3 * sizeof(float) + sizeof(float));
        row.has_throughput = false;
        row.take(time_runs(
            [&] {
                shade(context, map, receivers.mem, count, intensity.mem, options);
                context.finish();
            },
            env.warmups, env.reps));
        row.extra["receivers"] = count;
        row.extra["ns_per_receiver"] = median(row.ms) * 1e6 / double(count);
        row.extra["texel_fetches_per_receiver"] = lookup == Lookup::bilinear ? 4 : 1;
        if (lookup == Lookup::bilinear) bilinear = read_floats(context, intensity.mem, count);
        if (lookup == Lookup::dither) {
            // Error against bilinear: one frame, and the mean of 64 frames.
            std::vector<double> mean(count, 0.0);
            double one_frame = 0.0;
            for (std::uint32_t frame = 0; frame < 64; ++frame) {
                options.frame = frame;
                shade(context, map, receivers.mem, count, intensity.mem, options);
                const std::vector<float> y = read_floats(context, intensity.mem, count);
                for (std::size_t i = 0; i < count; ++i) {
                    mean[i] += y[i] / 64.0;
                    if (frame == 0) one_frame += (y[i] - bilinear[i]) * (y[i] - bilinear[i]);
                }
            }
            double rms = 0.0, worst = 0.0;
            for (std::size_t i = 0; i < count; ++i) {
                rms += (mean[i] - bilinear[i]) * (mean[i] - bilinear[i]);
                worst = std::max(worst, std::abs(mean[i] - bilinear[i]));
            }
            row.extra["rms_vs_bilinear_one_frame"] = std::sqrt(one_frame / count);
            row.extra["rms_vs_bilinear_mean_64_frames"] = std::sqrt(rms / count);
            row.extra["max_vs_bilinear_mean_64_frames"] = worst;
        }
        rows.push_back(row);
    }
    return rows;
}

// Two translucent layers over the workload's depth map, smoke-like: layer 0 a little in
// front of the opaque surface (z - 0.05) with opacity 0.5 on a checkerboard of 16-texel
// squares (0 elsewhere), layer 1 at a constant depth 0.3 with a smooth opacity ramp
// across the map; per sample, as the opaque depth.
std::vector<TranslucentLayer> translucent_layers(const Workload& work) {
    std::vector<TranslucentLayer> layers(2);
    const std::size_t values = work.texels() * work.samples;
    for (TranslucentLayer& layer : layers) {
        layer.depth.resize(values);
        layer.opacity.resize(values);
    }
    for (int y = 0; y < work.size; ++y)
        for (int x = 0; x < work.size; ++x)
            for (int s = 0; s < work.samples; ++s) {
                const std::size_t i = (static_cast<std::size_t>(y) * work.size + x) * work.samples + s;
                layers[0].depth[i] = std::max(0.0f, work.depth->depth[i] - 0.05f);
                layers[0].opacity[i] = ((x / 16 + y / 16) & 1) ? 0.5f : 0.0f;
                layers[1].depth[i] = 0.3f;
                layers[1].opacity[i] = 0.8f * static_cast<float>(x) / work.size;
            }
    return layers;
}

std::vector<CaseResult> run_translucent(BenchEnv& env, const Workload& work) {
    Context& context = *env.context;
    const FilterOptions options = work.filter_options();
    const DeviceDepth depth = work.device_depth();

    // The layers on the device, layer after layer.
    const std::vector<TranslucentLayer> layers = translucent_layers(work);
    std::vector<float> layer_depth, layer_opacity;
    for (const TranslucentLayer& layer : layers) {
        layer_depth.insert(layer_depth.end(), layer.depth.begin(), layer.depth.end());
        layer_opacity.insert(layer_opacity.end(), layer.opacity.begin(), layer.opacity.end());
    }
    Buffer depth_buffer(context, layer_depth.size() * sizeof(float), layer_depth.data());
    Buffer opacity_buffer(context, layer_opacity.size() * sizeof(float), layer_opacity.data());
    const DeviceLayers device_layers{depth_buffer.mem, opacity_buffer.mem, static_cast<int>(layers.size())};

    CaseResult opaque;
    opaque.name = "filter_opaque";
    opaque.bytes = work.bytes();
    opaque.take(time_runs(
        [&] {
            filter(context, depth, work.texture_buffer, options);
            context.finish();
        },
        env.warmups, env.reps));
    CaseResult translucent;
    translucent.name = "filter_translucent2";
    translucent.bytes = work.bytes() + 2 * layer_depth.size() * sizeof(float);
    translucent.take(time_runs(
        [&] {
            filter(context, depth, device_layers, work.texture_buffer, options);
            context.finish();
        },
        env.warmups, env.reps));
    translucent.extra["layers"] = layers.size();
    translucent.extra["time_over_opaque"] = median(translucent.ms) / median(opaque.ms);
    return {opaque, translucent};
}

MSMCL_BENCH_CASE({"lookups", 120, run_lookups});
MSMCL_BENCH_CASE({"translucent", 130, run_translucent});

} // namespace

} // namespace msmcl::bench
