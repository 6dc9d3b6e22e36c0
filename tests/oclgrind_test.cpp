// Every kernel and variant a GPU can be given, run under Oclgrind with its race detector,
// its uninitialized-value checker and its API checks (ctest label `oclgrind`). PoCL runs the
// work-items of a group one after another, which hides races between them, missing fences
// and reads of memory nothing wrote; Oclgrind simulates every work-item and reports each.
// Any Oclgrind diagnostic fails the test, and every output is compared with PoCL's.
//
// How: Oclgrind's ICD library joins the system's ICDs in a vendors folder of this process
// (OCL_ICD_VENDORS, set before the first OpenCL call), with the checks switched on by
// Oclgrind's environment variables. Each case builds a fresh Oclgrind Context whose
// diagnostics go to a log file of its own (OCLGRIND_LOG), which must stay empty; Oclgrind's
// own bugs are worked around in host/runtime/quirks.hpp, never here or in the kernels.
// Maps are small (45x37, not a multiple of any block size): Oclgrind interprets every
// instruction (docs/devices.md gives the label's time).
//
// Oclgrind not installed: the tests skip, unless MSMCL_REQUIRE_OCLGRIND=1 (.ci/run sets
// it), which makes the skip a failure.
#include "tools/scatter_geometry.hpp"
#include "filter_fixtures.hpp"
#include "io/scene_json.hpp"
#include "seeded_test.hpp"

#include <msmcl/context.hpp>
#include <msmcl/errors.hpp>
#include <msmcl/filter.hpp>
#include <msmcl/interop.hpp>
#include <msmcl/sat.hpp>
#include <msmcl/scatter.hpp>
#include <msmcl/shade.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#ifndef MSMCL_OCLGRIND_ICD // CMake found no Oclgrind: the tests skip (or fail, see above)
#define MSMCL_OCLGRIND_ICD ""
#endif

namespace {

namespace fs = std::filesystem;
using msmcl::Context;
using msmcl::DepthImage;
using msmcl::DepthRange;
using msmcl::FilterKernel;
using msmcl::FilterOptions;
using msmcl::Format;
using msmcl::SatKernel;
using msmcl::ScatterKernel;
using msmcl::Texture;
using msmcl::TranslucentLayer;

constexpr int kWidth = 45;
constexpr int kHeight = 37;

bool oclgrind_required() {
    const char* text = std::getenv("MSMCL_REQUIRE_OCLGRIND");
    return text && std::string(text) == "1";
}

/// The process's OpenCL set-up, made once before the first OpenCL call: a vendors folder
/// holding Oclgrind's ICD and a copy of every system ICD (PoCL's among them).
class OclgrindPlatform {
public:
    static OclgrindPlatform& get() {
        static OclgrindPlatform platform;
        return platform;
    }
    ~OclgrindPlatform() {
        std::error_code ignored;
        if (!folder_.empty()) fs::remove_all(folder_, ignored);
    }

    /// Empty when Oclgrind can be used; else why not.
    const std::string& missing() const { return missing_; }
    const fs::path& folder() const { return folder_; }

private:
    OclgrindPlatform() {
        const std::string icd = MSMCL_OCLGRIND_ICD;
        if (icd.empty() || !fs::exists(icd)) {
            missing_ = "Oclgrind is not installed (apt-get install oclgrind; CMake looks for liboclgrind-rt-icd.so)";
            return;
        }
        std::string pattern = (fs::temp_directory_path() / "msmcl-oclgrind-XXXXXX").string();
        if (!mkdtemp(pattern.data())) {
            missing_ = "cannot create a temporary folder";
            return;
        }
        folder_ = pattern;
        std::ofstream(folder_ / "oclgrind.icd") << icd << '\n';
        // The ICDs the process would load otherwise.
        const char* vendors = std::getenv("OCL_ICD_VENDORS");
        const fs::path system = vendors && fs::is_directory(vendors) ? fs::path(vendors) : fs::path("/etc/OpenCL/vendors");
        std::error_code error;
        for (const fs::directory_entry& entry : fs::directory_iterator(system, error))
            if (entry.path().extension() == ".icd" && entry.path().filename() != "oclgrind.icd")
                fs::copy_file(entry.path(), folder_ / entry.path().filename(), error);
        setenv("OCL_ICD_VENDORS", folder_.c_str(), 1);
        // The checks of `oclgrind --data-races --uninitialized --check-api`; one simulator
        // thread per test process (ctest runs the tests side by side).
        setenv("OCLGRIND_DATA_RACES", "1", 1);
        setenv("OCLGRIND_UNINITIALIZED", "1", 1);
        setenv("OCLGRIND_CHECK_API", "1", 1);
        setenv("OCLGRIND_NUM_THREADS", "1", 0);
    }

