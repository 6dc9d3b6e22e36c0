// Which work distribution `automatic` gives a device: the one rule every operation with
// a GPU and a CPU distribution (filter, sat, scatter) follows, so that a device gets the
// same family of kernels from all of them (docs/devices.md).
#pragma once

#include <msmcl/context.hpp>
#include <optional>

namespace msmcl::detail {

/// True when `automatic` picks the GPU distribution: the device reports
/// CL_DEVICE_TYPE_GPU (whatever else it reports: Oclgrind says CPU|GPU|ACCELERATOR), or
/// reports neither GPU nor CPU (accelerators, custom devices). Only a device that is a
/// CPU and not a GPU gets the CPU distribution, whose kernels are written for an OpenCL
/// compiler that runs a work-group's items one after another in vector lanes.
inline bool prefers_gpu_distribution(const DeviceInfo& device) {
    return device.is_gpu || !device.is_cpu;
}

/// The most loop iterations one work-item may run, where the device limits them. Mesa's
/// llvmpipe (rusticl) compiles every kernel with its shader guard against endless loops:
/// a work-item stops looping after 65535 iterations of all its loops together, silently,
/// and what it had left to do is never done (measured: the CPU filter's 128x64 tile lost
/// its last 19 output rows). std::nullopt: no limit.
inline std::optional<long> loop_iteration_limit(const DeviceInfo& device) {
    if (device.platform_name == "rusticl" && device.name.rfind("llvmpipe", 0) == 0) return 65535;
    return std::nullopt;
}

} // namespace msmcl::detail
