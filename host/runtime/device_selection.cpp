// Enumerating devices and choosing one: composable filters, environment, strict mode.
#include "runtime/device_selection.hpp"

#include <msmcl/errors.hpp>

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace msmcl {

namespace {

std::string lower(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return text;
}

bool is_index(const std::string& text) {
    return !text.empty() && std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); });
}

std::string trimmed_info(const cl::Device& device, cl_device_info what) {
    std::string value;
    device.getInfo(what, &value);
    while (!value.empty() && (value.back() == '\0' || value.back() == ' ')) value.pop_back();
    return value;
}

std::string environment(const char* name) {
    const char* value = std::getenv(name);
    return value ? std::string(value) : std::string();
}

} // namespace

DeviceFilter DeviceFilter::any() { return DeviceFilter(); }
DeviceFilter DeviceFilter::gpu() {
    return DeviceFilter([](const DeviceInfo& d) { return d.is_gpu; });
}
DeviceFilter DeviceFilter::cpu() {
    return DeviceFilter([](const DeviceInfo& d) { return d.is_cpu; });
}
DeviceFilter DeviceFilter::name_contains(std::string text) {
    return DeviceFilter([needle = lower(std::move(text))](const DeviceInfo& d) {
        return lower(d.name).find(needle) != std::string::npos;
    });
}
DeviceFilter DeviceFilter::platform_contains(std::string text) {
    return DeviceFilter([needle = lower(std::move(text))](const DeviceInfo& d) {
        return lower(d.platform_name).find(needle) != std::string::npos;
    });
}
DeviceFilter DeviceFilter::platform_index(int index) {
    return DeviceFilter([index](const DeviceInfo& d) { return d.platform_index == index; });
}
DeviceFilter DeviceFilter::device_index(int index) {
    return DeviceFilter([index](const DeviceInfo& d) { return d.device_index == index; });
}

DeviceFilter DeviceFilter::parse(const std::string& spec) {
    const std::string text = lower(spec);
    if (text.empty() || text == "any" || text == "default") return any();
    if (text == "gpu") return gpu();
    if (text == "cpu") return cpu();
    if (is_index(text)) return device_index(std::stoi(text));
    const std::size_t colon = text.find(':');
    if (colon != std::string::npos && is_index(text.substr(0, colon)) && is_index(text.substr(colon + 1)))
        return platform_index(std::stoi(text.substr(0, colon))) &&
               device_index(std::stoi(text.substr(colon + 1)));
    return name_contains(spec);
}

DeviceFilter DeviceFilter::parse_platform(const std::string& spec) {
    if (spec.empty()) return any();
    if (is_index(spec)) return platform_index(std::stoi(spec));
    return platform_contains(spec);
}

DeviceFilter operator&&(DeviceFilter a, DeviceFilter b) {
    return DeviceFilter([a = std::move(a), b = std::move(b)](const DeviceInfo& d) { return a(d) && b(d); });
}
DeviceFilter operator||(DeviceFilter a, DeviceFilter b) {
    return DeviceFilter([a = std::move(a), b = std::move(b)](const DeviceInfo& d) { return a(d) || b(d); });
}
DeviceFilter operator!(DeviceFilter a) {
    return DeviceFilter([a = std::move(a)](const DeviceInfo& d) { return !a(d); });
}

namespace detail {

DeviceInfo describe_device(const cl::Device& device, int platform_index, int device_index,
                           const std::string& platform_name) {
    DeviceInfo info;
    info.platform_index = platform_index;
    info.device_index = device_index;
    info.platform_name = platform_name;
    info.name = trimmed_info(device, CL_DEVICE_NAME);
    info.vendor = trimmed_info(device, CL_DEVICE_VENDOR);
    info.driver_version = trimmed_info(device, CL_DRIVER_VERSION);
    info.opencl_version = trimmed_info(device, CL_DEVICE_VERSION);
    const cl_device_type type = device.getInfo<CL_DEVICE_TYPE>();
    info.is_gpu = (type & CL_DEVICE_TYPE_GPU) != 0;
    info.is_cpu = (type & CL_DEVICE_TYPE_CPU) != 0;
    info.compute_units = device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
    info.max_work_group_size = device.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>();
    info.local_mem_bytes = device.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
    info.global_mem_bytes = device.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
    info.max_alloc_bytes = device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
    info.image2d_max_width = device.getInfo<CL_DEVICE_IMAGE2D_MAX_WIDTH>();
    info.image2d_max_height = device.getInfo<CL_DEVICE_IMAGE2D_MAX_HEIGHT>();
    info.host_unified_memory = device.getInfo<CL_DEVICE_HOST_UNIFIED_MEMORY>() == CL_TRUE;
    return info;
}

std::vector<DeviceCandidate> enumerate_devices() {
    std::vector<DeviceCandidate> candidates;
    std::vector<cl::Platform> platforms;
    // No ICD or no platform: an empty list, the caller decides what that means.
    if (cl::Platform::get(&platforms) != CL_SUCCESS) return candidates;
    for (std::size_t p = 0; p < platforms.size(); ++p) {
        std::string platform_name;
        platforms[p].getInfo(CL_PLATFORM_NAME, &platform_name);
        while (!platform_name.empty() && platform_name.back() == '\0') platform_name.pop_back();
        std::vector<cl::Device> devices;
        if (platforms[p].getDevices(CL_DEVICE_TYPE_ALL, &devices) != CL_SUCCESS) continue;
        for (std::size_t d = 0; d < devices.size(); ++d)
            candidates.push_back({devices[d], describe_device(devices[d], static_cast<int>(p),
                                                              static_cast<int>(d), platform_name)});
    }
    return candidates;
}

DeviceCandidate select_device(const DeviceSelection& selection) {
    const std::vector<DeviceCandidate> candidates = enumerate_devices();
    if (candidates.empty())
        throw device_error("no OpenCL device found (is an ICD such as pocl-opencl-icd installed?)");

    // The user's request: explicit specs first, the environment otherwise.
    std::string device_spec = selection.device;
    std::string platform_spec = selection.platform;
    bool strict = selection.strict;
    if (selection.use_environment) {
        if (device_spec.empty()) device_spec = environment("MSMCL_DEVICE");
        if (platform_spec.empty()) platform_spec = environment("MSMCL_PLATFORM");
        const std::string strict_env = environment("MSMCL_STRICT");
        if (!strict_env.empty() && strict_env != "0") strict = true;
    }
    const bool requested = !device_spec.empty() || !platform_spec.empty() || selection.filter.has_value();
    if (requested) {
        DeviceFilter wanted = DeviceFilter::parse(device_spec) && DeviceFilter::parse_platform(platform_spec);
        if (selection.filter) wanted = wanted && *selection.filter;
        for (const DeviceCandidate& c : candidates)
            if (wanted(c.info)) return c;
        if (strict)
            throw device_error("no OpenCL device matches device '" + device_spec + "' platform '" +
                               platform_spec + "' (run 'msmcl devices' to list them)");
    }
    // Default: the first GPU, else the first CPU, else the first device.
    for (const DeviceCandidate& c : candidates)
        if (c.info.is_gpu) return c;
    for (const DeviceCandidate& c : candidates)
        if (c.info.is_cpu) return c;
    return candidates.front();
}

} // namespace detail

std::vector<DeviceInfo> list_devices() {
    std::vector<DeviceInfo> infos;
    for (const detail::DeviceCandidate& c : detail::enumerate_devices()) infos.push_back(c.info);
    return infos;
}

} // namespace msmcl
