// Readable OpenCL error names and the exception types of errors.hpp.
#include <msmcl/errors.hpp>

#include <CL/cl.h>

namespace msmcl {

const char* opencl_error_name(int code) noexcept {
    switch (code) {
#define MSMCL_CL_ERROR(name) case name: return #name;
        MSMCL_CL_ERROR(CL_SUCCESS)
        MSMCL_CL_ERROR(CL_DEVICE_NOT_FOUND)
        MSMCL_CL_ERROR(CL_DEVICE_NOT_AVAILABLE)
        MSMCL_CL_ERROR(CL_COMPILER_NOT_AVAILABLE)
        MSMCL_CL_ERROR(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        MSMCL_CL_ERROR(CL_OUT_OF_RESOURCES)
        MSMCL_CL_ERROR(CL_OUT_OF_HOST_MEMORY)
        MSMCL_CL_ERROR(CL_PROFILING_INFO_NOT_AVAILABLE)
        MSMCL_CL_ERROR(CL_MEM_COPY_OVERLAP)
        MSMCL_CL_ERROR(CL_IMAGE_FORMAT_MISMATCH)
        MSMCL_CL_ERROR(CL_IMAGE_FORMAT_NOT_SUPPORTED)
        MSMCL_CL_ERROR(CL_BUILD_PROGRAM_FAILURE)
        MSMCL_CL_ERROR(CL_MAP_FAILURE)
        MSMCL_CL_ERROR(CL_MISALIGNED_SUB_BUFFER_OFFSET)
        MSMCL_CL_ERROR(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
        MSMCL_CL_ERROR(CL_COMPILE_PROGRAM_FAILURE)
        MSMCL_CL_ERROR(CL_LINKER_NOT_AVAILABLE)
        MSMCL_CL_ERROR(CL_LINK_PROGRAM_FAILURE)
        MSMCL_CL_ERROR(CL_DEVICE_PARTITION_FAILED)
        MSMCL_CL_ERROR(CL_KERNEL_ARG_INFO_NOT_AVAILABLE)
        MSMCL_CL_ERROR(CL_INVALID_VALUE)
        MSMCL_CL_ERROR(CL_INVALID_DEVICE_TYPE)
        MSMCL_CL_ERROR(CL_INVALID_PLATFORM)
        MSMCL_CL_ERROR(CL_INVALID_DEVICE)
        MSMCL_CL_ERROR(CL_INVALID_CONTEXT)
        MSMCL_CL_ERROR(CL_INVALID_QUEUE_PROPERTIES)
        MSMCL_CL_ERROR(CL_INVALID_COMMAND_QUEUE)
        MSMCL_CL_ERROR(CL_INVALID_HOST_PTR)
        MSMCL_CL_ERROR(CL_INVALID_MEM_OBJECT)
        MSMCL_CL_ERROR(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR)
        MSMCL_CL_ERROR(CL_INVALID_IMAGE_SIZE)
        MSMCL_CL_ERROR(CL_INVALID_SAMPLER)
        MSMCL_CL_ERROR(CL_INVALID_BINARY)
        MSMCL_CL_ERROR(CL_INVALID_BUILD_OPTIONS)
        MSMCL_CL_ERROR(CL_INVALID_PROGRAM)
        MSMCL_CL_ERROR(CL_INVALID_PROGRAM_EXECUTABLE)
        MSMCL_CL_ERROR(CL_INVALID_KERNEL_NAME)
        MSMCL_CL_ERROR(CL_INVALID_KERNEL_DEFINITION)
        MSMCL_CL_ERROR(CL_INVALID_KERNEL)
        MSMCL_CL_ERROR(CL_INVALID_ARG_INDEX)
        MSMCL_CL_ERROR(CL_INVALID_ARG_VALUE)
        MSMCL_CL_ERROR(CL_INVALID_ARG_SIZE)
        MSMCL_CL_ERROR(CL_INVALID_KERNEL_ARGS)
        MSMCL_CL_ERROR(CL_INVALID_WORK_DIMENSION)
        MSMCL_CL_ERROR(CL_INVALID_WORK_GROUP_SIZE)
        MSMCL_CL_ERROR(CL_INVALID_WORK_ITEM_SIZE)
        MSMCL_CL_ERROR(CL_INVALID_GLOBAL_OFFSET)
        MSMCL_CL_ERROR(CL_INVALID_EVENT_WAIT_LIST)
        MSMCL_CL_ERROR(CL_INVALID_EVENT)
        MSMCL_CL_ERROR(CL_INVALID_OPERATION)
        MSMCL_CL_ERROR(CL_INVALID_GL_OBJECT)
        MSMCL_CL_ERROR(CL_INVALID_BUFFER_SIZE)
        MSMCL_CL_ERROR(CL_INVALID_MIP_LEVEL)
        MSMCL_CL_ERROR(CL_INVALID_GLOBAL_WORK_SIZE)
        MSMCL_CL_ERROR(CL_INVALID_PROPERTY)
        MSMCL_CL_ERROR(CL_INVALID_IMAGE_DESCRIPTOR)
        MSMCL_CL_ERROR(CL_INVALID_COMPILER_OPTIONS)
        MSMCL_CL_ERROR(CL_INVALID_LINKER_OPTIONS)
        MSMCL_CL_ERROR(CL_INVALID_DEVICE_PARTITION_COUNT)
#undef MSMCL_CL_ERROR
        case -1001: return "CL_PLATFORM_NOT_FOUND_KHR";
        default: return "CL_UNKNOWN_ERROR";
    }
}

namespace {
std::string describe(int code, const std::string& call, const std::string& detail) {
    std::string text = call + ": " + opencl_error_name(code) + " (" + std::to_string(code) + ")";
    if (!detail.empty()) text += ": " + detail;
    return text;
}
} // namespace

opencl_error::opencl_error(int code, const std::string& call, const std::string& detail)
    : error(describe(code, call, detail)), code_(code) {}

const char* opencl_error::name() const noexcept { return opencl_error_name(code_); }

build_error::build_error(int code, const std::string& program, const std::string& options,
                         std::string log)
    : opencl_error(code, "clBuildProgram",
                   program + (options.empty() ? "" : " with '" + options + "'") +
                       " failed; build log:\n" + log),
      log_(std::move(log)) {}

} // namespace msmcl
