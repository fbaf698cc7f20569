// Bandwidth and compute-tonemap probes (see gpu_probes.hpp).
#include "gpu_probes.hpp"

#include "gpu_vk.hpp"
#include "vk_util.hpp"

#include <skygraph/pipeline_builder.hpp>
#include <skygraph/shader_compiler.hpp>

#include <algorithm>
#include <string>

namespace skygraph::gpubench {
namespace {

constexpr uint32_t kCopyGroupSize = 256;

// Grid-stride loops: a dispatch of at most 65535 groups covers any buffer.
constexpr const char* kFillShader = R"(#version 450
layout(local_size_x = 256) in;
layout(set = 0, binding = 0) writeonly buffer Dst { uvec4 d[]; };
layout(push_constant) uniform P { uint count; uint seed; } p;
void main() {
    uint stride = gl_NumWorkGroups.x * 256u;
    for (uint i = gl_GlobalInvocationID.x; i < p.count; i += stride) {
        uint h = (i + p.seed) * 2654435761u;
        h ^= h >> 15;
        d[i] = uvec4(h, h * 3u + 1u, h ^ 0x9e3779b9u, ~h);
    }
})";

constexpr const char* kCopyShader = R"(#version 450
layout(local_size_x = 256) in;
layout(set = 0, binding = 0) readonly buffer Src { uvec4 s[]; };
layout(set = 0, binding = 1) writeonly buffer Dst { uvec4 d[]; };
layout(push_constant) uniform P { uint count; uint seed; } p;
void main() {
    uint stride = gl_NumWorkGroups.x * 256u;
    for (uint i = gl_GlobalInvocationID.x; i < p.count; i += stride) d[i] = s[i];
})";

// A pattern with real HDR range (0..~16, some texels above 1) so the tone curve does work.
constexpr const char* kHdrFillShader = R"(#version 450
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform writeonly image2D hdr;
void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(hdr)))) return;
    uint h = uint(p.x) * 73856093u ^ uint(p.y) * 19349663u;
    h ^= h >> 13; h *= 0x5bd1e995u; h ^= h >> 15;
    vec3 c = vec3(h & 1023u, (h >> 10) & 1023u, (h >> 20) & 1023u) / 64.0;
    imageStore(hdr, p, vec4(c, 1.0));
})";

// tonemap.frag's body, one invocation per pixel (QUAD 0) or per 2x2 pixels (QUAD 1), reading
// through a sampler (LOAD_IMAGE 0, as the fragment shader does) or imageLoad (LOAD_IMAGE 1).
constexpr const char* kTonemapShader = R"(#version 450
#extension GL_GOOGLE_include_directive : require
#include "common/tonemap.glsl"
layout(local_size_x = GROUP_X, local_size_y = GROUP_Y) in;
#if LOAD_IMAGE
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D hdrInput;
#define LOAD(p) imageLoad(hdrInput, p)
#else
layout(set = 0, binding = 0) uniform sampler2D hdrInput;
#define LOAD(p) texelFetch(hdrInput, p, 0)
#endif
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D outImage;
layout(push_constant) uniform Params { float exposureEv; int toneOperator; int encodeSrgb; } params;
void shade(ivec2 p, ivec2 size) {
    if (any(greaterThanEqual(p, size))) return;
    vec3 c = tonemap(LOAD(p).rgb, params.exposureEv, params.toneOperator);
    if (params.encodeSrgb != 0) c = srgbEncode(c);
    imageStore(outImage, p, vec4(c, 1.0));
}
void main() {
    ivec2 size = imageSize(outImage);
#if QUAD
    // The group's 2x2 blocks tile a (2*GROUP_X) x (2*GROUP_Y) region; each invocation's four
    // loads are issued before any store.
    ivec2 base = ivec2(gl_WorkGroupID.xy) * ivec2(2 * GROUP_X, 2 * GROUP_Y) + ivec2(gl_LocalInvocationID.xy);
    shade(base, size);
    shade(base + ivec2(GROUP_X, 0), size);
    shade(base + ivec2(0, GROUP_Y), size);
    shade(base + ivec2(GROUP_X, GROUP_Y), size);
#else
    shade(ivec2(gl_GlobalInvocationID.xy), size);
#endif
})";

