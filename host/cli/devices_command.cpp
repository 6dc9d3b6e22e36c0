#include "cli/devices_command.hpp"

#include <msmcl/filter.hpp>
#include <msmcl/sat.hpp>

#include <iostream>
#include <string>
#include <vector>

namespace msmcl::cli {
namespace {

/// --verbose: the work distributions the automatic choice gives on the picked device, and
/// why (docs/devices.md). The filter's choice depends on the built kernels' limits, so a
/// 16x16 map is filtered in the 64-bit and 32-bit formats to find it out.
void print_kernel_choices(const GlobalArguments& global) {
    Context context(global.selection());
    DepthImage depth;
    depth.width = 16;
    depth.height = 16;
    depth.depth.assign(16 * 16, 0.5f);
    std::cout << "automatic choices on " << context.device().name << ":\n";
    for (Format format : {Format::msm64, Format::nlq32}) {
        FilterOptions options;
        options.format = format;
        filter(context, depth, options);
        for (const std::string& line : context.kernel_choices())
            std::cout << "  " << format_name(format) << " " << line << '\n';
    }
    std::cout << "  sat: " << sat_kernel_name(sat_kernel_for(context, SatKernel::automatic)) << '\n';
    std::cout.flush();
}

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
    if (global.verbose) print_kernel_choices(global);
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
