// What the queue planner decides per pass, and the submits cut from it: a pass opens a new
// submit on its queue when it waits, and closes one when another queue waits for it.
#pragma once

#include <skygraph/plan.hpp>

#include <array>
#include <cstdint>
#include <set>
#include <vector>

namespace skygraph {

/// Pass numbers beside the plan's: the frame's first submit (on the graphics queue), and none.
constexpr int32_t kFrameStart = -1;
constexpr int32_t kNever = -2;

/// A release barrier, recorded after pass `source` on the queue that gives the resource up.
struct PendingRelease {
    int32_t source;
    Barrier barrier;
};

/// A wait for pass `source` of queue kind `queue`, at `stages`.
struct QueueWait {
    size_t queue;
    int32_t source;
    VkPipelineStageFlags2 stages;
};

struct QueueSchedule {
    std::vector<QueueKind> queues;                ///< per pass
    std::vector<std::vector<Barrier>> barriers;   ///< per pass, cut to its queue
    std::vector<std::vector<QueueWait>> waits;    ///< per pass: before it
    std::vector<QueueWait> endWaits;              ///< of the frame's last submit
    std::vector<PendingRelease> releases;
    /// Per queue kind: the passes it signals after (kFrameStart: the first submit).
    std::array<std::set<int32_t>, kQueueKinds> signals;
    std::vector<VkPipelineStageFlags2> signalStages;  ///< per pass: what its signal must hold
};

/// Writes `schedule` into `plan`: the passes' barriers and the submits, with one timeline
/// value per signalling pass. The first submit signals the frame's start; the last, on the
/// graphics queue, waits for `endWaits`.
void writeSubmits(QueueSchedule schedule, Plan& plan);

}  // namespace skygraph
