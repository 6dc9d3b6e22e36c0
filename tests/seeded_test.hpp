// A GoogleTest fixture with a reproducible random generator: a fixed default seed,
// MSMCL_TEST_SEED overrides it, the seed is printed once and recorded per test, and each
// test draws from its own stream (the seed mixed with the test's name).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>

namespace msmcl::testing {

/// The run's seed: MSMCL_TEST_SEED, else `default_seed`; printed on first use.
inline std::uint64_t run_seed(std::uint64_t default_seed = 20170731u) {
    static const std::uint64_t seed = [default_seed] {
        const char* env = std::getenv("MSMCL_TEST_SEED");
        const std::uint64_t value = env ? std::strtoull(env, nullptr, 0) : default_seed;
        std::printf("MSMCL_TEST_SEED=%llu\n", static_cast<unsigned long long>(value));
        return value;
    }();
    return seed;
}

class SeededTest : public ::testing::Test {
protected:
    void SetUp() override {
        seed_ = run_seed();
        RecordProperty("seed", std::to_string(seed_));
        rng_.seed(seed_ ^ std::hash<std::string>{}(
                              ::testing::UnitTest::GetInstance()->current_test_info()->name()));
    }
    double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }

    std::uint64_t seed_ = 0;
    std::mt19937_64 rng_;
};

} // namespace msmcl::testing

#include <msmcl/context.hpp>

#include <memory>

namespace msmcl::testing {

/// A suite sharing one msmcl::Context on the default device (built once per suite, as
/// PoCL compiles programs per context); every test skips where there is no device.
/// `Suite` is the deriving fixture, so that each suite has its own context; `DefaultSeed`
/// the seed of the run when MSMCL_TEST_SEED is not set.
template <class Suite, std::uint64_t DefaultSeed = 20160227u>
class DeviceSuite : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        seed_ = static_cast<std::uint32_t>(run_seed(DefaultSeed));
        if (msmcl::list_devices().empty()) return;
        context_ = std::make_unique<msmcl::Context>();
    }
    static void TearDownTestSuite() { context_.reset(); }
    void SetUp() override {
        if (!context_) GTEST_SKIP() << "no OpenCL device";
    }
    static msmcl::Context& context() { return *context_; }
    static inline std::unique_ptr<msmcl::Context> context_;
    static inline std::uint32_t seed_ = 0;
};

} // namespace msmcl::testing
