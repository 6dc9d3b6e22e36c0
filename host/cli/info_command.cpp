#include "cli/info_command.hpp"
#include "cli/option_values.hpp"
#include "cli/texture_files.hpp"

#include "io/atomic_file.hpp"
#include "io/dds.hpp"
#include "io/exr_io.hpp"
#include "io/gpu_image.hpp"
#include "io/ktx2.hpp"
#include "io/sat_exr.hpp"
#include "io/scene_json.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/scatter.hpp>
#include <msmcl/device_math.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <type_traits>
#include <variant>

namespace msmcl::cli {
namespace {

using nlohmann::json;

/// Value statistics of one channel or decoded quantity.
struct ChannelStats {
    std::string name;
    std::string type;
    std::optional<std::pair<double, double>> range; ///< what the kind allows; none: anything finite
    std::size_t count = 0, nan = 0, inf = 0, out_of_range = 0;
    double min = std::numeric_limits<double>::infinity();
    double max = -std::numeric_limits<double>::infinity();

    void add(double value) {
        ++count;
        if (std::isnan(value)) {
            ++nan;
        } else if (std::isinf(value)) {
            ++inf;
        } else {
            min = std::min(min, value);
            max = std::max(max, value);
            if (range && (value < range->first || value > range->second)) ++out_of_range;
        }
    }
    json to_json() const {
        json j = {{"name", name}, {"type", type}, {"count", count}, {"nan", nan}, {"inf", inf},
                  {"out_of_range", out_of_range}};
        const bool any_finite = min <= max;
        j["min"] = any_finite ? json(min) : json(nullptr);
        j["max"] = any_finite ? json(max) : json(nullptr);
        j["range"] = range ? json::array({range->first, range->second}) : json(nullptr);
        return j;
    }
};

using Range = std::optional<std::pair<double, double>>;

// What `info` calls a filtered map of `format`: its representation's kind of shadow map.
std::string map_kind(Format format) {
    return detail::representation_info(detail::representation_of(format)).map_kind;
}

ChannelStats stats_of(const std::string& name, const std::string& type, Range range, const std::vector<float>& values) {
    ChannelStats stats{name, type, range};
    for (float value : values) stats.add(value);
    return stats;
}
ChannelStats stats_of(const std::string& name, Range range, const std::vector<std::uint32_t>& codes) {
    ChannelStats stats{name, "uint32", range};
    for (std::uint32_t code : codes) stats.add(static_cast<double>(code));
    return stats;
}

const char* type_name(io::SampleType type) {
    switch (type) {
    case io::SampleType::uint32: return "uint32";
    case io::SampleType::half: return "half";
    case io::SampleType::float32: return "float32";
    }
    return "?";
}

bool starts_with(const std::string& text, const std::string& prefix) { return text.rfind(prefix, 0) == 0; }
bool ends_with(const std::string& text, const std::string& suffix) {
    return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// The decoded quantities of every texel of a filtered map, with the ranges each may take
/// (the format's row of the format table: decoded_quantities, decode_texel).
json texture_channels(const Texture& texture) {
    std::vector<ChannelStats> stats;
    for (const DecodedQuantity& quantity : decoded_quantities(texture))
        stats.push_back({quantity.name, "decoded", std::make_pair(quantity.min, quantity.max)});
    // Every texel of every array layer.
    const std::size_t texels = static_cast<std::size_t>(texture.width) * texture.height * texture.layers;
    float values[4];
    for (std::size_t t = 0; t < texels; ++t) {
        decode_texel(texture, t, values);
        for (std::size_t c = 0; c < stats.size(); ++c) stats[c].add(values[c]);
    }
    json channels = json::array();
    for (const ChannelStats& s : stats) channels.push_back(s.to_json());
    return channels;
}

json sat_fields(const SatTable& table) {
    return {{"max_kernel_texels", table.max_kernel_texels},
            {"scale", table.scale},
            {"precision_bits", std::log2(static_cast<double>(table.scale))}};
}

json attributes_of(const io::ExrImage& image) {
    json attributes = json::object();
    for (const io::ExrAttribute& attribute : image.attributes)
        std::visit(
            [&](const auto& value) {
                // Floats as the shortest text that reads back to them, not as widened doubles.
                if constexpr (std::is_same_v<std::decay_t<decltype(value)>, float>)
                    attributes[attribute.name] = std::stod(float_text(value));
                else
                    attributes[attribute.name] = value;
            },
            attribute.value);
    return attributes;
}

/// An EXR file: its kind from its attributes and channels; decoded quantities for maps,
/// raw channel statistics (with the ranges the kind allows) for everything else.
json describe_exr(const std::string& path, DepthRange depth_range) {
    const io::ExrImage image = io::read_exr(path);
    // An EXR holds one image: one array layer, never a texture array.
    json info = {{"container", "exr"}, {"width", image.width},     {"height", image.height},
                 {"layers", 1},         {"texture_array", false}, {"attributes", attributes_of(image)}};
    const io::ExrAttribute* format = image.find_attribute("msmcl:format");
    const std::string format_text =
        format && std::holds_alternative<std::string>(format->value) ? std::get<std::string>(format->value) : "";
    const auto has = [&](const char* name) { return image.find_channel(name) != nullptr; };
    const Range depth = depth_range == DepthRange::zero_one ? Range(std::make_pair(0.0, 1.0))
                                                            : Range(std::make_pair(-1.0, 1.0));

    // Filtered maps and tables through the strict readers; what they refuse is reported.
    if (format_text == "sat") {
        info["kind"] = "summed-area table";
        info["format"] = "sat";
        try {
            const io::SatFile table = io::read_sat_exr(path);
            info.update(sat_fields(table.table));
            info["samples"] = table.info.samples;
        } catch (const input_error& e) {
            info["problem"] = e.what();
        }
    } else if (const std::optional<Format> format = parse_format(format_text)) {
        info["kind"] = map_kind(*format);
        info["format"] = format_text;
        try {
            const io::TextureFile map = io::read_texture_exr(path);
            info["samples"] = map.info.samples;
            info["channels"] = texture_channels(map.texture);
            return info;
        } catch (const input_error& e) {
            info["problem"] = e.what();
        }
    } else if (has("U") && has("V") && has("Z")) {
        info["kind"] = "receivers";
    } else if (has("Z") || has("sample0.Z")) {
        info["kind"] = "depth map";
    } else if (has("Y")) {
        info["kind"] = image.find_attribute("msmcl:scatterMethod") ? "radiance" : "shadow intensity";
    } else if (has("b1")) {
        info["kind"] = "scattering moments";
    } else {
        info["kind"] = "image";
    }

    // Samples and translucent layers of depth maps.
    int samples = 0;
    std::set<std::string> layers;
    for (const io::ExrChannel& channel : image.channels) {
        if (starts_with(channel.name, "sample") && ends_with(channel.name, ".Z")) ++samples;
        if (starts_with(channel.name, "layer")) layers.insert(channel.name.substr(0, channel.name.find('.')));
    }
    if (info["kind"] == "depth map") {
        info["samples"] = has("Z") ? 1 : samples;
        info["translucent_layers"] = layers.size();
    }

    // Every channel, with the range its meaning allows.
    json channels = json::array();
    const std::string kind = info["kind"];
    for (const io::ExrChannel& channel : image.channels) {
        Range range;
        const std::string& name = channel.name;
        if ((kind == "depth map" && ends_with(name, "Z")) || (kind == "receivers" && name == "Z")) range = depth;
        else if (kind == "depth map" && ends_with(name, ".A")) range = std::make_pair(0.0, 1.0);
        else if (kind == "shadow intensity" && name == "Y") range = std::make_pair(0.0, 1.0);
        else if (kind == "radiance" && name == "Y") range = std::make_pair(0.0, std::numeric_limits<double>::max());
        else if ((kind == "receivers") && (name == "PX" || name == "PY")) range = std::make_pair(0.0, 16777216.0);
        else if (parse_format(format_text) && channel.type == io::SampleType::uint32 && format_text != "nlq32")
            range = std::make_pair(0.0, 65535.0);
        channels.push_back((channel.type == io::SampleType::uint32 ? stats_of(name, range, channel.codes)
                                                                   : stats_of(name, type_name(channel.type), range,
                                                                              channel.values))
                               .to_json());
    }
    info["channels"] = channels;
    return info;
}

/// A KTX2 key/value entry as JSON: msmcl's own keys that hold a decimal number (msmcl:samples,
/// msmcl:sigma, ...) as that number, as the EXR attributes give them; everything else as text.
json metadata_value(const std::string& key, const std::string& text) {
    static const std::regex decimal(R"(-?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][-+]?[0-9]+)?)");
    if (!starts_with(key, "msmcl:") || !std::regex_match(text, decimal)) return text;
    return json::parse(text);
}

/// A KTX2 or DDS file: its GPU format, key/value data, and the decoded texels where the
/// format is known.
json describe_gpu_file(const std::string& path, Container container) {
    const io::GpuImage image = container == Container::ktx2 ? io::read_ktx2(path) : io::read_dds(path);
    const io::GpuFormatInfo& gpu = io::gpu_format_info(image.format);
    json info = {{"container", container_name(container)}, {"width", image.width}, {"height", image.height},
                 {"layers", image.layers}, {"texture_array", image.array}, {"gpu_format", gpu.name},
                 {"vk_format", gpu.vk_format},
                 {"dxgi_format", gpu.dxgi_format}};
    json attributes = json::object();
    for (const auto& [key, value] : image.metadata) attributes[key] = metadata_value(key, value);
    info["attributes"] = attributes;
    if (attributes.contains("msmcl:samples") && attributes["msmcl:samples"].is_number_integer())
        info["samples"] = attributes["msmcl:samples"];

    const std::optional<std::string> recorded = image.find_metadata("msmcl:format");
    if (image.format == io::GpuFormat::r32g32b32a32_uint || recorded == std::optional<std::string>("sat")) {
        info["kind"] = "summed-area table";
        info["format"] = "sat";
        if (const std::optional<std::string> n = image.find_metadata("msmcl:maxKernelTexels")) {
            char* end = nullptr;
            const unsigned long long value = std::strtoull(n->c_str(), &end, 10);
            if (n->empty() || end != n->c_str() + n->size() || value < sat_min_kernel_texels ||
                value > sat_max_kernel_texels) {
                info["problem"] = "key msmcl:maxKernelTexels is '" + *n + "', not a kernel size N";
            } else {
                SatTable table;
                table.max_kernel_texels = static_cast<std::uint32_t>(value);
                table.scale = sat_scale(table.max_kernel_texels);
                info.update(sat_fields(table));
            }
        } else {
            info["problem"] = "records no largest kernel N (DDS keeps none)";
        }
        return info;
    }
    if (image.format == io::GpuFormat::a2b10g10r10_unorm_pack32) {
        info["kind"] = "scattering map plane";
        ChannelStats r{"R", "unorm10", std::make_pair(0.0, 1.0)}, g{"G", "unorm10", std::make_pair(0.0, 1.0)},
            b{"B", "unorm10", std::make_pair(0.0, 1.0)};
        for (std::size_t i = 0; i + 3 < image.bytes.size(); i += 4) {
            std::uint32_t word = 0;
            std::memcpy(&word, image.bytes.data() + i, 4);
            r.add((word & 1023u) / 1023.0), g.add(((word >> 10) & 1023u) / 1023.0), b.add(((word >> 20) & 1023u) / 1023.0);
        }
        info["channels"] = json::array({r.to_json(), g.to_json(), b.to_json()});
        return info;
    }
    // The format: the recorded one, else the only one with this texel type; msm64 and nlq64
    // share theirs (both moment shadow maps), and a DDS file records none.
    const std::vector<Format> candidates = detail::formats_with(image.format);
    const std::optional<Format> recorded_format = recorded ? parse_format(*recorded) : std::nullopt;
    const bool known = recorded_format.has_value() || candidates.size() == 1;
    const Format format = recorded_format.value_or(candidates.size() == 1 ? candidates.front() : Format::msm64);
    info["kind"] = map_kind(format);
    if (!known) {
        // Describe the raw 16-bit codes.
        info["format"] = nullptr;
        info["candidates"] = json::array({format_name(Format::msm64), format_name(Format::nlq64)});
        ChannelStats codes[4] = {{"R", "unorm16", std::make_pair(0.0, 65535.0)},
                                 {"G", "unorm16", std::make_pair(0.0, 65535.0)},
                                 {"B", "unorm16", std::make_pair(0.0, 65535.0)},
                                 {"A", "unorm16", std::make_pair(0.0, 65535.0)}};
        for (std::size_t i = 0; i + 1 < image.bytes.size(); i += 2)
            codes[(i / 2) % 4].add(image.bytes[i] | (image.bytes[i + 1] << 8));
        info["channels"] = json::array();
        for (const ChannelStats& s : codes) info["channels"].push_back(s.to_json());
        return info;
    }
    info["format"] = format_name(format);
    try {
        info["channels"] = texture_channels(io::texture_of(image, format, path));
    } catch (const input_error& e) {
        info["problem"] = e.what();
    }
    return info;
}

/// A scattering scene: what `msmcl scatter` would use.
json describe_scene(const std::string& path) {
    const ScatterScene scene = load_scatter_scene(path);
    return {{"container", "json"},
            {"kind", "scattering scene"},
            {"width", scene.camera.width},
            {"height", scene.camera.height},
            {"attributes",
             {{"rectified", std::to_string(scene.rectified_width) + "x" + std::to_string(scene.rectified_height)},
              {"extinction", scene.medium.extinction},
              {"phase_g", scene.medium.phase_g},
              {"irradiance", scene.medium.irradiance},
              {"guard_band", scene.guard_band}}}};
}

/// A PNG preview: its header (msmcl writes previews, never reads their pixels).
json describe_png(const std::string& path, const std::string& bytes) {
    if (bytes.size() < 33 || bytes.compare(12, 4, "IHDR") != 0) throw input_error(path + ": truncated PNG header");
    const auto u32 = [&](std::size_t at) {
        return (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at])) << 24) |
               (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + 1])) << 16) |
               (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + 2])) << 8) |
               static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + 3]));
    };
    const int color = static_cast<unsigned char>(bytes[25]);
    return {{"container", "png"},
            {"kind", "preview image"},
            {"width", u32(16)},
            {"height", u32(20)},
            {"attributes",
             {{"bit_depth", static_cast<int>(static_cast<unsigned char>(bytes[24]))},
              {"color", color == 0 ? "gray" : color == 2 ? "rgb" : color == 6 ? "rgba" : "other"}}}};
}

