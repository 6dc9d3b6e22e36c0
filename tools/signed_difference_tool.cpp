// msmcl-signed-difference: the signed difference of an approximation from its ground truth
// (two EXRs of one size) as a PNG in the diverging colour map of signed_difference.hpp, with
// its legend bar, and one line of statistics on stdout.
#include "exr_channels.hpp"
#include "signed_difference.hpp"

#include "io/exr_io.hpp"

#include <msmcl/errors.hpp>

#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <map>

using msmcl::tools::float_channel;

int main(int argc, char** argv) {
    CLI::App app{"msmcl-signed-difference: light(APPROXIMATION) - light(TRUTH) as a PNG with a legend bar "
                 "(red: lighter than the truth, white: equal, blue: darker)",
                 "msmcl-signed-difference"};
    std::string approximation_path, truth_path, output, channel = "Y", truth_channel;
    double range = 0.5, threshold = 0.3;
    msmcl::tools::Quantity quantity = msmcl::tools::Quantity::shadow_intensity;
    const std::map<std::string, msmcl::tools::Quantity> quantities{
        {"shadow", msmcl::tools::Quantity::shadow_intensity}, {"light", msmcl::tools::Quantity::light}};
    app.add_option("approximation", approximation_path, "EXR of the approximation")->required();
    app.add_option("truth", truth_path, "EXR of the ground truth, same size")->required();
    app.add_option("output", output, "PNG to write (the image, then a 4-row gap and a 16-row legend bar)")->required();
    app.add_option("--channel", channel, "channel of the approximation")->capture_default_str();
    app.add_option("--truth-channel", truth_channel, "channel of the truth (default: --channel)");
    app.add_option("--quantity", quantity, "what the channels store: shadow (intensity, 1 = dark) or light")
        ->transform(CLI::CheckedTransformer(quantities))
        ->default_str("shadow");
    app.add_option("--range", range, "|difference| drawn in full colour")->capture_default_str()->check(CLI::PositiveNumber);
    app.add_option("--threshold", threshold, "difference counted as lighter/darker in the statistics")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    CLI11_PARSE(app, argc, argv);
    if (truth_channel.empty()) truth_channel = channel;
    try {
        const msmcl::io::ExrImage approximation = msmcl::io::read_exr(approximation_path);
        const msmcl::io::ExrImage truth = msmcl::io::read_exr(truth_path);
        if (approximation.width != truth.width || approximation.height != truth.height)
            throw msmcl::input_error(truth_path + ": size differs from " + approximation_path);
        // Difference in light, then the picture and the numbers.
        const std::vector<double> difference = msmcl::tools::signed_difference(
            float_channel(approximation, approximation_path, channel),
            float_channel(truth, truth_path, truth_channel), quantity);
        msmcl::tools::write_signed_difference_png(output, truth.width, truth.height, difference, range);
        const msmcl::tools::DifferenceStats stats = msmcl::tools::difference_stats(difference, threshold);
        std::printf("pixels %zu, mean |d| %.4f, p99 |d| %.4f, max |d| %.4f, lighter by > %g: %.2f%%, darker by > %g: %.2f%%\n",
                    stats.pixels, stats.mean_abs, stats.p99_abs, stats.max_abs, threshold, 100.0 * stats.share_lighter,
                    threshold, 100.0 * stats.share_darker);
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "msmcl-signed-difference: " << e.what() << std::endl;
        return dynamic_cast<const msmcl::input_error*>(&e) ? 2 : 1;
    }
}
