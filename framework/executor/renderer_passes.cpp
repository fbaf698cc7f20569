// Renderer::Impl: each pass's static state (its recording code, the render pass from the
// plan's attachments) and its per-slot state (framebuffer, barriers, bound resources).
#include "renderer_impl.hpp"

#include <spdlog/spdlog.h>

namespace skygraph {

using namespace detail;

namespace detail {

PassAttachments attachmentsOf(const PlannedPass& pass, const std::vector<ResourceState>& resources) {
    PassAttachments a;
    for (uint32_t i = 0; i < pass.usages.size(); ++i) {
        const PlannedUsage& u = pass.usages[i];
        if (u.usage.stage == Stage::ColorAttachment) a.colors.push_back(i);
        if (u.usage.stage == Stage::DepthAttachment) {
            if (a.depth >= 0)
                throw ExecutorError(passError(pass, resources.at(u.resource).desc->name,
                                              "a pass can have one depth attachment"));
            a.depth = static_cast<int32_t>(i);
        }
    }
    for (uint32_t c : a.colors) a.layers = std::max(a.layers, pass.usages[c].range.layerCount);
    if (a.depth >= 0) a.layers = std::max(a.layers, pass.usages[size_t(a.depth)].range.layerCount);
    return a;
}

VkExtent2D framebufferExtent(const PlannedPass& pass, const PassAttachments& attachments,
                             const std::vector<ResourceState>& resources) {
    // compile() refuses attachments of different sizes or layer counts: the first speaks for all.
    const uint32_t first =
        attachments.colors.empty() ? static_cast<uint32_t>(attachments.depth) : attachments.colors[0];
    const PlannedUsage& u = pass.usages[first];
    const ResourceState& r = resources[u.resource];
    return VkExtent2D{r.mipWidth(u.range.baseMip), r.mipHeight(u.range.baseMip)};
}

/// The loader binds a file's usages to its pass type's slots; a GraphDesc built in code names
/// slots itself, and recording code counts on what its declaration promises (a required slot
/// filled, with the usage it declares), so the renderer holds the plan to it.
void checkSlots(const PlannedPass& pass, const PassTypeInfo& type, const std::vector<ResourceState>& resources) {
    std::vector<uint32_t> filled(type.slots.size(), 0);
    for (const PlannedUsage& u : pass.usages) {
        const std::string& resource = resources.at(u.resource).desc->name;
        const auto slot = std::find_if(type.slots.begin(), type.slots.end(),
                                       [&](const SlotDecl& s) { return s.name == u.slot; });
        if (slot == type.slots.end())
            throw ExecutorError(passError(pass, resource,
                                          u.slot.empty() ? "fills no slot of type '" + type.name + "'"
                                                         : "fills '" + std::string(u.slot) + "', which type '" +
                                                               type.name + "' does not declare"));
        if (!slot->accepts(u.usage))
            throw ExecutorError(passError(pass, resource, "fills slot '" + slot->name + "' (" + slot->describeUsage() +
                                                              ") as " + toString(u.usage)));
        const ResourceType resourceType = resources.at(u.resource).desc->type;
        if (!slot->takes(resourceType))
            throw ExecutorError(passError(pass, resource, "fills slot '" + slot->name + "', which takes " +
                                                              slot->describeTypes() + ", with a resource of type " +
                                                              std::string(toString(resourceType))));
        if (!slot->takesLayers(*resources.at(u.resource).desc, u.range.baseLayer, u.range.layerCount))
            throw ExecutorError(passError(pass, resource, "fills slot '" + slot->name +
                                                              "', which binds the whole cube, with layers [" +
                                                              std::to_string(u.range.baseLayer) + ", " +
                                                              std::to_string(u.range.layerCount) + "] of it"));
        if (++filled[size_t(slot - type.slots.begin())] > 1 && !slot->repeated)
            throw ExecutorError(passError(pass, resource, "fills slot '" + slot->name + "' a second time"));
    }
    for (size_t i = 0; i < type.slots.size(); ++i)
        if (!type.slots[i].optional && filled[i] == 0)
            throw ExecutorError(passError(pass, "", "type '" + type.name + "' needs slot '" + type.slots[i].name + "' (" +
                                                        type.slots[i].describeUsage() + "); no usage fills it"));
}

// The loader tells a file that names a slot for such a type the same.
void checkNoSlots(const PlannedPass& pass, const PassTypeInfo& type, const std::vector<ResourceState>& resources) {
    for (const PlannedUsage& u : pass.usages)
        if (!u.slot.empty())
            throw ExecutorError(passError(pass, resources.at(u.resource).desc->name,
                                          "fills slot '" + std::string(u.slot) + "', but type '" + type.name +
                                              "' takes any usage and has no slots"));
}

void checkWithTypeValidators(const PlannedPass& pass, const PassDesc& desc, const PassTypeInfo& type,
                             const GraphDesc& graph, const Plan& plan) {
    std::string problems;
    const auto add = [&](const std::string& resource, const std::string& what) {
        problems += (problems.empty() ? "" : "; ") + passError(pass, resource, what);
    };
    // The application's validators: what they throw is reported like what they return.
    try {
        if (type.validateParams)
            for (const ParamError& e : type.validateParams(desc.params.json()))
                add("", e.pathUnder("params") + ": " + e.message);
        if (type.validateUsages)
            for (const UsageError& e : type.validateUsages(desc, graph))
                add(e.usage < desc.uses.size() ? graph.resources.at(desc.uses[e.usage].resource).name : "", e.message);
        if (type.validatePlannedPass)
            for (const UsageError& e : type.validatePlannedPass(pass, plan)) {
                const bool named = e.usage < pass.usages.size();
                add(named ? std::string(plan.resources()[pass.usages[e.usage].resource].name) : "", e.message);
            }
    } catch (const std::exception& e) {
        add("", "the validators of type '" + type.name + "' threw: " + e.what());
    } catch (...) {
        add("", "the validators of type '" + type.name + "' threw something other than a std::exception");
    }
    if (!problems.empty()) throw ExecutorError(problems);
}

}  // namespace detail

namespace {

/// Where the graph declares `pass` (a pass of the graph, not a step the compiler inserted), as
/// the compiler's messages begin ("graphs/raster.json: passes[3]"): what to fix is in that file.
std::string declaredAt(const GraphDesc& graph, const PlannedPass& pass) {
    const PassDesc& d = graph.passes.at(static_cast<size_t>(pass.declIndex));
    return graph.file + ": " + (d.jsonPath.empty() ? "passes[" + std::to_string(pass.declIndex) + "]" : d.jsonPath);
}

}  // namespace

std::unique_ptr<PassImplementation> Renderer::Impl::implementationOf(const PlannedPass& pass, const PassDesc& desc) const {
    if (!options.passes)
        throw ExecutorError(passError(pass, "", "no recording code for type '" + desc.type +
                                                    "': the renderer has no pass library (RendererOptions::passes); "
                                                    "pass one, e.g. PassLibrary::withBuiltins()"));
    const PassFactory* factory = options.passes->factory(desc.type);
    if (!factory) {
        // Types without recording code of their own run with the library's Generic.
        factory = options.passes->factory("Generic");
        if (!factory)
            throw ExecutorError(passError(pass, "", "type '" + desc.type +
                                                        "' has no recording code and the pass library has no "
                                                        "'Generic' to run it with"));
        // Said once per type: a type the application meant to implement and did not register
        // shows as a placeholder, and the reason should not wait for -v.
        // A library of Generic alone (PassLibrary::genericOnly()) asks for exactly this.
        const std::vector<std::string> types = options.passes->registry().names();
        const bool genericAlone = types.size() == 1 && types.front() == "Generic";
        if (!genericAlone && typesRunAsGeneric.insert(desc.type).second)
            spdlog::warn("pass '{}' of type '{}' runs as Generic: the renderer's pass library has no recording code "
                         "for '{}' (the pass performs its declared accesses and draws nothing of its own)",
                         pass.name, desc.type, desc.type);
    }
    // The application's code: what it throws is named with the pass, as an ExecutorError, the
    // one exception the renderer's construction and setGraph promise.
    std::unique_ptr<PassImplementation> implementation;
    try {
        implementation = (*factory)(desc);
    } catch (const std::exception& e) {
        throw ExecutorError(passError(pass, "making the implementation of type '" + desc.type + "'", e));
    } catch (...) {
        throw ExecutorError(passError(pass, "", "making the implementation of type '" + desc.type +
                                                    "': its factory threw something other than a std::exception"));
    }
    if (!implementation) throw ExecutorError(passError(pass, "", "the pass factory returned nothing"));
    return implementation;
}

void Renderer::Impl::buildPassStatic(PlanState& s, size_t index) {
    const PlannedPass& pass = s.plan.passes()[index];
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
            // Poison would destroy contents that outlive the frame.
            if (ps.kind == StepKind::Clobber && s.plan.resources()[u.resource].placement == PlannedResource::kNoPlacement)
                throw ExecutorError(passError(pass, r.desc->name, "a clobber of a resource that is not transient"));
        }
        s.passes.push_back(std::move(ps));
        return;
    }
    if (static_cast<size_t>(pass.declIndex) >= s.graph.passes.size())
        throw ExecutorError(passError(pass, "", "the plan's pass is not in the graph"));
    ps.desc = &s.graph.passes[static_cast<size_t>(pass.declIndex)];
    try {
        if (options.passes)
            if (const PassTypeInfo* type = options.passes->registry().find(ps.desc->type)) {
                if (type->acceptsAnyUsage) checkNoSlots(pass, *type, s.resources);
                else checkSlots(pass, *type, s.resources);
                checkWithTypeValidators(pass, *ps.desc, *type, s.graph, s.plan);
            }
        ps.implementation = implementationOf(pass, *ps.desc);
        ps.attachments = attachmentsOf(pass, s.resources);
        if (ps.attachments.any()) buildRenderPass(s, ps);
    } catch (const DeviceCapacityError&) {
        throw;  // named at the resource's declaration by whoever knows the size it was asked for
    } catch (const UnsupportedResourceError&) {
        throw;  // named at the resource's declaration by whoever has the graph's file
    } catch (const ExecutorError& e) {
        throw ExecutorError(declaredAt(s.graph, pass) + ": " + e.what());
    }
    s.passes.push_back(std::move(ps));
}

