// Renderer::Impl: frame slots (command buffers, fences, timestamp queries), recording a frame
// pass by pass, submission and timings.
#include "renderer_impl.hpp"

namespace skygraph {

using namespace detail;

void Renderer::Impl::createFrames() {
    frames.resize(options.framesInFlight);
    for (FrameSlot& f : frames) {
        VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pci.queueFamilyIndex = dev.queueFamily;
        VkCommandPool pool;
        vk::check(vkCreateCommandPool(vkd, &pci, nullptr, &pool), "vkCreateCommandPool");
        f.pool = vk::CommandPool(vkd, pool);
        VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        ai.commandPool = pool;
        ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        ai.commandBufferCount = 1;
        vk::check(vkAllocateCommandBuffers(vkd, &ai, &f.cmd), "vkAllocateCommandBuffers");
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkFence fence;
        vk::check(vkCreateFence(vkd, &fci, nullptr, &fence), "vkCreateFence");
        f.fence = vk::Fence(vkd, fence);
    }
}

void Renderer::Impl::ensureQueries(FrameSlot& f, uint32_t count) {
    if (f.queryCount >= count && f.queries) return;
    f.queries.reset();
    VkQueryPoolCreateInfo qci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qci.queryCount = std::max(count, 2u);
    VkQueryPool qp;
    vk::check(vkCreateQueryPool(vkd, &qci, nullptr, &qp), "vkCreateQueryPool");
    f.queries = vk::QueryPool(vkd, qp);
    f.queryCount = qci.queryCount;
}

void Renderer::Impl::waitSlot(FrameSlot& f) {
    if (!f.submitted) return;
    const VkFence fence = f.fence.get();
    vk::check(vkWaitForFences(vkd, 1, &fence, VK_TRUE, kWaitForever), "vkWaitForFences");
    f.submitted = false;
    collectTimings(f);
}

void Renderer::Impl::collectTimings(FrameSlot& f) {
    if (!f.timingsPending) return;
    f.timingsPending = false;
    const auto n = static_cast<uint32_t>(f.passNames.size());
    if (n == 0) return;
    std::vector<uint64_t> ts(size_t(n) * 2);
    if (vkGetQueryPoolResults(vkd, f.queries.get(), 0, n * 2, ts.size() * 8, ts.data(), 8,
                              VK_QUERY_RESULT_64_BIT) != VK_SUCCESS) {
        return;
    }
    timings.clear();
    for (uint32_t i = 0; i < n; ++i) {
        const double ns = static_cast<double>(ts[2 * i + 1] - ts[2 * i]) * dev.timestampPeriod;
        timings.push_back({f.passNames[i], ns / 1.0e6});
    }
}

void Renderer::Impl::dependency(VkCommandBuffer cmd, const std::vector<VkImageMemoryBarrier2>& images,
                                const std::vector<VkBufferMemoryBarrier2>& buffers,
                                const std::vector<VkMemoryBarrier2>& memory) const {
    if (images.empty() && buffers.empty() && memory.empty()) return;
    VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    di.memoryBarrierCount = static_cast<uint32_t>(memory.size());
    di.pMemoryBarriers = memory.data();
    di.bufferMemoryBarrierCount = static_cast<uint32_t>(buffers.size());
    di.pBufferMemoryBarriers = buffers.data();
    di.imageMemoryBarrierCount = static_cast<uint32_t>(images.size());
    di.pImageMemoryBarriers = images.data();
    vkCmdPipelineBarrier2(cmd, &di);
}

void Renderer::Impl::recordClear(VkCommandBuffer cmd, PlanState& s, const PassState& ps, uint32_t slot) {
    for (const PlannedUsage& u : ps.pass->usages) {
        const ResourceState& r = s.resources[u.resource];
        const VkImageSubresourceRange range{r.aspect, u.range.baseMip, u.range.mipCount,
                                            u.range.baseLayer, u.range.layerCount};
        const VkImage image = r.images[r.copyFor(slot)].image;
        if (r.desc->format.isDepthStencil()) {
            const VkClearDepthStencilValue v{r.desc->clear->depth, r.desc->clear->stencil};
            vkCmdClearDepthStencilImage(cmd, image, u.layout, &v, 1, &range);
        } else {
            VkClearColorValue v{};
            std::memcpy(v.float32, r.desc->clear->color.data(), 16);
            vkCmdClearColorImage(cmd, image, u.layout, &v, 1, &range);
        }
    }
}

void Renderer::Impl::beginRenderPass(VkCommandBuffer cmd, const PassState& ps, const PassSlot& sl) {
    VkRenderPassBeginInfo rbi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    rbi.renderPass = ps.renderPass.get();
    rbi.framebuffer = sl.framebuffer.get();
    rbi.renderArea = {{0, 0}, sl.extent};
    rbi.clearValueCount = static_cast<uint32_t>(ps.clearValues.size());
    rbi.pClearValues = ps.clearValues.data();
    vkCmdBeginRenderPass(cmd, &rbi, VK_SUBPASS_CONTENTS_INLINE);
    setViewportAndScissor(cmd, sl.extent);
}

void Renderer::Impl::recordPass(VkCommandBuffer cmd, PlanState& s, PassState& ps, uint32_t slot) {
    if (ps.isClear) {
        recordClear(cmd, s, ps, slot);
        return;
    }
    if (ps.custom) {
        PassSlot& sl = ps.slots[slot];
        RecordContext rc;
        rc.cmd = cmd;
        rc.pass = ps.pass;
        rc.desc = ps.desc;
        rc.resources = sl.bound;
        rc.renderArea = ps.program.graphics ? sl.extent : VkExtent2D{0, 0};
        rc.linearSampler = linearSampler.get();
        rc.repeatSampler = repeatSampler.get();
        rc.frame = &frameData;
        rc.frameIndex = frameIndex;
        if (ps.program.graphics) beginRenderPass(cmd, ps, sl);
        ps.custom->record(rc);
        if (ps.program.graphics) vkCmdEndRenderPass(cmd);
        return;
    }
    recordGeneric(cmd, s, ps, slot);
}

void Renderer::Impl::recordFrame(VkCommandBuffer cmd, uint32_t slot, FrameSlot* frame) {
    PlanState& s = *state;
    const auto passCount = static_cast<uint32_t>(s.passes.size());
    if (frame) {
        ensureQueries(*frame, passCount * 2);
        vkCmdResetQueryPool(cmd, frame->queries.get(), 0, frame->queryCount);
    }
    for (uint32_t i = 0; i < passCount; ++i) {
        PassState& ps = s.passes[i];
        const PassSlot& sl = ps.slots[slot];
        if (frame && dev.fn.cmdBeginLabel) {
            VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
            label.pLabelName = ps.label.c_str();
            dev.fn.cmdBeginLabel(cmd, &label);
        }
        dependency(cmd, sl.imageBarriers, sl.bufferBarriers, sl.memoryBarriers);
        if (frame) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, frame->queries.get(), 2 * i);
        recordPass(cmd, s, ps, slot);
        if (frame) {
            vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, frame->queries.get(), 2 * i + 1);
            if (dev.fn.cmdEndLabel) dev.fn.cmdEndLabel(cmd);
        }
    }
    const FinalSlot& fin = s.finals[slot];
    dependency(cmd, fin.imageBarriers, fin.bufferBarriers, fin.memoryBarriers);
    if (frame && s.readbackResource >= 0) {
        // The executor's "present": copy the target out, then make it visible to the host.
        const ResourceState& r = s.resources[size_t(s.readbackResource)];
        VkBufferImageCopy c{};
        c.imageSubresource = {copyAspectOf(r.desc->format), 0, 0, 1};
        c.imageExtent = {r.width, r.height, 1};
        const VkBuffer dst = s.readbackBuffers[slot].buffer.get();
        vkCmdCopyImageToBuffer(cmd, r.images[r.copyFor(slot)].image,
                               VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst, 1, &c);
        VkBufferMemoryBarrier2 bb{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
        bb.srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
        bb.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
        bb.dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT;
        bb.dstAccessMask = VK_ACCESS_2_HOST_READ_BIT;
        bb.srcQueueFamilyIndex = bb.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        bb.buffer = dst;
        bb.size = VK_WHOLE_SIZE;
        dependency(cmd, {}, {bb}, {});
    }
    if (frame) {
        frame->passNames.clear();
        for (const PassState& ps : s.passes) frame->passNames.push_back(ps.label);
    }
}

void Renderer::Impl::renderFrame() {
    const auto slot = static_cast<uint32_t>(frameIndex % frames.size());
    FrameSlot& f = frames[slot];
    waitSlot(f);
    const VkFence fence = f.fence.get();
    vk::check(vkResetFences(vkd, 1, &fence), "vkResetFences");
    vk::check(vkResetCommandBuffer(f.cmd, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vk::check(vkBeginCommandBuffer(f.cmd, &bi), "vkBeginCommandBuffer");
    recordFrame(f.cmd, slot, &f);
    vk::check(vkEndCommandBuffer(f.cmd), "vkEndCommandBuffer");
    VkCommandBufferSubmitInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cbi.commandBuffer = f.cmd;
    VkSubmitInfo2 si{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    si.commandBufferInfoCount = 1;
    si.pCommandBufferInfos = &cbi;
    vk::check(vkQueueSubmit2(dev.queue, 1, &si, f.fence.get()), "vkQueueSubmit2");
    f.submitted = true;
    f.timingsPending = true;
    lastSlot = slot;
    ++frameIndex;
}

void Renderer::Impl::waitIdle() {
    for (FrameSlot& f : frames) waitSlot(f);
}

}  // namespace skygraph
