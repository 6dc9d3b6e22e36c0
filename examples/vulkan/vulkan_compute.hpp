// A minimal headless Vulkan 1.2 compute harness: one device and queue, images uploaded
// through staging buffers, samplers, storage buffers, and one-shot compute dispatches.
// No window, no swapchain. Errors throw VulkanError naming the call and its VkResult.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace msmcl_vulkan {

struct VulkanError : std::runtime_error {
    using std::runtime_error::runtime_error;
};
/// Thrown when the machine has no Vulkan device (or no loader): the consumer exits with
/// code 3 then, so that tests can tell "no device" from a failure.
struct NoVulkanDevice : VulkanError {
    using VulkanError::VulkanError;
};

/// A device-local image with its memory and a view (2D, or 2D array with `layers` > 1).
struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    std::uint32_t width = 0, height = 0, layers = 1;
};

/// A host-visible storage buffer (lavapipe's memory is all host-visible; on a discrete GPU
/// an engine would use device-local memory and a staging copy, as for images).
struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize size = 0;
};

/// What a compute dispatch binds at one binding of descriptor set 0.
struct Binding {
    std::uint32_t binding = 0;
    VkDescriptorType type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    VkImageView view = VK_NULL_HANDLE; // combined image samplers and sampled images
    VkSampler sampler = VK_NULL_HANDLE; // combined image samplers and samplers
    VkBuffer buffer = VK_NULL_HANDLE;  // storage buffers
};

class VulkanCompute {
public:
    /// Picks `device_index` (-1: the first device with a compute queue).
    explicit VulkanCompute(int device_index = -1);
    ~VulkanCompute();
    VulkanCompute(const VulkanCompute&) = delete;
    VulkanCompute& operator=(const VulkanCompute&) = delete;

    /// Names of every physical device (for `msmcl-vulkan devices`).
    static std::vector<std::string> device_names();
    std::string device_name() const;

    /// True when the format can be sampled (and linearly filtered, when `linear`) from
    /// optimal-tiling images.
    bool supports_sampling(VkFormat format, bool linear) const;

    /// Creates an image of `format` and uploads `bytes` (layer after layer, rows top to
    /// bottom, texels packed) through a staging buffer: copy, then a barrier into
    /// SHADER_READ_ONLY_OPTIMAL for compute shaders.
    /// `array`: a VK_IMAGE_VIEW_TYPE_2D_ARRAY view even of one layer (several layers always get one).
    Image upload_image(VkFormat format, std::uint32_t width, std::uint32_t height, std::uint32_t layers,
                       const std::vector<std::uint8_t>& bytes, bool array = false);
    void destroy(Image& image);

    VkSampler create_sampler(VkFilter filter, VkSamplerAddressMode address_u, VkSamplerAddressMode address_v);

    Buffer create_buffer(VkDeviceSize size);
    void write_buffer(const Buffer& buffer, const void* data, std::size_t size);
    void read_buffer(const Buffer& buffer, void* data, std::size_t size);
    void destroy(Buffer& buffer);

    /// Builds a compute pipeline from SPIR-V (`entry` point) with the layout of `bindings`
    /// and `push_bytes` of push constants, dispatches ceil(count / local_size) groups, waits.
    void dispatch(const std::vector<std::uint32_t>& spirv, const char* entry, const std::vector<Binding>& bindings,
                  const void* push, std::uint32_t push_bytes, std::uint32_t count, std::uint32_t local_size);

private:
    std::uint32_t memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags flags) const;
    VkCommandBuffer begin_commands();
    void submit_and_wait(VkCommandBuffer commands);

    VkInstance instance_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    std::uint32_t queue_family_ = 0;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    std::vector<VkSampler> samplers_;
};

} // namespace msmcl_vulkan
