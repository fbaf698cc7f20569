#include "synchronizer.hpp"

#include "subresources.hpp"
#include "vulkan_state.hpp"

#include <algorithm>
#include <numeric>
#include <optional>

namespace skygraph {
namespace {

/// What is known about one subresource between passes.
struct SubresourceState {
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkPipelineStageFlags2 writeStages = 0;    ///< Stages of the last write (or the outside).
    /// Write accesses of that write. A barrier whose source is `writeStages` always repeats
    /// them: an earlier availability operation only counts for barriers that chain after the
    /// barrier that performed it (through its destination stages), which this one may not.
    VkAccessFlags2 writeAccess = 0;
    VkPipelineStageFlags2 readStages = 0;     ///< Reads since the last write: WAR sources.
    VkPipelineStageFlags2 visibleStages = 0;  ///< Scope the last write is visible to.
    VkAccessFlags2 visibleAccess = 0;
    /// Contents came from outside the frame; a barrier needing a source stage chains with
    /// the semaphore wait at the first use's stages.
    bool fromOutside = false;
};

/// One usage of one resource in plan order.
struct AccessRef {
    uint32_t step = 0;   ///< Index into Plan::passes.
    uint32_t usage = 0;  ///< Index into PlannedPass::usages.
};

bool covers(VkPipelineStageFlags2 haveStages, VkAccessFlags2 haveAccess, const VulkanScope& need) {
    return (need.stages & ~haveStages) == 0 && (need.access & ~haveAccess) == 0;
}

/// Union-find over the accesses of one resource, grouping runs of reads that must share one
/// layout (reads of overlapping subresources with no write between).
struct ReadRuns {
    std::vector<uint32_t> parent;
    uint32_t find(uint32_t a) {
        while (parent[a] != a) a = parent[a] = parent[parent[a]];
        return a;
    }
    void unite(uint32_t a, uint32_t b) { parent[find(a)] = find(b); }
};

class Synchronizer {
public:
    Synchronizer(const GraphDesc& g, const CompileOptions& o) : graph_(g), options_(o) {}

    Plan run(const Schedule& schedule) {
        plan_.graph = graph_.name;
        buildSteps(schedule);
        collectAccesses();
        for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
            groupReadRuns(r);
            computeRunScopes(r);
        }
        initState();
        for (uint32_t s = 0; s < plan_.passes.size(); ++s) {
            for (uint32_t u = 0; u < plan_.passes[s].usages.size(); ++u) applyAccess(s, u);
            mergeAdjacent(plan_.passes[s].barriers);
        }
        finalBarriers();
        return std::move(plan_);
    }

private:
    const ResourceDesc& decl(uint32_t planResource) const {
        return graph_.resources[plan_.resources[planResource].decl];
    }
    ExternalState replaced(ExternalState s) const {
        return s == ExternalState::Present ? options_.presentReplacement : s;
    }

    // Plan passes, resources and usages, with clears placed.
    void buildSteps(const Schedule& schedule) {
        std::vector<int32_t> planIndex(graph_.resources.size(), -1);
        for (uint32_t p : schedule.passes) {
            const PassDesc& pass = graph_.passes[p];
            PlannedPass step{pass.name, pass.type, static_cast<int32_t>(p), {}, {}};
            for (const auto& u : pass.uses) {
                if (planIndex[u.resource] < 0) {
                    planIndex[u.resource] = static_cast<int32_t>(plan_.resources.size());
                    PlannedResource res;
                    res.decl = u.resource;
                    res.name = graph_.resources[u.resource].name;
                    plan_.resources.push_back(res);
                    grids_.emplace_back(graph_.resources[u.resource], options_.outputWidth,
                                        options_.outputHeight);
                }
                const uint32_t r = static_cast<uint32_t>(planIndex[u.resource]);
                PlannedUsage pu;
                pu.resource = r;
                pu.usage = u.usage;
                pu.slot = u.slot;
                pu.range = grids_[r].resolve(u.usage);
                step.usages.push_back(pu);
            }
            plan_.passes.push_back(std::move(step));
        }
        placeClears();
        for (auto& step : plan_.passes)
            for (auto& pu : step.usages) {
                const auto scope = vulkanScope(decl(pu.resource), effectiveUsage(pu));
                pu.layout = scope.layout;
                pu.stages = scope.stages;
                pu.access = scope.access;
            }
    }

