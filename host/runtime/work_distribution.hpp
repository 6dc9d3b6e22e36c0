// Which work distribution `automatic` gives a device: the one rule every operation with
// a GPU and a CPU distribution (filter, sat, scatter) follows, so that a device gets the
// same family of kernels from all of them (docs/devices.md).
#pragma once

#include <msmcl/context.hpp>

namespace msmcl::detail {

/// True when `automatic` picks the GPU distribution: the device reports
/// CL_DEVICE_TYPE_GPU (whatever else it reports: Oclgrind says CPU|GPU|ACCELERATOR), or
/// reports neither GPU nor CPU (accelerators, custom devices). Only a device that is a
/// CPU and not a GPU gets the CPU distribution, whose kernels are written for an OpenCL
/// compiler that runs a work-group's items one after another in vector lanes.
inline bool prefers_gpu_distribution(const DeviceInfo& device) {
    return device.is_gpu || !device.is_cpu;
}

} // namespace msmcl::detail
