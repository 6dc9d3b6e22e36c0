// msmcl-preview: one channel of an EXR (e.g. the Y of `msmcl shade`) as a PNG; with
// --lighting (from msmcl-scene / msmcl-rasterize) the shadow intensity Y darkens the
// direct light of the view: ambient + direct * (1 - Y).
#include "io/exr_io.hpp"
#include "io/png_io.hpp"
#include "exr_channels.hpp"

#include <msmcl/errors.hpp>

#include <CLI/CLI.hpp>

#include <iostream>

using msmcl::tools::float_channel;

int main(int argc, char** argv) {
    CLI::App app{"msmcl-preview: an EXR channel (optionally lit by a view's lighting terms) as PNG", "msmcl-preview"};
    std::string input, output, channel = "Y", lighting_path;
    float black = 0.0f, white = 1.0f;
    app.add_option("input", input, "EXR to show")->required();
    app.add_option("output", output, "PNG to write")->required();
    app.add_option("--channel", channel, "channel to show")->capture_default_str();
    app.add_option("--lighting", lighting_path, "EXR with channels ambient and direct of the same size");
    app.add_option("--black", black, "value shown black")->capture_default_str();
    app.add_option("--white", white, "value shown white")->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    try {
        const msmcl::io::ExrImage image = msmcl::io::read_exr(input);
        std::vector<float> values = float_channel(image, input, channel);
        if (!lighting_path.empty()) {
            // Shade the view: the intensity removes that share of the direct light.
            const msmcl::io::ExrImage lighting = msmcl::io::read_exr(lighting_path);
            if (lighting.width != image.width || lighting.height != image.height)
                throw msmcl::input_error(lighting_path + ": size differs from " + input);
            const std::vector<float>& ambient = float_channel(lighting, lighting_path, "ambient");
            const std::vector<float>& direct = float_channel(lighting, lighting_path, "direct");
            for (std::size_t i = 0; i < values.size(); ++i) values[i] = ambient[i] + direct[i] * (1.0f - values[i]);
        }
        msmcl::io::write_png_preview(output, image.width, image.height, 1, values, black, white);
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "msmcl-preview: " << e.what() << std::endl;
        return dynamic_cast<const msmcl::input_error*>(&e) ? 2 : 1;
    }
}
