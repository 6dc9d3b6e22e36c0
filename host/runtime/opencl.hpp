// The one place the Khronos C++ bindings are included, with the version pinned.
#pragma once

#ifndef CL_HPP_TARGET_OPENCL_VERSION
#define CL_HPP_TARGET_OPENCL_VERSION 120
#endif
#ifndef CL_HPP_MINIMUM_OPENCL_VERSION
#define CL_HPP_MINIMUM_OPENCL_VERSION 120
#endif
#include <CL/opencl.hpp>

#include <msmcl/errors.hpp>

namespace msmcl::detail {

/// Throws opencl_error naming `call` unless `status` is CL_SUCCESS.
inline void check(cl_int status, const char* call) {
    if (status != CL_SUCCESS) throw opencl_error(status, call);
}

/// Sets kernel argument `index`, throwing on failure. Raw cl_mem handles (a caller's
/// buffers) go through here too: the bindings' setArg refuses pointer types.
inline void set_arg(cl::Kernel& kernel, cl_uint index, cl_mem memory) {
    check(kernel.setArg(index, sizeof(cl_mem), &memory), "clSetKernelArg");
}
template <class T>
inline void set_arg(cl::Kernel& kernel, cl_uint index, const T& value) {
    check(kernel.setArg(index, value), "clSetKernelArg");
}

} // namespace msmcl::detail
