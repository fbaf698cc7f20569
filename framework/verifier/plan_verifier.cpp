// The plan verifier: an independent check that a compiled Plan is free of data races, layout
// errors and memory-aliasing errors under the Vulkan 1.3 memory model, from the plan alone.
// docs/verifier.md is the long form of this comment; include/skygraph/verifier.hpp the API.
//
// It is the project's own oracle where the Khronos validation layer is blind: hazards between
// aliased images described differently, write-after-write between dispatches of storage
// images, and (later) semaphores between queues. It shares no code with the compiler's
// synchronizer: its stage and access tables are its own reading of the specification
// (sync_tables.hpp), and it reads only the public headers.
//
// THE MODEL
//
// A frame as the executor records it. For each plan step in order: its barrier batch (one
// vkCmdPipelineBarrier2; each Barrier is a dependency of its own, a Memory barrier is a global
// VkMemoryBarrier2), then its accesses: each PlannedUsage accesses `range` of `resource` at
// `stages` with `access` in `layout`, and writes if `access` has a write bit. A ReadWrite
// usage at Stage::Transfer is two commands, a copy out (read) and a copy in (write), with the
// step's in-pass barriers (Plan::inPassBarriers()) between them; the step's other accesses are
// neither before nor after those barriers. After the last step come Plan::finalBarriers(),
// then the submit's render-complete semaphore signal (Plan::presentations()) and its fence.
// Inserted steps (Clear, Readback, Clobber) are ordinary accesses.
//
// Happens-before is a small graph of synchronization points (happens_before.hpp): every
// barrier, semaphore wait or signal, and fence is a point with a first and a second
// synchronization scope (stage sets, expanded by the pipelines' logical order) and a first and
// a second access scope (never expanded). An access happens before a point when the point is
// later on its queue and the access's stages are in the point's first scope; a point happens
// before an access when the access is later and its stages are in the point's second scope.
// Two points chain when they are on one queue in that order, in different batches, and the
// earlier one's second scope meets the later one's first scope (or the later one's first
// scope is ALL_COMMANDS, which includes the operations of earlier synchronization commands).
// A semaphore signal reaches its wait, or an agent outside the queues, by an explicit edge.
// Multiple queues add points on other queues and signal-to-wait edges between them; nothing
// else changes.
//
// Memory dependencies. For every pair of accesses to overlapping memory where at least one
// writes, the earlier must happen before the later. If the earlier writes, its write must be
// made available by a point it happens before directly whose first access scope holds the
// write's (stage, access type) pairs and whose memory covers it, and that availability must be
// made visible to the later access by the same point or one chained after it, whose second
// access scope holds the later access's pairs and whose memory covers it. A layout transition
// is a write of every subresource it names, after its barrier's availability operation and
// before its visibility operation; its writes are available at once, and available writes are
// visible to it. Write-after-read needs only the execution dependency. A pair is left out when
// layout transitions between the two rewrote all the memory they share: the pairs with those
// transitions carry the order.
//
// Memory. A resource with a MemoryPlacement lives at [offset, offset + bytes) of its heap,
// one heap per frame in flight; every other resource has memory of its own. Two accesses
// overlap when they touch the same subresource of one resource, or any part of two placements
// that overlap (every subresource of an image overlaps its whole placement; buffers are
// linear, and a buffer and an image overlap within bufferImageGranularity). An image or buffer
// barrier covers the subresources it names of its own resource. Between two different
// resources that share memory the spec's Memory Aliasing section asks that the barrier
// contain every overlapping subresource, so there a barrier covers only if it names every
// subresource of its resource, alone or together with barriers of the same batch with the
// same scopes. A Memory barrier, semaphore or fence covers all memory.
//
// Layouts and contents. Each image subresource's layout is tracked through barriers: a
// barrier's oldLayout must be the current layout or UNDEFINED, each usage's layout must be the
// current one and one its usage allows. A transition from UNDEFINED, a DONT_CARE load or store,
// and a write through another resource sharing the memory make the contents undefined; reading
// undefined contents is a finding. External resources start in their initialLayout with
// contents visible: they come from outside the frame.
//
// Aliasing. A resource whose memory another resource used earlier in the frame must move each
// of its subresources from UNDEFINED before its first use (the happens-before checks order
// that after the other's last use), and two overlapping placements must never both be in use
// at once.
//
// Outside the frame. The presentation engine reads a presented image before the acquire
// semaphore is signalled (the submit waits on it at Presentation::acquireWaitStages) and after
// the render-complete signal (at renderCompleteStages), which must follow the image's writes
// and its transition to PRESENT_SRC_KHR. The host reads each read-back's copy after the
// frame's fence, which makes device writes available but not visible to it: a barrier to
// HOST / HOST_READ must. Whoever takes an exported resource after the frame reads it in its
// final state's scope (ShaderRead: sampled, or storage reads of a buffer, in FRAGMENT_SHADER and
// COMPUTE_SHADER; TransferSrc: transfer reads), and a shared external resource was last read
// that way in its initial state before the first frame.
//
// Frames. Resources with one copy across frames (SharedExported, SharedReadOnly) carry their
// state into the next frame, which the executor submits after this one on the same queue: the
// verifier checks a second frame against the first for them. Every other resource, and every
// heap, has a copy per frame in flight, ordered by the fence the host waits on before reusing
// it, which is outside the model.
//
// verifyPlan builds the frame model, then runs each check over it.
#include <skygraph/verifier.hpp>

#include "checks.hpp"
#include "frame_model.hpp"
#include "report.hpp"

namespace skygraph::verifier {

VerificationReport verifyPlan(const Plan& plan, const GraphDesc& graph, const VerifyOptions& options) {
    Reporter reporter(options.maxFindings);
    const FrameModel model = buildFrameModel(plan, graph, options, reporter);
    checkLayoutsAndContents(model, plan, graph, reporter);
    checkLiveOverlaps(model, reporter);
    const size_t pairs = checkMemoryDependencies(model, plan, reporter);
    VerificationReport report = std::move(reporter.report());
    report.accessesChecked = model.accesses.size();
    report.pairsChecked = pairs;
    return report;
}

}  // namespace skygraph::verifier
