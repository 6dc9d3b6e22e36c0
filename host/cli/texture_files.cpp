#include "cli/texture_files.hpp"
#include "cli/option_values.hpp"

#include "io/dds.hpp"
#include "io/gpu_image.hpp"
#include "io/ktx2.hpp"

#include <msmcl/errors.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>

namespace msmcl::cli {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
    throw input_error(path + ": " + problem);
}

/// The extension of `path` in lower case, with its dot ("" when there is none).
std::string extension_of(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string extension = path.substr(dot);
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return extension;
}

std::optional<Container> container_of_extension(const std::string& path) {
    const std::string extension = extension_of(path);
    if (extension == ".exr") return Container::exr;
    if (extension == ".ktx2") return Container::ktx2;
    if (extension == ".dds") return Container::dds;
    return std::nullopt;
}

/// The value of KTX2 key `key` as a whole number in [lowest, highest], if present.
std::optional<long long> metadata_integer(const io::GpuImage& image, const std::string& path, const char* key,
                                          long long lowest, long long highest) {
    const std::optional<std::string> text = image.find_metadata(key);
    if (!text) return std::nullopt;
    char* end = nullptr;
    errno = 0;
    const long long value = std::strtoll(text->c_str(), &end, 10);
    if (text->empty() || end != text->c_str() + text->size() || errno == ERANGE || value < lowest || value > highest)
        fail(path, std::string("key ") + key + " is '" + *text + "', not a whole number in [" +
                       std::to_string(lowest) + ", " + std::to_string(highest) + "]");
    return value;
}

/// The record of a filtered map kept in KTX2 key/value data; defaults where a key is absent.
io::TextureInfo info_of(const io::GpuImage& image, const std::string& path) {
    io::TextureInfo info;
    if (const std::optional<std::string> sigma = image.find_metadata("msmcl:sigma")) {
        char* end = nullptr;
        const float value = std::strtof(sigma->c_str(), &end);
        if (sigma->empty() || end != sigma->c_str() + sigma->size() || !(value >= 0.0f) || value > 1e30f)
            fail(path, "key msmcl:sigma is '" + *sigma + "', not a sigma >= 0");
        info.sigma = value;
    }
    if (const std::optional<long long> samples = metadata_integer(image, path, "msmcl:samples", 1, 16))
        info.samples = static_cast<int>(*samples);
    if (const std::optional<std::string> range = image.find_metadata("msmcl:depthRange")) {
        const std::optional<DepthRange> parsed = parse_depth_range(*range);
        if (!parsed) fail(path, "key msmcl:depthRange is '" + *range + "', expected 0,1 or -1,1");
        info.depth_range = *parsed;
    }
    return info;
}

io::GpuImage read_gpu_image(const std::string& path, Container container) {
    return container == Container::ktx2 ? io::read_ktx2(path) : io::read_dds(path);
}

} // namespace

const char* container_name(Container container) noexcept {
    switch (container) {
    case Container::exr: return "exr";
    case Container::ktx2: return "ktx2";
    case Container::dds: return "dds";
    }
    return "exr";
}

Container output_container(const std::string& option, const std::string& path) {
    const std::optional<Container> by_extension = container_of_extension(path);
    if (option.empty()) {
        if (!by_extension)
            throw usage_error(path + ": unknown output extension '" + extension_of(path) +
                              "' (expected .exr, .ktx2 or .dds, or say --out-container exr|ktx2|dds)");
        return *by_extension;
    }
    Container chosen = Container::exr;
    if (option == "exr") chosen = Container::exr;
    else if (option == "ktx2") chosen = Container::ktx2;
    else if (option == "dds") chosen = Container::dds;
    else throw usage_error(unknown_value_message("--out-container", option, {"exr", "ktx2", "dds"}));
    if (by_extension && *by_extension != chosen)
        throw usage_error(path + ": the extension says " + container_name(*by_extension) + ", --out-container says " +
                          container_name(chosen));
    return chosen;
}

