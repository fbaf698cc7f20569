// Happens-before as a graph of synchronization points (Vulkan 1.3 §7.1 "Execution and Memory
// Dependencies", §7.1.1 "execution dependency chains").
//
// A point is one dependency: a pipeline barrier, a semaphore signal or wait, a fence signal.
// It has a first and a second synchronization scope (stage sets, expanded by logical order)
// and a first and a second access scope (never expanded). Points are placed on a queue in
// submission order; points of one batch (one vkCmdPipelineBarrier2) never chain with each
// other. Edges between points come from two places:
// - chains on one queue: a point whose second side is ordered by the queue (a barrier, a
//   semaphore wait) reaches a later point whose first side is (a barrier, a signal) when the
//   second scope meets the first scope, or when the later first scope is every stage (ALL_COMMANDS
//   also covers the operations of earlier synchronization commands);
// - explicit edges: a semaphore signal to its wait. With one queue there are none: the
//   swapchain's semaphores and the frame's fence lead to agents outside the queue (the
//   presentation engine, the host), whose accesses hang on the signal or wait directly
//   (waitingFor, signalling). A second queue adds its points on queue 1 and an edge per
//   signal/wait pair (addEdge), and every query below works unchanged.
// Accesses are not points: an access sits on a queue (or, for the host and the presentation
// engine, on the far side of a signal or a wait) and is placed by the points it enters (whose
// first scope it is in) and the points it comes after (whose second scope it is in).
#pragma once

#include "sync_tables.hpp"

#include <cstdint>
#include <vector>

namespace skygraph::verifier {

/// A set of point ids.
class PointSet {
public:
    PointSet() = default;
    explicit PointSet(size_t size) : words_((size + 63) / 64, 0) {}
    void set(uint32_t i) { words_[i / 64] |= uint64_t(1) << (i % 64); }
    [[nodiscard]] bool test(uint32_t i) const { return i / 64 < words_.size() && (words_[i / 64] >> (i % 64) & 1u); }
    [[nodiscard]] bool any() const;
    [[nodiscard]] bool intersects(const PointSet& o) const;
    PointSet& operator|=(const PointSet& o);
    template <class F>
    void forEach(F&& f) const {
        for (size_t w = 0; w < words_.size(); ++w)
            for (uint64_t bits = words_[w]; bits; bits &= bits - 1)
                f(static_cast<uint32_t>(w * 64 + static_cast<size_t>(__builtin_ctzll(bits))));
    }

private:
    std::vector<uint64_t> words_;
};

using PointId = uint32_t;

struct SyncPoint {
    enum class Kind : uint8_t {
        PipelineBarrier,  ///< Both sides ordered by its queue.
        SemaphoreWait,    ///< First side: the signals with edges to it; second side: its queue.
        SemaphoreSignal,  ///< First side: its queue; second side: its edges (fences, presents).
    };
    Kind kind = Kind::PipelineBarrier;
    uint32_t queue = 0;
    uint64_t position = 0;  ///< Submission order on its queue.
    uint64_t batch = 0;     ///< Points of one batch do not chain.
    StageSet firstSync, secondSync;
    AccessScope firstAccess, secondAccess;
    /// An in-pass barrier of this plan step: the step's other accesses are neither before nor
    /// after it (only the ReadWrite transfer's two halves are). -1 for the rest.
    int64_t inPassStep = -1;
};

/// Where an access on a queue is.
struct QueuePlace {
    uint32_t queue = 0;
    uint64_t position = 0;
    int64_t step = -1;
    /// Not one half of a ReadWrite transfer: in-pass barriers do not order it.
    bool outsideInPassOrder = true;
    StageSet stages;
};

/// An access placed in the graph: the points it happens before directly (it is in their first
/// scope) and the points it happens after directly (it is in their second scope).
struct AccessPlace {
    PointSet enters;
    PointSet after;
};

class HappensBefore {
public:
    PointId add(const SyncPoint& point);
    /// A signal-to-wait edge (or a signal to another agent's wait).
    void addEdge(PointId from, PointId to);
    /// Computes the chains and their transitive closure; call once, after adding every point.
    void finalize();

    [[nodiscard]] size_t size() const noexcept { return points_.size(); }
    [[nodiscard]] const SyncPoint& point(PointId p) const { return points_.at(p); }

    [[nodiscard]] AccessPlace onQueue(const QueuePlace& place) const;
    /// A layout transition: inside its barrier, after the availability operation and before
    /// the visibility operation.
    [[nodiscard]] AccessPlace inside(PointId barrier) const;
    /// The layout transition (or the change of owner) of a queue family ownership transfer:
    /// after its release, and before its acquire is done (§7.7.4).
    [[nodiscard]] AccessPlace between(PointId release, PointId acquire) const;
    /// An access by an agent outside the queues (the host after a fence, the presentation
    /// engine after the render-complete signal) that waits for `signal`: the signal, and every
    /// earlier point of the signal's queue whose second scope holds `stages` (a barrier with a
    /// HOST destination, for the host), come before it.
    [[nodiscard]] AccessPlace waitingFor(PointId signal, StageSet stages) const;
    /// An access by an agent outside the queues that the queue waits for through `wait`.
    [[nodiscard]] AccessPlace signalling(PointId wait) const;

    /// The points that happen after `p` through chains and edges (`p` not included).
    [[nodiscard]] const PointSet& successors(PointId p) const { return closure_.at(p); }
    /// `set` with every point that happens after one of its points.
    [[nodiscard]] PointSet withSuccessors(const PointSet& set) const;
    /// Whether `earlier` happens before `later`: a point it enters is, or chains to, a point
    /// that `later` comes after.
    [[nodiscard]] bool happensBefore(const AccessPlace& earlier, const AccessPlace& later) const;

private:
    [[nodiscard]] bool chains(const SyncPoint& from, const SyncPoint& to) const;
    void close(PointId p, std::vector<uint8_t>& state);

    std::vector<SyncPoint> points_;
    std::vector<std::vector<PointId>> edges_;  // explicit, then chains after finalize()
    std::vector<PointSet> closure_;
};

}  // namespace skygraph::verifier
