// Small RAII owners of Vulkan device-level handles, for executor code and for embedding
// users who write their own passes (see pipeline_builder.hpp).
#pragma once

#include <vulkan/vulkan_core.h>

#include <utility>

namespace skygraph::owned {

/// How each owner below destroys its handle: a call into the library, so that this header
/// needs no Vulkan prototypes and includes under VK_NO_PROTOTYPES (volk and other loaders).
struct DestroyImage { static void destroy(VkDevice, VkImage) noexcept; };
struct DestroyBuffer { static void destroy(VkDevice, VkBuffer) noexcept; };
struct FreeMemory { static void destroy(VkDevice, VkDeviceMemory) noexcept; };
struct DestroyImageView { static void destroy(VkDevice, VkImageView) noexcept; };
struct DestroySampler { static void destroy(VkDevice, VkSampler) noexcept; };
struct DestroyRenderPass { static void destroy(VkDevice, VkRenderPass) noexcept; };
struct DestroyFramebuffer { static void destroy(VkDevice, VkFramebuffer) noexcept; };
struct DestroyPipeline { static void destroy(VkDevice, VkPipeline) noexcept; };
struct DestroyPipelineLayout { static void destroy(VkDevice, VkPipelineLayout) noexcept; };
struct DestroySetLayout { static void destroy(VkDevice, VkDescriptorSetLayout) noexcept; };
struct DestroyShaderModule { static void destroy(VkDevice, VkShaderModule) noexcept; };
struct DestroyCommandPool { static void destroy(VkDevice, VkCommandPool) noexcept; };
struct DestroyFence { static void destroy(VkDevice, VkFence) noexcept; };
struct DestroyQueryPool { static void destroy(VkDevice, VkQueryPool) noexcept; };

/// Owns one device-level handle and destroys it with `Destroyer::destroy(device, handle)` when
/// it is reset, reassigned or destroyed. Move-only; a moved-from owner holds nothing. The
/// device must outlive the owner; the owner does not wait for the GPU to finish with the
/// handle, so destroy it only once no submitted work uses it.
template <typename T, typename Destroyer>
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
        if (handle_ != VK_NULL_HANDLE) Destroyer::destroy(device_, handle_);
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
using Image = Owned<VkImage, DestroyImage>;
using Buffer = Owned<VkBuffer, DestroyBuffer>;
using Memory = Owned<VkDeviceMemory, FreeMemory>;
using ImageView = Owned<VkImageView, DestroyImageView>;
using Sampler = Owned<VkSampler, DestroySampler>;
using RenderPass = Owned<VkRenderPass, DestroyRenderPass>;
using Framebuffer = Owned<VkFramebuffer, DestroyFramebuffer>;
using Pipeline = Owned<VkPipeline, DestroyPipeline>;
using PipelineLayout = Owned<VkPipelineLayout, DestroyPipelineLayout>;
using SetLayout = Owned<VkDescriptorSetLayout, DestroySetLayout>;
using ShaderModule = Owned<VkShaderModule, DestroyShaderModule>;
using CommandPool = Owned<VkCommandPool, DestroyCommandPool>;
using Fence = Owned<VkFence, DestroyFence>;
using QueryPool = Owned<VkQueryPool, DestroyQueryPool>;

}  // namespace skygraph::owned