// Reads a buffer larger than the L2 cache (clean lines, nothing to write back later), so the
// next timed operation starts with its inputs in DRAM only.
constexpr const char* kEvictShader = R"(#version 450
layout(local_size_x = 256) in;
layout(set = 0, binding = 0) readonly buffer Src { uvec4 s[]; };
layout(set = 0, binding = 1) writeonly buffer Sink { uint sink[]; };
layout(push_constant) uniform P { uint count; uint seed; } p;
void main() {
    uint stride = gl_NumWorkGroups.x * 256u;
    uvec4 acc = uvec4(0);
    for (uint i = gl_GlobalInvocationID.x; i < p.count; i += stride) acc ^= s[i];
    if (acc.x == 0x9e3779b9u && acc.y == p.seed) sink[0] = acc.z;  // keeps the loads alive
})";

// A fullscreen triangle writing a constant: the fragment path's own cost (rasterizer, fragment
// launch, color output), with no texture read and no arithmetic.
constexpr const char* kFullscreenVertex = R"(#version 450
void main() {
    vec2 uv = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    gl_Position = vec4(uv * 2.0 - 1.0, 0.0, 1.0);
})";
constexpr const char* kConstantFragment = R"(#version 450
layout(location = 0) out vec4 outColor;
void main() { outColor = vec4(0.25, 0.5, 0.75, 1.0); }
)";

constexpr const char* kEmptyShader = R"(#version 450
layout(local_size_x = 64) in;
void main() {}
)";

std::string withDefines(std::string source, const std::string& defines) {
    const auto eol = source.find('\n');
    return source.insert(eol + 1, defines);
}

ComputePipeline computePipeline(Device& device, ShaderCompiler& compiler, const std::string& source,
                                const std::string& name, std::vector<VkDescriptorSetLayoutBinding> bindings,
                                uint32_t pushBytes) {
    ComputePipelineRecipe recipe;
    recipe.compute = compiler.compile(VK_SHADER_STAGE_COMPUTE_BIT, source, name);
    recipe.bindings = std::move(bindings);
    recipe.pushConstantBytes = pushBytes;
    return createComputePipeline(device.device(), recipe);
}

VkWriteDescriptorSet bufferWrite(uint32_t binding, const VkDescriptorBufferInfo* info) {
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstBinding = binding;
    w.descriptorCount = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    w.pBufferInfo = info;
    return w;
}

VkWriteDescriptorSet imageWrite(uint32_t binding, VkDescriptorType type, const VkDescriptorImageInfo* info) {
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstBinding = binding;
    w.descriptorCount = 1;
    w.descriptorType = type;
    w.pImageInfo = info;
    return w;
}

ProbeResult summarize(std::string name, double bytes, const std::vector<double>& ms) {
    ProbeResult r;
    r.name = std::move(name);
    r.bytes = bytes;
    r.medianMs = median(ms);
    r.p10Ms = quantile(ms, 0.1);
    r.p90Ms = quantile(ms, 0.9);
    r.repetitions = static_cast<uint32_t>(ms.size());
    return r;
}

