// msmcl-soft-truth: brute-force PCSS of a view in double precision (the ground truth of the
// soft-shadow figures), and the error of moment soft shadow mapping against it taken apart
// by cause (docs/soft_shadows.md). Links the double-precision references (tests/reference).
#include "signed_difference.hpp"

#include "io/exr_io.hpp"
#include "reference/soft_analysis.hpp"

#include <msmcl/errors.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <map>
#include <thread>

namespace {

namespace ref = msmcl::reference;

struct Inputs {
    std::string depth, receivers;
    double light_size = 60, depth_bias = 0.02, min_filter = 1;
    std::uint32_t max_kernel = 4096;
    int search_size = 0;
    int threads = 0;
};

struct Scene {
    ref::DepthMap map;
    msmcl::io::ReceiverGrid receivers;
    ref::SoftParams params;
    std::vector<double> zf; // internal receiver depths, bias subtracted
};

// floor(sqrt(n)) exactly.
int integer_sqrt(std::uint32_t n) {
    int root = static_cast<int>(std::sqrt(double(n)));
    while (std::int64_t(root) * root > n) --root;
    while (std::int64_t(root + 1) * (root + 1) <= n) ++root;
    return root;
}

Scene load(const Inputs& in) {
    Scene scene;
    const msmcl::DepthImage depth = msmcl::io::read_depth_exr(in.depth, msmcl::DepthRange::zero_one);
    scene.map.width = depth.width;
    scene.map.height = depth.height;
    scene.map.samples = depth.samples;
    scene.map.depth = depth.depth;
    scene.map.zero_one = true;
    scene.receivers = msmcl::io::read_receivers_exr(in.receivers);
    // The limits msmcl soft applies: search side and largest filter floor(sqrt(N)).
    const int side = integer_sqrt(in.max_kernel);
    if (in.search_size < 0 || in.search_size > side)
        throw msmcl::input_error("--search-size must be in [0, " + std::to_string(side) + "]");
    scene.params.search_size = in.search_size == 0 ? side : in.search_size;
    scene.params.light_size = in.light_size;
    scene.params.min_filter_size = in.min_filter;
    scene.params.max_filter_size = side;
    for (float z : scene.receivers.points.z) scene.zf.push_back(ref::internal_depth(z, true) - in.depth_bias);
    return scene;
}

// Runs f(i) for every receiver on `threads` threads (each result depends on i only).
void for_each_receiver(std::size_t count, int threads, const std::function<void(std::size_t)>& f) {
    if (threads <= 0) threads = std::max(1u, std::thread::hardware_concurrency());
    std::atomic<std::size_t> next{0};
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&] {
            for (std::size_t start; (start = next.fetch_add(256)) < count;)
                for (std::size_t i = start; i < std::min(count, start + 256); ++i) f(i);
        });
    for (std::thread& thread : pool) thread.join();
}

void write_y(const std::string& path, int width, int height, const std::vector<double>& values) {
    msmcl::io::ExrImage image;
    image.width = width;
    image.height = height;
    msmcl::io::ExrChannel y;
    y.name = "Y";
    y.type = msmcl::io::SampleType::float32;
    for (double v : values) y.values.push_back(static_cast<float>(v));
    image.channels.push_back(std::move(y));
    msmcl::io::write_exr(path, image);
}

// Sky pixels: receivers on the near plane (z = 0 as rendered), lit by construction.
bool is_sky(float z) { return z <= 0.0f; }

// Share lighter / darker than the truth by more than 0.3 and the p99 of |difference|, over
// the receivers that are not sky.
std::string error_line(const std::vector<double>& shadow, const std::vector<double>& truth,
                       const std::vector<float>& z) {
    std::vector<double> light_difference;
    for (std::size_t i = 0; i < truth.size(); ++i)
        if (!is_sky(z[i])) light_difference.push_back(truth[i] - shadow[i]);
    const msmcl::tools::DifferenceStats s = msmcl::tools::difference_stats(light_difference, 0.3);
    char line[256];
    std::snprintf(line, sizeof line, "lighter by > 0.3: %.2f%%, p99 |d| %.3f, darker by > 0.3: %.2f%%, mean |d| %.4f",
                  100 * s.share_lighter, s.p99_abs, 100 * s.share_darker, s.mean_abs);
    return line;
}

int run_pcss(const Inputs& in, const std::string& output) {
    const Scene scene = load(in);
    const ref::PcssMap pcss_map(scene.map);
    const std::size_t count = scene.receivers.points.size();
    std::vector<double> shadow(count);
    for_each_receiver(count, in.threads, [&](std::size_t i) {
        shadow[i] = pcss_map.pcss(scene.receivers.points.u[i], scene.receivers.points.v[i], scene.zf[i], scene.params).shadow;
    });
    write_y(output, scene.receivers.width, scene.receivers.height, shadow);
    return 0;
}

