// Device enumeration and choice (the public side is in context.hpp).
#pragma once

#include "runtime/opencl.hpp"

#include <msmcl/context.hpp>

#include <vector>

namespace msmcl::detail {

struct DeviceCandidate {
    cl::Device device;
    DeviceInfo info;
};

DeviceInfo describe_device(const cl::Device& device, int platform_index, int device_index,
                           const std::string& platform_name);
std::vector<DeviceCandidate> enumerate_devices();
/// Applies DeviceSelection; throws device_error when nothing can be chosen.
DeviceCandidate select_device(const DeviceSelection& selection);

} // namespace msmcl::detail
