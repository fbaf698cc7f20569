// A resource's mip x layer grid, flattened, for per-subresource state tracking.
#pragma once

#include <skygraph/graph.hpp>
#include <skygraph/usage.hpp>

#include <cstdint>
#include <vector>

namespace skygraph {

struct SubresourceGrid {
    uint32_t mips = 1;
    uint32_t layers = 1;

    SubresourceGrid() = default;
    SubresourceGrid(const ResourceDesc& r, uint32_t outputWidth, uint32_t outputHeight)
        : mips(r.isImage() ? r.mipCount(outputWidth, outputHeight) : 1),
          layers(r.isImage() ? r.layers : 1) {}

    [[nodiscard]] size_t size() const noexcept { return size_t(mips) * layers; }
    [[nodiscard]] size_t index(uint32_t mip, uint32_t layer) const noexcept {
        return size_t(mip) * layers + layer;
    }
    [[nodiscard]] SubresourceRange whole() const noexcept { return {0, mips, 0, layers}; }
    /// The usage's range, or the whole resource; clipped to the grid.
    [[nodiscard]] SubresourceRange resolve(const Usage& u) const noexcept {
        if (!u.range) return whole();
        SubresourceRange r = *u.range;
        r.baseMip = std::min(r.baseMip, mips - 1);
        r.mipCount = std::min(r.mipCount, mips - r.baseMip);
        return r;
    }
    [[nodiscard]] bool contains(const SubresourceRange& r) const noexcept {
        return r.baseMip + r.mipCount <= mips && r.baseLayer + r.layerCount <= layers;
    }
    template <typename F>
    void forEach(const SubresourceRange& r, F&& f) const {
        for (uint32_t m = r.baseMip; m < r.baseMip + r.mipCount; ++m)
            for (uint32_t l = r.baseLayer; l < r.baseLayer + r.layerCount; ++l) f(index(m, l));
    }
};

}  // namespace skygraph
