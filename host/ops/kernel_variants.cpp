// The catalogue of program variants (host/ops/kernel_variants.hpp): the operations' own
// define functions and device choices, enumerated.
#include "ops/kernel_variants.hpp"
#include "runtime/texture_kinds.hpp"

#include <initializer_list>
#include <set>

namespace msmcl::detail {

DeviceInfo synthetic_gpu(std::size_t max_work_group_size, unsigned long long local_mem_bytes) {
    DeviceInfo device;
    device.name = "synthetic GPU";
    device.is_gpu = true;
    device.compute_units = 1;
    device.max_work_group_size = max_work_group_size;
    device.local_mem_bytes = local_mem_bytes;
    device.global_mem_bytes = 1ull << 34;
    device.max_alloc_bytes = 1ull << 32;
    return device;
}

namespace {


std::string format_text(Format format) { return format_name(format); }

std::string range_text(DepthRange range) { return range == DepthRange::zero_one ? "d 0..1" : "d -1..1"; }

std::string variant_note(Format format, int samples, DepthRange range, int layers) {
    std::string note = format_text(format) + " S=" + std::to_string(samples) + " " + range_text(range);
    if (layers > 0) note += ", " + std::to_string(layers) + (layers == 1 ? " layer" : " layers");
    return note;
}

// (samples, depth range, layers) combinations of a depth-map program.
struct DepthVariant {
    int samples;
    DepthRange range;
    int layers;
};

std::vector<DepthVariant> depth_variants(bool full, std::initializer_list<int> covering_samples,
                                         std::initializer_list<int> covering_layered_samples) {
    std::vector<DepthVariant> variants;
    if (full) {
        for (int samples : {1, 2, 4, 8, 16})
            for (DepthRange range : {DepthRange::zero_one, DepthRange::minus_one_one})
                for (int layers = 0; layers <= max_translucent_layers; ++layers)
                    variants.push_back({samples, range, layers});
        return variants;
    }
    // Every sample count opaque, the other depth convention once, 1 and 8 layers.
    for (int samples : covering_samples) variants.push_back({samples, DepthRange::zero_one, 0});
    variants.push_back({1, DepthRange::minus_one_one, 0});
    for (int samples : covering_layered_samples)
        for (int layers : {1, max_translucent_layers}) variants.push_back({samples, DepthRange::zero_one, layers});
    return variants;
}

} // namespace

std::vector<KernelVariant> kernel_variants(bool full) {
    std::vector<KernelVariant> variants;
    // What `automatic` picks on GPUs: one that runs the paper's kernel, one too small for it.
    const DeviceInfo gpus[] = {synthetic_gpu(1024, 65536), synthetic_gpu(128, 16384)};
    std::set<FilterKernel> gpu_filters;
    std::set<SatKernel> gpu_sats;
    for (const DeviceInfo& gpu : gpus) {
        gpu_filters.insert(filter_kernel_for(gpu, FilterKernel::automatic));
        gpu_sats.insert(sat_kernel_for(gpu, SatKernel::automatic));
    }
    const auto on_gpu = [&](FilterKernel kernel) { return gpu_filters.count(kernel) > 0; };
    const auto sat_on_gpu = [&](SatKernel kernel) { return gpu_sats.count(kernel) > 0; };
    // The host's local-memory figure of the variant just added.
    const auto states_local_bytes = [&](FilterKernel kernel, Format format) {
        variants.back().local_bytes = filter_local_bytes(kernel, format, filter_cpu_tile_width());
    };

    // filter: the three distributions, every format.
    for (Format format : filter_formats()) {
        for (const DepthVariant& v : depth_variants(full, {1, 2, 4, 8, 16}, {1, 4})) {
            variants.push_back({"filter", "filter_fused_gpu.cl", filter_defines(v.samples, format, v.range, v.layers),
                                {{"filter_fused_gpu", on_gpu(FilterKernel::fused_paper)}},
                                "fused_paper " + variant_note(format, v.samples, v.range, v.layers)});
            states_local_bytes(FilterKernel::fused_paper, format);
        }
        for (const DepthVariant& v : depth_variants(full, {1, 4, 16}, {1})) {
            const bool gpu = on_gpu(FilterKernel::three_pass);
            variants.push_back({"filter", "filter_three_pass.cl", filter_defines(v.samples, format, v.range, v.layers),
                                {{"filter_resolve", gpu}, {"filter_horizontal", gpu}, {"filter_vertical_quantize", gpu}},
                                "three_pass " + variant_note(format, v.samples, v.range, v.layers)});
        }
        for (const DepthVariant& v : depth_variants(full, {4}, {})) {
            const bool gpu = on_gpu(FilterKernel::fused_cpu);
            variants.push_back({"filter", "filter_fused_cpu.cl", filter_cpu_defines(v.samples, format, v.range, v.layers),
                                {{"filter_fused_cpu_interior", gpu}, {"filter_fused_cpu_border", gpu}},
                                "fused_cpu " + variant_note(format, v.samples, v.range, v.layers)});
            states_local_bytes(FilterKernel::fused_cpu, format);
        }
    }
    // The translucent resolve of the CPU kernel once (covering set).
    if (!full) {
        variants.push_back({"filter", "filter_fused_cpu.cl",
                            filter_cpu_defines(4, Format::nlq64, DepthRange::zero_one, max_translucent_layers),
                            {{"filter_fused_cpu_interior", on_gpu(FilterKernel::fused_cpu)},
                             {"filter_fused_cpu_border", on_gpu(FilterKernel::fused_cpu)}},
                            "fused_cpu " + variant_note(Format::nlq64, 4, DepthRange::zero_one, max_translucent_layers)});
        states_local_bytes(FilterKernel::fused_cpu, Format::nlq64);
    }
    // Texture arrays (MSM_ARRAY): the layer-slicing programs, opaque and translucent.
    for (Format format : {Format::msm64, Format::nlq64}) {
        for (int layers : {0, 1}) {
            variants.push_back({"filter", "filter_fused_gpu.cl",
                                filter_defines(4, format, DepthRange::zero_one, layers, true),
                                {{"filter_fused_gpu", on_gpu(FilterKernel::fused_paper)}},
                                "fused_paper array " + variant_note(format, 4, DepthRange::zero_one, layers)});
            states_local_bytes(FilterKernel::fused_paper, format);
        }
        variants.push_back({"filter", "filter_three_pass.cl", filter_defines(4, format, DepthRange::zero_one, 0, true),
                            {{"filter_resolve", on_gpu(FilterKernel::three_pass)},
                             {"filter_horizontal", on_gpu(FilterKernel::three_pass)},
                             {"filter_vertical_quantize", on_gpu(FilterKernel::three_pass)}},
                            "three_pass array " + variant_note(format, 4, DepthRange::zero_one, 0)});
        variants.push_back({"filter", "filter_fused_cpu.cl", filter_cpu_defines(4, format, DepthRange::zero_one, 0, true),
                            {{"filter_fused_cpu_interior", on_gpu(FilterKernel::fused_cpu)},
                             {"filter_fused_cpu_border", on_gpu(FilterKernel::fused_cpu)}},
                            "fused_cpu array " + variant_note(format, 4, DepthRange::zero_one, 0)});
        states_local_bytes(FilterKernel::fused_cpu, format);
    }
    // Depth upload from images or planes (interop).
    variants.push_back({"interop", "interop.cl", {}, {{"depth_interleave_layers", true}}, ""});

    // sat: the tiled GPU build and the baseline share a program; the CPU band scan.
    const auto sat_note = [](int samples, DepthRange range) {
        return "depth S=" + std::to_string(samples) + " " + range_text(range);
    };
    for (int samples : {1, 2, 4, 8, 16}) {
        for (DepthRange range : {DepthRange::zero_one, DepthRange::minus_one_one}) {
            if (!full && range == DepthRange::minus_one_one && samples != 1) continue;
            variants.push_back({"sat", "sat_build.cl", sat_build_defines(true, samples, range, SatKernel::tiled_gpu),
                                {{"sat_tile_totals", sat_on_gpu(SatKernel::tiled_gpu)},
                                 {"sat_tile_scan", sat_on_gpu(SatKernel::tiled_gpu)},
                                 {"sat_rows_per_thread", sat_on_gpu(SatKernel::row_per_thread)},
                                 {"sat_columns_per_thread", sat_on_gpu(SatKernel::row_per_thread)}},
                                "tiled_gpu, row_per_thread " + sat_note(samples, range)});
            if (!full && samples > 4) continue;
            variants.push_back({"sat", "sat_build_cpu.cl", sat_build_defines(true, samples, range, SatKernel::tiled_cpu),
                                {{"sat_band_totals_cpu", sat_on_gpu(SatKernel::tiled_cpu)},
                                 {"sat_band_totals_texels_cpu", sat_on_gpu(SatKernel::tiled_cpu)},
                                 {"sat_band_scan_cpu", sat_on_gpu(SatKernel::tiled_cpu)}},
                                "tiled_cpu " + sat_note(samples, range)});
        }
    }
    // Ready integer texels (translucent builds): both distributions, and the CPU band scan
    // over the texels its first step left in the table.
    variants.push_back({"sat", "sat_build.cl", sat_build_defines(false, 1, DepthRange::zero_one, SatKernel::tiled_gpu),
                        {{"sat_tile_totals", sat_on_gpu(SatKernel::tiled_gpu)},
                         {"sat_tile_scan", sat_on_gpu(SatKernel::tiled_gpu)},
                         {"sat_rows_per_thread", sat_on_gpu(SatKernel::row_per_thread)},
                         {"sat_columns_per_thread", sat_on_gpu(SatKernel::row_per_thread)}},
                        "tiled_gpu, row_per_thread texels"});
    for (bool step1 : {false, true}) {
        variants.push_back({"sat", "sat_build_cpu.cl",
                            sat_build_defines(false, 1, DepthRange::zero_one, SatKernel::tiled_cpu, step1),
                            {{"sat_band_totals_cpu", sat_on_gpu(SatKernel::tiled_cpu)},
                             {"sat_band_scan_cpu", sat_on_gpu(SatKernel::tiled_cpu)}},
                            std::string("tiled_cpu texels") + (step1 ? " of step 1" : "")});
    }
    variants.push_back({"sat", "sat_carries.cl", {},
                        {{"sat_column_carries", true}, {"sat_row_carries", true}, {"sat_corner_carries", true}}, ""});
    for (const DepthVariant& v : depth_variants(full, {}, {1, 4})) {
        if (v.layers == 0) continue;
        variants.push_back({"sat", "sat_translucent.cl", sat_translucent_defines(v.samples, v.layers, v.range),
                            {{"sat_translucent_texels", true}},
                            "S=" + std::to_string(v.samples) + " " + range_text(v.range) + ", " +
                                std::to_string(v.layers) + " layers"});
    }
    // Texture arrays (MSM_ARRAY): every build program once.
    variants.push_back({"sat", "sat_build.cl",
                        sat_build_defines(true, 4, DepthRange::zero_one, SatKernel::tiled_gpu, false, true),
                        {{"sat_tile_totals", sat_on_gpu(SatKernel::tiled_gpu)},
                         {"sat_tile_scan", sat_on_gpu(SatKernel::tiled_gpu)},
                         {"sat_rows_per_thread", sat_on_gpu(SatKernel::row_per_thread)},
                         {"sat_columns_per_thread", sat_on_gpu(SatKernel::row_per_thread)}},
                        "array, tiled_gpu, row_per_thread " + sat_note(4, DepthRange::zero_one)});
    variants.push_back({"sat", "sat_build_cpu.cl",
                        sat_build_defines(true, 4, DepthRange::zero_one, SatKernel::tiled_cpu, false, true),
                        {{"sat_band_totals_cpu", sat_on_gpu(SatKernel::tiled_cpu)},
                         {"sat_band_totals_texels_cpu", sat_on_gpu(SatKernel::tiled_cpu)},
                         {"sat_band_scan_cpu", sat_on_gpu(SatKernel::tiled_cpu)}},
                        "array, tiled_cpu " + sat_note(4, DepthRange::zero_one)});
    variants.push_back({"sat", "sat_carries.cl", sat_carries_defines(true),
                        {{"sat_column_carries", true}, {"sat_row_carries", true}, {"sat_corner_carries", true}},
                        "array"});
    variants.push_back({"sat", "sat_translucent.cl", sat_translucent_defines(4, 1, DepthRange::zero_one, true),
                        {{"sat_translucent_texels", true}}, "array, S=4 d 0..1, 1 layers"});
    variants.push_back({"sat", "sat_query.cl", {}, {{"sat_query_moments", true}}, ""});

    // soft shadows, shade.
    for (DepthRange range : {DepthRange::zero_one, DepthRange::minus_one_one})
        variants.push_back({"soft", "sat_soft.cl", soft_defines(range), {{"sat_soft_shade", true}}, range_text(range)});
    for (Format format : filter_formats()) {
        for (Lookup lookup : {Lookup::nearest, Lookup::bilinear, Lookup::dither}) {
            for (DepthRange range : {DepthRange::zero_one, DepthRange::minus_one_one}) {
                if (!full && range == DepthRange::minus_one_one && lookup != Lookup::bilinear) continue;
                for (bool pixels : {false, true}) {
                    if (pixels && lookup != Lookup::dither) continue;
                    variants.push_back({"shade", "shade.cl", shade_defines(format, lookup, range, pixels),
                                        {{lookup == Lookup::dither ? "shade_dither" : "shade", true}},
                                        format_text(format) + " " + lookup_name(lookup) + " " + range_text(range) +
                                            (pixels ? ", receiver pixels" : "")});
                }
            }
        }
    }

    // scatter: row tiling of GPUs and of CPUs.
    DeviceInfo cpu = synthetic_gpu(1024, 65536);
    cpu.is_gpu = false;
    cpu.is_cpu = true;
    for (int moments : {4, 6}) {
        for (const DeviceInfo* device : {&gpus[0], static_cast<const DeviceInfo*>(&cpu)}) {
            variants.push_back({"scatter", "scatter.cl", scatter_defines(moments, *device),
                                {{"scatter_prefilter", device->is_gpu},
                                 {"scatter_evaluate", device->is_gpu},
                                 {"scatter_ray_march", device->is_gpu}},
                                std::to_string(moments) + " moments, " + (device->is_gpu ? "GPU" : "CPU") +
                                    " row tiling"});
        }
    }
    return variants;
}

} // namespace msmcl::detail
