// Renderer::Impl: the plans around a frame. The setup plan gives external resources their first
// contents before the first frame; both it and image read-backs are recorded step by step with
// the compiler's barriers, like a frame, and submitted on their own.
#include "renderer_impl.hpp"

#include <algorithm>
#include <skygraph/transfer_plans.hpp>

#include <cstring>
#include <optional>
#include <string>

namespace skygraph {

using namespace detail;

void Renderer::Impl::submitAndWait(const std::function<void(CommandSink&)>& record) {
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
    pci.queueFamilyIndex = dev.queueFamily;
    VkCommandPool rawPool;
    vk::check(vkCreateCommandPool(vkd, &pci, nullptr, &rawPool), "vkCreateCommandPool");
    owned::CommandPool pool(vkd, rawPool);
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = rawPool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cmd;
    vk::check(vkAllocateCommandBuffers(vkd, &ai, &cmd), "vkAllocateCommandBuffers");
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vk::check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
    VulkanCommands sink(cmd, commandFunctions());
    record(sink);
    vk::check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    VkCommandBufferSubmitInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cbi.commandBuffer = cmd;
    VkSubmitInfo2 si{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    si.commandBufferInfoCount = 1;
    si.pCommandBufferInfos = &cbi;
    // A fence of its own: waiting for the queue to be idle would also wait for every frame
    // that other renderers have in flight there.
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence rawFence;
    vk::check(vkCreateFence(vkd, &fci, nullptr, &rawFence), "vkCreateFence");
    owned::Fence fence(vkd, rawFence);
    vk::check(vkQueueSubmit2(dev.queue, 1, &si, rawFence), "vkQueueSubmit2");
    vk::check(vkWaitForFences(vkd, 1, &rawFence, VK_TRUE, kWaitForever), "vkWaitForFences");
}

namespace {

/// What an external image holds before anything is uploaded: its clear value, else mid grey
/// (depth: 1, the far plane of a forward-Z buffer).
void recordInitialClear(CommandSink& sink, const ResourceState& r, VkImage image, const PlannedUsage& u) {
    const VkImageSubresourceRange range{r.aspect, u.range.baseMip, u.range.mipCount, u.range.baseLayer,
                                        u.range.layerCount};
    const std::optional<ClearValue>& clear = r.desc->clear;
    if (r.desc->format.isDepthStencil()) {
        sink.clearDepthStencil(image, u.layout, {clear ? clear->depth : 1.0f, clear ? clear->stencil : 0u}, range);
        return;
    }
    const std::array<float, 4> grey{0.5f, 0.5f, 0.5f, 1.0f};
    const std::array<float, 4>& c = clear ? clear->color : grey;
    sink.clearColor(image, u.layout, clearColorOf(r.format, c), range);
}

/// How many copies the renderer keeps of a resource: one, or one per frame slot.
size_t copiesOf(const ResourceState& r) { return r.isImage ? r.images.size() : r.buffers.size(); }

}  // namespace

std::optional<std::string> Renderer::Impl::externalPixelsProblem(const PlanState& s, const std::string& resource,
                                                                 const ImageData& pixels) {
    const ResourceDesc* desc = s.graph.findResource(resource);
    if (!desc) return "no resource '" + resource + "' in the graph";
    if (!desc->isImage()) return "'" + resource + "' is a buffer, not an external image";
    if (!desc->external) return "'" + resource + "' is not an external image";
    const auto ext = desc->extent.resolve(s.outputWidth(), s.outputHeight());
    if (pixels.width != ext[0] || pixels.height != ext[1])
        return "'" + resource + "' is " + std::to_string(ext[0]) + "x" + std::to_string(ext[1]) + ", the pixels are " +
               std::to_string(pixels.width) + "x" + std::to_string(pixels.height);
    if (pixels.rgba.size() != size_t(pixels.width) * pixels.height * 4)
        return "the pixels of '" + resource + "' say " + std::to_string(pixels.width) + "x" +
               std::to_string(pixels.height) + " but hold " + std::to_string(pixels.rgba.size()) + " floats, not " +
               std::to_string(size_t(pixels.width) * pixels.height * 4);
    const uint32_t texel = findFormat(desc->format.format) ? desc->format.bytesPerTexel : 0;
    std::array<float, 4> probe{1, 1, 1, 1};
    const auto encoded = encodeTexel(desc->format.format, texel, probe);
    if (texel == 0 || std::all_of(encoded.begin(), encoded.end(), [](uint8_t b) { return b == 0; }))
        return "cannot upload pixels to format " + std::string(desc->format.name);
    return std::nullopt;
}

void Renderer::Impl::runSetup(PlanState& s, std::string_view only, bool withNextFrame) {
    SetupOptions o;
    for (const auto& [name, image] : imports) o.imports.insert(name);
    for (const auto& [name, pixels] : uploads) {
        if (s.plan.resourceIndex(name) < 0 || imports.count(name)) continue;
        // Kept from setExternalImage() for an earlier plan: a resize or a new graph may have
        // changed the image (the copy would read past the pixels) or made it no external one.
        if (const auto problem = externalPixelsProblem(s, name, pixels))
            throw ExecutorError("the pixels setExternalImage() gave '" + name + "' do not fit this plan: " + *problem +
                                " (forgetExternalImage() them, rebuild, then give pixels that fit)");
        o.uploads.insert(name);
    }
    if (!only.empty()) {
        // Every other external resource keeps its contents: to the setup, it is provided.
        for (const PlannedResource& r : s.plan.resources())
            if (r.name != only && s.graph.resources[r.decl].external) o.imports.insert(std::string(r.name));
        std::erase_if(o.uploads, [&](const std::string& name) { return name != only; });
    }
    // A setup of one resource is the renderer's own business: setupPlan() stays the one that
    // ran before the first frame.
    auto planned = std::make_shared<Plan>();
    try {
        *planned = planSetup(s.graph, s.plan, o);
        if (setupPlanEdit) setupPlanEdit(*planned);
    } catch (const GraphError& e) {
        throw ExecutorError(e.what());
    }
    if (only.empty()) s.setup = *planned;
    const Plan& setup = *planned;
    if (setup.passes().empty()) return;
    // Each setup resource is a frame resource of the same name; a per-slot one is set up once
    // per copy.
    std::vector<uint32_t> frameResource;
    for (const PlannedResource& r : setup.resources()) frameResource.push_back(uint32_t(s.plan.resourceIndex(r.name)));
    for (const uint32_t r : frameResource) ++s.resources[r].contentsReplaced;
    const auto copiesOfSetupResource = [&](uint32_t r) { return copiesOf(s.resources[frameResource[r]]); };
    // Host contents of the Upload steps, written before the submission (which makes host writes
    // visible to it): one staging buffer per step, shared by the copies.
    auto stagingOwned = std::make_shared<std::vector<OwnedBuffer>>(setup.passes().size());
    std::vector<OwnedBuffer>& staging = *stagingOwned;
    for (size_t i = 0; i < setup.passes().size(); ++i) {
        if (setup.passes()[i].type != "Upload") continue;
        const ResourceState& r = s.resources[frameResource[setup.passes()[i].usages[0].resource]];
        if (!r.isImage) {
            staging[i] = makeHostBuffer(r.size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
            fillBufferPattern(static_cast<uint8_t*>(staging[i].mapped), r.size, 0.5f);
            continue;
        }
        const ImageData& px = uploads.at(r.desc->name);
        const uint32_t texel = copyTexelBytes(r.desc->format);
        const VkDeviceSize layerBytes = VkDeviceSize(r.width) * r.height * texel;
        staging[i] = spareStaging(layerBytes * r.layers);
        auto* dst = static_cast<uint8_t*>(staging[i].mapped);
        // Float RGBA is what the pixels are already (an HDRI): copied as it is.
        const bool asIs = r.format == VK_FORMAT_R32G32B32A32_SFLOAT && texel == 16;
        for (uint32_t l = 0; l < r.layers && asIs; ++l) std::memcpy(dst + l * layerBytes, px.rgba.data(), layerBytes);
        for (uint32_t l = 0; l < r.layers && !asIs; ++l)
            for (size_t p = 0; p < size_t(r.width) * r.height; ++p) {
                const std::array<float, 4> c{px.rgba[p * 4], px.rgba[p * 4 + 1], px.rgba[p * 4 + 2], px.rgba[p * 4 + 3]};
                const auto t = encodeTexel(r.format, texel, c);
                std::memcpy(dst + l * layerBytes + p * texel, t.data(), texel);
            }
    }
    auto record = [this, &s, planned, stagingOwned, frameResource](CommandSink& sink) {
        const Plan& steps = *planned;
        const std::vector<OwnedBuffer>& stagingOf = *stagingOwned;
        const size_t copies = options.framesInFlight;
        for (uint32_t c = 0; c < copies; ++c) {
            // Copy c of a per-slot resource is frame slot c's, whose first binding slot is this.
            const uint32_t binding = c * s.presentImages;
            const auto target = [&](uint32_t r) { return s.resources[frameResource[r]].barrierTarget(binding); };
            for (size_t i = 0; i < steps.passes().size(); ++i) {
                const PlannedPass& step = steps.passes()[i];
                const PlannedUsage& u = step.usages[0];
                const ResourceState& r = s.resources[frameResource[u.resource]];
                if (c >= copiesOf(r)) continue;
                if (const BarrierBatch before(step.barriers, target, s.families()); !before.empty()) sink.barriers(before);
                if (step.type == "Clear") {
                    recordInitialClear(sink, r, r.images[c].image, u);
                } else if (step.type == "Downsample") {
                    sink.blitImage(r.images[c].image, step.usages[1].layout, u.layout,
                                   downsampleRegion(r.aspect, r.width, r.height, step.usages[1].range, u.range));
                } else if (!r.isImage) {
                    const VkBufferCopy region{0, 0, r.size};
                    sink.copyBuffer(stagingOf[i].buffer.get(), r.buffers[c].buffer.get(), {&region, 1});
                } else {
                    VkBufferImageCopy region{};
                    region.imageSubresource = {copyAspectOf(r.desc->format), 0, 0, r.layers};
                    region.imageExtent = {r.width, r.height, 1};
                    sink.copyBufferToImage(stagingOf[i].buffer.get(), r.images[c].image, u.layout, {&region, 1});
                }
            }
            std::vector<Barrier> finals;
            for (const Barrier& b : steps.finalBarriers())
                if (c < copiesOf(s.resources[frameResource[b.resource]])) finals.push_back(b);
            if (const BarrierBatch after(finals, target, s.families()); !after.empty()) sink.barriers(after);
        }
    };
    // One copy of each resource, and every submit of the plan on the queue the setup is made
    // for: the next frame records the steps before its passes and nothing waits, since their
    // barriers follow every use by the frames before in that queue's submission order. A
    // resource with a copy per frame slot may be in use by frames in flight, and a use on
    // another queue is not ordered before them.
    bool singleCopies = true;
    for (const PlannedPass& step : setup.passes()) singleCopies &= copiesOfSetupResource(step.usages[0].resource) == 1;
    for (const Submit& sub : s.plan.submits()) singleCopies &= dev.queues[static_cast<size_t>(sub.queue)] == dev.queue;
    // Pixels set up now replace any still waiting for the next frame, which would otherwise
    // be copied over them.
    const auto supersedes = [&](const PendingSetup& p) {
        return p.state == &s && (only.empty() || p.resource == only);
    };
    if (withNextFrame && singleCopies) {
        std::erase_if(pendingSetups, supersedes);
        lastStaging = stagingOwned;
        pendingSetups.push_back(PendingSetup{&s, std::string(only), std::move(record), std::move(stagingOwned)});
        return;
    }
    if (withNextFrame) waitIdle();  // the caller left the frames running for a setup that would ride with one
    submitAndWait(record);
    std::erase_if(pendingSetups, supersedes);
}

OwnedBuffer Renderer::Impl::spareStaging(VkDeviceSize bytes) {
    // A buffer kept from an upload before whose frame has finished (nothing else holds the
    // list): re-uploading the same image again and again allocates nothing.
    if (lastStaging && lastStaging.use_count() == 1)
        for (OwnedBuffer& b : *lastStaging)
            if (b.buffer && b.size == bytes) return std::move(b);
    return makeHostBuffer(bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
}

}  // namespace skygraph
