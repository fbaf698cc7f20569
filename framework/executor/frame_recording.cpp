// Recording one frame of a plan into a CommandSink: the plan's barrier batch before each step,
// the step's work, the final barriers. Needs no device: a test records into a CommandLog.
#include "renderer_impl.hpp"

#include <cstring>

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
            VkClearColorValue v{};
            std::memcpy(v.float32, r.desc->clear->color.data(), 16);
            sink.clearColor(image, u.layout, v, range);
        }
    }
}

/// A Readback step: the first mip and layer of its image into this slot's host buffer.
void recordReadback(CommandSink& sink, const PlanState& s, uint32_t step, uint32_t slot) {
    const PlannedUsage& u = s.plan.passes[step].usages[0];
    const ResourceState& r = s.resources[u.resource];
    const ReadbackTarget* target = s.readbackOf(u.resource);
    VkBufferImageCopy c{};
    c.imageSubresource = {copyAspectOf(r.desc->format), 0, 0, 1};
    c.imageExtent = {r.width, r.height, 1};
    sink.copyImageToBuffer(r.images[r.copyFor(slot)].image, u.layout, target->perSlot[slot].buffer.get(), {&c, 1});
}

/// The Generic pass's copies: out of each read, into each write. A ReadWrite copy's two halves
/// are ordered by the plan's in-pass barriers, recorded between all copies out and all copies in.
void recordTransfers(CommandSink& sink, const PlanState& s, const PassState& ps, uint32_t slot) {
    const PlannedPass& pass = *ps.pass;
    const PassSlot& sl = ps.slots[slot];
    for (const bool writing : {false, true}) {
        if (writing && !sl.inPass.empty()) sink.barriers(sl.inPass);
        for (size_t t = 0; t < ps.program.transfers.size(); ++t) {
            const PlannedUsage& u = pass.usages[ps.program.transfers[t]];
            if (writing ? !writesContents(u.usage.access) : !readsContents(u.usage.access)) continue;
            const ResourceState& r = s.resources[u.resource];
            const VkDeviceSize offset = ps.transferOffsets[t];
            // Reads land in the slot's sink, writes come from the pass's host-filled source.
            const VkBuffer scratch = writing ? ps.source.buffer.get() : sl.sink.buffer.get();
            if (!r.isImage) {
                const VkBuffer buffer = r.buffers[r.copyFor(slot)].buffer.get();
                const VkBufferCopy region = writing ? VkBufferCopy{offset, 0, r.size} : VkBufferCopy{0, offset, r.size};
                if (writing) sink.copyBuffer(scratch, buffer, {&region, 1});
                else sink.copyBuffer(buffer, scratch, {&region, 1});
                continue;
            }
            const VkImage image = r.images[r.copyFor(slot)].image;
            std::vector<VkBufferImageCopy> regions;
            VkDeviceSize o = offset;
            const uint32_t texel = copyTexelBytes(r.desc->format);
            for (uint32_t m = u.range.baseMip; m < u.range.baseMip + u.range.mipCount; ++m) {
                VkBufferImageCopy c{};
                c.bufferOffset = o;
                c.imageSubresource = {copyAspectOf(r.desc->format), m, u.range.baseLayer, u.range.layerCount};
                c.imageExtent = {r.mipWidth(m), r.mipHeight(m), 1};
                regions.push_back(c);
                o += VkDeviceSize(r.mipWidth(m)) * r.mipHeight(m) * texel * u.range.layerCount;
            }
            if (writing) sink.copyBufferToImage(scratch, image, u.layout, regions);
            else sink.copyImageToBuffer(image, u.layout, scratch, regions);
        }
    }
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

/// A Generic pass: its transfers, then its dispatch, then its draw.
void recordGeneric(CommandSink& sink, const PlanState& s, const PassState& ps, uint32_t slot) {
    const GenericProgram& p = ps.program;
    const PassSlot& sl = ps.slots[slot];
    if (!p.transfers.empty()) recordTransfers(sink, s, ps, slot);
    if (p.compute) {
        sink.bindPipeline(VK_PIPELINE_BIND_POINT_COMPUTE, ps.computePipeline.get());
        if (!sl.computeWrites.empty())
            sink.pushDescriptors(VK_PIPELINE_BIND_POINT_COMPUTE, ps.computeLayout.get(), sl.computeWrites);
        sink.pushConstants(ps.computeLayout.get(), VK_SHADER_STAGE_COMPUTE_BIT,
                           {sl.computeExtent.width, sl.computeExtent.height, 0, 0});
        sink.dispatch((sl.computeExtent.width + 7) / 8, (sl.computeExtent.height + 7) / 8);
    }
    if (p.graphics) {
        sink.beginRenderPass(renderPassBegin(ps, sl));
        sink.bindPipeline(VK_PIPELINE_BIND_POINT_GRAPHICS, ps.graphicsPipeline.get());
        if (!sl.graphicsWrites.empty())
            sink.pushDescriptors(VK_PIPELINE_BIND_POINT_GRAPHICS, ps.graphicsLayout.get(), sl.graphicsWrites);
        sink.pushConstants(ps.graphicsLayout.get(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                           {sl.extent.width, sl.extent.height, 0, 0});
        if (!sl.vertexBuffers.empty()) sink.bindVertexBuffers(sl.vertexBuffers, sl.vertexOffsets);
        if (sl.indexBuffer) sink.bindIndexBuffer(sl.indexBuffer);
        if (sl.indirectBuffer) sink.drawIndirect(sl.indirectBuffer, sl.indexBuffer != VK_NULL_HANDLE);
        else if (sl.indexBuffer) sink.drawIndexed(3, p.attachmentLayers);
        else sink.draw(3, p.attachmentLayers);
        sink.endRenderPass();
    }
}

void recordStep(CommandSink& sink, PlanState& s, uint32_t step, const FrameRecording& r) {
    PassState& ps = s.passes[step];
    switch (ps.kind) {
        case StepKind::Clear: return recordClear(sink, s, ps, r.slot);
        case StepKind::Readback: return recordReadback(sink, s, step, r.slot);
        case StepKind::Upload: throw ExecutorError(passError(*ps.pass, "", "an Upload step belongs to a setup plan"));
        case StepKind::Pass: break;
    }
    if (!ps.custom) return recordGeneric(sink, s, ps, r.slot);
    PassSlot& sl = ps.slots[r.slot];
    RecordContext rc;
    rc.pass = ps.pass;
    rc.desc = ps.desc;
    rc.resources = sl.bound;
    rc.renderArea = ps.program.graphics ? sl.extent : VkExtent2D{0, 0};
    rc.linearSampler = r.linearSampler;
    rc.repeatSampler = r.repeatSampler;
    rc.frame = r.frameData;
    rc.frameIndex = r.frameIndex;
    rc.recordInPassBarriers = [&] {
        if (!sl.inPass.empty()) sink.barriers(sl.inPass);
    };
    if (ps.program.graphics) sink.beginRenderPass(renderPassBegin(ps, sl));
    sink.recordPass(*ps.custom, rc);
    if (ps.program.graphics) sink.endRenderPass();
}

}  // namespace

StepKind stepKindOf(const PlannedPass& pass) {
    if (pass.declIndex >= 0) return StepKind::Pass;
    return pass.type == "Clear" ? StepKind::Clear : pass.type == "Readback" ? StepKind::Readback : StepKind::Upload;
}

void translatePassBarriers(const PlanState& s, PassState& ps, uint32_t slot) {
    PassSlot& sl = ps.slots.at(slot);
    const auto target = [&](uint32_t r) { return s.resources.at(r).barrierTarget(slot); };
    sl.before = BarrierBatch(ps.pass->barriers, target);
    std::vector<Barrier> inPass;
    for (const InPassBarrier& ib : s.plan.inPassBarriers)
        if (&s.plan.passes[ib.pass] == ps.pass) inPass.push_back(ib.barrier);
    sl.inPass = BarrierBatch(inPass, target);
}

void translateFinalBarriers(PlanState& s, uint32_t slots) {
    s.finals.clear();
    for (uint32_t slot = 0; slot < slots; ++slot)
        s.finals.emplace_back(s.plan.finalBarriers, [&](uint32_t r) { return s.resources.at(r).barrierTarget(slot); });
}

void recordFrame(CommandSink& sink, PlanState& s, const FrameRecording& r) {
    const auto passCount = static_cast<uint32_t>(s.passes.size());
    if (r.queries) sink.resetQueries(r.queries, r.queryCount);
    for (uint32_t i = 0; i < passCount; ++i) {
        PassState& ps = s.passes[i];
        if (r.labels) sink.beginLabel(ps.label.c_str());
        if (!ps.slots[r.slot].before.empty()) sink.barriers(ps.slots[r.slot].before);
        if (r.queries) sink.timestamp(VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, r.queries, 2 * i);
        recordStep(sink, s, i, r);
        if (r.queries) sink.timestamp(VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, r.queries, 2 * i + 1);
        if (r.labels) sink.endLabel();
    }
    if (!s.finals[r.slot].empty()) sink.barriers(s.finals[r.slot]);
}

}  // namespace skygraph::detail
