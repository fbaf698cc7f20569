// One or two frames of a plan as the executor records them: the memory objects, the
// synchronization points, every access with its place among them, and the order of it all
// for the layout walk. Everything that does not fit (an index out of range, an empty range)
// is reported here and left out.
#pragma once

#include "happens_before.hpp"
#include "memory_map.hpp"
#include <skygraph/verifier.hpp>
#include "report.hpp"

#include <optional>
#include <variant>
#include <vector>

namespace skygraph::verifier {

/// One access to memory.
struct ModelAccess {
    enum class Kind : uint8_t {
        Usage,                ///< A PlannedUsage (not a ReadWrite transfer).
        CopyOut,              ///< A ReadWrite transfer's read.
        CopyIn,               ///< A ReadWrite transfer's write.
        Transition,           ///< A barrier's layout transition: a write of the range it names.
        ReadbackCopy,         ///< A read-back's write of its host-visible copy.
        HostRead,             ///< The host reading that copy after the fence.
        PresentationAcquire,  ///< The presentation engine's last read, before the acquire.
        PresentationRead,     ///< The present, after the render-complete signal.
        OutsideRead,          ///< Whoever reads an external or exported resource outside the frame.
    };
    Kind kind = Kind::Usage;
    uint32_t object = 0;
    SubresourceRange cells;
    AccessScope performs;  ///< (stage, access type) pairs; empty for transitions and the presentation engine.
    bool writes = false;
    AccessPlace place;
    /// Transitions: their barrier (an ownership transfer's: its release); the present: the
    /// render-complete signal. Visibility to these is automatic; what they need is
    /// availability at or before this point.
    std::optional<PointId> anchor;
    /// A transition of an ownership transfer: its acquire, where its own writes are done.
    /// Others: the anchor.
    std::optional<PointId> doneAt;
    uint32_t frame = 1;
    FindingSite site;
};

/// An item of the layout walk, in recording order.
struct TimelineItem {
    enum class Kind : uint8_t { Barrier, Usage, FrameEnd, Present };
    Kind kind = Kind::Usage;
    uint32_t frame = 1;
    uint32_t object = 0;
    const Barrier* barrier = nullptr;     ///< Barrier.
    const PlannedUsage* usage = nullptr;  ///< Usage.
    /// Usage: which half of a ReadWrite transfer this is (neither for every other usage).
    bool copyOut = false, copyIn = false;
    FindingSite site;
    /// The queue kind it is recorded on (Barrier and Usage).
    QueueKind queue = QueueKind::Graphics;
    /// Barrier: the release half of an ownership transfer (a submit's releases).
    bool release = false;
};

struct FrameModel {
    explicit FrameModel(uint64_t granularity) : memory(granularity) {}

    MemoryMap memory;
    HappensBefore graph;
    std::vector<BarrierMemory> pointMemory;  ///< Per point.
    std::vector<ModelAccess> accesses;       ///< In recording order: earlier before later.
    std::vector<TimelineItem> timeline;
    /// objectOf[frame - 1][plan resource]: its memory object, or -1 when the resource is malformed.
    std::vector<std::vector<int32_t>> objectOf;
    uint32_t frames = 1;
};

/// Builds the model of `plan`; malformed items are reported to `reporter` and left out.
[[nodiscard]] FrameModel buildFrameModel(const Plan& plan, const GraphDesc& graph, const VerifyOptions& options,
                                         Reporter& reporter);

}  // namespace skygraph::verifier
