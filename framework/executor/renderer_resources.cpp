// Renderer::Impl: images, buffers and views of the plan's resources, their per-slot copies,
// and the one-time import of external resources.
#include "renderer_impl.hpp"

#include <cstdio>

namespace skygraph {

using namespace detail;

namespace {

std::string gib(VkDeviceSize bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f GiB", static_cast<double>(bytes) / double(1ull << 30));
    return text;
}

/// Refuses a plan whose resources the device cannot hold, before anything is allocated (so
/// a resize or a reload to an absurd extent leaves the running plan untouched): each image
/// within the device's dimension and layer limits, each buffer within its binding range,
/// and all of them together within the memory cap, half of the largest device-local heap
/// (docs/reliability.md: the other half is left to pipelines, staging and other programs).
void refuseOversizedResources(const PlanState& s, VkPhysicalDevice physical, uint32_t outputWidth,
                              uint32_t outputHeight, uint32_t slots) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(physical, &props);
    VkPhysicalDeviceMemoryProperties mem;
    vkGetPhysicalDeviceMemoryProperties(physical, &mem);
    VkDeviceSize heap = 0;
    for (uint32_t i = 0; i < mem.memoryHeapCount; ++i)
        if (mem.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) heap = std::max(heap, mem.memoryHeaps[i].size);
    const VkDeviceSize cap = heap / 2;
    const VkPhysicalDeviceLimits& limits = props.limits;
    VkDeviceSize total = 0;
    for (const ResourceState& r : s.resources) {
        const ResourceDesc& d = *r.desc;
        const uint32_t copies = r.presented ? 0 : r.perSlot ? slots : 1;  // present images are not ours
        VkDeviceSize bytes = 0;
        if (!r.isImage) {
            const bool storage = r.bufferUsage & VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
            const bool uniform = r.bufferUsage & VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT;
            if (storage && d.sizeBytes > limits.maxStorageBufferRange)
                throw ExecutorError("resource '" + d.name + "': a storage buffer of " + std::to_string(d.sizeBytes) +
                                    " bytes exceeds the device's maxStorageBufferRange (" +
                                    std::to_string(limits.maxStorageBufferRange) + "); nothing was allocated");
            if (uniform && d.sizeBytes > limits.maxUniformBufferRange)
                throw ExecutorError("resource '" + d.name + "': a uniform buffer of " + std::to_string(d.sizeBytes) +
                                    " bytes exceeds the device's maxUniformBufferRange (" +
                                    std::to_string(limits.maxUniformBufferRange) + "); nothing was allocated");
            bytes = d.sizeBytes;
        } else {
            const auto [w, h] = d.extent.resolve(outputWidth, outputHeight);
            const bool cube = d.type == ResourceType::Cube;
            const uint32_t most = cube ? limits.maxImageDimensionCube : limits.maxImageDimension2D;
            if (w > most || h > most)
                throw ExecutorError("resource '" + d.name + "': " + std::to_string(w) + "x" + std::to_string(h) +
                                    " exceeds the device's " + (cube ? "maxImageDimensionCube" : "maxImageDimension2D") +
                                    " (" + std::to_string(most) + ") at output " + std::to_string(outputWidth) + "x" +
                                    std::to_string(outputHeight) + "; nothing was allocated");
            if (d.layers > limits.maxImageArrayLayers)
                throw ExecutorError("resource '" + d.name + "': " + std::to_string(d.layers) +
                                    " layers exceed the device's maxImageArrayLayers (" +
                                    std::to_string(limits.maxImageArrayLayers) + "); nothing was allocated");
            const uint32_t mips = std::max(1u, d.mipCount(outputWidth, outputHeight));
            const VkDeviceSize texel = std::max(1u, copyTexelBytes(d.format));
            for (uint32_t m = 0; m < mips; ++m)
                bytes += VkDeviceSize(std::max(1u, w >> m)) * std::max(1u, h >> m) * texel * std::max(1u, d.layers);
        }
        total += bytes * copies;
    }
    if (cap != 0 && total > cap)
        throw ExecutorError("the plan's resources need " + gib(total) + " at output " + std::to_string(outputWidth) +
                            "x" + std::to_string(outputHeight) + ", over the memory cap of " + gib(cap) +
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

OwnedBuffer Renderer::Impl::makeBuffer(VkDeviceSize size, VkBufferUsageFlags usage, bool hostVisible) {
    OwnedBuffer b;
    b.size = std::max<VkDeviceSize>(size, 4);
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = b.size;
    bci.usage = usage;
    VkBuffer buffer;
    vk::check(vkCreateBuffer(vkd, &bci, nullptr, &buffer), "vkCreateBuffer");
    b.buffer = vk::Buffer(vkd, buffer);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(vkd, buffer, &req);
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = vk::findMemoryType(
        dev.physical, req.memoryTypeBits,
        hostVisible ? (VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT)
                    : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    VkDeviceMemory mem;
    vk::check(vkAllocateMemory(vkd, &mai, nullptr, &mem), "vkAllocateMemory");
    b.memory = vk::Memory(vkd, mem);
    vk::check(vkBindBufferMemory(vkd, buffer, mem, 0), "vkBindBufferMemory");
    if (hostVisible) vk::check(vkMapMemory(vkd, mem, 0, VK_WHOLE_SIZE, 0, &b.mapped), "vkMapMemory");
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
    img.views.emplace(key, vk::ImageView(vkd, v));
    return v;
}

void Renderer::Impl::describeResources(PlanState& s) {
    const uint32_t slots = options.framesInFlight;
    describePresent(s);
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
        if (pr.copies == ResourceCopies::PerFrameWrittenNotExported && r.isImage &&
            pr.initialLayout != VK_IMAGE_LAYOUT_UNDEFINED &&
            pr.finalLayout != pr.initialLayout) {
            throw ExecutorError("resource '" + r.desc->name +
                                "': an external image that the graph writes ends the frame in a "
                                "different layout than it arrives in; give it a `final` state");
        }
        if (r.isImage) {
            r.format = r.desc->format.format;
            r.aspect = aspectOf(r.desc->format);
            if (r.format == VK_FORMAT_UNDEFINED)
                throw ExecutorError("resource '" + r.desc->name + "' has no format");
        }
    }
    // Layouts the resource arrives in or is left in need their usage flags too (an
    // environment map exported as ShaderRead is sampled by the next graph).
    for (size_t i = 0; i < s.plan.resources().size(); ++i) {
        for (const VkImageLayout l : {s.plan.resources()[i].initialLayout, s.plan.resources()[i].finalLayout})
            s.resources[i].imageUsage |= layoutUsage(l);
    }
    for (const PlannedPass& pass : s.plan.passes()) {
        for (const PlannedUsage& u : pass.usages) {
            if (u.resource >= s.resources.size())
                throw ExecutorError(passError(pass, "", "usage refers to an unknown resource"));
            ResourceState& r = s.resources[u.resource];
            addUsageFlags(u, r.desc->isImage(), r.imageUsage, r.bufferUsage);
        }
    }
    refuseOversizedResources(s, dev.physical, s.outputWidth(), s.outputHeight(), options.framesInFlight);
}

void Renderer::Impl::createResources(PlanState& s) {
    const uint32_t slots = options.framesInFlight;
    for (ResourceState& r : s.resources) {
        const ResourceDesc& d = *r.desc;
        const uint32_t copies = r.perSlot ? slots : 1;
        r.images.clear();
        r.buffers.clear();
        if (!r.isImage) {
            if (d.sizeBytes == 0) throw ExecutorError("buffer '" + d.name + "' has no size");
            r.size = d.sizeBytes;
            for (uint32_t c = 0; c < copies; ++c) r.buffers.push_back(makeBuffer(r.size, r.bufferUsage, false));
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
        VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
        ci.flags = d.type == ResourceType::Cube ? VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT : 0;
        ci.imageType = VK_IMAGE_TYPE_2D;
        ci.format = r.format;
        ci.extent = {r.width, r.height, 1};
        ci.mipLevels = r.mips;
        ci.arrayLayers = r.layers;
        ci.samples = VK_SAMPLE_COUNT_1_BIT;
        ci.tiling = VK_IMAGE_TILING_OPTIMAL;
        ci.usage = r.imageUsage;
        ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        VkImageFormatProperties fp;
        if (vkGetPhysicalDeviceImageFormatProperties(dev.physical, ci.format, ci.imageType, ci.tiling,
                                                     ci.usage, ci.flags, &fp) != VK_SUCCESS ||
            fp.maxMipLevels < r.mips || fp.maxArrayLayers < r.layers ||
            fp.maxExtent.width < r.width || fp.maxExtent.height < r.height) {
            throw ExecutorError("resource '" + d.name + "': the device cannot create a " +
                                std::string(d.format.name) + " image of " +
                                std::to_string(r.width) + "x" + std::to_string(r.height) +
                                " with the usages the plan needs");
        }
        if (const auto it = imports.find(d.name); it != imports.end()) {
            r.images.push_back(adoptImport(s, size_t(&r - s.resources.data()), it->second));
            continue;
        }
        for (uint32_t c = 0; c < copies; ++c) {
            ImageCopy img;
            auto storage = std::make_shared<ImageStorage>();
            VkImage image;
            vk::check(vkCreateImage(vkd, &ci, nullptr, &image), "vkCreateImage");
            storage->image = vk::Image(vkd, image);
            img.image = image;
            VkMemoryRequirements req;
            vkGetImageMemoryRequirements(vkd, image, &req);
            VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
            mai.allocationSize = req.size;
            mai.memoryTypeIndex = vk::findMemoryType(dev.physical, req.memoryTypeBits,
                                                     VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
            VkDeviceMemory mem;
            vk::check(vkAllocateMemory(vkd, &mai, nullptr, &mem), "vkAllocateMemory");
            storage->memory = vk::Memory(vkd, mem);
            img.storage = std::move(storage);
            vk::check(vkBindImageMemory(vkd, image, mem, 0), "vkBindImageMemory");
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
        const VkDeviceSize bytes = VkDeviceSize(r.width) * r.height * copyTexelBytes(r.desc->format);
        for (uint32_t slot = 0; slot < options.framesInFlight; ++slot)
            t.perSlot.push_back(makeBuffer(bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true));
        s.readbacks.push_back(std::move(t));
    }
}

ImageCopy Renderer::Impl::adoptImport(const PlanState& s, size_t index, const SharedImage& shared) const {
    const SharedImage::Impl& from = *shared.impl_;
    const ResourceState& r = s.resources[index];
    const std::string what = "importImage: resource '" + r.desc->name + "' from " + from.origin + ": ";
    if (from.device != vkd) throw ExecutorError(what + "the image belongs to another device");
    if (from.format != r.format || from.width != r.width || from.height != r.height || from.mips != r.mips ||
        from.layers != r.layers) {
        throw ExecutorError(what + "the image is " + std::to_string(from.width) + "x" + std::to_string(from.height) +
                            ", " + std::to_string(from.mips) + " mips, " + std::to_string(from.layers) +
                            " layers of format " + std::to_string(from.format) + "; the graph declares " +
                            std::to_string(r.width) + "x" + std::to_string(r.height) + ", " + std::to_string(r.mips) +
                            " mips, " + std::to_string(r.layers) + " layers of format " + std::to_string(r.format));
    }
    if ((r.imageUsage & ~from.usage) != 0) throw ExecutorError(what + "the image lacks usages this plan needs");
    for (const PlannedPass& pass : s.plan.passes())
        for (const PlannedUsage& u : pass.usages)
            if (u.resource == index && writesContents(u.usage.access))
                throw ExecutorError(what + "pass '" + std::string(pass.name) + "' writes it; an imported image is read-only");
    if (s.plan.resources()[index].initialLayout != from.layout)
        throw ExecutorError(what + "the producer leaves it in layout " + std::to_string(from.layout) +
                            ", this plan expects it to arrive in " +
                            std::to_string(s.plan.resources()[index].initialLayout) + " (its `initial` state)");
    ImageCopy copy;
    copy.storage = from.storage;
    copy.image = from.storage->image.get();
    return copy;
}

}  // namespace skygraph
