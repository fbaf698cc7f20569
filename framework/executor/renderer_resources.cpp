// Renderer::Impl: images, buffers and views of the plan's resources, their per-slot copies,
// and the one-time import of external resources.
#include "renderer_impl.hpp"
#include "resource_creation.hpp"

#include <skygraph/plan_format.hpp>

#include <string_view>
#include <unordered_set>

namespace skygraph {

using namespace detail;

namespace {

/// Refuses a plan whose resources the device cannot hold, before anything is allocated (so
/// a resize or a reload to an absurd extent leaves the running plan untouched): each image
/// within the device's dimension and layer limits, each buffer within its binding range,
/// each heap within one allocation's limit, and all of them together within the memory cap
/// (resource_creation.hpp). Transients placed
/// in heaps count as the heaps they share, once per frame slot (once if the frames share
/// them); the others as themselves, once per copy.
void refuseOversizedResources(const PlanState& s, const DeviceCapacity& capacity, uint32_t slots) {
    const uint32_t outputWidth = s.outputWidth(), outputHeight = s.outputHeight();
    // The output size is named only where it made the sizes: a bake's fixed-size cubes have none.
    const std::string atOutput = " at output " + std::to_string(outputWidth) + "x" + std::to_string(outputHeight);
    bool anyFollowsOutput = false;
    VkDeviceSize total = 0;
    for (const ResourceState& r : s.resources) {
        const ResourceDesc& d = *r.desc;
        const uint32_t copies = r.presented ? 0 : r.perSlot ? slots : 1;  // present images are not ours
        VkDeviceSize bytes = 0;
        if (!r.isImage) {
            refuseBufferBeyondLimits(capacity, d, r.bufferUsage);
            bytes = bufferBytes(d);
        } else {
            const auto [w, h] = d.extent.resolve(outputWidth, outputHeight);
            const uint32_t mips = std::max(1u, d.mipCount(outputWidth, outputHeight));
            refuseImageBeyondLimits(capacity, d, w, h, mips, d.layers, d.extent.relativeToOutput ? atOutput : "");
            anyFollowsOutput |= d.extent.relativeToOutput;
            bytes = packedBytes(d, w, h, mips, d.layers);
        }
        if (r.placement == PlannedResource::kNoPlacement) total += bytes * copies;
    }
    const std::string at = anyFollowsOutput ? atOutput : "";
    const std::vector<MemoryHeap>& heaps = s.plan.memory().heaps;
    for (size_t h = 0; h < heaps.size(); ++h)
        if (capacity.maxAllocation != 0 && heaps[h].bytes > capacity.maxAllocation)
            throw DeviceCapacityError("heap " + std::to_string(h) + " of the plan's transients needs " + gib(heaps[h].bytes) +
                                at + ", over the " + gib(capacity.maxAllocation) +
                                " one allocation of the device may have (maxMemoryAllocationSize); nothing was allocated");
    total += s.plan.memory().heapBytes() * (s.plan.memory().sharedAcrossFrames ? 1 : slots);
    if (capacity.memoryCap != 0 && total > capacity.memoryCap)
        throw DeviceCapacityError("the plan's resources need " + gib(total) + at + ", over the memory cap of " +
                            gib(capacity.memoryCap) +
                            " (half the device's largest device-local heap); nothing was allocated");
}

}  // namespace

namespace detail {

VkImageUsageFlags layoutUsage(VkImageLayout layout) noexcept {
    if (layout == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL) return VK_IMAGE_USAGE_SAMPLED_BIT;
    if (layout == VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL) return VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    return 0;
}

void addUsageFlags(const PlannedUsage& u, bool isImage, VkImageUsageFlags& image, VkBufferUsageFlags& buffer) noexcept {
    const UsageFlags f = usageFlags(u.usage, isImage);
    image |= f.image;
    buffer |= f.buffer;
}

VkImageUsageFlags planImageUsage(const Plan& plan, uint32_t resource) {
    if (resource >= plan.resources().size()) throw ExecutorError("plan resource " + std::to_string(resource) + " does not exist");
    const PlannedResource& res = plan.resources()[resource];
    VkImageUsageFlags image = layoutUsage(res.initialLayout) | layoutUsage(res.finalLayout);
    VkBufferUsageFlags buffer = 0;
    for (const PlannedPass& pass : plan.passes())
        for (const PlannedUsage& u : pass.usages)
            if (u.resource == resource) addUsageFlags(u, true, image, buffer);
    return image;
}

}  // namespace detail

OwnedBuffer Renderer::Impl::makeHostBuffer(VkDeviceSize size, VkBufferUsageFlags usage) {
    OwnedBuffer b;
    b.size = std::max<VkDeviceSize>(size, 4);
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = b.size;
    bci.usage = usage;
    VkBuffer buffer;
    vk::check(vkCreateBuffer(vkd, &bci, nullptr, &buffer), "vkCreateBuffer");
    b.buffer = owned::Buffer(vkd, buffer);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(vkd, buffer, &req);
    b.memory = allocate(req.size, req.memoryTypeBits,
                        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, "host buffer");
    const VkDeviceMemory mem = b.memory->memory.get();
    vk::check(vkBindBufferMemory(vkd, buffer, mem, 0), "vkBindBufferMemory");
    vk::check(vkMapMemory(vkd, mem, 0, VK_WHOLE_SIZE, 0, &b.mapped), "vkMapMemory");
    return b;
}

VkImageView Renderer::Impl::view(ResourceState& r, uint32_t copy, VkImageViewType type,
                                 const SubresourceRange& range, bool attachment) {
    ImageCopy& img = r.images[copy];
    const auto key = std::make_tuple(static_cast<int>(type) + (attachment ? 100 : 0), range.baseMip,
                                     range.mipCount, range.baseLayer, range.layerCount);
    if (auto it = img.views.find(key); it != img.views.end()) return it->second.get();
    VkImageViewCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    ci.image = img.image;
    ci.viewType = type;
    ci.format = r.format;
    // Sampling a depth/stencil image reads one aspect; attachments use all of them.
    ci.subresourceRange.aspectMask =
        attachment ? r.aspect
                   : ((r.aspect & VK_IMAGE_ASPECT_DEPTH_BIT) ? VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT)
                                                            : r.aspect);
    ci.subresourceRange.baseMipLevel = range.baseMip;
    ci.subresourceRange.levelCount = range.mipCount;
    ci.subresourceRange.baseArrayLayer = range.baseLayer;
    ci.subresourceRange.layerCount = range.layerCount;
    VkImageView v;
    vk::check(vkCreateImageView(vkd, &ci, nullptr, &v), "vkCreateImageView");
    img.views.emplace(key, owned::ImageView(vkd, v));
    return v;
}

