// The synchronizer's sweeps over the plan's accesses: the first (planAccesses) places clears,
// records every usage and joins read runs; a backward one gives multi-subresource reads their
// run scopes; the last (emitSteps) settles layouts and attachment ops and writes the barriers.
// The rules themselves live beside it: one subresource's hazards in barrier_rules.hpp, the
// layout of a run of reads in read_runs.hpp, merging of ranges in barrier_merge.hpp.
#include "synchronizer.hpp"

#include "barrier_merge.hpp"
#include "barrier_rules.hpp"
#include "memory_planner.hpp"
#include "plan_builder.hpp"
#include "read_runs.hpp"
#include "subresources.hpp"
#include "vulkan_state.hpp"

#include <algorithm>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

namespace skygraph {
namespace {

using namespace sync;  // the rules beside this file: barrier_rules.hpp, read_runs.hpp, barrier_merge.hpp

constexpr uint32_t kNone = ~0u;

/// One usage in plan order (access k is the k-th usage of the plan), beside its PlannedUsage
/// (written when the access is recorded: resource, range, stages, access and, until rule 4
/// settles it, its own layout): what the sweeps need besides. Each resource's accesses are
/// chained through `next`. It repeats what the forward sweep would otherwise look up per
/// access in the per-resource tables, which it reaches in no useful order (a cache miss each).
/// Trivially constructible: addAccess writes every field into an array it does not zero first.
struct AccessRecord {
    uint32_t step;        ///< Index into Plan::passes().
    uint32_t next;        ///< The same resource's next access, or kNone.
    /// Index of its first entry in Synchronizer::runScope_, or kNone where runScopeFrom walks
    /// the chain instead: a resource of one subresource under LayoutPolicy::FewestBarriers.
    uint32_t runScopes;
    uint32_t cell;        ///< Flat index of its range's first subresource.
    bool writes;          ///< Of the effective usage (a load-op clear writes).
    bool loadOpClear;     ///< The first use of a `clear` resource, cleared by the load op.
    bool image;           ///< Of its resource.
    bool firstOfResource;
};
static_assert(std::is_trivially_default_constructible_v<AccessRecord>);

/// Per plan resource, what the sweeps ask of it often (its ResourceDesc is large and cold).
struct ResourceFacts {
    uint32_t firstAccess = kNone;  ///< Its accesses, chained through AccessRecord::next.
    uint32_t lastAccess = kNone;
    SubresourceGrid grid;          ///< At the output size.
    /// Where its subresources start in the per-subresource arrays (state_, and the read
    /// runs' and run scopes' scratch), which hold the plan's resources end to end.
    uint32_t firstCell = 0;
    ScopeRow scopeRow{};      ///< Its aspects, as vulkanScope's table row.
    bool image = false;
    bool exported = false;
    bool external = false;
    uint32_t lastStep = 0;    ///< The step of its last access (PlannedResource::lastPass once emitted).
    uint32_t placement = PlannedResource::kNoPlacement;  ///< As PlannedResource::placement.
};

class Synchronizer {
public:
    Synchronizer(const GraphIndex& index, const CompileOptions& o)
        : graph_(index.graph()), index_(index), options_(o), layouts_(o.layouts.value_or(graph_.layouts)) {}

    Plan run(const Schedule& schedule) {
        detail::PlanBuilder::graph(plan_) = graph_.name;
        detail::PlanBuilder::layouts(plan_) = layouts_;
        usages_ = &detail::PlanBuilder::usages(plan_);
        for (const std::string& name : options_.readbacks)  // compile() checked the names
            readbacks_.push_back(static_cast<uint32_t>(graph_.findResource(name) - graph_.resources.data()));
        planAccesses(schedule);
        if (layouts_ == LayoutPolicy::Optimal) joinReadRunsOptimally();
        computeRunScopes();  // while planAccesses' usages are in cache
        planMemory();
        emitSteps();
        finishResources();
        decideCopies();
        return std::move(plan_);
    }

private:
    /// What the barrier sweep needs of a plan pass (a scheduled pass or an inserted Clear),
    /// and where it comes from, which the sweep writes into its PlannedPass.
    struct Step {
        uint32_t firstAccess = 0;  ///< Its accesses are [firstAccess, next step's).
        int32_t declIndex = kInsertedPass;  ///< PlannedPass::declIndex.
        /// Whether two of its barriers can be for one resource (a resource used twice, or a
        /// range of several subresources): only then can mergeAdjacent find anything.
        bool mayMerge = false;
        /// For an inserted step (declIndex < 0): a Readback or a Clobber rather than a Clear.
        bool readback = false;
        bool clobber = false;
    };

