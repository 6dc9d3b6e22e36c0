// The parts every EXR layout of msmcl (exr_io.hpp) shares: an opened file whose header
// passed the checks of exr_header_check.hpp (ExrReader), the header msmcl writes and the
// atomic write of a whole image, and the words of error messages. Internal to msmcl_io.
#pragma once

#include "io/exr_io.hpp"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfPixelType.h>

#include <cstddef>
#include <exception>
#include <memory>
#include <string>
#include <vector>

namespace msmcl::io::exr {

/// Throws input_error "<path>: <problem>".
[[noreturn]] void fail(const std::string& path, const std::string& problem);

/// OpenEXR decodes and encodes the blocks of a file on its global thread pool: give it
/// one thread per hardware thread, once, unless the program has chosen a count itself.
int openexr_threads();

/// OpenEXR's message without the quoted file name it repeats (ours leads the line).
std::string openexr_problem(const std::string& path, const std::exception& e);

/// "1.5", "NaN", "+Inf": how a bad value appears in a message.
std::string describe_value(double value);

std::string texel_name(long long x, long long y);

const char* sample_type_name(Imf::PixelType type);

Imf::PixelType to_pixel_type(SampleType type);

/// An opened EXR file whose header passed the checks every msmcl reader needs: a real
/// OpenEXR file, not deep, a data window that is neither empty nor absurd, and no
/// subsampled channels. OpenEXR's exceptions become input_error naming the file.
class ExrReader {
public:
    explicit ExrReader(const std::string& path);

    const std::string& path() const { return path_; }
    const Imf::Header& header() const { return file_->header(); }
    const Imath::Box2i data_window() const { return header().dataWindow(); }
    int width() const { return width_; }
    int height() const { return height_; }
    std::size_t texel_count() const { return static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_); }

    /// The channel of that name, or null.
    const Imf::Channel* find_channel(const std::string& name) const {
        return header().channels().findChannel(name);
    }
    std::vector<std::string> channel_names() const {
        std::vector<std::string> names;
        for (auto it = header().channels().begin(); it != header().channels().end(); ++it) names.push_back(it.name());
        return names;
    }

    /// Reads all rows into the slices of `frame_buffer`.
    void read(const Imf::FrameBuffer& frame_buffer) {
        try {
            file_->setFrameBuffer(frame_buffer);
            const Imath::Box2i window = data_window();
            file_->readPixels(window.min.y, window.max.y);
        } catch (const std::exception& e) {
            fail(path_, openexr_problem(path_, e));
        }
    }

    /// A FLOAT slice that writes channel values with the given strides into `base`
    /// (base = the value of the data window's first texel).
    Imf::Slice float_slice(float* base, std::size_t x_stride, std::size_t y_stride) const {
        return Imf::Slice::Make(Imf::FLOAT, base, data_window(), x_stride, y_stride);
    }

private:
    std::string path_;
    std::unique_ptr<Imf::IStream> stream_;
    std::unique_ptr<Imf::InputFile> file_;
    int width_ = 0;
    int height_ = 0;
};

/// "A, B, G, R" (at most 8 names) for messages.
std::string list_names(const std::vector<std::string>& names);

/// Requires a HALF or FLOAT channel `name`; `purpose` says what it is for in messages.
void require_float_channel(const ExrReader& reader, const std::string& name, const std::string& purpose);

/// The header msmcl writes for `image`: display window = data window, ZIP, the image's
/// channels and attributes and nothing else (the channels' data is not looked at).
Imf::Header exr_header(const ExrImage& image);

/// Writes `image` (validated, ZIP, deterministic) atomically.
void write_exr_atomically(const std::string& path, const ExrImage& image);

// --- shared by the layouts, defined in exr_depth.cpp

/// read_depth_exr on an opened file (read_translucent_depth_exr reads its layers from the
/// same one).
DepthImage read_depth(ExrReader& reader, DepthRange range);

/// The sample counts msmcl reads and writes: 1, 2, 4, 8 or 16.
bool is_supported_samples(int samples);

} // namespace msmcl::io::exr
