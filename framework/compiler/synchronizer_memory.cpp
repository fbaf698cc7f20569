// Where each transient lives (rule 16 of docs/barriers.md): the planner's inputs gathered from
// the accesses, its placements wired to the plan's resources, and what each resource taking
// over memory will wait for, which the barrier sweep (synchronizer_barriers.cpp) applies.
#include "synchronizer_state.hpp"

#include "memory_planner.hpp"

#include <string>
#include <vector>

namespace skygraph::sync {

/// A model's answer the planner can place: a size, a power-of-two alignment, a memory type,
/// and a size that stays far from overflowing the heap's offsets. An embedder's model that
/// answers otherwise is named with the resource it answered for.
void Synchronizer::checkRequirements(const MemoryRequirements& m, const ResourceDesc& d, const MemoryModel& model) const {
    constexpr uint64_t kLargest = uint64_t(1) << 52;  // a petabyte: offsets add far below 2^64
    std::string problem;
    if (m.size == 0 || m.size > kLargest) problem = "a size of " + std::to_string(m.size) + " bytes";
    else if (m.alignment == 0 || (m.alignment & (m.alignment - 1)) != 0 || m.alignment > kLargest)
        problem = "an alignment of " + std::to_string(m.alignment) + ", not a power of two";
    else if (m.memoryTypeBits == 0) problem = "no memory type";
    if (problem.empty()) return;
    Diagnostics diags;
    diags.add({graph_.file, d.jsonPath(), "", d.name,
               "the memory model '" + model.name() + "' answered " + problem + " for '" + d.name +
                   "', which cannot be placed"});
    throw GraphError(std::move(diags));
}

/// Where each transient resource lives (rule 16 of docs/barriers.md): the plan's memory
/// layout, from the lifetimes planAccesses found and the requirements of options_.memory.
void Synchronizer::planMemory() {
    // Without a model the estimate answers, and it needs no usage flags.
    const MemoryModel* model = options_.memory.get();
    std::vector<TransientResource> transients;
    transients.reserve(facts_.size());
    bool sorted = true;  // by first step
    uint32_t latestFirstStep = 0;
    const auto& usages = *usages_;
    for (uint32_t r = 0; r < facts_.size(); ++r) {
        const ResourceFacts& f = facts_[r];
        if (f.external || f.exported) continue;
        const ResourceDesc& d = decl(r);
        MemoryQuery q;
        q.resource = &d;
        if (f.image) {
            const auto [w, h] = d.extent.resolve(options_.outputWidth, options_.outputHeight);
            q.width = w;
            q.height = h;
            q.mips = f.grid.mips;
            q.layers = f.grid.layers;
        }
        if (model) {
            q.imageUsage = f.image ? kAlwaysUsable.image : 0;
            q.bufferUsage = f.image ? 0 : kAlwaysUsable.buffer;
            for (uint32_t k = f.firstAccess; k != kNone; k = accesses_[k].next) {
                const UsageFlags u = usageFlags(usages[k].usage, f.image);
                q.imageUsage |= f.image ? u.image : 0;
                q.bufferUsage |= f.image ? 0 : u.buffer;
            }
        }
        // Field by field, in place: a braced temporary copied in stalls on store forwarding.
        TransientResource& t = transients.emplace_back();
        t.resource = r;
        t.firstStep = planResources()[r].firstPass;
        t.lastStep = f.lastStep;
        sorted &= t.firstStep >= latestFirstStep;
        latestFirstStep = t.firstStep;
        t.requirements = model ? model->requirements(q) : estimatedRequirements(q);
        if (model) checkRequirements(t.requirements, d, *model);
        t.linear = !f.image;
        t.aliasable = d.alias;
    }
    // Resources are numbered as the schedule meets them, but a Clear or Clobber before a
    // pass is the first use of the resource it fills: the planner wants first-use order.
    const auto byFirstStep = [](const TransientResource& x, const TransientResource& y) {
        return x.firstStep < y.firstStep;
    };
    if (!sorted) std::stable_sort(transients.begin(), transients.end(), byFirstStep);
    const uint64_t granularity = model ? model->bufferImageGranularity() : estimatedMemory()->bufferImageGranularity();
    if (granularity == 0 || (granularity & (granularity - 1)) != 0) {
        Diagnostics diags;
        diags.add({graph_.file, "", "", "",
                   "the memory model '" + (model ? model->name() : std::string("estimate")) +
                       "' answered a bufferImageGranularity of " + std::to_string(granularity) +
                       ", not a power of two"});
        throw GraphError(std::move(diags));
    }
    MemoryLayout& layout = detail::PlanBuilder::memory(plan_);
    layout = placeTransients(transients, static_cast<uint32_t>(steps_.size()), granularity, options_.placement,
                             options_.aliasing, options_.shareTransientsAcrossFrames);
    layout.model = model ? model->name() : "estimate";
    // With frames sharing the heaps, the next frame's first holders of each byte wait for
    // every use of it in this frame: per plan resource, its own last uses and, through
    // its aliases (placed before it), every earlier use of its bytes.
    const bool acrossFrames = options_.shareTransientsAcrossFrames;
    std::vector<StageAccess> usesUpTo(acrossFrames ? facts_.size() : 0);
    std::vector<uint32_t> firstHolders;  // placements with previous-frame aliases
    for (uint32_t p = 0; p < layout.placements.size(); ++p) {
        const MemoryPlacement& placement = layout.placements[p];
        const uint32_t r = placement.resource;
        // Set here, not in sweeps of their own: the records are in cache now.
        PlannedResource& planned = planResources()[r];
        planned.placement = p;
        if (acrossFrames) planned.copies = ResourceCopies::SharedTransient;
        facts_[r].placement = p;
        if (acrossFrames) {
            StageAccess uses = lastUsesInFrame(r);
            for (const uint32_t a : placement.aliases) {
                uses.stages |= usesUpTo[a].stages;
                uses.access |= usesUpTo[a].access;
            }
            usesUpTo[r] = uses;
            if (!placement.previousFrameAliases.empty()) firstHolders.push_back(p);
        }
        if (placement.aliases.empty() && placement.previousFrameAliases.empty()) continue;
        // Which resources take over memory (startAliased looks no further for the rest)
        // and which are taken over from (their last uses are kept when they end).
        if (facts_[r].grid.size() > 1) ++wholeAliasingBarriers_;
        if (takesOver_.empty()) {
            takesOver_.resize(facts_.size());
            predecessor_.resize(facts_.size());
            lastUses_.resize(facts_.size());
            earlierUses_.resize(facts_.size());
        }
        takesOver_[r] = 1;
        for (const uint32_t a : placement.aliases) predecessor_[a] = 1;
    }
    if (firstHolders.empty()) return;
    previousFrameLastUses_.resize(layout.placements.size());
    for (const uint32_t p : firstHolders)
        for (const uint32_t a : layout.placements[p].previousFrameAliases) {
            previousFrameLastUses_[p].stages |= usesUpTo[a].stages;
            previousFrameLastUses_[p].access |= usesUpTo[a].access;
        }
}

/// What a barrier after resource r's uses in the frame waits for, as addLastUses would
/// find it after the frame's barriers: from what addAccess folded per subresource, before
/// they are written (the next frame's first uses of r's bytes need it at their start).
StageAccess Synchronizer::lastUsesInFrame(uint32_t r) {
    StageAccess last;
    const FrameUses* uses = &frameUses_[facts_[r].firstCell];
    for (size_t c = 0; c < facts_[r].grid.size(); ++c) {
        last.stages |= uses[c].writes.stages | uses[c].readsSince | uses[c].lastWriteStages;
        last.access |= uses[c].writes.access;
        // A subresource never used was transitioned by the first step's aliasing barrier.
        if (!uses[c].readsSince && !uses[c].lastWriteStages) last.stages |= plan_.resources()[r].firstStages;
    }
    return last;
}

}  // namespace skygraph::sync