    // The plan's arrays, written through the compiler's access to it (plan_builder.hpp).
    std::vector<PlannedResource>& planResources() noexcept { return detail::PlanBuilder::resources(plan_); }
    std::vector<PlannedPass>& planPasses() noexcept { return detail::PlanBuilder::passes(plan_); }

    const ResourceDesc& decl(uint32_t planResource) const {
        return graph_.resources[plan_.resources()[planResource].decl];
    }
    bool isImage(uint32_t planResource) const { return facts_[planResource].image; }
    ExternalState replaced(ExternalState s) const {
        return s == ExternalState::Present ? options_.presentReplacement : s;
    }

    // Plan steps (with clears placed), plan resources, and an access record per usage.
    void planAccesses(const Schedule& schedule) {
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
        }
        // After the frame's last pass: each read-back copies its image's first mip and layer
        // (a `clear` image no pass uses is cleared first, as at any first use).
        for (const uint32_t d : readbacks_) {
            if (planIndex[d] == kNone) {
                planIndex[d] = addResource(d);
                if (index_.clear(d)) addClearStep(planIndex[d]);
            }
            const uint32_t r = planIndex[d];
            steps_.push_back({accessCount_, kInsertedPass, false, true});
            currentStep_ = static_cast<uint32_t>(steps_.size() - 1);
            readbackSteps_.push_back(currentStep_);
            nameInsertedStep("read back ", r);
            addAccess(r, kReadbackUsage, SubresourceRange{0, 1, 0, 1}, false);
        }
    }

    /// Fills transient r with poison before its first use (CompileOptions::clobberTransients):
    /// a transfer write of the whole resource, like a Clear, that the first use then keeps.
    void addClobberStep(uint32_t r) { addFillStep(r, true); }
    void addClearStep(uint32_t r) { addFillStep(r, false); }
    /// An inserted Clear or Clobber step: one transfer write of the whole resource.
    void addFillStep(uint32_t r, bool clobber) {
        Step& step = steps_.emplace_back();
        step.firstAccess = accessCount_;
        step.clobber = clobber;
        currentStep_ = static_cast<uint32_t>(steps_.size() - 1);
        nameInsertedStep(clobber ? "clobber " : "clear ", r);
        addAccess(r, kClearUsage, facts_[r].grid.whole(), false);
    }

    /// Names the step last added "<verb><resource>", once the compiler's own text is complete
    /// (emitSteps).
    void nameInsertedStep(std::string_view verb, uint32_t r) {
        const uint32_t at = addOwnText(verb);
        addOwnText(planResources()[r].name);
        insertedNameAt_.push_back({currentStep_, at, static_cast<uint32_t>(ownText_.size() - at)});
    }