int run_analyse(const Inputs& in, double threshold, const std::vector<std::string>& filters,
                const std::vector<std::string>& shadows) {
    const Scene scene = load(in);
    const ref::PcssMap pcss_map(scene.map);
    const ref::MomentTable table(scene.map, in.max_kernel);
    const msmcl::Receivers& r = scene.receivers.points;
    const std::size_t count = r.size();
    std::vector<double> pcss(count), method(count);
    for_each_receiver(count, in.threads, [&](std::size_t i) {
        pcss[i] = pcss_map.pcss(r.u[i], r.v[i], scene.zf[i], scene.params).shadow;
        method[i] = table.soft_shadow(pcss_map, r.u[i], r.v[i], scene.zf[i], scene.params).shadow;
    });
    std::size_t visible = 0;
    for (float z : r.z) visible += !is_sky(z);
    std::printf("receivers: %zu (%zu not sky); the published method in double vs PCSS: %s\n", count, visible,
                error_line(method, pcss, r.z).c_str());

    // The receivers off by more than the threshold, and what each stage swapped alone fixes.
    std::vector<std::size_t> off;
    for (std::size_t i = 0; i < count; ++i)
        if (!is_sky(r.z[i]) && std::abs(method[i] - pcss[i]) > threshold) off.push_back(i);
    struct Stage {
        const char* name;
        std::function<void(ref::SoftSwaps&)> swap;
    };
    const std::vector<Stage> stages = {
        {"blocker search: three-depth reconstruction -> the samples' blocker share and depth",
         [](ref::SoftSwaps& s) { s.exact_blockers = true; }},
        {"blocker search: eps-weighted average -> plain average", [](ref::SoftSwaps& s) { s.plain_average = true; }},
        {"umbra early-out -> always filter", [](ref::SoftSwaps& s) { s.no_umbra_early_out = true; }},
        {"filter size -> PCSS's", [](ref::SoftSwaps& s) { s.pcss_filter_size = true; }},
        {"4MSM bound of the filter region -> its exact PCF", [](ref::SoftSwaps& s) { s.exact_filter = true; }},
        {"table precision -> unquantized double moments", [](ref::SoftSwaps& s) { s.unquantized_table = true; }},
    };
    // fixed_alone[k][j]: stage k swapped alone brings off[j] within the threshold;
    // cumulative[j]: the first k such that stages 0..k swapped together do.
    std::vector<std::vector<char>> fixed_alone(stages.size(), std::vector<char>(off.size(), 0));
    std::vector<int> cumulative(off.size(), -1);
    for_each_receiver(off.size(), in.threads, [&](std::size_t j) {
        const std::size_t i = off[j];
        ref::SoftSwaps together;
        for (std::size_t k = 0; k < stages.size(); ++k) {
            ref::SoftSwaps alone;
            stages[k].swap(alone);
            stages[k].swap(together);
            const double a = table.soft_shadow(pcss_map, r.u[i], r.v[i], scene.zf[i], scene.params, alone).shadow;
            fixed_alone[k][j] = std::abs(a - pcss[i]) <= threshold;
            if (cumulative[j] < 0) {
                const double c = table.soft_shadow(pcss_map, r.u[i], r.v[i], scene.zf[i], scene.params, together).shadow;
                if (std::abs(c - pcss[i]) <= threshold) cumulative[j] = static_cast<int>(k);
            }
        }
    });
    std::size_t lighter = 0, smaller_filter = 0, larger_filter = 0, umbra = 0;
    for (std::size_t i : off) {
        lighter += method[i] < pcss[i];
        const ref::SoftResult m = table.soft_shadow(pcss_map, r.u[i], r.v[i], scene.zf[i], scene.params);
        const ref::SoftResult t = pcss_map.pcss(r.u[i], r.v[i], scene.zf[i], scene.params);
        umbra += m.filter_size == 0;
        smaller_filter += m.filter_size != 0 && m.filter_size < 0.8 * t.filter_size;
        larger_filter += m.filter_size > 1.25 * t.filter_size;
    }
    std::printf("off receivers: filter side < 0.8x PCSS's: %zu, > 1.25x: %zu, umbra early-out: %zu\n", smaller_filter,
                larger_filter, umbra);
    std::printf("off by > %.2f: %zu receivers (%.2f%% of those not sky; %zu lighter than PCSS, %zu darker)\n",
                threshold, off.size(), 100.0 * off.size() / std::max<std::size_t>(visible, 1), lighter,
                off.size() - lighter);
    std::printf("| stage swapped for its exact counterpart | fixed by this swap alone | fixed by it alone and no other | first fixed when swapped in this order |\n| --- | --- | --- | --- |\n");
    const double total = std::max<std::size_t>(off.size(), 1);
    std::size_t none_alone = 0;
    for (std::size_t j = 0; j < off.size(); ++j) {
        bool any = false;
        for (std::size_t k = 0; k < stages.size(); ++k) any = any || fixed_alone[k][j];
        none_alone += !any;
    }
    for (std::size_t k = 0; k < stages.size(); ++k) {
        std::size_t alone = 0, only = 0, first = 0;
        for (std::size_t j = 0; j < off.size(); ++j) {
            alone += fixed_alone[k][j];
            bool other = false;
            for (std::size_t o = 0; o < stages.size(); ++o) other = other || (o != k && fixed_alone[o][j]);
            only += fixed_alone[k][j] && !other;
            first += cumulative[j] == static_cast<int>(k);
        }
        std::printf("| %s | %.1f%% | %.1f%% | %.1f%% |\n", stages[k].name, 100 * alone / total, 100 * only / total,
                    100 * first / total);
    }
    std::printf("fixed by no single swap: %.1f%%\n", 100 * none_alone / total);

    // Device results (EXR channel Y of msmcl soft) against PCSS.
    for (const std::string& path : shadows) {
        const msmcl::io::ExrImage image = msmcl::io::read_exr(path);
        const msmcl::io::ExrChannel* y = image.find_channel("Y");
        if (!y || y->type == msmcl::io::SampleType::uint32 || y->values.size() != count)
            throw msmcl::input_error(path + ": no FLOAT channel Y of the receivers' size");
        const std::vector<double> shadow(y->values.begin(), y->values.end());
        std::printf("%s vs PCSS: %s\n", path.c_str(), error_line(shadow, pcss, r.z).c_str());
    }
    // Candidates against PCSS (double, same table): "k,parts" (see SoftVariant).
    for (const std::string& candidate : filters) {
        ref::SoftVariant variant;
        if (std::sscanf(candidate.c_str(), "%lf,%d", &variant.receiver_weight, &variant.parts) != 2 || variant.parts < 1)
            throw msmcl::input_error("--candidate wants K,PARTS (receiver weight, filter parts per side), got " + candidate);
        std::vector<double> shadow(count);
        for_each_receiver(count, in.threads, [&](std::size_t i) {
            shadow[i] = table.soft_shadow(pcss_map, r.u[i], r.v[i], scene.zf[i], scene.params, {}, variant).shadow;
        });
        std::printf("candidate receiver weight %g, %dx%d filter parts vs PCSS: %s\n", variant.receiver_weight,
                    variant.parts, variant.parts, error_line(shadow, pcss, r.z).c_str());
    }
    return 0;
}

