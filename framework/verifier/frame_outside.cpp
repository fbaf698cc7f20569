// The agents outside the queue: the presentation engine (through the acquire and
// render-complete semaphores), the host (after the frame's fence), and whoever reads an
// external or exported resource before or after the frame.
#include "frame_builder.hpp"

#include <optional>

namespace skygraph::verifier {
namespace {

/// What the world outside the frame does with a resource it hands in or takes out in a state
/// (docs/graph-format.md, "External, initial and final"): sampled by shaders (ShaderRead),
/// copied from (TransferSrc). General hands it to the next frame itself and Present to the
/// presentation engine, which are modelled on their own.
std::optional<RequiredScope> outsideScope(bool image, VkImageLayout layout, ExternalState state) {
    if (image && layout == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
        return RequiredScope{VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                             VK_ACCESS_2_SHADER_SAMPLED_READ_BIT};
    if (image && layout == VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)
        return RequiredScope{VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT};
    if (!image && state == ExternalState::ShaderRead)
        return RequiredScope{VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                             VK_ACCESS_2_SHADER_STORAGE_READ_BIT};
    return std::nullopt;
}

}  // namespace

/// The presentation engine's read of each presented image before its acquire semaphore is
/// signalled. It reaches the frame only through the wait for that semaphore, which
/// recordAcquireWaits places where the executor waits.
std::vector<FrameBuilder::Presented> FrameBuilder::recordAcquires(uint32_t f) {
    const auto presentations = plan_.presentations();
    std::vector<Presented> presented;
    for (size_t k = 0; k < presentations.size(); ++k) {
        const Presentation& pr = presentations[k];
        const FindingSite site{f, -1, "presentation engine", "read of the image before the acquire"};
        const int32_t object = objectOf(f, pr.resource, site);
        if (object < 0) continue;
        if (!shapes_[pr.resource].image) {
            if (f == 1) report(FindingKind::MalformedPlan, site, "a presented buffer", pr.resource);
            continue;
        }
        ModelAccess a;
        a.kind = ModelAccess::Kind::PresentationAcquire;
        a.object = static_cast<uint32_t>(object);
        a.cells = model_.memory.object(a.object).whole();
        a.frame = f;
        a.site = site;
        acquireReads_.push_back({&pr, model_.accesses.size()});
        addAccess(std::move(a), {PlaceSpec::Kind::Signalling, {}, 0, {}});  // the point: its wait's
        presented.push_back({&pr, static_cast<uint32_t>(object)});
    }
    return presented;
}

/// The waits for the acquire semaphores of the reads recordAcquires left waiting, in `batch`
/// on `queue`: the executor waits in the submit that has Submit::waitsForAcquire (in the batch
/// of its other waits), at Presentation::acquireWaitStages. Where no submit has it (`waited`
/// false), nothing in the frame waits and the wait orders nothing.
void FrameBuilder::recordAcquireWaits(QueueKind queue, uint64_t batch, bool waited) {
    for (const auto& [pr, access] : acquireReads_) {
        SyncPoint wait;
        wait.kind = SyncPoint::Kind::SemaphoreWait;
        wait.queue = static_cast<uint32_t>(queue);
        wait.position = ++position_;
        wait.batch = batch;
        if (waited) wait.secondSync = synchronizationScope(pr->acquireWaitStages, ScopeSide::Second);
        wait.secondAccess = AccessScope::allDeviceAccess();
        pending_[access].point = addPoint(wait, BarrierMemory{true, 0, {}, true});
    }
    acquireReads_.clear();
}

void FrameBuilder::recordPresentsAndFence(uint32_t f, const std::vector<Presented>& presented) {
    const auto afterFrame = static_cast<int64_t>(plan_.passes().size());
    for (const auto& [pr, object] : presented) {
        SyncPoint signal;
        signal.kind = SyncPoint::Kind::SemaphoreSignal;
        signal.position = ++position_;
        signal.batch = ++batch_;
        signal.firstSync = synchronizationScope(pr->renderCompleteStages, ScopeSide::First);
        signal.firstAccess = AccessScope::allDeviceAccess();
        const PointId s = addPoint(signal, BarrierMemory{true, 0, {}, true});
        ModelAccess a;
        a.kind = ModelAccess::Kind::PresentationRead;
        a.object = object;
        a.cells = model_.memory.object(object).whole();
        a.anchor = s;
        a.frame = f;
        a.site = {f, afterFrame, "presentation engine", "present (after the render-complete signal)"};
        model_.timeline.push_back({TimelineItem::Kind::Present, f, object, nullptr, nullptr, false, false, a.site});
        addAccess(std::move(a), {PlaceSpec::Kind::WaitingFor, {}, s, {}});
    }
    SyncPoint fence;
    fence.kind = SyncPoint::Kind::SemaphoreSignal;
    fence.position = ++position_;
    fence.batch = ++batch_;
    fence.firstSync = allDeviceStages();
    fence.firstAccess = AccessScope::allDeviceAccess();
    const PointId fenceId = addPoint(fence, BarrierMemory{true, 0, {}, true});
    for (const uint32_t copy : hostCopies_) {
        ModelAccess h;
        h.kind = ModelAccess::Kind::HostRead;
        h.object = copy;
        h.cells = {0, 1, 0, 1};
        h.performs = accessScope(VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
        h.frame = f;
        h.site = {f, afterFrame, "host", "read of the " + model_.memory.object(copy).name + " after the fence"};
        addAccess(std::move(h), {PlaceSpec::Kind::WaitingFor, {}, fenceId, only(verifier::Stage::Host)});
    }
}

/// Who read a shared external resource last outside the frame (the previous frame's
/// consumer, or whoever its initial state names), on the queue before the first frame: the
/// frame's writes must wait for it. In frame 2 the first frame's consumer is that reader.
void FrameBuilder::recordOutsideReadsBefore(uint32_t f) {
    const auto resources = plan_.resources();
    for (size_t r = 0; r < resources.size(); ++r) {
        const ResourceShape& s = shapes_[r];
        // Per-frame copies were last used by an earlier frame in flight, which the fence
        // the host waits on before reusing them orders; only shared ones meet the outside.
        if (!s.valid || !s.external || s.presented || !s.shared || f > 1) continue;
        const auto scope = outsideScope(s.image, resources[r].initialLayout, s.initialState);
        if (!scope) continue;
        recordOutsideRead(f, static_cast<uint32_t>(r), *scope, -1, "read before the frame, in its initial state");
    }
}

/// Whoever takes an exported resource after the frame, reading it in its final state.
void FrameBuilder::recordOutsideReadsAfter(uint32_t f) {
    const auto resources = plan_.resources();
    for (size_t r = 0; r < resources.size(); ++r) {
        const ResourceShape& s = shapes_[r];
        if (!s.valid || !s.exported || s.presented) continue;
        const auto scope = outsideScope(s.image, resources[r].finalLayout, s.finalState);
        if (!scope) continue;
        recordOutsideRead(f, static_cast<uint32_t>(r), *scope, static_cast<int64_t>(plan_.passes().size()),
                          "read after the frame, in its final state");
    }
}

void FrameBuilder::recordOutsideRead(uint32_t f, uint32_t r, const RequiredScope& scope, int64_t step,
                                     const char* what) {
    const auto object = static_cast<uint32_t>(model_.objectOf[f - 1][r]);
    ModelAccess a;
    a.kind = ModelAccess::Kind::OutsideRead;
    a.object = object;
    a.cells = model_.memory.object(object).whole();
    a.performs = accessScope(scope.stages, scope.access);
    a.frame = f;
    a.site = {f, step, "outside the frame",
              std::string(what) + " (" + stageNames(scope.stages) + " / " + accessNames(scope.access) + ")"};
    QueuePlace q;
    q.position = ++position_;
    q.stages = accessScopeStages(scope.stages);
    addAccess(std::move(a), {PlaceSpec::Kind::Queue, q, 0, {}});
}

}  // namespace skygraph::verifier
