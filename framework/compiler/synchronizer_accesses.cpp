// The synchronizer's first sweep: plan steps (with Clear, Clobber and Readback steps placed),
// plan resources, and an access record per usage, each resource's accesses chained and each
// read joined to its run (rule 4 of docs/barriers.md); then a backward sweep gives the reads
// of resources of several subresources their run scopes.
#include "synchronizer_state.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace skygraph::sync {

/// Fills transient r with poison before its first use (CompileOptions::clobberTransients):
/// a transfer write of the whole resource, like a Clear, that the first use then keeps.
void Synchronizer::addClobberStep(uint32_t r) { addFillStep(r, true); }

void Synchronizer::addClearStep(uint32_t r) { addFillStep(r, false); }

/// An inserted Clear or Clobber step: one transfer write of the whole resource.
void Synchronizer::addFillStep(uint32_t r, bool clobber) {
    Step& step = steps_.emplace_back();
    step.firstAccess = accessCount_;
    step.clobber = clobber;
    currentStep_ = static_cast<uint32_t>(steps_.size() - 1);
    nameInsertedStep(clobber ? "clobber " : "clear ", r);
    addAccess(r, kClearUsage, facts_[r].grid.whole(), false);
}

/// Names the step last added "<verb><resource>", once the compiler's own text is complete
/// (emitSteps).
void Synchronizer::nameInsertedStep(std::string_view verb, uint32_t r) {
    const uint32_t at = addOwnText(verb);
    addOwnText(planResources()[r].name);
    insertedNameAt_.push_back({currentStep_, at, static_cast<uint32_t>(ownText_.size() - at)});
}

// Run once per resource, from planAccesses' loop, and always inlined there (as addAccess is,
// per usage): as calls they cost 5% of a large compile.
inline uint32_t Synchronizer::addResource(uint32_t declIndex) {
    PlannedResource& res = planResources().emplace_back();
    res.decl = declIndex;
    res.name = index_.resourceName(declIndex);
    const SubresourceGrid& grid = index_.grid(declIndex);
#if __cpp_aggregate_paren_init >= 201902L  // in place: a braced temporary is built, then copied
    facts_.emplace_back(kNone, kNone, grid, cellCount_, scopeRow(index_.aspects(declIndex)),
                        index_.aspects(declIndex).image, index_.exported(declIndex), index_.external(declIndex));
#else
    facts_.push_back({kNone, kNone, grid, cellCount_, scopeRow(index_.aspects(declIndex)),
                      index_.aspects(declIndex).image, index_.exported(declIndex), index_.external(declIndex)});
#endif
    if (index_.exported(declIndex)) exported_.push_back(static_cast<uint32_t>(planResources().size() - 1));
    if (index_.external(declIndex)) external_.push_back(static_cast<uint32_t>(planResources().size() - 1));
    cellCount_ += static_cast<uint32_t>(grid.size());
    return static_cast<uint32_t>(planResources().size() - 1);
}

// A `clear` resource is cleared by its first use: through the load op when that use is an
// attachment covering the whole resource, otherwise by a Clear pass inserted before it.
bool Synchronizer::clearsThroughLoadOp(const IndexedUsage& firstUse) const {
    const SubresourceGrid& grid = index_.grid(firstUse.resource);
    return isAttachmentStage(firstUse.usage.stage) && grid.resolve(index_.writtenRange(firstUse)) == grid.whole();
}

// A load-op clear writes, so a Read attachment that clears is a ReadWrite for sync.
Access Synchronizer::effectiveAccess(Access a, bool loadOpClear) {
    return loadOpClear && a == Access::Read ? Access::ReadWrite : a;
}

/// Names the slot that the usage last added (`u`, of pass `pass`) fills.
void Synchronizer::addSlot(uint32_t pass, const IndexedUsage& u) {
    const std::string_view slot = graph_.slotName(index_.declOf(pass, u).slot);
    slotAt_.push_back({accessCount_ - 1, addOwnText(slot),
                       static_cast<uint32_t>(slot.size())});
}

/// Appends to the compiler's own name table; returns where the text starts.
uint32_t Synchronizer::addOwnText(std::string_view text) {
    const auto offset = static_cast<uint32_t>(ownText_.size());
    ownText_ += text;
    return offset;
}

