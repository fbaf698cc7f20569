// The owners' destroyers (vk_handles.hpp), out of line so that the header needs no prototypes.
#include <skygraph/vk_handles.hpp>

#include <vulkan/vulkan.h>

namespace skygraph::owned {

#define SKYGRAPH_DESTROYER(Destroyer, Handle, call) \
    void Destroyer::destroy(VkDevice device, Handle handle) noexcept { call(device, handle, nullptr); }

SKYGRAPH_DESTROYER(DestroyImage, VkImage, vkDestroyImage)
SKYGRAPH_DESTROYER(DestroyBuffer, VkBuffer, vkDestroyBuffer)
SKYGRAPH_DESTROYER(FreeMemory, VkDeviceMemory, vkFreeMemory)
SKYGRAPH_DESTROYER(DestroyImageView, VkImageView, vkDestroyImageView)
SKYGRAPH_DESTROYER(DestroySampler, VkSampler, vkDestroySampler)
SKYGRAPH_DESTROYER(DestroyRenderPass, VkRenderPass, vkDestroyRenderPass)
SKYGRAPH_DESTROYER(DestroyFramebuffer, VkFramebuffer, vkDestroyFramebuffer)
SKYGRAPH_DESTROYER(DestroyPipeline, VkPipeline, vkDestroyPipeline)
SKYGRAPH_DESTROYER(DestroyPipelineLayout, VkPipelineLayout, vkDestroyPipelineLayout)
SKYGRAPH_DESTROYER(DestroySetLayout, VkDescriptorSetLayout, vkDestroyDescriptorSetLayout)
SKYGRAPH_DESTROYER(DestroyShaderModule, VkShaderModule, vkDestroyShaderModule)
SKYGRAPH_DESTROYER(DestroyCommandPool, VkCommandPool, vkDestroyCommandPool)
SKYGRAPH_DESTROYER(DestroyFence, VkFence, vkDestroyFence)
SKYGRAPH_DESTROYER(DestroyQueryPool, VkQueryPool, vkDestroyQueryPool)

#undef SKYGRAPH_DESTROYER

}  // namespace skygraph::owned
