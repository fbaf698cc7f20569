// Internal: what benchmarks reach inside a Renderer: recording its plan into their own command
// buffer, and the handles it records with, for the benchmark's hand-written recording of the
// same commands. Not part of the public API (bench/ includes it from framework/executor).
#pragma once

#include <skygraph/renderer.hpp>

#include <vulkan/vulkan_core.h>

#include <vector>

namespace skygraph {

/// One pass as plain Vulkan handles and arrays (graphics and/or compute only).
struct HandPass {
    std::vector<VkImageMemoryBarrier2> imageBarriers;
    std::vector<VkBufferMemoryBarrier2> bufferBarriers;
    std::vector<VkMemoryBarrier2> memoryBarriers;
    VkRenderPass renderPass = VK_NULL_HANDLE;
    VkFramebuffer framebuffer = VK_NULL_HANDLE;
    VkExtent2D extent{};
    std::vector<VkClearValue> clearValues;
    VkPipeline graphicsPipeline = VK_NULL_HANDLE;
    VkPipelineLayout graphicsLayout = VK_NULL_HANDLE;
    std::vector<VkWriteDescriptorSet> graphicsWrites;
    uint32_t instances = 1;
    VkPipeline computePipeline = VK_NULL_HANDLE;
    VkPipelineLayout computeLayout = VK_NULL_HANDLE;
    std::vector<VkWriteDescriptorSet> computeWrites;
    VkExtent2D computeExtent{};
};

struct HandFrame {
    std::vector<HandPass> passes;
    std::vector<VkImageMemoryBarrier2> finalImageBarriers;
    std::vector<VkBufferMemoryBarrier2> finalBufferBarriers;
    std::vector<VkMemoryBarrier2> finalMemoryBarriers;
    PFN_vkCmdPushDescriptorSetKHR pushDescriptors = nullptr;
};

struct RendererAccess {
    /// Records `renderer`'s current plan for frame slot `slot` into `cmd` (begun by the
    /// caller), without labels or timestamps (its Readback steps included). For benchmarks that
    /// compare against hand recording. Throws ExecutorError for a slot out of range.
    static void recordInto(Renderer& renderer, VkCommandBuffer cmd, uint32_t slot);
    /// Copies the handles of frame slot `slot`. They stay valid while `renderer` lives and is
    /// not resized. Throws ExecutorError for plans with transfers, clears or vertex input,
    /// which the hand recording does not cover.
    static HandFrame handFrame(Renderer& renderer, uint32_t slot);
};

}  // namespace skygraph
