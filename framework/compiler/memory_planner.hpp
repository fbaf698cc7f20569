// Placing transient resources in heaps: a pure function of their lifetimes and memory
// requirements (docs/memory.md). The synchronizer gathers the inputs once the plan's steps are
// known and uses the placements' `aliases` for its aliasing barriers.
#pragma once

#include <skygraph/memory.hpp>

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

/// What estimatedMemory() answers, without the call through MemoryModel: the compiler's path
/// when no model is given (it needs no usage flags).
[[nodiscard]] MemoryRequirements estimatedRequirements(const MemoryQuery& query) noexcept;

namespace detail {
/// The planner's write access to a layout's alias storage.
struct MemoryLayoutBuilder {
    static std::vector<uint32_t>& aliasStorage(MemoryLayout& m) noexcept { return m.aliasStorage_; }
};
}  // namespace detail

}  // namespace skygraph
