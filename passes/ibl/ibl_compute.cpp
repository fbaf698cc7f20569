// IblComputeProgram and helpers: see ibl_compute.hpp.
#include "ibl_compute.hpp"
#include "ibl_formats.hpp"

namespace skygraph::passes::ibl {

const BoundResource* findSlot(const PipelineContext& ctx, std::string_view slot) {
    for (const auto& r : ctx.resources)
        if (r.usage && r.usage->slot == slot) return &r;
    return nullptr;
}

std::string storageQualifier(const PassDesc& pass, const BoundResource& resource) {
    // The loader refuses other formats for a graph file; a GraphDesc built in code meets this.
    if (const char* qualifier = iblStorageQualifier(resource.format)) return qualifier;
    throw ExecutorError("pass '" + pass.name + "', resource '" + (resource.desc ? resource.desc->name : "?") +
                        "': " + iblStorageProblem(pass.type, formatName(resource.format)));
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
