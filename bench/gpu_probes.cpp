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

// tonemap.frag's body, one invocation per pixel instead of one fragment.
constexpr const char* kTonemapShader = R"(#version 450
#extension GL_GOOGLE_include_directive : require
#include "common/tonemap.glsl"
layout(local_size_x = GROUP_X, local_size_y = GROUP_Y) in;
layout(set = 0, binding = 0) uniform sampler2D hdrInput;
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D outImage;
layout(push_constant) uniform Params { float exposureEv; int toneOperator; int encodeSrgb; } params;
void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(outImage)))) return;
    vec3 c = tonemap(texelFetch(hdrInput, p, 0).rgb, params.exposureEv, params.toneOperator);
    if (params.encodeSrgb != 0) c = srgbEncode(c);
    imageStore(outImage, p, vec4(c, 1.0));
})";

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
/// for one descriptor; `buffers` are bound at bindings 0.. with the same offsets.
void dispatchOverBuffers(VkCommandBuffer cmd, Device& device, const ComputePipeline& pipe,
                         PFN_vkCmdPushDescriptorSetKHR push, const std::vector<VkBuffer>& buffers,
                         uint64_t bytes, uint32_t seed) {
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
    std::vector<double> copyMs, computeMs;
    for (uint32_t i = 0; i < repetitions; ++i) {
        copyMs.push_back(timer.time([&](VkCommandBuffer cmd) {
            const VkBufferCopy region{0, 0, bytes};
            vkCmdCopyBuffer(cmd, src.buffer.get(), dst.buffer.get(), 1, &region);
        }));
        computeMs.push_back(timer.time([&](VkCommandBuffer cmd) {
            dispatchOverBuffers(cmd, device, copy, push, {src.buffer.get(), dst.buffer.get()}, bytes, 0);
        }));
    }
    return {summarize("copy_buffer", moved, copyMs), summarize("compute_copy_uvec4", moved, computeMs)};
}

std::vector<ProbeResult> measureComputeTonemap(Device& device, uint32_t width, uint32_t height,
                                               uint32_t repetitions) {
    const VkExtent2D extent{width, height};
    const DeviceImage hdr = createDeviceImage(device, VK_FORMAT_R16G16B16A16_SFLOAT, extent,
                                              VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
    const DeviceImage out = createDeviceImage(device, VK_FORMAT_R8G8B8A8_UNORM, extent, VK_IMAGE_USAGE_STORAGE_BIT);
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSampler rawSampler;
    vk::check(vkCreateSampler(device.device(), &sci, nullptr, &rawSampler), "vkCreateSampler");
    const vk::Sampler sampler(device.device(), rawSampler);

    ShaderCompiler compiler(ShaderCompiler::defaultIncludeDir());
    const auto push = pushDescriptorFunction(device.device());
    const VkDescriptorSetLayoutBinding storage0{0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    const ComputePipeline fill = computePipeline(device, compiler, kHdrFillShader, "hdr fill", {storage0}, 0);
    GpuTimer timer(device);
    const VkDescriptorImageInfo hdrStorage{VK_NULL_HANDLE, hdr.view.get(), VK_IMAGE_LAYOUT_GENERAL};
    timer.run([&](VkCommandBuffer cmd) {
        transitionImage(cmd, hdr.image.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
        transitionImage(cmd, out.image.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, fill.pipeline.get());
        const VkWriteDescriptorSet w = imageWrite(0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, &hdrStorage);
        push(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, fill.layout.get(), 0, 1, &w);
        vkCmdDispatch(cmd, (width + 7) / 8, (height + 7) / 8, 1);
        transitionImage(cmd, hdr.image.get(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    });

    const VkDescriptorSetLayoutBinding sampled0{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1,
                                                VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    const VkDescriptorSetLayoutBinding storage1{1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    const VkDescriptorImageInfo hdrSampled{sampler.get(), hdr.view.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    const VkDescriptorImageInfo outStorage{VK_NULL_HANDLE, out.view.get(), VK_IMAGE_LAYOUT_GENERAL};
    const double bytes = 12.0 * width * height;
    std::vector<ProbeResult> results;
    for (const auto& [gx, gy] : {std::pair{8u, 8u}, std::pair{16u, 16u}, std::pair{32u, 8u}}) {
        const std::string defines = "#define GROUP_X " + std::to_string(gx) + "\n#define GROUP_Y " + std::to_string(gy) + "\n";
        const std::string name = "tonemap_compute_" + std::to_string(gx) + "x" + std::to_string(gy);
        const ComputePipeline pipe = computePipeline(device, compiler, withDefines(kTonemapShader, defines), name,
                                                     {sampled0, storage1}, 12);
        const VkWriteDescriptorSet writes[2] = {
            imageWrite(0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &hdrSampled),
            imageWrite(1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, &outStorage)};
        const struct { float exposureEv; int32_t op; int32_t encodeSrgb; } pc{0.0f, 0, 1};
        std::vector<double> ms;
        for (uint32_t i = 0; i < repetitions; ++i) {
            ms.push_back(timer.time([&](VkCommandBuffer cmd) {
                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipe.pipeline.get());
                push(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipe.layout.get(), 0, 2, writes);
                vkCmdPushConstants(cmd, pipe.layout.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(pc), &pc);
                vkCmdDispatch(cmd, (width + gx - 1) / gx, (height + gy - 1) / gy, 1);
            }));
        }
        results.push_back(summarize(name, bytes, ms));
    }
    return results;
}

}  // namespace skygraph::gpubench
