// Memory dependencies between accesses (Vulkan 1.3 §7.1, §7.1.1 "Availability and
// visibility"; the Memory Aliasing section for accesses through different resources).
#include "checks.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace skygraph::verifier {
namespace {

enum class Outcome : uint8_t { Ok, NotAvailable, NotVisible };

const char* hazardName(const ModelAccess& earlier, const ModelAccess& later) {
    if (earlier.writes) return later.writes ? "write-after-write" : "read-after-write";
    return "write-after-read";
}

class PairChecker {
public:
    PairChecker(const FrameModel& model, const Plan& plan, Reporter& reporter)
        : model_(model), plan_(plan), reporter_(reporter), reach_(model.accesses.size()),
          transitionsOf_(model.memory.size()) {
        // Indexed once: asked per pair, a scan of every access between the two (and, across
        // aliases, of every resource) made the check quartic in the passes of a long chain.
        for (uint32_t t = 0; t < model.accesses.size(); ++t) {
            const ModelAccess& a = model.accesses[t];
            if (a.kind != ModelAccess::Kind::Transition) continue;
            transitionsOf_[a.object].push_back(t);
            const MemoryObject& o = model.memory.object(a.object);
            if (o.kind != MemoryObject::Kind::Image || !o.placement) continue;
            if (o.placement->heapInstance >= placedTransitions_.size())
                placedTransitions_.resize(o.placement->heapInstance + 1);
            placedTransitions_[o.placement->heapInstance].push_back(t);
        }
    }

    size_t run() {
        const auto& accesses = model_.accesses;
        size_t pairs = 0;
        for (size_t x = 0; x < accesses.size(); ++x) {
            for (size_t e = 0; e < x; ++e) {
                const ModelAccess& earlier = accesses[e];
                const ModelAccess& later = accesses[x];
                // The second frame adds only what crosses from the first: the rest repeats it.
                if (earlier.frame > 1) continue;
                if (!earlier.writes && !later.writes) continue;
                const Overlap o = model_.memory.overlap(earlier.object, earlier.cells, later.object, later.cells);
                if (o.kind == Overlap::Kind::None) continue;
                ++pairs;
                check(e, x, o);
                if (reporter_.full()) return pairs;
            }
        }
        return pairs;
    }

private:
    const PointSet& reach(size_t access) {
        if (!reach_[access]) reach_[access] = model_.graph.withSuccessors(model_.accesses[access].place.enters);
        return *reach_[access];
    }

    void check(size_t e, size_t x, const Overlap& o) {
        const ModelAccess& earlier = model_.accesses[e];
        const ModelAccess& later = model_.accesses[x];
        if (!reach(e).intersects(later.place.after)) {
            const bool samePlace = earlier.site.step == later.site.step && earlier.frame == later.frame;
            add(FindingKind::Unordered, earlier, later,
                std::string(hazardName(earlier, later)) +
                    (samePlace ? " within one step, with nothing between them that orders them"
                               : ": no chain of barriers orders the first before the second"));
            return;
        }
        if (!earlier.writes) return;  // write-after-read needs the execution dependency only
        if (o.kind == Overlap::Kind::SameObject) {
            const MemoryObject& obj = model_.memory.object(earlier.object);
            for (uint32_t mip = o.cells.baseMip; mip < o.cells.baseMip + o.cells.mipCount; ++mip)
                for (uint32_t layer = o.cells.baseLayer; layer < o.cells.baseLayer + o.cells.layerCount; ++layer) {
                    const bool image = obj.kind == MemoryObject::Kind::Image;
                    const SubresourceRange cell = image ? SubresourceRange{mip, 1, layer, 1} : obj.whole();
                    if (image && transitionedBetween(earlier.object, cell, e, x)) continue;
                    const MemoryProbe probe{earlier.object, cell, false, 0, {}};
                    const Outcome outcome = dependency(earlier, later, probe, probe, AliasCoverage::WholeResource);
                    if (outcome != Outcome::Ok) {
                        reportMemory(earlier, later, outcome, false,
                                     image ? " (mip " + std::to_string(mip) + ", layer " + std::to_string(layer) + ")"
                                           : std::string());
                        return;
                    }
                }
            return;
        }
        if (supersededAcrossAliases(earlier, e, x, o.bytes)) return;
        const MemoryProbe pe{earlier.object, earlier.cells, true, later.object, o.bytes};
        const MemoryProbe px{later.object, later.cells, true, earlier.object, o.bytes};
        const Outcome outcome = dependency(earlier, later, pe, px, AliasCoverage::WholeResource);
        if (outcome != Outcome::Ok)
            reportMemory(
                earlier, later, outcome, holdsSubresourceBySubresource(earlier, later, o.bytes),
                " (bytes [" + std::to_string(o.bytes.begin) + ", " + std::to_string(o.bytes.end) + ") they share)");
    }

