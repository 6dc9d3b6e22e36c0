#include "cli/stages.hpp"

#include "runtime/memory_strategy.hpp"

#include <msmcl/errors.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace msmcl::cli {
namespace {

double milliseconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

Stages::Stages(bool verbose, int planned) : verbose_(verbose), planned_(planned > 0 ? planned : 1) {
    // --verbose prints lines instead of the progress line.
    progress_ = std::make_unique<ProgressLine>(!verbose_, [this](double elapsed_s) { return progress_text(elapsed_s); });
}

Stages::~Stages() = default;

void Stages::begin(const std::string& name) {
    note_.clear();
    stage_start_ = std::chrono::steady_clock::now();
    std::lock_guard<std::mutex> lock(mutex_);
    stage_ = name;
}

void Stages::end() {
    const double ms = milliseconds_since(stage_start_);
    std::string name;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        name = stage_;
        ++done_;
    }
    if (verbose_) {
        std::fprintf(stderr, "msmcl: %s: %.1f ms%s\n", name.c_str(), ms, note_.empty() ? "" : (" (" + note_ + ")").c_str());
        std::fflush(stderr);
    }
}

std::string Stages::progress_text(double elapsed_s) {
    std::lock_guard<std::mutex> lock(mutex_);
    char text[256];
    std::snprintf(text, sizeof text, "msmcl: %s %d/%d %s %.1f s",
                  progress_bar(static_cast<std::size_t>(done_), static_cast<std::size_t>(planned_)).c_str(),
                  std::min(done_ + 1, planned_), planned_, stage_.c_str(), elapsed_s);
    return text;
}

DeviceBuffer::DeviceBuffer(Context& context, std::size_t bytes, const void* data, HostArray use) : bytes_(bytes) {
    cl_int status = CL_SUCCESS;
    in_place_ = data && bytes > 0 && use != HostArray::copy && detail::shares_host_memory(context.device());
    const bool copied = data && !in_place_ && use != HostArray::result_in_place;
    const cl_mem_flags flags =
        CL_MEM_READ_WRITE | (in_place_ ? CL_MEM_USE_HOST_PTR : 0) | (copied ? CL_MEM_COPY_HOST_PTR : 0);
    memory_ = clCreateBuffer(context.cl_context_handle(), flags, bytes > 0 ? bytes : 4,
                             in_place_ || copied ? const_cast<void*>(data) : nullptr, &status);
    if (status != CL_SUCCESS) throw opencl_error(status, "clCreateBuffer", std::to_string(bytes) + " bytes");
}

DeviceBuffer::~DeviceBuffer() {
    if (memory_) clReleaseMemObject(memory_);
}

void DeviceBuffer::read(Context& context, void* data) const {
    if (bytes_ == 0) return;
    cl_int status = CL_SUCCESS;
    if (!in_place_) {
        status = clEnqueueReadBuffer(context.cl_queue_handle(), memory_, CL_TRUE, 0, bytes_, data, 0, nullptr, nullptr);
        if (status != CL_SUCCESS) throw opencl_error(status, "clEnqueueReadBuffer");
        return;
    }
    // Mapping makes the host array hold the result; unmapping hands the buffer back.
    void* mapped = clEnqueueMapBuffer(context.cl_queue_handle(), memory_, CL_TRUE, CL_MAP_READ, 0, bytes_, 0, nullptr,
                                      nullptr, &status);
    if (status != CL_SUCCESS) throw opencl_error(status, "clEnqueueMapBuffer");
    status = clEnqueueUnmapMemObject(context.cl_queue_handle(), memory_, mapped, 0, nullptr, nullptr);
    if (status == CL_SUCCESS) status = clFinish(context.cl_queue_handle());
    if (status != CL_SUCCESS) throw opencl_error(status, "clEnqueueUnmapMemObject");
}

DeviceDepth DeviceLayeredDepth::depth_view() const { return {depth->get(), width, height, samples, array_layers}; }

DeviceLayers DeviceLayeredDepth::layers_view() const {
    if (layer_count == 0) return {};
    return {layer_depth->get(), layer_opacity->get(), layer_count};
}

DeviceLayeredDepth upload_layered_depth(Stages& stages, Context& context, const io::TranslucentDepth& layered) {
    const DepthImage& depth = layered.depth;
    // The layers one after another, as the device calls take them; for a texture array, the
    // translucent layers of array layer 0, then those of array layer 1, ... (DeviceLayers).
    std::vector<float> layer_depth, layer_opacity;
    const std::size_t slice = depth.depth.size() / static_cast<std::size_t>(std::max(depth.layers, 1));
    for (int a = 0; a < depth.layers; ++a)
        for (const TranslucentLayer& layer : layered.layers) {
            const auto from = static_cast<std::ptrdiff_t>(slice * static_cast<std::size_t>(a));
            const auto to = from + static_cast<std::ptrdiff_t>(slice);
            layer_depth.insert(layer_depth.end(), layer.depth.begin() + from, layer.depth.begin() + to);
            layer_opacity.insert(layer_opacity.end(), layer.opacity.begin() + from, layer.opacity.begin() + to);
        }
    DeviceLayeredDepth device;
    device.width = depth.width;
    device.height = depth.height;
    device.samples = depth.samples;
    device.array_layers = depth.layers;
    device.layer_count = static_cast<int>(layered.layers.size());
    stages.run("upload", [&] {
        device.depth = std::make_unique<DeviceBuffer>(context, depth.depth.size() * sizeof(float), depth.depth.data(),
                                                      HostArray::input_in_place);
        if (device.layer_count > 0) {
            device.layer_depth =
                std::make_unique<DeviceBuffer>(context, layer_depth.size() * sizeof(float), layer_depth.data());
            device.layer_opacity =
                std::make_unique<DeviceBuffer>(context, layer_opacity.size() * sizeof(float), layer_opacity.data());
        }
        context.finish();
        stages.note(std::to_string((depth.depth.size() + layer_depth.size() + layer_opacity.size()) * sizeof(float)) +
                    " bytes" + (device.depth->in_place() ? ", the depth in place" : ""));
    });
    return device;
}

} // namespace msmcl::cli
