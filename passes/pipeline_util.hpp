// Pipeline plumbing shared by the built-in passes: shader loading with defines, and one
// graphics-pipeline recipe (dynamic viewport/scissor, push descriptors in set 0).
#pragma once

#include "vk_util.hpp"

#include <skygraph/shader_compiler.hpp>

#include <string>
#include <utility>
#include <vector>

namespace skygraph::passes {

/// SPIR-V for shaders/<relativePath> with `#define NAME VALUE` lines inserted after the
/// #version and #extension lines. Throws ExecutorError with glslang's log.
[[nodiscard]] std::vector<uint32_t> compileShader(ShaderCompiler& compiler, VkShaderStageFlagBits stage,
                                                  const std::string& relativePath,
                                                  const std::vector<std::pair<std::string, std::string>>& defines = {});

struct GraphicsPipelineRecipe {
    std::vector<uint32_t> vertex, fragment;
    VkRenderPass renderPass = VK_NULL_HANDLE;
    uint32_t colorAttachments = 1;
    bool depthTest = false;
    bool depthWrite = false;
    VkCompareOp depthCompare = VK_COMPARE_OP_ALWAYS;
    std::vector<VkVertexInputBindingDescription> vertexBindings;
    std::vector<VkVertexInputAttributeDescription> vertexAttributes;
    VkCullModeFlags cullMode = VK_CULL_MODE_NONE;
    /// Set 0, created with VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR.
    std::vector<VkDescriptorSetLayoutBinding> bindings;
    uint32_t pushConstantBytes = 0;
};

/// The objects one pipeline needs; moved into a pass once every step succeeded, so a failed
/// rebuild leaves the previous pipeline untouched.
struct GraphicsPipeline {
    vk::SetLayout setLayout;
    vk::PipelineLayout layout;
    vk::Pipeline pipeline;
};

[[nodiscard]] GraphicsPipeline createGraphicsPipeline(VkDevice device, const GraphicsPipelineRecipe& recipe);

/// Full-render-area viewport and scissor.
void setViewportAndScissor(VkCommandBuffer cmd, VkExtent2D extent);

/// vkCmdPushDescriptorSetKHR, looked up once per device.
[[nodiscard]] PFN_vkCmdPushDescriptorSetKHR pushDescriptorFunction(VkDevice device);

/// A combined image sampler write for binding `binding` of set 0.
[[nodiscard]] VkWriteDescriptorSet sampledImageWrite(uint32_t binding, const VkDescriptorImageInfo* info);

}  // namespace skygraph::passes
