// The synchronizer's state, shared by the files of its phases (synchronizer.cpp runs them in
// order): access planning, memory, the barrier sweep and the frame's boundaries.
// Internal to the compiler; the rules it applies live beside it (barrier_rules.hpp,
// read_runs.hpp, barrier_merge.hpp).
#pragma once

#include "barrier_merge.hpp"
#include "barrier_rules.hpp"
#include "graph_index.hpp"
#include "plan_builder.hpp"
#include "read_runs.hpp"
#include "scheduler.hpp"
#include "subresources.hpp"
#include "vulkan_state.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/memory.hpp>
#include <skygraph/plan.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace skygraph::sync {

inline constexpr uint32_t kNone = ~0u;

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
    Synchronizer(const Synchronizer&) = delete;
    Synchronizer& operator=(const Synchronizer&) = delete;

    /// The phases in order (synchronizer.cpp). Call once: the plan is moved out.
    Plan run(const Schedule& schedule);

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
    SubresourceState* stateOf(uint32_t r) { return &state_[facts_[r].firstCell]; }
    /// Calls f(flat index into the per-subresource arrays) for every subresource of `range`
    /// of resource r.
    template <typename F>
    void forEachCell(uint32_t r, const SubresourceRange& range, F&& f) const {
        const uint32_t base = facts_[r].firstCell;
        facts_[r].grid.forEach(range, [&](size_t sub) { f(base + sub); });
    }

    // Members declared inline are called only from their own file's loops. Those called per
    // usage or per resource are always inlined: GCC inlines a member called from one place
    // only where no other file can call it, which a class shared by several files is not.

    // Access planning (synchronizer_accesses.cpp): plan steps with clears placed, plan
    // resources, an access record per usage, and the read runs' scopes.
    void planAccesses(const Schedule& schedule);
    void joinReadRunsOptimally();
    void computeRunScopes();
    template <bool InLayout>
    void sweepRunScopes();
    inline void addClobberStep(uint32_t r);
    inline void addClearStep(uint32_t r);
    inline void addFillStep(uint32_t r, bool clobber);
    inline void nameInsertedStep(std::string_view verb, uint32_t r);
    [[gnu::always_inline]] inline uint32_t addResource(uint32_t declIndex);
    [[gnu::always_inline]] inline bool clearsThroughLoadOp(const IndexedUsage& firstUse) const;
    [[gnu::always_inline]] static inline Access effectiveAccess(Access a, bool loadOpClear);
    inline void addSlot(uint32_t pass, const IndexedUsage& u);
    [[noreturn]] void refuseUsedTwice(uint32_t pass, std::span<const IndexedUsage> uses) const;
    inline uint32_t addOwnText(std::string_view text);
    [[gnu::always_inline]] inline void addAccess(uint32_t r, const UsageMode& usage, const SubresourceRange& range,
                                                 bool loadOpClear);

    // Memory (synchronizer_memory.cpp): the transients' placements, wired to the plan's
    // resources, and what the aliasing barriers will wait for (rule 16).
    void planMemory();
    inline void checkRequirements(const MemoryRequirements& m, const ResourceDesc& d, const MemoryModel& model) const;
    [[gnu::always_inline]] inline StageAccess lastUsesInFrame(uint32_t r);

    // The barrier sweep (synchronizer_barriers.cpp): layouts, attachment ops and the barriers
    // before each pass, aliasing barriers included.
    void emitSteps();
    /// Also for the final barriers (synchronizer_boundaries.cpp).
    VulkanScope boundaryScope(uint32_t r, ExternalState state) const;
    [[gnu::always_inline]] inline uint32_t stepEnd(uint32_t s) const;
    [[gnu::always_inline]] inline bool readLater(uint32_t k, const SubresourceRange& range) const;
    [[gnu::always_inline]] inline StageAccess runScopeFrom(uint32_t k, size_t cell) const;
    /// Also for the final barriers of inputs that arrive with no stages of their own.
    VulkanScope firstUsesScope(uint32_t r) const;
    [[gnu::always_inline]] inline void startState(uint32_t r, std::vector<Barrier>& batch);
    inline void replayAccesses(uint32_t r);
    [[gnu::always_inline]] inline bool poisoned(uint32_t r, const SubresourceRange& range) const;
    [[gnu::always_inline]] inline void applyAccess(PlannedUsage& pu, uint32_t k, std::vector<Barrier>& batch);
    inline void addInPassBarrier(const PlannedUsage& pu, uint32_t k);
    [[gnu::always_inline]] inline bool startAliased(uint32_t r, SubresourceState* states, size_t cells,
                                                    std::vector<Barrier>& batch);
    inline void startAliasedWhole(uint32_t r, SubresourceState* states, size_t cells, StageAccess last,
                                  std::vector<Barrier>& batch);
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

    // The frame's boundaries (synchronizer_boundaries.cpp): final barriers, copies per frame
    // in flight, and presentation.
    void finishResources();
    void decideCopies();
    [[noreturn]] void secondPresentedImage(uint32_t first, uint32_t second) const;
    void presentation(uint32_t r);

#if __cpp_aggregate_paren_init < 201902L
    static inline const PlannedUsage kBlankUsage{};  // see addAccess
#endif
    static constexpr int32_t kInsertedPass = -1;  // a Step's declIndex for an inserted step
    static constexpr std::string_view kClearType = "Clear";
    static constexpr std::string_view kReadbackType = "Readback";
    static constexpr std::string_view kClobberType = "Clobber";
    static constexpr UsageMode kClearUsage{Access::Write, Stage::Transfer, BindAs::Default};
    static constexpr UsageMode kReadbackUsage{Access::Read, Stage::Transfer, BindAs::Default};

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
    uint32_t usedTwice_ = kNone;           // an access sharing a subresource with one before it in its step
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
    // Rule 16: room for the aliasing barriers of resources of several subresources, beyond
    // the usages' own.
    uint32_t wholeAliasingBarriers_ = 0;
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

}  // namespace skygraph::sync