/// The version of the description's layout; a change of a key's meaning gets a new one.
constexpr const char* info_schema = "msmcl-info/1";
constexpr const char* info_keys[] = {"file", "container", "kind", "width", "height", "layers", "texture_array",
                                     "format", "candidates", "samples", "translucent_layers", "gpu_format",
                                     "vk_format", "dxgi_format", "max_kernel_texels", "scale", "precision_bits",
                                     "attributes", "channels", "problem"};

json describe(const std::string& path, DepthRange depth_range) {
    // The first bytes tell PNG and JSON apart from the texture containers.
    // A regular file or standard input only: a FIFO or device is refused, not waited on.
    const std::string head = io::read_file_head(path, 64);
    json info;
    if (head.size() >= 8 && head.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0) {
        info = describe_png(path, head);
    } else if (head.find_first_not_of(" \t\r\n") != std::string::npos && head[head.find_first_not_of(" \t\r\n")] == '{') {
        info = describe_scene(path);
    } else {
        const Container container = sniff_container(path);
        info = container == Container::exr ? describe_exr(path, depth_range) : describe_gpu_file(path, container);
    }
    info["file"] = path;
    // Every description has the same keys (docs/schemas/msmcl-info-1.schema.json): null where
    // the container or the kind of file does not know.
    info["schema"] = info_schema;
    for (const char* key : info_keys)
        if (!info.contains(key)) info[key] = nullptr;
    return info;
}