void require_exr_output(const std::string& path) {
    if (container_of_extension(path) != Container::exr)
        throw usage_error(path + ": unknown output extension '" + extension_of(path) +
                          "' (this output is written as OpenEXR: name it .exr)");
}

Container sniff_container(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) fail(path, "cannot open");
    std::array<unsigned char, 12> head{};
    file.read(reinterpret_cast<char*>(head.data()), head.size());
    const std::size_t got = static_cast<std::size_t>(file.gcount());
    // OpenEXR magic 76 2f 31 01; KTX2 identifier AB 4B 54 58 20 32 30 BB; DDS "DDS ".
    if (got >= 4 && head[0] == 0x76 && head[1] == 0x2f && head[2] == 0x31 && head[3] == 0x01) return Container::exr;
    static const unsigned char ktx2[8] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB};
    if (got >= 8 && std::equal(ktx2, ktx2 + 8, head.begin())) return Container::ktx2;
    if (got >= 4 && head[0] == 'D' && head[1] == 'D' && head[2] == 'S' && head[3] == ' ') return Container::dds;
    fail(path, "not an OpenEXR, KTX2 or DDS file");
}

io::TextureFile read_texture_file(const std::string& path, std::optional<Format> format) {
    const Container container = sniff_container(path);
    if (container == Container::exr) {
        io::TextureFile file = io::read_texture_exr(path);
        if (format && *format != file.texture.format)
            fail(path, std::string("holds a ") + format_name(file.texture.format) + " texture, --format says " +
                           format_name(*format));
        return file;
    }
    const io::GpuImage image = read_gpu_image(path, container);
    // The format: the file's record (KTX2), else the texel type where it tells (DDS).
    std::optional<Format> recorded;
    if (const std::optional<std::string> name = image.find_metadata("msmcl:format")) {
        recorded = parse_format(*name);
        if (!recorded) fail(path, "key msmcl:format is '" + *name + "', not a moment shadow map format");
    } else if (image.format == io::GpuFormat::r32g32b32a32_sfloat) {
        recorded = Format::moments128;
    } else if (image.format == io::GpuFormat::r32_uint) {
        recorded = Format::nlq32;
    } else if (image.format == io::GpuFormat::r16g16b16a16_unorm && !format) {
        fail(path, std::string(container_name(container)) +
                       " file of r16g16b16a16_unorm texels may be msm64 or nlq64: say which with --format msm64 or "
                       "--format nlq64");
    }
    if (recorded && format && *recorded != *format)
        fail(path, std::string("holds a ") + format_name(*recorded) + " texture, --format says " + format_name(*format));
    // The commands that read a map take one 2D texture (info reads arrays itself).
    if (image.layers != 1 || image.array)
        fail(path, "holds a texture array of " + std::to_string(image.layers) + " layers, expected one 2D texture");
    io::TextureFile file;
    file.texture = io::texture_of(image, recorded.value_or(format.value_or(Format::nlq64)), path);
    file.info = info_of(image, path);
    return file;
}

namespace {

/// EXR files hold one 2D texture.
void require_one_map_for_exr(const std::string& path, Container container, int layers, bool array) {
    if (container == Container::exr && (array || layers != 1))
        throw usage_error(path + ": an OpenEXR texture holds one map; write a texture array as .ktx2 or .dds");
}

} // namespace

void write_texture_file(const std::string& path, Container container, const Texture& texture,
                        const io::TextureInfo& info, bool array) {
    require_one_map_for_exr(path, container, texture.layers, array);
    if (container == Container::exr) {
        io::write_texture_exr(path, texture, info);
        return;
    }
    io::GpuImage image = io::gpu_image_of(texture, {{"msmcl:sigma", float_text(info.sigma)},
                                                    {"msmcl:samples", std::to_string(info.samples)},
                                                    {"msmcl:depthRange", depth_range_name(info.depth_range)}});
    image.array = image.array || array;
    if (container == Container::ktx2) io::write_ktx2(path, image);
    else io::write_dds(path, image);
}

