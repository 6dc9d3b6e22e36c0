// Everything msmcl knows about particular devices and drivers, in one place.
#pragma once

#include <msmcl/context.hpp>

#include <optional>
#include <string>

namespace msmcl::detail {

/// PoCL (the portable CPU implementation CI runs on).
inline bool is_pocl(const DeviceInfo& device) {
    return device.platform_name.find("Portable Computing Language") != std::string::npos ||
           device.driver_version.find("pocl") != std::string::npos ||
           device.opencl_version.find("pocl") != std::string::npos;
}

/// Oclgrind, the OpenCL simulator that checks every memory access of the kernels for races
/// and uninitialized values (tests/oclgrind_test.cpp, docs/devices.md).
inline bool is_oclgrind(const DeviceInfo& device) { return device.name == "Oclgrind Simulator"; }

/// Build options a device needs besides the program's own, for the embedded program
/// `program` ("shade.cl").
///
/// PoCL's compiler prints its diagnostics ("2 warnings generated.") straight to the
/// process's stderr, which would break the CLI's one-line error contract: silence warnings
/// there (the build log still carries errors).
///
/// Oclgrind 21.10 (Debian 12) runs LLVM 14 IR and lacks a few of its parts; each option
/// steers clang around one of them, none changes what a kernel computes:
///  - `-fno-inline -Dalways_inline=noinline -Dflatten=noinline`: the inliner emits
///    `llvm.experimental.noalias.scope.decl` for struct returns and `restrict` arguments,
///    which Oclgrind cannot execute (kernel creation fails); with no inlining none is made.
///  - `-D__builtin_floorf=floor -D__builtin_ceilf=ceil`: it has no `llvm.floor` and
///    `llvm.ceil`; OpenCL's floor() and ceil() give the same IEEE results.
///  - `-U__clang__`: its uninitialized-value checker takes a shufflevector lane index of 16
///    for "undefined" (it compares the mask with LLVM's `Value::UndefValueVal`, which is 16
///    in LLVM 14) and reports false uses of uninitialized values; without `__clang__` the
///    kernels take their portable shuffle2() path (kernels/sat_build_cpu.cl).
///  - shade.cl at `-cl-opt-disable`: LLVM's DivRemPairs pass turns the dithered lookup's
///    `i / width` and `i % width` into a `freeze`, an instruction the uninitialized-value
///    checker refuses (fatal error); unoptimized code has none.
///    The soft-shadow kernel's filter parts (kernels/msm_sat.clh) avoid the pair altogether:
///    nested loops over the parts' rows and columns instead of one loop with / and %.
inline std::string device_build_options(const DeviceInfo& device, const std::string& program) {
    if (is_pocl(device)) return "-w";
    if (is_oclgrind(device)) {
        std::string options = "-fno-inline -Dalways_inline=noinline -Dflatten=noinline "
                              "-D__builtin_floorf=floor -D__builtin_ceilf=ceil -U__clang__";
        if (program == "shade.cl") options += " -cl-opt-disable";
        return options;
    }
    return "";
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
