// The last compile phase: passes on several queues. It splits the single-queue plan that the
// synchronizer wrote into submits per queue, turns every dependency between queues into a
// timeline semaphore wait at the exact stages, pairs release and acquire barriers where an
// exclusive resource changes queue family, and keeps each barrier to stages its queue has.
// The rules are docs/queues.md's.
#pragma once

#include "graph_index.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/plan.hpp>

namespace skygraph {

/// Gives `plan` (synchronized for one queue) its submits. A plan whose passes all run on the
/// graphics queue keeps its barriers and gets one submit. Throws GraphError when a presented
/// image is used off the graphics queue.
void planQueues(const GraphIndex& index, const CompileOptions& options, Plan& plan);

}  // namespace skygraph
