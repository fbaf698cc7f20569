// Renderer::Impl: the Generic pass (and pass types run as Generic): pipelines built with the
// public pipeline recipe, and recording of its transfers, dispatch and draw.
#include "renderer_impl.hpp"

namespace skygraph {

using namespace detail;

std::vector<VkDescriptorSetLayoutBinding> Renderer::Impl::layoutBindings(const std::vector<ShaderBinding>& bindings) {
    std::vector<VkDescriptorSetLayoutBinding> b;
    for (const auto& sb : bindings) {
        VkDescriptorSetLayoutBinding lb{};
        lb.binding = sb.binding;
        lb.descriptorCount = sb.kind == BindKind::StorageImage ? sb.levels : 1;
        lb.stageFlags = static_cast<VkShaderStageFlags>(sb.stage);
        switch (sb.kind) {
            case BindKind::SampledImage: lb.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER; break;
            case BindKind::StorageImage: lb.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE; break;
            case BindKind::StorageBuffer: lb.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER; break;
            case BindKind::UniformBuffer: lb.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER; break;
        }
        b.push_back(lb);
    }
    return b;
}

void Renderer::Impl::buildGraphicsPipeline(PlanState& s, PassState& ps) {
    const PlannedPass& pass = *ps.pass;
    const GenericProgram& p = ps.program;
    GraphicsPipelineRecipe recipe;
    recipe.bindings = layoutBindings(p.graphicsBindings);
    recipe.pushConstantBytes = 16;
    recipe.vertex = shaders.compile(VK_SHADER_STAGE_VERTEX_BIT, p.vertexSource, ps.label + ".vert");
    recipe.fragment = shaders.compile(VK_SHADER_STAGE_FRAGMENT_BIT, p.fragmentSource, ps.label + ".frag");
    recipe.renderPass = ps.renderPass.get();
    for (uint32_t i = 0; i < p.vertexBuffers.size(); ++i) {
        recipe.vertexBindings.push_back({i, 4, VK_VERTEX_INPUT_RATE_VERTEX});
        recipe.vertexAttributes.push_back({i, i, VK_FORMAT_R32_SFLOAT, 0});
    }
    if (p.depth >= 0) {
        const PlannedUsage& du = pass.usages[static_cast<size_t>(p.depth)];
        const bool hasDepth = s.resources[du.resource].desc->format.hasDepth;
        // The test always passes so that colors do not depend on earlier depth values,
        // but it is enabled: the attachment is really read (and written unless Read).
        recipe.depthTest = hasDepth;
        recipe.depthWrite = hasDepth && writesContents(du.usage.access);
        recipe.depthCompare = VK_COMPARE_OP_ALWAYS;
    }
    for (uint32_t c : p.colors) {
        const PlannedUsage& u = pass.usages[c];
        VkPipelineColorBlendAttachmentState b{};
        b.colorWriteMask = 0xf;
        const bool integer = !scalarPrefix(s.resources[u.resource].format).empty();
        if (u.usage.access == Access::ReadWrite && !integer) {
            // ReadWrite: additive blending reads the attachment.
            b.blendEnable = VK_TRUE;
            b.srcColorBlendFactor = b.dstColorBlendFactor = VK_BLEND_FACTOR_ONE;
            b.srcAlphaBlendFactor = b.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
            b.colorBlendOp = b.alphaBlendOp = VK_BLEND_OP_ADD;
        }
        recipe.blends.push_back(b);
    }
    recipe.colorAttachments = static_cast<uint32_t>(recipe.blends.size());
    GraphicsPipeline built = createGraphicsPipeline(vkd, recipe);
    ps.graphicsSetLayout = std::move(built.setLayout);
    ps.graphicsLayout = std::move(built.layout);
    ps.graphicsPipeline = std::move(built.pipeline);
}

void Renderer::Impl::buildCompute(PassState& ps) {
    const GenericProgram& p = ps.program;
    ComputePipelineRecipe recipe;
    recipe.bindings = layoutBindings(p.computeBindings);
    recipe.pushConstantBytes = 16;
    recipe.compute = shaders.compile(VK_SHADER_STAGE_COMPUTE_BIT, p.computeSource, ps.label + ".comp");
    ComputePipeline built = createComputePipeline(vkd, recipe);
    ps.computeSetLayout = std::move(built.setLayout);
    ps.computeLayout = std::move(built.layout);
    ps.computePipeline = std::move(built.pipeline);
}

void Renderer::Impl::recordTransfers(VkCommandBuffer cmd, PlanState& s, const PassState& ps, uint32_t slot) {
    const PlannedPass& pass = *ps.pass;
    const PassSlot& sl = ps.slots[slot];
    for (size_t t = 0; t < ps.program.transfers.size(); ++t) {
        const PlannedUsage& u = pass.usages[ps.program.transfers[t]];
        const ResourceState& r = s.resources[u.resource];
        const VkDeviceSize offset = ps.transferOffsets[t];
        const bool read = readsContents(u.usage.access);
        const bool write = writesContents(u.usage.access);
        if (!r.isImage) {
            const VkBuffer buffer = r.buffers[r.copyFor(slot)].buffer.get();
            if (read) {
                const VkBufferCopy region{0, offset, r.size};
                vkCmdCopyBuffer(cmd, buffer, sl.sink.buffer.get(), 1, &region);
            }
            if (read && write) {
                // Inside the pass: the pass's own read must finish before its own write.
                VkBufferMemoryBarrier2 bb{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
                bb.srcStageMask = bb.dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
                bb.dstAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
                bb.srcQueueFamilyIndex = bb.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
                bb.buffer = buffer;
                bb.size = VK_WHOLE_SIZE;
                dependency(cmd, {}, {bb}, {});
            }
            if (write) {
                const VkBufferCopy region{offset, 0, r.size};
                vkCmdCopyBuffer(cmd, ps.source.buffer.get(), buffer, 1, &region);
            }
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
        const auto count = static_cast<uint32_t>(regions.size());
        if (read) vkCmdCopyImageToBuffer(cmd, image, u.layout, sl.sink.buffer.get(), count, regions.data());
        if (read && write) {
            VkImageMemoryBarrier2 ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
            ib.srcStageMask = ib.dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
            ib.dstAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
            ib.oldLayout = ib.newLayout = u.layout;
            ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            ib.image = image;
            ib.subresourceRange = {r.aspect, u.range.baseMip, u.range.mipCount, u.range.baseLayer,
                                   u.range.layerCount};
            dependency(cmd, {ib}, {}, {});
        }
        if (write) vkCmdCopyBufferToImage(cmd, ps.source.buffer.get(), image, u.layout, count, regions.data());
    }
}

void Renderer::Impl::recordGeneric(VkCommandBuffer cmd, PlanState& s, PassState& ps, uint32_t slot) {
    const GenericProgram& p = ps.program;
    PassSlot& sl = ps.slots[slot];
    if (!p.transfers.empty()) recordTransfers(cmd, s, ps, slot);
    if (p.compute) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, ps.computePipeline.get());
        if (!sl.computeWrites.empty())
            dev.fn.cmdPushDescriptorSet(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, ps.computeLayout.get(), 0,
                                        static_cast<uint32_t>(sl.computeWrites.size()),
                                        sl.computeWrites.data());
        const uint32_t pc[4] = {sl.computeExtent.width, sl.computeExtent.height, 0, 0};
        vkCmdPushConstants(cmd, ps.computeLayout.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, 16, pc);
        vkCmdDispatch(cmd, (sl.computeExtent.width + 7) / 8, (sl.computeExtent.height + 7) / 8, 1);
    }
    if (p.graphics) {
        beginRenderPass(cmd, ps, sl);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, ps.graphicsPipeline.get());
        if (!sl.graphicsWrites.empty())
            dev.fn.cmdPushDescriptorSet(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, ps.graphicsLayout.get(), 0,
                                        static_cast<uint32_t>(sl.graphicsWrites.size()),
                                        sl.graphicsWrites.data());
        const uint32_t pc[4] = {sl.extent.width, sl.extent.height, 0, 0};
        vkCmdPushConstants(cmd, ps.graphicsLayout.get(),
                           VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, 16, pc);
        if (!sl.vertexBuffers.empty())
            vkCmdBindVertexBuffers(cmd, 0, static_cast<uint32_t>(sl.vertexBuffers.size()),
                                   sl.vertexBuffers.data(), sl.vertexOffsets.data());
        if (sl.indexBuffer) vkCmdBindIndexBuffer(cmd, sl.indexBuffer, 0, VK_INDEX_TYPE_UINT32);
        if (sl.indirectBuffer && sl.indexBuffer) {
            vkCmdDrawIndexedIndirect(cmd, sl.indirectBuffer, 0, 1, 20);
        } else if (sl.indirectBuffer) {
            vkCmdDrawIndirect(cmd, sl.indirectBuffer, 0, 1, 16);
        } else if (sl.indexBuffer) {
            vkCmdDrawIndexed(cmd, 3, p.attachmentLayers, 0, 0, 0);
        } else {
            vkCmdDraw(cmd, 3, p.attachmentLayers, 0, 0);
        }
        vkCmdEndRenderPass(cmd);
    }
}

}  // namespace skygraph
