// msmcl-quality, report: the Markdown tables (stdout), the PNG images and the JSON
// (bench/quality.hpp).
#include "quality.hpp"

#include "io/png_io.hpp"
#include "tools/label_text.hpp"
#include "tools/signed_difference.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

namespace quality {

namespace {

/// Signed error in light, d = reference - shadow (shadow intensities): the colour map of every
/// difference figure (tools/signed_difference.hpp: red where the method is lighter than the
/// reference, i.e. leaks, blue where darker, white where equal).
std::vector<double> light_difference(const std::vector<double>& shadow, const std::vector<double>& reference) {
    std::vector<double> d(shadow.size());
    for (std::size_t i = 0; i < shadow.size(); ++i) d[i] = reference[i] - shadow[i];
    return d;
}

/// Rows of the legend below the marks image: swatches and their meaning in one line of text.
constexpr int marks_legend_rows = msmcl::tools::kGlyphHeight + 8;

/// The 128-bit shadow in grey (0.85 lit .. 0.25 shadowed), receivers where `shadow` differs
/// from it by more than 3% in orange and by more than 10% in red; below, a legend that says so.
std::vector<float> difference_marks(const std::vector<double>& shadow, const std::vector<double>& moments128,
                                    int width, const std::string& method) {
    std::vector<float> rgb((shadow.size() + static_cast<std::size_t>(width) * marks_legend_rows) * 3, 1.0f);
    for (std::size_t i = 0; i < shadow.size(); ++i) {
        const double error = std::abs(shadow[i] - moments128[i]);
        const float grey = static_cast<float>(0.85 - 0.6 * std::clamp(moments128[i], 0.0, 1.0));
        std::array<float, 3> colour = {grey, grey, grey};
        if (error > large_error_threshold) colour = {1.0f, 0.0f, 0.0f};
        else if (error > error_threshold) colour = {1.0f, 0.6f, 0.0f};
        std::copy(colour.begin(), colour.end(), rgb.begin() + 3 * i);
    }
    // Legend: an orange and a red swatch, each followed by what it marks.
    const int height = static_cast<int>(shadow.size() / width) + marks_legend_rows, top = height - marks_legend_rows + 4;
    int x = 2;
    for (const auto& [colour, text] : {std::make_pair(std::array<float, 3>{1.0f, 0.6f, 0.0f}, "> 3%"),
                                       std::make_pair(std::array<float, 3>{1.0f, 0.0f, 0.0f}, "> 10%")}) {
        for (int y = top; y < top + msmcl::tools::kGlyphHeight; ++y)
            for (int dx = 0; dx < 10; ++dx) std::copy(colour.begin(), colour.end(), rgb.begin() + 3 * (y * width + x + dx));
        msmcl::tools::draw_text(rgb, width, height, 3, x + 14, top, text, {0.0f, 0.0f, 0.0f});
        x += 14 + msmcl::tools::text_width(text) + 12;
    }
    // What is compared, where the image is wide enough for it (the caption says it otherwise).
    const std::string compared = "|" + method + " - moments128|, grey: moments128";
    if (x + msmcl::tools::text_width(compared) <= width)
        msmcl::tools::draw_text(rgb, width, height, 3, x, top, compared, {0.0f, 0.0f, 0.0f});
    return rgb;
}

std::string percent(double share) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f%%", 100.0 * share);
    return text;
}

std::string fixed(double value, int digits = 4) {
    char text[32];
    std::snprintf(text, sizeof text, "%.*f", digits, value);
    return text;
}

std::string error_cells(const ErrorStats& s) {
    return percent(s.share_above) + " (" + std::to_string(s.count_above) + ") | " + std::to_string(s.count_above_large) +
           " | " + fixed(s.max) + " | " + fixed(s.mean, 5);
}

nlohmann::json stats_json(const ErrorStats& s) {
    return {{"share_above_3pct", s.share_above}, {"count_above_3pct", s.count_above},
            {"count_above_10pct", s.count_above_large}, {"max", s.max}, {"mean", s.mean}};
}

} // namespace