    std::string missing_;
    fs::path folder_;
};

/// Names the differences between two word arrays (at most 8 listed); empty when equal.
std::string word_differences(const std::vector<std::uint32_t>& oclgrind, const std::vector<std::uint32_t>& pocl,
                             std::size_t words_per_item = 1) {
    if (oclgrind.size() != pocl.size())
        return "sizes differ: " + std::to_string(oclgrind.size()) + " vs " + std::to_string(pocl.size());
    std::ostringstream text;
    std::size_t count = 0;
    for (std::size_t i = 0; i < oclgrind.size(); ++i) {
        if (oclgrind[i] == pocl[i]) continue;
        if (++count <= 8)
            text << " [item " << i / words_per_item << " word " << i % words_per_item << ": 0x" << std::hex
                 << oclgrind[i] << " vs 0x" << pocl[i] << std::dec << "]";
    }
    if (count == 0) return "";
    return std::to_string(count) + " of " + std::to_string(oclgrind.size()) + " words differ (Oclgrind vs PoCL):" +
           text.str();
}

/// A bit field of a word and how far Oclgrind's value may be from PoCL's.
struct Field {
    int shift;
    int bits;
    std::uint32_t tolerance;
};

/// Names the words whose fields differ by more than their tolerance; empty when none does.
/// Lists how many words differ at all.
std::string field_differences(const std::vector<std::uint32_t>& oclgrind, const std::vector<std::uint32_t>& pocl,
                              const std::vector<std::vector<Field>>& fields_by_word) {
    if (oclgrind.size() != pocl.size())
        return "sizes differ: " + std::to_string(oclgrind.size()) + " vs " + std::to_string(pocl.size());
    std::ostringstream text;
    std::size_t beyond = 0, differing = 0;
    for (std::size_t i = 0; i < oclgrind.size(); ++i) {
        if (oclgrind[i] == pocl[i]) continue;
        ++differing;
        for (const Field& field : fields_by_word[i % fields_by_word.size()]) {
            const std::uint32_t mask = field.bits == 32 ? 0xffffffffu : (1u << field.bits) - 1u;
            const std::int64_t a = (oclgrind[i] >> field.shift) & mask, b = (pocl[i] >> field.shift) & mask;
            if (std::llabs(a - b) <= field.tolerance) continue;
            if (++beyond <= 8)
                text << " [word " << i << " bits " << field.shift << ".." << field.shift + field.bits - 1 << ": " << a
                     << " vs " << b << "]";
        }
    }
    std::printf("  %zu of %zu words differ (Oclgrind vs PoCL), %zu beyond the tolerance\n", differing, oclgrind.size(),
                beyond);
    if (beyond == 0) return "";
    return std::to_string(beyond) + " fields differ beyond their tolerance:" + text.str();
}

/// Names the values further apart than `tolerance`; prints the largest difference.
std::string float_differences(const std::vector<std::uint32_t>& oclgrind_bits, const std::vector<std::uint32_t>& pocl_bits,
                              double tolerance) {
    if (oclgrind_bits.size() != pocl_bits.size())
        return "sizes differ: " + std::to_string(oclgrind_bits.size()) + " vs " + std::to_string(pocl_bits.size());
    std::ostringstream text;
    std::size_t beyond = 0, differing = 0;
    double largest = 0.0;
    for (std::size_t i = 0; i < oclgrind_bits.size(); ++i) {
        if (oclgrind_bits[i] == pocl_bits[i]) continue;
        ++differing;
        float a, b;
        std::memcpy(&a, &oclgrind_bits[i], 4);
        std::memcpy(&b, &pocl_bits[i], 4);
        const double difference = std::isnan(a) || std::isnan(b) ? INFINITY : std::fabs(double(a) - double(b));
        largest = std::max(largest, difference);
        if (difference > tolerance && ++beyond <= 8) text << " [" << i << ": " << a << " vs " << b << "]";
    }
    std::printf("  %zu of %zu values differ (Oclgrind vs PoCL), by at most %.3g\n", differing, oclgrind_bits.size(),
                largest);
    if (beyond == 0) return "";
    return std::to_string(beyond) + " values differ by more than " + std::to_string(tolerance) + ":" + text.str();
}

std::vector<std::uint32_t> bits_of(const std::vector<float>& values) {
    std::vector<std::uint32_t> words(values.size());
    if (!values.empty()) std::memcpy(words.data(), values.data(), values.size() * sizeof(float));
    return words;
}

class Oclgrind : public msmcl::testing::SeededTest {
protected:
    /// Every lookup of `format` on a filtered map, under Oclgrind against PoCL (Shading, below).
    void shade_lookups(Format format);

    void SetUp() override {
        SeededTest::SetUp();
        const OclgrindPlatform& platform = OclgrindPlatform::get();
        if (!platform.missing().empty()) {
            if (oclgrind_required()) FAIL() << platform.missing() << ", and MSMCL_REQUIRE_OCLGRIND=1";
            GTEST_SKIP() << platform.missing();
        }
        // Both devices must be there once the platform is set up.
        bool oclgrind = false, pocl = false;
        for (const msmcl::DeviceInfo& device : msmcl::list_devices()) {
            oclgrind = oclgrind || device.name == "Oclgrind Simulator";
            pocl = pocl || device.platform_name.find("Portable Computing Language") != std::string::npos;
        }
        ASSERT_TRUE(oclgrind) << "Oclgrind's ICD (" << MSMCL_OCLGRIND_ICD << ") did not load";
        ASSERT_TRUE(pocl) << "no PoCL device to compare with (pocl-opencl-icd)";
    }
    void TearDown() override {
        if (cpu_tile_set_) unsetenv("MSMCL_CPU_TILE");
    }