void Renderer::Impl::describeResources(PlanState& s) {
    const uint32_t slots = options.framesInFlight;
    describePresent(s);
    // The embedding API finds resources by name (importImage, setExternalImage, stageUpload,
    // shareImage): two of one name would be one to it. The loader refuses them in a file; a
    // GraphDesc built in code reaches here.
    std::unordered_set<std::string_view> names;
    for (const ResourceDesc& r : s.graph.resources)
        if (!names.insert(r.name).second)
            throw ExecutorError("the graph has two resources named '" + r.name + "': the renderer finds resources by name");
    s.resources.resize(s.plan.resources().size());
    for (size_t i = 0; i < s.plan.resources().size(); ++i) {
        const PlannedResource& pr = s.plan.resources()[i];
        if (pr.decl >= s.graph.resources.size())
            throw ExecutorError("plan resource '" + std::string(pr.name) + "' is not in the graph");
        ResourceState& r = s.resources[i];
        r.desc = &s.graph.resources[pr.decl];
        r.isImage = r.desc->isImage();
        r.presented = int32_t(i) == s.presentResource;
        r.perSlot = perFrameInFlight(pr.copies) && slots > 1 && !r.presented;
        r.presentImages = s.presentImages;
        // The compiler moves such an image back; a plan edited or built without that would
        // have the next frame's barriers transition it from a layout it is not in.
        const bool arrivesAsItWasLeft = pr.copies == ResourceCopies::PerFrameWrittenNotExported ||
                                        pr.copies == ResourceCopies::SharedReadOnly;
        if (arrivesAsItWasLeft && r.isImage && pr.initialLayout != VK_IMAGE_LAYOUT_UNDEFINED &&
            pr.finalLayout != pr.initialLayout) {
            throw ExecutorError("resource '" + r.desc->name + "': an external image that is not exported ends the frame in " +
                                layoutName(pr.finalLayout) + " but the next frame expects it in " +
                                layoutName(pr.initialLayout) + "; the plan lacks the final barrier back");
        }
        if (r.isImage) {
            r.format = r.desc->format.format;
            r.aspect = aspectOf(r.desc->format);
            if (r.format == VK_FORMAT_UNDEFINED)
                throw ExecutorError("resource '" + r.desc->name + "' has no format");
        }
        if (pr.placement != PlannedResource::kNoPlacement) {
            const MemoryLayout& layout = s.plan.memory();
            if (pr.placement >= layout.placements.size() || layout.placements[pr.placement].resource != i ||
                layout.placements[pr.placement].heap >= layout.heaps.size())
                throw ExecutorError("resource '" + r.desc->name + "': its placement is not in the plan's memory layout");
            // Only transients live in heaps: a copy per frame slot in the slot's heaps, or one
            // copy in heaps the frames share.
            const ResourceCopies transient =
                layout.sharedAcrossFrames ? ResourceCopies::SharedTransient : ResourceCopies::PerFrameTransient;
            if (pr.copies != transient || r.presented)
                throw ExecutorError("resource '" + r.desc->name + "': only a transient resource can be placed in a heap");
            r.placement = pr.placement;
        }
    }
    // Layouts the resource arrives in or is left in need their usage flags too (an
    // environment map exported as ShaderRead is sampled by the next graph). Not for a placed
    // transient: it is created with exactly the usage the compiler asked its memory
    // requirements for (kAlwaysUsable and its usages'), which its layouts add nothing to, as
    // it arrives UNDEFINED and ends in its last use's layout.
    for (size_t i = 0; i < s.plan.resources().size(); ++i) {
        if (s.resources[i].placement != PlannedResource::kNoPlacement) continue;
        for (const VkImageLayout l : {s.plan.resources()[i].initialLayout, s.plan.resources()[i].finalLayout})
            s.resources[i].imageUsage |= layoutUsage(l);
    }
    for (const PlannedPass& pass : s.plan.passes()) {
        const bool upload = pass.type == "UploadPass";
        for (const PlannedUsage& u : pass.usages) {
            if (u.resource >= s.resources.size())
                throw ExecutorError(passError(pass, "", "usage refers to an unknown resource"));
            ResourceState& r = s.resources[u.resource];
            addUsageFlags(u, r.desc->isImage(), r.imageUsage, r.bufferUsage);
            r.uploaded = r.uploaded || upload;
        }
    }
    refuseOversizedResources(s, DeviceCapacity::of(dev.physical), options.framesInFlight);
}