    /// Whether a layout transition of `cell` of `object` lies between accesses e and x: it
    /// rewrote the subresource, so (e, it) and (it, x) are the pairs that matter.
    bool transitionedBetween(uint32_t object, const SubresourceRange& cell, size_t e, size_t x) const {
        const std::vector<uint32_t>& transitions = transitionsOf_[object];
        for (auto t = std::upper_bound(transitions.begin(), transitions.end(), e); t != transitions.end() && *t < x; ++t)
            if (rangeContains(model_.accesses[*t].cells, cell)) return true;
        return false;
    }

    /// Whether, between accesses e and x through two resources sharing `shared`, resources
    /// holding all of those bytes had every subresource rewritten by layout transitions (the
    /// hand-over from one alias to the next): then the pairs with those transitions are the
    /// ones that matter, not (e, x).
    bool supersededAcrossAliases(const ModelAccess& earlier, size_t e, size_t x, const ByteRange& shared) const {
        const MemoryObject& a = model_.memory.object(earlier.object);
        if (!a.placement || a.placement->heapInstance >= placedTransitions_.size()) return false;
        // The transitions between the two in the heap, in order: the first resource rewritten
        // whole usually holds all the shared bytes, and the walk stops there.
        std::vector<std::pair<uint32_t, std::vector<uint8_t>>> marked;  // per object met: cells transitioned
        std::vector<ByteRange> rewritten;  // placements whose every subresource was transitioned
        const std::vector<uint32_t>& transitions = placedTransitions_[a.placement->heapInstance];
        for (auto t = std::upper_bound(transitions.begin(), transitions.end(), e); t != transitions.end() && *t < x;
             ++t) {
            const ModelAccess& tr = model_.accesses[*t];
            const MemoryObject& candidate = model_.memory.object(tr.object);
            const ByteRange& bytes = candidate.placement->bytes;
            if (bytes.end <= shared.begin || shared.end <= bytes.begin) continue;
            auto m = std::find_if(marked.begin(), marked.end(), [&](const auto& p) { return p.first == tr.object; });
            if (m == marked.end()) m = marked.insert(marked.end(), {tr.object, std::vector<uint8_t>(candidate.cellCount())});
            std::vector<uint8_t>& cells = m->second;
            if (cells.empty()) continue;  // already rewritten whole
            for (uint32_t mip = tr.cells.baseMip; mip < tr.cells.baseMip + tr.cells.mipCount; ++mip)
                for (uint32_t layer = tr.cells.baseLayer; layer < tr.cells.baseLayer + tr.cells.layerCount; ++layer)
                    cells[candidate.cell(mip, layer)] = 1;
            if (!std::all_of(cells.begin(), cells.end(), [](uint8_t c) { return c != 0; })) continue;
            cells.clear();
            rewritten.push_back(bytes);
            std::sort(rewritten.begin(), rewritten.end(),
                      [](const ByteRange& l, const ByteRange& r) { return l.begin < r.begin; });
            uint64_t covered = shared.begin;
            for (const ByteRange& r : rewritten)
                if (r.begin <= covered) covered = std::max(covered, r.end);
            if (covered >= shared.end) return true;
        }
        return false;
    }

