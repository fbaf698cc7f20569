// The frame's boundaries: the final barriers of resources that outlive the frame and of
// read-backs, which resources need a copy per frame in flight, and the presented image's
// semaphores.
#include "synchronizer_state.hpp"

#include <algorithm>
#include <iterator>
#include <string>
#include <vector>

namespace skygraph::sync {

/// The final barriers, and the final layouts, of the resources that outlive the frame: an
/// exported one goes into its `final` state; an external one that is not exported goes back
/// into its `initial` state, where the next frame (or the next frame on this copy) finds it.
/// Without that, a frame that reads an input in another layout (storage, a copy) would leave it
/// there, and the next frame's barriers would transition it from a layout it is not in.
void Synchronizer::finishResources() {
    std::vector<uint32_t> outliving;  // in plan order
    outliving.reserve(exported_.size() + external_.size());
    std::set_union(exported_.begin(), exported_.end(), external_.begin(), external_.end(),
                   std::back_inserter(outliving));
    for (const uint32_t r : outliving) {
        auto& res = planResources()[r];
        SubresourceState* states = stateOf(r);
        const auto& d = decl(r);
        const ExternalState end = replaced(facts_[r].exported ? d.final : d.initial);
        VulkanScope scope = boundaryScope(r, end);
        // A state with no stages of its own (Present, of an image that is not presented): the
        // next frame's first barrier waits in its first uses' stages (rule 8), so the barrier
        // back ends in those, to chain with it.
        if (!facts_[r].exported && scope.stages == 0) scope.stages = firstUsesScope(r).stages;
        // A persistent resource's next frame repeats this one (an external one that is not
        // exported is one too). If it writes anywhere, the final barrier must order every
        // access of this frame, readers included, before the next frame's first use, exactly
        // as a write would: later passes of the next frame chain through that first use and
        // never name this frame's stages.
        const bool persistent = d.external && end == replaced(d.initial);
        bool framesWrite = false;
        for (uint32_t k = facts_[r].firstAccess; k != kNone; k = accesses_[k].next)
            framesWrite |= accesses_[k].writes;
        const bool nextUseWrites = writeBits(scope.access) != 0 || (persistent && framesWrite);
        perSub_.clear();
        const SubresourceGrid& grid = facts_[r].grid;
        grid.forEach(grid.whole(), [&](size_t sub) {
            perSub_.push_back(barrierFor(states[sub], scope,
                                         d.isImage() ? scope.layout : VK_IMAGE_LAYOUT_UNDEFINED,
                                         nextUseWrites, false,
                                         [&] { return StageAccess{scope.stages, scope.access}; }));
        });
        merger_.emitMerged(r, isImage(r) ? BarrierKind::Image : BarrierKind::Buffer, grid.whole(), perSub_,
                           detail::PlanBuilder::finalBarriers(plan_));
        res.finalLayout = d.isImage() ? scope.layout : VK_IMAGE_LAYOUT_UNDEFINED;
    }
    for (const uint32_t s : readbackSteps_) {
        const uint32_t copied = (*usages_)[steps_[s].firstAccess].resource;
        detail::PlanBuilder::finalBarriers(plan_).push_back(hostReadAfterCopy(copied));
    }
}

/// Which resources need a copy per frame in flight: frames in flight overlap on the GPU,
/// and nothing in a plan orders one frame's accesses after another's unless a resource is
/// external or exported (its final barrier and the next frame's first use chain across frames;
/// one written, not exported, gets a copy per frame all the same, as its contents are not kept). A
/// transient is SharedTransient when the frames share the heaps (set by planMemory), and
/// otherwise keeps the default, PerFrameTransient.
void Synchronizer::decideCopies() {
    int64_t presented = -1;
    for (const uint32_t r : external_) {
        const ResourceFacts& f = facts_[r];
        PlannedResource& res = planResources()[r];
        if (decl(r).final == ExternalState::Present) {
            res.copies = ResourceCopies::PerFramePresented;
            if (replaced(ExternalState::Present) == ExternalState::Present) {
                if (presented >= 0) secondPresentedImage(static_cast<uint32_t>(presented), r);
                presented = r;
                presentation(r);
            }
        } else if (f.exported) {
            res.copies = ResourceCopies::SharedExported;
        } else {
            bool written = false;
            for (uint32_t k = f.firstAccess; k != kNone; k = accesses_[k].next) written |= accesses_[k].writes;
            res.copies = written ? ResourceCopies::PerFrameWrittenNotExported : ResourceCopies::SharedReadOnly;
        }
    }
}

/// A frame has one swapchain image to present. A file may declare several presented
/// images for passes that features choose between, but one plan presents one (a plan
/// compiled to run headless, CompileOptions::presentReplacement, presents none).
[[noreturn]] void Synchronizer::secondPresentedImage(uint32_t first, uint32_t second) const {
    Diagnostics diags;
    diags.add({graph_.file, decl(second).jsonPath() + ".final", "", decl(second).name,
               "a frame presents one image, and passes of this plan also use the presented image '" +
                   decl(first).name + "'; choose one with features or conditions"});
    throw GraphError(std::move(diags));
}

/// A presented image (not read back instead) meets the swapchain's semaphores. The
/// frame's first use (its first barrier, from UNDEFINED, waits in those stages) waits on
/// the acquire. The final barrier to PRESENT_SRC_KHR gets the last use's stages as its
/// destination, and the render-complete signal is in them: the signal chains with the
/// barrier, so it follows the layout transition. (With destination NONE only an
/// ALL_COMMANDS signal would, and validation layers before 1.3.278 report that as a hazard.)
void Synchronizer::presentation(uint32_t r) {
    VkPipelineStageFlags2 lastStages = 0;
    for (Barrier& b : detail::PlanBuilder::finalBarriers(plan_))
        if (b.resource == r && b.newLayout == VK_IMAGE_LAYOUT_PRESENT_SRC_KHR) {
            b.dstStages = b.srcStages;
            lastStages |= b.srcStages;
        }
    detail::PlanBuilder::presentations(plan_).push_back({r, planResources()[r].firstStages, lastStages});
}

}  // namespace skygraph::sync
