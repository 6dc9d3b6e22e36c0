#include "cli/texture_files.hpp"
#include "cli/option_values.hpp"

#include "io/dds.hpp"
#include "io/gpu_image.hpp"
#include "io/ktx2.hpp"
#include "io/texture_metadata.hpp"
#include "io/atomic_file.hpp"

#include <msmcl/errors.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <cstdlib>

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
    // The first bytes alone, of a regular file or standard input (never waiting on a FIFO).
    const std::string bytes = io::read_file_head(path, 12);
    std::array<unsigned char, 12> head{};
    std::copy(bytes.begin(), bytes.end(), head.begin());
    const std::size_t got = bytes.size();
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
    } else if (const std::vector<Format> candidates = detail::formats_with(image.format); candidates.size() == 1) {
        recorded = candidates.front();
    } else if (candidates.size() > 1 && format &&
               std::find(candidates.begin(), candidates.end(), *format) == candidates.end()) {
        fail(path, std::string(container_name(container)) + " file of " + io::gpu_format_info(image.format).name +
                       " texels holds no " + format_name(*format) + " texture, --format says " + format_name(*format));
    } else if (candidates.size() > 1 && !format) {
        std::string names, options;
        for (Format candidate : candidates) {
            names += std::string(names.empty() ? "" : " or ") + format_name(candidate);
            options += std::string(options.empty() ? "" : " or ") + "--format " + format_name(candidate);
        }
        fail(path, std::string(container_name(container)) + " file of " + io::gpu_format_info(image.format).name +
                       " texels may be " + names + ": say which with " + options);
    }
    if (recorded && format && *recorded != *format)
        fail(path, std::string("holds a ") + format_name(*recorded) + " texture, --format says " + format_name(*format));
    // The commands that read a map take one 2D texture (info reads arrays itself).
    if (image.layers != 1 || image.array)
        fail(path, "holds a texture array of " + std::to_string(image.layers) + " layers, expected one 2D texture");
    io::TextureFile file;
    file.texture = io::texture_of(image, recorded.value_or(format.value_or(Format::nlq64)), path);
    file.info = io::texture_info_of(image, path);
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
        file.table.max_kernel_texels = io::sat_max_kernel_of(image, path, max_kernel, container_name(container));
        file.table.scale = sat_scale(file.table.max_kernel_texels);
        file.table.width = image.width;
        file.table.height = image.height;
        file.table.words.resize(image.bytes.size() / sizeof(std::uint32_t));
        if (!image.bytes.empty()) std::copy_n(image.bytes.data(), image.bytes.size(), reinterpret_cast<unsigned char*>(file.table.words.data()));
        const io::TextureInfo info = io::texture_info_of(image, path);
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