    /// The relaxed reading, to tell a partial barrier from a missing one: every subresource of
    /// the write made available by a barrier naming it, and every subresource of the second
    /// access made visible by a barrier naming it.
    bool holdsSubresourceBySubresource(const ModelAccess& earlier, const ModelAccess& later,
                                       const ByteRange& shared) const {
        const auto cellsOf = [&](const ModelAccess& a) {
            std::vector<SubresourceRange> cells;
            const MemoryObject& o = model_.memory.object(a.object);
            if (o.kind != MemoryObject::Kind::Image) return std::vector<SubresourceRange>{o.whole()};
            for (uint32_t mip = a.cells.baseMip; mip < a.cells.baseMip + a.cells.mipCount; ++mip)
                for (uint32_t layer = a.cells.baseLayer; layer < a.cells.baseLayer + a.cells.layerCount; ++layer)
                    cells.push_back({mip, 1, layer, 1});
            return cells;
        };
        const auto laterCells = cellsOf(later);
        for (const SubresourceRange& ce : cellsOf(earlier)) {
            const MemoryProbe pe{earlier.object, ce, true, later.object, shared};
            const PointSet afterAvailability = available(earlier, later, pe, AliasCoverage::OwnSubresources);
            if (!afterAvailability.any()) return false;
            for (const SubresourceRange& cx : laterCells) {
                const MemoryProbe px{later.object, cx, true, earlier.object, shared};
                if (visibility(later, afterAvailability, px, AliasCoverage::OwnSubresources) != Outcome::Ok)
                    return false;
            }
        }
        return true;
    }

    /// The points at or after an availability operation for `earlier`'s write that happens
    /// before `later` (empty: none does).
    PointSet available(const ModelAccess& earlier, const ModelAccess& later, const MemoryProbe& pe,
                       AliasCoverage rule) const {
        const HappensBefore& g = model_.graph;
        PointSet points(g.size());
        const auto beforeLater = [&](uint32_t p) {
            if (later.anchor) return p == *later.anchor || g.successors(p).test(*later.anchor);
            return later.place.after.test(p) || g.successors(p).intersects(later.place.after);
        };
        if (earlier.kind == ModelAccess::Kind::Transition) {
            // A layout transition's writes are available as soon as it is done.
            const PointId done = earlier.doneAt.value_or(*earlier.anchor);
            if (beforeLater(done)) points.set(done);
        } else {
            const AccessScope writes = earlier.performs.writesOnly();
            earlier.place.enters.forEach([&](uint32_t p) {
                if (beforeLater(p) && g.point(p).firstAccess.contains(writes) &&
                    model_.memory.covers(model_.pointMemory[p], pe, rule))
                    points.set(p);
            });
        }
        return g.withSuccessors(points);
    }

    /// Whether writes available at `afterAvailability` become visible to `later`.
    Outcome visibility(const ModelAccess& later, const PointSet& afterAvailability, const MemoryProbe& px,
                       AliasCoverage rule) const {
        const HappensBefore& g = model_.graph;
        // Visibility to a layout transition or the present is automatic: availability before
        // it is what they need.
        if (later.anchor) return afterAvailability.test(*later.anchor) ? Outcome::Ok : Outcome::NotAvailable;
        bool visible = false;
        afterAvailability.forEach([&](uint32_t p) {
            if (visible || !later.place.after.test(p)) return;
            visible = g.point(p).secondAccess.contains(later.performs) &&
                      model_.memory.covers(model_.pointMemory[p], px, rule);
        });
        return visible ? Outcome::Ok : Outcome::NotVisible;
    }

    /// Whether `earlier`'s write is made available and then visible to `later`.
    Outcome dependency(const ModelAccess& earlier, const ModelAccess& later, const MemoryProbe& pe,
                       const MemoryProbe& px, AliasCoverage rule) const {
        const PointSet afterAvailability = available(earlier, later, pe, rule);
        if (!afterAvailability.any()) return Outcome::NotAvailable;
        return visibility(later, afterAvailability, px, rule);
    }