void Renderer::Impl::createPipelines(PlanState& s) {
    for (PassState& ps : s.passes) createPipelines(s, ps);
}

void Renderer::Impl::createPipelines(PlanState& s, PassState& ps) {
    {
        if (!ps.implementation) return;
        std::vector<std::span<const BoundResource>> frameSlots;
        for (const PassSlot& sl : ps.slots) frameSlots.emplace_back(sl.bound);
        PipelineContext pc;
        pc.device = vkd;
        pc.physicalDevice = dev.physical;
        pc.instance = dev.instance;
        pc.queueFamily = dev.queueFamily;
        pc.queue = dev.queue;
        pc.renderPass = ps.renderPass.get();
        pc.pass = ps.pass;
        pc.desc = ps.desc;
        pc.resources = ps.slots[0].bound;
        pc.frameSlots = frameSlots;
        pc.outputExtent = {s.outputWidth(), s.outputHeight()};
        pc.shaders = shaders.get();
        try {
            ps.implementation->createPipelines(pc);
        } catch (const std::exception& e) {  // an ExecutorError of the pipeline builder too: it knows no pass
            throw ExecutorError(declaredAt(s.graph, *ps.pass) + ": " + passError(*ps.pass, "creating pipelines", e));
        }
    }
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

void Renderer::Impl::buildRenderPass(PlanState& s, PassState& ps) {
    const PlannedPass& pass = *ps.pass;
    const PassAttachments& p = ps.attachments;
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
                cv.color = clearColorOf(r.desc->format.format, r.desc->clear->color);
            }
        }
        ps.clearValues.push_back(cv);
        atts.push_back(a);
        return VkAttachmentReference{static_cast<uint32_t>(atts.size() - 1), u.layout};
    };
    // The loader allows what current GPUs do; a device that allows fewer refuses here, before
    // a driver is handed a render pass it need not survive.
    if (const uint32_t most = dev.properties.limits.maxColorAttachments; p.colors.size() > most)
        throw ExecutorError(passError(pass, "", std::to_string(p.colors.size()) + " colour attachments, and the device '" +
                                                    dev.name + "' allows " + std::to_string(most) +
                                                    " (maxColorAttachments)"));
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
    ps.renderPass = owned::RenderPass(vkd, rp);
}

