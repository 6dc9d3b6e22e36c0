// The OpenCL runtime layer: device choice, embedded sources, program cache, errors.
#include "runtime/context_impl.hpp"
#include "runtime/kernel_sources.hpp"
#include "runtime/quirks.hpp"
#include "runtime/work_distribution.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <unistd.h>
#include <filesystem>

namespace {

bool have_device() { return !msmcl::list_devices().empty(); }

TEST(OpenclErrorNames, KnownAndUnknownCodes) {
    EXPECT_STREQ(msmcl::opencl_error_name(CL_INVALID_VALUE), "CL_INVALID_VALUE");
    EXPECT_STREQ(msmcl::opencl_error_name(CL_BUILD_PROGRAM_FAILURE), "CL_BUILD_PROGRAM_FAILURE");
    EXPECT_STREQ(msmcl::opencl_error_name(-12345), "CL_UNKNOWN_ERROR");
    const msmcl::opencl_error e(CL_OUT_OF_RESOURCES, "clEnqueueNDRangeKernel", "filter");
    EXPECT_EQ(e.code(), CL_OUT_OF_RESOURCES);
    EXPECT_STREQ(e.name(), "CL_OUT_OF_RESOURCES");
    EXPECT_NE(std::string(e.what()).find("clEnqueueNDRangeKernel: CL_OUT_OF_RESOURCES (-5): filter"),
              std::string::npos);
}

TEST(EmbeddedKernels, EveryKernelFileIsEmbeddedAndIncludesResolve) {
    const auto names = msmcl::detail::embedded_kernel_names();
    ASSERT_FALSE(names.empty());
    // Every file in kernels/ of the source tree is in the library.
    for (const auto& entry : std::filesystem::directory_iterator(MSMCL_SOURCE_DIR "/kernels")) {
        const std::string file = entry.path().filename().string();
        EXPECT_NE(std::find(names.begin(), names.end(), file), names.end()) << file << " not embedded";
    }
    // Assembled sources carry no quoted #include line left (comments may mention one).
    for (const std::string& name : names) {
        const std::string source = msmcl::detail::assemble_kernel_source(name);
        EXPECT_EQ(source.find("\n#include \""), std::string::npos) << name;
        EXPECT_NE(source.rfind("#include \"", 0), 0u) << name;
    }
    EXPECT_THROW(msmcl::detail::embedded_kernel_file("no_such_file.cl"), msmcl::error);
}

// `automatic` gives the GPU distributions to any device that reports GPU (Oclgrind reports
// CPU|GPU|ACCELERATOR) or neither type, the CPU ones only to a CPU that is not a GPU; the
// Oclgrind build options are keyed on its device name and come with none else.
TEST(DeviceQuirks, DistributionAndOclgrindOptions) {
    msmcl::DeviceInfo oclgrind;
    oclgrind.name = "Oclgrind Simulator";
    oclgrind.platform_name = "Oclgrind";
    oclgrind.is_cpu = oclgrind.is_gpu = true;
    msmcl::DeviceInfo cpu;
    cpu.name = "pthread-skylake";
    cpu.platform_name = "Portable Computing Language";
    cpu.is_cpu = true;
    msmcl::DeviceInfo accelerator;
    accelerator.name = "FPGA";
    EXPECT_TRUE(msmcl::detail::prefers_gpu_distribution(oclgrind));
    EXPECT_FALSE(msmcl::detail::prefers_gpu_distribution(cpu));
    EXPECT_TRUE(msmcl::detail::prefers_gpu_distribution(accelerator));
    EXPECT_TRUE(msmcl::detail::is_oclgrind(oclgrind));
    EXPECT_FALSE(msmcl::detail::is_oclgrind(cpu));
    const std::string options = msmcl::detail::device_build_options(oclgrind, "filter_fused_cpu.cl");
    EXPECT_NE(options.find("-fno-inline"), std::string::npos) << options;
    EXPECT_EQ(options.find("-cl-opt-disable"), std::string::npos) << options;
    EXPECT_NE(msmcl::detail::device_build_options(oclgrind, "shade.cl").find("-cl-opt-disable"), std::string::npos);
    EXPECT_EQ(msmcl::detail::device_build_options(cpu, "shade.cl"), "-w");
    EXPECT_EQ(msmcl::detail::device_build_options(accelerator, "shade.cl"), "");
}

TEST(DeviceFilters, ComposeAndParse) {
    msmcl::DeviceInfo gpu;
    gpu.name = "NVIDIA GeForce GTX 970";
    gpu.platform_name = "NVIDIA CUDA";
    gpu.is_gpu = true;
    gpu.platform_index = 1;
    gpu.device_index = 0;
    msmcl::DeviceInfo cpu;
    cpu.name = "pthread-skylake";
    cpu.platform_name = "Portable Computing Language";
    cpu.is_cpu = true;
    using F = msmcl::DeviceFilter;
    EXPECT_TRUE(F::parse("gpu")(gpu));
    EXPECT_FALSE(F::parse("gpu")(cpu));
    EXPECT_TRUE(F::parse("geforce")(gpu));
    EXPECT_TRUE(F::parse("1:0")(gpu));
    EXPECT_FALSE(F::parse("0:0")(gpu));
    EXPECT_TRUE((F::cpu() || F::name_contains("gtx"))(gpu));
    EXPECT_FALSE((F::cpu() && F::name_contains("gtx"))(gpu));
    EXPECT_TRUE((!F::gpu())(cpu));
    EXPECT_TRUE(F::parse_platform("portable")(cpu));
    EXPECT_TRUE(msmcl::detail::is_pocl(cpu));
    EXPECT_FALSE(msmcl::detail::is_pocl(gpu));
}

TEST(DeviceSelection, StrictSelectionOfAMissingDeviceThrows) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    msmcl::DeviceSelection selection;
    selection.device = "no-such-device-anywhere";
    selection.strict = true;
    EXPECT_THROW(msmcl::Context{selection}, msmcl::device_error);
    // Not strict: falls back to the default device.
    selection.strict = false;
    msmcl::Context fallback(selection);
    EXPECT_FALSE(fallback.device().name.empty());
}

