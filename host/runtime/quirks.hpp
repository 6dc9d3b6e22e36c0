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

/// Build options a device needs besides the program's own. PoCL's compiler prints its
/// diagnostics ("2 warnings generated.") straight to the process's stderr, which would
/// break the CLI's one-line error contract: silence warnings there (the build log still
/// carries errors).
inline std::string device_build_options(const DeviceInfo& device) {
    return is_pocl(device) ? "-w" : "";
}

} // namespace msmcl::detail
