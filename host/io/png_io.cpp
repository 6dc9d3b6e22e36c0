#include "io/png_io.hpp"

#include "io/atomic_file.hpp"

#include <msmcl/errors.hpp>

#include <png.h>

#include <cmath>
#include <csetjmp>
#include <cstdint>

namespace msmcl::io {
namespace {

void append_bytes(png_structp png, png_bytep data, png_size_t length) {
    auto* bytes = static_cast<std::vector<unsigned char>*>(png_get_io_ptr(png));
    bytes->insert(bytes->end(), data, data + length);
}
void flush_nothing(png_structp) {}

/// Encodes 8-bit rows with libpng into `encoded`; false (and libpng's message) on failure.
/// No C++ object is created after setjmp, so a longjmp skips no destructor.
bool encode_png(int width, int height, int channels, const std::vector<png_bytep>& rows,
                std::vector<unsigned char>& encoded) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    if (!png) return false;
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        return false;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, &encoded, append_bytes, flush_nothing);
    png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
                 channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 6);
    png_write_info(png, info);
    png_write_image(png, const_cast<png_bytepp>(rows.data()));
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return true;
}

} // namespace

void write_png_preview(const std::string& path, int width, int height, int channels,
                       const std::vector<float>& values, float black, float white) {
    if (width <= 0 || height <= 0 || (channels != 1 && channels != 3) ||
        values.size() != static_cast<std::size_t>(width) * height * channels)
        throw input_error(path + ": preview image size does not match its data");
    if (!(white != black) || !std::isfinite(black) || !std::isfinite(white))
        throw input_error(path + ": preview needs finite black and white levels that differ");

    // Map to 8 bits.
    std::vector<unsigned char> pixels(values.size());
    const double scale = 255.0 / (static_cast<double>(white) - black);
    for (std::size_t i = 0; i < values.size(); ++i) {
        const double level = std::isnan(values[i]) ? 0.0 : (values[i] - static_cast<double>(black)) * scale;
        pixels[i] = static_cast<unsigned char>(std::lround(std::fmin(255.0, std::fmax(0.0, level))));
    }
    std::vector<png_bytep> rows(static_cast<std::size_t>(height));
    for (int y = 0; y < height; ++y)
        rows[static_cast<std::size_t>(y)] = pixels.data() + static_cast<std::size_t>(y) * width * channels;

    // Encode in memory, then publish atomically.
    std::vector<unsigned char> encoded;
    if (!encode_png(width, height, channels, rows, encoded)) throw error(path + ": PNG encoding failed");
    write_file_atomically(path, encoded.data(), encoded.size());
}

} // namespace msmcl::io
