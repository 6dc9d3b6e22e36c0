// How a device-side call joins the caller's command stream.
#pragma once

#include <CL/cl.h>

#include <vector>

namespace msmcl {

/// Queue and event plumbing for calls on caller-owned cl_mem objects.
/// `queue` null = the Context's own queue. The call waits for `wait_for`, and if
/// `done` is non-null stores a new event (the caller releases it) that completes
/// when the call's last command does. Nothing blocks unless `blocking` is set.
struct Enqueue {
    cl_command_queue queue = nullptr;
    std::vector<cl_event> wait_for;
    cl_event* done = nullptr;
    bool blocking = false;
};

} // namespace msmcl
