#include "cli/devices_command.hpp"

#include <iostream>
#include <vector>

namespace msmcl::cli {
namespace {

/// Prints one line per device to stdout and marks the one a Context would pick.
void run_devices(const GlobalArguments& global) {
    const std::vector<DeviceInfo> devices = list_devices();
    if (devices.empty()) throw device_error("no OpenCL device found (is an ICD such as pocl-opencl-icd installed?)");

    // The device a Context would pick with these options and the environment.
    const Context context(global.selection());
    const DeviceInfo& picked = context.device();
    const char* mark = global.device.empty() ? "  [default]" : "  [selected]";

    for (const DeviceInfo& device : devices) {
        const char* type = device.is_gpu ? "GPU" : device.is_cpu ? "CPU" : "other";
        const bool is_picked =
            device.platform_index == picked.platform_index && device.device_index == picked.device_index;
        std::cout << device.platform_index << ':' << device.device_index << "  " << device.name << "  (" << type
                  << ", driver " << device.driver_version << ", platform " << device.platform_name << ")"
                  << (is_picked ? mark : "") << '\n';
    }
    std::cout.flush();
}

} // namespace

Subcommand add_devices_command(CLI::App& app) {
    CLI::App* devices_command = app.add_subcommand("devices", "List OpenCL devices; marks the one msmcl picks");
    return {devices_command, [](const GlobalArguments& global) {
                run_devices(global);
                return 0;
            }};
}

} // namespace msmcl::cli
