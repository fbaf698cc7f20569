// The Generic pass: what a planned pass does with each usage, and the GLSL that does it.
#pragma once

#include <skygraph/graph.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/plan.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace skygraph::passes {

enum class BindKind : uint8_t { SampledImage, StorageImage, StorageBuffer, UniformBuffer };

/// One push-descriptor binding of a generated shader.
struct ShaderBinding {
    uint32_t usage = 0;    ///< Index into PlannedPass::usages.
    uint32_t binding = 0;  ///< Binding number in set 0.
    BindKind kind = BindKind::SampledImage;
    VkShaderStageFlagBits stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    VkImageViewType viewType = VK_IMAGE_VIEW_TYPE_2D;
    bool read = false;
    bool write = false;
    std::string glslFormat;   ///< Storage-image format qualifier; empty for write-only.
    std::string scalarPrefix; ///< "", "u" or "i" for float, unsigned, signed formats.
    uint32_t uniformVec4s = 1;  ///< Uniform buffers: array length of uvec4.
    /// Storage images: the usage's mip count. A storage view addresses one level, so the
    /// binding is an array of one view per level and the shader reads and writes every one
    /// (docs/executor.md: every declared access is really performed, which synchronization
    /// validation can only check for subresources a bound view covers).
    uint32_t levels = 1;
};

/// How the Generic pass performs one planned pass: derived from usages only.
struct GenericProgram {
    std::vector<uint32_t> colors;  ///< Usage indices of color attachments, in order.
    int32_t depth = -1;            ///< Usage index of the depth attachment, or -1.
    std::vector<ShaderBinding> graphicsBindings;
    std::vector<ShaderBinding> computeBindings;
    std::vector<uint32_t> vertexBuffers;
    int32_t indexBuffer = -1;
    int32_t indirectBuffer = -1;
    std::vector<uint32_t> transfers;
    bool graphics = false;  ///< Needs a render pass and a draw.
    bool compute = false;   ///< Needs a dispatch.
    uint32_t attachmentLayers = 1;
    std::array<float, 4> color{0.25f, 0.5f, 0.75f, 1.0f};  ///< params.color
    float depthValue = 0.5f;                               ///< params.depth

    std::string vertexSource;
    std::string fragmentSource;
    std::string computeSource;
};

/// A Generic pass's params: { "color": [r, g, b, a], "depth": d }.
struct GenericParams {
    std::array<float, 4> color{0.25f, 0.5f, 0.75f, 1.0f};
    float depth = 0.5f;
};

/// `desc`'s params; `strict` makes malformed ones an error (the type Generic) instead of
/// being ignored (other pass types run as Generic). Throws ExecutorError naming the pass.
[[nodiscard]] GenericParams parseGenericParams(const PassDesc& desc, bool strict);

/// Analyzes `pass`, whose usages bind `resources` (parallel to them), and generates its
/// shaders. Throws ExecutorError naming the pass and the resource.
[[nodiscard]] GenericProgram buildGenericProgram(const PlannedPass& pass, std::span<const BoundResource> resources,
                                                 const GenericParams& params, bool layeredRendering);

}  // namespace skygraph::passes
