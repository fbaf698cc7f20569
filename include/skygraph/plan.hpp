// The compiler's output: what runs, in which order, and every barrier between.
// The executor records exactly this and derives no synchronization of its own.
//
// A Plan is read-only to its users: compile() (and planSetup / planImageRead) write it, and
// everything else reads it through const accessors. Ownership and validity, for every view
// that a Plan hands out:
// - The arrays (passes(), resources(), finalBarriers(), inPassBarriers(), culled()) and each
//   PlannedPass's `barriers` and `usages` view storage that the Plan owns: valid while that
//   Plan lives and is not assigned to. Moving a Plan keeps them valid (they then belong to
//   the Plan moved to); copying a Plan gives the copy views of its own, valid whatever
//   happens to the original.
// - Names (PlannedPass::name and ::type, PlannedResource::name, PlannedUsage::slot) view text
//   that the Plan shares with its copies and never modifies: valid while the Plan or any copy
//   of it lives, even after the GraphDesc it was compiled from is gone.
// - A PlannedPass, PlannedUsage or PlannedResource copied out of its Plan holds these views,
//   not the data: it is valid only as long as the views it holds are.
#pragma once

#include <skygraph/condition.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/memory.hpp>
#include <skygraph/usage.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
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
    uint32_t resource = 0;  ///< Index into Plan::resources().
    BarrierKind kind = BarrierKind::Image;
    /// An aliasing barrier: the resource takes over memory that other resources used earlier
    /// in the frame, or that the previous frame used (itself included, when the frames share
    /// the heaps): its MemoryPlacement's aliases and previousFrameAliases. The source scope is
    /// every earlier use of those bytes, and images start from UNDEFINED.
    bool aliasing = false;
    /// A queue family ownership transfer when the two differ (docs/queues.md, "Ownership"):
    /// the release half is recorded on `srcQueue` (Submit::releases), the acquire half, this
    /// same barrier, on `dstQueue` (a pass's batch or the final barriers). The executor turns
    /// the kinds into the families of its queues. Equal (graphics) for every other barrier.
    QueueKind srcQueue = QueueKind::Graphics;
    QueueKind dstQueue = QueueKind::Graphics;
    VkPipelineStageFlags2 srcStages = 0;
    VkAccessFlags2 srcAccess = 0;
    VkPipelineStageFlags2 dstStages = 0;
    VkAccessFlags2 dstAccess = 0;
    VkImageLayout oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;  ///< Images only.
    VkImageLayout newLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    SubresourceRange range;  ///< Images only; buffers are always whole.

    [[nodiscard]] bool transfersOwnership() const noexcept { return srcQueue != dstQueue; }
    friend bool operator==(const Barrier&, const Barrier&) = default;
};

/// A wait for, or a signal of, a queue's timeline semaphore within one frame. Each queue kind
/// that signals has one timeline semaphore; values count that queue's signals in the frame
/// from 1 (the executor adds the frames before). Waiting for value v waits for every signal
/// up to v of that queue.
struct SemaphoreOp {
    QueueKind semaphore = QueueKind::Graphics;  ///< Whose timeline.
    uint32_t value = 0;
    /// A wait's second synchronization scope, a signal's first (VkSemaphoreSubmitInfo::stageMask).
    VkPipelineStageFlags2 stages = 0;

    friend bool operator==(const SemaphoreOp&, const SemaphoreOp&) = default;
};

/// One VkSubmitInfo2: passes of one queue, in plan order, between its waits and its signals.
/// Its command buffer holds, in order: each pass's barrier batch and the pass; then its
/// releases; then, in the frame's last submit, the final barriers (and read-back copies).
struct Submit {
    QueueKind queue = QueueKind::Graphics;
    std::span<const uint32_t> passes;        ///< Indices into Plan::passes(), ascending.
    std::span<const SemaphoreOp> waits;      ///< At the start, before its first command.
    std::span<const Barrier> releases;       ///< Release halves, after its last pass.
    std::span<const SemaphoreOp> signals;    ///< At most one: this queue's next value.
    /// Waits for the swapchain image's acquire semaphore (Presentation::acquireWaitStages).
    bool waitsForAcquire = false;
};

