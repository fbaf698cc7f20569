#include "barrier_batch.hpp"

#include <skygraph/executor.hpp>

#include <string>

namespace skygraph::detail {

BarrierBatch::BarrierBatch(std::span<const Barrier> barriers, const std::function<BarrierTarget(uint32_t)>& target,
                           const std::array<uint32_t, kQueueKinds>& families) {
    for (const Barrier& b : barriers) {
        uint32_t srcFamily = VK_QUEUE_FAMILY_IGNORED, dstFamily = VK_QUEUE_FAMILY_IGNORED;
        if (b.transfersOwnership()) {
            srcFamily = families[static_cast<size_t>(b.srcQueue)];
            dstFamily = families[static_cast<size_t>(b.dstQueue)];
            if (srcFamily == dstFamily)
                throw ExecutorError("plan resource " + std::to_string(b.resource) + ": an ownership transfer from the " +
                                    std::string(toString(b.srcQueue)) + " to the " + std::string(toString(b.dstQueue)) +
                                    " queue, which are one queue family here: the plan was compiled for other queue "
                                    "families (CompileOptions::queueFamilies)");
        }
        if (b.kind == BarrierKind::Memory) {
            VkMemoryBarrier2 mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
            mb.srcStageMask = b.srcStages;
            mb.srcAccessMask = b.srcAccess;
            mb.dstStageMask = b.dstStages;
            mb.dstAccessMask = b.dstAccess;
            memory_.push_back(mb);
            continue;
        }
        const BarrierTarget t = target(b.resource);
        if (b.kind == BarrierKind::Image) {
            if (!t.image) throw ExecutorError("plan resource " + std::to_string(b.resource) + ": an image barrier on a buffer");
            VkImageMemoryBarrier2 ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
            ib.srcStageMask = b.srcStages;
            ib.srcAccessMask = b.srcAccess;
            ib.dstStageMask = b.dstStages;
            ib.dstAccessMask = b.dstAccess;
            ib.oldLayout = b.oldLayout;
            ib.newLayout = b.newLayout;
            ib.srcQueueFamilyIndex = srcFamily;
            ib.dstQueueFamilyIndex = dstFamily;
            ib.image = t.image;
            ib.subresourceRange = {t.aspect, b.range.baseMip, b.range.mipCount, b.range.baseLayer, b.range.layerCount};
            images_.push_back(ib);
        } else {
            if (!t.buffer) throw ExecutorError("plan resource " + std::to_string(b.resource) + ": a buffer barrier on an image");
            VkBufferMemoryBarrier2 bb{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
            bb.srcStageMask = b.srcStages;
            bb.srcAccessMask = b.srcAccess;
            bb.dstStageMask = b.dstStages;
            bb.dstAccessMask = b.dstAccess;
            bb.srcQueueFamilyIndex = srcFamily;
            bb.dstQueueFamilyIndex = dstFamily;
            bb.buffer = t.buffer;
            bb.offset = 0;
            bb.size = VK_WHOLE_SIZE;
            buffers_.push_back(bb);
        }
    }
}

VkDependencyInfo BarrierBatch::dependencyInfo() const noexcept {
    VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    di.memoryBarrierCount = static_cast<uint32_t>(memory_.size());
    di.pMemoryBarriers = memory_.data();
    di.bufferMemoryBarrierCount = static_cast<uint32_t>(buffers_.size());
    di.pBufferMemoryBarriers = buffers_.data();
    di.imageMemoryBarrierCount = static_cast<uint32_t>(images_.size());
    di.pImageMemoryBarriers = images_.data();
    return di;
}

}  // namespace skygraph::detail