/// Records the next usage in plan order (of the step last added): its Vulkan scope, its
/// place in its resource's chain of accesses and in its read run (rule 4, as
/// LayoutPolicy::FewestBarriers joins them; joinReadRunsOptimally joins them anew for
/// Optimal).
inline void Synchronizer::addAccess(uint32_t r, const UsageMode& usage, const SubresourceRange& range,
                                      bool loadOpClear) {
    const uint32_t k = accessCount_++;
    const Access effective = effectiveAccess(usage.access, loadOpClear);
    const VulkanScope scope = vulkanScope(facts_[r].scopeRow, effective, usage.stage, usage.as);
    // Constructed in place, each field stored once. Value-initialising the record zeroes
    // it with `rep stos`, whose start-up cost is paid once per usage; building it as a
    // braced temporary first stores its empty slot as two 8-byte halves, which the copy
    // into the array reads as one 16-byte load that the CPU cannot forward from its store
    // buffer (perf showed that one instruction at a tenth of this function). Without
    // aggregate initialisation from parentheses (clang before 16), it is copied from a
    // blank constant and filled in place.
#if __cpp_aggregate_paren_init >= 201902L
    usages_->emplace_back(scope.stages, scope.access, std::string_view(), range, r, scope.layout, usage,
                          loadOpClear ? LoadOp::Clear : LoadOp::Load, StoreOp::Store);
#else
    PlannedUsage& pu = usages_->emplace_back(kBlankUsage);
    pu.stages = scope.stages;
    pu.access = scope.access;
    pu.usage = usage;
    pu.range = range;
    pu.resource = r;
    pu.layout = scope.layout;
    if (loadOpClear) pu.load = LoadOp::Clear;
#endif
    AccessRecord& a = accesses_[k];
    a.step = currentStep_;
    a.next = kNone;
    const ResourceFacts& facts = facts_[r];
    a.writes = writesContents(effective);
    a.loadOpClear = loadOpClear;
    a.image = facts.image;
    a.firstOfResource = false;
    a.cell = facts.firstCell;  // of a resource of one subresource, every range compile() accepts
    a.runScopes = kNone;
    if (facts.grid.size() > 1) {
        a.cell += static_cast<uint32_t>(facts.grid.index(range.baseMip, range.baseLayer));
        a.runScopes = runScopeCount_;
        runScopeCount_ += static_cast<uint32_t>(cells(range));
        runScopeAccesses_.push_back(k);
    }
    readRuns_.add(k, !a.writes && a.image ? scope.layout : VK_IMAGE_LAYOUT_UNDEFINED);
    if (a.image) {
        if (cells(range) == 1)  // most accesses; spelled out, as the lambda below is not inlined
            readRuns_.visit(k, a.cell, !a.writes);
        else
            forEachCell(r, range, [&](size_t sub) { readRuns_.visit(k, sub, !a.writes); });
    }
    ResourceFacts& f = facts_[r];  // taken again: one mutable reference from the top measured +0.35M instructions
    // The stages that the resource's first pass uses it in are gathered here, while its
    // plan record is in cache (the barrier sweep would reach it cold).
    if (f.firstAccess == kNone) {
        f.firstAccess = k;
        a.firstOfResource = true;
        planResources()[r].firstPass = a.step;
        planResources()[r].firstStages = scope.stages;
    } else {
        accesses_[f.lastAccess].next = k;
        if (accesses_[f.lastAccess].step == a.step) {
            steps_.back().mayMerge = true;
            if (planResources()[r].firstPass == a.step) planResources()[r].firstStages |= scope.stages;
            // Only a resource used again in its step can have a subresource used twice there.
            if (usedTwice_ == kNone)
                for (uint32_t j = steps_.back().firstAccess; j < k; ++j)
                    if ((*usages_)[j].resource == r && (*usages_)[j].range.overlaps(range)) usedTwice_ = k;
        }
    }
    if (cells(range) > 1) steps_.back().mayMerge = true;
    f.lastAccess = k;
    f.lastStep = a.step;
    if (!frameUses_.empty()) {
        const auto fold = [&](FrameUses& uses) {
            if (a.writes) {
                uses.writes.stages |= scope.stages;
                uses.writes.access |= writeBits(scope.access);
                uses.lastWriteStages = scope.stages;
                uses.readsSince = 0;
            } else {
                uses.readsSince |= scope.stages;
            }
        };
        if (cells(range) == 1) fold(frameUses_[a.cell]);  // most accesses
        else forEachCell(r, range, [&](size_t c) { fold(frameUses_[c]); });
    }
}