/// What a render pass does with an attachment at its start and end.
enum class LoadOp : uint8_t { Load, Clear, DontCare };
enum class StoreOp : uint8_t { Store, DontCare, None };

/// A usage with everything Vulkan needs to perform it.
struct PlannedUsage {
    VkPipelineStageFlags2 stages = 0;
    VkAccessFlags2 access = 0;
    /// The pass type's slot this usage fills; empty for Generic passes and inserted clears.
    /// Views the plan's names: valid while the plan or any copy of it lives.
    std::string_view slot;
    SubresourceRange range;  ///< Resolved: the usage's range, or the whole resource.
    uint32_t resource = 0;   ///< Index into Plan::resources().
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;  ///< Layout during the pass.
    UsageMode usage;         ///< As written; its range, resolved, is `range`.
    /// Attachments only. Clear when this is the first use of a `clear` resource.
    LoadOp load = LoadOp::Load;
    /// Attachments only: Store when a later pass or the export reads the result.
    StoreOp store = StoreOp::Store;
};

/// A pass that runs. Its names view the plan's names (valid while the plan or any copy of it
/// lives); its barriers and usages view the plan's own arrays (valid while the plan that holds
/// this pass lives and is not assigned to).
struct PlannedPass {
    std::string_view name;
    std::string_view type;   ///< Pass type; "Clear" for a clear inserted by the compiler.
    int32_t declIndex = -1;  ///< Index into GraphDesc::passes; -1 for inserted passes.
    /// One vkCmdPipelineBarrier2 batch, before the pass.
    std::span<const Barrier> barriers;
    std::span<const PlannedUsage> usages;  ///< In the order the pass declares them.
};

/// How many copies of a resource the executor keeps, and why. Frames in flight overlap on
/// the GPU; what orders one frame's accesses before the next frame's is an external or exported
/// resource's final barrier, or, for transients in heaps the frames share, the next frame's aliasing
/// barriers. Every other resource that a frame writes gets a copy per frame in flight. Plans
/// that share transients between frames assume the frames run in submission order on one
/// queue, as the executor submits them.
enum class ResourceCopies : uint8_t {
    PerFrameTransient,           ///< Not external: written anew by every frame.
    /// Not external, in memory that the frames in flight share (CompileOptions::
    /// shareTransientsAcrossFrames): one copy, and each frame's first uses of its bytes wait
    /// for the previous frame's last uses of them (MemoryPlacement::previousFrameAliases).
    SharedTransient,
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
    std::string_view name;    ///< Views the plan's names, like PlannedPass::name.
    /// The stages that the frame's first access waits in (for semaphores at the frame's start).
    VkPipelineStageFlags2 firstStages = 0;
    uint32_t decl = 0;        ///< Index into GraphDesc::resources.
    uint32_t firstPass = 0;   ///< Indices into Plan::passes(): the lifetime.
    uint32_t lastPass = 0;
    /// Layout the resource must be in when the frame starts (external resources).
    VkImageLayout initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    /// Layout after the final barriers; the next frame's `initialLayout` for externals.
    VkImageLayout finalLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    ResourceCopies copies = ResourceCopies::PerFrameTransient;
    /// Index into Plan::memory().placements for a transient resource; kNoPlacement for the
    /// rest, which the executor gives memory of their own.
    uint32_t placement = kNoPlacement;
    static constexpr uint32_t kNoPlacement = ~0u;
};

/// A barrier between two commands of one pass. A ReadWrite transfer is a copy out of the
/// subresources and then a copy into them; the copy in waits for the copy out.
struct InPassBarrier {
    uint32_t pass = 0;   ///< Index into Plan::passes().
    uint32_t usage = 0;  ///< Index into that pass's usages: the ReadWrite transfer.
    Barrier barrier;
};