    static msmcl::DeviceSelection selection(const char* name_or_platform, bool platform) {
        msmcl::DeviceSelection selection;
        (platform ? selection.platform : selection.device) = name_or_platform;
        selection.strict = true;
        selection.use_environment = false;
        return selection;
    }

    /// Runs `work` on a fresh Oclgrind Context (its log file of its own) and fails the test
    /// with the log when Oclgrind reported anything.
    template <class Result>
    Result on_oclgrind(const std::string& what, const std::function<Result(Context&)>& work) {
        const fs::path log = OclgrindPlatform::get().folder() / ("case" + std::to_string(++cases_) + ".log");
        setenv("OCLGRIND_LOG", log.c_str(), 1);
        Result result{};
        {
            Context context(selection("Oclgrind Simulator", false));
            result = work(context);
        } // releasing the context closes the log
        std::ifstream in(log);
        const std::string diagnostics{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
        const std::size_t shown = 6000;
        EXPECT_TRUE(diagnostics.find_first_not_of(" \t\r\n") == std::string::npos)
            << what << ": Oclgrind reported (" << diagnostics.size() << " bytes of log):\n"
            << diagnostics.substr(0, shown) << (diagnostics.size() > shown ? "\n..." : "");
        return result;
    }

    /// Runs `work` on PoCL (one Context per test).
    template <class Result>
    Result on_pocl(const std::function<Result(Context&)>& work) {
        if (!pocl_) pocl_.emplace(selection("Portable Computing Language", true));
        return work(*pocl_);
    }

    using Work = std::function<std::vector<std::uint32_t>(Context&)>;

    /// Both, and the outputs (as 32-bit words) equal bit for bit.
    void expect_identical(const std::string& what, const Work& work, std::size_t words_per_item = 1) {
        const auto oclgrind = on_oclgrind<std::vector<std::uint32_t>>(what, work);
        const auto pocl = on_pocl<std::vector<std::uint32_t>>(work);
        ASSERT_FALSE(pocl.empty()) << what;
        EXPECT_EQ(word_differences(oclgrind, pocl, words_per_item), "") << what << " (seed " << seed_ << ")";
    }

    /// Both, and every field of the outputs within its tolerance (`fields_by_word` per word
    /// of an item, cyclically).
    void expect_fields_close(const std::string& what, const Work& work,
                             const std::vector<std::vector<Field>>& fields_by_word) {
        const auto oclgrind = on_oclgrind<std::vector<std::uint32_t>>(what, work);
        const auto pocl = on_pocl<std::vector<std::uint32_t>>(work);
        ASSERT_FALSE(pocl.empty()) << what;
        std::printf("%s:\n", what.c_str());
        EXPECT_EQ(field_differences(oclgrind, pocl, fields_by_word), "") << what << " (seed " << seed_ << ")";
    }

    /// Both, and the float outputs at most `tolerance` apart.
    void expect_floats_close(const std::string& what, const Work& work, double tolerance) {
        const auto oclgrind = on_oclgrind<std::vector<std::uint32_t>>(what, work);
        const auto pocl = on_pocl<std::vector<std::uint32_t>>(work);
        ASSERT_FALSE(pocl.empty()) << what;
        std::printf("%s:\n", what.c_str());
        EXPECT_EQ(float_differences(oclgrind, pocl, tolerance), "") << what << " (seed " << seed_ << ")";
    }

    /// A filtered texture: bit for bit, except the Psi4 code of the nlq formats, which may
    /// differ by one. Psi4 is a log of a log and its quantizer checks the code with an exp
    /// of an exp (msm_formats.clh); OpenCL lets log and exp be 3 ulp off, and Oclgrind
    /// (the host's libm in double) and PoCL (its own float code) differ in about 1 of
    /// 500 log and 1 of 10 exp results (a probe of 20000 random arguments). Every other
    /// operation the kernels use (+, -, *, /, fma, sqrt) is correctly rounded on both and
    /// gives the same bits.
    void expect_texture(const std::string& what, Format format, const Work& work) {
        const Field all{0, 32, 0};
        if (format == Format::nlq64)
            expect_fields_close(what, work, {{all}, {Field{0, 16, 0}, Field{16, 16, 1}}});
        else if (format == Format::nlq32)
            expect_fields_close(what, work, {{Field{0, 6, 1}, Field{6, 26, 0}}});
        else
            expect_identical(what, work, msmcl::texel_words(format));
    }

    DepthImage depth(int samples, DepthRange range = DepthRange::zero_one, int width = kWidth, int height = kHeight) {
        return filter_fixtures::make_depth(width, height, samples, range, static_cast<std::uint32_t>(rng_()));
    }

    /// `count` translucent layers over `depth`: random depths, opacity 0 on about a third of
    /// the samples (no surface there) and in [0.1, 0.9] elsewhere.
    std::vector<TranslucentLayer> layers(const DepthImage& depth, int count, DepthRange range = DepthRange::zero_one) {
        std::vector<TranslucentLayer> result(count);
        std::uniform_real_distribution<float> unit(0.0f, 1.0f);
        for (TranslucentLayer& layer : result) {
            for (std::size_t i = 0; i < depth.depth.size(); ++i) {
                const float d = unit(rng_);
                layer.depth.push_back(range == DepthRange::zero_one ? d : 2.0f * d - 1.0f);
                layer.opacity.push_back(unit(rng_) < 0.33f ? 0.0f : 0.1f + 0.8f * unit(rng_));
            }
        }
        return result;
    }

    static std::function<std::vector<std::uint32_t>(Context&)> filtering(const DepthImage& depth,
                                                                         const std::vector<TranslucentLayer>& layers,
                                                                         Format format, FilterKernel kernel,
                                                                         DepthRange range = DepthRange::zero_one) {
        return [=](Context& context) {
            FilterOptions options;
            options.format = format;
            options.kernel = kernel;
            options.depth_range = range;
            return msmcl::filter(context, depth, layers, options).words;
        };
    }

    static std::string variant(Format format, int samples, int layers = 0) {
        return std::string(msmcl::format_name(format)) + ", S = " + std::to_string(samples) +
               (layers ? ", " + std::to_string(layers) + " translucent layers" : "");
    }

    void use_cpu_tile(const char* tile) {
        setenv("MSMCL_CPU_TILE", tile, 1);
        cpu_tile_set_ = true;
    }

    std::optional<Context> pocl_;
    int cases_ = 0;
    bool cpu_tile_set_ = false;
};

const Format kFormats[] = {Format::moments128, Format::msm64, Format::nlq64, Format::nlq32};

std::string format_test_name(const ::testing::TestParamInfo<Format>& info) {
    return msmcl::format_name(info.param);
}

class OclgrindFormat : public Oclgrind, public ::testing::WithParamInterface<Format> {};

// ---- Filter kernels.

// The paper's kernel (what `automatic` gives a GPU): one and four samples per texel, and the
// -1,1 depth convention at four samples.
TEST_P(OclgrindFormat, FusedPaper) {
    const Format format = GetParam();
    const DepthImage one = depth(1), four = depth(4), four_signed = depth(4, DepthRange::minus_one_one);
    expect_texture("fused_paper " + variant(format, 1), format, filtering(one, {}, format, FilterKernel::fused_paper));
    expect_texture("fused_paper " + variant(format, 4), format, filtering(four, {}, format, FilterKernel::fused_paper));
    if (format == Format::nlq32)
        expect_texture("fused_paper " + variant(format, 4) + ", depth range -1,1", format,
                         filtering(four_signed, {}, format, FilterKernel::fused_paper, DepthRange::minus_one_one));
}

// The paper's kernel in its smaller groups (MSMCL_FUSED_WORK_ITEMS: 32 work-items, each
// playing 8 of the 256 roles, as on llvmpipe): the same texels.
TEST_F(Oclgrind, FusedPaperInSmallerGroups) {
    const DepthImage four = depth(4);
    setenv("MSMCL_FUSED_WORK_ITEMS", "32", 1);
    for (Format format : {Format::msm64, Format::nlq64})
        expect_texture("fused_paper, 32 work-items, " + variant(format, 4), format,
                       filtering(four, {}, format, FilterKernel::fused_paper));
    unsetenv("MSMCL_FUSED_WORK_ITEMS");
}

// The CPU distribution with a 16x8 tile, so that a 45-texel row has interior and border
// tile columns (filter_fused_cpu_interior and _border); a sample count per format.
TEST_P(OclgrindFormat, FusedCpuInteriorAndBorder) {
    const Format format = GetParam();
    use_cpu_tile("16x8");
    const int samples = format == Format::moments128 ? 1 : format == Format::nlq32 ? 2 : 4;
    expect_texture("fused_cpu 16x8 " + variant(format, samples), format,
                     filtering(depth(samples), {}, format, FilterKernel::fused_cpu));
}

// The three-pass baseline.
TEST_P(OclgrindFormat, ThreePass) {
    const Format format = GetParam();
    expect_texture("three_pass " + variant(format, 4), format, filtering(depth(4), {}, format, FilterKernel::three_pass));
}

INSTANTIATE_TEST_SUITE_P(Formats, OclgrindFormat, ::testing::ValuesIn(kFormats), format_test_name);

// Translucent layers in the paper's kernel: two layers at four samples, the most (8) at one.
TEST_F(Oclgrind, FusedPaperTranslucent) {
    const DepthImage four = depth(4), one = depth(1);
    expect_texture("fused_paper " + variant(Format::msm64, 4, 2), Format::msm64,
                     filtering(four, layers(four, 2), Format::msm64, FilterKernel::fused_paper));
    expect_texture("fused_paper " + variant(Format::nlq64, 1, msmcl::max_translucent_layers), Format::nlq64,
                     filtering(one, layers(one, msmcl::max_translucent_layers), Format::nlq64,
                               FilterKernel::fused_paper));
}

// Translucent layers in the CPU distribution (interior and border) and the three passes.
TEST_F(Oclgrind, FusedCpuAndThreePassTranslucent) {
    const DepthImage one = depth(1);
    const std::vector<TranslucentLayer> two = layers(one, 2);
    use_cpu_tile("16x8");
    expect_texture("fused_cpu 16x8 " + variant(Format::nlq64, 1, 2), Format::nlq64,
                     filtering(one, two, Format::nlq64, FilterKernel::fused_cpu));
    expect_texture("three_pass " + variant(Format::msm64, 1, 2), Format::msm64,
                     filtering(one, two, Format::msm64, FilterKernel::three_pass));
}

// The CPU distribution with its default 128x64 tile (one work-item a tile): border only
// on a map this small.
TEST_F(Oclgrind, FusedCpuDefaultTile) {
    expect_texture("fused_cpu " + variant(Format::msm64, 4), Format::msm64,
                     filtering(depth(4), {}, Format::msm64, FilterKernel::fused_cpu));
}

// Texture arrays (MSM_ARRAY programs: the layer from the launch's third dimension): two
// maps of 45x13 in one call through every filter and table distribution, translucent
// layers in the paper's kernel; Oclgrind checks that no layer reads or writes another's.
TEST_F(Oclgrind, TextureArrays) {
    DepthImage two = depth(1, DepthRange::zero_one, kWidth, 13);
    const DepthImage second = depth(1, DepthRange::zero_one, kWidth, 13);
    two.depth.insert(two.depth.end(), second.depth.begin(), second.depth.end());
    two.layers = 2;
    expect_texture("fused_paper array of 2, " + variant(Format::msm64, 1), Format::msm64,
                   filtering(two, {}, Format::msm64, FilterKernel::fused_paper));
    expect_texture("fused_paper array of 2, " + variant(Format::nlq64, 1, 1), Format::nlq64,
                   filtering(two, layers(two, 1), Format::nlq64, FilterKernel::fused_paper));
    expect_texture("three_pass array of 2, " + variant(Format::nlq32, 1), Format::nlq32,
                   filtering(two, {}, Format::nlq32, FilterKernel::three_pass));
    for (SatKernel kernel : {SatKernel::tiled_gpu, SatKernel::tiled_cpu, SatKernel::row_per_thread}) {
        expect_identical(std::string("sat array of 2, ") + msmcl::sat_kernel_name(kernel), [=](Context& context) {
            msmcl::SatOptions options;
            options.kernel = kernel;
            options.max_kernel_texels = 100;
            return msmcl::build_sat(context, two, options).words;
        }, 4);
    }
    use_cpu_tile("16x8");
    expect_texture("fused_cpu 16x8 array of 2, " + variant(Format::nlq64, 1), Format::nlq64,
                   filtering(two, {}, Format::nlq64, FilterKernel::fused_cpu));
}

// Filtering from a depth image whose samples are layers of an image array: the interop
// path's interleaving kernel (depth_interleave_layers), then the paper's kernel.
TEST_F(Oclgrind, FilterFromLayeredDepthImage) {
    const DepthImage map = depth(2);
    // Oclgrind 21.10 does not carry the initialized state of memory through device-side
    // copies (Memory::copy notifies a plain store, which its uninitialized-value checker
    // ignores), and this path starts with clEnqueueCopyImageToBuffer: every value the
    // interleaving kernel reads would be reported. The checker is off for this case only;
    // races and API misuse are still checked.
    unsetenv("OCLGRIND_UNINITIALIZED");
    expect_texture("depth image layers -> fused_paper " + variant(Format::nlq64, 2), Format::nlq64, [&](Context& context) {
        // Sample s of every texel into layer s.
        std::vector<float> planes(map.depth.size());
        const std::size_t texels = static_cast<std::size_t>(map.width) * map.height;
        for (std::size_t t = 0; t < texels; ++t)
            for (int s = 0; s < map.samples; ++s) planes[s * texels + t] = map.depth[t * map.samples + s];
        cl_image_format format{CL_R, CL_FLOAT};
        cl_image_desc description{};
        description.image_type = CL_MEM_OBJECT_IMAGE2D_ARRAY;
        description.image_width = static_cast<std::size_t>(map.width);
        description.image_height = static_cast<std::size_t>(map.height);
        description.image_array_size = static_cast<std::size_t>(map.samples);
        cl_int status = CL_SUCCESS;
        cl_mem image = clCreateImage(context.cl_context_handle(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, &format,
                                     &description, planes.data(), &status);
        EXPECT_EQ(status, CL_SUCCESS);
        std::vector<std::uint32_t> words(texels * msmcl::texel_words(Format::nlq64));
        cl_mem texture = clCreateBuffer(context.cl_context_handle(), CL_MEM_READ_WRITE, words.size() * 4, nullptr, &status);
        EXPECT_EQ(status, CL_SUCCESS);
        FilterOptions options;
        options.format = Format::nlq64;
        options.kernel = FilterKernel::fused_paper;
        msmcl::filter(context, msmcl::DeviceDepthImage{image, map.width, map.height, map.samples,
                                                       msmcl::SampleLayout::layers},
                      texture, options);
        EXPECT_EQ(clEnqueueReadBuffer(context.cl_queue_handle(), texture, CL_TRUE, 0, words.size() * 4, words.data(), 0,
                                      nullptr, nullptr),
                  CL_SUCCESS);
        clReleaseMemObject(texture);
        clReleaseMemObject(image);
        return words;
    });
    setenv("OCLGRIND_UNINITIALIZED", "1", 1);
}

// ---- The VSM, EVSM and ESM formats of the filter (docs/formats.md, "Filterable
// representations"): their warps (msm_exp) and codes (msm_half_bits, unorm16) use only
// correctly rounded operations, so Oclgrind and PoCL agree bit for bit.

const Format kFilterableFormats[] = {Format::vsm32,    Format::vsm64,     Format::evsm2_32,
                                     Format::evsm4_64, Format::evsm4_128, Format::esm32};

class OclgrindFilterable : public Oclgrind, public ::testing::WithParamInterface<Format> {};

// The paper's kernel and the CPU distribution (16x8 tiles: interior and border columns),
// one sample count each; evsm4_64 also with the -1,1 range and translucent layers.
TEST_P(OclgrindFilterable, FusedPaperAndFusedCpu) {
    const Format format = GetParam();
    const DepthImage four = depth(4);
    expect_texture("fused_paper " + variant(format, 4), format, filtering(four, {}, format, FilterKernel::fused_paper));
    if (format == Format::evsm4_64) {
        expect_texture("fused_paper " + variant(format, 4) + ", depth range -1,1", format,
                       filtering(depth(4, DepthRange::minus_one_one), {}, format, FilterKernel::fused_paper,
                                 DepthRange::minus_one_one));
        expect_texture("fused_paper " + variant(format, 4, 2), format,
                       filtering(four, layers(four, 2), format, FilterKernel::fused_paper));
    }
    use_cpu_tile("16x8");
    expect_texture("fused_cpu 16x8 " + variant(format, 2), format,
                   filtering(depth(2), {}, format, FilterKernel::fused_cpu));
}

// The three-pass baseline: a unorm16 and a float32 format.
TEST_F(Oclgrind, FilterableThreePass) {
    for (Format format : {Format::vsm32, Format::evsm4_128})
        expect_texture("three_pass " + variant(format, 4), format,
                       filtering(depth(4), {}, format, FilterKernel::three_pass));
}

INSTANTIATE_TEST_SUITE_P(Formats, OclgrindFilterable, ::testing::ValuesIn(kFilterableFormats), format_test_name);

// ---- Shading.

// Shading of the formats that are no moment formats (VSM, EVSM, ESM), from textures the
// filter makes: the same lookups as ShadeLookups below.
class OclgrindShade : public Oclgrind, public ::testing::WithParamInterface<Format> {};
const Format kWarpedFormats[] = {Format::vsm32,    Format::vsm64,     Format::evsm2_32,
                                 Format::evsm4_64, Format::evsm4_128, Format::esm32};
TEST_P(OclgrindShade, WarpedFormatLookups) { shade_lookups(GetParam()); }
INSTANTIATE_TEST_SUITE_P(Formats, OclgrindShade, ::testing::ValuesIn(kWarpedFormats), format_test_name);

// Every lookup of every format, at receivers inside and around the map (clamped); the
// dithered lookup with row-major pixels and with explicit ones.
TEST_P(OclgrindFormat, ShadeLookups) { shade_lookups(GetParam()); }

void Oclgrind::shade_lookups(Format format) {
    const DepthImage map_depth = depth(4);
    const Texture map = on_pocl<Texture>([&](Context& context) {
        FilterOptions options;
        options.format = format;
        return msmcl::filter(context, map_depth, options);
    });
    msmcl::Receivers receivers;
    msmcl::ReceiverPixels pixels;
    std::uniform_real_distribution<float> u(-2.0f, kWidth + 2.0f), v(-2.0f, kHeight + 2.0f), z(0.0f, 1.0f);
    for (int i = 0; i < 20 * 15; ++i) {
        receivers.u.push_back(u(rng_));
        receivers.v.push_back(v(rng_));
        receivers.z.push_back(z(rng_));
        pixels.x.push_back(static_cast<std::uint32_t>(i % 20 + 100));
        pixels.y.push_back(static_cast<std::uint32_t>(i / 20 + 7));
    }
    for (msmcl::Lookup lookup : {msmcl::Lookup::nearest, msmcl::Lookup::bilinear, msmcl::Lookup::dither}) {
        msmcl::ShadeOptions options;
        options.lookup = lookup;
        options.frame = 5;
        options.screen_width = 20;
        const std::string what = std::string("shade ") + msmcl::format_name(format) + " " + msmcl::lookup_name(lookup);
        // moments128 and msm64: bit for bit. nlq64, nlq32: Psi4^-1 is an exp of an exp
        // (msm_formats.clh), whose last bits differ between Oclgrind and PoCL (see
        // expect_texture); a few intensities move by an ulp or two (at most 6e-8 seen).
        const double tolerance = format == Format::nlq64 || format == Format::nlq32 ? 1e-6 : 0.0;
        expect_floats_close(what, [&](Context& context) { return bits_of(msmcl::shade(context, map, receivers, options)); },
                            tolerance);
        if (lookup == msmcl::Lookup::dither)
            expect_floats_close(what + " with pixels", [&](Context& context) {
                return bits_of(msmcl::shade(context, map, receivers, pixels, options));
            }, tolerance);
    }
}

// ---- Summed-area tables.

std::string sat_test_name(const ::testing::TestParamInfo<SatKernel>& info) { return msmcl::sat_kernel_name(info.param); }

class OclgrindSat : public Oclgrind, public ::testing::WithParamInterface<SatKernel> {};

// Every build distribution: one sample, four samples in the -1,1 convention, translucent
// layers, and the prefix sums of given texels.
TEST_P(OclgrindSat, Build) {
    const SatKernel kernel = GetParam();
    const std::string name = std::string("sat ") + msmcl::sat_kernel_name(kernel);
    const auto building = [kernel](const DepthImage& map, const std::vector<TranslucentLayer>& layers,
                                   DepthRange range) {
        return [=](Context& context) {
            msmcl::SatOptions options;
            options.kernel = kernel;
            options.depth_range = range;
            options.max_kernel_texels = 100;
            return msmcl::build_sat(context, map, layers, options).words;
        };
    };
    const DepthImage one = depth(1), four = depth(4, DepthRange::minus_one_one);
    expect_identical(name + ", S = 1", building(one, {}, DepthRange::zero_one), 4);
    expect_identical(name + ", S = 4, depth range -1,1", building(four, {}, DepthRange::minus_one_one), 4);
    expect_identical(name + ", S = 1, 2 translucent layers", building(one, layers(one, 2), DepthRange::zero_one), 4);
    std::vector<std::uint32_t> texels(static_cast<std::size_t>(kWidth) * kHeight * 4);
    for (std::uint32_t& word : texels) word = static_cast<std::uint32_t>(rng_());
    expect_identical(name + " prefix sums", [&](Context& context) {
        return msmcl::sat_prefix_sums(context, texels, kWidth, kHeight, kernel);
    }, 4);
}

INSTANTIATE_TEST_SUITE_P(Distributions, OclgrindSat,
                         ::testing::Values(SatKernel::tiled_gpu, SatKernel::tiled_cpu, SatKernel::row_per_thread),
                         sat_test_name);

// Interpolated queries on the device (valid rectangles, and ones that leave the map or hold
// more than N texels: NaN) and moment soft shadows.
TEST_F(Oclgrind, SatQueriesAndSoftShadows) {
    const DepthImage map = depth(4);
    const msmcl::SatTable table = on_pocl<msmcl::SatTable>([&](Context& context) {
        msmcl::SatOptions options;
        options.max_kernel_texels = 144;
        return msmcl::build_sat(context, map, options);
    });
    std::vector<float> rectangles;
    std::uniform_real_distribution<float> x(-1.0f, kWidth - 4.0f), y(-1.0f, kHeight - 4.0f), side(0.2f, 13.0f);
    for (int i = 0; i < 200; ++i) {
        const float left = x(rng_), top = y(rng_);
        rectangles.insert(rectangles.end(), {left, top, left + side(rng_), top + side(rng_)});
    }
    const std::size_t count = rectangles.size() / 4;
    expect_identical("sat_query_moments", [&](Context& context) {
        cl_int status = CL_SUCCESS;
        const cl_context cl = context.cl_context_handle();
        cl_mem table_buffer = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, table.words.size() * 4,
                                             const_cast<std::uint32_t*>(table.words.data()), &status);
        cl_mem rectangle_buffer = clCreateBuffer(cl, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, rectangles.size() * 4,
                                                 rectangles.data(), &status);
        cl_mem moment_buffer = clCreateBuffer(cl, CL_MEM_WRITE_ONLY, count * 16, nullptr, &status);
        msmcl::sat_query_moments(context,
                                 msmcl::DeviceSat{table_buffer, table.width, table.height, table.max_kernel_texels},
                                 rectangle_buffer, count, moment_buffer);
        std::vector<float> moments(count * 4);
        EXPECT_EQ(clEnqueueReadBuffer(context.cl_queue_handle(), moment_buffer, CL_TRUE, 0, count * 16, moments.data(),
                                      0, nullptr, nullptr),
                  CL_SUCCESS);
        for (cl_mem buffer : {table_buffer, rectangle_buffer, moment_buffer}) clReleaseMemObject(buffer);
        return bits_of(moments);
    }, 4);

    msmcl::Receivers receivers;
    std::uniform_real_distribution<float> u(-2.0f, kWidth + 2.0f), v(-2.0f, kHeight + 2.0f), z(0.0f, 1.0f);
    for (int i = 0; i < 300; ++i) {
        receivers.u.push_back(u(rng_));
        receivers.v.push_back(v(rng_));
        receivers.z.push_back(z(rng_));
    }
    msmcl::SoftShadowOptions options;
    options.light_size = 20.0f;
    expect_identical("sat_soft_shade", [&](Context& context) {
        return bits_of(msmcl::soft_shade(context, table, receivers, options));
    });
}

// ---- Single scattering.

// Radiance (a fully lit ray of the hall scene gives about 0.3) and the normalized prefix
// sums (moments in [-1, 1]), Oclgrind against PoCL: at most 6e-8 and 1.2e-7 apart in the
// runs that set these bounds (see Prefilter).
constexpr double kRadianceTolerance = 1e-6;
constexpr double kPrefixSumTolerance = 1e-6;

std::string scatter_test_name(const ::testing::TestParamInfo<ScatterKernel>& info) {
    return msmcl::scatter_kernel_name(info.param);
}

class OclgrindScatter : public Oclgrind, public ::testing::WithParamInterface<ScatterKernel> {
protected:
    void SetUp() override {
        Oclgrind::SetUp();
        if (IsSkipped() || HasFatalFailure()) return;
        // The hall scene at a small camera and rectified map.
        std::ifstream in(std::string(MSMCL_SOURCE_DIR) + "/data/scatter/hall.json");
        const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
        scene_ = msmcl::parse_scatter_scene(text);
        scene_.camera.width = 24;
        scene_.camera.height = 18;
        scene_.rectified_width = 40;
        scene_.rectified_height = 21;
        const auto geometry = msmcl::scatter_data::parse_geometry(text);
        shadow_ = msmcl::scatter_data::render_shadow_map(scene_, geometry, kWidth, kHeight);
        camera_ = msmcl::scatter_data::render_camera_depth(scene_, geometry);
    }

