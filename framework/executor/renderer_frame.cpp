// Renderer::Impl: frame slots (command buffers, fences, timestamp queries), recording a frame
// pass by pass, submission and timings.
#include "renderer_impl.hpp"
#include "swapchain.hpp"

namespace skygraph {

using namespace detail;

void Renderer::Impl::createFrames() {
    frames.resize(options.framesInFlight);
    for (FrameSlot& f : frames) {
        for (size_t k = 0; k < kQueueKinds; ++k) {
            VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
            pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
            pci.queueFamilyIndex = dev.families[k];
            VkCommandPool pool;
            vk::check(vkCreateCommandPool(vkd, &pci, nullptr, &pool), "vkCreateCommandPool");
            f.pools[k] = owned::CommandPool(vkd, pool);
        }
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkFence fence;
        vk::check(vkCreateFence(vkd, &fci, nullptr, &fence), "vkCreateFence");
        f.fence = owned::Fence(vkd, fence);
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
    f.queries = owned::QueryPool(vkd, qp);
    f.queryCount = qci.queryCount;
}

void Renderer::Impl::waitSlot(FrameSlot& f) {
    if (!f.submitted) return;
    releaseHeld(f, HeldRelease::AfterFinished);
    const VkFence fence = f.fence.get();
    vk::check(vkWaitForFences(vkd, 1, &fence, VK_TRUE, kWaitForever), "vkWaitForFences");
    f.submitted = false;
    f.setupKeep.reset();
    f.stagedKeep.clear();
    collectTimings(f);
    releaseRetired();
}

void Renderer::Impl::collectTimings(FrameSlot& f) {
    if (!f.timingsPending) return;
    f.timingsPending = false;
    if (!f.queries) return;
    const auto n = static_cast<uint32_t>(f.passNames.size());
    if (n == 0) return;
    // Each query's value and availability: passes on a queue without timestamps wrote none.
    std::vector<uint64_t> ts(size_t(n) * 4);
    const VkResult got = vkGetQueryPoolResults(vkd, f.queries.get(), 0, n * 2, ts.size() * 8, ts.data(), 16,
                                               VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WITH_AVAILABILITY_BIT);
    if (got != VK_SUCCESS && got != VK_NOT_READY) return;
    // A frame older than the one timed last (slots are not always collected in frame order)
    // says nothing new.
    if (timingsFrame && f.frame < *timingsFrame) return;
    timingsFrame = f.frame;
    timings.clear();
    for (uint32_t i = 0; i < n; ++i) {
        const uint64_t* begin = &ts[4 * i];
        const uint64_t* end = &ts[4 * i + 2];
        if (begin[1] == 0 || end[1] == 0) continue;
        const double ns = static_cast<double>(end[0] - begin[0]) * dev.timestampPeriod;
        timings.push_back({f.passNames[i], ns / 1.0e6});
    }
}

VulkanCommands::Functions Renderer::Impl::commandFunctions() const {
    return {dev.fn.cmdBeginLabel, dev.fn.cmdEndLabel};
}

std::vector<VkCommandBuffer> Renderer::Impl::commandBuffers(detail::FrameSlot& f, std::span<const Submit> submits) {
    std::array<size_t, kQueueKinds> used{};
    std::vector<VkCommandBuffer> out;
    for (const Submit& sub : submits) {
        const auto k = static_cast<size_t>(sub.queue);
        std::vector<VkCommandBuffer>& pool = f.cmds[k];
        if (pool.size() == used[k]) {
            VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
            ai.commandPool = f.pools[k].get();
            ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
            ai.commandBufferCount = 1;
            VkCommandBuffer cmd;
            vk::check(vkAllocateCommandBuffers(vkd, &ai, &cmd), "vkAllocateCommandBuffers");
            pool.push_back(cmd);
        }
        out.push_back(pool[used[k]++]);
    }
    return out;
}

void Renderer::Impl::ensureTimelines() {
    if (timelines[0]) return;
    for (auto& t : timelines) {
        VkSemaphoreTypeCreateInfo type{VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO};
        type.semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE;
        VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO, &type};
        VkSemaphore raw;
        vk::check(vkCreateSemaphore(vkd, &sci, nullptr, &raw), "vkCreateSemaphore");
        t = owned::Semaphore(vkd, raw);
    }
}

/// The submit before `waiter` that signals the value `wait` waits for (the plan orders each
/// wait after its signal).
size_t Renderer::Impl::signallerOf(std::span<const Submit> submits, const SemaphoreOp& wait, size_t waiter) {
    for (size_t k = 0; k < waiter; ++k)
        for (const SemaphoreOp& sg : submits[k].signals)
            if (sg.semaphore == wait.semaphore && sg.value == wait.value) return k;
    throw ExecutorError("submit " + std::to_string(waiter) + " waits for " + std::string(toString(wait.semaphore)) +
                        " value " + std::to_string(wait.value) + ", which no earlier submit signals");
}

VkSemaphore Renderer::Impl::binarySemaphore(FrameSlot& f, size_t index) {
    while (f.binaries.size() <= index) f.binaries.push_back(vk::makeBinarySemaphore(vkd));
    return f.binaries[index].get();
}

void Renderer::Impl::recordFrame(VkCommandBuffer cmd, uint32_t slot, FrameSlot* frame, std::optional<size_t> submit) {
    PlanState& s = *state;
    const auto passCount = static_cast<uint32_t>(s.passes.size());
    FrameRecording r;
    r.slot = slot;
    r.frameIndex = frameIndex;
    r.linearSampler = linearSampler.get();
    r.repeatSampler = repeatSampler.get();
    r.frameData = &frameData;
    r.staged = &staged;
    r.sampledImagePlanEdit = &sampledImagePlanEdit;
    if (frame && options.timestamps) {
        ensureQueries(*frame, passCount * 2);
        r.queries = frame->queries.get();
        r.queryCount = frame->queryCount;
        // Without host resets the first submit resets the queries, which orders them only
        // before the writes of its own queue.
        r.resetQueries = !dev.hostQueryReset;
        for (size_t k = 0; k < kQueueKinds; ++k)
            r.timestamps[k] = dev.timestamps[k] && (dev.hostQueryReset || dev.queues[k] == dev.queue);
    }
    if (frame) r.labels = dev.fn.cmdBeginLabel != nullptr;
    VulkanCommands sink(cmd, commandFunctions());
    if (submit) detail::recordSubmit(sink, s, r, *submit);
    else detail::recordFrame(sink, s, r);
    if (frame && (!submit || *submit + 1 == s.plan.submits().size())) {
        frame->passNames.clear();
        for (const PassState& ps : s.passes) frame->passNames.push_back(ps.label);
    }
}

bool Renderer::Impl::releaseHeld(FrameSlot& f, HeldRelease when) {
    if (!f.held) return true;
    std::vector<VkFence> fences;
    if (when != HeldRelease::Now)
        for (const owned::Fence& r : f.runFences) fences.push_back(r.get());
    if (!fences.empty()) {
        const VkResult done = vkWaitForFences(vkd, static_cast<uint32_t>(fences.size()), fences.data(), VK_TRUE,
                                              when == HeldRelease::AfterFinished ? kWaitForever : 0);
        if (done == VK_TIMEOUT) return false;
        vk::check(done, "vkWaitForFences");
        // Every copy of the staged pixels has run, unless the held submit records one.
        if (!f.held->recordsPasses) f.stagedKeep.clear();
    }
    FrameSlot::HeldSubmit& h = *f.held;
    VkSubmitInfo2 batch{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    batch.commandBufferInfoCount = 1;
    batch.pCommandBufferInfos = &h.cmd;
    batch.waitSemaphoreInfoCount = static_cast<uint32_t>(h.waits.size());
    batch.pWaitSemaphoreInfos = h.waits.data();
    batch.signalSemaphoreInfoCount = static_cast<uint32_t>(h.signals.size());
    batch.pSignalSemaphoreInfos = h.signals.data();
    vk::check(vkQueueSubmit2(h.queue, 1, &batch, f.fence.get()), "vkQueueSubmit2");
    f.held.reset();
    return true;
}

void Renderer::Impl::remakePassImplementations() {
    // Frames in flight record with the implementations being replaced.
    waitIdle();
    PlanState& s = *state;
    std::vector<std::unique_ptr<PassImplementation>> previous(s.passes.size());
    try {
        for (size_t i = 0; i < s.passes.size(); ++i) {
            PassState& ps = s.passes[i];
            if (!ps.implementation) continue;
            std::unique_ptr<PassImplementation> fresh = implementationOf(*ps.pass, *ps.desc);
            previous[i] = std::exchange(ps.implementation, std::move(fresh));
            createPipelines(s, ps);
        }
    } catch (...) {
        for (size_t i = 0; i < s.passes.size(); ++i)
            if (previous[i]) s.passes[i].implementation = std::move(previous[i]);
        throw;
    }
    passesRecordedUnsubmitted = false;
}

void Renderer::Impl::abandonFrame(FrameSlot& f, const PresentTarget* target) noexcept {
    passesRecordedUnsubmitted = true;
    // Still submitted: the wait for the slot's last frame failed, and its fence is not free.
    if (!target || f.submitted) return;
    // The acquire has a signal pending, and a binary semaphore is unsignalled again only by a
    // wait on a queue: a batch of no commands waits for it and signals the slot's fence, so
    // that the slot reuses the semaphore only once that wait has run. Failing, the slot stays
    // unsubmitted: the error being thrown already says more.
    const VkFence fence = f.fence.get();
    if (vkResetFences(vkd, 1, &fence) != VK_SUCCESS) return;
    VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    wait.semaphore = target->acquired;
    wait.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    VkSubmitInfo2 batch{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    batch.waitSemaphoreInfoCount = 1;
    batch.pWaitSemaphoreInfos = &wait;
    if (vkQueueSubmit2(dev.queue, 1, &batch, fence) == VK_SUCCESS) f.submitted = true;
}

void Renderer::Impl::submitFrame(uint32_t slot, uint32_t binding, const PresentTarget* target, bool background) {
    FrameSlot& f = frames[slot];
    const Plan& plan = state->plan;
    const std::span<const Submit> submits = plan.submits();
    std::vector<VkCommandBuffer> cmds;
    try {
        if (passesRecordedUnsubmitted) remakePassImplementations();
        // A frame follows the whole of the frame before (docs/queues.md), whose last submit a
        // background frame in another slot may still hold: it goes to its queue first. No
        // wait: the GPU orders it after the rest of its frame, and this frame after it.
        for (FrameSlot& other : frames) releaseHeld(other, HeldRelease::Now);
        waitSlot(f);
        const VkFence fence = f.fence.get();
        vk::check(vkResetFences(vkd, 1, &fence), "vkResetFences");
        cmds = commandBuffers(f, submits);
        if (submits.size() > 1) ensureTimelines();
        // Setups for a plan state since replaced have nothing left to set up.
        std::erase_if(pendingSetups, [&](const PendingSetup& p) { return p.state != state.get(); });
        for (size_t k = 0; k < submits.size(); ++k) {
            vk::check(vkResetCommandBuffer(cmds[k], 0), "vkResetCommandBuffer");
            VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
            bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
            vk::check(vkBeginCommandBuffer(cmds[k], &bi), "vkBeginCommandBuffer");
            if (k == 0) {
                VulkanCommands sink(cmds[k], commandFunctions());
                for (const PendingSetup& p : pendingSetups) p.record(sink);
            }
            recordFrame(cmds[k], binding, &f, k);
            vk::check(vkEndCommandBuffer(cmds[k]), "vkEndCommandBuffer");
        }
    } catch (...) {
        // Nothing recorded is submitted, and the setups stay pending for the next frame.
        abandonFrame(f, target);
        throw;
    }
    std::vector<std::shared_ptr<void>> keep;
    for (PendingSetup& p : pendingSetups) keep.push_back(std::move(p.keep));
    pendingSetups.clear();
    if (!keep.empty()) f.setupKeep = std::make_shared<std::vector<std::shared_ptr<void>>>(std::move(keep));
    // The fence wait above finished every use of the queries.
    if (dev.hostQueryReset && f.queries) vkResetQueryPool(vkd, f.queries.get(), 0, f.queryCount);
    // The plan's semaphore values count within the frame; the frames before have used the
    // values up to timelineValues.
    std::array<uint64_t, kQueueKinds> signalled{};
    std::vector<VkCommandBufferSubmitInfo> cbis(submits.size(), {VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO});
    std::vector<std::vector<VkSemaphoreSubmitInfo>> waits(submits.size()), signals(submits.size());
    std::vector<VkSubmitInfo2> batches(submits.size(), {VK_STRUCTURE_TYPE_SUBMIT_INFO_2});
    auto semaphoreInfo = [&](const SemaphoreOp& op) {
        VkSemaphoreSubmitInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
        const auto q = static_cast<size_t>(op.semaphore);
        info.semaphore = timelines[q].get();
        info.value = timelineValues[q] + op.value;
        info.stageMask = op.stages;
        return info;
    };
    // Presenting: the frame waits for the acquire where the plan first uses the image, and
    // its last submit signals the image's render-complete semaphore for the present.
    VkSemaphoreSubmitInfo acquire{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    bool acquireInBatch = false;
    if (target) {
        const auto resource = uint32_t(state->presentResource);
        acquire.semaphore = target->acquired;
        acquire.stageMask = acquireWaitOverride.value_or(acquireWaitStages(plan, resource));
        acquireInBatch = acquire.stageMask != 0;
    }
    // Under validation each wait gets a binary semaphore of its own, signalled by the submit
    // that signals the value it waits for: validation layer 1.3.239 pairs semaphore waits with
    // signals as it does binary ones, one signal to one wait, ignoring timeline values
    // (docs/queues.md, "What validation sees"). Same submits, same stages, same order.
    const bool binary = device.validationEnabled() && submits.size() > 1;
    size_t binaryCount = 0;
    for (size_t k = 0; k < submits.size(); ++k) {
        const Submit& sub = submits[k];
        cbis[k].commandBuffer = cmds[k];
        for (const SemaphoreOp& sg : sub.signals) {
            if (!binary) signals[k].push_back(semaphoreInfo(sg));
            auto& most = signalled[static_cast<size_t>(sg.semaphore)];
            most = std::max<uint64_t>(most, sg.value);
        }
        for (const SemaphoreOp& w : sub.waits) {
            if (!binary) {
                waits[k].push_back(semaphoreInfo(w));
                continue;
            }
            const size_t signaller = signallerOf(submits, w, k);
            const VkSemaphore one = binarySemaphore(f, binaryCount++);
            VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
            wait.semaphore = one;
            wait.stageMask = w.stages;
            waits[k].push_back(wait);
            VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
            signal.semaphore = one;
            for (const SemaphoreOp& sg : submits[signaller].signals)
                if (sg.semaphore == w.semaphore) signal.stageMask = sg.stages;
            signals[signaller].push_back(signal);
        }
        if (target && sub.waitsForAcquire && acquireInBatch) waits[k].push_back(acquire);
        if (target && k + 1 == submits.size()) {
            VkSemaphoreSubmitInfo done{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
            done.semaphore = target->renderComplete;
            done.stageMask = signalOverride.value_or(presentSignalStages(plan, uint32_t(state->presentResource)));
            signals[k].push_back(done);
        }
    }
    for (size_t k = 0; k < submits.size(); ++k) {  // a later wait may add to an earlier submit's signals
        batches[k].commandBufferInfoCount = 1;
        batches[k].pCommandBufferInfos = &cbis[k];
        batches[k].waitSemaphoreInfoCount = static_cast<uint32_t>(waits[k].size());
        batches[k].pWaitSemaphoreInfos = waits[k].data();
        batches[k].signalSemaphoreInfoCount = static_cast<uint32_t>(signals[k].size());
        batches[k].pSignalSemaphoreInfos = signals[k].data();
    }
    // The test hook's "no wait" (stages 0) still consumes the acquire semaphore, in a batch of
    // its own after the frame's, so that only the frame's ordering is missing.
    if (target && !acquireInBatch) {
        acquire.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
        VkSubmitInfo2 consume{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
        consume.waitSemaphoreInfoCount = 1;
        consume.pWaitSemaphoreInfos = &acquire;
        batches.push_back(consume);
    }
    // Consecutive batches for one VkQueue go in one call, in the plan's order, which submits
    // every signal before its wait. The frame ends on the graphics queue, after every other
    // queue's work: the fence of that last call (with the acquire's consumer) covers them all.
    // A background frame submits all but its last submit now, each call with a fence of its
    // own, and holds the last back: it waits for the other queues, and on the graphics queue
    // that wait would hold up every frame submitted after it.
    const bool hold = background && submits.size() > 1;
    const size_t now = hold ? submits.size() - 1 : submits.size();
    size_t calls = 0;
    for (size_t first = 0; first < now;) {
        const VkQueue queue = dev.queues[static_cast<size_t>(submits[first].queue)];
        size_t end = first + 1;
        while (end < now && dev.queues[static_cast<size_t>(submits[end].queue)] == queue) ++end;
        const bool last = end == submits.size();
        if (last) end = batches.size();
        VkFence submitFence = last ? f.fence.get() : VK_NULL_HANDLE;
        if (hold) {
            if (f.runFences.size() == calls) {
                VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
                VkFence made;
                vk::check(vkCreateFence(vkd, &fci, nullptr, &made), "vkCreateFence");
                f.runFences.emplace_back(vkd, made);
            }
            submitFence = f.runFences[calls].get();
            vk::check(vkResetFences(vkd, 1, &submitFence), "vkResetFences");
        }
        vk::check(vkQueueSubmit2(queue, static_cast<uint32_t>(end - first), &batches[first], submitFence), "vkQueueSubmit2");
        ++calls;
        first = end;
    }
    if (hold) {
        f.runFences.resize(calls);
        const size_t k = submits.size() - 1;
        f.held = FrameSlot::HeldSubmit{cbis[k], std::move(waits[k]), std::move(signals[k]),
                                       dev.queues[static_cast<size_t>(submits[k].queue)],
                                       !submits[k].passes.empty()};
    }
    f.frame = frameIndex;
    f.stagedKeep = std::exchange(staged, {});
    for (size_t q = 0; q < kQueueKinds; ++q) timelineValues[q] += signalled[q];
    f.submitted = true;
    f.timingsPending = true;
    lastSlot = slot;
    lastBinding = binding;
    ++frameIndex;
}

void Renderer::Impl::renderFrame(bool background) {
    if (present)
        throw ExecutorError("this renderer presents: render with renderFrame(Swapchain&) or "
                            "renderFrame(const PresentTarget&)");
    if (const int32_t index = state->presentsWithoutImages; index >= 0)
        throw ExecutorError("present resource '" + std::string(state->plan.resources()[size_t(index)].name) +
                            "': the plan was compiled to present, and this renderer has no present images: "
                            "render with renderFrame(Swapchain&) (or RendererOptions::presentTo, setPresentImages), "
                            "or compile with CompileOptions::presentReplacement to render headless");
    const auto slot = static_cast<uint32_t>(frameIndex % frames.size());
    submitFrame(slot, slot, nullptr, background);  // headless: the binding slot is the frame slot
}

void Renderer::Impl::waitIdle() {
    for (FrameSlot& f : frames) waitSlot(f);  // in any order: collectTimings keeps the newest
}

}  // namespace skygraph