/// How a frame whose plan ends in a presented image (`final: Present`) meets the swapchain.
/// The frame's submit waits on the semaphore that acquired the image and signals the one that
/// vkQueuePresentKHR waits on. A plan compiled with Present replaced (headless) has none.
struct Presentation {
    uint32_t resource = 0;  ///< Index into Plan::resources(): the presented image.
    /// Where the submit waits on the acquire semaphore: the stages of the image's first use,
    /// which its first barrier (from UNDEFINED) waits in. Waiting later would let that layout
    /// transition race the presentation engine's read of the image.
    VkPipelineStageFlags2 acquireWaitStages = 0;
    /// Where the submit signals the render-complete semaphore: the stages of the image's last
    /// use, which are the destination of its final barrier to PRESENT_SRC_KHR, so the signal
    /// follows that layout transition.
    VkPipelineStageFlags2 renderCompleteStages = 0;

    friend bool operator==(const Presentation&, const Presentation&) = default;
};

struct CulledPass {
    std::string name;
    std::string reason;
};

namespace detail {
struct PlanBuilder;  // the implementation's own access; not part of the API
struct PlanEditor;   // the implementation's own access; not part of the API
}

/// A compiled plan: read-only, see the top of this file for what its views point to and how
/// long they are valid. Copies are deep and independent; moves keep every view valid.
class Plan {
public:
    /// An empty plan: no passes, no resources, the empty graph name and a 0x0 output.
    Plan() = default;
    /// A deep copy whose views point into the copy's own arrays (its names are shared, as
    /// they are never modified). The copy is valid on its own, whatever happens to `other`.
    Plan(const Plan& other);
    /// As the copy constructor. Arrays and spans obtained from this plan before are invalid
    /// afterwards (names stay valid while another copy of the plan they came from lives);
    /// views into `other` are not affected.
    Plan& operator=(const Plan& other);
    /// The arrays move with their storage: views obtained from `other` stay valid and now
    /// view this plan. `other` is left valid but unspecified (assign to it or destroy it).
    Plan(Plan&&) noexcept = default;
    /// As the move constructor; arrays and spans obtained from this plan before are invalid
    /// afterwards, as after a copy assignment.
    Plan& operator=(Plan&&) noexcept = default;
    ~Plan() = default;

    /// The graph's name (GraphDesc::name). Owned by this plan: valid while it lives and is
    /// not assigned to.
    [[nodiscard]] const std::string& graph() const noexcept { return graph_; }
    /// The feature values the plan was compiled with, every feature of the graph included.
    /// Owned by this plan: valid while it lives and is not assigned to.
    [[nodiscard]] const FeatureValues& features() const noexcept { return features_; }
    /// The output extent the plan was compiled for: `"output"` extents and `"mips": "full"`
    /// chains resolve against it, so the plan is valid at this size only.
    [[nodiscard]] uint32_t outputWidth() const noexcept { return outputWidth_; }
    [[nodiscard]] uint32_t outputHeight() const noexcept { return outputHeight_; }
    /// How runs of reads were laid out: CompileOptions::layouts, else the graph's `"layouts"`.
    [[nodiscard]] LayoutPolicy layouts() const noexcept { return layouts_; }

