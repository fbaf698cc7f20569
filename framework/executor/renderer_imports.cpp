// Renderer::Impl: swapping an imported image while frames run (importImage), e.g. new
// environment products from a background bake. Nothing waits: the frames already submitted
// keep what they were recorded with until they finish.
#include "renderer_impl.hpp"

#include <algorithm>

namespace skygraph {

using namespace detail;

void Renderer::Impl::swapImport(PlanState& s, size_t index, const SharedImage& image) {
    ImageCopy next = adoptImport(s, index, image);
    RetiredImport old;
    old.untilFrame = frameIndex;
    ResourceState& r = s.resources[index];
    old.image = std::move(r.images.at(0));
    r.images[0] = std::move(next);
    ++r.contentsReplaced;
    for (PassState& ps : s.passes) {
        const bool uses = std::any_of(ps.pass->usages.begin(), ps.pass->usages.end(),
                                      [&](const PlannedUsage& u) { return u.resource == index; });
        if (!uses) {
            for (uint32_t slot = 0; slot < ps.slots.size(); ++slot) translatePassBarriers(s, ps, slot);
            continue;
        }
        // A pass implementation may keep its slots' handles for its whole life
        // (PipelineContext::frameSlots): one that does is replaced. One that reads them while
        // recording keeps its pipelines, which depend on formats and sizes, not images.
        const bool remake = ps.implementation && ps.implementation->keepsSlotHandles();
        if (remake) {
            old.implementations.push_back(std::move(ps.implementation));
            ps.implementation = implementationOf(*ps.pass, *ps.desc);
        }
        for (uint32_t slot = 0; slot < ps.slots.size(); ++slot) {
            if (ps.slots[slot].framebuffer) old.framebuffers.push_back(std::move(ps.slots[slot].framebuffer));
            buildPassSlot(s, ps, slot);
        }
        if (remake) createPipelines(s, ps);
    }
    translateFinalBarriers(s, static_cast<uint32_t>(s.finals.size()));
    retired.push_back(std::move(old));
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
