// How host data reaches a device and comes back: the one rule every host-memory path of
// the library follows (transfer.hpp), chosen by what the device reports (docs/devices.md).
#pragma once

#include <msmcl/context.hpp>

namespace msmcl::detail {

/// True when the device works on host memory in place: it reports
/// CL_DEVICE_HOST_UNIFIED_MEMORY (CPU devices such as PoCL's, integrated GPUs; discrete
/// GPUs report false). Such a device gets buffers
/// made with CL_MEM_USE_HOST_PTR over the caller's arrays and returns results through
/// clEnqueueMapBuffer on them: a driver that can alias the memory (PoCL does for any
/// pointer, integrated GPUs for page-aligned ones) then copies nothing, and one that
/// cannot copies once, as clEnqueueReadBuffer would. Other devices get a copy at creation
/// (CL_MEM_COPY_HOST_PTR) and clEnqueueReadBuffer.
inline bool shares_host_memory(const DeviceInfo& device) {
    return device.host_unified_memory;
}

} // namespace msmcl::detail