    // A `clear` resource is cleared by its first use: through the load op when that use is an
    // attachment covering the whole resource, otherwise by a Clear pass inserted before it.
    void placeClears() {
        constexpr uint32_t kNone = ~0u;
        std::vector<std::pair<uint32_t, uint32_t>> first(plan_.resources.size(), {kNone, 0});
        for (uint32_t s = 0; s < plan_.passes.size(); ++s)
            for (uint32_t u = 0; u < plan_.passes[s].usages.size(); ++u) {
                auto& f = first[plan_.passes[s].usages[u].resource];
                if (f.first == kNone) f = {s, u};
            }
        std::vector<std::vector<uint32_t>> clearsBefore(plan_.passes.size());
        bool inserts = false;
        for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
            if (!decl(r).clear || first[r].first == kNone) continue;
            auto& use = plan_.passes[first[r].first].usages[first[r].second];
            if (isAttachmentStage(use.usage.stage) && use.range == grids_[r].whole()) {
                use.load = LoadOp::Clear;
            } else {
                clearsBefore[first[r].first].push_back(r);
                inserts = true;
            }
        }
        if (!inserts) return;
        std::vector<PlannedPass> steps;
        steps.reserve(plan_.passes.size() + plan_.resources.size());
        for (uint32_t s = 0; s < plan_.passes.size(); ++s) {
            for (uint32_t r : clearsBefore[s]) {
                PlannedUsage clear;
                clear.resource = r;
                clear.usage = {Access::Write, Stage::Transfer, BindAs::Default, std::nullopt};
                clear.range = grids_[r].whole();
                steps.push_back(PlannedPass{"clear " + decl(r).name, "Clear", -1, {}, {clear}});
            }
            steps.push_back(std::move(plan_.passes[s]));
        }
        plan_.passes = std::move(steps);
    }

    // A load-op clear writes, so a Read attachment that clears is a ReadWrite for sync.
    static Usage effectiveUsage(const PlannedUsage& pu) {
        Usage u = pu.usage;
        if (pu.load == LoadOp::Clear && u.access == Access::Read) u.access = Access::ReadWrite;
        return u;
    }

    void collectAccesses() {
        accesses_.assign(plan_.resources.size(), {});
        for (uint32_t s = 0; s < plan_.passes.size(); ++s)
            for (uint32_t u = 0; u < plan_.passes[s].usages.size(); ++u) {
                const uint32_t r = plan_.passes[s].usages[u].resource;
                if (accesses_[r].empty()) plan_.resources[r].firstPass = s;
                plan_.resources[r].lastPass = s;
                accesses_[r].push_back({s, u});
            }
        accessIndex_.resize(plan_.passes.size());
        for (uint32_t r = 0; r < plan_.resources.size(); ++r)
            for (uint32_t i = 0; i < accesses_[r].size(); ++i) {
                auto& per = accessIndex_[accesses_[r][i].step];
                per.resize(plan_.passes[accesses_[r][i].step].usages.size());
                per[accesses_[r][i].usage] = i;
            }
    }

    const PlannedUsage& usageOf(const AccessRef& a) const {
        return plan_.passes[a.step].usages[a.usage];
    }
    bool writes(const PlannedUsage& pu) const { return writesContents(effectiveUsage(pu).access); }