    // Both run once per usage or resource, from planAccesses' loop: inlined there (GCC 12 stops
    // inlining them once they have three callers, which costs 5% of a large compile).
    [[gnu::always_inline]] uint32_t addResource(uint32_t declIndex) {
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
    bool clearsThroughLoadOp(const IndexedUsage& firstUse) const {
        const SubresourceGrid& grid = index_.grid(firstUse.resource);
        return isAttachmentStage(firstUse.usage.stage) && grid.resolve(index_.writtenRange(firstUse)) == grid.whole();
    }
#if __cpp_aggregate_paren_init < 201902L
    static inline const PlannedUsage kBlankUsage{};  // see addAccess
#endif
    static constexpr int32_t kInsertedPass = -1;  // a Step's declIndex for an inserted step
    static constexpr std::string_view kClearType = "Clear";
    static constexpr std::string_view kReadbackType = "Readback";
    static constexpr std::string_view kClobberType = "Clobber";
    static constexpr UsageMode kClearUsage{Access::Write, Stage::Transfer, BindAs::Default};
    static constexpr UsageMode kReadbackUsage{Access::Read, Stage::Transfer, BindAs::Default};

    // A load-op clear writes, so a Read attachment that clears is a ReadWrite for sync.
    static Access effectiveAccess(Access a, bool loadOpClear) {
        return loadOpClear && a == Access::Read ? Access::ReadWrite : a;
    }

    /// Names the slot that the usage last added (`u`, of pass `pass`) fills.
    void addSlot(uint32_t pass, const IndexedUsage& u) {
        const std::string_view slot = graph_.slotName(index_.declOf(pass, u).slot);
        slotAt_.push_back({accessCount_ - 1, addOwnText(slot),
                           static_cast<uint32_t>(slot.size())});
    }
    /// Appends to the compiler's own name table; returns where the text starts.
    uint32_t addOwnText(std::string_view text) {
        const auto offset = static_cast<uint32_t>(ownText_.size());
        ownText_ += text;
        return offset;
    }

    /// Records the next usage in plan order (of the step last added): its Vulkan scope, its
    /// place in its resource's chain of accesses and in its read run (rule 4, as
    /// LayoutPolicy::FewestBarriers joins them; joinReadRunsOptimally joins them anew for
    /// Optimal).
    [[gnu::always_inline]] void addAccess(uint32_t r, const UsageMode& usage, const SubresourceRange& range,
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
    StageAccess runScopeFrom(uint32_t k, size_t cell) const {
        if (accesses_[k].runScopes != kNone) return runScope_[accesses_[k].runScopes + cell];
        const auto& usages = *usages_;
        StageAccess scope{usages[k].stages, usages[k].access};
        for (uint32_t j = accesses_[k].next; j != kNone && !accesses_[j].writes; j = accesses_[j].next) {
            scope.stages |= usages[j].stages;
            scope.access |= usages[j].access;
        }
        return scope;
    }

    /// LayoutPolicy::Optimal's read runs (rule 4), joined anew in place of those planAccesses
    /// joined as FewestBarriers does (a sweep of its own, so that planAccesses tests no policy
    /// per read), and every read's layout settled to its run's. A read's run scope then ends at
    /// the first later read of the subresource in another layout, which runScopeFrom's walk
    /// does not look for: every access gets its run scopes from computeRunScopes instead.
    void joinReadRunsOptimally() {
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
    void computeRunScopes() {
        if (layouts_ == LayoutPolicy::Optimal) sweepRunScopes<true>();
        else sweepRunScopes<false>();
    }
    /// computeRunScopes' sweep; `InLayout`: under LayoutPolicy::Optimal, where a run of a
    /// subresource also ends at a read in another layout.
    template <bool InLayout>
    void sweepRunScopes() {
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

    /// Settles each usage's layout (rule 4) and attachment ops and writes the barriers before
    /// each pass, in one forward sweep. Barriers go straight into the plan's array, and each
    /// PlannedPass is written as soon as its batch is done; then the plan takes the name
    /// tables that its names view.
    void emitSteps() {
        state_ = std::make_unique_for_overwrite<SubresourceState[]>(cellCount_);
        auto& usages = *usages_;
        auto& barriers = detail::PlanBuilder::barriers(plan_);
        // Room for the most barriers there can be (one per subresource an access touches), so
        // the array never moves and each pass's spans are set as its batch is done.
        barriers.reserve(accessCount_ - runScopeAccesses_.size() + runScopeCount_ + aliasedCells_);
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
            const bool aliasingAdded = !aliasedHere_.empty() && finishAliasing(barriers, s);
            if (step.mayMerge || aliasingAdded) mergeAdjacent(barriers, batch);
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
    uint32_t stepEnd(uint32_t s) const {
        return s + 1 < steps_.size() ? steps_[s + 1].firstAccess : accessCount_;
    }

    /// Whether a later access (or the export) reads what access `k` leaves in `range`.
    bool readLater(uint32_t k, const SubresourceRange& range) const {
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

    /// Stages and accesses of resource r's uses in its first pass.
    VulkanScope firstPassScope(uint32_t r) const {
        VulkanScope scope;
        const uint32_t first = plan_.resources()[r].firstPass;
        for (uint32_t k = facts_[r].firstAccess; k != kNone && accesses_[k].step == first; k = accesses_[k].next) {
            scope.stages |= (*usages_)[k].stages;
            scope.access |= (*usages_)[k].access;
        }
        return scope;
    }

    /// Stages and accesses of the first use of each of resource r's subresources: where a
    /// frame's accesses of them begin (different subresources may begin in different passes).
    VulkanScope firstUsesScope(uint32_t r) const {
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
    VulkanScope boundaryScope(uint32_t r, ExternalState state) const {
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
    void startState(uint32_t r) {
        const ResourceFacts& facts = facts_[r];
        SubresourceState* states = &state_[facts.firstCell];
        const size_t cells = facts.grid.size();
        if (cells == 1) *states = SubresourceState{};  // most resources; fill_n's loop costs more
        else std::fill_n(states, cells, SubresourceState{});
        if (!facts_[r].external) {
            if (!takesOver_.empty() && takesOver_[r]) startAliased(r, states, cells);
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
    SubresourceState* stateOf(uint32_t r) { return &state_[facts_[r].firstCell]; }
    /// Whether any subresource of `range` of resource r still holds a Clobber step's poison.
    bool poisoned(uint32_t r, const SubresourceRange& range) const {
        bool any = false;
        forEachCell(r, range, [&](size_t c) { any |= state_[c].poisoned; });
        return any;
    }
    /// Calls f(flat index into the per-subresource arrays) for every subresource of `range`
    /// of resource r.
    template <typename F>
    void forEachCell(uint32_t r, const SubresourceRange& range, F&& f) const {
        const uint32_t base = facts_[r].firstCell;
        facts_[r].grid.forEach(range, [&](size_t sub) { f(base + sub); });
    }

    /// Barriers for one usage (access `k`) onto `batch`, then the state after it, and the
    /// usage's layout (its read run's) and attachment ops.
    void applyAccess(PlannedUsage& pu, uint32_t k, std::vector<Barrier>& batch) {
        const AccessRecord& a = accesses_[k];
        const uint32_t r = pu.resource;
        const bool image = a.image;
        const bool write = a.writes;
        // Here, not in a loop of its own: the first pass's usages it reads are in cache now.
        if (a.firstOfResource) startState(r);
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
            // aliased, which finishAliasing adds.)
            if (!lastUses_.empty() && predecessor_[r]) addLastUses(lastUses_[r], stateOf(r), facts_[r].grid.size());
        }
    }

    /// A ReadWrite transfer takes two commands, a copy out and then a copy in, of the same
    /// subresources: the write waits for the read (write-after-read: execution only).
    void addInPassBarrier(const PlannedUsage& pu, uint32_t k) {
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

    /// The final barriers of exported resources, and their final layouts, once every pass
    /// is emitted.
    void finishResources() {
        for (const uint32_t r : exported_) {
            auto& res = planResources()[r];
            SubresourceState* states = stateOf(r);
            const auto& d = decl(r);
            const VulkanScope scope = boundaryScope(r, replaced(d.final));
            // A persistent resource's next frame repeats this one. If it writes anywhere, the
            // final barrier must order every access of this frame, readers included, before
            // the next frame's first use, exactly as a write would: later passes of the next
            // frame chain through that first use and never name this frame's stages.
            const bool persistent = d.external && replaced(d.final) == replaced(d.initial);
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
        // Each read-back's copy lands in host memory the executor reads after the frame's
        // fence: its writes are made available to the host domain here.
        for (const uint32_t s : readbackSteps_) {
            Barrier b;
            b.resource = (*usages_)[steps_[s].firstAccess].resource;
            b.kind = BarrierKind::Memory;
            b.srcStages = VK_PIPELINE_STAGE_2_TRANSFER_BIT;
            b.srcAccess = VK_ACCESS_2_TRANSFER_WRITE_BIT;
            b.dstStages = VK_PIPELINE_STAGE_2_HOST_BIT;
            b.dstAccess = VK_ACCESS_2_HOST_READ_BIT;
            detail::PlanBuilder::finalBarriers(plan_).push_back(b);
        }
    }

    /// Which resources need a copy per frame in flight: frames in flight overlap on the GPU,
    /// and nothing in a plan orders one frame's accesses after another's unless a resource is
    /// exported (its final barrier and the next frame's first use chain across frames). A
    /// transient is SharedTransient when the frames share the heaps (set by planMemory), and
    /// otherwise keeps the default, PerFrameTransient.
    void decideCopies() {
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
    [[noreturn]] void secondPresentedImage(uint32_t first, uint32_t second) const {
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
    void presentation(uint32_t r) {
        VkPipelineStageFlags2 lastStages = 0;
        for (Barrier& b : detail::PlanBuilder::finalBarriers(plan_))
            if (b.resource == r && b.newLayout == VK_IMAGE_LAYOUT_PRESENT_SRC_KHR) {
                b.dstStages = b.srcStages;
                lastStages |= b.srcStages;
            }
        detail::PlanBuilder::presentations(plan_).push_back({r, planResources()[r].firstStages, lastStages});
    }

    /// A model's answer the planner can place: a size, a power-of-two alignment, a memory type,
    /// and a size that stays far from overflowing the heap's offsets. An embedder's model that
    /// answers otherwise is named with the resource it answered for.
    void checkRequirements(const MemoryRequirements& m, const ResourceDesc& d, const MemoryModel& model) const {
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
    void planMemory() {
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
            if (facts_[r].grid.size() > 1) aliasedCells_ += static_cast<uint32_t>(facts_[r].grid.size());
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

    /// Adds to `last` what a barrier after the uses of a resource in the frame waits for, given
    /// the state of its subresources `states` after them (rule 16): per subresource, its last
    /// write with its access and the reads since. The caller adds every earlier write of the
    /// frame to it too: the reads alone would order the writes (rule 2), but the barriers that
    /// made the writes available named only the subresources they wrote, and the spec asks
    /// the barrier between aliases to contain every subresource that overlaps. The aliasing
    /// barrier does, so it is the memory dependency itself.
    static void addLastUses(StageAccess& last, const SubresourceState* states, size_t cells) {
        for (size_t c = 0; c < cells; ++c) {
            last.stages |= states[c].readStages | states[c].writeStages;
            last.access |= states[c].writeAccess;
        }
    }

    /// What a barrier after resource r's uses in the frame waits for, as addLastUses would
    /// find it after the frame's barriers: from what addAccess folded per subresource, before
    /// they are written (the next frame's first uses of r's bytes need it at their start).
    StageAccess lastUsesInFrame(uint32_t r) {
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

    /// Resource r's accesses in the frame replayed with rules 1-5's bookkeeping into replay_
    /// (per subresource, what the frame leaves), before the frame's barriers are written.
    void replayAccesses(uint32_t r) {
        const auto& usages = *usages_;
        const SubresourceGrid& grid = facts_[r].grid;
        replay_.assign(grid.size(), SubresourceState{});
        for (uint32_t k = facts_[r].firstAccess; k != kNone; k = accesses_[k].next) {
            const VulkanScope scope{usages[k].stages, usages[k].access, VK_IMAGE_LAYOUT_UNDEFINED};
            grid.forEach(usages[k].range,
                         [&](size_t sub) { recordAccess(replay_[sub], accesses_[k].writes, scope.layout, scope); });
        }
    }

    /// The memory that resource r takes over was last used by its placement's `aliases`
    /// (rule 16): every subresource of r starts as if they had written it, their last uses
    /// standing for the write. Where they read last, waiting for the reads orders the writes
    /// before them too (rule 2); writes nothing read are waited for with a memory dependency.
    /// Returns false when r takes over no memory.
    bool startAliased(uint32_t r, SubresourceState* states, size_t cells) {
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
        for (size_t c = 0; c < cells; ++c) {
            states[c].aliased = true;
            states[c].writeStages = last.stages;
            states[c].writeAccess = last.access;
        }
        // A resource of one subresource is covered by its first access's own barrier.
        if (cells > 1) aliasedHere_.push_back(r);
        return true;
    }

    /// After the first step of each resource that takes over memory (aliasedHere_): the
    /// subresources that step did not touch get their aliasing barrier too, into the layout
    /// of its first use, so that the step's batch covers the whole resource (the spec's
    /// "Memory Aliasing": the barrier must contain every subresource that overlaps). Returns
    /// whether it added any.
    bool finishAliasing(std::vector<Barrier>& batch, uint32_t step) {
        bool added = false;
        for (const uint32_t r : aliasedHere_) {
            SubresourceState* states = stateOf(r);
            const SubresourceGrid& grid = facts_[r].grid;
            const VulkanScope first = firstPassScope(r);
            const VkImageLayout layout = (*usages_)[facts_[r].firstAccess].layout;
            perSub_.clear();
            bool any = false;
            grid.forEach(grid.whole(), [&](size_t sub) {
                SubresourceState& st = states[sub];
                if (!st.aliased) {
                    perSub_.emplace_back();
                    return;
                }
                Barrier b;
                b.aliasing = true;
                b.srcStages = st.writeStages;
                b.srcAccess = st.writeAccess;
                b.dstStages = first.stages;
                b.dstAccess = first.access;
                b.newLayout = layout;
                perSub_.push_back(b);
                // The transition wrote it: visible to the first step's scope (a later use
                // inside that scope needs no barrier, rule 8's reasoning), nothing else.
                st = SubresourceState{};
                st.layout = layout;
                st.fromOutside = true;
                st.writeStages = first.stages;
                st.visibleStages = first.stages;
                st.visibleAccess = first.access;
                any = true;
            });
            if (any) merger_.emitMerged(r, BarrierKind::Image, grid.whole(), perSub_, batch);
            if (any && planResources()[r].lastPass == step && predecessor_[r]) lastUses_[r].stages |= first.stages;
            added |= any;
        }
        aliasedHere_.clear();
        return added;
    }

    const GraphDesc& graph_;
    const GraphIndex& index_;
    const CompileOptions& options_;
    Plan plan_;
    // Per plan resource.
    std::vector<ResourceFacts> facts_;
    std::vector<uint32_t> exported_;       // plan resources that are exported, in plan order
    std::vector<uint32_t> external_;       // plan resources that are external, in plan order
    std::vector<uint32_t> readbacks_;      // graph resources read back to the host, by name
    std::vector<uint32_t> readbackSteps_;  // their steps
    uint32_t cellCount_ = 0;               // subresources of all plan resources
    std::vector<Step> steps_;              // per plan pass
    uint32_t currentStep_ = 0;             // the step last added, whose accesses are being added
    // Per access (usage in plan order).
    // Sized for every access there can be (planAccesses), so records are written in place.
    std::unique_ptr<AccessRecord[]> accesses_;
    uint32_t accessCount_ = 0;
    std::vector<PlannedUsage>* usages_ = nullptr;  // the plan's, one per access
    // The compiler's own name table: slot names and inserted clears' names, one after
    // another, and which usage's slot (slotAt_) or plan pass's name (insertedNameAt_) views each.
    struct NameAt { uint32_t item, offset, length; };
    std::string ownText_;
    std::vector<NameAt> slotAt_, insertedNameAt_;
    ReadRuns readRuns_;
    uint32_t runScopeCount_ = 0;
    std::vector<StageAccess> runScope_;    // per access of runScopeAccesses_, per cell of its range
    std::vector<uint32_t> runScopeAccesses_;  // accesses whose run scopes runScope_ holds, in order
    // Per subresource of every resource.
    std::unique_ptr<SubresourceState[]> state_;  // each resource's set at its first access
    // Scratch, reused across usages.
    std::vector<std::optional<Barrier>> perSub_;
    BarrierMerger merger_;
    // Rule 16: resources whose first step is being emitted and that take over memory, and
    // room for their aliasing barriers beyond the usages' own.
    std::vector<uint32_t> aliasedHere_;
    uint32_t aliasedCells_ = 0;
    // With frames sharing the heaps: per placement, the previous frame's last uses of the bytes
    // no earlier resource of the frame holds.
    std::vector<StageAccess> previousFrameLastUses_;
    std::vector<StageAccess> lastUses_;   // per plan resource taken over from: its writes, then its last uses
    std::vector<StageAccess> earlierUses_;  // per plan resource taking over: what its aliasing barrier waits for
    std::vector<uint8_t> takesOver_;      // per plan resource: its placement has aliases
    std::vector<uint8_t> predecessor_;    // per plan resource: some placement names it an alias
    std::vector<SubresourceState> replay_;  // replayAccesses' result
    // With frames sharing the heaps, per subresource of every resource (as state_): its
    // accesses in the frame folded as replayAccesses would leave it, while addAccess has them.
    struct FrameUses {
        StageAccess writes;                     // every write
        VkPipelineStageFlags2 lastWriteStages = 0;
        VkPipelineStageFlags2 readsSince = 0;   // the reads after the last write
    };
    std::vector<FrameUses> frameUses_;
    const LayoutPolicy layouts_;  // the options', else the graph's
};

}  // namespace

Plan synchronize(const GraphIndex& index, const Schedule& schedule, const CompileOptions& options) {
    return Synchronizer(index, options).run(schedule);
}

}  // namespace skygraph
