// msmcl-lookup-preview: one PNG that compares the lookups of a filtered map (docs/math.md, Lookups)
// side by side on a view's receivers: nearest, bilinear, dither (one frame) and the mean of
// dither over N frames, each lit by the view's lighting (ambient + direct * (1 - Y)) where
// given, else the shadow intensity (white lit, black shadowed). A crop and an integer zoom
// (pixel replication) show the texel structure. A strip above the panels names each one.
#include "io/exr_io.hpp"
#include "io/png_io.hpp"
#include "exr_channels.hpp"
#include "label_text.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/shade.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <iostream>
#include <sstream>

using msmcl::tools::float_channel;

namespace {

struct Crop {
    int x = 0, y = 0, width = 0, height = 0; ///< width 0: the whole view
};

Crop parse_crop(const std::string& text, int view_width, int view_height) {
    Crop crop{0, 0, view_width, view_height};
    if (text.empty()) return crop;
    char c1 = 0, c2 = 0, c3 = 0;
    std::istringstream in(text);
    if (!(in >> crop.x >> c1 >> crop.y >> c2 >> crop.width >> c3 >> crop.height) || c1 != ',' || c2 != ',' ||
        c3 != ',' || crop.x < 0 || crop.y < 0 || crop.width <= 0 || crop.height <= 0 ||
        crop.x + crop.width > view_width || crop.y + crop.height > view_height)
        throw msmcl::input_error("--crop must be X,Y,W,H inside the " + std::to_string(view_width) + "x" +
                                 std::to_string(view_height) + " view, got '" + text + "'");
    return crop;
}


} // namespace

int main(int argc, char** argv) {
    CLI::App app{"msmcl-lookup-preview: nearest | bilinear | dither | dither mean of N frames, side by side",
                 "msmcl-lookup-preview"};
    std::string map_path, receivers_path, output, lighting_path, crop_text;
    int frames = 64, zoom = 1, gap = 4;
    app.add_option("map", map_path, "texture EXR written by msmcl filter")->required();
    app.add_option("receivers", receivers_path, "receivers EXR (U, V, Z; optional PX, PY)")->required();
    app.add_option("output", output, "PNG to write")->required();
    app.add_option("--lighting", lighting_path, "EXR with the view's ambient and direct terms");
    app.add_option("--frames", frames, "dither frames averaged in the last panel")->capture_default_str()->check(CLI::Range(1, 4096));
    app.add_option("--crop", crop_text, "X,Y,W,H: the part of the view to show");
    app.add_option("--zoom", zoom, "pixel replication factor")->capture_default_str()->check(CLI::Range(1, 16));
    CLI11_PARSE(app, argc, argv);
    try {
        // Inputs: the map, the receivers (and their pixels), the lighting terms.
        const msmcl::io::TextureFile map = msmcl::io::read_texture_exr(map_path);
        const msmcl::io::ReceiverGrid view = msmcl::io::read_receivers_exr(receivers_path);
        const Crop crop = parse_crop(crop_text, view.width, view.height);
        std::vector<float> ambient, direct;
        if (!lighting_path.empty()) {
            const msmcl::io::ExrImage lighting = msmcl::io::read_exr(lighting_path);
            if (lighting.width != view.width || lighting.height != view.height)
                throw msmcl::input_error(lighting_path + ": size differs from " + receivers_path);
            ambient = float_channel(lighting, lighting_path, "ambient");
            direct = float_channel(lighting, lighting_path, "direct");
        }

        // The four panels' shadow intensities.
        msmcl::Context context;
        msmcl::ShadeOptions options;
        options.depth_range = map.info.depth_range;
        options.screen_width = static_cast<std::uint32_t>(view.width);
        std::vector<std::vector<float>> panels;
        for (msmcl::Lookup lookup : {msmcl::Lookup::nearest, msmcl::Lookup::bilinear, msmcl::Lookup::dither}) {
            options.lookup = lookup;
            panels.push_back(msmcl::shade(context, map.texture, view.points, view.pixels, options));
        }
        std::vector<float> mean(view.points.size(), 0.0f);
        for (int frame = 0; frame < frames; ++frame) {
            options.frame = static_cast<std::uint32_t>(frame);
            const std::vector<float> y = msmcl::shade(context, map.texture, view.points, view.pixels, options);
            for (std::size_t i = 0; i < mean.size(); ++i) mean[i] += y[i] / static_cast<float>(frames);
        }
        panels.push_back(mean);

        // Compose: lit panels, cropped, zoomed, side by side on a mid-gray background, below a
        // strip with each panel's name in black.
        const int panel_width = crop.width * zoom, panel_height = crop.height * zoom;
        const int label_rows = msmcl::tools::kGlyphHeight + 6;
        const int width = static_cast<int>(panels.size()) * panel_width + (static_cast<int>(panels.size()) - 1) * gap;
        const int height = label_rows + panel_height;
        std::vector<float> image(static_cast<std::size_t>(width) * height, 0.5f);
        const std::string names[] = {"nearest", "bilinear", "dither (frame 0)",
                                     "mean of " + std::to_string(frames) + " dither frames"};
        for (std::size_t p = 0; p < panels.size(); ++p)
            msmcl::tools::draw_text(image, width, height, 1, static_cast<int>(p) * (panel_width + gap) + 2, 3, names[p],
                                    {0.0f, 0.0f, 0.0f});
        for (std::size_t p = 0; p < panels.size(); ++p)
            for (int y = 0; y < panel_height; ++y)
                for (int x = 0; x < panel_width; ++x) {
                    const std::size_t i = static_cast<std::size_t>(crop.y + y / zoom) * view.width + crop.x + x / zoom;
                    const float shadow = panels[p][i];
                    const float value = ambient.empty() ? 1.0f - shadow : ambient[i] + direct[i] * (1.0f - shadow);
                    image[static_cast<std::size_t>(label_rows + y) * width + p * (panel_width + gap) + x] = value;
                }
        msmcl::io::write_png_preview(output, width, height, 1, image);
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "msmcl-lookup-preview: " << e.what() << std::endl;
        return dynamic_cast<const msmcl::input_error*>(&e) ? 2 : 1;
    }
}