void print_preamble(const std::string& device_name, const std::string& kernel_name) {
    std::cout << "# msmcl quality table\n\n"
              << "device: " << device_name << "; filter kernel " << kernel_name << "; blur sigma "
              << blur_sigma << " (9x9), depth bias "
              << depth_bias << " (internal depth), bilinear lookup unless said. Every method is the library's "
                 "texture shaded by the library (msmcl::filter, msmcl::shade) with the format's defaults (VSM and "
                 "EVSM minimum variance and exponents: docs/formats.md); *_lbr0.15: EVSM with light-bleed "
                 "reduction "
              << filament_light_bleed_reduction
              << " (Filament's default). Kernel: the filter's kernel stage, median of " << timed_filter_runs
              << " runs, and its ratio to msm64's in the same run.\n\n"
              << "Errors are |shadow - reference| over all receivers of the view (sky pixels included, lit). "
                 "PCF truth: percentage-closer filtering of the map's samples with the same 9x9 Gaussian and "
                 "bilinear weights, in double, each sample compared with the receiver's plane (depth gradient "
                 "from the neighbouring pixels) continued to the sample's position, minus the bias: no surface "
                 "acne in the truth. Banner leak (railing scene): banner receivers with PCF truth >= "
              << leak_truth_min << " (shadowed by the railing 14 cm in front); leak = mean of max(0, truth - "
                 "method), and the share of them leaking more than "
              << leak_significant << ". Error images (--out): red = lighter than the PCF truth, blue = darker, "
                 "white = equal, full colour at |error| >= 0.1 (colour bar below each).\n\n";
}