    void reportMemory(const ModelAccess& earlier, const ModelAccess& later, Outcome outcome, bool partial,
                      const std::string& where) {
        const std::string hazard = hazardName(earlier, later);
        if (partial) {
            add(FindingKind::PartialAliasBarrier, earlier, later,
                hazard + where +
                    " between resources sharing memory relies on a barrier that names only part of "
                    "its resource; the spec's Memory Aliasing rule needs every subresource that overlaps");
        } else if (outcome == Outcome::NotAvailable) {
            add(FindingKind::NotAvailable, earlier, later,
                hazard + where + ": no barrier after the write has it in its source access scope and memory" +
                    (later.anchor ? " before the second access (a transition or present needs it available)" : ""));
        } else {
            add(FindingKind::NotVisible, earlier, later,
                hazard + where +
                    ": the write is made available but no barrier chained after that makes it "
                    "visible to the second access's stage and access type");
        }
    }

    void add(FindingKind kind, const ModelAccess& earlier, const ModelAccess& later, std::string reason) {
        Finding f;
        f.kind = kind;
        if (earlier.object == later.object && model_.memory.object(earlier.object).kind == MemoryObject::Kind::Image)
            f.subresources = intersection(earlier.cells, later.cells);
        for (const uint32_t object : {earlier.object, later.object}) {
            const MemoryObject& o = model_.memory.object(object);
            if (o.resource >= 0 &&
                std::find(f.resources.begin(), f.resources.end(), uint32_t(o.resource)) == f.resources.end()) {
                f.resources.push_back(static_cast<uint32_t>(o.resource));
                f.resourceNames.emplace_back(plan_.resources()[static_cast<size_t>(o.resource)].name);
            } else if (o.resource < 0 && f.resourceNames.empty()) {
                f.resourceNames.push_back(o.name);
            }
        }
        f.earlier = earlier.site;
        f.later = later.site;
        f.reason = std::move(reason);
        reporter_.add(std::move(f));
    }

    const FrameModel& model_;
    const Plan& plan_;
    Reporter& reporter_;
    std::vector<std::optional<PointSet>> reach_;
    std::vector<std::vector<uint32_t>> transitionsOf_;      // per object: its transitions' access indices
    std::vector<std::vector<uint32_t>> placedTransitions_;  // per heap instance: transitions of images in it
};

}  // namespace

size_t checkMemoryDependencies(const FrameModel& model, const Plan& plan, Reporter& reporter) {
    return PairChecker(model, plan, reporter).run();
}

void checkLiveOverlaps(const FrameModel& model, Reporter& reporter) {
    // Each placed object's first and last item of the recording (usages and barriers).
    struct Span {
        size_t first = 0, last = 0;
        FindingSite firstSite, lastSite;
    };
    std::map<uint32_t, Span> spans;
    for (size_t i = 0; i < model.timeline.size(); ++i) {
        const TimelineItem& t = model.timeline[i];
        if (t.kind != TimelineItem::Kind::Barrier && t.kind != TimelineItem::Kind::Usage) continue;
        if (!model.memory.object(t.object).placement) continue;
        auto [it, fresh] = spans.try_emplace(t.object, Span{i, i, t.site, t.site});
        if (!fresh) {
            it->second.last = i;
            it->second.lastSite = t.site;
        }
    }
    for (auto a = spans.begin(); a != spans.end(); ++a) {
        for (auto b = std::next(a); b != spans.end(); ++b) {
            ByteRange shared;
            if (!model.memory.placementsOverlap(a->first, b->first, &shared)) continue;
            const Span& x = a->second.first <= b->second.first ? a->second : b->second;  // starts first
            const Span& y = &x == &a->second ? b->second : a->second;
            if (y.first > x.last) continue;
            const MemoryObject& ox = model.memory.object(&x == &a->second ? a->first : b->first);
            const MemoryObject& oy = model.memory.object(&x == &a->second ? b->first : a->first);
            Finding f;
            f.kind = FindingKind::LiveOverlap;
            f.resources = {static_cast<uint32_t>(oy.resource), static_cast<uint32_t>(ox.resource)};
            f.resourceNames = {oy.name, ox.name};
            f.earlier = y.firstSite;
            f.later = x.lastSite;
            f.reason = oy.name + " is in use while " + ox.name + ", which shares bytes [" +
                       std::to_string(shared.begin) + ", " + std::to_string(shared.end) +
                       ") of its heap with it, is still used afterwards";
            reporter.add(std::move(f));
        }
    }
}

}  // namespace skygraph::verifier