    msmcl::ScatterScene scene_;
    DepthImage shadow_;
    std::vector<float> camera_;
};

// Both row distributions of the prefilter: filtered resampling (the paper's filter kernel
// first) with 6 moments, unfiltered with 4, and the float prefix sums before quantization.
// Not bit for bit: the rectification (msm_scatter.clh) places every texel with sin and cos,
// which OpenCL lets be 4 ulp off and which differ in their last bits
// between Oclgrind and PoCL (as log and exp do, see expect_texture). So a stored code may
// differ by one and the float sums by kPrefixSumTolerance; the distribution of the work
// plays no part (each row's sums are the same operations in the same order on both).
TEST_P(OclgrindScatter, Prefilter) {
    const ScatterKernel kernel = GetParam();
    const std::string name = std::string("scatter ") + msmcl::scatter_kernel_name(kernel);
    const Field code10{0, 10, 1}, code16{0, 16, 1};
    for (const auto& [moments, filtered] : {std::pair{6, true}, std::pair{4, false}}) {
        msmcl::ScatterOptions options;
        options.moments = moments;
        options.filtered = filtered;
        options.kernel = kernel;
        options.filter_kernel = FilterKernel::fused_paper;
        const std::vector<std::vector<Field>> codes =
            moments == 6 ? std::vector<std::vector<Field>>{{code10, Field{10, 10, 1}, Field{20, 10, 1}, Field{30, 2, 0}}}
                         : std::vector<std::vector<Field>>{{code16, Field{16, 16, 1}}};
        expect_fields_close(name + ", " + std::to_string(moments) + " moments" + (filtered ? "" : ", unfiltered") +
                                ", map",
                            [&](Context& context) { return msmcl::scatter_prefilter(context, scene_, shadow_, options).words; },
                            codes);
    }
    msmcl::ScatterOptions options;
    options.filtered = false;
    options.kernel = kernel;
    expect_floats_close(name + ", prefix sums", [&](Context& context) {
        return bits_of(msmcl::scatter_rectified_moments(context, scene_, shadow_, options, true));
    }, kPrefixSumTolerance);
}

INSTANTIATE_TEST_SUITE_P(Distributions, OclgrindScatter, ::testing::Values(ScatterKernel::rows_gpu, ScatterKernel::rows_cpu),
                         scatter_test_name);

// Evaluation of a prefiltered map (the same map, made on PoCL, on both devices) with 6 and
// 4 moments, and the ground truth, ray marching with and without jitter (exp per segment):
// the radiance within kRadianceTolerance, see Prefilter.
TEST_F(OclgrindScatter, EvaluateAndRayMarch) {
    for (int moments : {6, 4}) {
        msmcl::ScatterOptions options;
        options.moments = moments;
        options.filtered = false;
        const msmcl::ScatterMap map =
            on_pocl<msmcl::ScatterMap>([&](Context& context) { return msmcl::scatter_prefilter(context, scene_, shadow_, options); });
        expect_floats_close("scatter_evaluate, " + std::to_string(moments) + " moments", [&](Context& context) {
            return bits_of(msmcl::scatter_evaluate(context, scene_, map, camera_, options));
        }, kRadianceTolerance);
    }
    for (std::uint32_t jitter : {0u, 7u})
        expect_floats_close("scatter_ray_march jitter " + std::to_string(jitter), [&](Context& context) {
            return bits_of(msmcl::scatter_ray_march(context, scene_, shadow_, camera_, 8, jitter));
        }, kRadianceTolerance);
}

} // namespace