    void groupReadRuns(uint32_t r) {
        const auto& list = accesses_[r];
        ReadRuns runs;
        runs.parent.resize(list.size());
        std::iota(runs.parent.begin(), runs.parent.end(), 0u);
        std::vector<int64_t> open(grids_[r].size(), -1);
        for (uint32_t i = 0; i < list.size(); ++i) {
            const auto& pu = usageOf(list[i]);
            const bool isWrite = writes(pu);
            grids_[r].forEach(pu.range, [&](size_t sub) {
                if (isWrite) {
                    open[sub] = -1;
                } else {
                    if (open[sub] >= 0) runs.unite(static_cast<uint32_t>(open[sub]), i);
                    open[sub] = i;
                }
            });
        }
        auto& layouts = runLayout_.emplace_back(list.size(), VK_IMAGE_LAYOUT_UNDEFINED);
        auto& root = runRoot_.emplace_back(list.size());
        for (uint32_t i = 0; i < list.size(); ++i) {
            root[i] = runs.find(i);
            const auto& pu = usageOf(list[i]);
            if (writes(pu)) continue;
            auto& l = layouts[root[i]];
            l = l == VK_IMAGE_LAYOUT_UNDEFINED ? pu.layout : commonReadLayout(l, pu.layout);
        }
        for (uint32_t i = 0; i < list.size(); ++i) {
            auto& pu = plan_.passes[list[i].step].usages[list[i].usage];
            if (!writes(pu) && decl(r).isImage()) pu.layout = layouts[root[i]];
        }
    }

    /// For every read access and subresource it touches: the union of the scopes of the reads
    /// of that subresource from this one up to the next write. All of them belong to one run
    /// (rule 4 in docs/barriers.md), so this is what a barrier before this read makes visible.
    /// One backward sweep per resource; `runScopeOffset_` indexes the flattened result.
    void computeRunScopes(uint32_t r) {
        const auto& list = accesses_[r];
        auto& offsets = runScopeOffset_.emplace_back(list.size() + 1, 0);
        for (uint32_t i = 0; i < list.size(); ++i) {
            const auto& range = usageOf(list[i]).range;
            offsets[i + 1] = offsets[i] + size_t(range.mipCount) * range.layerCount;
        }
        auto& scopes = runScope_.emplace_back(offsets.back());
        std::vector<VulkanScope> pending(grids_[r].size());
        for (uint32_t i = static_cast<uint32_t>(list.size()); i-- > 0;) {
            const auto& pu = usageOf(list[i]);
            const bool isWrite = writes(pu);
            size_t k = offsets[i];
            grids_[r].forEach(pu.range, [&](size_t sub) {
                if (isWrite) {
                    pending[sub] = {};
                } else {
                    pending[sub].stages |= pu.stages;
                    pending[sub].access |= pu.access;
                    scopes[k] = pending[sub];
                }
                ++k;
            });
        }
    }

    /// Whether a later access (or the export) reads what access `i` leaves in `range`.
    bool readLater(uint32_t r, uint32_t i, const SubresourceRange& range) const {
        const auto& list = accesses_[r];
        for (uint32_t j = i + 1; j < list.size(); ++j) {
            const auto& pu = usageOf(list[j]);
            if (!pu.range.overlaps(range)) continue;
            if (readsContents(effectiveUsage(pu).access)) return true;
            const auto& o = pu.range;
            if (o.baseMip <= range.baseMip && o.baseMip + o.mipCount >= range.baseMip + range.mipCount &&
                o.baseLayer <= range.baseLayer && o.baseLayer + o.layerCount >= range.baseLayer + range.layerCount)
                return false;
        }
        return decl(r).isExported();  // the same notion of "live at the end" as culling
    }

    /// Where a persistent external resource's contents must be visible at the frame's start.
    /// For `General` (state the graph itself consumes next frame, e.g. accumulation) that is
    /// exactly the first use's scope; otherwise the documented table in vulkan_state.cpp.
    VulkanScope boundaryScope(uint32_t r, ExternalState state) const {
        VulkanScope scope = externalScope(decl(r), state);
        if (state == ExternalState::General && decl(r).external && !accesses_[r].empty()) {
            const uint32_t first = plan_.resources[r].firstPass;
            VulkanScope firstUse{0, 0, scope.layout};
            for (const auto& a : accesses_[r]) {
                if (a.step != first) break;
                firstUse.stages |= usageOf(a).stages;
                firstUse.access |= usageOf(a).access;
            }
            return firstUse;
        }
        return scope;
    }