io::SatFile read_sat_file(const std::string& path, std::optional<std::uint32_t> max_kernel) {
    const Container container = sniff_container(path);
    io::SatFile file;
    if (container == Container::exr) {
        file = io::read_sat_exr(path);
    } else {
        const io::GpuImage image = read_gpu_image(path, container);
        if (image.format != io::GpuFormat::r32g32b32a32_uint)
            fail(path, std::string("holds ") + io::gpu_format_info(image.format).name +
                           " texels, a summed-area table is r32g32b32a32_uint");
        if (const std::optional<std::string> kind = image.find_metadata("msmcl:format"); kind && *kind != "sat")
            fail(path, "key msmcl:format is '" + *kind + "', not sat");
        if (image.layers != 1 || image.array) fail(path, "holds a texture array, expected one 2D texture");
        // N: the record (KTX2), else what the user said (DDS keeps none).
        const std::optional<long long> recorded = metadata_integer(image, path, "msmcl:maxKernelTexels",
                                                                   sat_min_kernel_texels, sat_max_kernel_texels);
        if (!recorded && !max_kernel)
            fail(path, std::string(container_name(container)) +
                           " file records no largest kernel N: say it with --max-kernel N (as given to msmcl sat)");
        if (recorded && max_kernel && static_cast<std::uint32_t>(*recorded) != *max_kernel)
            fail(path, "records N = " + std::to_string(*recorded) + ", --max-kernel says " + std::to_string(*max_kernel));
        file.table.max_kernel_texels = recorded ? static_cast<std::uint32_t>(*recorded) : *max_kernel;
        file.table.scale = sat_scale(file.table.max_kernel_texels);
        if (const std::optional<long long> scale = metadata_integer(image, path, "msmcl:scale", 1, 0xffffffffll);
            scale && static_cast<std::uint32_t>(*scale) != file.table.scale)
            fail(path, "key msmcl:scale is " + std::to_string(*scale) + "; N = " +
                           std::to_string(file.table.max_kernel_texels) + " needs " + std::to_string(file.table.scale));
        file.table.width = image.width;
        file.table.height = image.height;
        file.table.words.resize(image.bytes.size() / sizeof(std::uint32_t));
        if (!image.bytes.empty()) std::copy_n(image.bytes.data(), image.bytes.size(), reinterpret_cast<unsigned char*>(file.table.words.data()));
        const io::TextureInfo info = info_of(image, path);
        file.info.samples = info.samples;
        file.info.depth_range = info.depth_range;
    }
    if (max_kernel && file.table.max_kernel_texels != *max_kernel)
        fail(path, "records N = " + std::to_string(file.table.max_kernel_texels) + ", --max-kernel says " +
                       std::to_string(*max_kernel));
    return file;
}

void write_sat_file(const std::string& path, Container container, const SatTable& table, const io::SatInfo& info,
                    bool array) {
    require_one_map_for_exr(path, container, table.layers, array);
    if (container == Container::exr) {
        io::write_sat_exr(path, table, info);
        return;
    }
    io::GpuImage image = io::gpu_image_of(table);
    image.array = image.array || array;
    image.metadata.emplace_back("msmcl:samples", std::to_string(info.samples));
    image.metadata.emplace_back("msmcl:depthRange", depth_range_name(info.depth_range));
    if (container == Container::ktx2) io::write_ktx2(path, image);
    else io::write_dds(path, image);
}

std::string float_text(float value) {
    char text[32];
    for (int digits = 6; digits <= 9; ++digits) {
        std::snprintf(text, sizeof text, "%.*g", digits, static_cast<double>(value));
        if (std::strtof(text, nullptr) == value) break;
    }
    return text;
}

} // namespace msmcl::cli
