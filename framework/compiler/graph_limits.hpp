// The graph format's limits (docs/graph-format.md, "Limits and defaults"): the loader refuses
// a file past them, and compile() a GraphDesc built in code.
#pragma once

#include <skygraph/diagnostics.hpp>
#include <skygraph/graph.hpp>

#include <bit>
#include <cstdint>

namespace skygraph {

/// The largest image extent a file may give (the common maxImageDimension2D; devices may allow
/// less); extents, mip counts and mip ranges are bounded by it.
inline constexpr uint32_t kMaxImageExtent = 16384;
inline constexpr uint32_t kMaxLayers = 2048;
inline constexpr uint32_t kMaxDivisor = 4096;  ///< Of "output/N".
inline constexpr uint64_t kMaxBufferBytes = 1ull << 31;
/// The largest graph file loadGraphFile() reads (a 100,000-pass graph is about 20 MiB).
inline constexpr uint64_t kMaxGraphFileBytes = 256ull << 20;

/// Whether `r`'s extent, layers, mip count and size are within the limits; the index asks
/// once per resource, so only a resource past them costs a message.
[[nodiscard]] inline bool withinLimits(const ResourceDesc& r) noexcept {
    if (!r.isImage()) return r.sizeBytes != 0 && r.sizeBytes <= kMaxBufferBytes;
    const Extent& e = r.extent;
    const bool extent = e.relativeToOutput ? e.divisor != 0 && e.divisor <= kMaxDivisor
                                           : e.width != 0 && e.height != 0 && e.width <= kMaxImageExtent &&
                                                 e.height <= kMaxImageExtent;
    return extent && r.layers != 0 && r.layers <= kMaxLayers && r.mips <= std::bit_width(kMaxImageExtent);
}

/// A diagnostic for each resource of `graph` past the limits, naming it and what is wrong.
[[nodiscard]] Diagnostics limitProblems(const GraphDesc& graph);

}  // namespace skygraph
