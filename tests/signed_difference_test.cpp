// The signed-difference colour map of the quality figures (tools/signed_difference.hpp): the
// colours at the documented points, the sign convention for shadow intensities and light,
// the statistics, and the PNG's size with its legend rows.
#include "tools/signed_difference.hpp"

#include <msmcl/errors.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <vector>

namespace {

using msmcl::tools::Quantity;

std::array<int, 3> bytes_of(const std::array<float, 3>& colour) {
    return {int(std::lround(colour[0] * 255)), int(std::lround(colour[1] * 255)), int(std::lround(colour[2] * 255))};
}

TEST(SignedDifference, ColoursAtTheDocumentedPoints) {
    // White at 0, ColorBrewer RdBu's ends at +-range and beyond, gray for NaN.
    EXPECT_EQ(bytes_of(msmcl::tools::signed_difference_colour(0.0, 0.5)), (std::array<int, 3>{255, 255, 255}));
    EXPECT_EQ(bytes_of(msmcl::tools::signed_difference_colour(0.5, 0.5)), (std::array<int, 3>{0xb2, 0x18, 0x2b}));
    EXPECT_EQ(bytes_of(msmcl::tools::signed_difference_colour(7.0, 0.5)), (std::array<int, 3>{0xb2, 0x18, 0x2b}));
    EXPECT_EQ(bytes_of(msmcl::tools::signed_difference_colour(-0.5, 0.5)), (std::array<int, 3>{0x21, 0x66, 0xac}));
    EXPECT_EQ(bytes_of(msmcl::tools::signed_difference_colour(-1e9, 0.5)), (std::array<int, 3>{0x21, 0x66, 0xac}));
    EXPECT_EQ(bytes_of(msmcl::tools::signed_difference_colour(std::nan(""), 0.5)), (std::array<int, 3>{128, 128, 128}));
    // Lighter is red-ish (red above blue), darker blue-ish, more so the larger |d|.
    for (double d : {0.05, 0.2, 0.4}) {
        const auto lighter = msmcl::tools::signed_difference_colour(d, 0.5);
        const auto darker = msmcl::tools::signed_difference_colour(-d, 0.5);
        EXPECT_GT(lighter[0], lighter[2]) << d;
        EXPECT_GT(darker[2], darker[0]) << d;
        EXPECT_LT(msmcl::tools::signed_difference_colour(d + 0.05, 0.5)[1], lighter[1]) << d;
    }
}

TEST(SignedDifference, DifferenceIsTakenInLight) {
    // A shadow intensity below the truth's is lighter: d > 0; for light the sign stays.
    const std::vector<double> shadow = msmcl::tools::signed_difference({0.2f, 0.9f}, {0.5f, 0.5f}, Quantity::shadow_intensity);
    EXPECT_NEAR(shadow[0], 0.3, 1e-7);
    EXPECT_NEAR(shadow[1], -0.4, 1e-7);
    const std::vector<double> light = msmcl::tools::signed_difference({0.2f, NAN}, {0.5f, 0.5f}, Quantity::light);
    EXPECT_NEAR(light[0], -0.3, 1e-7);
    EXPECT_TRUE(std::isnan(light[1]));
    EXPECT_THROW(msmcl::tools::signed_difference({0.0f}, {0.0f, 1.0f}, Quantity::light), msmcl::input_error);
}

TEST(SignedDifference, Statistics) {
    // 100 values: 0.01 .. 1.00 lighter, NaN skipped; p99 by nearest rank is the 99th.
    std::vector<double> d;
    for (int i = 1; i <= 100; ++i) d.push_back(i / 100.0);
    d.push_back(std::nan(""));
    d[0] = -0.5;
    const msmcl::tools::DifferenceStats s = msmcl::tools::difference_stats(d, 0.3);
    EXPECT_EQ(s.pixels, 100u);
    EXPECT_DOUBLE_EQ(s.p99_abs, 0.99);
    EXPECT_DOUBLE_EQ(s.max_abs, 1.0);
    EXPECT_DOUBLE_EQ(s.share_lighter, 0.70); // 0.31 .. 1.00
    EXPECT_DOUBLE_EQ(s.share_darker, 0.01);  // -0.5
}

TEST(SignedDifference, PngHasTheLegendRowsBelowTheImage) {
    const std::filesystem::path path = std::filesystem::temp_directory_path() / "msmcl_signed_difference_test.png";
    const int width = 13, height = 7;
    std::vector<double> d(width * height);
    for (std::size_t i = 0; i < d.size(); ++i) d[i] = (double(i) / d.size() - 0.5) * 2.0;
    msmcl::tools::write_signed_difference_png(path.string(), width, height, d, 0.5);
    // IHDR: width and height, big-endian, at bytes 16 and 20.
    std::ifstream in(path, std::ios::binary);
    std::vector<unsigned char> header(24);
    in.read(reinterpret_cast<char*>(header.data()), 24);
    const auto be32 = [&](int at) {
        return (std::uint32_t(header[at]) << 24) | (header[at + 1] << 16) | (header[at + 2] << 8) | header[at + 3];
    };
    EXPECT_EQ(be32(16), std::uint32_t(width));
    EXPECT_EQ(be32(20), std::uint32_t(height + msmcl::tools::kLegendRows));
    std::filesystem::remove(path);
    EXPECT_THROW(msmcl::tools::write_signed_difference_png(path.string(), width, height, d, 0.0), msmcl::input_error);
    EXPECT_THROW(msmcl::tools::write_signed_difference_png(path.string(), width, height + 1, d, 0.5), msmcl::input_error);
    EXPECT_FALSE(std::filesystem::exists(path));
}

} // namespace
