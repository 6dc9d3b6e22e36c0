// OpenEXR files of msmcl: depth maps in, filtered textures out and back, receivers,
// shading results, and a generic reader/writer for tools and tests.
// Every error is an msmcl::input_error (or msmcl::error for a failed write) whose
// message starts with the file name: "<file>: <problem>".
// Every write is atomic (see atomic_file.hpp) and byte-deterministic: ZIP compression,
// no time stamps, attributes only as given.
// One file per layout (exr_depth.cpp, exr_translucent_depth.cpp, exr_receivers.cpp,
// exr_texture.cpp, exr_intensity.cpp) over exr_file.hpp, the opened and checked file and
// the generic reader and writer; exr_header_check.hpp checks a header before OpenEXR does.
#pragma once

#include <msmcl/types.hpp>

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

namespace msmcl::io {

/// Largest accepted data window side; anything bigger is treated as a corrupt header.
inline constexpr int max_image_side = 65536;

/// Pixel type of an EXR channel.
enum class SampleType { uint32, half, float32 };

/// One channel of an ExrImage, row-major over its own samples
/// (width/x_sampling by height/y_sampling).
struct ExrChannel {
    std::string name;
    SampleType type = SampleType::float32;
    std::vector<float> values;         ///< half and float32 channels
    std::vector<std::uint32_t> codes;  ///< uint32 channels
    int x_sampling = 1;
    int y_sampling = 1;
};

/// A header attribute of one of the three kinds msmcl uses.
struct ExrAttribute {
    std::string name;
    std::variant<std::string, float, int> value;
};

/// A whole single-part EXR image.
struct ExrImage {
    int width = 0;
    int height = 0;
    int x_origin = 0; ///< data window minimum corner
    int y_origin = 0;
    bool tiled = false; ///< write 32x32 tiles instead of scanlines
    std::vector<ExrChannel> channels;
    std::vector<ExrAttribute> attributes;

    const ExrChannel* find_channel(const std::string& name) const;
    const ExrAttribute* find_attribute(const std::string& name) const;
};

/// Writes any image (tools, tests). Validates that each channel holds exactly its
/// number of samples.
void write_exr(const std::string& path, const ExrImage& image);
/// Reads every channel (uint32 into `codes`, half and float into `values`) and the
/// string, float and int attributes of the first part of a scanline or tiled file.
/// Subsampled channels are rejected.
ExrImage read_exr(const std::string& path);

/// A depth map: channel `Z` (one sample) or `sample0.Z .. sample<S-1>.Z`, HALF or FLOAT,
/// S in {1, 2, 4, 8, 16}. Every depth must be finite and inside `range`; the first bad
/// texel is named in the error.
DepthImage read_depth_exr(const std::string& path, DepthRange range);
/// Writes `Z` for one sample, else `sample<s>.Z` layers, as FLOAT or HALF.
void write_depth_exr(const std::string& path, const DepthImage& depth,
                     SampleType type = SampleType::float32);

/// A depth map with translucent layers (docs/math.md).
struct TranslucentDepth {
    DepthImage depth;
    std::vector<TranslucentLayer> layers;
};
/// The opaque depth as read_depth_exr reads it, plus layers k = 0, 1, ... (at most
/// max_translucent_layers, numbered without gaps, in any order of the channels): per layer
/// `layer<k>.Z` and `layer<k>.A` (depth and opacity, one value for every sample of the
/// texel), or with S > 1 samples `layer<k>.sample<s>.Z` and `layer<k>.sample<s>.A` for
/// every s. HALF or FLOAT; depths finite and in `range`, opacities in [0, 1]. A file
/// without layers gives an empty list.
TranslucentDepth read_translucent_depth_exr(const std::string& path, DepthRange range);
/// Writes the opaque depth as write_depth_exr, and each layer per sample (`layer<k>.Z`,
/// `layer<k>.A` for one sample, else `layer<k>.sample<s>.Z`, `layer<k>.sample<s>.A`).
void write_translucent_depth_exr(const std::string& path, const TranslucentDepth& depth,
                                 SampleType type = SampleType::float32);

/// Receiver points on a width x height grid (row-major), e.g. the pixels of a view.
struct ReceiverGrid {
    int width = 0;
    int height = 0;
    Receivers points;
    /// Optional screen pixel of each receiver (channels `PX`, `PY`); empty when the file has
    /// none (the receivers are then the row-major pixels of the grid).
    ReceiverPixels pixels;
};
/// FLOAT (or HALF) channels `U`, `V`, `Z`, all finite; optionally `PX` and `PY` (both or
/// neither; UINT, or HALF/FLOAT holding whole numbers in [0, 2^24]).
ReceiverGrid read_receivers_exr(const std::string& path);
/// Writes `U`, `V`, `Z` as FLOAT, and `PX`, `PY` as UINT when the grid has pixels.
void write_receivers_exr(const std::string& path, const ReceiverGrid& receivers);

/// What a filtered texture file records besides its texels.
struct TextureInfo {
    float sigma = 2.4f;
    int samples = 1;
    DepthRange depth_range = DepthRange::zero_one;
};
struct TextureFile {
    Texture texture;
    TextureInfo info;
};
/// docs/formats.md: moments128 as FLOAT R,G,B,A (b1..b4); msm64 and nlq64 as UINT R,G,B,A
/// holding the 16-bit codes; nlq32 as one UINT R; attributes msmcl:format (string),
/// msmcl:sigma (float), msmcl:samples (int), msmcl:depthRange (string).
void write_texture_exr(const std::string& path, const Texture& texture, const TextureInfo& info);
/// Reads a file written by write_texture_exr back bit-exactly, validating the format
/// attribute, the channel set and types, code ranges and the other attributes.
TextureFile read_texture_exr(const std::string& path);

/// Shadow intensities (or any scalar image) as one FLOAT channel `Y`.
void write_intensity_exr(const std::string& path, int width, int height,
                         const std::vector<float>& intensity);

} // namespace msmcl::io