std::string number_text(const json& value) {
    if (value.is_null()) return "-";
    std::ostringstream text;
    text.precision(7);
    text << value.get<double>();
    return text.str();
}

/// The description as a few lines of text.
void print_text(std::ostream& out, const json& info) {
    out << info["file"].get<std::string>() << ": " << info["kind"].get<std::string>() << ", "
        << info["width"].get<long long>() << "x" << info["height"].get<long long>() << ", "
        << info["container"].get<std::string>();
    // Null keys (what the container does not know) are left out; an EXR's single layer too.
    const bool exr = info["container"] == "exr";
    for (const char* key : {"format", "gpu_format", "samples", "layers", "translucent_layers", "max_kernel_texels",
                            "precision_bits"}) {
        const json& value = info[key];
        if (value.is_null() && key == std::string("format") && info["candidates"].is_array()) {
            // Ambiguous: the texel type of several formats and no record of which.
            std::string names;
            for (const json& name : info["candidates"]) names += (names.empty() ? "" : " or ") + name.get<std::string>();
            out << ", format " << names;
        } else if (!value.is_null() && !(exr && key == std::string("layers"))) {
            out << ", " << key << " " << (value.is_string() ? value.get<std::string>() : number_text(value));
        }
    }
    // A texture array (KTX2 layerCount >= 1, DDS arraySize > 1), also of one layer.
    if (info["texture_array"] == true) out << " (texture array)";
    out << '\n';
    if (!info["problem"].is_null()) out << "  problem: " << info["problem"].get<std::string>() << '\n';
    if (info["attributes"].is_object())
        for (const auto& [key, value] : info["attributes"].items())
            out << "  attribute " << key << " = " << (value.is_string() ? value.get<std::string>() : value.dump())
                << '\n';
    if (info["channels"].is_array())
        for (const json& channel : info["channels"]) {
            out << "  " << channel["name"].get<std::string>() << " (" << channel["type"].get<std::string>()
                << "): min " << number_text(channel["min"]) << ", max " << number_text(channel["max"]) << ", NaN "
                << channel["nan"].get<std::size_t>() << ", Inf " << channel["inf"].get<std::size_t>();
            if (!channel["range"].is_null())
                out << ", outside [" << number_text(channel["range"][0]) << ", " << number_text(channel["range"][1])
                    << "] " << channel["out_of_range"].get<std::size_t>();
            out << '\n';
        }
}

