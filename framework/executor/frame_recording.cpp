// Recording one frame of a plan into a CommandSink: the plan's barrier batch before each step,
// the step's work, the final barriers. Needs no device: a test records into a CommandLog.
#include "poison.hpp"
#include "renderer_impl.hpp"

namespace skygraph::detail {
namespace {

void recordClear(CommandSink& sink, const PlanState& s, const PassState& ps, uint32_t slot) {
    for (const PlannedUsage& u : ps.pass->usages) {
        const ResourceState& r = s.resources[u.resource];
        const VkImageSubresourceRange range{r.aspect, u.range.baseMip, u.range.mipCount, u.range.baseLayer,
                                            u.range.layerCount};
        const VkImage image = r.images[r.copyFor(slot)].image;
        if (r.desc->format.isDepthStencil()) {
            sink.clearDepthStencil(image, u.layout, {r.desc->clear->depth, r.desc->clear->stencil}, range);
        } else {
            sink.clearColor(image, u.layout, clearColorOf(r.desc->format.format, r.desc->clear->color), range);
        }
    }
}

/// A Clobber step: its one usage, the whole resource, filled with poison (poison.hpp).
void recordClobber(CommandSink& sink, const PlanState& s, const PassState& ps, uint32_t slot) {
    for (const PlannedUsage& u : ps.pass->usages) {
        const ResourceState& r = s.resources[u.resource];
        if (!r.isImage) {
            sink.fillBuffer(r.buffers[r.copyFor(slot)].buffer.get(), 0, VK_WHOLE_SIZE, kPoisonBufferWord);
            continue;
        }
        const VkImageSubresourceRange range{r.aspect, u.range.baseMip, u.range.mipCount, u.range.baseLayer,
                                            u.range.layerCount};
        const VkImage image = r.images[r.copyFor(slot)].image;
        const VkClearValue poison = poisonFor(r.desc->format);
        if (r.desc->format.isDepthStencil()) sink.clearDepthStencil(image, u.layout, poison.depthStencil, range);
        else sink.clearColor(image, u.layout, poison.color, range);
    }
}

/// A Readback step: the first mip and layer of its image into this slot's host buffer.
void recordReadback(CommandSink& sink, const PlanState& s, uint32_t step, uint32_t slot) {
    const PlannedUsage& u = s.plan.passes()[step].usages[0];
    const ResourceState& r = s.resources[u.resource];
    const ReadbackTarget* target = s.readbackOf(u.resource);
    VkBufferImageCopy c{};
    c.imageSubresource = {copyAspectOf(r.desc->format), 0, 0, 1};
    c.imageExtent = {r.width, r.height, 1};
    const uint32_t frameSlot = slot / s.presentImages;
    sink.copyImageToBuffer(r.images[r.copyFor(slot)].image, u.layout, target->perSlot[frameSlot].buffer.get(), {&c, 1});
}

VkRenderPassBeginInfo renderPassBegin(const PassState& ps, const PassSlot& sl) {
    VkRenderPassBeginInfo rbi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    rbi.renderPass = ps.renderPass.get();
    rbi.framebuffer = sl.framebuffer.get();
    rbi.renderArea = {{0, 0}, sl.extent};
    rbi.clearValueCount = static_cast<uint32_t>(ps.clearValues.size());
    rbi.pClearValues = ps.clearValues.data();
    return rbi;
}

void recordStep(CommandSink& sink, PlanState& s, uint32_t step, const FrameRecording& r) {
    PassState& ps = s.passes[step];
    switch (ps.kind) {
        case StepKind::Clear: return recordClear(sink, s, ps, r.slot);
        case StepKind::Clobber: return recordClobber(sink, s, ps, r.slot);
        case StepKind::Readback: return recordReadback(sink, s, step, r.slot);
        case StepKind::Upload: throw ExecutorError(passError(*ps.pass, "", "an Upload step belongs to a setup plan"));
        case StepKind::Pass: break;
    }
    PassSlot& sl = ps.slots[r.slot];
    const bool graphics = ps.attachments.any();
    RecordContext rc;
    rc.pass = ps.pass;
    rc.desc = ps.desc;
    rc.resources = sl.bound;
    rc.frameSlot = r.slot;
    rc.renderArea = graphics ? sl.extent : VkExtent2D{0, 0};
    rc.linearSampler = r.linearSampler;
    rc.repeatSampler = r.repeatSampler;
    rc.frame = r.frameData;
    rc.staged = [&r](std::string_view resource) -> const StagingBuffer* {
        if (!r.staged) return nullptr;
        const auto it = r.staged->find(resource);
        return it == r.staged->end() ? nullptr : it->second.get();
    };
    rc.frameIndex = r.frameIndex;
    rc.recordInPassBarriers = [&] {
        if (!sl.inPass.empty()) sink.barriers(sl.inPass);
    };
    // Copies, blits and their barriers are not allowed inside a render pass, and the blits
    // and the fragment shader's wait need the graphics queue.
    bool inRenderPass = false;
    const bool onGraphicsQueue = s.plan.queueOf(step) == QueueKind::Graphics;
    rc.fillSampledImages = [&](std::span<const SampledImageFill> fills) {
        if (inRenderPass || !onGraphicsQueue)
            throw ExecutorError(passError(*ps.pass, "",
                                          inRenderPass ? "fillSampledImages was called inside the render pass: call it "
                                                         "from recordBeforeRenderPass"
                                                       : "fillSampledImages needs the graphics queue, and the pass "
                                                         "runs on the " + std::string(toString(s.plan.queueOf(step))) +
                                                             " queue"));
        recordSampledImageFills(sink, fills, s.families(), r.sampledImagePlanEdit);
    };
    if (graphics) {
        sink.recordPassBeforeRenderPass(*ps.implementation, rc);
        sink.beginRenderPass(renderPassBegin(ps, sl));
        inRenderPass = true;
    }
    sink.recordPass(*ps.implementation, rc);
    if (graphics) sink.endRenderPass();
}

}  // namespace

StepKind stepKindOf(const PlannedPass& pass) {
    if (pass.declIndex >= 0) return StepKind::Pass;
    if (pass.type == "Clear") return StepKind::Clear;
    if (pass.type == "Clobber") return StepKind::Clobber;
    return pass.type == "Readback" ? StepKind::Readback : StepKind::Upload;
}

void translatePassBarriers(const PlanState& s, PassState& ps, uint32_t slot) {
    PassSlot& sl = ps.slots.at(slot);
    const auto target = [&](uint32_t r) { return s.resources.at(r).barrierTarget(slot); };
    sl.before = BarrierBatch(ps.pass->barriers, target, s.families());
    std::vector<Barrier> inPass;
    for (const InPassBarrier& ib : s.plan.inPassBarriers())
        if (&s.plan.passes()[ib.pass] == ps.pass) inPass.push_back(ib.barrier);
    sl.inPass = BarrierBatch(inPass, target, s.families());
}

void translateFinalBarriers(PlanState& s, uint32_t slots) {
    s.finals.clear();
    s.releases.clear();
    for (uint32_t slot = 0; slot < slots; ++slot) {
        const auto target = [&](uint32_t r) { return s.resources.at(r).barrierTarget(slot); };
        s.finals.emplace_back(s.plan.finalBarriers(), target, s.families());
        auto& releases = s.releases.emplace_back();
        for (const Submit& submit : s.plan.submits()) releases.emplace_back(submit.releases, target, s.families());
    }
}

void recordSubmit(CommandSink& sink, PlanState& s, const FrameRecording& r, size_t submit) {
    const Submit& sub = s.plan.submits()[submit];
    if (r.queries && r.resetQueries && submit == 0) sink.resetQueries(r.queries, r.queryCount);
    const bool timed = r.queries && r.timestamps[static_cast<size_t>(sub.queue)];
    for (const uint32_t i : sub.passes) {
        PassState& ps = s.passes[i];
        if (r.labels) sink.beginLabel(ps.label.c_str());
        if (!ps.slots[r.slot].before.empty()) sink.barriers(ps.slots[r.slot].before);
        if (timed) sink.timestamp(VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, r.queries, 2 * i);
        recordStep(sink, s, i, r);
        if (timed) sink.timestamp(VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, r.queries, 2 * i + 1);
        if (r.labels) sink.endLabel();
    }
    if (!s.releases[r.slot][submit].empty()) sink.barriers(s.releases[r.slot][submit]);
    if (submit + 1 == s.plan.submits().size() && !s.finals[r.slot].empty()) sink.barriers(s.finals[r.slot]);
}

void recordFrame(CommandSink& sink, PlanState& s, const FrameRecording& r) {
    for (size_t k = 0; k < s.plan.submits().size(); ++k) recordSubmit(sink, s, r, k);
}

}  // namespace skygraph::detail
