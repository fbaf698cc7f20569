// The one place where plan barriers become Vulkan barrier structs (tests/executor's
// single_barrier_translation check keeps it so). A batch is translated once, when a plan is
// installed, and recorded by every frame as one vkCmdPipelineBarrier2.
#pragma once

#include <skygraph/plan.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
#include <functional>
#include <span>
#include <vector>

namespace skygraph::detail {

/// What a barrier's resource is in Vulkan for one frame slot.
struct BarrierTarget {
    VkImage image = VK_NULL_HANDLE;
    VkBuffer buffer = VK_NULL_HANDLE;
    VkImageAspectFlags aspect = 0;
};

/// A plan's barrier batch in Vulkan's form. Holds no handles it owns; valid while the images
/// and buffers it names live.
class BarrierBatch {
public:
    BarrierBatch() = default;
    /// Translates `barriers`; `target(resource)` gives the handles of a barrier's plan resource,
    /// `families` the queue family of each queue kind, for ownership transfers. Throws
    /// ExecutorError when a barrier's kind does not match its resource, or when it transfers
    /// ownership between kinds of one family (a plan compiled for other queue families).
    BarrierBatch(std::span<const Barrier> barriers, const std::function<BarrierTarget(uint32_t)>& target,
                 const std::array<uint32_t, kQueueKinds>& families);

    [[nodiscard]] bool empty() const noexcept { return images_.empty() && buffers_.empty() && memory_.empty(); }
    /// For vkCmdPipelineBarrier2; points into this batch, valid while it lives unchanged.
    [[nodiscard]] VkDependencyInfo dependencyInfo() const noexcept;
    [[nodiscard]] const std::vector<VkImageMemoryBarrier2>& images() const noexcept { return images_; }
    [[nodiscard]] const std::vector<VkBufferMemoryBarrier2>& buffers() const noexcept { return buffers_; }
    [[nodiscard]] const std::vector<VkMemoryBarrier2>& memory() const noexcept { return memory_; }

private:
    std::vector<VkImageMemoryBarrier2> images_;
    std::vector<VkBufferMemoryBarrier2> buffers_;
    std::vector<VkMemoryBarrier2> memory_;
};

}  // namespace skygraph::detail
