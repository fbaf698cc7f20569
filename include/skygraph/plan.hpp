// The compiler's output: what runs, in which order, and every barrier between.
// The executor records exactly this and derives no synchronization of its own.
#pragma once

#include <skygraph/condition.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/usage.hpp>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <string>
#include <vector>

namespace skygraph {

enum class BarrierKind : uint8_t { Image, Buffer, Memory };

/// One VkImageMemoryBarrier2 / VkBufferMemoryBarrier2 / VkMemoryBarrier2.
struct Barrier {
    uint32_t resource = 0;  ///< Index into Plan::resources.
    BarrierKind kind = BarrierKind::Image;
    VkPipelineStageFlags2 srcStages = 0;
    VkAccessFlags2 srcAccess = 0;
    VkPipelineStageFlags2 dstStages = 0;
    VkAccessFlags2 dstAccess = 0;
    VkImageLayout oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;  ///< Images only.
    VkImageLayout newLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    SubresourceRange range;  ///< Images only; buffers are always whole.

    friend bool operator==(const Barrier&, const Barrier&) = default;
};

/// What a render pass does with an attachment at its start and end.
enum class LoadOp : uint8_t { Load, Clear, DontCare };
enum class StoreOp : uint8_t { Store, DontCare, None };

/// A usage with everything Vulkan needs to perform it.
struct PlannedUsage {
    uint32_t resource = 0;  ///< Index into Plan::resources.
    Usage usage;            ///< As written, with the range resolved.
    std::string slot;
    SubresourceRange range;
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;  ///< Layout during the pass.
    VkPipelineStageFlags2 stages = 0;
    VkAccessFlags2 access = 0;
    /// Attachments only. Clear when this is the first use of a `clear` resource.
    LoadOp load = LoadOp::Load;
    /// Attachments only: Store when a later pass or the export reads the result.
    StoreOp store = StoreOp::Store;
};

struct PlannedPass {
    std::string name;
    std::string type;      ///< Pass type; "Clear" for a clear inserted by the compiler.
    int32_t declIndex = -1;  ///< Index into GraphDesc::passes; -1 for inserted passes.
    std::vector<Barrier> barriers;  ///< One vkCmdPipelineBarrier2 batch, before the pass.
    std::vector<PlannedUsage> usages;
};

/// A resource that at least one scheduled pass uses. Unused resources are not listed.
struct PlannedResource {
    uint32_t decl = 0;        ///< Index into GraphDesc::resources.
    std::string name;
    uint32_t firstPass = 0;   ///< Indices into Plan::passes: the lifetime.
    uint32_t lastPass = 0;
    /// Layout the resource must be in when the frame starts (external resources), and the
    /// stages that the frame's first access waits in (for semaphores at the frame's start).
    VkImageLayout initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkPipelineStageFlags2 firstStages = 0;
    /// Layout after the final barriers; the next frame's `initialLayout` for externals.
    VkImageLayout finalLayout = VK_IMAGE_LAYOUT_UNDEFINED;
};

struct CulledPass {
    std::string name;
    std::string reason;
};

struct Plan {
    std::string graph;
    FeatureValues features;
    std::vector<PlannedResource> resources;
    std::vector<PlannedPass> passes;
    std::vector<Barrier> finalBarriers;
    std::vector<CulledPass> culled;

    /// Index into `resources` for a graph resource, or -1 when no scheduled pass uses it.
    [[nodiscard]] int32_t resourceIndex(std::string_view name) const noexcept;
};

}  // namespace skygraph