TEST(ProgramCache, BuildsOnceAndReportsBuildLogs) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    msmcl::Context context;
    auto& impl = context.impl();
    const std::string source = "__kernel void twice(__global float* x) { x[get_global_id(0)] *= 2.0f; }\n";
    const std::size_t before = context.programs_built();
    cl::Kernel& first = impl.programs.kernel(impl.context, impl.device, "twice.cl", source, "", "twice");
    cl::Kernel& again = impl.programs.kernel(impl.context, impl.device, "twice.cl", source, "", "twice");
    EXPECT_EQ(&first, &again);
    EXPECT_EQ(context.programs_built(), before + 1);

    // A broken program throws build_error carrying the compiler's log.
    try {
        impl.programs.program(impl.context, impl.device, "broken.cl", "__kernel void f() { undeclared = 1; }", "");
        FAIL() << "expected build_error";
    } catch (const msmcl::build_error& e) {
        EXPECT_STREQ(e.name(), "CL_BUILD_PROGRAM_FAILURE");
        EXPECT_NE(e.log().find("undeclared"), std::string::npos) << e.log();
        EXPECT_NE(std::string(e.what()).find("broken.cl"), std::string::npos);
    }
}

TEST(ProgramCache, DiskCacheReloadsBinaries) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    const auto dir = std::filesystem::temp_directory_path() / ("msmcl-cache-test-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string source = "__kernel void add1(__global int* x) { x[get_global_id(0)] += 1; }\n";
    {
        msmcl::Context context;
        context.set_binary_cache_dir(dir.string());
        auto& impl = context.impl();
        impl.programs.kernel(impl.context, impl.device, "add1.cl", source, "", "add1");
        EXPECT_EQ(context.programs_built(), 1u);
    }
    std::size_t files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) files += entry.path().extension() == ".bin";
    EXPECT_EQ(files, 1u);
    {
        msmcl::Context context;
        context.set_binary_cache_dir(dir.string());
        auto& impl = context.impl();
        cl::Kernel& kernel = impl.programs.kernel(impl.context, impl.device, "add1.cl", source, "", "add1");
        EXPECT_EQ(context.programs_built(), 0u) << "the binary should come from the disk cache";
        // And the cached binary runs.
        cl_int status = CL_SUCCESS;
        int value = 41;
        cl::Buffer buffer(impl.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, sizeof value, &value, &status);
        ASSERT_EQ(status, CL_SUCCESS);
        kernel.setArg(0, buffer);
        ASSERT_EQ(impl.queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(1)), CL_SUCCESS);
        ASSERT_EQ(impl.queue.enqueueReadBuffer(buffer, CL_TRUE, 0, sizeof value, &value), CL_SUCCESS);
        EXPECT_EQ(value, 42);
    }
    std::filesystem::remove_all(dir);
}

TEST(Context, WrapsAnEnginesHandles) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    msmcl::Context owner;
    msmcl::Context borrowed(owner.cl_context_handle(), owner.cl_device_handle(), owner.cl_queue_handle());
    EXPECT_EQ(borrowed.cl_context_handle(), owner.cl_context_handle());
    EXPECT_EQ(borrowed.cl_queue_handle(), owner.cl_queue_handle());
    EXPECT_EQ(borrowed.device().name, owner.device().name);
    EXPECT_THROW(msmcl::Context(nullptr, nullptr), msmcl::input_error);
}

} // namespace
