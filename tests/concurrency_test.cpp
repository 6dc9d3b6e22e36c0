// One Context shared by several threads: every call gives exactly the bytes of the same
// call made alone (filter, shade and SAT builds, every format, both SAT distributions
// that keep per-Context scratch). MSMCL_CONCURRENCY_CALLS sets the calls per thread
// (default 100; the ThreadSanitizer stage runs fewer).
#include "seeded_test.hpp"

#include <msmcl/msmcl.hpp>

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

namespace {

bool have_device() {
    try {
        return !msmcl::list_devices().empty();
    } catch (const msmcl::error&) {
        return false;
    }
}

int calls_per_thread() {
    const char* text = std::getenv("MSMCL_CONCURRENCY_CALLS");
    const int calls = text ? std::atoi(text) : 100;
    return calls > 0 ? calls : 100;
}

class SharedContext : public msmcl::testing::SeededTest {};

TEST_F(SharedContext, EightThreadsGetTheSingleThreadedBytes) {
    if (!have_device()) GTEST_SKIP() << "no OpenCL device";
    constexpr int threads = 8;
    const int calls = calls_per_thread();
    // Small odd-sized maps: border handling everywhere, quick calls.
    const int width = 37, height = 29, samples = 4;
    msmcl::DepthImage depth{width, height, samples, {}};
    for (std::size_t i = 0; i < std::size_t(width) * height * samples; ++i)
        depth.depth.push_back(static_cast<float>(uniform(0.05, 0.95)));
    msmcl::Receivers receivers;
    for (int i = 0; i < 300; ++i) {
        receivers.u.push_back(static_cast<float>(uniform(0.0, width)));
        receivers.v.push_back(static_cast<float>(uniform(0.0, height)));
        receivers.z.push_back(static_cast<float>(uniform(0.0, 1.0)));
    }
    const msmcl::Format formats[] = {msmcl::Format::moments128, msmcl::Format::msm64, msmcl::Format::nlq64,
                                     msmcl::Format::nlq32};
    const msmcl::SatKernel sat_kernels[] = {msmcl::SatKernel::tiled_cpu, msmcl::SatKernel::tiled_gpu};

    msmcl::Context context;
    // What each call gives when it is the only one.
    std::vector<msmcl::Texture> textures;
    std::vector<std::vector<float>> shadows;
    for (msmcl::Format format : formats) {
        msmcl::FilterOptions options;
        options.format = format;
        textures.push_back(msmcl::filter(context, depth, options));
        shadows.push_back(msmcl::shade(context, textures.back(), receivers, msmcl::ShadeOptions{}));
    }
    std::vector<std::vector<std::uint32_t>> tables;
    for (msmcl::SatKernel kernel : sat_kernels) {
        msmcl::SatOptions options;
        options.kernel = kernel;
        tables.push_back(msmcl::build_sat(context, depth, options).words);
    }

    // All threads at once, every thread through every format and both SAT kernels, the
    // same format on several threads at a time.
    std::atomic<int> mismatches{0}, failures{0};
    std::vector<std::string> first_failure(threads);
    const auto work = [&](int thread) {
        try {
            for (int call = 0; call < calls; ++call) {
                const std::size_t f = static_cast<std::size_t>(call % 4);
                msmcl::FilterOptions options;
                options.format = formats[f];
                const msmcl::Texture texture = msmcl::filter(context, depth, options);
                mismatches += texture.words != textures[f].words;
                mismatches += msmcl::shade(context, texture, receivers, msmcl::ShadeOptions{}) != shadows[f];
                msmcl::SatOptions sat;
                sat.kernel = sat_kernels[(call + thread) % 2];
                mismatches += msmcl::build_sat(context, depth, sat).words != tables[(call + thread) % 2];
            }
        } catch (const std::exception& e) {
            ++failures;
            first_failure[static_cast<std::size_t>(thread)] = e.what();
        }
    };
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) pool.emplace_back(work, t);
    for (std::thread& t : pool) t.join();

    for (const std::string& failure : first_failure) EXPECT_TRUE(failure.empty()) << failure;
    EXPECT_EQ(failures.load(), 0);
    EXPECT_EQ(mismatches.load(), 0) << "of " << threads * calls * 3 << " calls";
    std::printf("%d threads x %d calls x (filter, shade, sat): %d results differ from the single-threaded bytes\n",
                threads, calls, mismatches.load());
}

} // namespace
