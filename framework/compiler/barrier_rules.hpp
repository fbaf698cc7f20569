// The hazard rules of docs/barriers.md for one subresource: what is known of it between
// passes, the barrier an access needs given that, and what the access leaves. Whole-frame,
// per-subresource state tracking in the spirit of Granite's render graph. Internal to the
// synchronizer's barrier sweep (synchronizer_barriers.cpp), which walks the plan's accesses in
// order and calls these, and to its final barriers (synchronizer_boundaries.cpp).
#pragma once

#include "vulkan_state.hpp"

#include <skygraph/plan.hpp>

#include <optional>
#include <type_traits>

namespace skygraph::sync {

/// What is known about one subresource between passes. Value-initialised (`{}`), it is the
/// undefined state: nothing written, no layout. Trivially constructible, so that an array of
/// them need not be zeroed up front (the synchronizer sets each resource's at its first use).
struct SubresourceState {
    VkImageLayout layout;
    /// Contents came from outside the frame; a barrier needing a source stage chains with
    /// the semaphore wait at the first use's stages. (Beside the layout: 48 bytes, not 56.)
    bool fromOutside;
    /// The memory was last used by other resources (the resource's MemoryPlacement::aliases):
    /// `writeStages` and `writeAccess` are their last uses, and a barrier from them is an
    /// aliasing barrier (rule 16).
    bool aliased;
    /// A Clobber step filled it with poison (CompileOptions::clobberTransients) and nothing has
    /// written it since: the next write that would discard it keeps what it does not write.
    bool poisoned;
    VkPipelineStageFlags2 writeStages;    ///< Stages of the last write (or the outside).
    /// Write accesses of that write. A barrier whose source is `writeStages` always repeats
    /// them: an earlier availability operation only counts for barriers that chain after the
    /// barrier that performed it (through its destination stages), which this one may not.
    VkAccessFlags2 writeAccess;
    VkPipelineStageFlags2 readStages;     ///< Reads since the last write: WAR sources.
    VkPipelineStageFlags2 visibleStages;  ///< Scope the last write is visible to.
    VkAccessFlags2 visibleAccess;
};
static_assert(sizeof(SubresourceState) == 48);
static_assert(std::is_trivially_default_constructible_v<SubresourceState>);

/// Stages and accesses without a layout: what a read run's scope needs.
struct StageAccess {
    VkPipelineStageFlags2 stages = 0;
    VkAccessFlags2 access = 0;
};

/// Whether what a write is visible to (`have*`) covers the scope `need` asks for.
inline bool covers(VkPipelineStageFlags2 haveStages, VkAccessFlags2 haveAccess, const VulkanScope& need) {
    return (need.stages & ~haveStages) == 0 && (need.access & ~haveAccess) == 0;
}

/// The barrier subresource `st` needs before an access with scope `need` that reads, or
/// writes (`write`), and must find it in `target` layout (`discard`: its old contents may be
/// dropped in a layout change), written into `b` (default-constructed by the caller, usually
/// in place at the end of the batch): whether one is needed. If so, `st` becomes what the
/// barrier achieves. `visibleAfter()` gives what a barrier before a read makes visible; it is
/// asked only when a read needs one.
template <typename VisibleAfter>
bool barrierInto(Barrier& b, SubresourceState& st, const VulkanScope& need, VkImageLayout target,
                 bool write, bool discard, VisibleAfter&& visibleAfter) {
    const bool layoutChange = st.layout != target;
    b.aliasing = st.aliased;
    b.dstStages = need.stages;
    b.dstAccess = need.access;
    b.oldLayout = discard && layoutChange ? VK_IMAGE_LAYOUT_UNDEFINED : st.layout;
    b.newLayout = target;
    bool needed = layoutChange;
    if (write) {
        // WAR: the reads since the last write chain after it, so waiting for them is an
        // execution dependency that also orders this write after that write.
        if (st.readStages) {
            // Contents from outside the frame may still be read there, in the scope they
            // arrived in (rule 8): those readers are waited for too.
            b.srcStages = st.readStages | (st.fromOutside ? st.writeStages : 0);
            needed = true;
        } else if (st.writeStages && !(st.fromOutside && covers(st.visibleStages, st.visibleAccess, need))) {
            b.srcStages = st.writeStages;  // WAW: memory dependency
            b.srcAccess = st.writeAccess;
            needed = true;
        } else if (layoutChange && st.fromOutside) {
            b.srcStages = st.writeStages;  // the transition waits for the outside's last writes
            b.srcAccess = st.writeAccess;
        }
    } else {
        const bool visible = covers(st.visibleStages, st.visibleAccess, need);
        if (layoutChange) {
            // The transition writes, so it waits for earlier reads (WAR). Those reads chain
            // after the barrier that made the last write available, so they alone are the
            // source then; without reads, the write is (RAW, a memory dependency).
            b.srcStages = st.readStages ? st.readStages | (st.fromOutside ? st.writeStages : 0) : st.writeStages;
            b.srcAccess = st.readStages ? 0 : st.writeAccess;
        } else if (!visible && (st.writeStages || st.fromOutside)) {
            b.srcStages = st.writeStages;  // RAW: memory dependency
            b.srcAccess = st.writeAccess;
            needed = true;
        }
        if (needed) {
            const StageAccess after = visibleAfter();
            b.dstStages = after.stages;
            b.dstAccess = after.access;
        }
    }
    if (needed && b.srcStages == 0 && st.fromOutside) b.srcStages = b.dstStages;
    if (!needed) return false;
    // What the barrier achieved.
    st.layout = target;
    st.fromOutside = st.fromOutside && !write;
    st.aliased = false;
    if (!write) {
        // A transition rewrites the memory: only this barrier's scope sees the result.
        st.visibleStages = (layoutChange ? 0 : st.visibleStages) | b.dstStages;
        st.visibleAccess = (layoutChange ? 0 : st.visibleAccess) | b.dstAccess;
        if (layoutChange) {
            // The transition wrote it last: a later barrier that sources from the last write
            // (to make the contents visible elsewhere, or a WAW) must chain after the
            // transition too, through this barrier's destination stages. The earlier write
            // stays in the source, with its access, as rule 1 repeats it.
            st.writeStages |= b.dstStages;
            st.readStages = 0;
        }
    }
    return true;
}

/// The same, as a value (for ranges of several subresources, whose barriers are merged).
template <typename VisibleAfter>
std::optional<Barrier> barrierFor(SubresourceState& st, const VulkanScope& need, VkImageLayout target,
                                  bool write, bool discard, VisibleAfter&& visibleAfter) {
    Barrier b;
    if (!barrierInto(b, st, need, target, write, discard, visibleAfter)) return std::nullopt;
    return b;
}

/// What an access (of `scope`) leaves in `st` after its barrier: a write replaces everything known (in
/// `target` layout); a read adds its stages to the reads a later write must wait for (WAR).
inline void recordAccess(SubresourceState& st, bool write, VkImageLayout target, const VulkanScope& scope) {
    if (write) {
        st = SubresourceState{};
        st.layout = target;
        st.writeStages = scope.stages;
        st.writeAccess = writeBits(scope.access);
    } else {
        st.readStages |= scope.stages;
    }
}

}  // namespace skygraph::sync