void add_inputs(CLI::App* command, Inputs& in) {
    command->add_option("depth", in.depth, "depth map EXR (as msmcl sat reads it; depth range [0,1])")->required();
    command->add_option("receivers", in.receivers, "receivers EXR (U, V, Z)")->required();
    command->add_option("--light-size", in.light_size, "as msmcl soft")->capture_default_str();
    command->add_option("--depth-bias", in.depth_bias, "as msmcl soft")->capture_default_str();
    command->add_option("--min-filter", in.min_filter, "as msmcl soft")->capture_default_str();
    command->add_option("--max-kernel", in.max_kernel, "the table's N (search and filter clamp floor(sqrt(N)))")
        ->capture_default_str();
    command->add_option("--search-size", in.search_size, "as msmcl soft (0: floor(sqrt(N)))")->capture_default_str();
    command->add_option("--threads", in.threads, "worker threads (0: one per core)")->capture_default_str();
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"msmcl-soft-truth: brute-force PCSS in double precision, and the moment soft shadows' error by cause",
                 "msmcl-soft-truth"};
    app.require_subcommand(1);
    Inputs pcss_inputs, analyse_inputs;
    std::string output;
    double threshold = 0.2;
    std::vector<std::string> candidates, shadows;
    CLI::App* pcss = app.add_subcommand("pcss", "PCSS of every receiver -> EXR channel Y (shadow intensity)");
    add_inputs(pcss, pcss_inputs);
    pcss->add_option("output", output, "EXR to write")->required();
    CLI::App* analyse = app.add_subcommand(
        "analyse", "moment soft shadows in double vs PCSS; the receivers off by > threshold classified by cause");
    add_inputs(analyse, analyse_inputs);
    analyse->add_option("--threshold", threshold, "|moment - PCSS| counted as off")->capture_default_str();
    analyse->add_option("--candidate", candidates, "variants to compare: K,PARTS (receiver weight of the blocker average, filter parts per side; 0,1 = published)");
    analyse->add_option("--shadow", shadows, "EXR (channel Y) of msmcl soft on the same receivers, to compare with PCSS");
    CLI11_PARSE(app, argc, argv);
    try {
        if (pcss->parsed()) return run_pcss(pcss_inputs, output);
        return run_analyse(analyse_inputs, threshold, candidates, shadows);
    } catch (const std::exception& e) {
        std::cerr << "msmcl-soft-truth: " << e.what() << std::endl;
        return dynamic_cast<const msmcl::input_error*>(&e) ? 2 : 1;
    }
}
