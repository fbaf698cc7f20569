// Pipeline building blocks for pass implementations (the built-in passes, the executor's
// Generic pass, and embedding users' own passes): shader loading with defines, one
// graphics-pipeline recipe (dynamic viewport/scissor, push descriptors in set 0), the compute
// equivalent, and small recording helpers.
//
// Ownership: the create functions return RAII owners (vk_handles.hpp) of every object they
// make; the caller keeps them for as long as the pipeline is in use and must not destroy them
// while submitted work still uses them, and `device` must outlive them. Shader modules are
// temporary and destroyed before the create function returns. The recipes only borrow what
// they point to (the render pass), during the call. Every function that can fail throws
// ExecutorError and then leaves nothing behind.
#pragma once

#include <skygraph/device.hpp>
#include <skygraph/shader_compiler.hpp>
#include <skygraph/vk_handles.hpp>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace skygraph {

/// SPIR-V for shaders/<relativePath> (relative to `compiler.includeDir()`) with
/// `#define NAME VALUE` lines inserted right after the #version line; a copy the
/// caller owns. The text is ShaderCompiler::source()'s: read once, until the compiler's
/// clear(). Throws ExecutorError when it cannot be read or does not compile (with glslang's
/// log).
[[nodiscard]] std::vector<uint32_t> compileShader(ShaderCompiler& compiler, VkShaderStageFlagBits stage,
                                                  const std::string& relativePath,
                                                  const std::vector<std::pair<std::string, std::string>>& defines = {});

/// What createGraphicsPipeline builds: one subpass 0 of `renderPass`, triangle lists, filled
/// polygons, counter-clockwise front faces, one sample, dynamic viewport and scissor, and a
/// layout of one push-descriptor set 0 plus optional push constants at offset 0.
struct GraphicsPipelineRecipe {
    /// SPIR-V; entry point "main". An empty `fragment` builds a pipeline without a fragment
    /// stage (depth only: set `colorAttachments` to the subpass's, 0 for a depth-only one);
    /// `vertex` is required.
    std::vector<uint32_t> vertex, fragment;
    /// Borrowed; must be compatible at draw time. Required: a pass without attachment slots
    /// has none (PipelineContext::renderPass is null) and records compute or copies instead.
    VkRenderPass renderPass = VK_NULL_HANDLE;
    /// The subpass's color attachments: without `blends`, each is written unblended, all
    /// channels.
    uint32_t colorAttachments = 1;
    /// Per-attachment blend states; when not empty, one per color attachment (as many as
    /// `colorAttachments`, else createGraphicsPipeline throws).
    std::vector<VkPipelineColorBlendAttachmentState> blends;
    /// A logical operation between each output and its integer or normalized attachment,
    /// instead of blending (needs the device's logicOp feature, which Device enables where the
    /// device has it; not checked here, as only the VkDevice is given); none when
    /// empty. Float and sRGB attachments are written as they are.
    std::optional<VkLogicOp> logicOp;
    /// Depth test enabled: the attachment is read with `depthCompare` (ALWAYS keeps the read
    /// without letting earlier depth values decide what is drawn).
    bool depthTest = false;
    bool depthWrite = false;
    VkCompareOp depthCompare = VK_COMPARE_OP_ALWAYS;
    std::vector<VkVertexInputBindingDescription> vertexBindings;
    std::vector<VkVertexInputAttributeDescription> vertexAttributes;
    VkCullModeFlags cullMode = VK_CULL_MODE_NONE;
    /// Set 0, created with VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR.
    std::vector<VkDescriptorSetLayoutBinding> bindings;
    /// Push constants for the vertex and fragment stages, a multiple of 4 bytes; none when 0.
    uint32_t pushConstantBytes = 0;
};

/// The objects one pipeline needs, owned. Returned only once every step succeeded, so a
/// failed rebuild leaves the caller's previous pipeline untouched.
struct PipelineObjects {
    owned::SetLayout setLayout;
    owned::PipelineLayout layout;
    owned::Pipeline pipeline;
};
using GraphicsPipeline = PipelineObjects;
using ComputePipeline = PipelineObjects;

[[nodiscard]] GraphicsPipeline createGraphicsPipeline(VkDevice device, const GraphicsPipelineRecipe& recipe);

/// A compute pipeline with the same layout scheme: push-descriptor set 0 and optional push
/// constants (compute stage) at offset 0.
struct ComputePipelineRecipe {
    std::vector<uint32_t> compute;  ///< SPIR-V; entry point "main".
    std::vector<VkDescriptorSetLayoutBinding> bindings;
    uint32_t pushConstantBytes = 0;  ///< A multiple of 4; none when 0.
};

[[nodiscard]] ComputePipeline createComputePipeline(VkDevice device, const ComputePipelineRecipe& recipe);

/// Full-render-area viewport (depth 0..1) and scissor, for the dynamic state of the recipes.
void setViewportAndScissor(VkCommandBuffer cmd, VkExtent2D extent) noexcept;

/// vkCmdPushDescriptorSetKHR of `device`, valid while the device lives; look it up once (e.g.
/// when creating pipelines). Throws ExecutorError when VK_KHR_push_descriptor is not enabled.
[[nodiscard]] PFN_vkCmdPushDescriptorSetKHR pushDescriptorFunction(VkDevice device);

/// A combined image sampler write for binding `binding` of set 0; `info` is borrowed and must
/// stay valid until the write is pushed.
[[nodiscard]] VkWriteDescriptorSet sampledImageWrite(uint32_t binding, const VkDescriptorImageInfo* info) noexcept;

}  // namespace skygraph