    /// The resources that at least one scheduled pass uses, in order of first use; unused
    /// resources are not listed. Views this plan's array: valid while the plan lives and is
    /// not assigned to (a move keeps it valid).
    [[nodiscard]] std::span<const PlannedResource> resources() const noexcept { return resources_; }
    /// The passes that run, in order, inserted ones (clears, read-backs) included. Views this
    /// plan's array, and each pass views this plan's barriers and usages: valid while the plan
    /// lives and is not assigned to (a move keeps them valid).
    [[nodiscard]] std::span<const PlannedPass> passes() const noexcept { return passes_; }
    /// The barriers after the last pass, which hand resources to what follows the plan (an
    /// export's final state, a read-back's host read). Views this plan's array; valid as
    /// passes().
    [[nodiscard]] std::span<const Barrier> finalBarriers() const noexcept { return finalBarriers_; }
    /// In pass order; empty unless a pass performs a ReadWrite transfer. Views this plan's
    /// array; valid as passes().
    [[nodiscard]] std::span<const InPassBarrier> inPassBarriers() const noexcept { return inPassBarriers_; }
    /// The passes that do not run, in file order, and why. Views this plan's array; valid as
    /// passes().
    [[nodiscard]] std::span<const CulledPass> culled() const noexcept { return culled_; }
    /// The presented images' semaphore stages, in resources() order; empty unless the plan
    /// keeps a `final: Present` image. Views this plan's array; valid as passes().
    [[nodiscard]] std::span<const Presentation> presentations() const noexcept { return presentations_; }
    /// Where the transient resources live, and how much memory they need with and without
    /// sharing it. Owned by this plan: valid while it lives and is not assigned to.
    [[nodiscard]] const MemoryLayout& memory() const noexcept { return memory_; }
    /// The frame's submits in submission order (docs/queues.md). One graphics submit holding
    /// every pass when all passes run on the graphics queue; the last submit is a graphics
    /// submit, which records the final barriers, signals the render-complete semaphore and
    /// the frame's fence. Views this plan's arrays; valid as passes().
    [[nodiscard]] std::span<const Submit> submits() const noexcept { return submits_; }
    /// The queue each pass runs on, by index into passes().
    [[nodiscard]] QueueKind queueOf(uint32_t pass) const noexcept {
        return pass < passQueues_.size() ? passQueues_[pass] : QueueKind::Graphics;
    }
    /// The queue family of each queue kind that the plan was compiled for
    /// (CompileOptions::queueFamilies): ownership transfers are between different ones. Owned
    /// by this plan; valid while it lives and is not assigned to.
    [[nodiscard]] const std::array<uint32_t, kQueueKinds>& queueFamilies() const noexcept { return queueFamilies_; }
    /// Whether plan resource `r` is shared concurrently by the queue families that use it
    /// (VK_SHARING_MODE_CONCURRENT) rather than owned by one at a time.
    [[nodiscard]] bool concurrent(uint32_t r) const noexcept { return r < concurrent_.size() && concurrent_[r] != 0; }

    /// Index into resources() for a graph resource, or -1 when no scheduled pass uses it.
    /// Compares names; `name` need not outlive the call.
    [[nodiscard]] int32_t resourceIndex(std::string_view name) const noexcept;

private:
    friend struct detail::PlanBuilder;
    friend struct detail::PlanEditor;
    std::string graph_;
    FeatureValues features_;
    uint32_t outputWidth_ = 0;
    uint32_t outputHeight_ = 0;
    LayoutPolicy layouts_ = LayoutPolicy::FewestBarriers;
    std::vector<PlannedResource> resources_;
    std::vector<PlannedPass> passes_;
    std::vector<Barrier> finalBarriers_;
    std::vector<InPassBarrier> inPassBarriers_;
    std::vector<CulledPass> culled_;
    std::vector<Presentation> presentations_;
    MemoryLayout memory_;
    std::vector<Submit> submits_;
    std::array<uint32_t, kQueueKinds> queueFamilies_{0, 1, 2};
    std::vector<QueueKind> passQueues_;
    std::vector<uint8_t> concurrent_;              // per resource
    std::vector<uint32_t> submitPasses_;           // every submit's passes, submit after submit
    std::vector<SemaphoreOp> semaphoreOps_;        // every submit's waits and signals
    std::vector<Barrier> releases_;                // every submit's releases
    std::vector<PlannedUsage> usages_;   // every pass's usages, pass after pass
    std::vector<Barrier> barriers_;      // every pass's barrier batch, pass after pass
    std::vector<std::shared_ptr<const std::string>> nameTables_;  // what the names view
};

}  // namespace skygraph
