// Placing transient resources in heaps: a pure function of their lifetimes and memory
// requirements (docs/memory.md). The synchronizer gathers the inputs once the plan's steps are
// known and uses the placements' `aliases` for its aliasing barriers.
#pragma once

#include <skygraph/memory.hpp>

#include <algorithm>
#include <cstdint>
#include <span>

namespace skygraph {

/// One transient resource, as placement needs it.
struct TransientResource {
    uint32_t resource = 0;   ///< Index into Plan::resources().
    uint32_t firstStep = 0;  ///< Its lifetime in plan steps, inclusive.
    uint32_t lastStep = 0;
    MemoryRequirements requirements;
    bool linear = false;     ///< A buffer (the spec's linear resource); images are optimal.
    bool aliasable = true;
};

/// Places `transients` (in order of first use) in heaps, for a frame of `steps` plan steps.
/// Resources share bytes only when their lifetimes are disjoint; with `aliasing` off, or for a
/// resource that is not aliasable, never. With `acrossFrames`, consecutive frames use the same
/// heaps, and each placement also names what the previous frame left in its bytes.
/// Deterministic: equal inputs give equal layouts. Fills everything in the result but `model`.
[[nodiscard]] MemoryLayout placeTransients(std::span<const TransientResource> transients, uint32_t steps,
                                           uint64_t granularity, MemoryStrategy strategy, bool aliasing,
                                           bool acrossFrames = false);

/// The device-free estimate's figures (docs/memory.md, "Requirements").
namespace estimate {
inline constexpr uint64_t kImageGranule = 64 * 1024;  // a common GPU page: images are placed in them
inline constexpr uint64_t kBufferAlignment = 256;     // the largest minStorageBufferOffsetAlignment seen
inline constexpr uint64_t kGranularity = 1024;        // bufferImageGranularity of current desktop GPUs
}  // namespace estimate

/// What estimatedMemory() answers, without the call through MemoryModel: the compiler's path
/// when no model is given (it needs no usage flags). Inline: the compiler asks once per
/// transient.
[[nodiscard]] inline MemoryRequirements estimatedRequirements(const MemoryQuery& q) noexcept {
    const auto roundUp = [](uint64_t v, uint64_t to) { return (v + to - 1) / to * to; };
    const ResourceDesc& d = *q.resource;
    if (!d.isImage()) return {roundUp(std::max<uint64_t>(d.sizeBytes, 4), 4), estimate::kBufferAlignment, 1u};
    uint64_t bytes = 0;
    const uint64_t texel = std::max(1u, d.format.bytesPerTexel);
    for (uint32_t m = 0; m < q.mips; ++m)
        bytes += uint64_t(std::max(1u, q.width >> m)) * std::max(1u, q.height >> m) * texel;
    return {roundUp(bytes * std::max(1u, q.layers), estimate::kImageGranule), estimate::kImageGranule, 1u};
}

namespace detail {
/// The planner's write access to a layout's alias storage.
struct MemoryLayoutBuilder {
    static std::vector<uint32_t>& aliasStorage(MemoryLayout& m) noexcept { return m.aliasStorage_; }
};
}  // namespace detail

}  // namespace skygraph
