// Case opencv (built only where OpenCV's core and imgproc are found): the filter as a user
// of OpenCV writes it: the per-texel moments (mean over the samples) into a CV_32FC4
// image, cv::GaussianBlur (9x9, sigma, replicated border = clamp to the edge), then
// quantization per texel (the kernels' math headers), both loops in cv::parallel_for_.
// OpenCV computes its own Gaussian weights (in double, rounded to float), so its texture
// may differ from the kernels' by a rounding; equal_to_three_pass reports how often.
#ifdef MSMCL_BENCH_HAVE_OPENCV

#include "harness.hpp"

#include "kernels/msm_formats.clh"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace msmcl::bench {

namespace {

void filter_with_opencv(const DepthImage& depth, Format format, float sigma, std::uint32_t* texture) {
    const int width = depth.width, height = depth.height, samples = depth.samples;
    // Moments of every texel.
    cv::Mat moments(height, width, CV_32FC4);
    cv::parallel_for_(cv::Range(0, height), [&](const cv::Range& rows) {
        for (int y = rows.start; y < rows.end; ++y) {
            const float* row = depth.depth.data() + static_cast<std::size_t>(y) * width * samples;
            cv::Vec4f* out = moments.ptr<cv::Vec4f>(y);
            for (int x = 0; x < width; ++x) {
                msm_moments sum = msm_moments_of(msm_internal_depth(row[x * samples], 1));
                for (int s = 1; s < samples; ++s)
                    sum = msm_moments_add(sum, msm_moments_of(msm_internal_depth(row[x * samples + s], 1)));
                const msm_moments m = msm_moments_scale(sum, 1.0f / float(samples));
                out[x] = cv::Vec4f(m.b1, m.b2, m.b3, m.b4);
            }
        }
    });
    // The 9x9 Gaussian.
    cv::Mat blurred;
    cv::GaussianBlur(moments, blurred, cv::Size(9, 9), sigma, sigma, cv::BORDER_REPLICATE);
    // Quantize.
    const std::size_t words = texel_words(format);
    cv::parallel_for_(cv::Range(0, height), [&](const cv::Range& rows) {
        for (int y = rows.start; y < rows.end; ++y) {
            const cv::Vec4f* in = blurred.ptr<cv::Vec4f>(y);
            std::uint32_t* out = texture + static_cast<std::size_t>(y) * width * words;
            for (int x = 0; x < width; ++x) {
                msm_moments m;
                m.b1 = in[x][0], m.b2 = in[x][1], m.b3 = in[x][2], m.b4 = in[x][3];
                if (format == Format::moments128) {
                    out[4 * x] = as_uint(m.b1), out[4 * x + 1] = as_uint(m.b2);
                    out[4 * x + 2] = as_uint(m.b3), out[4 * x + 3] = as_uint(m.b4);
                } else if (format == Format::msm64) {
                    const msm_word2 code = msm_encode_msm64(m);
                    out[2 * x] = code.w0, out[2 * x + 1] = code.w1;
                } else if (format == Format::nlq64) {
                    const msm_word2 code = msm_encode_nlq64(msm_nlq_from_moments(msm_bias(m, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT)));
                    out[2 * x] = code.w0, out[2 * x + 1] = code.w1;
                } else {
                    out[x] = msm_encode_nlq32(msm_nlq_from_moments(msm_bias(m, MSM_ALPHA_FLOAT, MSM_BSTAR_FLOAT)));
                }
            }
        }
    });
}

std::vector<CaseResult> run_opencv(BenchEnv& env, const Workload& work) {
    std::vector<std::uint32_t> texture(work.texels() * texel_words(work.format));
    CaseResult result;
    result.name = "opencv";
    result.bytes = work.bytes();
    result.take(time_runs([&] { filter_with_opencv(*work.depth, work.format, work.sigma, texture.data()); },
                          env.warmups, env.reps));
    result.extra["threads"] = cv::getNumThreads();
    result.extra["opencv"] = CV_VERSION;
    if (!env.three_pass_words.empty()) result.extra["equal_to_three_pass"] = equal_share(texture, env.three_pass_words);
    return {result};
}

MSMCL_BENCH_CASE({"opencv", 50, run_opencv});

} // namespace

} // namespace msmcl::bench

#endif