void Renderer::Impl::createResources(PlanState& s) {
    const uint32_t slots = options.framesInFlight;
    allocateHeaps(s);
    const ConcurrentFamilies families = distinctFamilies(dev.families);
    for (ResourceState& r : s.resources) {
        const ResourceDesc& d = *r.desc;
        const bool concurrent = s.plan.concurrent(static_cast<uint32_t>(&r - s.resources.data()));
        const uint32_t copies = r.perSlot ? slots : 1;
        r.images.clear();
        r.buffers.clear();
        if (!r.isImage) {
            if (d.sizeBytes == 0) throw ExecutorError("buffer '" + d.name + "' has no size");
            r.size = d.sizeBytes;
            VkBufferCreateInfo ci = bufferCreateInfo(d, r.bufferUsage);
            if (concurrent) shareConcurrently(ci, families);
            for (uint32_t c = 0; c < copies; ++c) {
                OwnedBuffer b;
                b.size = ci.size;
                VkBuffer buffer;
                vk::check(vkCreateBuffer(vkd, &ci, nullptr, &buffer), "vkCreateBuffer");
                b.buffer = owned::Buffer(vkd, buffer);
                b.memory = bindBuffer(s, r, c, buffer);
                r.buffers.push_back(std::move(b));
            }
            continue;
        }
        const auto ext = d.extent.resolve(s.outputWidth(), s.outputHeight());
        r.width = ext[0];
        r.height = ext[1];
        r.mips = std::max(1u, d.mipCount(s.outputWidth(), s.outputHeight()));
        r.layers = std::max(1u, d.layers);
        if (r.presented) {
            // The present images: checked against the plan by describePresent.
            for (const VkImage image : present->images.images) {
                ImageCopy img;
                img.image = image;
                r.images.push_back(std::move(img));
            }
            continue;
        }
        VkImageCreateInfo ci = imageCreateInfo(d, r.width, r.height, r.mips, r.layers, r.imageUsage);
        if (concurrent) shareConcurrently(ci, families);
        refuseUnsupportedImage(dev.physical, d, ci);
        if (const auto it = imports.find(d.name); it != imports.end()) {
            r.images.push_back(adoptImport(s, size_t(&r - s.resources.data()), it->second));
            continue;
        }
        for (uint32_t c = 0; c < copies; ++c) {
            ImageCopy img;
            auto storage = std::make_shared<ImageStorage>();
            VkImage image;
            vk::check(vkCreateImage(vkd, &ci, nullptr, &image), "vkCreateImage");
            storage->image = owned::Image(vkd, image);
            storage->concurrent = ci.sharingMode == VK_SHARING_MODE_CONCURRENT;
            img.image = image;
            storage->memory = bindImage(s, r, c, image);
            img.storage = std::move(storage);
            if (dev.fn.setObjectName) {
                VkDebugUtilsObjectNameInfoEXT ni{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
                ni.objectType = VK_OBJECT_TYPE_IMAGE;
                ni.objectHandle = reinterpret_cast<uint64_t>(image);
                const std::string name = d.name + (r.perSlot ? "#" + std::to_string(c) : "");
                ni.pObjectName = name.c_str();
                dev.fn.setObjectName(vkd, &ni);
            }
            r.images.push_back(std::move(img));
        }
    }
}

void Renderer::Impl::buildSized(PlanState& s) {
    const uint32_t slots = options.framesInFlight * s.presentImages;  // binding slots
    createResources(s);
    for (PassState& ps : s.passes) {
        ps.slots.clear();
        ps.slots.resize(slots);
        for (uint32_t slot = 0; slot < slots; ++slot) buildPassSlot(s, ps, slot);
    }
    translateFinalBarriers(s, slots);
    createReadbackTargets(s);
    runSetup(s);
}

void Renderer::Impl::createReadbackTargets(PlanState& s) {
    s.readbacks.clear();
    for (uint32_t step = 0; step < s.plan.passes().size(); ++step) {
        if (s.passes[step].kind != StepKind::Readback) continue;
        ReadbackTarget t;
        t.step = step;
        t.resource = s.plan.passes()[step].usages[0].resource;
        const ResourceState& r = s.resources[t.resource];
        if (!readsBack(r.format)) throw ExecutorError(notReadBackable(r.desc->name, r.format));
        const VkDeviceSize bytes = VkDeviceSize(r.width) * r.height * copyTexelBytes(r.desc->format);
        for (uint32_t slot = 0; slot < options.framesInFlight; ++slot)
            t.perSlot.push_back(makeHostBuffer(bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT));
        s.readbacks.push_back(std::move(t));
    }
}

void Renderer::Impl::checkImportShape(const ResourceDesc& d, uint32_t outputWidth, uint32_t outputHeight,
                                      const SharedImage& shared) const {
    const SharedImage::Impl& from = *shared.impl_;
    const std::string what = "importImage: resource '" + d.name + "' from " + from.origin + ": ";
    if (from.device != vkd) throw ExecutorError(what + "the image belongs to another device");
    const auto ext = d.extent.resolve(outputWidth, outputHeight);
    const uint32_t mips = std::max(1u, d.mipCount(outputWidth, outputHeight));
    const uint32_t layers = std::max(1u, d.layers);
    if (from.format != d.format.format || from.width != ext[0] || from.height != ext[1] || from.mips != mips ||
        from.layers != layers) {
        throw ExecutorError(what + "the image is " + std::to_string(from.width) + "x" + std::to_string(from.height) +
                            ", " + std::to_string(from.mips) + " mips, " + std::to_string(from.layers) +
                            " layers of format " + formatName(from.format) + "; the graph declares " +
                            std::to_string(ext[0]) + "x" + std::to_string(ext[1]) + ", " + std::to_string(mips) +
                            " mips, " + std::to_string(layers) + " layers of format " + std::string(d.format.name));
    }
}

ImageCopy Renderer::Impl::adoptImport(const PlanState& s, size_t index, const SharedImage& shared) const {
    const SharedImage::Impl& from = *shared.impl_;
    const ResourceState& r = s.resources[index];
    const std::string what = "importImage: resource '" + r.desc->name + "' from " + from.origin + ": ";
    checkImportShape(*r.desc, s.outputWidth(), s.outputHeight(), shared);
    if ((r.imageUsage & ~from.usage) != 0)
        throw ExecutorError(what + "the image lacks usage " + vk::imageUsageText(r.imageUsage & ~from.usage) +
                            ", which this plan needs");
    for (const PlannedPass& pass : s.plan.passes())
        for (const PlannedUsage& u : pass.usages)
            if (u.resource == index && writesContents(u.usage.access))
                throw ExecutorError(what + "pass '" + std::string(pass.name) + "' writes it; an imported image is read-only");
    if (s.plan.resources()[index].initialLayout != from.layout)
        throw ExecutorError(what + "the producer leaves it in " + layoutName(from.layout) +
                            ", this plan expects it to arrive in " +
                            layoutName(s.plan.resources()[index].initialLayout) + " (its `initial` state)");
    const bool concurrentHere = s.plan.concurrent(static_cast<uint32_t>(index)) && distinctFamilies(dev.families).count > 1;
    if (from.storage->concurrent != concurrentHere)
        throw ExecutorError(what + "the producer created it " +
                            (from.storage->concurrent ? "concurrent" : "exclusive") + ", this plan shares it " +
                            (concurrentHere ? "concurrently" : "exclusively") +
                            " between queue families; give it the same `sharing` in both graphs");
    ImageCopy copy;
    copy.storage = from.storage;
    copy.image = from.storage->image.get();
    return copy;
}

}  // namespace skygraph