int run_info(const InfoArguments& arguments) {
    const DepthRange depth_range = parse_depth_range_option(arguments.depth_range);
    // Every readable file is described; each bad one is named on stderr (as exrheader and
    // oiiotool --info do), and the exit code says that one was bad.
    json all = json::array();
    bool bad_input = false;
    for (const std::string& file : arguments.files) {
        try {
            all.push_back(describe(file, depth_range));
        } catch (const input_error& e) {
            std::cerr << "msmcl: " << e.what() << std::endl;
            bad_input = true;
        }
    }
    std::ostringstream out;
    if (arguments.json) {
        out << all.dump(2) << '\n';
    } else {
        for (const json& info : all) print_text(out, info);
    }
    std::cout << out.str() << std::flush;
    return bad_input ? 2 : 0;
}

} // namespace

std::string describe_json(const std::string& path, DepthRange depth_range) {
    return describe(path, depth_range).dump();
}

Subcommand add_info_command(CLI::App& app) {
    const auto parsed = std::make_shared<InfoArguments>();
    InfoArguments& arguments = *parsed;
    CLI::App* command = app.add_subcommand(
        "info", "Describe files msmcl reads or writes: kind, size, format, attributes, value ranges, NaN/Inf counts");
    command->add_option("files", arguments.files, "EXR, KTX2, DDS, scene JSON or PNG files")->required();
    command->add_flag("--json", arguments.json, "one JSON array on stdout instead of text");
    command->add_option("--depth-range", arguments.depth_range,
                                  "convention of depth maps and receivers: 0,1 or -1,1 (they record none)")
        ->capture_default_str()
        ->type_name("RANGE");
    return {command, [parsed](const GlobalArguments&) { return run_info(*parsed); }};
}

} // namespace msmcl::cli
