// Typed exceptions thrown by every msmcl call. The library never prints.
#pragma once

#include <stdexcept>
#include <string>

namespace msmcl {

/// Base of every exception the library throws.
class error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// The caller's data or arguments are unusable (bad size, NaN depth, unknown format...).
/// The CLI maps it to exit code 2.
class input_error : public error {
public:
    using error::error;
};

/// An OpenCL call failed. `code()` is the raw cl_int, `name()` its readable name
/// ("CL_OUT_OF_RESOURCES"); what() reads "<call>: <name> (<code>)[: detail]".
class opencl_error : public error {
public:
    opencl_error(int code, const std::string& call, const std::string& detail = {});
    int code() const noexcept { return code_; }
    const char* name() const noexcept;

private:
    int code_;
};

/// clBuildProgram failed; `log()` is the device's full build log.
class build_error : public opencl_error {
public:
    build_error(int code, const std::string& program, const std::string& options, std::string log);
    const std::string& log() const noexcept { return log_; }

private:
    std::string log_;
};

/// No OpenCL platform/device matches the request (strict selection, or none at all).
class device_error : public error {
public:
    using error::error;
};

/// An explicitly requested work distribution (FilterKernel, SatKernel, ScatterKernel) that
/// the device's built kernels cannot run: too many work-items per group or too much local
/// memory; the message names the limit. A usage choice (the CLI exits 2), where `automatic`
/// would have picked a distribution that fits.
class unfit_kernel_error : public device_error {
public:
    using device_error::device_error;
};

/// Readable name of an OpenCL error code ("CL_INVALID_VALUE"), "CL_UNKNOWN_ERROR" if unknown.
const char* opencl_error_name(int code) noexcept;

} // namespace msmcl
