// The one place that maps graph-file usages to Vulkan stages, accesses and layouts.
// Both the loader (to reject impossible usages) and the synchronizer read it.
#pragma once

#include <skygraph/graph.hpp>
#include <skygraph/usage.hpp>

#include <vulkan/vulkan_core.h>

#include <string>

namespace skygraph {

/// A synchronization scope plus the layout an image must be in for it.
struct VulkanScope {
    VkPipelineStageFlags2 stages = 0;
    VkAccessFlags2 access = 0;  ///< Only the kinds of access the usage performs.
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
};

/// Empty when the usage is possible for the resource; otherwise why not, in words that name
/// the expected usage (e.g. a depth format used as a color attachment).
[[nodiscard]] std::string usageProblem(const ResourceDesc& resource, const Usage& usage);

/// The `as` a usage gets when the file leaves it out (contract §1).
[[nodiscard]] BindAs resolveBindAs(const ResourceDesc& resource, const Usage& usage);

/// What the mapping below asks of a resource: kept apart by the compiler's sweeps, which would
/// otherwise read a whole ResourceDesc per usage.
struct ResourceAspects {
    bool image = false;
    bool depth = false;
    bool stencil = false;
};
[[nodiscard]] ResourceAspects aspectsOf(const ResourceDesc& resource) noexcept;

/// Stages, accesses and layout of a valid usage. Buffers get layout UNDEFINED.
[[nodiscard]] VulkanScope vulkanScope(const ResourceDesc& resource, const Usage& usage);
[[nodiscard]] VulkanScope vulkanScope(const ResourceAspects& resource, const Usage& usage);

/// The scope of an external state: where `initial` contents are visible, and what a
/// `final` barrier must make them visible to (docs/barriers.md has the table).
[[nodiscard]] VulkanScope externalScope(const ResourceDesc& resource, ExternalState state);

/// One layout that serves two reads of the same image, for runs of reads (GENERAL if no
/// read-only layout serves both).
[[nodiscard]] VkImageLayout commonReadLayout(VkImageLayout a, VkImageLayout b);

/// The write bits of an access mask: the part that needs making available.
[[nodiscard]] VkAccessFlags2 writeBits(VkAccessFlags2 access) noexcept;

}  // namespace skygraph
