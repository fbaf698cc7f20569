// The synchronizer's barrier sweep: in one forward pass over the plan's accesses it settles
// each usage's layout and attachment ops, tracks every subresource's state, and writes the
// barriers before each pass (rules 1-15 of docs/barriers.md, applied by barrier_rules.hpp),
// and the aliasing barriers of resources that take over another's memory (rule 16), with the
// waits that synchronizer_memory.cpp prepared.
#include "synchronizer_state.hpp"

#include <algorithm>
#include <span>
#include <stdexcept>

namespace skygraph::sync {

/// Settles each usage's layout (rule 4) and attachment ops and writes the barriers before
/// each pass, in one forward sweep. Barriers go straight into the plan's array, and each
/// PlannedPass is written as soon as its batch is done; then the plan takes the name
/// tables that its names view.
void Synchronizer::emitSteps() {
    state_ = std::make_unique_for_overwrite<SubresourceState[]>(cellCount_);
    auto& usages = *usages_;
    auto& barriers = detail::PlanBuilder::barriers(plan_);
    // Room for the most barriers there can be (one per subresource an access touches), so
    // the array never moves and each pass's spans are set as its batch is done.
    barriers.reserve(accessCount_ - runScopeAccesses_.size() + runScopeCount_ + wholeAliasingBarriers_);
    const Barrier* const base = barriers.data();
    const size_t room = barriers.capacity();
    // Each plan pass is written once, whole, here (an inserted Clear's name comes at the
    // end): built in planAccesses, its record would have left the cache by the time its
    // spans are known.
    planPasses().reserve(steps_.size());
    for (uint32_t s = 0; s < steps_.size(); ++s) {
        const size_t batch = barriers.size();
        const Step& step = steps_[s];
        const uint32_t first = step.firstAccess, end = stepEnd(s);
        for (uint32_t k = first; k < end; ++k) applyAccess(usages[k], k, barriers);
        if (step.mayMerge) mergeAdjacent(barriers, batch);
        const std::span<const Barrier> batchView =
            barriers.size() > batch ? std::span<const Barrier>(base + batch, barriers.size() - batch)
                                    : std::span<const Barrier>();
        const std::span<const PlannedUsage> usesView(usages.data() + first, end - first);
        // Inserted clears are named below, once the compiler's own text is complete.
        const std::string_view name = step.declIndex < 0 ? std::string_view() : index_.passName(step.declIndex);
        const std::string_view type = step.declIndex >= 0 ? index_.passType(step.declIndex)
                                      : step.readback      ? kReadbackType
                                      : step.clobber       ? kClobberType
                                                           : kClearType;
#if __cpp_aggregate_paren_init >= 201902L
        planPasses().emplace_back(name, type, step.declIndex, batchView, usesView);
#else  // clang before 16 (the sanitizer build): no aggregate initialisation from parentheses
        planPasses().push_back(PlannedPass{name, type, step.declIndex, batchView, usesView});
#endif
    }
    if (barriers.capacity() != room) throw std::logic_error("synchronizer: the barrier bound was exceeded");
    // Pass and resource names view the index's name table; slots and inserted clears
    // view the compiler's own, which no longer grows.
    detail::PlanBuilder::keepNames(plan_, index_.names());
    if (!ownText_.empty()) {
        auto own = std::make_shared<const std::string>(std::move(ownText_));
        const std::string_view text = *own;
        for (const NameAt& n : slotAt_) usages[n.item].slot = text.substr(n.offset, n.length);
        for (const NameAt& n : insertedNameAt_) planPasses()[n.item].name = text.substr(n.offset, n.length);
        detail::PlanBuilder::keepNames(plan_, std::move(own));
    }
}

/// The end of step s's accesses.
uint32_t Synchronizer::stepEnd(uint32_t s) const {
    return s + 1 < steps_.size() ? steps_[s + 1].firstAccess : accessCount_;
}

/// Whether a later access (or the export) reads what access `k` leaves in `range`.
bool Synchronizer::readLater(uint32_t k, const SubresourceRange& range) const {
    for (uint32_t j = accesses_[k].next; j != kNone; j = accesses_[j].next) {
        const auto& o = (*usages_)[j].range;
        if (!o.overlaps(range)) continue;
        // As written: a load-op clear turns Read into ReadWrite, and both read.
        if (readsContents((*usages_)[j].usage.access)) return true;
        if (o.baseMip <= range.baseMip && o.baseMip + o.mipCount >= range.baseMip + range.mipCount &&
            o.baseLayer <= range.baseLayer && o.baseLayer + o.layerCount >= range.baseLayer + range.layerCount)
            return false;
    }
    return facts_[(*usages_)[k].resource].exported;  // the same notion of "live at the end" as culling
}

/// What a barrier before read `k` makes visible in the `cell`-th subresource of its range:
/// the union of the scopes of the reads of that subresource from this one up to the next
/// write or, under LayoutPolicy::Optimal, up to the next read in another layout (whose
/// transition makes the contents visible to its own run: rule 5). They all belong to one
/// run (rule 4 in docs/barriers.md), and only the run's first read that needs a barrier
/// asks (the barrier makes the rest visible). For a resource of one subresource every
/// later access touches it, so walking its chain to the next write costs no more than the
/// run; for one of several, a walk would step over the accesses of other subresources
/// again for each (quadratic for a layer-per-pass array), so those come from
/// computeRunScopes(), and so do all under LayoutPolicy::Optimal (so that the walk needs
/// no test of the policy).
StageAccess Synchronizer::runScopeFrom(uint32_t k, size_t cell) const {
    if (accesses_[k].runScopes != kNone) return runScope_[accesses_[k].runScopes + cell];
    const auto& usages = *usages_;
    StageAccess scope{usages[k].stages, usages[k].access};
    for (uint32_t j = accesses_[k].next; j != kNone && !accesses_[j].writes; j = accesses_[j].next) {
        scope.stages |= usages[j].stages;
        scope.access |= usages[j].access;
    }
    return scope;
}

/// Stages and accesses of the first use of each of resource r's subresources: where a
/// frame's accesses of them begin (different subresources may begin in different passes).
VulkanScope Synchronizer::firstUsesScope(uint32_t r) const {
    VulkanScope scope;
    const SubresourceGrid& grid = facts_[r].grid;
    std::vector<bool> seen(grid.size());
    size_t left = grid.size();
    for (uint32_t k = facts_[r].firstAccess; k != kNone && left; k = accesses_[k].next) {
        bool first = false;
        grid.forEach((*usages_)[k].range, [&](size_t sub) {
            if (seen[sub]) return;
            seen[sub] = true;
            first = true;
            --left;
        });
        if (!first) continue;
        scope.stages |= (*usages_)[k].stages;
        scope.access |= (*usages_)[k].access;
    }
    return scope;
}

/// Where a persistent external resource's contents must be visible at the frame's start.
/// For `General` (state the graph itself consumes next frame, e.g. accumulation) that is
/// exactly where the frame's first uses of its subresources are; otherwise the documented
/// table in vulkan_state.cpp.
VulkanScope Synchronizer::boundaryScope(uint32_t r, ExternalState state) const {
    VulkanScope scope = externalScope(decl(r), state);
    if (state == ExternalState::General && decl(r).external) {
        const VulkanScope firstUses = firstUsesScope(r);
        return {firstUses.stages, firstUses.access, scope.layout};
    }
    return scope;
}

/// Resource r's state before its first access (and an external plan resource's initial
/// layout): undefined, or for an external resource what its `initial` state holds.
/// state_ is not initialised before: written here, its lines are in cache for the access
/// that follows, where zeroing the whole array first would have them evicted by then (a
/// second miss per line). External resources' states are written field by field (a local
/// SubresourceState copied in would stall the CPU's store forwarding, once per resource).
void Synchronizer::startState(uint32_t r, std::vector<Barrier>& batch) {
    const ResourceFacts& facts = facts_[r];
    SubresourceState* states = &state_[facts.firstCell];
    const size_t cells = facts.grid.size();
    if (cells == 1) *states = SubresourceState{};  // most resources; fill_n's loop costs more
    else std::fill_n(states, cells, SubresourceState{});
    if (!facts_[r].external) {
        if (!takesOver_.empty() && takesOver_[r]) startAliased(r, states, cells, batch);
        return;
    }
    const VulkanScope scope = boundaryScope(r, replaced(decl(r).initial));
    // A persistent resource's last writer is the previous frame, in the scope its final
    // barrier handed the contents to: a barrier that sources from it repeats those writes'
    // accesses (rule 1), as it would for a writer in the frame. Synchronization validation
    // asks for exactly that before a layout transition of such a subresource.
    const VkAccessFlags2 outsideWrites = writeBits(scope.access);
    // The previous frame's last write of each subresource, when this frame's is the
    // previous one's (`final: General` carries the contents over): the barrier repeats it
    // too, so that it covers that write directly and not only through the final barrier
    // (the validation layer follows no chain into a layout transition without it).
    const bool persistent = decl(r).final == ExternalState::General && replaced(decl(r).initial) == ExternalState::General;
    if (persistent) replayAccesses(r);
    for (size_t i = 0; i < facts_[r].grid.size(); ++i) {
        states[i].layout = scope.layout;
        states[i].writeStages = scope.stages | (persistent ? replay_[i].writeStages : 0);
        states[i].writeAccess = outsideWrites | (persistent ? replay_[i].writeAccess : 0);
        states[i].visibleStages = scope.stages;
        states[i].visibleAccess = scope.access;
        states[i].fromOutside = true;
    }
    planResources()[r].initialLayout = scope.layout;
}

/// Resource r's accesses in the frame replayed with rules 1-5's bookkeeping into replay_
/// (per subresource, what the frame leaves), before the frame's barriers are written.
void Synchronizer::replayAccesses(uint32_t r) {
    const auto& usages = *usages_;
    const SubresourceGrid& grid = facts_[r].grid;
    replay_.assign(grid.size(), SubresourceState{});
    for (uint32_t k = facts_[r].firstAccess; k != kNone; k = accesses_[k].next) {
        const VulkanScope scope{usages[k].stages, usages[k].access, VK_IMAGE_LAYOUT_UNDEFINED};
        grid.forEach(usages[k].range,
                     [&](size_t sub) { recordAccess(replay_[sub], accesses_[k].writes, scope.layout, scope); });
    }
}

/// Whether any subresource of `range` of resource r still holds a Clobber step's poison.
bool Synchronizer::poisoned(uint32_t r, const SubresourceRange& range) const {
    bool any = false;
    forEachCell(r, range, [&](size_t c) { any |= state_[c].poisoned; });
    return any;
}

/// Barriers for one usage (access `k`) onto `batch`, then the state after it, and the
/// usage's layout (its read run's) and attachment ops.
void Synchronizer::applyAccess(PlannedUsage& pu, uint32_t k, std::vector<Barrier>& batch) {
    const AccessRecord& a = accesses_[k];
    const uint32_t r = pu.resource;
    const bool image = a.image;
    const bool write = a.writes;
    // Here, not in a loop of its own: the first pass's usages it reads are in cache now.
    if (a.firstOfResource) startState(r, batch);
    if (!write && image) pu.layout = readRuns_.layout(k);  // rule 4
    bool discard = pu.usage.access == Access::Write;  // a load-op clear only turns Read into ReadWrite
    // Poison from a Clobber step stays where a discarding write does not write: no
    // transition from UNDEFINED, and an attachment loads it.
    bool loadsPoison = false;
    if (discard && options_.clobberTransients && poisoned(r, pu.range)) {
        discard = false;
        if (isAttachmentStage(pu.usage.stage)) {
            loadsPoison = true;
            pu.access |= pu.usage.stage == Stage::ColorAttachment ? VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT
                                                                  : VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
        }
    }
    const VulkanScope need{pu.stages, pu.access, pu.layout};
    const VkImageLayout target = image ? pu.layout : VK_IMAGE_LAYOUT_UNDEFINED;
    if (cells(pu.range) == 1) {  // the common case: one barrier at most, nothing to merge
        SubresourceState& st = state_[a.cell];
        Barrier& b = batch.emplace_back();
        const auto runScope = [&] { return runScopeFrom(k, 0); };
        if (barrierInto(b, st, need, target, write, discard, runScope)) {
            b.resource = r;
            b.kind = image ? BarrierKind::Image : BarrierKind::Buffer;
            b.range = pu.range;
        } else {
            batch.pop_back();
        }
        recordAccess(st, write, target, need);
    } else {
        const SubresourceGrid& grid = facts_[r].grid;
        SubresourceState* states = stateOf(r);
        perSub_.clear();
        size_t cell = 0;
        grid.forEach(pu.range, [&](size_t sub) {
            const auto runScope = [&, c = cell++] { return runScopeFrom(k, c); };
            perSub_.push_back(barrierFor(states[sub], need, target, write, discard, runScope));
            recordAccess(states[sub], write, target, need);
        });
        merger_.emitMerged(r, image ? BarrierKind::Image : BarrierKind::Buffer, pu.range, perSub_, batch);
    }

    // Every write of a resource that others take over from: their aliasing barriers repeat
    // them (rule 16), so they are gathered here, where the usage is at hand.
    if (write && !predecessor_.empty() && predecessor_[r]) {
        lastUses_[r].stages |= pu.stages;
        lastUses_[r].access |= writeBits(pu.access);
    }
    if (options_.clobberTransients && steps_[a.step].clobber) forEachCell(r, pu.range, [&](size_t c) { state_[c].poisoned = true; });
    if (pu.usage.stage == Stage::Transfer && pu.usage.access == Access::ReadWrite) addInPassBarrier(pu, k);
    if (isAttachmentStage(pu.usage.stage)) {
        if (pu.load != LoadOp::Clear)
            pu.load = pu.usage.access == Access::Write && !loadsPoison ? LoadOp::DontCare : LoadOp::Load;
        pu.store = !write ? StoreOp::None : readLater(k, pu.range) ? StoreOp::Store : StoreOp::DontCare;
    }
    // Its last access: the lifetime ends, and the layout is final unless an export's final
    // barrier changes it (finishResources). Set here, while the resource's record is in
    // cache from its first access a few passes back, rather than in a sweep of its own.
    if (a.next == kNone) {
        PlannedResource& res = planResources()[r];
        res.lastPass = a.step;
        res.finalLayout = stateOf(r)->layout;
        // What a resource taking over its memory later will wait for; kept now, while its
        // state is in cache. (Subresources it never used have nothing to wait for unless
        // aliased: then their aliasing barrier's transition is their last use.)
        if (!lastUses_.empty() && predecessor_[r]) addLastUses(lastUses_[r], stateOf(r), facts_[r].grid.size());
    }
}

/// A ReadWrite transfer takes two commands, a copy out and then a copy in, of the same
/// subresources: the write waits for the read (write-after-read: execution only).
void Synchronizer::addInPassBarrier(const PlannedUsage& pu, uint32_t k) {
    const uint32_t step = accesses_[k].step;
    Barrier b;
    b.resource = pu.resource;
    b.kind = accesses_[k].image ? BarrierKind::Image : BarrierKind::Buffer;
    b.srcStages = pu.stages;
    b.dstStages = pu.stages;
    b.dstAccess = writeBits(pu.access);
    b.oldLayout = b.newLayout = pu.layout;
    b.range = pu.range;
    detail::PlanBuilder::inPassBarriers(plan_).push_back({step, k - steps_[step].firstAccess, b});
}

/// The memory that resource r takes over was last used by its placement's `aliases`
/// (rule 16): every subresource of r starts as if they had written it, their last uses
/// standing for the write. Where they read last, waiting for the reads orders the writes
/// before them too (rule 2); writes nothing read are waited for with a memory dependency.
/// A resource of several subresources gets its aliasing barrier here (startAliasedWhole); one
/// of one subresource, from its first access, as any other barrier. (One that takes over only
/// its own bytes from the previous frame is the same image in the executor, but the plan
/// verifier, and this rule, treat each frame's as a resource of its own.) Returns false when
/// r takes over no memory.
bool Synchronizer::startAliased(uint32_t r, SubresourceState* states, size_t cells, std::vector<Barrier>& batch) {
    const uint32_t p = facts_[r].placement;
    if (p == PlannedResource::kNoPlacement) return false;
    const MemoryPlacement& placement = plan_.memory().placements[p];
    const std::span<const uint32_t> aliases = placement.aliases;
    if (aliases.empty() && placement.previousFrameAliases.empty()) return false;
    // Every earlier use of these bytes in the frame: the aliases' own and, through what each
    // waited for, their predecessors'. The last holders alone would order the rest, but
    // a barrier on them covers only their own bytes, and memory past a smaller alias's end
    // keeps an older holder's writes (the validation layer reports exactly that).
    StageAccess last = previousFrameLastUses_.empty() ? StageAccess{} : previousFrameLastUses_[p];
    for (const uint32_t a : aliases) {
        last.stages |= lastUses_[a].stages | earlierUses_[a].stages;
        last.access |= lastUses_[a].access | earlierUses_[a].access;
    }
    earlierUses_[r] = last;
    if (!last.stages) return false;
    if (cells > 1) {
        startAliasedWhole(r, states, cells, last, batch);
        return true;
    }
    states->aliased = true;
    states->writeStages = last.stages;
    states->writeAccess = last.access;
    return true;
}

/// The aliasing barrier of a resource of several subresources: one barrier over all of them,
/// before its first step's usages, since the spec's "Memory Aliasing" asks that a barrier
/// contain every subresource that overlaps, and for images described differently that is
/// each one. So the barrier has one layout and one destination scope, those of the whole
/// first step: where its usages need different layouts, all of them take GENERAL, which every
/// usage accepts. (Each of them writes: a read there would have no source.) Subresources
/// the first step does not use are transitioned too, and start from the transition.
void Synchronizer::startAliasedWhole(uint32_t r, SubresourceState* states, size_t cells, StageAccess last,
                                     std::vector<Barrier>& batch) {
    auto& usages = *usages_;
    const uint32_t firstAccess = facts_[r].firstAccess;
    const uint32_t step = accesses_[firstAccess].step;
    VulkanScope first{0, 0, usages[firstAccess].layout};
    for (uint32_t k = firstAccess; k != kNone && accesses_[k].step == step; k = accesses_[k].next) {
        first.stages |= usages[k].stages;
        first.access |= usages[k].access;
        if (usages[k].layout != first.layout) first.layout = VK_IMAGE_LAYOUT_GENERAL;
    }
    if (first.layout == VK_IMAGE_LAYOUT_GENERAL)
        for (uint32_t k = firstAccess; k != kNone && accesses_[k].step == step; k = accesses_[k].next)
            usages[k].layout = VK_IMAGE_LAYOUT_GENERAL;
    Barrier& b = batch.emplace_back();
    b.resource = r;
    b.kind = BarrierKind::Image;
    b.range = facts_[r].grid.whole();
    b.aliasing = true;
    b.srcStages = last.stages;
    b.srcAccess = last.access;
    b.dstStages = first.stages;
    b.dstAccess = first.access;
    b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    b.newLayout = first.layout;
    // The transition wrote every subresource: visible to the first step's scope (its usages
    // need no barrier of their own, rule 8's reasoning), nothing else.
    for (size_t c = 0; c < cells; ++c) {
        SubresourceState& st = states[c];
        st = SubresourceState{};
        st.layout = first.layout;
        st.fromOutside = true;
        st.writeStages = first.stages;
        st.visibleStages = first.stages;
        st.visibleAccess = first.access;
    }
}

}  // namespace skygraph::sync
