// Resources, exports and placements, checked before anything is built on them.
#include "frame_resources.hpp"

#include <algorithm>
#include <cstdio>

namespace skygraph::verifier {
namespace {

void report(Reporter& reporter, const Plan& plan, FindingKind kind, FindingSite site, std::string reason,
            int64_t resource = -1) {
    reporter.addAt(kind, std::move(site), std::move(reason), plan, resource);
}

void describe(const Plan& plan, const GraphDesc& graph, std::vector<ResourceShape>& shapes, Reporter& reporter) {
    const auto resources = plan.resources();
    shapes.resize(resources.size());
    for (size_t r = 0; r < resources.size(); ++r) {
        const PlannedResource& pr = resources[r];
        const FindingSite site{1, -1, "resources", "resource " + std::to_string(r)};
        if (pr.decl >= graph.resources.size()) {
            report(reporter, plan, FindingKind::MalformedPlan, site,
                   "decl " + std::to_string(pr.decl) + " is not a graph resource", int64_t(r));
            continue;
        }
        const ResourceDesc& d = graph.resources[pr.decl];
        // What the checks below read of the graph must be this resource's: a plan verified
        // against another graph (or one whose resources moved) would be judged by others'.
        if (pr.name != d.name) {
            report(reporter, plan, FindingKind::MalformedPlan, site,
                   "decl " + std::to_string(pr.decl) + " is the graph's '" + d.name + "', not '" + std::string(pr.name) + "'",
                   int64_t(r));
            continue;
        }
        if (pr.firstPass > pr.lastPass || pr.lastPass >= plan.passes().size())
            report(reporter, plan, FindingKind::MalformedPlan, site,
                   "its lifetime, passes " + std::to_string(pr.firstPass) + " to " + std::to_string(pr.lastPass) +
                       ", is not within the plan's " + std::to_string(plan.passes().size()) + " passes",
                   int64_t(r));
        ResourceShape& s = shapes[r];
        s.valid = true;
        s.image = d.isImage();
        // A transient in heaps the frames share is still a resource of each frame (its
        // contents do not carry over); what the frames share is its memory (makeObjects).
        s.shared = !perFrameInFlight(pr.copies) && pr.copies != ResourceCopies::SharedTransient;
        s.external = d.external;
        s.finalState = d.final;
        s.initialState = d.initial != ExternalState::None ? d.initial
                         : d.final != ExternalState::None ? d.final
                                                          : ExternalState::ShaderRead;
        s.exported = d.isExported();
        if (s.image) {
            s.mips = std::max(1u, d.mipCount(plan.outputWidth(), plan.outputHeight()));
            s.layers = std::max(1u, d.layers);
        }
    }
}

/// Exports the file does not declare (read-backs, CompileOptions::exports) show in the
/// plan as final barriers and read-back steps.
void markExportsAndPresents(const Plan& plan, std::vector<ResourceShape>& shapes) {
    const auto mark = [&](uint32_t r, bool ResourceShape::*flag) {
        if (r < shapes.size()) shapes[r].*flag = true;
    };
    for (const Barrier& b : plan.finalBarriers())
        if (b.kind != BarrierKind::Memory) mark(b.resource, &ResourceShape::exported);
    for (const PlannedPass& p : plan.passes())
        if (p.declIndex < 0 && p.type == "Readback")
            for (const PlannedUsage& u : p.usages) mark(u.resource, &ResourceShape::exported);
    for (const Presentation& pr : plan.presentations()) mark(pr.resource, &ResourceShape::presented);
}

void place(const Plan& plan, std::vector<ResourceShape>& shapes, Reporter& reporter) {
    const MemoryLayout& m = plan.memory();
    const auto resources = plan.resources();
    for (size_t p = 0; p < m.placements.size(); ++p) {
        const MemoryPlacement& pl = m.placements[p];
        const FindingSite site{1, -1, "memory", "placement " + std::to_string(p)};
        if (pl.resource >= resources.size() || !shapes[pl.resource].valid) {
            report(reporter, plan, FindingKind::MalformedPlan, site,
                   "names no valid plan resource (" + std::to_string(pl.resource) + ")");
            continue;
        }
        const auto r = static_cast<int64_t>(pl.resource);
        if (pl.heap >= m.heaps.size()) {
            report(reporter, plan, FindingKind::MalformedPlan, site,
                   "heap " + std::to_string(pl.heap) + " does not exist", r);
            continue;
        }
        if (resources[pl.resource].placement != p)
            report(reporter, plan, FindingKind::MalformedPlan, site,
                   "the resource's placement index is not this placement", r);
        const MemoryHeap& heap = m.heaps[pl.heap];
        const uint64_t end = pl.offset + pl.bytes;
        if (end < pl.offset || end > heap.bytes)
            report(reporter, plan, FindingKind::PlacementInvalid, site,
                   "[" + std::to_string(pl.offset) + ", " + std::to_string(end) + ") is outside heap " +
                       std::to_string(pl.heap) + " of " + std::to_string(heap.bytes) + " bytes",
                   r);
        if (pl.bytes < pl.requirements.size)
            report(reporter, plan, FindingKind::PlacementInvalid, site,
                   "holds " + std::to_string(pl.bytes) + " bytes of the " + std::to_string(pl.requirements.size) +
                       " required",
                   r);
        if (pl.requirements.alignment && pl.offset % pl.requirements.alignment)
            report(reporter, plan, FindingKind::PlacementInvalid, site,
                   "offset " + std::to_string(pl.offset) + " is not aligned to " +
                       std::to_string(pl.requirements.alignment),
                   r);
        // The executor allocates a heap in any one of its types: each must be one the resource
        // can live in.
        if ((heap.memoryTypeBits & ~pl.requirements.memoryTypeBits) != 0) {
            char types[48];
            std::snprintf(types, sizeof types, "0x%x, the heap's 0x%x", pl.requirements.memoryTypeBits,
                          heap.memoryTypeBits);
            report(reporter, plan, FindingKind::PlacementInvalid, site,
                   std::string("its heap may be allocated in a memory type it cannot live in (its types ") + types +
                       ")",
                   r);
        }
        if (heap.granular && m.granularity > 1 && (pl.offset % m.granularity || pl.bytes % m.granularity))
            report(reporter, plan, FindingKind::PlacementInvalid, site,
                   "a granular heap's placement must start and end on a multiple of " + std::to_string(m.granularity),
                   r);
        // The heaps hold transients only: a copy per frame in flight, or one the frames share.
        const ResourceCopies transient =
            m.sharedAcrossFrames ? ResourceCopies::SharedTransient : ResourceCopies::PerFrameTransient;
        if (resources[pl.resource].copies != transient) {
            report(reporter, plan, FindingKind::PlacementInvalid, site,
                   m.sharedAcrossFrames ? "only transient resources live in the heaps the frames share"
                                        : "only transient resources live in the per-frame heaps",
                   r);
            continue;
        }
        ResourceShape& s = shapes[pl.resource];
        if (s.heap) {
            report(reporter, plan, FindingKind::MalformedPlan, site, "a second placement of the same resource", r);
            continue;
        }
        s.heap = pl.heap;
        s.bytes = {pl.offset, std::max(pl.offset, end)};
    }
    for (size_t r = 0; r < resources.size(); ++r) {
        const uint32_t p = resources[r].placement;
        if (p != PlannedResource::kNoPlacement && (p >= m.placements.size() || m.placements[p].resource != r))
            report(reporter, plan, FindingKind::MalformedPlan, {1, -1, "resources", "resource " + std::to_string(r)},
                   "placement " + std::to_string(p) + " is not this resource's", int64_t(r));
    }
}

}  // namespace

std::vector<ResourceShape> describeResources(const Plan& plan, const GraphDesc& graph, Reporter& reporter) {
    std::vector<ResourceShape> shapes;
    describe(plan, graph, shapes, reporter);
    markExportsAndPresents(plan, shapes);
    place(plan, shapes, reporter);
    return shapes;
}

std::string rangeText(const SubresourceRange& r) {
    return "mips[" + std::to_string(r.baseMip) + "+" + std::to_string(r.mipCount) + "] layers[" +
           std::to_string(r.baseLayer) + "+" + std::to_string(r.layerCount) + "]";
}

bool rangeInside(const SubresourceRange& r, uint32_t mips, uint32_t layers) {
    return r.mipCount > 0 && r.layerCount > 0 && r.baseMip < mips && r.mipCount <= mips - r.baseMip &&
           r.baseLayer < layers && r.layerCount <= layers - r.baseLayer;
}

}  // namespace skygraph::verifier
