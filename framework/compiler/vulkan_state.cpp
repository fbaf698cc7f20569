#include "vulkan_state.hpp"

#include <array>

namespace skygraph {
namespace {

constexpr VkAccessFlags2 kWriteBits =
    VK_ACCESS_2_SHADER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT |
    VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
    VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_HOST_WRITE_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;

constexpr VkAccessFlags2 pick(Access a, VkAccessFlags2 read, VkAccessFlags2 write) {
    switch (a) {
        case Access::Read: return read;
        case Access::Write: return write;
        case Access::ReadWrite: return read | write;
    }
    return 0;
}

bool isDepthReadOnly(VkImageLayout l) {
    return l == VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL ||
           l == VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL ||
           l == VK_IMAGE_LAYOUT_STENCIL_READ_ONLY_OPTIMAL;
}

}  // namespace

VkAccessFlags2 writeBits(VkAccessFlags2 access) noexcept { return access & kWriteBits; }

VulkanScope vulkanScope(const ResourceDesc& r, const Usage& u) {
    return vulkanScope(scopeRow(aspectsOf(r)), u.access, u.stage, u.as);
}

namespace {

constexpr VulkanScope computeScope(const ResourceAspects& r, const Usage& u) {
    VulkanScope s;
    const BindAs as = resolvedBinding(u.mode(), r.image);
    switch (u.stage) {
        case Stage::ColorAttachment:
            s.stages = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
            s.access = pick(u.access, VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT,
                            VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
            s.layout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
            break;
        case Stage::DepthAttachment: {
            // Depth tests run in early and late fragment tests; which one a driver uses is its
            // choice, so both are in scope.
            s.stages = VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT |
                       VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
            s.access = pick(u.access, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT,
                            VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
            const bool ro = u.access == Access::Read;
            if (r.depth && r.stencil)
                s.layout = ro ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL
                              : VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
            else if (r.depth)
                s.layout = ro ? VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL
                              : VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
            else
                s.layout = ro ? VK_IMAGE_LAYOUT_STENCIL_READ_ONLY_OPTIMAL
                              : VK_IMAGE_LAYOUT_STENCIL_ATTACHMENT_OPTIMAL;
            break;
        }
        case Stage::Vertex:
        case Stage::Fragment:
        case Stage::Compute:
            s.stages = u.stage == Stage::Vertex     ? VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT
                       : u.stage == Stage::Fragment ? VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT
                                                    : VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
            if (as == BindAs::Sampled) {
                s.access = VK_ACCESS_2_SHADER_SAMPLED_READ_BIT;
                s.layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
            } else if (as == BindAs::Uniform) {
                s.access = VK_ACCESS_2_UNIFORM_READ_BIT;
            } else {
                s.access = pick(u.access, VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                                VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
                s.layout = VK_IMAGE_LAYOUT_GENERAL;
            }
            break;
        case Stage::Transfer:
            s.stages = VK_PIPELINE_STAGE_2_TRANSFER_BIT;
            s.access = pick(u.access, VK_ACCESS_2_TRANSFER_READ_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
            s.layout = u.access == Access::Read    ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL
                       : u.access == Access::Write ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL
                                                   : VK_IMAGE_LAYOUT_GENERAL;
            break;
        case Stage::VertexInput:
            if (u.as == BindAs::Index) {
                s.stages = VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT;
                s.access = VK_ACCESS_2_INDEX_READ_BIT;
            } else {
                s.stages = VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT;
                s.access = VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT;
            }
            break;
        case Stage::Indirect:
            s.stages = VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT;
            s.access = VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT;
            break;
    }
    if (!r.image) s.layout = VK_IMAGE_LAYOUT_UNDEFINED;
    return s;
}

}  // namespace

// Every combination (8 aspect sets x 120 usages) is worked out while skygraph is built; the
// compiler's per-usage vulkanScope is a lookup (vulkan_state.hpp).
constinit const std::array<VulkanScope, detail::kScopeTableSize> detail::kScopeTable = [] {
    std::array<VulkanScope, detail::kScopeTableSize> t{};
    size_t i = 0;
    for (int aspects = 0; aspects < 8; ++aspects)
        for (size_t stage = 0; stage < kScopeStages; ++stage)
            for (size_t access = 0; access < kScopeAccesses; ++access)
                for (size_t as = 0; as < kScopeBindAs; ++as)
                    t[i++] = computeScope({(aspects & 1) != 0, (aspects & 2) != 0, (aspects & 4) != 0},
                                          {static_cast<Access>(access), static_cast<Stage>(stage),
                                           static_cast<BindAs>(as), std::nullopt});
    return t;
}();

VulkanScope externalScope(const ResourceDesc& r, ExternalState state) {
    VulkanScope s;
    const VkPipelineStageFlags2 shaders =
        VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    switch (state) {
        case ExternalState::None: break;
        case ExternalState::Present:
            // The presentation engine waits on a semaphore, not on a pipeline stage.
            s.layout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
            break;
        case ExternalState::TransferSrc:
            s = {VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                 VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL};
            break;
        case ExternalState::ShaderRead:
            s = {shaders,
                 r.isImage() ? VK_ACCESS_2_SHADER_SAMPLED_READ_BIT : VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                 VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
            break;
        case ExternalState::General:
            s = {shaders, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                 VK_IMAGE_LAYOUT_GENERAL};
            break;
    }
    if (!r.isImage()) s.layout = VK_IMAGE_LAYOUT_UNDEFINED;
    return s;
}

namespace {

/// optimalCommonReadLayout's answer, inlined into commonReadLayout too: rule 4 asks that of
/// every join of a read run under either policy.
inline VkImageLayout sharedOptimalReadLayout(VkImageLayout a, VkImageLayout b) {
    if (a == b) return a;
    // Depth read-only layouts also allow sampling (§12.4 "Image Layouts"), so they serve a
    // sampled read as well as SHADER_READ_ONLY_OPTIMAL would.
    if (isDepthReadOnly(a) && b == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL) return a;
    if (isDepthReadOnly(b) && a == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL) return b;
    return VK_IMAGE_LAYOUT_UNDEFINED;
}

}  // namespace

VkImageLayout optimalCommonReadLayout(VkImageLayout a, VkImageLayout b) { return sharedOptimalReadLayout(a, b); }

VkImageLayout commonReadLayout(VkImageLayout a, VkImageLayout b) {
    const VkImageLayout optimal = sharedOptimalReadLayout(a, b);
    return optimal != VK_IMAGE_LAYOUT_UNDEFINED || a == b ? optimal : VK_IMAGE_LAYOUT_GENERAL;
}

}  // namespace skygraph
