// The recording seam: every command the executor records itself goes through a CommandSink.
// VulkanCommands records into a command buffer; CommandLog (command_log.hpp) writes each
// command down as a line of text, so a test can compare a frame's commands and barriers with
// its plan without a device (Blender's VKCommandBufferLog is the model). Pass implementations
// record their own work into the command buffer they are given (recordPass).
#pragma once

#include "barrier_batch.hpp"

#include <skygraph/pass.hpp>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <span>

namespace skygraph::detail {

class CommandSink {
public:
    CommandSink() = default;
    virtual ~CommandSink() = default;
    CommandSink(const CommandSink&) = delete;
    CommandSink& operator=(const CommandSink&) = delete;

    /// One vkCmdPipelineBarrier2 of a plan's batch; never called with an empty batch.
    virtual void barriers(const BarrierBatch& batch) = 0;
    virtual void beginLabel(const char* name) = 0;
    virtual void endLabel() = 0;
    virtual void resetQueries(VkQueryPool pool, uint32_t count) = 0;
    virtual void timestamp(VkPipelineStageFlags2 stage, VkQueryPool pool, uint32_t query) = 0;

    virtual void clearColor(VkImage image, VkImageLayout layout, const VkClearColorValue& value,
                            const VkImageSubresourceRange& range) = 0;
    virtual void clearDepthStencil(VkImage image, VkImageLayout layout, const VkClearDepthStencilValue& value,
                                   const VkImageSubresourceRange& range) = 0;
    virtual void copyBufferToImage(VkBuffer from, VkImage to, VkImageLayout layout,
                                   std::span<const VkBufferImageCopy> regions) = 0;
    virtual void copyImageToBuffer(VkImage from, VkImageLayout layout, VkBuffer to,
                                   std::span<const VkBufferImageCopy> regions) = 0;
    virtual void copyBuffer(VkBuffer from, VkBuffer to, std::span<const VkBufferCopy> regions) = 0;
    /// vkCmdBlitImage within one image, linear filter (a setup plan's Downsample step).
    virtual void blitImage(VkImage image, VkImageLayout fromLayout, VkImageLayout toLayout, const VkImageBlit& region) = 0;
    /// vkCmdFillBuffer: `size` bytes from `offset` (VK_WHOLE_SIZE: to the end) with `word`.
    virtual void fillBuffer(VkBuffer buffer, VkDeviceSize offset, VkDeviceSize size, uint32_t word) = 0;

    /// Begins a render pass over the whole framebuffer, with viewport and scissor to match.
    virtual void beginRenderPass(const VkRenderPassBeginInfo& info) = 0;
    virtual void endRenderPass() = 0;

    /// A pass implementation records its work (PassImplementation::record); `context.cmd` is
    /// this sink's command buffer.
    virtual void recordPass(PassImplementation& pass, RecordContext& context) = 0;
    /// The same for what a graphics pass records before its render pass
    /// (PassImplementation::recordBeforeRenderPass).
    virtual void recordPassBeforeRenderPass(PassImplementation& pass, RecordContext& context) = 0;
};

/// Records into a command buffer that the caller has begun. Borrows everything.
class VulkanCommands final : public CommandSink {
public:
    struct Functions {
        PFN_vkCmdBeginDebugUtilsLabelEXT beginLabel = nullptr;  ///< may be null
        PFN_vkCmdEndDebugUtilsLabelEXT endLabel = nullptr;
    };
    VulkanCommands(VkCommandBuffer cmd, const Functions& fn) : cmd_(cmd), fn_(fn) {}

    void barriers(const BarrierBatch& batch) override;
    void beginLabel(const char* name) override;
    void endLabel() override;
    void resetQueries(VkQueryPool pool, uint32_t count) override;
    void timestamp(VkPipelineStageFlags2 stage, VkQueryPool pool, uint32_t query) override;
    void clearColor(VkImage image, VkImageLayout layout, const VkClearColorValue& value,
                    const VkImageSubresourceRange& range) override;
    void clearDepthStencil(VkImage image, VkImageLayout layout, const VkClearDepthStencilValue& value,
                           const VkImageSubresourceRange& range) override;
    void copyBufferToImage(VkBuffer from, VkImage to, VkImageLayout layout,
                           std::span<const VkBufferImageCopy> regions) override;
    void copyImageToBuffer(VkImage from, VkImageLayout layout, VkBuffer to,
                           std::span<const VkBufferImageCopy> regions) override;
    void copyBuffer(VkBuffer from, VkBuffer to, std::span<const VkBufferCopy> regions) override;
    void blitImage(VkImage image, VkImageLayout fromLayout, VkImageLayout toLayout, const VkImageBlit& region) override;
    void fillBuffer(VkBuffer buffer, VkDeviceSize offset, VkDeviceSize size, uint32_t word) override;
    void beginRenderPass(const VkRenderPassBeginInfo& info) override;
    void endRenderPass() override;
    void recordPass(PassImplementation& pass, RecordContext& context) override;
    void recordPassBeforeRenderPass(PassImplementation& pass, RecordContext& context) override;

private:
    VkCommandBuffer cmd_;
    Functions fn_;
};

}  // namespace skygraph::detail
