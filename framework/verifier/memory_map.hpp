// Which accesses touch the same memory, and which barriers cover it: the spec's "Memory
// Aliasing" section (resources chapter) applied to the plan's placements.
#pragma once

#include <skygraph/usage.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace skygraph::verifier {

struct ByteRange {
    uint64_t begin = 0, end = 0;
    [[nodiscard]] bool contains(const ByteRange& o) const noexcept { return begin <= o.begin && o.end <= end; }
};

/// A transient resource's place in one frame's copy of a heap.
struct PlacedBytes {
    uint32_t heapInstance = 0;  ///< Heap index + frame copy (the heap index alone when frames share heaps).
    ByteRange bytes;
};

/// Something accesses touch: one frame's copy of a plan resource, or a read-back's host copy.
struct MemoryObject {
    enum class Kind : uint8_t { Image, Buffer, HostCopy };
    Kind kind = Kind::Image;
    int32_t resource = -1;  ///< Index into Plan::resources(); -1 for a host copy.
    uint32_t frame = 1;     ///< The frame whose copy it is (a shared resource's is frame 1's).
    bool shared = false;    ///< One copy for all frames.
    /// External or exported: what it holds after the frame (PlannedResource::finalLayout) matters.
    bool handedOut = false;
    /// Exported to a reader after the frame other than the presentation engine (the file's
    /// final state, a read-back): its contents at the frame's end are what that reader gets.
    bool readAfterFrame = false;
    uint32_t mips = 1, layers = 1;
    std::optional<PlacedBytes> placement;
    std::string name;

    [[nodiscard]] bool linear() const noexcept { return kind != Kind::Image; }
    [[nodiscard]] SubresourceRange whole() const noexcept { return {0, mips, 0, layers}; }
    [[nodiscard]] uint32_t cellCount() const noexcept { return mips * layers; }
    [[nodiscard]] uint32_t cell(uint32_t mip, uint32_t layer) const noexcept { return mip * layers + layer; }
};

[[nodiscard]] bool rangeContains(const SubresourceRange& outer, const SubresourceRange& inner) noexcept;
[[nodiscard]] SubresourceRange intersection(const SubresourceRange& a, const SubresourceRange& b) noexcept;

/// How two accesses' memory overlaps.
struct Overlap {
    enum class Kind : uint8_t { None, SameObject, Aliased };
    Kind kind = Kind::None;
    SubresourceRange cells;  ///< SameObject: the subresources both touch.
    ByteRange bytes;         ///< Aliased: the bytes both placements hold.
};

/// The memory one side of a dependency must have covered: an access's own subresources, and
/// for an access to memory another resource shares, the bytes they share.
struct MemoryProbe {
    uint32_t object = 0;
    SubresourceRange cells;
    bool aliased = false;
    uint32_t otherObject = 0;  ///< Aliased: the other resource's object.
    ByteRange sharedBytes;     ///< Aliased: what both hold.
};

/// What a barrier's memory is.
struct BarrierMemory {
    bool all = false;  ///< A Memory barrier, semaphore or fence.
    uint32_t object = 0;
    SubresourceRange range;
    /// It names every subresource of its object, alone or with barriers of its batch that
    /// have the same scopes: what a barrier between aliases must do.
    bool wholeObject = false;
};

/// How strictly a barrier between resources sharing memory must cover them.
enum class AliasCoverage : uint8_t {
    WholeResource,    ///< The spec's rule: it names every subresource of its resource.
    OwnSubresources,  ///< Relaxed, to tell a partial barrier from a missing one in messages.
};

class MemoryMap {
public:
    explicit MemoryMap(uint64_t granularity) : granularity_(granularity == 0 ? 1 : granularity) {}

    uint32_t add(MemoryObject object);
    [[nodiscard]] const MemoryObject& object(uint32_t id) const { return objects_.at(id); }
    [[nodiscard]] size_t size() const noexcept { return objects_.size(); }

    /// The memory that accesses to (a, cellsA) and (b, cellsB) share.
    [[nodiscard]] Overlap overlap(uint32_t a, const SubresourceRange& cellsA, uint32_t b,
                                  const SubresourceRange& cellsB) const;
    /// Whether two placed objects share bytes (padded to the granularity between a linear and
    /// a non-linear one, as the spec defines aliasing); the shared bytes in `shared`.
    [[nodiscard]] bool placementsOverlap(uint32_t a, uint32_t b, ByteRange* shared = nullptr) const;
    /// Whether barrier memory `m` covers `probe`.
    [[nodiscard]] bool covers(const BarrierMemory& m, const MemoryProbe& probe, AliasCoverage rule) const;

private:
    uint64_t granularity_;
    std::vector<MemoryObject> objects_;
};

}  // namespace skygraph::verifier
