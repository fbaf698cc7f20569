// The Renderer: resources, pipelines and per-frame recording of one plan.
#include "generic_program.hpp"
#include <skygraph/shader_compiler.hpp>
#include "vk_util.hpp"

#include <skygraph/executor.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/pipeline_builder.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <tuple>

namespace skygraph {
namespace {

constexpr uint64_t kWaitForever = std::numeric_limits<uint64_t>::max();

std::string passError(const PlannedPass& pass, const std::string& resource, const std::string& what) {
    std::string s = "pass '" + pass.name + "'";
    if (!resource.empty()) s += ", resource '" + resource + "'";
    return s + ": " + what;
}

VkImageAspectFlags aspectOf(const FormatInfo& f) {
    if (!f.isDepthStencil()) return VK_IMAGE_ASPECT_COLOR_BIT;
    VkImageAspectFlags a = 0;
    if (f.hasDepth) a |= VK_IMAGE_ASPECT_DEPTH_BIT;
    if (f.hasStencil) a |= VK_IMAGE_ASPECT_STENCIL_BIT;
    return a;
}

/// Aspect for buffer<->image copies: one aspect only (depth for depth formats).
VkImageAspectFlags copyAspectOf(const FormatInfo& f) {
    if (!f.isDepthStencil()) return VK_IMAGE_ASPECT_COLOR_BIT;
    return f.hasDepth ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_STENCIL_BIT;
}

uint32_t copyTexelBytes(const FormatInfo& f) {
    if (!f.isDepthStencil()) return f.bytesPerTexel;
    switch (f.format) {
        case VK_FORMAT_D16_UNORM: case VK_FORMAT_D16_UNORM_S8_UINT: return 2;
        case VK_FORMAT_S8_UINT: return 1;
        default: return 4;  // D32, D24 (packed in 4 bytes), X8_D24
    }
}

BindAs resolveAs(const ResourceDesc& r, const Usage& u) {
    if (u.as != BindAs::Default) return u.as;
    if (!r.isImage()) return BindAs::Storage;
    return u.access == Access::Read ? BindAs::Sampled : BindAs::Storage;
}

float halfToFloat(uint16_t h) {
    const uint32_t sign = (h & 0x8000u) << 16;
    const uint32_t exp = (h >> 10) & 0x1fu;
    const uint32_t mant = h & 0x3ffu;
    uint32_t bits;
    if (exp == 0) {
        if (mant == 0) {
            bits = sign;
        } else {
            float v = std::ldexp(static_cast<float>(mant), -24);
            return (h & 0x8000u) ? -v : v;
        }
    } else if (exp == 31) {
        bits = sign | 0x7f800000u | (mant << 13);
    } else {
        bits = sign | ((exp + 112) << 23) | (mant << 13);
    }
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

/// A buffer with its memory; mapped when host-visible.
struct OwnedBuffer {
    vk::Buffer buffer;
    vk::Memory memory;
    void* mapped = nullptr;
    VkDeviceSize size = 0;
};

struct ImageCopy {
    vk::Image image;
    vk::Memory memory;
    std::map<std::tuple<int, uint32_t, uint32_t, uint32_t, uint32_t>, vk::ImageView> views;
};

/// One plan resource: its description and one or N (per frame slot) Vulkan copies.
struct ResourceState {
    const ResourceDesc* desc = nullptr;
    bool isImage = false;
    bool perSlot = false;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkImageAspectFlags aspect = 0;
    uint32_t width = 1, height = 1, mips = 1, layers = 1;
    VkDeviceSize size = 0;
    VkImageUsageFlags imageUsage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    VkBufferUsageFlags bufferUsage =
        VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    std::vector<ImageCopy> images;
    std::vector<OwnedBuffer> buffers;

    [[nodiscard]] uint32_t copyFor(uint32_t slot) const { return perSlot ? slot : 0; }
    [[nodiscard]] uint32_t mipWidth(uint32_t mip) const { return std::max(1u, width >> mip); }
    [[nodiscard]] uint32_t mipHeight(uint32_t mip) const { return std::max(1u, height >> mip); }
};

/// Per pass and frame slot: everything recording needs, with handles resolved.
struct PassSlot {
    vk::Framebuffer framebuffer;
    VkExtent2D extent{1, 1};
    VkExtent2D computeExtent{1, 1};
    std::vector<VkDescriptorImageInfo> imageInfos;
    std::vector<VkDescriptorBufferInfo> bufferInfos;
    std::vector<VkWriteDescriptorSet> graphicsWrites;
    std::vector<VkWriteDescriptorSet> computeWrites;
    std::vector<VkImageMemoryBarrier2> imageBarriers;
    std::vector<VkBufferMemoryBarrier2> bufferBarriers;
    std::vector<VkMemoryBarrier2> memoryBarriers;
    std::vector<VkBuffer> vertexBuffers;
    std::vector<VkDeviceSize> vertexOffsets;
    VkBuffer indexBuffer = VK_NULL_HANDLE;
    VkBuffer indirectBuffer = VK_NULL_HANDLE;
    OwnedBuffer sink;  ///< Destination of Transfer reads.
    std::vector<BoundResource> bound;  ///< Pass implementations: parallel to pass usages.
};

struct PassState {
    const PlannedPass* pass = nullptr;
    const PassDesc* desc = nullptr;
    bool isClear = false;
    /// Recording code from the PassLibrary; null for Generic (and types run as Generic).
    std::unique_ptr<PassImplementation> custom;
    GenericProgram program;
    vk::RenderPass renderPass;
    std::vector<VkClearValue> clearValues;
    vk::SetLayout graphicsSetLayout, computeSetLayout;
    vk::PipelineLayout graphicsLayout, computeLayout;
    vk::Pipeline graphicsPipeline, computePipeline;
    std::vector<VkDeviceSize> transferOffsets;  ///< Per transfer usage, into source and sink.
    VkDeviceSize transferBytes = 0;
    OwnedBuffer source;  ///< Host-filled contents of Transfer writes; read-only on the GPU.
    std::vector<PassSlot> slots;
};

struct FinalSlot {
    std::vector<VkImageMemoryBarrier2> imageBarriers;
    std::vector<VkBufferMemoryBarrier2> bufferBarriers;
    std::vector<VkMemoryBarrier2> memoryBarriers;
};

/// Everything that belongs to one plan; replaced whole by setPlan.
struct PlanState {
    GraphDesc graph;
    Plan plan;
    std::vector<ResourceState> resources;  ///< Parallel to plan.resources.
    std::vector<PassState> passes;         ///< Parallel to plan.passes.
    std::vector<FinalSlot> finals;         ///< Per slot.
    int32_t readbackResource = -1;
    std::vector<OwnedBuffer> readbackBuffers;  ///< Per slot.
};

struct FrameSlot {
    vk::CommandPool pool;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    vk::Fence fence;
    vk::QueryPool queries;
    uint32_t queryCount = 0;
    bool submitted = false;
    bool timingsPending = false;
    std::vector<std::string> passNames;  ///< Of the frame last recorded in this slot.
};

}  // namespace

struct Renderer::Impl {
    Device& device;
    Device::Impl& dev;
    VkDevice vkd;
    RendererOptions options;
    ShaderCompiler shaders;
    vk::Sampler sampler;
    vk::Sampler linearSampler;  ///< For pass implementations: trilinear, clamp.
    vk::Sampler repeatSampler;  ///< Trilinear, repeat U, clamp V (equirect).
    FrameData frameData;
    /// Pixels given to setExternalImage, by resource name; uploaded on every import.
    std::map<std::string, ImageData> uploads;
    bool layered = false;
    std::unique_ptr<PlanState> state;
    std::vector<FrameSlot> frames;
    uint64_t frameIndex = 0;
    int64_t lastSlot = -1;
    std::vector<PassTiming> timings;

