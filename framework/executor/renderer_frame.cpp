// Renderer::Impl: frame slots (command buffers, fences, timestamp queries), recording a frame
// pass by pass, submission and timings.
#include "renderer_impl.hpp"
#include "swapchain.hpp"

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

VulkanCommands::Functions Renderer::Impl::commandFunctions() const {
    return {dev.fn.cmdBeginLabel, dev.fn.cmdEndLabel};
}

void Renderer::Impl::recordFrame(VkCommandBuffer cmd, uint32_t slot, FrameSlot* frame) {
    PlanState& s = *state;
    const auto passCount = static_cast<uint32_t>(s.passes.size());
    FrameRecording r;
    r.slot = slot;
    r.frameIndex = frameIndex;
    r.linearSampler = linearSampler.get();
    r.repeatSampler = repeatSampler.get();
    r.frameData = &frameData;
    if (frame) {
        ensureQueries(*frame, passCount * 2);
        r.queries = frame->queries.get();
        r.queryCount = frame->queryCount;
        r.labels = dev.fn.cmdBeginLabel != nullptr;
    }
    VulkanCommands sink(cmd, commandFunctions());
    detail::recordFrame(sink, s, r);
    if (frame) {
        frame->passNames.clear();
        for (const PassState& ps : s.passes) frame->passNames.push_back(ps.label);
    }
}

void Renderer::Impl::submitFrame(uint32_t slot, uint32_t binding, const PresentTarget* target) {
    FrameSlot& f = frames[slot];
    waitSlot(f);
    const VkFence fence = f.fence.get();
    vk::check(vkResetFences(vkd, 1, &fence), "vkResetFences");
    vk::check(vkResetCommandBuffer(f.cmd, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vk::check(vkBeginCommandBuffer(f.cmd, &bi), "vkBeginCommandBuffer");
    recordFrame(f.cmd, binding, &f);
    vk::check(vkEndCommandBuffer(f.cmd), "vkEndCommandBuffer");
    VkCommandBufferSubmitInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cbi.commandBuffer = f.cmd;
    VkSubmitInfo2 si{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    si.commandBufferInfoCount = 1;
    si.pCommandBufferInfos = &cbi;
    // Presenting: the frame waits for the acquire where the plan first uses the image, and
    // signals the image's render-complete semaphore for the present.
    VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    if (target) {
        const Plan& plan = state->plan;
        const auto resource = uint32_t(state->presentResource);
        wait.semaphore = target->acquired;
        wait.stageMask = acquireWaitOverride.value_or(acquireWaitStages(plan, resource));
        signal.semaphore = target->renderComplete;
        signal.stageMask = signalOverride.value_or(presentSignalStages(plan, resource));
        si.waitSemaphoreInfoCount = 1;
        si.pWaitSemaphoreInfos = &wait;
        si.signalSemaphoreInfoCount = 1;
        si.pSignalSemaphoreInfos = &signal;
    }
    // The test hook's "no wait" (stages 0) still consumes the acquire semaphore, in a batch of
    // its own after the frame's, so that only the frame's ordering is missing.
    VkSubmitInfo2 batches[2] = {si, {VK_STRUCTURE_TYPE_SUBMIT_INFO_2}};
    uint32_t batchCount = 1;
    if (target && wait.stageMask == 0) {
        wait.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
        batches[0].waitSemaphoreInfoCount = 0;
        batches[1].waitSemaphoreInfoCount = 1;
        batches[1].pWaitSemaphoreInfos = &wait;
        batchCount = 2;
    }
    vk::check(vkQueueSubmit2(dev.queue, batchCount, batches, f.fence.get()), "vkQueueSubmit2");
    f.submitted = true;
    f.timingsPending = true;
    lastSlot = slot;
    lastBinding = binding;
    ++frameIndex;
}

void Renderer::Impl::renderFrame() {
    if (present)
        throw ExecutorError("this renderer presents: render with renderFrame(Swapchain&) or "
                            "renderFrame(const PresentTarget&)");
    const auto slot = static_cast<uint32_t>(frameIndex % frames.size());
    submitFrame(slot, slot, nullptr);  // headless: the binding slot is the frame slot
}

void Renderer::Impl::waitIdle() {
    for (FrameSlot& f : frames) waitSlot(f);
}

}  // namespace skygraph
