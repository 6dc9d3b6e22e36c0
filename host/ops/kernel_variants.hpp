// Every program variant the operations build, described without a device: each operation
// file defines the compile-time defines of its programs and its device-dependent choices
// here, and uses the same functions when it enqueues. kernel_variants() lists them for
// offline compilation (tests/gpu_compile/kernel_variants.cpp, scripts/gpu_compile_report.py).
#pragma once

#include "runtime/tuning.hpp"

#include <msmcl/context.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/formats.hpp>
#include <msmcl/sat.hpp>
#include <msmcl/scatter.hpp>
#include <msmcl/shade.hpp>

#include <string>
#include <vector>

namespace msmcl::detail {

// --- filter (host/ops/filter.cpp)
/// The kernel `requested` resolves to on `device` (automatic decides by the device).
FilterKernel filter_kernel_for(const DeviceInfo& device, FilterKernel requested);
/// Defines of filter_fused_gpu.cl and filter_three_pass.cl; `array`: the texture-array
/// program (MSM_ARRAY, one launch for every layer of a layered depth map); `exponents`: the
/// warp's (0: the format's defaults; texture_kind_defines).
std::vector<std::string> filter_defines(int samples, Format format, DepthRange range, int layers, bool array = false,
                                        WarpExponents exponents = {});
/// Local memory in bytes of one work-group of `kernel` (fused_paper, fused_cpu with tiles
/// `cpu_tile_width` wide) for `format`: the sizes the kernels compile with
/// (kernels/fused_layout.clh, fused_cpu_layout.clh); 0 for the others.
unsigned long long filter_local_bytes(FilterKernel kernel, Format format, int cpu_tile_width);
/// The CPU tile width in effect (MSMCL_CPU_TILE).
int filter_cpu_tile_width();
/// Defines of filter_fused_cpu.cl with the CPU tiling in effect (MSMCL_CPU_TILE), or the
/// nonzero sizes of `tile` (the tile a device was given: filter_cpu_tile).
std::vector<std::string> filter_cpu_defines(int samples, Format format, DepthRange range, int layers,
                                            bool array = false, TileSize tile = {}, WarpExponents exponents = {});
/// The CPU filter's tile on `device`: MSMCL_CPU_TILE or the default, its height cut where
/// the device limits a work-item's loops (runtime/quirks.hpp).
TileSize filter_cpu_tile(const DeviceInfo& device);

// --- sat (host/ops/sat.cpp)
/// The distribution `requested` resolves to on `device`.
SatKernel sat_kernel_for(const DeviceInfo& device, SatKernel requested);
/// Defines of sat_build.cl / sat_build_cpu.cl: a depth map (`is_depth`) or ready integer
/// texels; `step1_texels`: the texels step 1 of the CPU build leaves in the table.
std::vector<std::string> sat_build_defines(bool is_depth, int samples, DepthRange range, SatKernel kernel,
                                           bool step1_texels = false, bool array = false);
/// Defines of sat_translucent.cl.
std::vector<std::string> sat_translucent_defines(int samples, int layers, DepthRange range, bool array = false);
/// Defines of sat_carries.cl.
std::vector<std::string> sat_carries_defines(bool array = false);

// --- shade (host/ops/shade.cpp), soft (host/ops/soft.cpp), scatter (host/ops/scatter.cpp)
std::vector<std::string> shade_defines(Format format, Lookup lookup, DepthRange range, bool receiver_pixels);
std::vector<std::string> soft_defines(DepthRange range);
/// Defines of scatter.cl for `moments` on `device` (its row tiling depends on the device,
/// or on an explicit `kernel`).
std::vector<std::string> scatter_defines(int moments, const DeviceInfo& device,
                                         ScatterKernel kernel = ScatterKernel::automatic);

// --- the catalogue (host/ops/kernel_variants.cpp)
struct KernelVariant {
    std::string operation;            ///< "filter", "sat", "shade", ...
    std::string file;                 ///< embedded program, "filter_fused_gpu.cl"
    std::vector<std::string> defines; ///< as ContextImpl::kernel takes them
    struct Kernel {
        std::string name;
        bool gpu_path = false; ///< `automatic` can pick it on a GPU device (else CPU-only or
                               ///< a baseline chosen only explicitly: exempt from GPU budgets)
    };
    std::vector<Kernel> kernels; ///< the kernels the host creates from this program
    std::string note;            ///< what the variant is, "nlq64 S=4, 8 layers"
    unsigned long long local_bytes = 0; ///< the host's figure of each kernel's local memory (0: none stated)
};

/// The covering set (`full` false): every program and kernel, every format, lookup and
/// sample count, both depth conventions, 1 and 8 translucent layers; `full`: every
/// combination the host can build (thousands of programs).
std::vector<KernelVariant> kernel_variants(bool full = false);

/// A GPU device as `automatic` sees one, with the given limits.
DeviceInfo synthetic_gpu(std::size_t max_work_group_size, unsigned long long local_mem_bytes);

} // namespace msmcl::detail