    Impl(Device& d, RendererOptions o)
        : device(d), dev(d.impl()), vkd(d.device()), options(std::move(o)),
          shaders(options.shaderDir) {}

    // --- helpers -------------------------------------------------------------------------

    OwnedBuffer makeBuffer(VkDeviceSize size, VkBufferUsageFlags usage, bool hostVisible) {
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

    VkImageView view(ResourceState& r, uint32_t copy, VkImageViewType type,
                     const SubresourceRange& range, bool attachment) {
        ImageCopy& img = r.images[copy];
        const auto key = std::make_tuple(static_cast<int>(type) + (attachment ? 100 : 0), range.baseMip,
                                         range.mipCount, range.baseLayer, range.layerCount);
        if (auto it = img.views.find(key); it != img.views.end()) return it->second.get();
        VkImageViewCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        ci.image = img.image.get();
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

    // --- building a plan -----------------------------------------------------------------

    std::unique_ptr<PlanState> build(const GraphDesc& graph, Plan plan) {
        auto s = std::make_unique<PlanState>();
        s->graph = graph;
        s->plan = std::move(plan);
        describeResources(*s);
        for (size_t i = 0; i < s->plan.passes.size(); ++i) buildPassStatic(*s, i);
        buildSized(*s);
        for (PassState& ps : s->passes) {
            if (!ps.custom) continue;
            PipelineContext pc;
            pc.device = vkd;
            pc.physicalDevice = dev.physical;
            pc.renderPass = ps.renderPass.get();
            pc.pass = ps.pass;
            pc.desc = ps.desc;
            pc.resources = ps.slots[0].bound;
            pc.shaders = &shaders;
            try {
                ps.custom->createPipelines(pc);
            } catch (const ExecutorError&) {
                throw;
            } catch (const std::exception& e) {
                throw ExecutorError(passError(*ps.pass, "", std::string("creating pipelines: ") + e.what()));
            }
        }
        return s;
    }

    void describeResources(PlanState& s) {
        const uint32_t slots = options.framesInFlight;
        s.resources.resize(s.plan.resources.size());
        for (size_t i = 0; i < s.plan.resources.size(); ++i) {
            const PlannedResource& pr = s.plan.resources[i];
            if (pr.decl >= s.graph.resources.size())
                throw ExecutorError("plan resource '" + pr.name + "' is not in the graph");
            ResourceState& r = s.resources[i];
            r.desc = &s.graph.resources[pr.decl];
            r.isImage = r.desc->isImage();
            // Transients get one copy per frame slot; so does the swapchain target, like the
            // images of a real swapchain. Other externals persist and are shared.
            // Externals that the graph writes without exporting them have no cross-frame edge
            // in the plan; a copy per slot keeps frames in flight apart (slot reuse waits on
            // its fence).
            bool written = false;
            for (const PlannedPass& pass : s.plan.passes)
                for (const PlannedUsage& u : pass.usages)
                    written = written || (u.resource == i && writesContents(u.usage.access));
            const bool unexportedWrite = r.desc->external && !r.desc->isExported() && written;
            r.perSlot = (!r.desc->external || r.desc->final == ExternalState::Present || unexportedWrite) &&
                        slots > 1;
            if (unexportedWrite && r.isImage && pr.initialLayout != VK_IMAGE_LAYOUT_UNDEFINED &&
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
        for (size_t i = 0; i < s.plan.resources.size(); ++i) {
            for (const VkImageLayout l : {s.plan.resources[i].initialLayout, s.plan.resources[i].finalLayout}) {
                if (l == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL) s.resources[i].imageUsage |= VK_IMAGE_USAGE_SAMPLED_BIT;
                if (l == VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL) s.resources[i].imageUsage |= VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
            }
        }
        for (const PlannedPass& pass : s.plan.passes) {
            for (const PlannedUsage& u : pass.usages) {
                if (u.resource >= s.resources.size())
                    throw ExecutorError(passError(pass, "", "usage refers to an unknown resource"));
                ResourceState& r = s.resources[u.resource];
                const BindAs as = resolveAs(*r.desc, u.usage);
                switch (u.usage.stage) {
                    case Stage::ColorAttachment: r.imageUsage |= VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT; break;
                    case Stage::DepthAttachment: r.imageUsage |= VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT; break;
                    case Stage::Vertex: case Stage::Fragment: case Stage::Compute:
                        if (as == BindAs::Sampled) r.imageUsage |= VK_IMAGE_USAGE_SAMPLED_BIT;
                        else if (as == BindAs::Uniform) r.bufferUsage |= VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT;
                        else {
                            r.imageUsage |= VK_IMAGE_USAGE_STORAGE_BIT;
                            r.bufferUsage |= VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
                        }
                        break;
                    case Stage::VertexInput:
                        r.bufferUsage |= as == BindAs::Index ? VK_BUFFER_USAGE_INDEX_BUFFER_BIT
                                                             : VK_BUFFER_USAGE_VERTEX_BUFFER_BIT;
                        break;
                    case Stage::Indirect: r.bufferUsage |= VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT; break;
                    case Stage::Transfer: break;
                }
            }
        }
    }

    void buildPassStatic(PlanState& s, size_t index) {
        const PlannedPass& pass = s.plan.passes[index];
        PassState ps;
        ps.pass = &pass;
        ps.isClear = pass.type == "Clear" && pass.declIndex < 0;
        if (ps.isClear) {
            for (const PlannedUsage& u : pass.usages) {
                const ResourceState& r = s.resources[u.resource];
                if (!r.isImage || !r.desc->clear)
                    throw ExecutorError(passError(pass, r.desc->name, "clear pass on a resource without `clear`"));
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

    static std::vector<VkDescriptorSetLayoutBinding> layoutBindings(const std::vector<ShaderBinding>& bindings) {
        std::vector<VkDescriptorSetLayoutBinding> b;
        for (const auto& sb : bindings) {
            VkDescriptorSetLayoutBinding lb{};
            lb.binding = sb.binding;
            lb.descriptorCount = 1;
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

    static VkAttachmentLoadOp loadOp(LoadOp op) {
        switch (op) {
            case LoadOp::Load: return VK_ATTACHMENT_LOAD_OP_LOAD;
            case LoadOp::Clear: return VK_ATTACHMENT_LOAD_OP_CLEAR;
            case LoadOp::DontCare: return VK_ATTACHMENT_LOAD_OP_DONT_CARE;
        }
        return VK_ATTACHMENT_LOAD_OP_LOAD;
    }
    static VkAttachmentStoreOp storeOp(StoreOp op) {
        switch (op) {
            case StoreOp::Store: return VK_ATTACHMENT_STORE_OP_STORE;
            case StoreOp::DontCare: return VK_ATTACHMENT_STORE_OP_DONT_CARE;
            case StoreOp::None: return VK_ATTACHMENT_STORE_OP_NONE;
        }
        return VK_ATTACHMENT_STORE_OP_STORE;
    }

    void buildGraphics(PlanState& s, PassState& ps) {
        buildRenderPass(s, ps);
        buildGraphicsPipeline(s, ps);
    }

    void buildRenderPass(PlanState& s, PassState& ps) {
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

    void buildGraphicsPipeline(PlanState& s, PassState& ps) {
        const PlannedPass& pass = *ps.pass;
        const GenericProgram& p = ps.program;
        GraphicsPipelineRecipe recipe;
        recipe.bindings = layoutBindings(p.graphicsBindings);
        recipe.pushConstantBytes = 16;
        recipe.vertex = shaders.compile(VK_SHADER_STAGE_VERTEX_BIT, p.vertexSource, pass.name + ".vert");
        recipe.fragment = shaders.compile(VK_SHADER_STAGE_FRAGMENT_BIT, p.fragmentSource, pass.name + ".frag");
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

    void buildCompute(PassState& ps) {
        const GenericProgram& p = ps.program;
        ComputePipelineRecipe recipe;
        recipe.bindings = layoutBindings(p.computeBindings);
        recipe.pushConstantBytes = 16;
        recipe.compute = shaders.compile(VK_SHADER_STAGE_COMPUTE_BIT, p.computeSource, ps.pass->name + ".comp");
        ComputePipeline built = createComputePipeline(vkd, recipe);
        ps.computeSetLayout = std::move(built.setLayout);
        ps.computeLayout = std::move(built.layout);
        ps.computePipeline = std::move(built.pipeline);
    }

    // --- output-sized state --------------------------------------------------------------

    void createResources(PlanState& s) {
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
            const auto ext = d.extent.resolve(options.width, options.height);
            r.width = ext[0];
            r.height = ext[1];
            r.mips = std::max(1u, d.mipCount(options.width, options.height));
            r.layers = std::max(1u, d.layers);
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
            for (uint32_t c = 0; c < copies; ++c) {
                ImageCopy img;
                VkImage image;
                vk::check(vkCreateImage(vkd, &ci, nullptr, &image), "vkCreateImage");
                img.image = vk::Image(vkd, image);
                VkMemoryRequirements req;
                vkGetImageMemoryRequirements(vkd, image, &req);
                VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
                mai.allocationSize = req.size;
                mai.memoryTypeIndex = vk::findMemoryType(dev.physical, req.memoryTypeBits,
                                                         VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
                VkDeviceMemory mem;
                vk::check(vkAllocateMemory(vkd, &mai, nullptr, &mem), "vkAllocateMemory");
                img.memory = vk::Memory(vkd, mem);
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

    VkImageMemoryBarrier2 imageBarrier(const PlanState& s, const Barrier& b, uint32_t slot) const {
        const ResourceState& r = s.resources.at(b.resource);
        VkImageMemoryBarrier2 ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
        ib.srcStageMask = b.srcStages;
        ib.srcAccessMask = b.srcAccess;
        ib.dstStageMask = b.dstStages;
        ib.dstAccessMask = b.dstAccess;
        ib.oldLayout = b.oldLayout;
        ib.newLayout = b.newLayout;
        ib.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        ib.image = r.images.at(r.copyFor(slot)).image.get();
        ib.subresourceRange = {r.aspect, b.range.baseMip, b.range.mipCount, b.range.baseLayer,
                               b.range.layerCount};
        return ib;
    }

    void translateBarriers(const PlanState& s, const std::vector<Barrier>& barriers, uint32_t slot,
                           std::vector<VkImageMemoryBarrier2>& images,
                           std::vector<VkBufferMemoryBarrier2>& buffers,
                           std::vector<VkMemoryBarrier2>& memory) const {
        for (const Barrier& b : barriers) {
            if (b.resource >= s.resources.size()) throw ExecutorError("barrier on unknown resource");
            const ResourceState& r = s.resources[b.resource];
            switch (b.kind) {
                case BarrierKind::Image:
                    if (!r.isImage) throw ExecutorError("image barrier on buffer '" + r.desc->name + "'");
                    images.push_back(imageBarrier(s, b, slot));
                    break;
                case BarrierKind::Buffer: {
                    if (r.isImage) throw ExecutorError("buffer barrier on image '" + r.desc->name + "'");
                    VkBufferMemoryBarrier2 bb{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
                    bb.srcStageMask = b.srcStages;
                    bb.srcAccessMask = b.srcAccess;
                    bb.dstStageMask = b.dstStages;
                    bb.dstAccessMask = b.dstAccess;
                    bb.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
                    bb.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
                    bb.buffer = r.buffers.at(r.copyFor(slot)).buffer.get();
                    bb.offset = 0;
                    bb.size = VK_WHOLE_SIZE;
                    buffers.push_back(bb);
                    break;
                }
                case BarrierKind::Memory: {
                    VkMemoryBarrier2 mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
                    mb.srcStageMask = b.srcStages;
                    mb.srcAccessMask = b.srcAccess;
                    mb.dstStageMask = b.dstStages;
                    mb.dstAccessMask = b.dstAccess;
                    memory.push_back(mb);
                    break;
                }
            }
        }
    }

    VkExtent2D bindingExtent(const PlanState& s, const PlannedPass& pass,
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

    void buildPassSlot(PlanState& s, PassState& ps, uint32_t slot) {
        const PlannedPass& pass = *ps.pass;
        const GenericProgram& p = ps.program;
        PassSlot& sl = ps.slots[slot];
        translateBarriers(s, pass.barriers, slot, sl.imageBarriers, sl.bufferBarriers, sl.memoryBarriers);
        if (ps.isClear) return;

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
        sl.imageInfos.reserve(nb);
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
                    SubresourceRange range = u.range;
                    if (!sampled) range.mipCount = 1;  // storage views address one level
                    sl.imageInfos.push_back({sampled ? sampler.get() : VK_NULL_HANDLE,
                                             view(r, copy, b.viewType, range, false), u.layout});
                    w.descriptorType = sampled ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER
                                               : VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
                    w.pImageInfo = &sl.imageInfos.back();
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
                if (!any) e = {options.width, options.height};
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

    /// What a pass implementation sees of each usage: handles and a view of exactly the
    /// usage's subresources.
    void bindResources(PlanState& s, PassState& ps, uint32_t slot) {
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
            b.image = r.images[copy].image.get();
            b.extent = {r.mipWidth(u.range.baseMip), r.mipHeight(u.range.baseMip)};
            const bool attachment = isAttachmentStage(u.usage.stage);
            const bool sampled = isShaderStage(u.usage.stage) && resolveAs(*r.desc, u.usage) == BindAs::Sampled;
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

    static void fillBufferPattern(uint8_t* dst, VkDeviceSize bytes, float value) {
        const size_t words = static_cast<size_t>(bytes / 4);
        uint32_t valueBits;
        std::memcpy(&valueBits, &value, 4);
        for (size_t i = 0; i < words; ++i) {
            const uint32_t w = i == 0 ? 3u : i == 1 ? 1u : i < 8 ? 0u : valueBits;
            std::memcpy(dst + i * 4, &w, 4);
        }
    }

    void buildSized(PlanState& s) {
        const uint32_t slots = options.framesInFlight;
        createResources(s);
        for (PassState& ps : s.passes) {
            ps.slots.clear();
            ps.slots.resize(slots);
            for (uint32_t slot = 0; slot < slots; ++slot) buildPassSlot(s, ps, slot);
        }
        s.finals.assign(slots, {});
        for (uint32_t slot = 0; slot < slots; ++slot) {
            translateBarriers(s, s.plan.finalBarriers, slot, s.finals[slot].imageBarriers,
                              s.finals[slot].bufferBarriers, s.finals[slot].memoryBarriers);
        }
        // Read-back target.
        s.readbackResource = -1;
        s.readbackBuffers.clear();
        for (size_t i = 0; i < s.resources.size(); ++i) {
            const ResourceDesc& d = *s.resources[i].desc;
            const bool match = options.readback.empty() ? d.final == ExternalState::Present
                                                        : d.name == options.readback;
            if (match && s.resources[i].isImage &&
                s.plan.resources[i].finalLayout == VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL) {
                s.readbackResource = static_cast<int32_t>(i);
            }
        }
        if (s.readbackResource >= 0) {
            const ResourceState& r = s.resources[size_t(s.readbackResource)];
            const VkDeviceSize bytes = VkDeviceSize(r.width) * r.height * copyTexelBytes(r.desc->format);
            for (uint32_t slot = 0; slot < slots; ++slot)
                s.readbackBuffers.push_back(makeBuffer(bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true));
        }
        importExternals(s);
    }

    /// Gives every external resource defined contents (its clear value, or grey) and the
    /// layout the plan expects it to arrive in. Runs once, outside any frame, and waits.
    void importExternals(PlanState& s) {
        VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pci.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
        pci.queueFamilyIndex = dev.queueFamily;
        VkCommandPool rawPool;
        vk::check(vkCreateCommandPool(vkd, &pci, nullptr, &rawPool), "vkCreateCommandPool");
        vk::CommandPool pool(vkd, rawPool);
        VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        ai.commandPool = rawPool;
        ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        ai.commandBufferCount = 1;
        VkCommandBuffer cmd;
        vk::check(vkAllocateCommandBuffers(vkd, &ai, &cmd), "vkAllocateCommandBuffers");
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        vk::check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");

        std::vector<OwnedBuffer> staging;
        std::vector<VkImageMemoryBarrier2> toDst, toInitial;
        for (size_t i = 0; i < s.resources.size(); ++i) {
            ResourceState& r = s.resources[i];
            if (!r.desc->external) continue;
            if (!r.isImage) {
                staging.push_back(makeBuffer(r.size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true));
                fillBufferPattern(static_cast<uint8_t*>(staging.back().mapped), r.size, 0.5f);
                for (auto& b : r.buffers) {
                    VkBufferCopy region{0, 0, r.size};
                    vkCmdCopyBuffer(cmd, staging.back().buffer.get(), b.buffer.get(), 1, &region);
                }
                continue;
            }
            for (auto& img : r.images) {
                VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
                b.dstStageMask = VK_PIPELINE_STAGE_2_CLEAR_BIT;
                b.dstAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
                b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
                b.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
                b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
                b.image = img.image.get();
                b.subresourceRange = {r.aspect, 0, r.mips, 0, r.layers};
                toDst.push_back(b);
                const VkImageLayout initial = s.plan.resources[i].initialLayout;
                VkImageMemoryBarrier2 t = b;
                t.srcStageMask = VK_PIPELINE_STAGE_2_CLEAR_BIT;
                t.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
                t.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
                t.dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
                t.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
                t.newLayout = initial == VK_IMAGE_LAYOUT_UNDEFINED ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : initial;
                toInitial.push_back(t);
            }
        }
        auto barrier = [&](std::vector<VkImageMemoryBarrier2>& images) {
            if (images.empty()) return;
            VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
            di.imageMemoryBarrierCount = static_cast<uint32_t>(images.size());
            di.pImageMemoryBarriers = images.data();
            vkCmdPipelineBarrier2(cmd, &di);
        };
        barrier(toDst);
        for (size_t i = 0; i < s.resources.size(); ++i) {
            ResourceState& r = s.resources[i];
            if (!r.desc->external || !r.isImage) continue;
            for (auto& img : r.images) {
                const VkImageSubresourceRange range{r.aspect, 0, r.mips, 0, r.layers};
                if (r.desc->format.isDepthStencil()) {
                    VkClearDepthStencilValue v{r.desc->clear ? r.desc->clear->depth : 1.0f,
                                               r.desc->clear ? r.desc->clear->stencil : 0u};
                    vkCmdClearDepthStencilImage(cmd, img.image.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &v, 1, &range);
                } else {
                    VkClearColorValue v{};
                    const std::array<float, 4> grey{0.5f, 0.5f, 0.5f, 1.0f};
                    const auto& c = r.desc->clear ? r.desc->clear->color : grey;
                    if (scalarPrefix(r.format).empty()) {
                        std::memcpy(v.float32, c.data(), 16);
                    } else {
                        for (int k = 0; k < 4; ++k) v.uint32[k] = static_cast<uint32_t>(c[size_t(k)]);
                    }
                    vkCmdClearColorImage(cmd, img.image.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &v, 1, &range);
                }
            }
        }
        // Loaded textures: copy their pixels over the clear into mip 0 of every layer.
        std::vector<VkImageMemoryBarrier2> afterClear;
        std::vector<std::pair<VkImage, const ResourceState*>> uploadsToDo;
        for (size_t i = 0; i < s.resources.size(); ++i) {
            ResourceState& r = s.resources[i];
            if (!r.desc->external || !r.isImage || !uploads.count(r.desc->name)) continue;
            for (auto& img : r.images) {
                VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
                b.srcStageMask = b.dstStageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
                b.srcAccessMask = b.dstAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
                b.oldLayout = b.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
                b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
                b.image = img.image.get();
                b.subresourceRange = {r.aspect, 0, 1, 0, r.layers};
                afterClear.push_back(b);
                uploadsToDo.emplace_back(img.image.get(), &r);
            }
        }
        barrier(afterClear);
        for (const auto& [image, rp] : uploadsToDo) {
            const ResourceState& r = *rp;
            const ImageData& px = uploads.at(r.desc->name);
            const uint32_t texel = copyTexelBytes(r.desc->format);
            const VkDeviceSize layerBytes = VkDeviceSize(r.width) * r.height * texel;
            staging.push_back(makeBuffer(layerBytes * r.layers, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true));
            auto* dst = static_cast<uint8_t*>(staging.back().mapped);
            for (uint32_t l = 0; l < r.layers; ++l)
                for (size_t p = 0; p < size_t(r.width) * r.height; ++p) {
                    const std::array<float, 4> c{px.rgba[p * 4], px.rgba[p * 4 + 1], px.rgba[p * 4 + 2],
                                                 px.rgba[p * 4 + 3]};
                    const auto t = encodeTexel(r.format, texel, c);
                    std::memcpy(dst + l * layerBytes + p * texel, t.data(), texel);
                }
            VkBufferImageCopy c{};
            c.imageSubresource = {copyAspectOf(r.desc->format), 0, 0, r.layers};
            c.imageExtent = {r.width, r.height, 1};
            vkCmdCopyBufferToImage(cmd, staging.back().buffer.get(), image,
                                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &c);
        }
        for (auto& t : toInitial) {
            t.srcStageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
        }
        barrier(toInitial);
        if (!staging.empty()) {
            VkMemoryBarrier2 mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
            mb.srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
            mb.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
            mb.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
            mb.dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
            VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
            di.memoryBarrierCount = 1;
            di.pMemoryBarriers = &mb;
            vkCmdPipelineBarrier2(cmd, &di);
        }
        vk::check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
        VkCommandBufferSubmitInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
        cbi.commandBuffer = cmd;
        VkSubmitInfo2 si{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
        si.commandBufferInfoCount = 1;
        si.pCommandBufferInfos = &cbi;
        vk::check(vkQueueSubmit2(dev.queue, 1, &si, VK_NULL_HANDLE), "vkQueueSubmit2");
        vk::check(vkQueueWaitIdle(dev.queue), "vkQueueWaitIdle");
    }

    // --- frames --------------------------------------------------------------------------

    void createFrames() {
        frames.resize(options.framesInFlight);
        for (FrameSlot& f : frames) {
            VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
            pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
            pci.queueFamilyIndex = dev.queueFamily;
            VkCommandPool pool;
            vk::check(vkCreateCommandPool(vkd, &pci, nullptr, &pool), "vkCreateCommandPool");
            f.pool = vk::CommandPool(vkd, pool);
            VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
            ai.commandPool = pool;
            ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
            ai.commandBufferCount = 1;
            vk::check(vkAllocateCommandBuffers(vkd, &ai, &f.cmd), "vkAllocateCommandBuffers");
            VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
            VkFence fence;
            vk::check(vkCreateFence(vkd, &fci, nullptr, &fence), "vkCreateFence");
            f.fence = vk::Fence(vkd, fence);
        }
    }

    void ensureQueries(FrameSlot& f, uint32_t count) {
        if (f.queryCount >= count && f.queries) return;
        f.queries.reset();
        VkQueryPoolCreateInfo qci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        qci.queryType = VK_QUERY_TYPE_TIMESTAMP;
        qci.queryCount = std::max(count, 2u);
        VkQueryPool qp;
        vk::check(vkCreateQueryPool(vkd, &qci, nullptr, &qp), "vkCreateQueryPool");
        f.queries = vk::QueryPool(vkd, qp);
        f.queryCount = qci.queryCount;
    }

    void waitSlot(FrameSlot& f) {
        if (!f.submitted) return;
        const VkFence fence = f.fence.get();
        vk::check(vkWaitForFences(vkd, 1, &fence, VK_TRUE, kWaitForever), "vkWaitForFences");
        f.submitted = false;
        collectTimings(f);
    }

    void collectTimings(FrameSlot& f) {
        if (!f.timingsPending) return;
        f.timingsPending = false;
        const auto n = static_cast<uint32_t>(f.passNames.size());
        if (n == 0) return;
        std::vector<uint64_t> ts(size_t(n) * 2);
        if (vkGetQueryPoolResults(vkd, f.queries.get(), 0, n * 2, ts.size() * 8, ts.data(), 8,
                                  VK_QUERY_RESULT_64_BIT) != VK_SUCCESS) {
            return;
        }
        timings.clear();
        for (uint32_t i = 0; i < n; ++i) {
            const double ns = static_cast<double>(ts[2 * i + 1] - ts[2 * i]) * dev.timestampPeriod;
            timings.push_back({f.passNames[i], ns / 1.0e6});
        }
    }

    void dependency(VkCommandBuffer cmd, const std::vector<VkImageMemoryBarrier2>& images,
                    const std::vector<VkBufferMemoryBarrier2>& buffers,
                    const std::vector<VkMemoryBarrier2>& memory) const {
        if (images.empty() && buffers.empty() && memory.empty()) return;
        VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
        di.memoryBarrierCount = static_cast<uint32_t>(memory.size());
        di.pMemoryBarriers = memory.data();
        di.bufferMemoryBarrierCount = static_cast<uint32_t>(buffers.size());
        di.pBufferMemoryBarriers = buffers.data();
        di.imageMemoryBarrierCount = static_cast<uint32_t>(images.size());
        di.pImageMemoryBarriers = images.data();
        vkCmdPipelineBarrier2(cmd, &di);
    }

    void recordClear(VkCommandBuffer cmd, PlanState& s, const PassState& ps, uint32_t slot) {
        for (const PlannedUsage& u : ps.pass->usages) {
            const ResourceState& r = s.resources[u.resource];
            const VkImageSubresourceRange range{r.aspect, u.range.baseMip, u.range.mipCount,
                                                u.range.baseLayer, u.range.layerCount};
            const VkImage image = r.images[r.copyFor(slot)].image.get();
            if (r.desc->format.isDepthStencil()) {
                const VkClearDepthStencilValue v{r.desc->clear->depth, r.desc->clear->stencil};
                vkCmdClearDepthStencilImage(cmd, image, u.layout, &v, 1, &range);
            } else {
                VkClearColorValue v{};
                std::memcpy(v.float32, r.desc->clear->color.data(), 16);
                vkCmdClearColorImage(cmd, image, u.layout, &v, 1, &range);
            }
        }
    }

    void recordTransfers(VkCommandBuffer cmd, PlanState& s, const PassState& ps, uint32_t slot) {
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
            const VkImage image = r.images[r.copyFor(slot)].image.get();
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

    void recordPass(VkCommandBuffer cmd, PlanState& s, PassState& ps, uint32_t slot) {
        if (ps.isClear) {
            recordClear(cmd, s, ps, slot);
            return;
        }
        if (ps.custom) {
            PassSlot& sl = ps.slots[slot];
            RecordContext rc;
            rc.cmd = cmd;
            rc.pass = ps.pass;
            rc.desc = ps.desc;
            rc.resources = sl.bound;
            rc.renderArea = ps.program.graphics ? sl.extent : VkExtent2D{0, 0};
            rc.linearSampler = linearSampler.get();
            rc.repeatSampler = repeatSampler.get();
            rc.frame = &frameData;
            rc.frameIndex = frameIndex;
            if (ps.program.graphics) {
                VkRenderPassBeginInfo rbi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
                rbi.renderPass = ps.renderPass.get();
                rbi.framebuffer = sl.framebuffer.get();
                rbi.renderArea = {{0, 0}, sl.extent};
                rbi.clearValueCount = static_cast<uint32_t>(ps.clearValues.size());
                rbi.pClearValues = ps.clearValues.data();
                vkCmdBeginRenderPass(cmd, &rbi, VK_SUBPASS_CONTENTS_INLINE);
                const VkViewport vp{0, 0, float(sl.extent.width), float(sl.extent.height), 0, 1};
                const VkRect2D sc{{0, 0}, sl.extent};
                vkCmdSetViewport(cmd, 0, 1, &vp);
                vkCmdSetScissor(cmd, 0, 1, &sc);
            }
            ps.custom->record(rc);
            if (ps.program.graphics) vkCmdEndRenderPass(cmd);
            return;
        }
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
            VkRenderPassBeginInfo rbi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
            rbi.renderPass = ps.renderPass.get();
            rbi.framebuffer = sl.framebuffer.get();
            rbi.renderArea = {{0, 0}, sl.extent};
            rbi.clearValueCount = static_cast<uint32_t>(ps.clearValues.size());
            rbi.pClearValues = ps.clearValues.data();
            vkCmdBeginRenderPass(cmd, &rbi, VK_SUBPASS_CONTENTS_INLINE);
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, ps.graphicsPipeline.get());
            const VkViewport vp{0, 0, float(sl.extent.width), float(sl.extent.height), 0, 1};
            const VkRect2D sc{{0, 0}, sl.extent};
            vkCmdSetViewport(cmd, 0, 1, &vp);
            vkCmdSetScissor(cmd, 0, 1, &sc);
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

    void recordFrame(VkCommandBuffer cmd, uint32_t slot, FrameSlot* frame) {
        PlanState& s = *state;
        const auto passCount = static_cast<uint32_t>(s.passes.size());
        if (frame) {
            ensureQueries(*frame, passCount * 2);
            vkCmdResetQueryPool(cmd, frame->queries.get(), 0, frame->queryCount);
        }
        for (uint32_t i = 0; i < passCount; ++i) {
            PassState& ps = s.passes[i];
            const PassSlot& sl = ps.slots[slot];
            if (frame && dev.fn.cmdBeginLabel) {
                VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
                label.pLabelName = ps.pass->name.c_str();
                dev.fn.cmdBeginLabel(cmd, &label);
            }
            dependency(cmd, sl.imageBarriers, sl.bufferBarriers, sl.memoryBarriers);
            if (frame) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, frame->queries.get(), 2 * i);
            recordPass(cmd, s, ps, slot);
            if (frame) {
                vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, frame->queries.get(), 2 * i + 1);
                if (dev.fn.cmdEndLabel) dev.fn.cmdEndLabel(cmd);
            }
        }
        const FinalSlot& fin = s.finals[slot];
        dependency(cmd, fin.imageBarriers, fin.bufferBarriers, fin.memoryBarriers);
        if (frame && s.readbackResource >= 0) {
            // The executor's "present": copy the target out, then make it visible to the host.
            const ResourceState& r = s.resources[size_t(s.readbackResource)];
            VkBufferImageCopy c{};
            c.imageSubresource = {copyAspectOf(r.desc->format), 0, 0, 1};
            c.imageExtent = {r.width, r.height, 1};
            const VkBuffer dst = s.readbackBuffers[slot].buffer.get();
            vkCmdCopyImageToBuffer(cmd, r.images[r.copyFor(slot)].image.get(),
                                   VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst, 1, &c);
            VkBufferMemoryBarrier2 bb{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
            bb.srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
            bb.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
            bb.dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT;
            bb.dstAccessMask = VK_ACCESS_2_HOST_READ_BIT;
            bb.srcQueueFamilyIndex = bb.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            bb.buffer = dst;
            bb.size = VK_WHOLE_SIZE;
            dependency(cmd, {}, {bb}, {});
        }
        if (frame) {
            frame->passNames.clear();
            for (const PassState& ps : s.passes) frame->passNames.push_back(ps.pass->name);
        }
    }

    void renderFrame() {
        const auto slot = static_cast<uint32_t>(frameIndex % frames.size());
        FrameSlot& f = frames[slot];
        waitSlot(f);
        const VkFence fence = f.fence.get();
        vk::check(vkResetFences(vkd, 1, &fence), "vkResetFences");
        vk::check(vkResetCommandBuffer(f.cmd, 0), "vkResetCommandBuffer");
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        vk::check(vkBeginCommandBuffer(f.cmd, &bi), "vkBeginCommandBuffer");
        recordFrame(f.cmd, slot, &f);
        vk::check(vkEndCommandBuffer(f.cmd), "vkEndCommandBuffer");
        VkCommandBufferSubmitInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
        cbi.commandBuffer = f.cmd;
        VkSubmitInfo2 si{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
        si.commandBufferInfoCount = 1;
        si.pCommandBufferInfos = &cbi;
        vk::check(vkQueueSubmit2(dev.queue, 1, &si, f.fence.get()), "vkQueueSubmit2");
        f.submitted = true;
        f.timingsPending = true;
        lastSlot = slot;
        ++frameIndex;
    }

    void waitIdle() {
        for (FrameSlot& f : frames) waitSlot(f);
    }
};


namespace {

ImageData convertPixels(const void* data, uint32_t width, uint32_t height, VkFormat format,
                        const std::string& name) {
    ImageData out;
    out.width = width;
    out.height = height;
    out.format = format;
    out.rgba.resize(size_t(width) * height * 4);
    const auto* bytes = static_cast<const uint8_t*>(data);
    const size_t n = size_t(width) * height;
    for (size_t i = 0; i < n; ++i) {
        float* px = &out.rgba[i * 4];
        switch (format) {
            case VK_FORMAT_R8G8B8A8_UNORM:
            case VK_FORMAT_R8G8B8A8_SRGB:
                for (int c = 0; c < 4; ++c) px[c] = bytes[i * 4 + size_t(c)] / 255.0f;
                break;
            case VK_FORMAT_B8G8R8A8_UNORM:
            case VK_FORMAT_B8G8R8A8_SRGB:
                px[0] = bytes[i * 4 + 2] / 255.0f;
                px[1] = bytes[i * 4 + 1] / 255.0f;
                px[2] = bytes[i * 4 + 0] / 255.0f;
                px[3] = bytes[i * 4 + 3] / 255.0f;
                break;
            case VK_FORMAT_R16G16B16A16_SFLOAT: {
                uint16_t h[4];
                std::memcpy(h, bytes + i * 8, 8);
                for (int c = 0; c < 4; ++c) px[c] = halfToFloat(h[c]);
                break;
            }
            case VK_FORMAT_R32G32B32A32_SFLOAT:
                std::memcpy(px, bytes + i * 16, 16);
                break;
            case VK_FORMAT_R32_SFLOAT:
            case VK_FORMAT_D32_SFLOAT:
                std::memcpy(px, bytes + i * 4, 4);
                px[1] = px[2] = 0.0f;
                px[3] = 1.0f;
                break;
            case VK_FORMAT_R8_UNORM:
                px[0] = bytes[i] / 255.0f;
                px[1] = px[2] = 0.0f;
                px[3] = 1.0f;
                break;
            default:
                throw ExecutorError("cannot read back '" + name + "': its format is not supported "
                                    "for read-back");
        }
    }
    return out;
}

}  // namespace

Renderer::Renderer(Device& device, const GraphDesc& graph, Plan plan, RendererOptions options) {
    if (options.width == 0 || options.height == 0)
        throw ExecutorError("output extent must be at least 1x1");
    if (options.framesInFlight == 0 || options.framesInFlight > 8)
        throw ExecutorError("framesInFlight must be between 1 and 8");
    impl_ = std::make_unique<Impl>(device, std::move(options));
    Impl& d = *impl_;
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12, {}};
    vkGetPhysicalDeviceFeatures2(d.dev.physical, &f2);
    d.layered = f12.shaderOutputLayer == VK_TRUE;
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
    sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    sci.maxLod = VK_LOD_CLAMP_NONE;
    VkSampler sampler;
    vk::check(vkCreateSampler(d.vkd, &sci, nullptr, &sampler), "vkCreateSampler");
    d.sampler = vk::Sampler(d.vkd, sampler);
    sci.magFilter = sci.minFilter = VK_FILTER_LINEAR;
    sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
    vk::check(vkCreateSampler(d.vkd, &sci, nullptr, &sampler), "vkCreateSampler");
    d.linearSampler = vk::Sampler(d.vkd, sampler);
    sci.addressModeU = VK_SAMPLER_ADDRESS_MODE_REPEAT;
    vk::check(vkCreateSampler(d.vkd, &sci, nullptr, &sampler), "vkCreateSampler");
    d.repeatSampler = vk::Sampler(d.vkd, sampler);
    d.createFrames();
    d.state = d.build(graph, std::move(plan));
}

Renderer::~Renderer() {
    if (impl_) {
        vkDeviceWaitIdle(impl_->vkd);
    }
}

void Renderer::renderFrame() { impl_->renderFrame(); }
void Renderer::waitIdle() { impl_->waitIdle(); }

ImageData Renderer::readback() {
    Impl& d = *impl_;
    PlanState& s = *d.state;
    if (s.readbackResource < 0) {
        throw ExecutorError(
            d.options.readback.empty()
                ? "no read-back target: the graph exports no `Present` image that ends the frame in "
                  "TRANSFER_SRC_OPTIMAL (compile with presentReplacement = TransferSrc)"
                : "cannot read back '" + d.options.readback +
                      "': it is not an image left in TRANSFER_SRC_OPTIMAL (final: TransferSrc)");
    }
    if (d.lastSlot < 0) throw ExecutorError("no frame has been rendered yet");
    FrameSlot& f = d.frames[size_t(d.lastSlot)];
    d.waitSlot(f);
    const ResourceState& r = s.resources[size_t(s.readbackResource)];
    return convertPixels(s.readbackBuffers[size_t(d.lastSlot)].mapped, r.width, r.height, r.format,
                         r.desc->name);
}

void Renderer::resize(uint32_t width, uint32_t height) {
    if (width == 0 || height == 0) throw ExecutorError("output extent must be at least 1x1");
    Impl& d = *impl_;
    d.waitIdle();
    vk::check(vkDeviceWaitIdle(d.vkd), "vkDeviceWaitIdle");
    const uint32_t oldW = d.options.width, oldH = d.options.height;
    d.options.width = width;
    d.options.height = height;
    try {
        d.state = d.build(d.state->graph, d.state->plan);
    } catch (...) {
        d.options.width = oldW;
        d.options.height = oldH;
        throw;
    }
    d.lastSlot = -1;
}

void Renderer::setPlan(const GraphDesc& graph, Plan plan) {
    Impl& d = *impl_;
    d.waitIdle();
    auto next = d.build(graph, std::move(plan));  // throws: the old plan keeps running
    vk::check(vkDeviceWaitIdle(d.vkd), "vkDeviceWaitIdle");
    d.state = std::move(next);
    d.lastSlot = -1;
}

std::vector<PassTiming> Renderer::lastTimings() {
    Impl& d = *impl_;
    if (d.lastSlot >= 0) d.waitSlot(d.frames[size_t(d.lastSlot)]);
    return d.timings;
}

const Plan& Renderer::plan() const noexcept { return impl_->state->plan; }
const GraphDesc& Renderer::graph() const noexcept { return impl_->state->graph; }
FrameData& Renderer::frameData() noexcept { return impl_->frameData; }

void Renderer::setExternalImage(const std::string& resource, ImageData pixels) {
    Impl& d = *impl_;
    const ResourceDesc* desc = d.state->graph.findResource(resource);
    if (!desc) throw ExecutorError("setExternalImage: no resource '" + resource + "' in the graph");
    if (!desc->external || !desc->isImage())
        throw ExecutorError("setExternalImage: '" + resource + "' is not an external image");
    const auto ext = desc->extent.resolve(d.options.width, d.options.height);
    if (pixels.width != ext[0] || pixels.height != ext[1] ||
        pixels.rgba.size() != size_t(pixels.width) * pixels.height * 4) {
        throw ExecutorError("setExternalImage: '" + resource + "' is " + std::to_string(ext[0]) + "x" +
                            std::to_string(ext[1]) + ", the pixels are " + std::to_string(pixels.width) +
                            "x" + std::to_string(pixels.height));
    }
    const uint32_t texel = findFormat(desc->format.format) ? desc->format.bytesPerTexel : 0;
    std::array<float, 4> probe{1, 1, 1, 1};
    const auto encoded = encodeTexel(desc->format.format, texel, probe);
    if (texel == 0 || std::all_of(encoded.begin(), encoded.end(), [](uint8_t b) { return b == 0; }))
        throw ExecutorError("setExternalImage: cannot upload pixels to format " + std::string(desc->format.name));
    auto previous = d.uploads;
    d.uploads[resource] = std::move(pixels);
    try {
        setPlan(d.state->graph, d.state->plan);  // re-imports the externals with the pixels
    } catch (...) {
        d.uploads = std::move(previous);
        throw;
    }
}

void Renderer::reloadShaders() {
    Impl& d = *impl_;
    d.shaders.clear();
    d.waitIdle();
    auto next = d.build(d.state->graph, d.state->plan);  // throws: the old pipelines keep running
    vk::check(vkDeviceWaitIdle(d.vkd), "vkDeviceWaitIdle");
    d.state = std::move(next);
    d.lastSlot = -1;
}
uint64_t Renderer::frameCount() const noexcept { return impl_->frameIndex; }

void Renderer::recordInto(VkCommandBuffer cmd, uint32_t slot) {
    if (slot >= impl_->frames.size()) throw ExecutorError("frame slot out of range");
    impl_->recordFrame(cmd, slot, nullptr);
}

}  // namespace skygraph

#include "renderer_access.hpp"

namespace skygraph {

HandFrame RendererAccess::handFrame(Renderer& renderer, uint32_t slot) {
    Renderer::Impl& d = *renderer.impl_;
    PlanState& s = *d.state;
    if (slot >= d.frames.size()) throw ExecutorError("frame slot out of range");
    HandFrame f;
    f.pushDescriptors = d.dev.fn.cmdPushDescriptorSet;
    for (PassState& ps : s.passes) {
        const PassSlot& sl = ps.slots[slot];
        const GenericProgram& p = ps.program;
        if (ps.isClear || !p.transfers.empty() || !p.vertexBuffers.empty() || p.indexBuffer >= 0 ||
            p.indirectBuffer >= 0) {
            throw ExecutorError("pass '" + ps.pass->name + "': hand recording covers draws and dispatches only");
        }
        HandPass h;
        h.imageBarriers = sl.imageBarriers;
        h.bufferBarriers = sl.bufferBarriers;
        h.memoryBarriers = sl.memoryBarriers;
        if (p.graphics) {
            h.renderPass = ps.renderPass.get();
            h.framebuffer = sl.framebuffer.get();
            h.extent = sl.extent;
            h.clearValues = ps.clearValues;
            h.graphicsPipeline = ps.graphicsPipeline.get();
            h.graphicsLayout = ps.graphicsLayout.get();
            h.graphicsWrites = sl.graphicsWrites;
            h.instances = p.attachmentLayers;
        }
        if (p.compute) {
            h.computePipeline = ps.computePipeline.get();
            h.computeLayout = ps.computeLayout.get();
            h.computeWrites = sl.computeWrites;
            h.computeExtent = sl.computeExtent;
        }
        f.passes.push_back(std::move(h));
    }
    f.finalImageBarriers = s.finals[slot].imageBarriers;
    f.finalBufferBarriers = s.finals[slot].bufferBarriers;
    f.finalMemoryBarriers = s.finals[slot].memoryBarriers;
    return f;
}

}  // namespace skygraph
