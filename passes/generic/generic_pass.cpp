#include "generic_pass.hpp"

#include "builtin_passes.hpp"

#include "pass_error.hpp"
#include "texel_encoding.hpp"
#include "vk_util.hpp"

#include <skygraph/shader_compiler.hpp>

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace skygraph::passes {

using detail::passError;

namespace {

/// A buffer the pass owns, with its memory; mapped when host-visible.
struct OwnedBuffer {
    owned::Buffer buffer;
    owned::Memory memory;
    void* mapped = nullptr;
};

OwnedBuffer makeBuffer(const PipelineContext& ctx, VkDeviceSize size, VkBufferUsageFlags usage, bool hostVisible) {
    OwnedBuffer b;
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = std::max<VkDeviceSize>(size, 4);
    bci.usage = usage;
    VkBuffer buffer;
    vk::check(vkCreateBuffer(ctx.device, &bci, nullptr, &buffer), "vkCreateBuffer");
    b.buffer = owned::Buffer(ctx.device, buffer);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx.device, buffer, &req);
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = vk::findMemoryType(
        ctx.physicalDevice, req.memoryTypeBits,
        hostVisible ? (VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT)
                    : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    VkDeviceMemory mem;
    vk::check(vkAllocateMemory(ctx.device, &mai, nullptr, &mem), "vkAllocateMemory");
    b.memory = owned::Memory(ctx.device, mem);
    vk::check(vkBindBufferMemory(ctx.device, buffer, mem, 0), "vkBindBufferMemory");
    if (hostVisible) vk::check(vkMapMemory(ctx.device, mem, 0, VK_WHOLE_SIZE, 0, &b.mapped), "vkMapMemory");
    return b;
}

/// Layered rendering (gl_Layer from the vertex shader), which draws into every attachment layer.
bool hasShaderOutputLayer(VkPhysicalDevice physical) {
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12, {}};
    vkGetPhysicalDeviceFeatures2(physical, &f2);
    return f12.shaderOutputLayer == VK_TRUE;
}

/// Extent of mip `mip` of a usage whose base mip `baseMip` is `base` texels wide or high.
uint32_t mipSize(uint32_t base, uint32_t baseMip, uint32_t mip) { return std::max(1u, base >> (mip - baseMip)); }

std::vector<VkDescriptorSetLayoutBinding> layoutBindings(const std::vector<ShaderBinding>& bindings) {
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

/// The extent a pass's stage covers when it writes storage: the largest written storage image
/// (its usage's base mip), else enough invocations for the written storage buffers' words.
VkExtent2D bindingExtent(const std::vector<ShaderBinding>& bindings, std::span<const BoundResource> resources,
                         bool& any) {
    VkExtent2D e{1, 1};
    any = false;
    for (const auto& b : bindings) {
        if (b.kind == BindKind::StorageImage && b.write) {
            e.width = std::max(e.width, resources[b.usage].extent.width);
            e.height = std::max(e.height, resources[b.usage].extent.height);
            any = true;
        }
    }
    for (const auto& b : bindings) {
        if (b.kind == BindKind::StorageBuffer && b.write) {
            const auto n = static_cast<uint32_t>(std::min<VkDeviceSize>(resources[b.usage].size / 4, 1u << 20));
            if (!any) e.width = std::max(e.width, std::min(n, 256u));
            e.height = std::max(e.height, (n + e.width - 1) / e.width);
            any = true;
        }
    }
    return e;
}

}  // namespace

/// Per frame slot: descriptor writes and buffers resolved to that slot's resources.
struct GenericPass::Slot {
    std::vector<VkDescriptorImageInfo> imageInfos;
    std::vector<VkDescriptorBufferInfo> bufferInfos;
    std::vector<VkWriteDescriptorSet> graphicsWrites;
    std::vector<VkWriteDescriptorSet> computeWrites;
    VkExtent2D computeExtent{1, 1};
    std::vector<VkBuffer> vertexBuffers;
    std::vector<VkDeviceSize> vertexOffsets;
    VkBuffer indexBuffer = VK_NULL_HANDLE;
    VkBuffer indirectBuffer = VK_NULL_HANDLE;
    OwnedBuffer sink;  ///< Destination of Transfer reads; written once a frame, never read.
    /// A pass without attachments that draws: its own framebuffer (no attachments either).
    owned::Framebuffer framebuffer;
    VkExtent2D extent{0, 0};
};

/// Everything createPipelines makes: the program, its pipelines and what recording binds.
struct GenericPass::Built {
    GenericProgram program;
    bool executorRenderPass = false;  ///< The pass has attachments: it draws in the executor's.
    owned::RenderPass ownRenderPass;     ///< Draws without attachments: a render pass without any.
    PipelineObjects graphics, compute;
    PFN_vkCmdPushDescriptorSetKHR pushDescriptors = nullptr;
    owned::Sampler sampler;  ///< Nearest, clamp to edge: sampled reads take texels as they are.
    /// Views of one mip level for storage images bound per level, by image, type and range.
    std::map<std::tuple<VkImage, VkImageViewType, uint32_t, uint32_t, uint32_t>, owned::ImageView> levelViews;
    std::vector<VkDeviceSize> transferOffsets;  ///< Per transfer usage, into source and sink.
    std::vector<std::vector<VkBufferImageCopy>> transferRegions;  ///< Per transfer usage of an image.
    VkDeviceSize transferBytes = 0;
    OwnedBuffer source;  ///< Host-filled contents of Transfer writes; read-only on the GPU.
    std::vector<Slot> slots;

    /// Where each transfer's bytes lie in the scratch buffers (sizes depend on the output
    /// extent), the copy regions of images, and the source filled with the pass's value.
    void buildTransfers(const PipelineContext& ctx);

    VkImageView levelView(VkDevice device, const BoundResource& r, VkImageViewType type, uint32_t level) {
        const SubresourceRange& range = r.usage->range;
        const auto key = std::make_tuple(r.image, type, range.baseMip + level, range.baseLayer, range.layerCount);
        if (auto it = levelViews.find(key); it != levelViews.end()) return it->second.get();
        const FormatInfo& f = r.desc->format;  // shaders read one aspect: depth of depth/stencil
        VkImageViewCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        ci.image = r.image;
        ci.viewType = type;
        ci.format = r.format;
        ci.subresourceRange = {detail::copyAspectOf(f), range.baseMip + level, 1, range.baseLayer, range.layerCount};
        VkImageView v;
        vk::check(vkCreateImageView(device, &ci, nullptr, &v), "vkCreateImageView");
        levelViews.emplace(key, owned::ImageView(device, v));
        return v;
    }
};

GenericPass::GenericPass(const PassDesc& desc) : params_(parseGenericParams(desc, desc.type == "Generic")) {}

GenericPass::~GenericPass() = default;

namespace {

/// Whether a logic op combines with an attachment of this format: integer and normalized
/// integer ones (the spec's "Logical Operations"; float and sRGB ones are written as they are).
bool takesLogicOp(VkFormat format) {
    const std::optional<FormatInfo> f = findFormat(format);
    if (!f || f->isDepthStencil()) return false;
    const bool normalized = f->name.find("UNORM") != std::string_view::npos || f->name.find("SNORM") != std::string_view::npos;
    return !detail::scalarPrefix(format).empty() || (normalized && !f->srgb);
}

GraphicsPipeline graphicsPipeline(const PipelineContext& ctx, const GenericProgram& p, VkRenderPass renderPass) {
    const std::string label(ctx.pass->name);
    GraphicsPipelineRecipe recipe;
    recipe.bindings = layoutBindings(p.graphicsBindings);
    recipe.pushConstantBytes = 16;
    recipe.vertex = ctx.shaders->compile(VK_SHADER_STAGE_VERTEX_BIT, p.vertexSource, label + ".vert");
    recipe.fragment = ctx.shaders->compile(VK_SHADER_STAGE_FRAGMENT_BIT, p.fragmentSource, label + ".frag");
    recipe.renderPass = renderPass;
    for (uint32_t i = 0; i < p.vertexBuffers.size(); ++i) {
        recipe.vertexBindings.push_back({i, 4, VK_VERTEX_INPUT_RATE_VERTEX});
        recipe.vertexAttributes.push_back({i, i, VK_FORMAT_R32_SFLOAT, 0});
    }
    if (p.depth >= 0) {
        const BoundResource& d = ctx.resources[size_t(p.depth)];
        const bool hasDepth = d.desc->format.hasDepth;
        // The test always passes so that colors do not depend on earlier depth values,
        // but it is enabled: the attachment is really read (and written unless Read).
        recipe.depthTest = hasDepth;
        recipe.depthWrite = hasDepth && writesContents(d.usage->usage.access);
        recipe.depthCompare = VK_COMPARE_OP_ALWAYS;
    }
    // ReadWrite reads the attachment: by additive blending where the device blends its
    // format, else (integer formats; SNORM ones on lavapipe) by a logical XOR where the device
    // has logicOp. A logic op turns blending off for the whole subpass, so it is taken only when
    // every ReadWrite attachment of the pass takes it too; otherwise the attachments that cannot
    // blend are only written. A Read is read by the load op alone.
    const auto blends = [&](const BoundResource& r) {
        VkFormatProperties properties{};
        vkGetPhysicalDeviceFormatProperties(ctx.physicalDevice, r.format, &properties);
        return (properties.optimalTilingFeatures & VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT) != 0;
    };
    VkPhysicalDeviceFeatures features{};
    vkGetPhysicalDeviceFeatures(ctx.physicalDevice, &features);  // the device enables logicOp where it has it
    bool anyUnblendable = false, allTakeLogicOp = true;
    for (uint32_t c : p.colors) {
        const BoundResource& r = ctx.resources[c];
        if (r.usage->usage.access != Access::ReadWrite) continue;
        anyUnblendable |= !blends(r);
        allTakeLogicOp &= takesLogicOp(r.format);
    }
    const bool logicOp = anyUnblendable && allTakeLogicOp && features.logicOp;
    if (logicOp) recipe.logicOp = VK_LOGIC_OP_XOR;
    for (uint32_t c : p.colors) {
        const BoundResource& r = ctx.resources[c];
        VkPipelineColorBlendAttachmentState b{};
        // A Read has no output in the fragment shader (generic_program.cpp): nothing to write.
        const Access access = r.usage->usage.access;
        b.colorWriteMask = access == Access::Read ? 0 : 0xf;
        if (!logicOp && access == Access::ReadWrite && blends(r)) {
            b.blendEnable = VK_TRUE;
            b.srcColorBlendFactor = b.dstColorBlendFactor = VK_BLEND_FACTOR_ONE;
            b.srcAlphaBlendFactor = b.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
            b.colorBlendOp = b.alphaBlendOp = VK_BLEND_OP_ADD;
        }
        recipe.blends.push_back(b);
    }
    recipe.colorAttachments = static_cast<uint32_t>(recipe.blends.size());
    return createGraphicsPipeline(ctx.device, recipe);
}

ComputePipeline computePipeline(const PipelineContext& ctx, const GenericProgram& p) {
    ComputePipelineRecipe recipe;
    recipe.bindings = layoutBindings(p.computeBindings);
    recipe.pushConstantBytes = 16;
    recipe.compute = ctx.shaders->compile(VK_SHADER_STAGE_COMPUTE_BIT, p.computeSource, std::string(ctx.pass->name) + ".comp");
    return createComputePipeline(ctx.device, recipe);
}

owned::RenderPass renderPassWithoutAttachments(VkDevice device) {
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    VkRenderPassCreateInfo rpci{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    rpci.subpassCount = 1;
    rpci.pSubpasses = &sub;
    VkRenderPass rp;
    vk::check(vkCreateRenderPass(device, &rpci, nullptr, &rp), "vkCreateRenderPass");
    return owned::RenderPass(device, rp);
}

owned::Sampler nearestSampler(VkDevice device) {
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
    sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    sci.maxLod = VK_LOD_CLAMP_NONE;
    VkSampler sampler;
    vk::check(vkCreateSampler(device, &sci, nullptr, &sampler), "vkCreateSampler");
    return owned::Sampler(device, sampler);
}

/// Generic binds every shader usage of a pass in one push-descriptor set per pipeline, so a
/// pass of many usages can pass what the device allows: refused here by name, where a driver
/// would be handed a layout the spec makes undefined.
void checkDescriptorLimits(VkPhysicalDevice physical, const PlannedPass& pass, const GenericProgram& p) {
    VkPhysicalDevicePushDescriptorPropertiesKHR push{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PUSH_DESCRIPTOR_PROPERTIES_KHR};
    VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    properties.pNext = &push;
    vkGetPhysicalDeviceProperties2(physical, &properties);
    const VkPhysicalDeviceLimits& limits = properties.properties.limits;
    const auto refuse = [&](uint32_t count, const char* what, uint32_t most, const char* limit) {
        if (count <= most) return;
        throw ExecutorError(passError(pass, "", "binds " + std::to_string(count) + " " + what + ", and the device '" +
                                                    properties.properties.deviceName + "' allows " +
                                                    std::to_string(most) + " (" + limit + ")"));
    };
    for (const auto* set : {&p.graphicsBindings, &p.computeBindings}) {
        uint32_t descriptors = 0;
        for (const ShaderBinding& s : *set) descriptors += s.levels;
        refuse(descriptors, "descriptors in one set", push.maxPushDescriptors, "maxPushDescriptors");
        for (const VkShaderStageFlagBits stage :
             {VK_SHADER_STAGE_VERTEX_BIT, VK_SHADER_STAGE_FRAGMENT_BIT, VK_SHADER_STAGE_COMPUTE_BIT}) {
            uint32_t counts[4] = {};  // per BindKind
            for (const ShaderBinding& s : *set)
                if (s.stage == stage) counts[size_t(s.kind)] += s.levels;
            // A combined image sampler counts as a sampler and as a sampled image.
            refuse(counts[size_t(BindKind::SampledImage)], "sampled images in one stage",
                   std::min(limits.maxPerStageDescriptorSamplers, limits.maxPerStageDescriptorSampledImages),
                   "maxPerStageDescriptorSamplers, maxPerStageDescriptorSampledImages");
            refuse(counts[size_t(BindKind::StorageImage)], "storage image views in one stage",
                   limits.maxPerStageDescriptorStorageImages, "maxPerStageDescriptorStorageImages");
            refuse(counts[size_t(BindKind::StorageBuffer)], "storage buffers in one stage",
                   limits.maxPerStageDescriptorStorageBuffers, "maxPerStageDescriptorStorageBuffers");
            refuse(counts[size_t(BindKind::UniformBuffer)], "uniform buffers in one stage",
                   limits.maxPerStageDescriptorUniformBuffers, "maxPerStageDescriptorUniformBuffers");
        }
    }
}

}  // namespace

void GenericPass::createPipelines(const PipelineContext& ctx) {
    auto b = std::make_unique<Built>();
    const PlannedPass& pass = *ctx.pass;
    b->program = buildGenericProgram(pass, ctx.resources, params_, hasShaderOutputLayer(ctx.physicalDevice));
    const GenericProgram& p = b->program;
    checkDescriptorLimits(ctx.physicalDevice, pass, p);
    b->executorRenderPass = ctx.renderPass != VK_NULL_HANDLE;
    if (p.graphics) {
        if (!b->executorRenderPass) b->ownRenderPass = renderPassWithoutAttachments(ctx.device);
        b->graphics = graphicsPipeline(ctx, p, b->executorRenderPass ? ctx.renderPass : b->ownRenderPass.get());
    }
    if (p.compute) b->compute = computePipeline(ctx, p);
    if (!p.graphicsBindings.empty() || !p.computeBindings.empty()) b->pushDescriptors = pushDescriptorFunction(ctx.device);
    const auto sampled = [](const ShaderBinding& s) { return s.kind == BindKind::SampledImage; };
    if (std::any_of(p.graphicsBindings.begin(), p.graphicsBindings.end(), sampled) ||
        std::any_of(p.computeBindings.begin(), p.computeBindings.end(), sampled))
        b->sampler = nearestSampler(ctx.device);
    b->buildTransfers(ctx);

    b->slots.resize(ctx.frameSlots.size());
    for (size_t slot = 0; slot < ctx.frameSlots.size(); ++slot) {
        const std::span<const BoundResource> resources = ctx.frameSlots[slot];
        Slot& sl = b->slots[slot];
        if (b->transferBytes > 0) sl.sink = makeBuffer(ctx, b->transferBytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, false);

        size_t imageDescriptors = 0;  // reserved up front: the writes point into imageInfos
        for (const auto* list : {&p.graphicsBindings, &p.computeBindings})
            for (const ShaderBinding& s : *list) imageDescriptors += s.levels;
        sl.imageInfos.reserve(imageDescriptors);
        sl.bufferInfos.reserve(p.graphicsBindings.size() + p.computeBindings.size());
        auto writeFor = [&](const ShaderBinding& s) {
            const BoundResource& r = resources[s.usage];
            VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            w.dstBinding = s.binding;
            w.descriptorCount = 1;
            switch (s.kind) {
                case BindKind::SampledImage:
                case BindKind::StorageImage: {
                    // The bound view covers exactly the usage; a storage view addresses one
                    // level, so a storage usage of several levels binds one view per level.
                    const bool isSampled = s.kind == BindKind::SampledImage;
                    const size_t first = sl.imageInfos.size();
                    if (isSampled || s.levels == 1) {
                        sl.imageInfos.push_back({isSampled ? b->sampler.get() : VK_NULL_HANDLE, r.view, r.usage->layout});
                    } else {
                        for (uint32_t level = 0; level < s.levels; ++level)
                            sl.imageInfos.push_back(
                                {VK_NULL_HANDLE, b->levelView(ctx.device, r, s.viewType, level), r.usage->layout});
                    }
                    w.descriptorCount = uint32_t(sl.imageInfos.size() - first);
                    w.descriptorType =
                        isSampled ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER : VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
                    w.pImageInfo = &sl.imageInfos[first];
                    break;
                }
                case BindKind::StorageBuffer:
                case BindKind::UniformBuffer: {
                    const bool uniform = s.kind == BindKind::UniformBuffer;
                    sl.bufferInfos.push_back({r.buffer, 0, uniform ? VkDeviceSize(s.uniformVec4s) * 16 : VK_WHOLE_SIZE});
                    w.descriptorType = uniform ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
                    w.pBufferInfo = &sl.bufferInfos.back();
                    break;
                }
            }
            return w;
        };
        for (const auto& s : p.graphicsBindings) sl.graphicsWrites.push_back(writeFor(s));
        for (const auto& s : p.computeBindings) sl.computeWrites.push_back(writeFor(s));

        for (uint32_t v : p.vertexBuffers) {
            sl.vertexBuffers.push_back(resources[v].buffer);
            sl.vertexOffsets.push_back(0);
        }
        if (p.indexBuffer >= 0) {
            const BoundResource& r = resources[size_t(p.indexBuffer)];
            if (r.size < 12) throw ExecutorError(passError(pass, r.desc->name, "index buffer smaller than 12 bytes"));
            sl.indexBuffer = r.buffer;
        }
        if (p.indirectBuffer >= 0) {
            const BoundResource& r = resources[size_t(p.indirectBuffer)];
            if (r.size < 20) throw ExecutorError(passError(pass, r.desc->name, "indirect buffer smaller than 20 bytes"));
            sl.indirectBuffer = r.buffer;
        }
        bool anyCompute = false;
        sl.computeExtent = bindingExtent(p.computeBindings, resources, anyCompute);

        if (p.graphics && !b->executorRenderPass) {
            // Sized by what the draw writes, else the output.
            bool any = false;
            sl.extent = bindingExtent(p.graphicsBindings, resources, any);
            if (!any) sl.extent = ctx.outputExtent;
            VkFramebufferCreateInfo fci{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
            fci.renderPass = b->ownRenderPass.get();
            fci.width = sl.extent.width;
            fci.height = sl.extent.height;
            fci.layers = p.attachmentLayers;
            VkFramebuffer fb;
            vk::check(vkCreateFramebuffer(ctx.device, &fci, nullptr, &fb), "vkCreateFramebuffer");
            sl.framebuffer = owned::Framebuffer(ctx.device, fb);
        }
    }
    built_ = std::move(b);
}

void GenericPass::Built::buildTransfers(const PipelineContext& ctx) {
    const GenericProgram& p = program;
    for (uint32_t t : p.transfers) {
        const BoundResource& r = ctx.resources[t];
        const SubresourceRange& range = r.usage->range;
        transferOffsets.push_back(transferBytes);
        VkDeviceSize bytes = r.size;
        std::vector<VkBufferImageCopy> regions;
        if (r.desc->isImage()) {
            bytes = 0;
            const uint32_t texel = detail::copyTexelBytes(r.desc->format);
            if (texel == 0) throw ExecutorError(passError(*ctx.pass, r.desc->name, "format cannot be copied"));
            for (uint32_t m = range.baseMip; m < range.baseMip + range.mipCount; ++m) {
                VkBufferImageCopy c{};
                c.bufferOffset = transferBytes + bytes;
                c.imageSubresource = {detail::copyAspectOf(r.desc->format), m, range.baseLayer, range.layerCount};
                c.imageExtent = {mipSize(r.extent.width, range.baseMip, m), mipSize(r.extent.height, range.baseMip, m), 1};
                regions.push_back(c);
                bytes += VkDeviceSize(c.imageExtent.width) * c.imageExtent.height * texel * range.layerCount;
            }
        }
        transferRegions.push_back(std::move(regions));
        transferBytes += (bytes + 15) & ~VkDeviceSize(15);
    }
    if (transferBytes == 0) return;
    source = makeBuffer(ctx, transferBytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
    auto* bytes = static_cast<uint8_t*>(source.mapped);
    for (size_t i = 0; i < p.transfers.size(); ++i) {
        const BoundResource& r = ctx.resources[p.transfers[i]];
        const VkDeviceSize begin = transferOffsets[i];
        const VkDeviceSize end = i + 1 < p.transfers.size() ? transferOffsets[i + 1] : transferBytes;
        if (r.desc->isImage()) {
            const uint32_t texel = detail::copyTexelBytes(r.desc->format);
            const auto t = detail::encodeTexel(r.format, texel, p.color);
            for (VkDeviceSize o = begin; o + texel <= end; o += texel) std::memcpy(bytes + o, t.data(), texel);
        } else {
            detail::fillBufferPattern(bytes + begin, end - begin, p.color[0]);
        }
    }
}

void GenericPass::recordCopiesAndDispatch(const RecordContext& ctx, const Slot& sl) const {
    const Built& b = *built_;
    const GenericProgram& p = b.program;
    if (!p.transfers.empty()) {
        // Out of each read into the slot's sink, then into each write from the source. A
        // ReadWrite copy's two halves are ordered by the plan's in-pass barriers, between them.
        for (const bool writing : {false, true}) {
            if (writing) ctx.recordInPassBarriers();
            for (size_t t = 0; t < p.transfers.size(); ++t) {
                const BoundResource& r = ctx.resources[p.transfers[t]];
                const PlannedUsage& u = *r.usage;
                if (writing ? !writesContents(u.usage.access) : !readsContents(u.usage.access)) continue;
                const VkDeviceSize offset = b.transferOffsets[t];
                const VkBuffer scratch = writing ? b.source.buffer.get() : sl.sink.buffer.get();
                if (!r.desc->isImage()) {
                    const VkBufferCopy region = writing ? VkBufferCopy{offset, 0, r.size} : VkBufferCopy{0, offset, r.size};
                    if (writing) vkCmdCopyBuffer(ctx.cmd, scratch, r.buffer, 1, &region);
                    else vkCmdCopyBuffer(ctx.cmd, r.buffer, scratch, 1, &region);
                    continue;
                }
                const std::vector<VkBufferImageCopy>& regions = b.transferRegions[t];
                const auto n = static_cast<uint32_t>(regions.size());
                if (writing) vkCmdCopyBufferToImage(ctx.cmd, scratch, r.image, u.layout, n, regions.data());
                else vkCmdCopyImageToBuffer(ctx.cmd, r.image, u.layout, scratch, n, regions.data());
            }
        }
    }
    if (p.compute) {
        const VkPipelineLayout layout = b.compute.layout.get();
        vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, b.compute.pipeline.get());
        if (!sl.computeWrites.empty())
            b.pushDescriptors(ctx.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, uint32_t(sl.computeWrites.size()),
                              sl.computeWrites.data());
        const uint32_t extent[4] = {sl.computeExtent.width, sl.computeExtent.height, 0, 0};
        vkCmdPushConstants(ctx.cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof extent, extent);
        vkCmdDispatch(ctx.cmd, (sl.computeExtent.width + 7) / 8, (sl.computeExtent.height + 7) / 8, 1);
    }
}

void GenericPass::recordDraw(const RecordContext& ctx, const Slot& sl, VkExtent2D area) const {
    const Built& b = *built_;
    const GenericProgram& p = b.program;
    const VkPipelineLayout layout = b.graphics.layout.get();
    vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, b.graphics.pipeline.get());
    if (!sl.graphicsWrites.empty())
        b.pushDescriptors(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, uint32_t(sl.graphicsWrites.size()),
                          sl.graphicsWrites.data());
    const uint32_t extent[4] = {area.width, area.height, 0, 0};
    vkCmdPushConstants(ctx.cmd, layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof extent,
                       extent);
    if (!sl.vertexBuffers.empty())
        vkCmdBindVertexBuffers(ctx.cmd, 0, uint32_t(sl.vertexBuffers.size()), sl.vertexBuffers.data(),
                               sl.vertexOffsets.data());
    if (sl.indexBuffer) vkCmdBindIndexBuffer(ctx.cmd, sl.indexBuffer, 0, VK_INDEX_TYPE_UINT32);
    // Buffers Generic writes hold one draw command at offset 0 (the buffer pattern).
    if (sl.indirectBuffer && sl.indexBuffer)
        vkCmdDrawIndexedIndirect(ctx.cmd, sl.indirectBuffer, 0, 1, sizeof(VkDrawIndexedIndirectCommand));
    else if (sl.indirectBuffer)
        vkCmdDrawIndirect(ctx.cmd, sl.indirectBuffer, 0, 1, sizeof(VkDrawIndirectCommand));
    else if (sl.indexBuffer)
        vkCmdDrawIndexed(ctx.cmd, 3, p.attachmentLayers, 0, 0, 0);
    else
        vkCmdDraw(ctx.cmd, 3, p.attachmentLayers, 0, 0);
}

void GenericPass::recordBeforeRenderPass(const RecordContext& ctx) {
    recordCopiesAndDispatch(ctx, built_->slots.at(ctx.frameSlot));
}

void GenericPass::record(const RecordContext& ctx) {
    const Built& b = *built_;
    const Slot& sl = b.slots.at(ctx.frameSlot);
    if (b.executorRenderPass) {
        recordDraw(ctx, sl, ctx.renderArea);
        return;
    }
    recordCopiesAndDispatch(ctx, sl);
    if (!b.program.graphics) return;
    // A draw without attachments, in the pass's own render pass: nothing of the plan is in it.
    VkRenderPassBeginInfo rbi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    rbi.renderPass = b.ownRenderPass.get();
    rbi.framebuffer = sl.framebuffer.get();
    rbi.renderArea = {{0, 0}, sl.extent};
    vkCmdBeginRenderPass(ctx.cmd, &rbi, VK_SUBPASS_CONTENTS_INLINE);
    setViewportAndScissor(ctx.cmd, sl.extent);
    recordDraw(ctx, sl, sl.extent);
    vkCmdEndRenderPass(ctx.cmd);
}

GenericHandles GenericPass::handles(uint32_t frameSlot) const {
    if (!built_) throw std::out_of_range("GenericPass::handles before createPipelines");
    const Built& b = *built_;
    const GenericProgram& p = b.program;
    const Slot& sl = b.slots.at(frameSlot);
    GenericHandles h;
    if (p.graphics) {
        h.graphicsPipeline = b.graphics.pipeline.get();
        h.graphicsLayout = b.graphics.layout.get();
        h.graphicsWrites = sl.graphicsWrites;
        h.instances = p.attachmentLayers;
    }
    if (p.compute) {
        h.computePipeline = b.compute.pipeline.get();
        h.computeLayout = b.compute.layout.get();
        h.computeWrites = sl.computeWrites;
        h.computeExtent = sl.computeExtent;
    }
    h.recordsMore = !p.transfers.empty() || !p.vertexBuffers.empty() || p.indexBuffer >= 0 || p.indirectBuffer >= 0 ||
                    (p.graphics && !b.executorRenderPass);
    return h;
}

std::unique_ptr<PassImplementation> makeGenericPass(const PassDesc& desc) { return std::make_unique<GenericPass>(desc); }

}  // namespace skygraph::passes
