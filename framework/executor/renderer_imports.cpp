// Renderer::Impl: swapping an imported image while frames run (importImage), e.g. new
// environment products from a background bake. Nothing waits: the frames already submitted
// keep what they were recorded with until they finish.
#include "renderer_impl.hpp"

#include <algorithm>

namespace skygraph {

using namespace detail;

namespace {

/// Moves what a slot holds but its BoundResources (the framebuffer and its extent, the barrier
/// batches) from `from` to `to`: a pass whose recording code is kept keeps those where they are.
void moveAllButBound(PassSlot& from, PassSlot& to) noexcept {
    to.framebuffer = std::move(from.framebuffer);
    to.extent = from.extent;
    to.before = std::move(from.before);
    to.inPass = std::move(from.inPass);
}

/// What a swap replaced, kept until the new state is whole: when a pass implementation or a
/// pipeline throws part way, the renderer goes on with the old image, and until then the
/// frames in flight still use what is being replaced.
struct SwapJournal {
    struct PassBefore {
        PassState* pass = nullptr;
        /// A pass that uses the image: its slots (and recording code, when made again), whole.
        bool rebuilt = false;
        /// Its recording code is kept: its slots were rebuilt where they are, since it may keep
        /// pointers to their BoundResources (PipelineContext), and `slots` holds what they held.
        bool inPlace = false;
        std::unique_ptr<PassImplementation> implementation;
        std::vector<PassSlot> slots;
        /// Any other pass: only its slots' barriers change (they name the image's handle).
        std::vector<BarrierBatch> before, inPass;
    };
    ImageCopy image;
    std::vector<PassBefore> passes;
    std::vector<BarrierBatch> finals;
    std::vector<std::vector<BarrierBatch>> releases;

    /// Puts back everything saved so far (moves only: nothing here throws).
    void rollBack(PlanState& s, ResourceState& r) noexcept {
        for (PassBefore& p : passes) {
            if (p.inPlace) {
                for (size_t slot = 0; slot < p.slots.size(); ++slot) {
                    moveAllButBound(p.slots[slot], p.pass->slots[slot]);
                    p.pass->slots[slot].bound = p.slots[slot].bound;  // as many as now: the storage stays
                }
                continue;
            }
            if (p.rebuilt) {
                if (p.implementation) p.pass->implementation = std::move(p.implementation);
                p.pass->slots = std::move(p.slots);
                continue;
            }
            for (size_t slot = 0; slot < p.before.size(); ++slot) {
                p.pass->slots[slot].before = std::move(p.before[slot]);
                p.pass->slots[slot].inPass = std::move(p.inPass[slot]);
            }
        }
        s.finals = std::move(finals);
        s.releases = std::move(releases);
        r.images[0] = std::move(image);
    }

    /// What the frames in flight may still use, for releaseRetired.
    RetiredImport retired(uint64_t untilFrame) {
        RetiredImport old;
        old.untilFrame = untilFrame;
        old.image = std::move(image);
        for (PassBefore& p : passes) {
            if (p.implementation) old.implementations.push_back(std::move(p.implementation));
            for (PassSlot& slot : p.slots)
                if (slot.framebuffer) old.framebuffers.push_back(std::move(slot.framebuffer));
        }
        return old;
    }
};

}  // namespace

void Renderer::Impl::swapImport(PlanState& s, size_t index, const SharedImage& image) {
    ImageCopy next = adoptImport(s, index, image);
    ResourceState& r = s.resources[index];
    SwapJournal journal;
    // Room made first: once the new state is whole, retiring the old one must not throw.
    retired.reserve(retired.size() + 1);
    journal.image = std::move(r.images.at(0));
    r.images[0] = std::move(next);
    journal.finals = std::move(s.finals);
    journal.releases = std::move(s.releases);
    try {
        journal.passes.reserve(s.passes.size());
        for (PassState& ps : s.passes) {
            SwapJournal::PassBefore& before = journal.passes.emplace_back();
            before.pass = &ps;
            const bool usesImage = std::any_of(ps.pass->usages.begin(), ps.pass->usages.end(),
                                               [&](const PlannedUsage& u) { return u.resource == index; });
            if (!usesImage) {
                before.before.reserve(ps.slots.size());  // so that a slot's two batches move together
                before.inPass.reserve(ps.slots.size());
                for (uint32_t slot = 0; slot < ps.slots.size(); ++slot) {
                    before.before.push_back(std::move(ps.slots[slot].before));
                    before.inPass.push_back(std::move(ps.slots[slot].inPass));
                    translatePassBarriers(s, ps, slot);
                }
                continue;
            }
            // A pass implementation may keep its slots' handles for its whole life
            // (PipelineContext::frameSlots): one that does is replaced. One that reads them while
            // recording keeps its pipelines, which depend on formats and sizes, not images, and
            // the BoundResources it may point to, which are rebuilt where they are.
            if (ps.implementation && ps.implementation->keepsSlotHandles()) {
                before.rebuilt = true;
                before.slots = std::move(ps.slots);
                ps.slots = std::vector<PassSlot>(before.slots.size());
                before.implementation = std::move(ps.implementation);
                ps.implementation = implementationOf(*ps.pass, *ps.desc);
                for (uint32_t slot = 0; slot < ps.slots.size(); ++slot) buildPassSlot(s, ps, slot);
                createPipelines(s, ps);
            } else {
                // Every slot is saved, the copies (which may throw) first, before any changes:
                // until then a rollback has nothing of this pass's to put back.
                std::vector<PassSlot> saved(ps.slots.size());
                for (uint32_t slot = 0; slot < ps.slots.size(); ++slot) saved[slot].bound = ps.slots[slot].bound;
                for (uint32_t slot = 0; slot < ps.slots.size(); ++slot) moveAllButBound(ps.slots[slot], saved[slot]);
                before.slots = std::move(saved);
                before.inPlace = true;
                for (uint32_t slot = 0; slot < ps.slots.size(); ++slot) buildPassSlot(s, ps, slot);
            }
        }
        translateFinalBarriers(s, static_cast<uint32_t>(journal.finals.size()));
    } catch (...) {
        journal.rollBack(s, r);
        throw;
    }
    ++r.contentsReplaced;
    retired.push_back(journal.retired(frameIndex));
    releaseRetired();
}

void Renderer::Impl::releaseRetired() {
    const auto inUse = [&](const RetiredImport& r) {
        return std::any_of(frames.begin(), frames.end(),
                           [&](const FrameSlot& f) { return f.submitted && f.frame < r.untilFrame; });
    };
    std::erase_if(retired, [&](const RetiredImport& r) { return !inUse(r); });
}

}  // namespace skygraph
