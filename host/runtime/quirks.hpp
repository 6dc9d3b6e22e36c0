// Everything msmcl knows about particular devices and drivers, in one place.
#pragma once

#include <msmcl/context.hpp>

#include <string>

namespace msmcl::detail {

/// PoCL (the portable CPU implementation CI runs on).
inline bool is_pocl(const DeviceInfo& device) {
    return device.platform_name.find("Portable Computing Language") != std::string::npos ||
           device.driver_version.find("pocl") != std::string::npos ||
           device.opencl_version.find("pocl") != std::string::npos;
}

} // namespace msmcl::detail
