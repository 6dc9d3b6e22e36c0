#include "io/texture_metadata.hpp"

#include <msmcl/errors.hpp>
#include <msmcl/formats.hpp>
#include <msmcl/sat.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace msmcl::io {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
    throw input_error(path + ": " + problem);
}

} // namespace

std::optional<std::string> exponents_record(const Texture& texture) {
    if (max_exponents(texture.format) == WarpExponents{}) return std::nullopt;
    const WarpExponents used = effective_exponents(texture.format, texture.exponents, "texture");
    return detail::shortest_text(used.positive) + "," + detail::shortest_text(used.negative);
}

WarpExponents exponents_of_record(const std::optional<std::string>& record, Format format, const std::string& path) {
    if (!record) return effective_exponents(format, {}, path.c_str());
    const std::size_t comma = record->find(',');
    const auto number = [&](const std::string& text, float& value) {
        char* end = nullptr;
        value = std::strtof(text.c_str(), &end);
        return !text.empty() && end == text.c_str() + text.size() && std::isfinite(value);
    };
    WarpExponents exponents;
    if (comma == std::string::npos || !number(record->substr(0, comma), exponents.positive) ||
        !number(record->substr(comma + 1), exponents.negative))
        fail(path, "key msmcl:exponents is '" + *record + "', expected two numbers c+,c-");
    return effective_exponents(format, exponents, path.c_str());
}

std::optional<long long> metadata_integer(const GpuImage& image, const std::string& path, const char* key,
                                          long long lowest, long long highest) {
    const std::optional<std::string> text = image.find_metadata(key);
    if (!text) return std::nullopt;
    char* end = nullptr;
    errno = 0;
    const long long value = std::strtoll(text->c_str(), &end, 10);
    if (text->empty() || end != text->c_str() + text->size() || errno == ERANGE || value < lowest || value > highest)
        fail(path, std::string("key ") + key + " is '" + *text + "', not a whole number in [" +
                       std::to_string(lowest) + ", " + std::to_string(highest) + "]");
    return value;
}

TextureInfo texture_info_of(const GpuImage& image, const std::string& path) {
    TextureInfo info;
    if (const std::optional<std::string> sigma = image.find_metadata("msmcl:sigma")) {
        char* end = nullptr;
        const float value = std::strtof(sigma->c_str(), &end);
        if (sigma->empty() || end != sigma->c_str() + sigma->size() || !(value >= 0.0f) || value > 1e30f)
            fail(path, "key msmcl:sigma is '" + *sigma + "', not a sigma >= 0");
        info.sigma = value;
    }
    if (const std::optional<long long> samples = metadata_integer(image, path, "msmcl:samples", 1, 16))
        info.samples = static_cast<int>(*samples);
    if (const std::optional<std::string> range = image.find_metadata("msmcl:depthRange")) {
        const std::optional<DepthRange> parsed = parse_depth_range(*range);
        if (!parsed) fail(path, "key msmcl:depthRange is '" + *range + "', expected 0,1 or -1,1");
        info.depth_range = *parsed;
    }
    return info;
}

std::uint32_t sat_max_kernel_of(const GpuImage& image, const std::string& path, std::optional<std::uint32_t> given,
                                const char* container) {
    const std::optional<long long> recorded =
        metadata_integer(image, path, "msmcl:maxKernelTexels", sat_min_kernel_texels, sat_max_kernel_texels);
    if (!recorded && !given)
        fail(path, std::string(container) +
                       " file records no largest kernel N: say it with --max-kernel N (as given to msmcl sat)");
    if (recorded && given && static_cast<std::uint32_t>(*recorded) != *given)
        fail(path, "records N = " + std::to_string(*recorded) + ", --max-kernel says " + std::to_string(*given));
    const std::uint32_t max_kernel = recorded ? static_cast<std::uint32_t>(*recorded) : *given;
    if (const std::optional<long long> scale = metadata_integer(image, path, "msmcl:scale", 1, 0xffffffffll);
        scale && static_cast<std::uint32_t>(*scale) != sat_scale(max_kernel))
        fail(path, "key msmcl:scale is " + std::to_string(*scale) + "; N = " + std::to_string(max_kernel) + " needs " +
                       std::to_string(sat_scale(max_kernel)));
    return max_kernel;
}

} // namespace msmcl::io