/// What the loader refuses in a file, for a GraphDesc built in code: two usages of pass `p`
/// (its scheduled step, the last added) that share a subresource, the later of which
/// addAccess found (usedTwice_). A render pass cannot take an attachment as its own input,
/// and one barrier cannot order a pass after itself.
void Synchronizer::refuseUsedTwice(uint32_t p, std::span<const IndexedUsage> uses) const {
    const uint32_t first = steps_.back().firstAccess;
    const auto& usages = *usages_;
    const uint32_t i = usedTwice_ - first;
    uint32_t j = 0;
    while (usages[first + j].resource != usages[usedTwice_].resource ||
           !usages[first + j].range.overlaps(usages[usedTwice_].range))
        ++j;
    // Usages written by their resource's name share a path: the other is then named by index.
    const std::string at = index_.jsonPathOf(p, uses[i]), other = index_.jsonPathOf(p, uses[j]);
    Diagnostics diags;
    diags.add({graph_.file, at, graph_.passes[p].name, std::string(plan_.resources()[usages[usedTwice_].resource].name),
               "overlaps " + (other != at ? other : "the pass's usage " + std::to_string(j) + " of it") +
                   "; one pass may use each subresource once"});
    throw GraphError(std::move(diags));
}

// Plan steps (with clears placed), plan resources, and an access record per usage.
void Synchronizer::planAccesses(const Schedule& schedule) {
    std::vector<uint32_t> planIndex(graph_.resources.size(), kNone);
    // Every scheduled pass and usage, and an inserted Clear (one access) at most per
    // `clear` resource: at its first use only; when clobbering, a Clobber at most per other
    // resource.
    const size_t clobberRoom = options_.clobberTransients ? graph_.resources.size() : 0;
    steps_.reserve(schedule.passes.size() + index_.clearResources() + 2 * readbacks_.size() + clobberRoom);
    planResources().reserve(graph_.resources.size());
    facts_.reserve(graph_.resources.size());
    // Zeroed once, for every subresource there can be (the plan's resources are fewer).
    if (options_.shareTransientsAcrossFrames) frameUses_.resize(index_.cells());
    const size_t accessRoom = schedule.usages + index_.clearResources() + 2 * readbacks_.size() + clobberRoom;
    if (accessRoom >= kNone) throw std::length_error("synchronizer: more usages than access indices");
    accesses_ = std::make_unique_for_overwrite<AccessRecord[]>(accessRoom);
    usages_->reserve(accessRoom);
    readRuns_.allocate(accessRoom, index_.cells());  // the plan's resources are fewer
    std::vector<uint32_t> clearsBefore;    // resources that a Clear before this pass clears
    std::vector<uint32_t> clobbersBefore;  // transients that a Clobber before this pass poisons
    for (size_t s = 0; s < schedule.passes.size(); ++s) {
        const uint32_t p = schedule.passes[s];
        const auto uses = index_.usesOf(p);
        clearsBefore.clear();
        clobbersBefore.clear();
        for (const IndexedUsage& u : uses) {
            const uint32_t d = u.resource;
            if (planIndex[d] != kNone) continue;
            planIndex[d] = addResource(d);
            if (index_.clear(d)) {
                if (!clearsThroughLoadOp(u)) clearsBefore.push_back(planIndex[d]);
            } else if (clobberRoom && !index_.external(d) && !index_.exported(d)) {
                clobbersBefore.push_back(planIndex[d]);
            }
        }
        // The bound above holds by construction; checked once per pass all the same, as the
        // records are written without bounds checks.
        if (accessCount_ + clearsBefore.size() + clobbersBefore.size() + uses.size() > accessRoom)
            throw std::logic_error("synchronizer: the access bound was exceeded");
        for (uint32_t r : clearsBefore) addClearStep(r);
        for (uint32_t r : clobbersBefore) addClobberStep(r);
        steps_.push_back({accessCount_, static_cast<int32_t>(p)});
        currentStep_ = static_cast<uint32_t>(steps_.size() - 1);
        for (const IndexedUsage& u : uses) {
            const uint32_t r = planIndex[u.resource];
            // The resource's first access, unless a Clear pass above took that role.
            const bool loadOpClear =
                facts_[r].firstAccess == kNone && index_.clear(u.resource) && clearsThroughLoadOp(u);
            addAccess(r, u.usage, facts_[r].grid.resolve(index_.writtenRange(u)), loadOpClear);
            if (u.fillsSlot) addSlot(p, u);
        }
        if (usedTwice_ != kNone) refuseUsedTwice(p, uses);
    }
    // What the frame hands on after its last pass but no pass that runs used (its users
    // switched off or culled) joins the plan there: a `clear` one cleared, as at any first use.
    const auto usedAfterThePasses = [&](uint32_t d) {
        if (planIndex[d] == kNone) {
            planIndex[d] = addResource(d);
            if (index_.clear(d)) addClearStep(planIndex[d]);
        }
        return planIndex[d];
    };
    // An output is handed on whole.
    for (const uint32_t d : index_.clearOutputs()) (void)usedAfterThePasses(d);
    // Each read-back copies its image's first mip and layer.
    for (const uint32_t d : readbacks_) {
        const uint32_t r = usedAfterThePasses(d);
        steps_.push_back({accessCount_, kInsertedPass, false, true});
        currentStep_ = static_cast<uint32_t>(steps_.size() - 1);
        readbackSteps_.push_back(currentStep_);
        nameInsertedStep("read back ", r);
        addAccess(r, kReadbackUsage, SubresourceRange{0, 1, 0, 1}, false);
    }
}

