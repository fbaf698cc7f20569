// Pipeline building blocks for pass implementations; see include/skygraph/pipeline_builder.hpp.
#include <skygraph/pipeline_builder.hpp>

#include "vk_util.hpp"

#include <algorithm>
#include <array>
#include <string>

namespace skygraph {

std::vector<uint32_t> compileShader(ShaderCompiler& compiler, VkShaderStageFlagBits stage,
                                    const std::string& relativePath,
                                    const std::vector<std::pair<std::string, std::string>>& defines) {
    if (defines.empty()) return compiler.compileFile(stage, relativePath);
    // Right after the #version directive, which only comments and blank lines may precede;
    // #extension lines may follow a #define (both are preprocessor directives). Without one,
    // first.
    std::string definitions;
    for (const auto& [name, value] : defines) definitions += "#define " + name + " " + value + "\n";
    std::string source = compiler.source(relativePath);
    size_t at = 0;
    for (size_t line = 0; line < source.size();) {
        const size_t end = std::min(source.find('\n', line), source.size());
        const size_t text = source.find_first_not_of(" \t", line);
        if (text < end && source.compare(text, 8, "#version") == 0) {
            at = end == source.size() ? end : end + 1;
            break;
        }
        line = end + 1;
    }
    if (at == source.size() && !source.empty() && source.back() != '\n') {  // #version ends the file
        source += '\n';
        at = source.size();
    }
    source.insert(at, definitions);
    std::string name = relativePath;
    for (const auto& [n, v] : defines) name += " " + n + "=" + v;
    return compiler.compile(stage, source, name);
}

namespace {

/// Push-descriptor set 0 and the pipeline layout over it, owned by `setLayout`/`layout`.
void createLayouts(VkDevice device, const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                   VkShaderStageFlags pushStages, uint32_t pushConstantBytes, owned::SetLayout& setLayout,
                   owned::PipelineLayout& layout) {
    VkDescriptorSetLayoutCreateInfo sli{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    sli.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
    sli.bindingCount = static_cast<uint32_t>(bindings.size());
    sli.pBindings = bindings.data();
    VkDescriptorSetLayout set;
    vk::check(vkCreateDescriptorSetLayout(device, &sli, nullptr, &set), "vkCreateDescriptorSetLayout");
    setLayout = owned::SetLayout(device, set);

    VkPushConstantRange range{pushStages, 0, pushConstantBytes};
    VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pli.setLayoutCount = 1;
    pli.pSetLayouts = &set;
    pli.pushConstantRangeCount = pushConstantBytes ? 1 : 0;
    pli.pPushConstantRanges = &range;
    VkPipelineLayout l;
    vk::check(vkCreatePipelineLayout(device, &pli, nullptr, &l), "vkCreatePipelineLayout");
    layout = owned::PipelineLayout(device, l);
}

/// Code a stage can be built from: checked here, as Vulkan would take empty or foreign code as
/// undefined behaviour (a driver may crash on it).
void requireSpirv(const std::vector<uint32_t>& code, const char* function, const char* stage) {
    constexpr uint32_t kSpirvMagic = 0x07230203;
    if (code.empty())
        throw ExecutorError(std::string(function) + ": the recipe has no " + stage + " shader");
    if (code.front() != kSpirvMagic)
        throw ExecutorError(std::string(function) + ": the recipe's " + stage + " shader is not SPIR-V");
}

/// Vulkan takes push constant sizes in multiples of 4 bytes (VUID-VkPushConstantRange-size-00297).
void requirePushConstantSize(uint32_t bytes, const char* function) {
    if (bytes % 4 != 0)
        throw ExecutorError(std::string(function) + ": the recipe's pushConstantBytes (" + std::to_string(bytes) +
                            ") is not a multiple of 4");
}

owned::ShaderModule shaderModule(VkDevice device, const std::vector<uint32_t>& code) {
    VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    mi.codeSize = code.size() * 4;
    mi.pCode = code.data();
    VkShaderModule m;
    vk::check(vkCreateShaderModule(device, &mi, nullptr, &m), "vkCreateShaderModule");
    return owned::ShaderModule(device, m);
}

}  // namespace

GraphicsPipeline createGraphicsPipeline(VkDevice device, const GraphicsPipelineRecipe& recipe) {
    requireSpirv(recipe.vertex, "createGraphicsPipeline", "vertex");
    const bool fragmentStage = !recipe.fragment.empty();
    if (fragmentStage) requireSpirv(recipe.fragment, "createGraphicsPipeline", "fragment");
    if (recipe.renderPass == VK_NULL_HANDLE)
        throw ExecutorError("createGraphicsPipeline: the recipe has no render pass (a pass without attachment slots has "
                            "none, and records compute or copies instead)");
    requirePushConstantSize(recipe.pushConstantBytes, "createGraphicsPipeline");
    if (!recipe.blends.empty() && recipe.blends.size() != recipe.colorAttachments)
        throw ExecutorError("createGraphicsPipeline: the recipe has " + std::to_string(recipe.blends.size()) +
                            " blend state(s) for " + std::to_string(recipe.colorAttachments) +
                            " color attachment(s); give one per attachment of the subpass");
    GraphicsPipeline out;
    createLayouts(device, recipe.bindings, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                  recipe.pushConstantBytes, out.setLayout, out.layout);
    const VkPipelineLayout layout = out.layout.get();

    const owned::ShaderModule vs = shaderModule(device, recipe.vertex);
    const owned::ShaderModule fs = fragmentStage ? shaderModule(device, recipe.fragment) : owned::ShaderModule();
    std::array<VkPipelineShaderStageCreateInfo, 2> stages{};
    stages[0] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0,
                 VK_SHADER_STAGE_VERTEX_BIT, vs.get(), "main", nullptr};
    stages[1] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0,
                 VK_SHADER_STAGE_FRAGMENT_BIT, fs.get(), "main", nullptr};

    VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    vi.vertexBindingDescriptionCount = static_cast<uint32_t>(recipe.vertexBindings.size());
    vi.pVertexBindingDescriptions = recipe.vertexBindings.data();
    vi.vertexAttributeDescriptionCount = static_cast<uint32_t>(recipe.vertexAttributes.size());
    vi.pVertexAttributeDescriptions = recipe.vertexAttributes.data();
    VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    vp.viewportCount = 1;
    vp.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    rs.polygonMode = VK_POLYGON_MODE_FILL;
    rs.cullMode = recipe.cullMode;
    rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    rs.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    ds.depthTestEnable = recipe.depthTest;
    ds.depthWriteEnable = recipe.depthWrite;
    ds.depthCompareOp = recipe.depthCompare;
    std::vector<VkPipelineColorBlendAttachmentState> blends = recipe.blends;
    if (blends.empty()) {
        blends.resize(recipe.colorAttachments);
        for (auto& b : blends) b.colorWriteMask = 0xf;
    }
    VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    cb.attachmentCount = static_cast<uint32_t>(blends.size());
    cb.pAttachments = blends.data();
    if (recipe.logicOp) {
        cb.logicOpEnable = VK_TRUE;
        cb.logicOp = *recipe.logicOp;
    }
    const std::array<VkDynamicState, 2> dynamics{VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dyn{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dyn.dynamicStateCount = static_cast<uint32_t>(dynamics.size());
    dyn.pDynamicStates = dynamics.data();

    VkGraphicsPipelineCreateInfo gi{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    gi.stageCount = fragmentStage ? 2 : 1;
    gi.pStages = stages.data();
    gi.pVertexInputState = &vi;
    gi.pInputAssemblyState = &ia;
    gi.pViewportState = &vp;
    gi.pRasterizationState = &rs;
    gi.pMultisampleState = &ms;
    gi.pDepthStencilState = &ds;
    gi.pColorBlendState = &cb;
    gi.pDynamicState = &dyn;
    gi.layout = layout;
    gi.renderPass = recipe.renderPass;
    VkPipeline pipeline;
    vk::check(vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &gi, nullptr, &pipeline),
              "vkCreateGraphicsPipelines");
    out.pipeline = owned::Pipeline(device, pipeline);
    return out;
}

ComputePipeline createComputePipeline(VkDevice device, const ComputePipelineRecipe& recipe) {
    requireSpirv(recipe.compute, "createComputePipeline", "compute");
    requirePushConstantSize(recipe.pushConstantBytes, "createComputePipeline");
    ComputePipeline out;
    createLayouts(device, recipe.bindings, VK_SHADER_STAGE_COMPUTE_BIT, recipe.pushConstantBytes,
                  out.setLayout, out.layout);
    const owned::ShaderModule cs = shaderModule(device, recipe.compute);
    VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    ci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0,
                VK_SHADER_STAGE_COMPUTE_BIT, cs.get(), "main", nullptr};
    ci.layout = out.layout.get();
    VkPipeline pipeline;
    vk::check(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline),
              "vkCreateComputePipelines");
    out.pipeline = owned::Pipeline(device, pipeline);
    return out;
}

void setViewportAndScissor(VkCommandBuffer cmd, VkExtent2D extent) noexcept {
    const VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
}

PFN_vkCmdPushDescriptorSetKHR pushDescriptorFunction(VkDevice device) {
    auto fn = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(
        vkGetDeviceProcAddr(device, "vkCmdPushDescriptorSetKHR"));
    if (!fn) throw ExecutorError("VK_KHR_push_descriptor is not enabled on this device");
    return fn;
}

VkWriteDescriptorSet sampledImageWrite(uint32_t binding, const VkDescriptorImageInfo* info) noexcept {
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstBinding = binding;
    w.descriptorCount = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    w.pImageInfo = info;
    return w;
}

}  // namespace skygraph