/// Runs a storage-buffer kernel over [0, bytes) in chunks no larger than the device allows
/// for one descriptor; `buffers` are bound at bindings 0.. with the same offsets, then `whole`
/// (if given) whole at the next binding.
void dispatchOverBuffers(VkCommandBuffer cmd, Device& device, const ComputePipeline& pipe,
                         PFN_vkCmdPushDescriptorSetKHR push, const std::vector<VkBuffer>& buffers,
                         uint64_t bytes, uint32_t seed, VkBuffer whole = VK_NULL_HANDLE) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(device.physicalDevice(), &props);
    const uint64_t align = std::max<uint64_t>(props.limits.minStorageBufferOffsetAlignment, 16);
    uint64_t chunk = std::min<uint64_t>(bytes, props.limits.maxStorageBufferRange);
    chunk -= chunk % align;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipe.pipeline.get());
    for (uint64_t offset = 0; offset < bytes; offset += chunk) {
        const uint64_t size = std::min(chunk, bytes - offset);
        std::vector<VkDescriptorBufferInfo> infos;
        for (VkBuffer b : buffers) infos.push_back({b, offset, size});
        if (whole != VK_NULL_HANDLE) infos.push_back({whole, 0, VK_WHOLE_SIZE});
        std::vector<VkWriteDescriptorSet> writes;
        for (uint32_t i = 0; i < infos.size(); ++i) writes.push_back(bufferWrite(i, &infos[i]));
        push(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipe.layout.get(), 0, static_cast<uint32_t>(writes.size()),
             writes.data());
        const uint32_t pc[2] = {static_cast<uint32_t>(size / 16), seed};
        vkCmdPushConstants(cmd, pipe.layout.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(pc), pc);
        const uint64_t groups = (size / 16 + kCopyGroupSize - 1) / kCopyGroupSize;
        vkCmdDispatch(cmd, static_cast<uint32_t>(std::min<uint64_t>(groups, 65535)), 1, 1);
    }
}

}  // namespace