/// LayoutPolicy::Optimal's read runs (rule 4), joined anew in place of those planAccesses
/// joined as FewestBarriers does (a sweep of its own, so that planAccesses tests no policy
/// per read), and every read's layout settled to its run's. A read's run scope then ends at
/// the first later read of the subresource in another layout, which runScopeFrom's walk
/// does not look for: every access gets its run scopes from computeRunScopes instead.
void Synchronizer::joinReadRunsOptimally() {
    auto& usages = *usages_;
    readRuns_.allocate(accessCount_, index_.cells());
    runScopeAccesses_.clear();
    runScopeCount_ = 0;
    for (uint32_t k = 0; k < accessCount_; ++k) {
        AccessRecord& a = accesses_[k];
        // Each usage's layout is still its own (scope.layout): emitSteps settles it.
        readRuns_.add(k, a.image && !a.writes ? usages[k].layout : VK_IMAGE_LAYOUT_UNDEFINED);
        if (a.image) {
            const ResourceFacts& f = facts_[usages[k].resource];
            readRuns_.visitOptimal(k, f.firstCell, f.grid, usages[k].range, !a.writes);
        }
        a.runScopes = runScopeCount_;
        runScopeCount_ += static_cast<uint32_t>(cells(usages[k].range));
        runScopeAccesses_.push_back(k);
    }
    for (uint32_t k = 0; k < accessCount_; ++k)
        if (accesses_[k].image && !accesses_[k].writes) usages[k].layout = readRuns_.layout(k);
}

/// runScopeFrom's answers for every read of a resource of several subresources (of every
/// resource under LayoutPolicy::Optimal), per subresource of its range: one backward sweep
/// over those resources' accesses.
void Synchronizer::computeRunScopes() {
    if (layouts_ == LayoutPolicy::Optimal) sweepRunScopes<true>();
    else sweepRunScopes<false>();
}

/// computeRunScopes' sweep; `InLayout`: under LayoutPolicy::Optimal, where a run of a
/// subresource also ends at a read in another layout.
template <bool InLayout>
void Synchronizer::sweepRunScopes() {
    const auto& usages = *usages_;
    runScope_.resize(runScopeCount_);
    std::vector<StageAccess> pending(cellCount_);  // per subresource
    // Per subresource, the layout of the reads in `pending` (InLayout only).
    std::vector<VkImageLayout> pendingLayout(InLayout ? cellCount_ : 0, VK_IMAGE_LAYOUT_UNDEFINED);
    for (auto it = runScopeAccesses_.rbegin(); it != runScopeAccesses_.rend(); ++it) {
        const AccessRecord& a = accesses_[*it];
        const PlannedUsage& u = usages[*it];
        StageAccess* out = &runScope_[a.runScopes];
        forEachCell(u.resource, u.range, [&](size_t sub) {
            if (a.writes) {
                pending[sub] = {};
            } else {
                if (InLayout && std::exchange(pendingLayout[sub], u.layout) != u.layout)
                    pending[sub] = {};  // the reads after this one are another run's
                pending[sub].stages |= u.stages;
                pending[sub].access |= u.access;
                *out = pending[sub];
            }
            ++out;
        });
    }
}

}  // namespace skygraph::sync
