// The one place that maps graph-file usages to Vulkan stages, accesses and layouts.
// The synchronizer reads it; which usages are possible at all is usage_fit.hpp's.
#pragma once

#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>
#include <skygraph/usage.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace skygraph {

/// A synchronization scope plus the layout an image must be in for it.
struct VulkanScope {
    VkPipelineStageFlags2 stages = 0;
    VkAccessFlags2 access = 0;  ///< Only the kinds of access the usage performs.
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
};

/// What the mapping below asks of a resource: kept apart by the compiler's sweeps, which would
/// otherwise read a whole ResourceDesc per usage.
struct ResourceAspects {
    bool image = false;
    bool depth = false;
    bool stencil = false;
};
[[nodiscard]] inline ResourceAspects aspectsOf(const ResourceDesc& r) noexcept {
    return {r.isImage(), r.format.hasDepth, r.format.hasStencil};
}

namespace detail {
inline constexpr size_t kScopeAccesses = 3, kScopeStages = 8, kScopeBindAs = 5;
inline constexpr size_t kScopeTableSize = 8 * kScopeStages * kScopeAccesses * kScopeBindAs;
/// vulkanScope of every usage (range aside) for every aspect set, built at compile time.
extern const std::array<VulkanScope, kScopeTableSize> kScopeTable;
}  // namespace detail

/// Stages, accesses and layout of a valid usage. Buffers get layout UNDEFINED.
[[nodiscard]] VulkanScope vulkanScope(const ResourceDesc& resource, const Usage& usage);
/// A resource's aspects as the table's row, which the compiler keeps per resource rather than
/// combine three flags at every usage.
enum class ScopeRow : uint8_t {};
[[nodiscard]] inline ScopeRow scopeRow(const ResourceAspects& r) noexcept {
    return ScopeRow(uint8_t(r.image) | uint8_t(r.depth) << 1 | uint8_t(r.stencil) << 2);
}
/// The same, inline, for a resource's row: the compiler asks it once per usage, with `access`
/// in place of the usage's own when a load-op clear makes a read a read-write. (The fields are
/// passed one by one: a copy of the Usage with one byte changed and then read whole stalls the
/// store forwarding of the CPU's load unit, measurably so at one usage per call.)
[[nodiscard]] inline VulkanScope vulkanScope(ScopeRow row, Access access, Stage stage, BindAs as) noexcept {
    return detail::kScopeTable[((size_t(row) * detail::kScopeStages + size_t(stage)) * detail::kScopeAccesses +
                                size_t(access)) * detail::kScopeBindAs + size_t(as)];
}

/// The scope of an external state: where `initial` contents are visible, and what a
/// `final` barrier must make them visible to (docs/barriers.md has the table).
[[nodiscard]] VulkanScope externalScope(const ResourceDesc& resource, ExternalState state);

/// One layout that serves two reads of the same image, for runs of reads (GENERAL if no
/// read-only layout serves both).
[[nodiscard]] VkImageLayout commonReadLayout(VkImageLayout a, VkImageLayout b);
/// One layout optimal for both of two reads of the same image, for runs of reads under
/// LayoutPolicy::Optimal: their own when they agree, a depth read-only layout for a depth test
/// and sampling; UNDEFINED when there is none (then commonReadLayout would be GENERAL).
[[nodiscard]] VkImageLayout optimalCommonReadLayout(VkImageLayout a, VkImageLayout b);

/// The write bits of an access mask: the part that needs making available.
[[nodiscard]] VkAccessFlags2 writeBits(VkAccessFlags2 access) noexcept;

/// The final barrier after a read-back's copy of resource r: the host reads the copy once
/// the plan's fence has signalled, so its writes are made available to the host domain.
[[nodiscard]] inline Barrier hostReadAfterCopy(uint32_t r) noexcept {
    Barrier b;
    b.resource = r;
    b.kind = BarrierKind::Memory;
    b.srcStages = VK_PIPELINE_STAGE_2_TRANSFER_BIT;
    b.srcAccess = VK_ACCESS_2_TRANSFER_WRITE_BIT;
    b.dstStages = VK_PIPELINE_STAGE_2_HOST_BIT;
    b.dstAccess = VK_ACCESS_2_HOST_READ_BIT;
    return b;
}

}  // namespace skygraph