std::vector<ProbeResult> measureBandwidth(Device& device, uint64_t bytes, uint32_t repetitions) {
    bytes -= bytes % 256;
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    const DeviceBuffer src = createDeviceBuffer(device, bytes, usage);
    const DeviceBuffer dst = createDeviceBuffer(device, bytes, usage);
    ShaderCompiler compiler(ShaderCompiler::defaultIncludeDir());
    const VkDescriptorSetLayoutBinding b0{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    const VkDescriptorSetLayoutBinding b1{1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    const ComputePipeline fill = computePipeline(device, compiler, kFillShader, "bandwidth fill", {b0}, 8);
    const ComputePipeline copy = computePipeline(device, compiler, kCopyShader, "bandwidth copy", {b0, b1}, 8);
    const auto push = pushDescriptorFunction(device.device());
    GpuTimer timer(device);
    timer.run([&](VkCommandBuffer cmd) {
        dispatchOverBuffers(cmd, device, fill, push, {src.buffer.get()}, bytes, 1);
        dispatchOverBuffers(cmd, device, fill, push, {dst.buffer.get()}, bytes, 7);
        fullBarrier(cmd);
    });
    const double moved = 2.0 * static_cast<double>(bytes);
    // An empty prologue still puts a full barrier before each timed copy: no copy overlaps
    // the previous one's writes of `dst`.
    const auto nothing = [](VkCommandBuffer) {};
    std::vector<double> copyMs, computeMs;
    for (uint32_t i = 0; i < repetitions; ++i) {
        copyMs.push_back(timer.time([&](VkCommandBuffer cmd) {
            const VkBufferCopy region{0, 0, bytes};
            vkCmdCopyBuffer(cmd, src.buffer.get(), dst.buffer.get(), 1, &region);
        }, nothing));
        computeMs.push_back(timer.time([&](VkCommandBuffer cmd) {
            dispatchOverBuffers(cmd, device, copy, push, {src.buffer.get(), dst.buffer.get()}, bytes, 0);
        }, nothing));
    }
    return {summarize("copy_buffer", moved, copyMs), summarize("compute_copy_uvec4", moved, computeMs)};
}

ProbeResult measureFragmentFill(Device& device, uint32_t width, uint32_t height, uint32_t repetitions) {
    const VkDevice vkd = device.device();
    const DeviceImage target = createDeviceImage(device, VK_FORMAT_R8G8B8A8_UNORM, {width, height},
                                                 VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT);
    VkAttachmentDescription color{};
    color.format = VK_FORMAT_R8G8B8A8_UNORM;
    color.samples = VK_SAMPLE_COUNT_1_BIT;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;  // as the framework's tonemap output
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    color.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    color.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    color.finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    const VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &ref;
    // Earlier writes of the target (the previous repetition) finish before this one's.
    VkSubpassDependency dep{};
    dep.srcSubpass = VK_SUBPASS_EXTERNAL;
    dep.dstSubpass = 0;
    dep.srcStageMask = dep.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dep.srcAccessMask = dep.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    VkRenderPassCreateInfo rpi{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    rpi.attachmentCount = 1;
    rpi.pAttachments = &color;
    rpi.subpassCount = 1;
    rpi.pSubpasses = &subpass;
    rpi.dependencyCount = 1;
    rpi.pDependencies = &dep;
    VkRenderPass rawPass;
    vk::check(vkCreateRenderPass(vkd, &rpi, nullptr, &rawPass), "vkCreateRenderPass");
    const owned::RenderPass renderPass(vkd, rawPass);
    VkFramebufferCreateInfo fbi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fbi.renderPass = rawPass;
    fbi.attachmentCount = 1;
    const VkImageView view = target.view.get();
    fbi.pAttachments = &view;
    fbi.width = width;
    fbi.height = height;
    fbi.layers = 1;
    VkFramebuffer rawFramebuffer;
    vk::check(vkCreateFramebuffer(vkd, &fbi, nullptr, &rawFramebuffer), "vkCreateFramebuffer");
    const owned::Framebuffer framebuffer(vkd, rawFramebuffer);

    ShaderCompiler compiler(ShaderCompiler::defaultIncludeDir());
    GraphicsPipelineRecipe recipe;
    recipe.vertex = compiler.compile(VK_SHADER_STAGE_VERTEX_BIT, kFullscreenVertex, "fullscreen vertex");
    recipe.fragment = compiler.compile(VK_SHADER_STAGE_FRAGMENT_BIT, kConstantFragment, "constant fragment");
    recipe.renderPass = rawPass;
    const GraphicsPipeline pipe = createGraphicsPipeline(vkd, recipe);
    GpuTimer timer(device);
    std::vector<double> ms;
    for (uint32_t i = 0; i < repetitions; ++i) {
        ms.push_back(timer.time([&](VkCommandBuffer cmd) {
            VkRenderPassBeginInfo rbi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
            rbi.renderPass = rawPass;
            rbi.framebuffer = rawFramebuffer;
            rbi.renderArea = {{0, 0}, {width, height}};
            vkCmdBeginRenderPass(cmd, &rbi, VK_SUBPASS_CONTENTS_INLINE);
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipe.pipeline.get());
            setViewportAndScissor(cmd, {width, height});
            vkCmdDraw(cmd, 3, 1, 0, 0);
            vkCmdEndRenderPass(cmd);
        }));
    }
    return summarize("fragment_constant_fill", 4.0 * width * height, ms);
}

std::vector<ProbeResult> measureComputeTonemap(Device& device, uint32_t width, uint32_t height,
                                               uint32_t repetitions, uint64_t evictBytes) {
    const VkExtent2D extent{width, height};
    const DeviceImage hdr = createDeviceImage(device, VK_FORMAT_R16G16B16A16_SFLOAT, extent,
                                              VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
    const DeviceImage out = createDeviceImage(device, VK_FORMAT_R8G8B8A8_UNORM, extent, VK_IMAGE_USAGE_STORAGE_BIT);
    evictBytes = std::max<uint64_t>(evictBytes - evictBytes % 256, 256);
    const DeviceBuffer evict = createDeviceBuffer(device, evictBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    const DeviceBuffer sink = createDeviceBuffer(device, 256, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSampler rawSampler;
    vk::check(vkCreateSampler(device.device(), &sci, nullptr, &rawSampler), "vkCreateSampler");
    const owned::Sampler sampler(device.device(), rawSampler);

    ShaderCompiler compiler(ShaderCompiler::defaultIncludeDir());
    const auto push = pushDescriptorFunction(device.device());
    const auto binding = [](uint32_t b, VkDescriptorType t) {
        return VkDescriptorSetLayoutBinding{b, t, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    };
    const ComputePipeline fill = computePipeline(device, compiler, kHdrFillShader, "hdr fill",
                                                 {binding(0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE)}, 0);
    const ComputePipeline evictPipe = computePipeline(
        device, compiler, kEvictShader, "cache evict",
        {binding(0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER), binding(1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER)}, 8);
    const ComputePipeline empty = computePipeline(device, compiler, kEmptyShader, "empty dispatch", {}, 0);
    GpuTimer timer(device);
    // Both images stay in GENERAL: sampled and storage access alike, no layout change per variant.
    const VkDescriptorImageInfo hdrStorage{VK_NULL_HANDLE, hdr.view.get(), VK_IMAGE_LAYOUT_GENERAL};
    timer.run([&](VkCommandBuffer cmd) {
        transitionImage(cmd, hdr.image.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
        transitionImage(cmd, out.image.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, fill.pipeline.get());
        const VkWriteDescriptorSet w = imageWrite(0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, &hdrStorage);
        push(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, fill.layout.get(), 0, 1, &w);
        vkCmdDispatch(cmd, (width + 7) / 8, (height + 7) / 8, 1);
    });
    const auto evictCache = [&](VkCommandBuffer cmd) {
        dispatchOverBuffers(cmd, device, evictPipe, push, {evict.buffer.get()}, evictBytes, 1, sink.buffer.get());
    };

    std::vector<ProbeResult> results;
    {
        std::vector<double> ms;
        for (uint32_t i = 0; i < repetitions; ++i)
            ms.push_back(timer.time([&](VkCommandBuffer cmd) {
                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, empty.pipeline.get());
                vkCmdDispatch(cmd, 1, 1, 1);
            }, evictCache));
        results.push_back(summarize("empty_dispatch", 0, ms));
    }

    struct Variant {
        uint32_t groupX, groupY;
        bool loadImage, quad;
    };
    const Variant variants[] = {{8, 8, false, false},  {16, 16, false, false}, {32, 8, false, false},
                                {16, 16, true, false}, {8, 8, false, true},    {16, 8, false, true},
                                {8, 8, true, true}};
    const VkDescriptorImageInfo hdrSampled{sampler.get(), hdr.view.get(), VK_IMAGE_LAYOUT_GENERAL};
    const VkDescriptorImageInfo outStorage{VK_NULL_HANDLE, out.view.get(), VK_IMAGE_LAYOUT_GENERAL};
    const double bytes = 12.0 * width * height;
    for (const Variant& v : variants) {
        const std::string defines = "#define GROUP_X " + std::to_string(v.groupX) + "\n#define GROUP_Y " +
                                    std::to_string(v.groupY) + "\n#define LOAD_IMAGE " + (v.loadImage ? "1" : "0") +
                                    "\n#define QUAD " + (v.quad ? "1" : "0") + "\n";
        const std::string name = "tonemap_compute_" + std::to_string(v.groupX) + "x" + std::to_string(v.groupY) +
                                 (v.loadImage ? "_imageload" : "_texelfetch") + (v.quad ? "_2x2px" : "");
        const VkDescriptorType inputType =
            v.loadImage ? VK_DESCRIPTOR_TYPE_STORAGE_IMAGE : VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        const ComputePipeline pipe =
            computePipeline(device, compiler, withDefines(kTonemapShader, defines), name,
                            {binding(0, inputType), binding(1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE)}, 12);
        const VkWriteDescriptorSet writes[2] = {imageWrite(0, inputType, v.loadImage ? &hdrStorage : &hdrSampled),
                                                imageWrite(1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, &outStorage)};
        const struct { float exposureEv; int32_t op; int32_t encodeSrgb; } pc{0.0f, 0, 1};
        const uint32_t tileX = v.groupX * (v.quad ? 2 : 1), tileY = v.groupY * (v.quad ? 2 : 1);
        std::vector<double> ms;
        for (uint32_t i = 0; i < repetitions; ++i) {
            ms.push_back(timer.time([&](VkCommandBuffer cmd) {
                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipe.pipeline.get());
                push(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipe.layout.get(), 0, 2, writes);
                vkCmdPushConstants(cmd, pipe.layout.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(pc), &pc);
                vkCmdDispatch(cmd, (width + tileX - 1) / tileX, (height + tileY - 1) / tileY, 1);
            }, evictCache));
        }
        results.push_back(summarize(name, bytes, ms));
    }
    return results;
}

}  // namespace skygraph::gpubench
