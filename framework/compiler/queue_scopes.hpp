// What each kind of queue can do: its pipeline stages and the accesses those stages perform,
// and barriers cut to them. The queue planner's vocabulary (docs/queues.md).
#pragma once

#include <skygraph/plan.hpp>

namespace skygraph {

/// The stages a queue of this kind has (Vulkan 1.3 "Supported pipeline stage flags").
VkPipelineStageFlags2 queueStages(QueueKind q);

/// ALL_COMMANDS alone when it is there: the other stages add nothing to it.
VkPipelineStageFlags2 simplified(VkPipelineStageFlags2 stages);

/// The access types that `stages` can perform (all of them for ALL_COMMANDS).
VkAccessFlags2 accessesOf(VkPipelineStageFlags2 stages);

/// Cuts `b` to the stages queue `q` has: on the source side the other queues' stages are
/// reached through the semaphore wait instead; on the destination side they belong to reads
/// of the same run on other queues, which have barriers of their own there.
void keepToQueue(Barrier& b, QueueKind q);

/// Puts MEMORY_READ into a layout transition's source access scope (see queue_scopes.cpp).
void readsIntoTransition(Barrier& b);

}  // namespace skygraph