void Renderer::Impl::buildPassSlot(PlanState& s, PassState& ps, uint32_t slot) {
    const PlannedPass& pass = *ps.pass;
    PassSlot& sl = ps.slots[slot];
    translatePassBarriers(s, ps, slot);
    if (ps.kind != StepKind::Pass) return;
    bindResources(s, ps, slot);
    if (!ps.attachments.any()) return;

    std::vector<VkImageView> views;
    auto attach = [&](uint32_t usageIndex) {
        const PlannedUsage& u = pass.usages[usageIndex];
        ResourceState& r = s.resources[u.resource];
        const VkImageViewType type = u.range.layerCount > 1 ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
        views.push_back(view(r, r.copyFor(slot), type, u.range, true));
    };
    for (uint32_t c : ps.attachments.colors) attach(c);
    if (ps.attachments.depth >= 0) attach(static_cast<uint32_t>(ps.attachments.depth));
    const VkExtent2D e = framebufferExtent(pass, ps.attachments, s.resources);
    sl.extent = e;
    VkFramebufferCreateInfo fci{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fci.renderPass = ps.renderPass.get();
    fci.attachmentCount = static_cast<uint32_t>(views.size());
    fci.pAttachments = views.data();
    fci.width = e.width;
    fci.height = e.height;
    fci.layers = ps.attachments.layers;
    VkFramebuffer fb;
    vk::check(vkCreateFramebuffer(vkd, &fci, nullptr, &fb), "vkCreateFramebuffer");
    sl.framebuffer = owned::Framebuffer(vkd, fb);
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
        b.contentsReplaced = &r.contentsReplaced;
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
        if (!attachment && !isShaderStage(u.usage.stage)) {
            // A copy needs no view, and an image only copied has no usage a view could have.
            sl.bound.push_back(b);
            continue;
        }
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
