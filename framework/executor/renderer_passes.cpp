// Renderer::Impl: each pass's static state (render pass from the plan's attachments) and its
// per-slot state (framebuffer, descriptor writes, barriers, bound resources).
#include "renderer_impl.hpp"

#include <spdlog/spdlog.h>

#include <cstring>

namespace skygraph {

using namespace detail;

void Renderer::Impl::buildPassStatic(PlanState& s, size_t index) {
    const PlannedPass& pass = s.plan.passes[index];
    PassState ps;
    ps.pass = &pass;
    ps.label = pass.name;
    ps.kind = stepKindOf(pass);
    if (ps.kind != StepKind::Pass) {
        for (const PlannedUsage& u : pass.usages) {
            const ResourceState& r = s.resources[u.resource];
            if (ps.kind == StepKind::Clear && (!r.isImage || !r.desc->clear))
                throw ExecutorError(passError(pass, r.desc->name, "clear pass on a resource without `clear`"));
            if (ps.kind == StepKind::Readback && !r.isImage)
                throw ExecutorError(passError(pass, r.desc->name, "a read-back of a buffer"));
        }
        s.passes.push_back(std::move(ps));
        return;
    }
    nlohmann::json params = nlohmann::json::object();
    if (pass.declIndex >= 0 && static_cast<size_t>(pass.declIndex) < s.graph.passes.size()) {
        ps.desc = &s.graph.passes[static_cast<size_t>(pass.declIndex)];
        params = ps.desc->params;
    }
    const PassFactory* factory =
        options.passes && pass.type != "Generic" ? options.passes->factory(pass.type) : nullptr;
    if (factory && ps.desc) {
        ps.custom = (*factory)(*ps.desc);
        if (!ps.custom) throw ExecutorError(passError(pass, "", "the pass factory returned nothing"));
        for (uint32_t i = 0; i < pass.usages.size(); ++i) {
            const Stage st = pass.usages[i].usage.stage;
            if (st == Stage::ColorAttachment) ps.program.colors.push_back(i);
            if (st == Stage::DepthAttachment) {
                if (ps.program.depth >= 0)
                    throw ExecutorError(passError(pass, "", "a pass can have one depth attachment"));
                ps.program.depth = static_cast<int32_t>(i);
            }
        }
        ps.program.graphics = !ps.program.colors.empty() || ps.program.depth >= 0;
        for (uint32_t c : ps.program.colors)
            ps.program.attachmentLayers = std::max(ps.program.attachmentLayers, pass.usages[c].range.layerCount);
        if (ps.program.graphics) buildRenderPass(s, ps);
        s.passes.push_back(std::move(ps));
        return;
    }
    if (pass.type != "Generic") {
        spdlog::debug("pass '{}' of type '{}' runs as Generic (performs its declared accesses)",
                      pass.name, pass.type);
    }
    ps.program = buildGenericProgram(s.graph, s.plan, pass, params, pass.type == "Generic", layered);
    GenericProgram& p = ps.program;

    if (p.graphics) buildGraphics(s, ps);
    if (p.compute) buildCompute(ps);
    s.passes.push_back(std::move(ps));
}

VkAttachmentLoadOp Renderer::Impl::loadOp(LoadOp op) {
    switch (op) {
        case LoadOp::Load: return VK_ATTACHMENT_LOAD_OP_LOAD;
        case LoadOp::Clear: return VK_ATTACHMENT_LOAD_OP_CLEAR;
        case LoadOp::DontCare: return VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    }
    return VK_ATTACHMENT_LOAD_OP_LOAD;
}

VkAttachmentStoreOp Renderer::Impl::storeOp(StoreOp op) {
    switch (op) {
        case StoreOp::Store: return VK_ATTACHMENT_STORE_OP_STORE;
        case StoreOp::DontCare: return VK_ATTACHMENT_STORE_OP_DONT_CARE;
        case StoreOp::None: return VK_ATTACHMENT_STORE_OP_NONE;
    }
    return VK_ATTACHMENT_STORE_OP_STORE;
}

void Renderer::Impl::buildGraphics(PlanState& s, PassState& ps) {
    buildRenderPass(s, ps);
    buildGraphicsPipeline(s, ps);
}

void Renderer::Impl::buildRenderPass(PlanState& s, PassState& ps) {
    const PlannedPass& pass = *ps.pass;
    const GenericProgram& p = ps.program;
    // Render pass: every attachment stays in its planned layout (initial = subpass =
    // final), so there are no implicit transitions and no implicit external dependencies.
    std::vector<VkAttachmentDescription> atts;
    std::vector<VkAttachmentReference> colorRefs;
    VkAttachmentReference depthRef{};
    auto addAttachment = [&](uint32_t usageIndex) {
        const PlannedUsage& u = pass.usages[usageIndex];
        const ResourceState& r = s.resources[u.resource];
        VkAttachmentDescription a{};
        a.format = r.format;
        a.samples = VK_SAMPLE_COUNT_1_BIT;
        a.loadOp = loadOp(u.load);
        a.storeOp = storeOp(u.store);
        const bool stencil = r.desc->format.hasStencil;
        a.stencilLoadOp = stencil ? a.loadOp : VK_ATTACHMENT_LOAD_OP_DONT_CARE;
        a.stencilStoreOp = stencil ? a.storeOp : VK_ATTACHMENT_STORE_OP_DONT_CARE;
        if (!r.desc->format.hasDepth && r.desc->format.isDepthStencil()) {
            a.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
            a.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        }
        a.initialLayout = u.layout;
        a.finalLayout = u.layout;
        VkClearValue cv{};
        if (u.load == LoadOp::Clear) {
            if (!r.desc->clear)
                throw ExecutorError(passError(pass, r.desc->name, "LoadOp Clear without a clear value"));
            if (r.desc->format.isDepthStencil()) {
                cv.depthStencil = {r.desc->clear->depth, r.desc->clear->stencil};
            } else {
                std::memcpy(cv.color.float32, r.desc->clear->color.data(), 16);
            }
        }
        ps.clearValues.push_back(cv);
        atts.push_back(a);
        return VkAttachmentReference{static_cast<uint32_t>(atts.size() - 1), u.layout};
    };
    for (uint32_t c : p.colors) colorRefs.push_back(addAttachment(c));
    if (p.depth >= 0) depthRef = addAttachment(static_cast<uint32_t>(p.depth));
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = static_cast<uint32_t>(colorRefs.size());
    sub.pColorAttachments = colorRefs.data();
    sub.pDepthStencilAttachment = p.depth >= 0 ? &depthRef : nullptr;
    VkRenderPassCreateInfo rpci{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    rpci.attachmentCount = static_cast<uint32_t>(atts.size());
    rpci.pAttachments = atts.data();
    rpci.subpassCount = 1;
    rpci.pSubpasses = &sub;
    VkRenderPass rp;
    vk::check(vkCreateRenderPass(vkd, &rpci, nullptr, &rp), "vkCreateRenderPass");
    ps.renderPass = vk::RenderPass(vkd, rp);
}

VkExtent2D Renderer::Impl::bindingExtent(const PlanState& s, const PlannedPass& pass,
                                         const std::vector<ShaderBinding>& bindings, bool& any) const {
    VkExtent2D e{1, 1};
    any = false;
    for (const auto& b : bindings) {
        const PlannedUsage& u = pass.usages[b.usage];
        const ResourceState& r = s.resources[u.resource];
        if (b.kind == BindKind::StorageImage && b.write) {
            e.width = std::max(e.width, r.mipWidth(u.range.baseMip));
            e.height = std::max(e.height, r.mipHeight(u.range.baseMip));
            any = true;
        }
    }
    for (const auto& b : bindings) {
        const PlannedUsage& u = pass.usages[b.usage];
        const ResourceState& r = s.resources[u.resource];
        if (b.kind == BindKind::StorageBuffer && b.write) {
            const auto n = static_cast<uint32_t>(std::min<VkDeviceSize>(r.size / 4, 1u << 20));
            if (!any) {
                e.width = std::max(e.width, std::min(n, 256u));
            }
            e.height = std::max(e.height, (n + e.width - 1) / e.width);
            any = true;
        }
    }
    return e;
}

void Renderer::Impl::buildPassSlot(PlanState& s, PassState& ps, uint32_t slot) {
    const PlannedPass& pass = *ps.pass;
    const GenericProgram& p = ps.program;
    PassSlot& sl = ps.slots[slot];
    translatePassBarriers(s, ps, slot);
    if (ps.kind != StepKind::Pass) return;

    // Transfer scratch buffers (sizes depend on the output extent).
    if (slot == 0) {
        ps.transferOffsets.clear();
        ps.transferBytes = 0;
        for (uint32_t t : p.transfers) {
            const PlannedUsage& u = pass.usages[t];
            const ResourceState& r = s.resources[u.resource];
            ps.transferOffsets.push_back(ps.transferBytes);
            VkDeviceSize bytes = r.size;
            if (r.isImage) {
                bytes = 0;
                const uint32_t texel = copyTexelBytes(r.desc->format);
                if (texel == 0)
                    throw ExecutorError(passError(pass, r.desc->name, "format cannot be copied"));
                for (uint32_t m = u.range.baseMip; m < u.range.baseMip + u.range.mipCount; ++m)
                    bytes += VkDeviceSize(r.mipWidth(m)) * r.mipHeight(m) * texel * u.range.layerCount;
            }
            ps.transferBytes += (bytes + 15) & ~VkDeviceSize(15);
        }
        if (ps.transferBytes > 0) {
            ps.source = makeBuffer(ps.transferBytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
            auto* bytes = static_cast<uint8_t*>(ps.source.mapped);
            for (size_t i = 0; i < p.transfers.size(); ++i) {
                const PlannedUsage& u = pass.usages[p.transfers[i]];
                const ResourceState& r = s.resources[u.resource];
                const VkDeviceSize begin = ps.transferOffsets[i];
                const VkDeviceSize end =
                    i + 1 < p.transfers.size() ? ps.transferOffsets[i + 1] : ps.transferBytes;
                if (r.isImage) {
                    const uint32_t texel = copyTexelBytes(r.desc->format);
                    const auto t = encodeTexel(r.format, texel, p.color);
                    for (VkDeviceSize o = begin; o + texel <= end; o += texel)
                        std::memcpy(bytes + o, t.data(), texel);
                } else {
                    fillBufferPattern(bytes + begin, end - begin, p.color[0]);
                }
            }
        }
    }
    if (ps.transferBytes > 0)
        sl.sink = makeBuffer(ps.transferBytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, false);

    // Descriptors.
    const size_t nb = p.graphicsBindings.size() + p.computeBindings.size();
    size_t imageDescriptors = 0;  // reserved up front: the writes point into imageInfos
    for (const auto* list : {&p.graphicsBindings, &p.computeBindings})
        for (const ShaderBinding& b : *list) imageDescriptors += b.levels;
    sl.imageInfos.reserve(imageDescriptors);
    sl.bufferInfos.reserve(nb);
    auto writeFor = [&](const ShaderBinding& b) {
        const PlannedUsage& u = pass.usages[b.usage];
        ResourceState& r = s.resources[u.resource];
        const uint32_t copy = r.copyFor(slot);
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstBinding = b.binding;
        w.descriptorCount = 1;
        switch (b.kind) {
            case BindKind::SampledImage:
            case BindKind::StorageImage: {
                const bool sampled = b.kind == BindKind::SampledImage;
                const size_t first = sl.imageInfos.size();
                if (sampled) {
                    sl.imageInfos.push_back({sampler.get(), view(r, copy, b.viewType, u.range, false), u.layout});
                } else {
                    // Storage views address one level: one descriptor per level of the usage.
                    for (uint32_t level = 0; level < b.levels; ++level) {
                        SubresourceRange range = u.range;
                        range.baseMip = u.range.baseMip + level;
                        range.mipCount = 1;
                        sl.imageInfos.push_back({VK_NULL_HANDLE, view(r, copy, b.viewType, range, false), u.layout});
                    }
                }
                w.descriptorCount = uint32_t(sl.imageInfos.size() - first);
                w.descriptorType = sampled ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER
                                           : VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
                w.pImageInfo = &sl.imageInfos[first];
                break;
            }
            case BindKind::StorageBuffer:
            case BindKind::UniformBuffer: {
                const bool uniform = b.kind == BindKind::UniformBuffer;
                sl.bufferInfos.push_back({r.buffers[copy].buffer.get(), 0,
                                          uniform ? VkDeviceSize(b.uniformVec4s) * 16 : VK_WHOLE_SIZE});
                w.descriptorType = uniform ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER
                                           : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
                w.pBufferInfo = &sl.bufferInfos.back();
                break;
            }
        }
        return w;
    };
    for (const auto& b : p.graphicsBindings) sl.graphicsWrites.push_back(writeFor(b));
    for (const auto& b : p.computeBindings) sl.computeWrites.push_back(writeFor(b));

    auto bufferOf = [&](uint32_t usageIndex) {
        const ResourceState& r = s.resources[pass.usages[usageIndex].resource];
        return r.buffers[r.copyFor(slot)].buffer.get();
    };
    for (uint32_t v : p.vertexBuffers) {
        sl.vertexBuffers.push_back(bufferOf(v));
        sl.vertexOffsets.push_back(0);
    }
    if (p.indexBuffer >= 0) {
        const auto& r = s.resources[pass.usages[size_t(p.indexBuffer)].resource];
        if (r.size < 12) throw ExecutorError(passError(pass, r.desc->name, "index buffer smaller than 12 bytes"));
        sl.indexBuffer = bufferOf(static_cast<uint32_t>(p.indexBuffer));
    }
    if (p.indirectBuffer >= 0) {
        const auto& r = s.resources[pass.usages[size_t(p.indirectBuffer)].resource];
        if (r.size < 20) throw ExecutorError(passError(pass, r.desc->name, "indirect buffer smaller than 20 bytes"));
        sl.indirectBuffer = bufferOf(static_cast<uint32_t>(p.indirectBuffer));
    }

    bool anyCompute = false;
    sl.computeExtent = bindingExtent(s, pass, p.computeBindings, anyCompute);

    if (p.graphics) {
        std::vector<VkImageView> views;
        bool haveExtent = false;
        VkExtent2D e{0, 0};
        auto attach = [&](uint32_t usageIndex) {
            const PlannedUsage& u = pass.usages[usageIndex];
            ResourceState& r = s.resources[u.resource];
            const VkImageViewType type = u.range.layerCount > 1 ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
            views.push_back(view(r, r.copyFor(slot), type, u.range, true));
            const uint32_t w = r.mipWidth(u.range.baseMip), h = r.mipHeight(u.range.baseMip);
            e = haveExtent ? VkExtent2D{std::min(e.width, w), std::min(e.height, h)} : VkExtent2D{w, h};
            haveExtent = true;
        };
        for (uint32_t c : p.colors) attach(c);
        if (p.depth >= 0) attach(static_cast<uint32_t>(p.depth));
        if (!haveExtent) {
            bool any = false;
            e = bindingExtent(s, pass, p.graphicsBindings, any);
            if (!any) e = {s.outputWidth(), s.outputHeight()};
        }
        sl.extent = e;
        VkFramebufferCreateInfo fci{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
        fci.renderPass = ps.renderPass.get();
        fci.attachmentCount = static_cast<uint32_t>(views.size());
        fci.pAttachments = views.data();
        fci.width = e.width;
        fci.height = e.height;
        fci.layers = p.attachmentLayers;
        VkFramebuffer fb;
        vk::check(vkCreateFramebuffer(vkd, &fci, nullptr, &fb), "vkCreateFramebuffer");
        sl.framebuffer = vk::Framebuffer(vkd, fb);
    }
    if (ps.custom) bindResources(s, ps, slot);
}

void Renderer::Impl::bindResources(PlanState& s, PassState& ps, uint32_t slot) {
    const PlannedPass& pass = *ps.pass;
    PassSlot& sl = ps.slots[slot];
    sl.bound.clear();
    for (const PlannedUsage& u : pass.usages) {
        ResourceState& r = s.resources[u.resource];
        BoundResource b;
        b.usage = &u;
        b.desc = r.desc;
        b.format = r.format;
        const uint32_t copy = r.copyFor(slot);
        if (!r.isImage) {
            b.buffer = r.buffers[copy].buffer.get();
            b.size = r.size;
            sl.bound.push_back(b);
            continue;
        }
        b.image = r.images[copy].image;
        b.extent = {r.mipWidth(u.range.baseMip), r.mipHeight(u.range.baseMip)};
        const bool attachment = isAttachmentStage(u.usage.stage);
        const bool sampled = isShaderStage(u.usage.stage) && resolvedBinding(u.usage, r.desc->isImage()) == BindAs::Sampled;
        VkImageViewType type = VK_IMAGE_VIEW_TYPE_2D;
        if (sampled && r.desc->type == ResourceType::Cube && u.range.layerCount == 6 && u.range.baseLayer == 0) {
            type = VK_IMAGE_VIEW_TYPE_CUBE;
        } else if (u.range.layerCount > 1 || r.desc->type != ResourceType::Image2D) {
            type = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
        }
        b.view = view(r, copy, type, u.range, attachment);
        sl.bound.push_back(b);
    }
}

}  // namespace skygraph
