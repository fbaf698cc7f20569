// IblComputeProgram and helpers: see ibl_compute.hpp.
#include "ibl_compute.hpp"

namespace skygraph::passes::ibl {

const BoundResource* findSlot(const PipelineContext& ctx, std::string_view slot) {
    for (const auto& r : ctx.resources)
        if (r.usage && r.usage->slot == slot) return &r;
    return nullptr;
}

std::string storageQualifier(const PassDesc& pass, const BoundResource& resource) {
    switch (resource.format) {
        case VK_FORMAT_R16G16B16A16_SFLOAT: return "rgba16f";
        case VK_FORMAT_R32G32B32A32_SFLOAT: return "rgba32f";
        case VK_FORMAT_R16G16_SFLOAT: return "rg16f";
        case VK_FORMAT_R32G32_SFLOAT: return "rg32f";
        case VK_FORMAT_B10G11R11_UFLOAT_PACK32: return "r11f_g11f_b10f";
        default: break;
    }
    throw ExecutorError("pass '" + pass.name + "', resource '" + (resource.desc ? resource.desc->name : "?") +
                        "': the environment pipeline writes float images only (R16G16B16A16_SFLOAT, "
                        "R32G32B32A32_SFLOAT, R16G16_SFLOAT, R32G32_SFLOAT, B10G11R11_UFLOAT_PACK32)");
}

void IblComputeProgram::create(const PipelineContext& ctx, const std::string& shader, const BoundResource& storage,
                               bool hasSampledInput, uint32_t pushBytes) {
    ComputePipelineRecipe recipe;
    recipe.compute = compileShader(*ctx.shaders, VK_SHADER_STAGE_COMPUTE_BIT, shader,
                                   {{"OUT_FORMAT", storageQualifier(*ctx.desc, storage)}});
    if (hasSampledInput)
        recipe.bindings.push_back({0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    recipe.bindings.push_back({hasSampledInput ? 1u : 0u, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1,
                               VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    recipe.pushConstantBytes = pushBytes;
    pipeline_ = createComputePipeline(ctx.device, recipe);  // replaces the old one only on success
    pushDescriptors_ = pushDescriptorFunction(ctx.device);
    hasSampledInput_ = hasSampledInput;
}

void IblComputeProgram::bind(const RecordContext& ctx, const BoundResource* sampled, VkSampler sampler,
                             const BoundResource& storage) const {
    vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.pipeline.get());
    VkDescriptorImageInfo images[2]{};
    VkWriteDescriptorSet writes[2]{};
    uint32_t count = 0;
    if (hasSampledInput_) {
        images[count] = {sampler, sampled->view, sampled->usage->layout};
        writes[count] = sampledImageWrite(count, &images[count]);
        ++count;
    }
    images[count] = {VK_NULL_HANDLE, storage.view, storage.usage->layout};
    writes[count] = sampledImageWrite(count, &images[count]);
    writes[count].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    ++count;
    pushDescriptors_(ctx.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.layout.get(), 0, count, writes);
}

void IblComputeProgram::dispatch(VkCommandBuffer cmd, const void* push, uint32_t bytes, uint32_t width,
                                 uint32_t height, uint32_t layers) const {
    vkCmdPushConstants(cmd, pipeline_.layout.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, bytes, push);
    vkCmdDispatch(cmd, (width + 7) / 8, (height + 7) / 8, layers);
}

}  // namespace skygraph::passes::ibl
