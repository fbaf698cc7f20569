// Small RAII owners of Vulkan device-level handles, for executor code and for embedding
// users who write their own passes (see pipeline_builder.hpp).
#pragma once

#include <vulkan/vulkan_core.h>

#include <utility>

namespace skygraph::vk {

/// Owns one device-level handle and destroys it with `Destroy(device, handle, nullptr)` when
/// it is reset, reassigned or destroyed. Move-only; a moved-from owner holds nothing. The
/// device must outlive the owner; the owner does not wait for the GPU to finish with the
/// handle, so destroy it only once no submitted work uses it.
template <typename T, void (*Destroy)(VkDevice, T, const VkAllocationCallbacks*)>
class Owned {
public:
    Owned() = default;
    /// Takes ownership of `handle`, which was created on `device`.
    Owned(VkDevice device, T handle) noexcept : device_(device), handle_(handle) {}
    ~Owned() { reset(); }
    Owned(const Owned&) = delete;
    Owned& operator=(const Owned&) = delete;
    Owned(Owned&& o) noexcept
        : device_(o.device_), handle_(std::exchange(o.handle_, T(VK_NULL_HANDLE))) {}
    Owned& operator=(Owned&& o) noexcept {
        if (this != &o) {
            reset();
            device_ = o.device_;
            handle_ = std::exchange(o.handle_, T(VK_NULL_HANDLE));
        }
        return *this;
    }
    void reset() noexcept {
        if (handle_ != VK_NULL_HANDLE) Destroy(device_, handle_, nullptr);
        handle_ = VK_NULL_HANDLE;
    }
    /// The handle, still owned here: valid until this owner is reset, reassigned or destroyed.
    [[nodiscard]] T get() const noexcept { return handle_; }
    /// Gives up ownership: the handle is returned and no longer destroyed here.
    [[nodiscard]] T release() noexcept { return std::exchange(handle_, T(VK_NULL_HANDLE)); }
    [[nodiscard]] explicit operator bool() const noexcept { return handle_ != VK_NULL_HANDLE; }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    T handle_ = VK_NULL_HANDLE;
};

/// One owner per handle type the executor and the built-in passes create.
using Image = Owned<VkImage, vkDestroyImage>;
using Buffer = Owned<VkBuffer, vkDestroyBuffer>;
using Memory = Owned<VkDeviceMemory, vkFreeMemory>;
using ImageView = Owned<VkImageView, vkDestroyImageView>;
using Sampler = Owned<VkSampler, vkDestroySampler>;
using RenderPass = Owned<VkRenderPass, vkDestroyRenderPass>;
using Framebuffer = Owned<VkFramebuffer, vkDestroyFramebuffer>;
using Pipeline = Owned<VkPipeline, vkDestroyPipeline>;
using PipelineLayout = Owned<VkPipelineLayout, vkDestroyPipelineLayout>;
using SetLayout = Owned<VkDescriptorSetLayout, vkDestroyDescriptorSetLayout>;
using ShaderModule = Owned<VkShaderModule, vkDestroyShaderModule>;
using CommandPool = Owned<VkCommandPool, vkDestroyCommandPool>;
using Fence = Owned<VkFence, vkDestroyFence>;
using QueryPool = Owned<VkQueryPool, vkDestroyQueryPool>;

}  // namespace skygraph::vk
