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
