#include "cli/commands.hpp"
#include "cli/batch.hpp"
#include "cli/option_values.hpp"
#include "cli/stages.hpp"
#include "cli/texture_files.hpp"

#include "io/exr_io.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/shade.hpp>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>

namespace msmcl::cli {
namespace {

/// --frame: a whole number in [0, 2^32 - 1].
std::uint32_t parse_frame(const std::string& text) {
    char* end = nullptr;
    errno = 0;
    const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
    if (text.empty() || !std::isdigit(static_cast<unsigned char>(text[0])) || end != text.c_str() + text.size() ||
        errno == ERANGE || value > 0xffffffffull)
        throw usage_error("--frame must be a whole number in [0, 4294967295], got '" + text + "'");
    return static_cast<std::uint32_t>(value);
}

/// Library input errors do not know the file; put it in front.
[[noreturn]] void rethrow_with_file(const std::string& path, const input_error& e) {
    throw input_error(path + ": " + e.what());
}

} // namespace

namespace {

/// "1 program built" / "cache hit": what the stage's calls cost in program builds.
std::string build_note(const Context& context, std::size_t built_before) {
    const std::size_t built = context.programs_built() - built_before;
    return built == 0 ? "cache hit" : std::to_string(built) + (built == 1 ? " program built" : " programs built");
}

/// filter() split into the stages --verbose reports: the program (built or found in a
/// cache, by a run on a 1x1 map of the same kind), the upload, the kernels, the download.
/// Same texels as filter(context, depth, layers, options).
Texture filter_in_stages(Stages& stages, Context& context, const io::TranslucentDepth& layered,
                         const FilterOptions& options) {
    const DepthImage& depth = layered.depth;
    const std::size_t layer_count = layered.layers.size();
    stages.run("program", [&] {
        const std::size_t built = context.programs_built();
        const float mid = options.depth_range == DepthRange::zero_one ? 0.5f : 0.0f;
        // Texture arrays run other programs: the tiny map has layers then too.
        const int tiny_array_layers = depth.layers > 1 ? 2 : 1;
        DepthImage tiny{1, 1, depth.samples,
                        std::vector<float>(static_cast<std::size_t>(depth.samples * tiny_array_layers), mid),
                        tiny_array_layers};
        std::vector<TranslucentLayer> tiny_layers(layer_count, TranslucentLayer{tiny.depth, tiny.depth});
        filter(context, tiny, tiny_layers, options);
        stages.note(build_note(context, built) + ", warm-up on a 1x1 map");
    });
    const DeviceLayeredDepth device = upload_layered_depth(stages, context, layered);
    Texture texture;
    texture.format = options.format;
    texture.width = depth.width;
    texture.height = depth.height;
    texture.layers = depth.layers;
    texture.words.resize(static_cast<std::size_t>(depth.width) * depth.height * depth.layers *
                         texel_words(options.format));
    DeviceBuffer texture_buffer(context, texture.words.size() * sizeof(std::uint32_t), texture.words.data(),
                                HostArray::result_in_place);
    stages.run("kernel", [&] {
        filter(context, device.depth_view(), device.layers_view(), texture_buffer.get(), options);
        context.finish();
        // The distribution the device's built kernels allowed, and why (docs/devices.md).
        std::string choices;
        for (const std::string& line : context.kernel_choices()) choices += (choices.empty() ? "" : "; ") + line;
        stages.note(choices);
    });
    stages.run("download", [&] {
        texture_buffer.read(context, texture.words.data());
        stages.note(std::to_string(texture.words.size() * sizeof(std::uint32_t)) + " bytes" +
                    (texture_buffer.in_place() ? " in place" : ""));
    });
    return texture;
}

/// shade() split into stages as filter_in_stages.
std::vector<float> shade_in_stages(Stages& stages, Context& context, const Texture& map,
                                   const io::ReceiverGrid& receivers, const ShadeOptions& options) {
    stages.run("program", [&] {
        const std::size_t built = context.programs_built();
        Receivers one;
        one.u = {0.5f};
        one.v = {0.5f};
        one.z = {options.depth_range == DepthRange::zero_one ? 0.5f : 0.0f};
        ReceiverPixels pixel;
        if (!receivers.pixels.x.empty()) pixel = {{0u}, {0u}};
        shade(context, map, one, pixel, options);
        stages.note(build_note(context, built) + ", warm-up on one receiver");
    });
    const std::size_t count = receivers.points.size();
    std::vector<float> uvz;
    uvz.reserve(3 * count);
    for (const std::vector<float>* plane : {&receivers.points.u, &receivers.points.v, &receivers.points.z})
        uvz.insert(uvz.end(), plane->begin(), plane->end());
    std::vector<std::uint32_t> pixels(receivers.pixels.x);
    pixels.insert(pixels.end(), receivers.pixels.y.begin(), receivers.pixels.y.end());
    std::unique_ptr<DeviceBuffer> map_buffer, uvz_buffer, pixel_buffer;
    stages.run("upload", [&] {
        map_buffer = std::make_unique<DeviceBuffer>(context, map.words.size() * sizeof(std::uint32_t), map.words.data());
        uvz_buffer = std::make_unique<DeviceBuffer>(context, uvz.size() * sizeof(float), uvz.data());
        if (!pixels.empty())
            pixel_buffer = std::make_unique<DeviceBuffer>(context, pixels.size() * sizeof(std::uint32_t), pixels.data());
        context.finish();
    });
    std::vector<float> intensity(count);
    DeviceBuffer intensity_buffer(context, count * sizeof(float));
    stages.run("kernel", [&] {
        const DeviceTexture device_map{map_buffer->get(), map.format, map.width, map.height};
        shade(context, device_map, uvz_buffer->get(), pixel_buffer ? pixel_buffer->get() : nullptr, count,
              intensity_buffer.get(), options);
        context.finish();
    });
    stages.run("download", [&] { intensity_buffer.read(context, intensity.data()); });
    return intensity;
}

} // namespace

DeviceSelection GlobalArguments::selection() const {
    DeviceSelection selection;
    selection.device = device;
    // A --device that matches nothing is an error, not a silent fallback.
    selection.strict = !device.empty();
    return selection;
}

namespace {

/// One file of `msmcl filter`: the command line's options, overridden by the manifest's.
MapJob filter_job(const FilterArguments& arguments, const BatchEntry& entry) {
    // Check the option values before touching any file.
    const std::string format_text = entry_option(entry, "format", arguments.format);
    if (format_text.empty()) throw usage_error("--format is required");
    const std::optional<Format> format = parse_format(format_text);
    if (!format)
        throw usage_error("unknown --format '" + format_text + "' (expected moments128, msm64, nlq64 or nlq32)");
    const std::string sigma_text = entry_option(entry, "sigma", arguments.sigma);
    const float sigma = parse_finite_float("--sigma", sigma_text);
    if (sigma < 0.0f) throw usage_error("--sigma must be >= 0, got '" + sigma_text + "'");
    const DepthRange range = parse_depth_range_option(entry_option(entry, "depth-range", arguments.depth_range));
    const Container container =
        output_container(entry_option(entry, "out-container", arguments.out_container), entry.output);
    const std::string kernel_text = entry_option(entry, "kernel", arguments.kernel);
    const std::optional<FilterKernel> kernel = parse_filter_kernel(kernel_text);
    if (!kernel)
        throw usage_error("unknown --kernel '" + kernel_text +
                          "' (expected automatic, fused_paper, fused_cpu or three_pass)");

    FilterOptions options;
    options.format = *format;
    options.sigma = sigma;
    options.depth_range = range;
    options.kernel = *kernel;
    // Filter on the device, then publish the texture with what it was made from (DDS has
    // no place for the record).
    return map_job(
        entry, range, "filter",
        [options](Context& context, const io::TranslucentDepth& layered) {
            return filter(context, layered.depth, layered.layers, options);
        },
        [options](Stages& stages, Context& context, const io::TranslucentDepth& layered) {
            return filter_in_stages(stages, context, layered, options);
        },
        [options, container, output = entry.output, array = entry.array](const Texture& texture, int samples) {
            write_texture_file(output, container, texture, io::TextureInfo{options.sigma, samples, options.depth_range},
                               array);
        });
}

} // namespace

int run_filter(const GlobalArguments& global, const FilterArguments& arguments, const BatchArguments& batch) {
    MapCommand command;
    command.name = "filter";
    command.manifest_keys = {"format", "sigma", "depth-range", "kernel", "out-container"};
    command.out_container = arguments.out_container;
    command.make_job = [&](const BatchEntry& entry) { return filter_job(arguments, entry); };
    return run_map_command(global, batch, command);
}

void run_shade(const GlobalArguments& global, const ShadeArguments& arguments) {
    // Check the option values before touching any file.
    ShadeOptions options;
    const std::optional<Lookup> lookup = parse_lookup(arguments.lookup);
    if (!lookup) throw usage_error("unknown --lookup '" + arguments.lookup + "' (expected nearest, bilinear or dither)");
    options.lookup = *lookup;
    options.depth_bias = parse_finite_float("--depth-bias", arguments.depth_bias);
    options.frame = parse_frame(arguments.frame);
    std::optional<DepthRange> range;
    if (!arguments.depth_range.empty()) range = parse_depth_range_option(arguments.depth_range);
    std::optional<Format> format;
    if (!arguments.format.empty()) {
        format = parse_format(arguments.format);
        if (!format)
            throw usage_error("unknown --format '" + arguments.format + "' (expected moments128, msm64, nlq64 or nlq32)");
    }
    require_exr_output(arguments.output);
    Stages stages(global.verbose, global.verbose ? 7 : 4);

    // Read the map (EXR, KTX2 or DDS) and the receivers; the receivers' depth follows the
    // map's convention unless --depth-range says otherwise.
    const io::TextureFile map = stages.run("read map", [&] { return read_texture_file(arguments.map, format); });
    const io::ReceiverGrid receivers =
        stages.run("read receivers", [&] { return io::read_receivers_exr(arguments.receivers); });
    options.depth_range = range.value_or(map.info.depth_range);
    // Screen pixels for dither: the PX, PY channels, else the receivers' own grid.
    options.screen_width = static_cast<std::uint32_t>(receivers.width);

    // Shade on the device.
    Context context = stages.run("device setup", [&] { return Context(global.selection()); });
    std::vector<float> intensity;
    try {
        if (stages.verbose())
            intensity = shade_in_stages(stages, context, map.texture, receivers, options);
        else
            intensity = stages.run(
                "shade", [&] { return shade(context, map.texture, receivers.points, receivers.pixels, options); });
    } catch (const input_error& e) {
        rethrow_with_file(arguments.receivers, e);
    }

    // One intensity per receiver, on the receivers' grid.
    stages.run("write",
               [&] { io::write_intensity_exr(arguments.output, receivers.width, receivers.height, intensity); });
}

void run_devices(const GlobalArguments& global) {
    const std::vector<DeviceInfo> devices = list_devices();
    if (devices.empty()) throw device_error("no OpenCL device found (is an ICD such as pocl-opencl-icd installed?)");

    // The device a Context would pick with these options and the environment.
    const Context context(global.selection());
    const DeviceInfo& picked = context.device();
    const char* mark = global.device.empty() ? "  [default]" : "  [selected]";

    for (const DeviceInfo& device : devices) {
        const char* type = device.is_gpu ? "GPU" : device.is_cpu ? "CPU" : "other";
        const bool is_picked =
            device.platform_index == picked.platform_index && device.device_index == picked.device_index;
        std::cout << device.platform_index << ':' << device.device_index << "  " << device.name << "  (" << type
                  << ", driver " << device.driver_version << ", platform " << device.platform_name << ")"
                  << (is_picked ? mark : "") << '\n';
    }
    std::cout.flush();
}

} // namespace msmcl::cli
