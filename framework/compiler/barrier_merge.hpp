// Rule 11 of docs/barriers.md: barriers that agree in everything but their subresource
// ranges become one barrier over the union of those ranges, when it is a rectangle of mips x
// layers. Internal to the synchronizer's barrier sweep (synchronizer_barriers.cpp) and final barriers
// (synchronizer_boundaries.cpp).
#pragma once

#include "subresources.hpp"

#include <skygraph/plan.hpp>

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <optional>
#include <vector>

namespace skygraph::sync {

/// Whether two barriers could be one, apart from their ranges (rule 11). Field by field, not
/// `==` on copies with the ranges blanked: batches are compared pair by pair, and the copies
/// cost more than the comparison.
inline bool sameParams(const Barrier& a, const Barrier& b) {
    static_assert(sizeof(Barrier) == 64, "a new Barrier member must join this comparison");
    return a.resource == b.resource && a.kind == b.kind && a.aliasing == b.aliasing && a.srcStages == b.srcStages &&
           a.srcAccess == b.srcAccess && a.dstStages == b.dstStages && a.dstAccess == b.dstAccess &&
           a.oldLayout == b.oldLayout && a.newLayout == b.newLayout && a.srcQueue == b.srcQueue &&
           a.dstQueue == b.dstQueue;
}

/// Merges the barriers of one resource's range as they are emitted. Keeps its scratch
/// between calls (one per synchronizer).
class BarrierMerger {
public:
    /// Appends to `out` the per-subresource barriers of resource `r` (`perSub`: one per
    /// subresource of `range`, in SubresourceGrid::forEach order; empty where none is
    /// needed), coalesced into as few rectangles of mips x layers as agree.
    void emitMerged(uint32_t r, BarrierKind kind, const SubresourceRange& range,
                    const std::vector<std::optional<Barrier>>& perSub, std::vector<Barrier>& out) {
        assert(perSub.size() == cells(range));
        // One barrier (a usage of a range whose other subresources need none, most often) is
        // its own rectangle: no scratch to fill.
        const auto set = [](const std::optional<Barrier>& b) { return b.has_value(); };
        if (const auto only = std::find_if(perSub.begin(), perSub.end(), set);
            only != perSub.end() && std::find_if(only + 1, perSub.end(), set) == perSub.end()) {
            const auto c = static_cast<uint32_t>(only - perSub.begin());
            Barrier& b = out.emplace_back(**only);
            b.resource = r;
            b.kind = kind;
            b.range = {range.baseMip + c / range.layerCount, 1, range.baseLayer + c % range.layerCount, 1};
            return;
        }
        auto& open = open_;  // rectangles that may still grow by one more mip
        auto& row = row_;
        auto& next = next_;
        open.clear();
        size_t c = 0;
        for (uint32_t m = range.baseMip; m < range.baseMip + range.mipCount; ++m) {
            row.clear();
            for (uint32_t l = range.baseLayer; l < range.baseLayer + range.layerCount; ++l) {
                const auto& b = perSub[c++];
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
            next.clear();
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
            out.insert(out.end(), open.begin(), open.end());  // closed: they did not grow
            std::swap(open, next);
        }
        out.insert(out.end(), open.begin(), open.end());
    }

private:
    std::vector<Barrier> open_, row_, next_;  // emitMerged's scratch
};

/// Joins barriers of one batch (`batch` from `first` on) that differ only in adjoining
/// ranges, e.g. the per-mip usages of a pass that writes every level.
inline void mergeAdjacent(std::vector<Barrier>& batch, size_t first) {
    for (bool merged = true; merged;) {  // after each merge, look again from the start
        merged = false;
        const size_t n = batch.size();
        for (size_t i = first; i + 1 < n && !merged; ++i) {
            Barrier& a = batch[i];
            for (size_t j = i + 1; j < n; ++j) {
                const Barrier& b = batch[j];
                // Most batches hold one barrier per resource: the resource alone rules them out.
                if (a.resource != b.resource || !sameParams(a, b)) continue;
                const bool sameLayers = a.range.baseLayer == b.range.baseLayer &&
                                        a.range.layerCount == b.range.layerCount;
                const bool sameMips = a.range.baseMip == b.range.baseMip &&
                                      a.range.mipCount == b.range.mipCount;
                // Either may come first: a pass's usages of one resource may name its ranges
                // in any order.
                if (sameLayers && a.range.baseMip + a.range.mipCount == b.range.baseMip) {
                    a.range.mipCount += b.range.mipCount;
                } else if (sameLayers && b.range.baseMip + b.range.mipCount == a.range.baseMip) {
                    a.range.baseMip = b.range.baseMip;
                    a.range.mipCount += b.range.mipCount;
                } else if (sameMips && a.range.baseLayer + a.range.layerCount == b.range.baseLayer) {
                    a.range.layerCount += b.range.layerCount;
                } else if (sameMips && b.range.baseLayer + b.range.layerCount == a.range.baseLayer) {
                    a.range.baseLayer = b.range.baseLayer;
                    a.range.layerCount += b.range.layerCount;
                } else {
                    continue;
                }
                batch.erase(batch.begin() + static_cast<std::ptrdiff_t>(j));
                merged = true;
                break;
            }
        }
    }
}

}  // namespace skygraph::sync
