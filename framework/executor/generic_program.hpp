// The Generic pass: what a planned pass does with each usage, and the GLSL that does it.
#pragma once

#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace skygraph {

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

/// Analyzes `pass` of `plan` and generates its shaders. `params` are the pass's params
/// (color, depth); `strictParams` makes malformed ones an error (Generic) instead of being
/// ignored (other pass types run as Generic). Throws ExecutorError naming the pass.
[[nodiscard]] GenericProgram buildGenericProgram(const GraphDesc& graph, const Plan& plan,
                                                 const PlannedPass& pass,
                                                 const nlohmann::json& params, bool strictParams,
                                                 bool layeredRendering);

/// Whether a format stores unsigned ("u") or signed ("i") integers, else "".
[[nodiscard]] std::string scalarPrefix(VkFormat format);

/// Bytes of one texel of `format` filled with `color` (depth formats take color.x), for the
/// transfer writes of the Generic pass. Unknown encodings yield zero bytes.
[[nodiscard]] std::vector<uint8_t> encodeTexel(VkFormat format, uint32_t texelBytes,
                                               const std::array<float, 4>& color);

namespace detail {
/// "pass 'P', resource 'R': what" (", resource" only when `resource` is set): how the
/// executor's errors name what they are about.
inline std::string passError(const PlannedPass& pass, const std::string& resource, const std::string& what) {
    std::string s = "pass '" + std::string(pass.name) + "'";
    if (!resource.empty()) s += ", resource '" + resource + "'";
    return s + ": " + what;
}
}  // namespace detail

}  // namespace skygraph