void print_scene(const SceneResult& result) {
    const Scene& scene = result.scene;
    const std::vector<MethodResult>& methods = result.methods;
    std::cout << "## " << scene.name << " (" << result.width << "x" << result.height << ", " << result.samples
              << "x MSAA; " << result.view_width << "x" << result.view_height << " = " << result.count << " receivers";
    if (result.has_materials) std::cout << "; " << result.leak_set_size << " banner receivers in the railing's shadow";
    std::cout << ")\n\n"
              << "| method | bits | kernel ms (x msm64) | vs 128-bit: >3% | >10% | max | mean | vs PCF truth: >3% | "
                 ">10% | max | mean | banner leak: mean | leaking > 0.1 |\n"
              << "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
    double msm64_ms = 0;
    for (const MethodResult& m : methods)
        if (m.name == "msm64") msm64_ms = m.kernel_ms;
    for (const MethodResult& m : methods) {
        std::cout << "| " << m.name << " | " << 8 * msmcl::texel_bytes(m.format) << " | " << fixed(m.kernel_ms, 3)
                  << " (" << fixed(msm64_ms > 0 ? m.kernel_ms / msm64_ms : 0.0, 2) << ") | "
                  << error_cells(m.vs_moments128) << " | " << error_cells(m.vs_truth)
                  << " | " << (m.leak.available ? fixed(m.leak.mean_leak) : "-") << " | "
                  << (m.leak.available ? percent(m.leak.share_leaking) : "-") << " |\n";
    }
    if (result.has_materials)
        std::cout << "\nBanner leak set: " << result.leak_set_size << " receivers, mean PCF truth "
                  << fixed(methods[0].leak.mean_truth, 3) << ".";
    auto share_of = [](std::size_t part, std::size_t whole) {
        return percent(whole ? static_cast<double>(part) / whole : 0.0);
    };
    std::cout << "\nmoments128 vs PCF truth: " << result.moments128_above << " receivers off by > 3%: "
              << result.moments128_lighter << " (" << share_of(result.moments128_lighter, result.moments128_above)
              << ") lighter than the truth (the lower bound leaks light), " << result.moments128_darker_lit << " ("
              << share_of(result.moments128_darker_lit, result.moments128_above)
              << ") darker where the truth is lit (< 3%), and for " << result.moments128_self_shadow << " of those ("
              << share_of(result.moments128_self_shadow, result.moments128_darker_lit)
              << ") the error is within 3% of the 4MSM bound of the receiver's own plane alone (self-shadowing "
                 "of a surface sloped in light space); the rest darker in partial shadow. Against PCF with a "
                 "constant receiver depth (surface acne in the truth) moments128 is off by > 3% on "
              << percent(methods[0].vs_truth_constant_bias.share_above) << ".\n\n";

    std::cout << "nlq64 against 128-bit moments, step by step (double: the double-precision filtered "
                 "moments shaded in long double, reference/moment_math.hpp):\n\n"
              << "| comparison | what differs | >3% | >10% | max | mean |\n"
              << "| --- | --- | ---: | ---: | ---: | ---: |\n";
    for (const Step& step : result.steps)
        std::cout << "| " << step.name << " | " << step.what << " | " << error_cells(step.stats) << " |\n";
    std::cout << "\nnlq64 codes of the float32 encoder more than 1 step from the double encoding: "
              << percent(result.texels_off / result.texel_count) << " of texels (y1 " << percent(result.codes_off[0] / result.texel_count)
              << ", y2 " << percent(result.codes_off[1] / result.texel_count) << ", v2 " << percent(result.codes_off[2] / result.texel_count)
              << ", Psi4 " << percent(result.codes_off[3] / result.texel_count) << "); "
              << percent(result.texels_off ? static_cast<double>(result.texels_off_one_depth) / result.texels_off : 0.0)
              << " of those have a filtered variance < 1e-7 (one depth: y1, y2, v2 hardly constrained).\n\n"
              << "Where nlq64 differs from moments128 by > 3% (device, bilinear), by the spread of the "
                 "samples the lookup filters around the receiver's plane (internal depth):\n\n"
              << "| footprint | receivers | nlq64 > 3% | share of class | > 10% | of the > 3%: "
                 "exact nlq (double) > 3% too | nearest: nlq64 > 3% | nearest: device vs double nlq64 > 3% |\n"
              << "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
    for (std::size_t k = 0; k < result.classes.size(); ++k) {
        const FootprintClass& c = result.classes[k];
        std::cout << "| " << spread_class_names[k] << " | " << c.receivers << " | " << c.nlq64_above << " | "
                  << percent(c.receivers ? static_cast<double>(c.nlq64_above) / c.receivers : 0) << " | "
                  << c.nlq64_above_large << " | " << c.lookup_above << " | " << c.nearest_above << " | "
                  << c.nearest_encoder_above << " |\n";
    }
    std::cout << "\n";
}

void write_scene_images(const SceneResult& result, const std::string& out_dir) {
    const Scene& scene = result.scene;
    const std::vector<MethodResult>& methods = result.methods;
    // Images: ground truth, shadow and error per method, nlq64's > 3% receivers.
    const std::string prefix = out_dir + "/" + scene.name + "_";
    auto grey = [&](const std::string& name, const std::vector<double>& values) {
        msmcl::io::write_png_preview(prefix + name, result.view_width, result.view_height, 1,
                                     std::vector<float>(values.begin(), values.end()));
    };
    grey("pcf_truth.png", result.truth);
    grey("pcf_constant_bias.png", result.truth_constant_bias);
    for (const MethodResult& m : methods) {
        grey(m.name + "_shadow.png", m.shadow);
        // Full colour at |error| >= 0.1, with the labelled colour bar below.
        msmcl::tools::write_signed_difference_png(prefix + m.name + "_error.png", result.view_width,
                                                  result.view_height, light_difference(m.shadow, result.truth),
                                                  large_error_threshold);
    }
    msmcl::io::write_png_preview(prefix + "nlq64_vs_moments128.png", result.view_width,
                                 result.view_height + marks_legend_rows, 3,
                                 difference_marks(methods[2].shadow, methods[0].shadow, result.view_width, "nlq64"));
}

