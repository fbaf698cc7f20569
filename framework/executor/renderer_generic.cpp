// Renderer::Impl: the Generic pass (and pass types run as Generic): pipelines built with the
// public pipeline recipe. Its recording is in frame_recording.cpp.
#include "renderer_impl.hpp"

namespace skygraph {

using namespace detail;

std::vector<VkDescriptorSetLayoutBinding> Renderer::Impl::layoutBindings(const std::vector<ShaderBinding>& bindings) {
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

void Renderer::Impl::buildGraphicsPipeline(PlanState& s, PassState& ps) {
    const PlannedPass& pass = *ps.pass;
    const GenericProgram& p = ps.program;
    GraphicsPipelineRecipe recipe;
    recipe.bindings = layoutBindings(p.graphicsBindings);
    recipe.pushConstantBytes = 16;
    recipe.vertex = shaders.compile(VK_SHADER_STAGE_VERTEX_BIT, p.vertexSource, ps.label + ".vert");
    recipe.fragment = shaders.compile(VK_SHADER_STAGE_FRAGMENT_BIT, p.fragmentSource, ps.label + ".frag");
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

void Renderer::Impl::buildCompute(PassState& ps) {
    const GenericProgram& p = ps.program;
    ComputePipelineRecipe recipe;
    recipe.bindings = layoutBindings(p.computeBindings);
    recipe.pushConstantBytes = 16;
    recipe.compute = shaders.compile(VK_SHADER_STAGE_COMPUTE_BIT, p.computeSource, ps.label + ".comp");
    ComputePipeline built = createComputePipeline(vkd, recipe);
    ps.computeSetLayout = std::move(built.setLayout);
    ps.computeLayout = std::move(built.layout);
    ps.computePipeline = std::move(built.pipeline);
}

}  // namespace skygraph