    void initState() {
        state_.resize(plan_.resources.size());
        for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
            const auto& d = decl(r);
            SubresourceState init;
            if (d.external) {
                const ExternalState s = replaced(d.initial);
                const VulkanScope scope = boundaryScope(r, s);
                init.layout = scope.layout;
                init.writeStages = scope.stages;
                init.visibleStages = scope.stages;
                init.visibleAccess = scope.access;
                init.fromOutside = true;
            }
            state_[r].assign(grids_[r].size(), init);
            plan_.resources[r].initialLayout = init.layout;
            for (const auto& a : accesses_[r])
                if (a.step == plan_.resources[r].firstPass)
                    plan_.resources[r].firstStages |= usageOf(a).stages;
        }
    }

    /// The barrier subresource `st` needs before an access in `scope` that reads
    /// (`reads`) and/or writes (`write`) and must find it in `target` layout.
    std::optional<Barrier> barrierFor(SubresourceState& st, const VulkanScope& need,
                                      VkImageLayout target, bool write, bool discard,
                                      const VulkanScope& visibleAfter) {
        const bool layoutChange = st.layout != target;
        Barrier b;
        b.dstStages = need.stages;
        b.dstAccess = need.access;
        b.oldLayout = discard && layoutChange ? VK_IMAGE_LAYOUT_UNDEFINED : st.layout;
        b.newLayout = target;
        bool needed = layoutChange;
        if (write) {
            // WAR: the reads since the last write chain after it, so waiting for them is an
            // execution dependency that also orders this write after that write.
            if (st.readStages) {
                b.srcStages = st.readStages;
                needed = true;
            } else if (st.writeStages && !(st.fromOutside && covers(st.visibleStages, st.visibleAccess, need))) {
                b.srcStages = st.writeStages;  // WAW: memory dependency
                b.srcAccess = st.writeAccess;
                needed = true;
            } else if (layoutChange && st.fromOutside) {
                b.srcStages = st.writeStages;
            }
        } else {
            const bool visible = covers(st.visibleStages, st.visibleAccess, need);
            if (layoutChange) {
                // The transition writes, so it waits for earlier reads (WAR). Those reads chain
                // after the barrier that made the last write available, so they alone are the
                // source then; without reads, the write is (RAW, a memory dependency).
                b.srcStages = st.readStages ? st.readStages : st.writeStages;
                b.srcAccess = st.readStages ? 0 : st.writeAccess;
            } else if (!visible && (st.writeStages || st.fromOutside)) {
                b.srcStages = st.writeStages;  // RAW: memory dependency
                b.srcAccess = st.writeAccess;
                needed = true;
            }
            if (needed) {
                b.dstStages = visibleAfter.stages;
                b.dstAccess = visibleAfter.access;
            }
        }
        if (needed && b.srcStages == 0 && st.fromOutside) b.srcStages = b.dstStages;
        if (!needed) return std::nullopt;
        // What the barrier achieved.
        st.layout = target;
        st.fromOutside = st.fromOutside && !write;
        if (!write) {
            // A transition rewrites the memory: only this barrier's scope sees the result.
            st.visibleStages = (layoutChange ? 0 : st.visibleStages) | b.dstStages;
            st.visibleAccess = (layoutChange ? 0 : st.visibleAccess) | b.dstAccess;
        }
        return b;
    }

    void applyAccess(uint32_t s, uint32_t u) {
        PlannedUsage& pu = plan_.passes[s].usages[u];
        const uint32_t r = pu.resource;
        const uint32_t i = accessIndex_[s][u];
        const bool isImage = decl(r).isImage();
        const Usage eff = effectiveUsage(pu);
        const bool write = writesContents(eff.access);
        const VulkanScope need{pu.stages, pu.access, pu.layout};

        const VkImageLayout target = isImage ? pu.layout : VK_IMAGE_LAYOUT_UNDEFINED;
        auto update = [&](SubresourceState& st) {
            if (write) {
                st = SubresourceState{};
                st.layout = target;
                st.writeStages = pu.stages;
                st.writeAccess = writeBits(pu.access);
            } else {
                st.readStages |= pu.stages;
            }
        };
        const VulkanScope* runScopes = runScope_[r].data() + runScopeOffset_[r][i];
        if (grids_[r].size() == 1) {  // the common case: no per-subresource bookkeeping
            auto b = barrierFor(state_[r][0], need, target, write, eff.access == Access::Write,
                                write ? need : runScopes[0]);
            update(state_[r][0]);
            if (b) {
                b->resource = r;
                b->kind = isImage ? BarrierKind::Image : BarrierKind::Buffer;
                b->range = grids_[r].whole();
                plan_.passes[s].barriers.push_back(*b);
            }
        } else {
            scratch_.assign(grids_[r].size(), std::nullopt);
            size_t k = 0;
            grids_[r].forEach(pu.range, [&](size_t sub) {
                SubresourceState& st = state_[r][sub];
                scratch_[sub] = barrierFor(st, need, target, write, eff.access == Access::Write,
                                           write ? need : runScopes[k++]);
                update(st);
            });
            emitMerged(r, pu.range, scratch_, plan_.passes[s].barriers);
        }

        if (isAttachmentStage(pu.usage.stage)) {
            if (pu.load != LoadOp::Clear)
                pu.load = pu.usage.access == Access::Write ? LoadOp::DontCare : LoadOp::Load;
            pu.store = !write ? StoreOp::None : readLater(r, i, pu.range) ? StoreOp::Store : StoreOp::DontCare;
        }
    }

    /// Coalesces per-subresource barriers into as few rectangles of mips x layers as agree.
    void emitMerged(uint32_t r, const SubresourceRange& range,
                    const std::vector<std::optional<Barrier>>& perSub, std::vector<Barrier>& out) {
        const auto& grid = grids_[r];
        const BarrierKind kind = decl(r).isImage() ? BarrierKind::Image : BarrierKind::Buffer;
        std::vector<Barrier> open;  // rectangles that may still grow by one more mip
        auto sameParams = [](const Barrier& a, const Barrier& b) {
            Barrier x = a, y = b;
            x.range = y.range = {};
            return x == y;
        };
        for (uint32_t m = range.baseMip; m < range.baseMip + range.mipCount; ++m) {
            std::vector<Barrier> row;
            for (uint32_t l = range.baseLayer; l < range.baseLayer + range.layerCount; ++l) {
                const auto& b = perSub[grid.index(m, l)];
                if (!b) continue;
                Barrier nb = *b;
                nb.resource = r;
                nb.kind = kind;
                nb.range = {m, 1, l, 1};
                if (!row.empty() && sameParams(row.back(), nb) &&
                    row.back().range.baseLayer + row.back().range.layerCount == l) {
                    row.back().range.layerCount++;
                    continue;
                }
                row.push_back(nb);
            }
            std::vector<Barrier> next;
            for (auto& seg : row) {
                auto it = std::find_if(open.begin(), open.end(), [&](const Barrier& o) {
                    return sameParams(o, seg) && o.range.baseLayer == seg.range.baseLayer &&
                           o.range.layerCount == seg.range.layerCount &&
                           o.range.baseMip + o.range.mipCount == m;
                });
                if (it != open.end()) {
                    it->range.mipCount++;
                    next.push_back(*it);
                    open.erase(it);
                } else {
                    next.push_back(seg);
                }
            }
            for (auto& closed : open) out.push_back(closed);
            open = std::move(next);
        }
        for (auto& closed : open) out.push_back(closed);
    }

    /// Joins barriers of one batch that differ only in adjoining ranges, e.g. the per-mip
    /// usages of a pass that writes every level.
    static void mergeAdjacent(std::vector<Barrier>& batch) {
        for (bool merged = true; merged;) {
            merged = false;
            for (size_t i = 0; i < batch.size() && !merged; ++i)
                for (size_t j = i + 1; j < batch.size() && !merged; ++j) {
                    Barrier& a = batch[i];
                    const Barrier& b = batch[j];
                    Barrier x = a, y = b;
                    x.range = y.range = {};
                    if (!(x == y)) continue;
                    const bool sameLayers = a.range.baseLayer == b.range.baseLayer &&
                                            a.range.layerCount == b.range.layerCount;
                    const bool sameMips = a.range.baseMip == b.range.baseMip &&
                                          a.range.mipCount == b.range.mipCount;
                    if (sameLayers && a.range.baseMip + a.range.mipCount == b.range.baseMip) {
                        a.range.mipCount += b.range.mipCount;
                    } else if (sameMips && a.range.baseLayer + a.range.layerCount == b.range.baseLayer) {
                        a.range.layerCount += b.range.layerCount;
                    } else {
                        continue;
                    }
                    batch.erase(batch.begin() + static_cast<std::ptrdiff_t>(j));
                    merged = true;
                }
        }
    }

    void finalBarriers() {
        for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
            const auto& d = decl(r);
            auto& res = plan_.resources[r];
            res.finalLayout = state_[r].empty() ? VK_IMAGE_LAYOUT_UNDEFINED : state_[r][0].layout;
            if (!d.isExported()) continue;
            const VulkanScope scope = boundaryScope(r, replaced(d.final));
            // A persistent resource's next frame repeats this one. If it writes anywhere, the
            // final barrier must order every access of this frame, readers included, before
            // the next frame's first use, exactly as a write would: later passes of the next
            // frame chain through that first use and never name this frame's stages.
            const bool persistent = d.external && replaced(d.final) == replaced(d.initial);
            bool framesWrite = false;
            for (const auto& a : accesses_[r]) framesWrite |= writes(usageOf(a));
            const bool nextUseWrites = writeBits(scope.access) != 0 || (persistent && framesWrite);
            std::vector<std::optional<Barrier>> perSub(grids_[r].size());
            grids_[r].forEach(grids_[r].whole(), [&](size_t sub) {
                perSub[sub] = barrierFor(state_[r][sub], scope,
                                         d.isImage() ? scope.layout : VK_IMAGE_LAYOUT_UNDEFINED,
                                         nextUseWrites, false, scope);
            });
            emitMerged(r, grids_[r].whole(), perSub, plan_.finalBarriers);
            res.finalLayout = d.isImage() ? scope.layout : VK_IMAGE_LAYOUT_UNDEFINED;
        }
    }

    const GraphDesc& graph_;
    const CompileOptions& options_;
    Plan plan_;
    std::vector<SubresourceGrid> grids_;                    // per plan resource
    std::vector<std::vector<AccessRef>> accesses_;          // per plan resource, in order
    std::vector<std::vector<uint32_t>> accessIndex_;        // [step][usage] -> index in accesses_
    std::vector<std::vector<VkImageLayout>> runLayout_;     // per resource, by run root
    std::vector<std::vector<uint32_t>> runRoot_;            // per resource, per access
    std::vector<std::vector<SubresourceState>> state_;      // per resource, per subresource
    std::vector<std::vector<size_t>> runScopeOffset_;       // per resource, per access (+1)
    std::vector<std::vector<VulkanScope>> runScope_;        // per resource, flattened
    std::vector<std::optional<Barrier>> scratch_;           // per-subresource barriers
};

}  // namespace

Plan synchronize(const GraphDesc& graph, const Schedule& schedule, const CompileOptions& options) {
    return Synchronizer(graph, options).run(schedule);
}

}  // namespace skygraph
