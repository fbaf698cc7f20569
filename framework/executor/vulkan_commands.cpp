#include "command_sink.hpp"

#include <skygraph/pipeline_builder.hpp>

namespace skygraph::detail {

void VulkanCommands::barriers(const BarrierBatch& batch) {
    const VkDependencyInfo info = batch.dependencyInfo();
    vkCmdPipelineBarrier2(cmd_, &info);
}

void VulkanCommands::beginLabel(const char* name) {
    if (!fn_.beginLabel) return;
    VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
    label.pLabelName = name;
    fn_.beginLabel(cmd_, &label);
}

void VulkanCommands::endLabel() {
    if (fn_.endLabel) fn_.endLabel(cmd_);
}

void VulkanCommands::resetQueries(VkQueryPool pool, uint32_t count) { vkCmdResetQueryPool(cmd_, pool, 0, count); }

void VulkanCommands::timestamp(VkPipelineStageFlags2 stage, VkQueryPool pool, uint32_t query) {
    vkCmdWriteTimestamp2(cmd_, stage, pool, query);
}

void VulkanCommands::clearColor(VkImage image, VkImageLayout layout, const VkClearColorValue& value,
                                const VkImageSubresourceRange& range) {
    vkCmdClearColorImage(cmd_, image, layout, &value, 1, &range);
}

void VulkanCommands::clearDepthStencil(VkImage image, VkImageLayout layout, const VkClearDepthStencilValue& value,
                                       const VkImageSubresourceRange& range) {
    vkCmdClearDepthStencilImage(cmd_, image, layout, &value, 1, &range);
}

void VulkanCommands::copyBufferToImage(VkBuffer from, VkImage to, VkImageLayout layout,
                                       std::span<const VkBufferImageCopy> regions) {
    vkCmdCopyBufferToImage(cmd_, from, to, layout, static_cast<uint32_t>(regions.size()), regions.data());
}

void VulkanCommands::copyImageToBuffer(VkImage from, VkImageLayout layout, VkBuffer to,
                                       std::span<const VkBufferImageCopy> regions) {
    vkCmdCopyImageToBuffer(cmd_, from, layout, to, static_cast<uint32_t>(regions.size()), regions.data());
}

void VulkanCommands::blitImage(VkImage image, VkImageLayout fromLayout, VkImageLayout toLayout,
                               const VkImageBlit& region) {
    vkCmdBlitImage(cmd_, image, fromLayout, image, toLayout, 1, &region, VK_FILTER_LINEAR);
}

void VulkanCommands::copyBuffer(VkBuffer from, VkBuffer to, std::span<const VkBufferCopy> regions) {
    vkCmdCopyBuffer(cmd_, from, to, static_cast<uint32_t>(regions.size()), regions.data());
}

void VulkanCommands::fillBuffer(VkBuffer buffer, VkDeviceSize offset, VkDeviceSize size, uint32_t word) {
    vkCmdFillBuffer(cmd_, buffer, offset, size, word);
}

void VulkanCommands::beginRenderPass(const VkRenderPassBeginInfo& info) {
    vkCmdBeginRenderPass(cmd_, &info, VK_SUBPASS_CONTENTS_INLINE);
    setViewportAndScissor(cmd_, info.renderArea.extent);
}

void VulkanCommands::endRenderPass() { vkCmdEndRenderPass(cmd_); }

void VulkanCommands::recordPass(PassImplementation& pass, RecordContext& context) {
    context.cmd = cmd_;
    pass.record(context);
}

void VulkanCommands::recordPassBeforeRenderPass(PassImplementation& pass, RecordContext& context) {
    context.cmd = cmd_;
    pass.recordBeforeRenderPass(context);
}

}  // namespace skygraph::detail
