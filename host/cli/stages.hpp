// Stages of one msmcl command, timed for --verbose and shown as progress on a terminal.
//  - --verbose: one line per stage on stderr, "msmcl: <stage>: <ms> ms[ (<note>)]";
//  - stderr a terminal (and not --verbose): a progress line on stderr, redrawn while work
//    has run for more than half a second (MSMCL_PROGRESS_AFTER_MS), erased when the command
//    ends; nothing otherwise, so logs and pipes stay clean.
// The library never prints: the stages are timed here, around its calls.
#pragma once

#include "cli/progress.hpp"
#include "io/exr_io.hpp"

#include <msmcl/context.hpp>
#include <msmcl/types.hpp>

#include <chrono>
#include <cstddef>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace msmcl::cli {

class Stages {
public:
    /// `planned`: how many stages the command will run (the progress bar's length).
    Stages(bool verbose, int planned);
    ~Stages();
    Stages(const Stages&) = delete;
    Stages& operator=(const Stages&) = delete;

    bool verbose() const { return verbose_; }

    /// Runs `work` as the stage `name` and returns what it returns.
    template <class Work>
    auto run(const std::string& name, Work&& work) -> decltype(work()) {
        begin(name);
        if constexpr (std::is_void_v<decltype(work())>) {
            work();
            end();
        } else {
            auto result = work();
            end();
            return result;
        }
    }
    /// Text appended to the current stage's line (e.g. "1 program built").
    void note(const std::string& text) { note_ = text; }

private:
    void begin(const std::string& name);
    void end();
    /// The progress line's text: the bar over the planned stages, the current one, the time.
    std::string progress_text(double elapsed_s);

    bool verbose_ = false;
    int planned_ = 1;
    int done_ = 0;
    std::string note_;
    std::chrono::steady_clock::time_point stage_start_;

    // What the progress line shows, read by its drawing thread.
    std::mutex mutex_;
    std::string stage_;
    std::unique_ptr<ProgressLine> progress_;
};

/// How a DeviceBuffer holds the host array it is given: a copy made at creation, or, on
/// devices that share host memory (runtime/memory_strategy.hpp), the array itself, which
/// must then outlive the buffer: an input (copied elsewhere) or a result (elsewhere a
/// device buffer of its size), as the library's host calls do.
enum class HostArray { copy, input_in_place, result_in_place };

/// A device buffer of the CLI's staged uploads, released on destruction.
class DeviceBuffer {
public:
    DeviceBuffer(Context& context, std::size_t bytes, const void* data = nullptr, HostArray use = HostArray::copy);
    ~DeviceBuffer();
    DeviceBuffer(const DeviceBuffer&) = delete;
    DeviceBuffer& operator=(const DeviceBuffer&) = delete;
    cl_mem get() const { return memory_; }
    bool in_place() const { return in_place_; }
    /// Blocking read of the whole buffer (a map and unmap when it is `data` in place).
    void read(Context& context, void* data) const;

private:
    cl_mem memory_ = nullptr;
    std::size_t bytes_ = 0;
    bool in_place_ = false;
};

/// A depth map and its translucent layers in device buffers, as filter() and build_sat() take
/// them: the depths, then the layers' depths and opacities layer after layer.
struct DeviceLayeredDepth {
    std::unique_ptr<DeviceBuffer> depth, layer_depth, layer_opacity;
    DeviceDepth depth_view() const;
    DeviceLayers layers_view() const;

    int width = 0, height = 0, samples = 0, layer_count = 0;
    int array_layers = 1; ///< the layers of a texture array (DepthImage::layers)
};

/// The "upload" stage of filter and sat: `layered` into device buffers (noting the bytes);
/// the depth stays in place on devices that share host memory, so `layered` must outlive
/// the buffers.
DeviceLayeredDepth upload_layered_depth(Stages& stages, Context& context, const io::TranslucentDepth& layered);

} // namespace msmcl::cli
