// Overlap and coverage. A non-linear image's every subresource overlaps all the memory it is
// bound to, so between two resources sharing memory the question is always "which bytes",
// never "which subresource".
#include "memory_map.hpp"

#include <algorithm>

namespace skygraph::verifier {

bool rangeContains(const SubresourceRange& outer, const SubresourceRange& inner) noexcept {
    return outer.baseMip <= inner.baseMip && inner.baseMip + inner.mipCount <= outer.baseMip + outer.mipCount &&
           outer.baseLayer <= inner.baseLayer &&
           inner.baseLayer + inner.layerCount <= outer.baseLayer + outer.layerCount;
}

SubresourceRange intersection(const SubresourceRange& a, const SubresourceRange& b) noexcept {
    const uint32_t mip0 = std::max(a.baseMip, b.baseMip), layer0 = std::max(a.baseLayer, b.baseLayer);
    const uint32_t mip1 = std::min(a.baseMip + a.mipCount, b.baseMip + b.mipCount);
    const uint32_t layer1 = std::min(a.baseLayer + a.layerCount, b.baseLayer + b.layerCount);
    if (mip1 <= mip0 || layer1 <= layer0) return {0, 0, 0, 0};
    return {mip0, mip1 - mip0, layer0, layer1 - layer0};
}

uint32_t MemoryMap::add(MemoryObject object) {
    objects_.push_back(std::move(object));
    return static_cast<uint32_t>(objects_.size() - 1);
}

bool MemoryMap::placementsOverlap(uint32_t a, uint32_t b, ByteRange* shared) const {
    const MemoryObject& x = objects_.at(a);
    const MemoryObject& y = objects_.at(b);
    if (!x.placement || !y.placement || x.placement->heapInstance != y.placement->heapInstance) return false;
    ByteRange rx = x.placement->bytes, ry = y.placement->bytes;
    if (x.linear() != y.linear()) {
        // "paddedRange": aligned to bufferImageGranularity when one is linear and one is not.
        const auto pad = [&](ByteRange r) {
            return ByteRange{r.begin / granularity_ * granularity_,
                             (r.end + granularity_ - 1) / granularity_ * granularity_};
        };
        rx = pad(rx);
        ry = pad(ry);
    }
    const ByteRange common{std::max(rx.begin, ry.begin), std::min(rx.end, ry.end)};
    if (common.begin >= common.end) return false;
    if (shared) *shared = common;
    return true;
}

Overlap MemoryMap::overlap(uint32_t a, const SubresourceRange& cellsA, uint32_t b,
                           const SubresourceRange& cellsB) const {
    Overlap o;
    if (a == b) {
        const MemoryObject& x = objects_.at(a);
        // Buffers are one subresource; the plan always accesses them whole.
        o.cells = x.kind == MemoryObject::Kind::Image ? intersection(cellsA, cellsB) : x.whole();
        if (o.cells.mipCount && o.cells.layerCount) o.kind = Overlap::Kind::SameObject;
        return o;
    }
    if (placementsOverlap(a, b, &o.bytes)) o.kind = Overlap::Kind::Aliased;
    return o;
}

bool MemoryMap::covers(const BarrierMemory& m, const MemoryProbe& probe, AliasCoverage rule) const {
    if (m.all) return true;
    const MemoryObject& target = objects_.at(probe.object);
    const bool ownSubresources =
        m.object == probe.object && (target.kind != MemoryObject::Kind::Image || rangeContains(m.range, probe.cells));
    if (!probe.aliased) {
        if (m.object == probe.object) return ownSubresources;
        // A barrier on another resource covers this one's subresources only as memory: all of
        // its own, holding all of this one's bytes.
        ByteRange targetBytes;
        if (!m.wholeObject || !target.placement || !objects_.at(m.object).placement) return false;
        targetBytes = target.placement->bytes;
        const auto& placed = *objects_.at(m.object).placement;
        return placed.heapInstance == target.placement->heapInstance && placed.bytes.contains(targetBytes);
    }
    if (rule == AliasCoverage::OwnSubresources && ownSubresources) return true;
    if (!m.wholeObject) return false;
    if (m.object == probe.object || m.object == probe.otherObject) return true;
    const MemoryObject& barrierObject = objects_.at(m.object);
    return barrierObject.placement && target.placement &&
           barrierObject.placement->heapInstance == target.placement->heapInstance &&
           barrierObject.placement->bytes.contains(probe.sharedBytes);
}

}  // namespace skygraph::verifier
