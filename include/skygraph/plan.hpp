// The compiler's output: what runs, in which order, and every barrier between.
// The executor records exactly this and derives no synchronization of its own.
//
// Storage: a Plan keeps all usages of all passes in one array and all pass barriers in
// another; each PlannedPass views its part of them through spans, and names (of passes, pass
// types, resources and slots) are views into string tables that copies of a plan share (they
// are never modified): the text of every name in the graph, culled passes' and unused
// resources' included, and the compiler's own (slots, inserted clears). So compiling makes a
// handful of allocations instead of one or more per pass and name. The spans point into the
// Plan that holds the pass: copying a Plan rebases them onto the copy (each copy is valid on
// its own, whatever happens to the original); moving a Plan keeps them valid. A PlannedPass
// or PlannedUsage copied out of its Plan is valid only while that Plan lives unchanged. Code
// that edits a plan keeps every non-empty span viewing that plan's own arrays (reorder or
// drop `passes` freely; change barriers through barriersOf/eraseBarrier): a copy rebases
// views by their offset into those arrays.
#pragma once

#include <skygraph/condition.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/usage.hpp>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
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

/// A usage with everything Vulkan needs to perform it. (Members are ordered to pack into one
/// 64-byte cache line: a plan holds one per usage, and the compiler writes and reads them all.)
struct PlannedUsage {
    VkPipelineStageFlags2 stages = 0;
    VkAccessFlags2 access = 0;
    /// The pass type's slot this usage fills; empty for Generic passes and inserted clears.
    /// Views the plan's shared name tables: valid while any copy of the plan lives.
    std::string_view slot;
    SubresourceRange range;  ///< Resolved: the usage's range, or the whole resource.
    uint32_t resource = 0;   ///< Index into Plan::resources.
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;  ///< Layout during the pass.
    UsageMode usage;         ///< As written; its range, resolved, is `range`.
    /// Attachments only. Clear when this is the first use of a `clear` resource.
    LoadOp load = LoadOp::Load;
    /// Attachments only: Store when a later pass or the export reads the result.
    StoreOp store = StoreOp::Store;
};
static_assert(sizeof(PlannedUsage) == 64, "PlannedUsage: keep it one cache line");

/// A pass that runs. Its names view the plan's shared name tables (valid while any copy of
/// the plan lives). A plan cannot take text of its own: code that renames a pass keeps the new
/// text alive as long as the plan and every copy of it.
struct PlannedPass {
    std::string_view name;
    std::string_view type;   ///< Pass type; "Clear" for a clear inserted by the compiler.
    int32_t declIndex = -1;  ///< Index into GraphDesc::passes; -1 for inserted passes.
    /// One vkCmdPipelineBarrier2 batch, before the pass. Views the plan's barrier array;
    /// edit through Plan::barriersOf / Plan::eraseBarrier.
    std::span<const Barrier> barriers;
    std::span<const PlannedUsage> usages;  ///< Views the plan's usage array.
};

/// How many copies of a resource the executor keeps, and why. Frames in flight overlap on
/// the GPU, and only an exported resource's final barrier orders one frame's accesses before
/// the next frame's; every other resource that a frame writes gets a copy per frame in flight.
enum class ResourceCopies : uint8_t {
    PerFrameTransient,           ///< Not external: written anew by every frame.
    PerFramePresented,           ///< The swapchain target (`final: Present`), like swapchain images.
    PerFrameWrittenNotExported,  ///< External, written, not exported: nothing orders the frames.
    SharedExported,              ///< External and exported: its contents carry from frame to frame.
    SharedReadOnly,              ///< External and only read.
};

/// Whether the executor keeps one copy of the resource per frame in flight.
[[nodiscard]] constexpr bool perFrameInFlight(ResourceCopies c) noexcept {
    return c == ResourceCopies::PerFrameTransient || c == ResourceCopies::PerFramePresented ||
           c == ResourceCopies::PerFrameWrittenNotExported;
}

/// A resource that at least one scheduled pass uses. Unused resources are not listed.
struct PlannedResource {
    std::string_view name;    ///< Views the plan's shared name tables, like PlannedPass::name.
    /// The stages that the frame's first access waits in (for semaphores at the frame's start).
    VkPipelineStageFlags2 firstStages = 0;
    uint32_t decl = 0;        ///< Index into GraphDesc::resources.
    uint32_t firstPass = 0;   ///< Indices into Plan::passes: the lifetime.
    uint32_t lastPass = 0;
    /// Layout the resource must be in when the frame starts (external resources).
    VkImageLayout initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    /// Layout after the final barriers; the next frame's `initialLayout` for externals.
    VkImageLayout finalLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    ResourceCopies copies = ResourceCopies::PerFrameTransient;
};

/// A barrier between two commands of one pass. A ReadWrite transfer is a copy out of the
/// subresources and then a copy into them; the copy in waits for the copy out.
struct InPassBarrier {
    uint32_t pass = 0;   ///< Index into Plan::passes.
    uint32_t usage = 0;  ///< Index into that pass's usages: the ReadWrite transfer.
    Barrier barrier;
};

struct CulledPass {
    std::string name;
    std::string reason;
};

namespace detail {
struct PlanBuilder;  // the compiler's way of filling a plan's storage
}

struct Plan {
    std::string graph;
    FeatureValues features;
    /// The output extent the plan was compiled for: `"output"` extents and `"mips": "full"`
    /// chains resolve against it, so the plan is valid at this size only.
    uint32_t outputWidth = 0;
    uint32_t outputHeight = 0;
    std::vector<PlannedResource> resources;
    std::vector<PlannedPass> passes;
    std::vector<Barrier> finalBarriers;
    /// In pass order; empty unless a pass performs a ReadWrite transfer.
    std::vector<InPassBarrier> inPassBarriers;
    std::vector<CulledPass> culled;

    /// Index into `resources` for a graph resource, or -1 when no scheduled pass uses it.
    [[nodiscard]] int32_t resourceIndex(std::string_view name) const noexcept;

    /// Pass `pass`'s barriers, editable in place (tests weaken plans this way).
    [[nodiscard]] std::span<Barrier> barriersOf(size_t pass);
    /// Removes barrier `i` of pass `pass`; later passes' spans stay valid.
    void eraseBarrier(size_t pass, size_t i);

    Plan() = default;
    Plan(const Plan& other);  ///< Deep copy, with every span rebased onto the copy.
    Plan& operator=(const Plan& other);
    Plan(Plan&&) noexcept = default;  ///< Moved arrays keep their addresses: spans stay valid.
    Plan& operator=(Plan&&) noexcept = default;
    ~Plan() = default;

private:
    friend struct detail::PlanBuilder;
    std::vector<PlannedUsage> usages_;   // every pass's usages, pass after pass
    std::vector<Barrier> barriers_;      // every pass's barrier batch, pass after pass
    /// What the names of passes, resources and slots view: the graph's names, copied once
    /// by the compiler's index walk, and the compiler's own (slots, inserted clears).
    std::vector<std::shared_ptr<const std::string>> nameTables_;
};

}  // namespace skygraph
