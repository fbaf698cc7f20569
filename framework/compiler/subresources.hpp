// A resource's mip x layer grid, flattened, for per-subresource state tracking. GraphIndex lays
// the grids of a whole graph end to end, so that per-subresource values of every resource live
// in one flat array (one allocation per sweep, not one per resource).
#pragma once

#include <skygraph/graph.hpp>
#include <skygraph/usage.hpp>

#include <algorithm>
#include <cstdint>

namespace skygraph {

struct SubresourceGrid {
    uint32_t mips = 1;
    uint32_t layers = 1;

    SubresourceGrid() = default;
    SubresourceGrid(const ResourceDesc& r, uint32_t outputWidth, uint32_t outputHeight)
        // mipCount is out of line: it is called only for "full" chains.
        : mips(!r.isImage() ? 1 : r.mips != 0 ? r.mips : r.mipCount(outputWidth, outputHeight)),
          layers(r.isImage() ? r.layers : 1) {}

    [[nodiscard]] size_t size() const noexcept { return size_t(mips) * layers; }
    [[nodiscard]] size_t index(uint32_t mip, uint32_t layer) const noexcept {
        return size_t(mip) * layers + layer;
    }
    [[nodiscard]] SubresourceRange whole() const noexcept { return {0, mips, 0, layers}; }
    /// A usage's range as written (null: none), or the whole resource; clipped to the grid.
    /// Layers too: a GraphDesc built in code may name layers the image lacks, and the index
    /// walks a usage's subresources before validate() words that.
    [[nodiscard]] SubresourceRange resolve(const SubresourceRange* written) const noexcept {
        if (!written) return whole();
        SubresourceRange r = *written;
        r.baseMip = std::min(r.baseMip, mips - 1);
        r.mipCount = std::min(r.mipCount, mips - r.baseMip);
        r.baseLayer = std::min(r.baseLayer, layers - 1);
        r.layerCount = std::min(r.layerCount, layers - r.baseLayer);
        return r;
    }
    [[nodiscard]] bool contains(const SubresourceRange& r) const noexcept {
        return r.baseMip + r.mipCount <= mips && r.baseLayer + r.layerCount <= layers;
    }
    /// Calls f(grid index) for every subresource of `r`, mip-major: the order in which
    /// per-subresource results of a range are stored (see cells()).
    template <typename F>
    void forEach(const SubresourceRange& r, F&& f) const {
        if (r.mipCount == 1 && r.layerCount == 1) return f(index(r.baseMip, r.baseLayer));  // most usages
        for (uint32_t m = r.baseMip; m < r.baseMip + r.mipCount; ++m)
            for (uint32_t l = r.baseLayer; l < r.baseLayer + r.layerCount; ++l) f(index(m, l));
    }
};

/// Number of subresources in a range.
[[nodiscard]] inline size_t cells(const SubresourceRange& r) noexcept {
    return size_t(r.mipCount) * r.layerCount;
}

}  // namespace skygraph