nlohmann::json scene_json(const SceneResult& result) {
    const Scene& scene = result.scene;
    const std::vector<MethodResult>& methods = result.methods;
    nlohmann::json json_methods = nlohmann::json::array();
    for (const MethodResult& m : methods) {
        nlohmann::json entry{{"method", m.name},
                             {"format", msmcl::format_name(m.format)},
                             {"bits", 8 * msmcl::texel_bytes(m.format)},
                             {"light_bleed_reduction", m.light_bleed_reduction},
                             {"filter_kernel_ms", m.kernel_ms},
                             {"vs_moments128", stats_json(m.vs_moments128)},
                             {"vs_pcf_truth", stats_json(m.vs_truth)},
                             {"vs_pcf_constant_bias", stats_json(m.vs_truth_constant_bias)}};
        if (m.leak.available)
            entry["banner_leak"] = {{"mean", m.leak.mean_leak}, {"share_above_0_1", m.leak.share_leaking}};
        json_methods.push_back(entry);
    }
    nlohmann::json json_steps = nlohmann::json::array();
    for (const Step& step : result.steps)
        json_steps.push_back({{"comparison", step.name}, {"what", step.what}, {"stats", stats_json(step.stats)}});
    nlohmann::json json_classes = nlohmann::json::array();
    for (std::size_t k = 0; k < result.classes.size(); ++k)
        json_classes.push_back({{"class", spread_class_names[k]},
                                {"receivers", result.classes[k].receivers},
                                {"nlq64_above_3pct", result.classes[k].nlq64_above},
                                {"nlq64_above_10pct", result.classes[k].nlq64_above_large},
                                {"exact_nlq_above_3pct_too", result.classes[k].lookup_above},
                                {"nearest_nlq64_above_3pct", result.classes[k].nearest_above},
                                {"nearest_device_vs_double_nlq64_above_3pct", result.classes[k].nearest_encoder_above}});
    nlohmann::json json_scene{{"scene", scene.name},
                              {"depth", scene.depth_path},
                              {"receivers", scene.receivers_path},
                              {"receiver_count", result.count},
                              {"methods", json_methods},
                              {"nlq64_decomposition", json_steps},
                              {"nlq64_codes_off_by_more_than_1",
                               {{"texels", result.texels_off / result.texel_count},
                                {"y1", result.codes_off[0] / result.texel_count},
                                {"y2", result.codes_off[1] / result.texel_count},
                                {"v2", result.codes_off[2] / result.texel_count},
                                {"psi4", result.codes_off[3] / result.texel_count},
                                {"share_of_those_with_variance_below_1e-7",
                                 result.texels_off ? static_cast<double>(result.texels_off_one_depth) / result.texels_off : 0.0}}},
                              {"nlq64_above_3pct_by_footprint_spread", json_classes},
                              {"moments128_vs_truth_above_3pct",
                               {{"count", result.moments128_above},
                                {"lighter", result.moments128_lighter},
                                {"darker_where_truth_lit", result.moments128_darker_lit},
                                {"explained_by_own_plane", result.moments128_self_shadow}}}};
    if (result.has_materials) {
        json_scene["materials"] = scene.materials_path;
        json_scene["banner_leak_set"] = {{"count", result.leak_set_size}, {"mean_truth", methods[0].leak.mean_truth}};
    }
    return json_scene;
}

nlohmann::json results_json(const std::string& device_name, const std::string& kernel_name, nlohmann::json scenes) {
    return nlohmann::json{{"device", device_name},
                          {"kernel", kernel_name},
                          {"sigma", blur_sigma},
                          {"depth_bias", depth_bias},
                          {"filter_kernel_ms", "median kernel stage of " + std::to_string(timed_filter_runs) +
                                                   " filter runs per format"},
                          {"truth", "PCF with per-sample receiver planes, same 9x9 Gaussian, bilinear"},
                          {"leak_definition",
                           "banner receivers with PCF truth >= 0.5; mean of max(0, truth - method); share with "
                           "truth - method > 0.1"},
                          {"error_image_scale", "full colour at |error| >= 0.1; red lighter than truth, blue darker, white equal"},
                          {"scenes", std::move(scenes)}};
}

} // namespace quality
