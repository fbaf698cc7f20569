// Building the frame model from a plan: what the executor records, in the order it records
// it, one frame after the other.
#include "frame_builder.hpp"

#include <span>

namespace skygraph::verifier {
namespace {

std::vector<const Barrier*> pointers(std::span<const Barrier> barriers) {
    std::vector<const Barrier*> out;
    for (const Barrier& b : barriers) out.push_back(&b);
    return out;
}

}  // namespace

void FrameBuilder::run() {
    shapes_ = describeResources(plan_, graph_, reporter_);
    bool anyShared = plan_.memory().sharedAcrossFrames && !plan_.memory().placements.empty();
    for (const ResourceShape& s : shapes_) anyShared |= s.valid && s.shared;
    model_.frames = options_.consecutiveFrames && anyShared ? 2 : 1;
    makeObjects();
    for (uint32_t f = 1; f <= model_.frames; ++f) recordFrame(f);
    linkSemaphores();
    model_.graph.finalize();
    resolvePlaces();
    checkTransfersOrdered();
}

void FrameBuilder::makeObjects() {
    const auto resources = plan_.resources();
    const auto heaps = static_cast<uint32_t>(plan_.memory().heaps.size());
    model_.objectOf.assign(model_.frames, std::vector<int32_t>(resources.size(), -1));
    for (uint32_t f = 1; f <= model_.frames; ++f) {
        for (size_t r = 0; r < resources.size(); ++r) {
            const ResourceShape& s = shapes_[r];
            if (!s.valid) continue;
            if (f > 1 && s.shared) {
                model_.objectOf[f - 1][r] = model_.objectOf[0][r];
                continue;
            }
            MemoryObject o;
            o.kind = s.image ? MemoryObject::Kind::Image : MemoryObject::Kind::Buffer;
            o.resource = static_cast<int32_t>(r);
            o.frame = f;
            o.shared = s.shared;
            o.handedOut = s.external || s.exported;
            // The file's exports, and what the plan exports beyond them (read-backs, options:
            // an external input exported there is one the plan says carries its contents);
            // an external input's final barrier only gives it back, its contents not needed.
            o.readAfterFrame = !s.presented && (s.finalState != ExternalState::None || (!s.external && s.exported) ||
                                                resources[r].copies == ResourceCopies::SharedExported);
            o.mips = s.mips;
            o.layers = s.layers;
            o.name = std::string(resources[r].name);
            // Each frame in flight has its own copy of the heaps, unless the frames share them.
            const uint32_t copy = plan_.memory().sharedAcrossFrames ? 0 : (f - 1) * heaps;
            if (s.heap) o.placement = PlacedBytes{*s.heap + copy, s.bytes};
            model_.objectOf[f - 1][r] = static_cast<int32_t>(model_.memory.add(std::move(o)));
        }
    }
}

void FrameBuilder::recordFrame(uint32_t f) {
    hostCopies_.clear();
    queue_ = QueueKind::Graphics;
    recordOutsideReadsBefore(f);
    const std::vector<Presented> presented = recordAcquires(f);
    if (plan_.submits().empty()) {  // a plan built without submits: every step on one queue
        recordAcquireWaits(QueueKind::Graphics, ++batch_, true);
        for (size_t i = 0; i < plan_.passes().size(); ++i) recordStep(f, i);
        recordBatch(f, plan_.passes().size(), pointers(plan_.finalBarriers()), -1, "final barrier", ++position_);
    }
    for (size_t k = 0; k < plan_.submits().size(); ++k) recordSubmit(f, k);
    if (!acquireReads_.empty()) recordAcquireWaits(QueueKind::Graphics, ++batch_, false);  // no submit waits
    queue_ = QueueKind::Graphics;
    const auto passes = plan_.passes();
    model_.timeline.push_back({TimelineItem::Kind::FrameEnd, f, 0, nullptr, nullptr, false, false,
                               stepSite(f, passes.size(), "end of frame")});
    recordOutsideReadsAfter(f);
    recordPresentsAndFence(f, presented);
}

void FrameBuilder::recordStep(uint32_t f, size_t i) {
    const auto passes = plan_.passes();
    recordBatch(f, i, pointers(passes[i].barriers), -1, "barrier", ++position_);
    // The accesses, then the in-pass barriers, then the copies in of ReadWrite transfers.
    const uint64_t usagesAt = ++position_;
    position_ += 2;
    const std::vector<TimelineItem> copyIns = recordUsages(f, i, usagesAt);
    recordInPassBatch(f, i, usagesAt + 1);
    model_.timeline.insert(model_.timeline.end(), copyIns.begin(), copyIns.end());
}

void FrameBuilder::recordSubmit(uint32_t f, size_t k) {
    const Submit& s = plan_.submits()[k];
    queue_ = s.queue;
    recordWaits(f, k);
    for (const uint32_t i : s.passes) {
        if (i >= plan_.passes().size()) {
            if (f == 1)
                report(FindingKind::MalformedPlan, {1, -1, "submit " + std::to_string(k), ""},
                       "pass " + std::to_string(i) + " does not exist");
            continue;
        }
        if (plan_.queueOf(i) != s.queue && f == 1)
            report(FindingKind::MalformedPlan, stepSite(f, i, "its submit"),
                   "the pass runs on the " + std::string(toString(plan_.queueOf(i))) + " queue but submit " +
                       std::to_string(k) + " is on the " + std::string(toString(s.queue)) + " queue");
        recordStep(f, i);
    }
    if (!s.releases.empty()) {
        const size_t at = s.passes.empty() ? plan_.passes().size() : s.passes.back();
        recordBatch(f, at, pointers(s.releases), -1, "release", ++position_, true);
    }
    if (k + 1 == plan_.submits().size())
        recordBatch(f, plan_.passes().size(), pointers(plan_.finalBarriers()), -1, "final barrier", ++position_);
    recordSignals(f, k);
}

void FrameBuilder::recordWaits(uint32_t f, size_t k) {
    const Submit& s = plan_.submits()[k];
    if (s.waits.empty() && !s.waitsForAcquire) return;
    const uint64_t batch = ++batch_;
    for (const SemaphoreOp& w : s.waits) {
        const FindingSite site = submitSite(f, k, "wait for " + std::string(toString(w.semaphore)) + "=" +
                                                       std::to_string(w.value));
        checkQueueStages(f, site, "wait", w.stages);
        SyncPoint p;
        p.kind = SyncPoint::Kind::SemaphoreWait;
        p.queue = static_cast<uint32_t>(s.queue);
        p.position = ++position_;
        p.batch = batch;
        p.secondSync = synchronizationScope(w.stages, ScopeSide::Second);
        p.secondAccess = AccessScope::allDeviceAccess();
        const PointId id = addPoint(p, BarrierMemory{true, 0, {}, true});
        // Values count the frame's signals from 1, on top of what the semaphore held: a wait
        // for 0 has long been satisfied and orders nothing (linkSemaphores gives it no edge).
        if (w.value == 0 && f == 1)
            report(FindingKind::Semaphore, site,
                   "a wait for value 0 waits for nothing: the frame's signals count from 1, and the semaphore "
                   "holds at least the frames before");
        waits_.push_back({f, w.semaphore, w.value, id, k});
    }
    if (s.waitsForAcquire) recordAcquireWaits(s.queue, batch, true);
}

void FrameBuilder::recordSignals(uint32_t f, size_t k) {
    const Submit& s = plan_.submits()[k];
    if (s.signals.empty()) return;
    const uint64_t batch = ++batch_;
    for (const SemaphoreOp& sg : s.signals) {
        const FindingSite site = submitSite(f, k, "signal of " + std::string(toString(sg.semaphore)) + "=" +
                                                       std::to_string(sg.value));
        checkQueueStages(f, site, "signal", sg.stages);
        if (sg.semaphore != s.queue && f == 1)
            report(FindingKind::Semaphore, site, "a queue signals its own semaphore only");
        if (sg.value == 0 && f == 1)  // a timeline signal must exceed the semaphore's value
            report(FindingKind::Semaphore, site,
                   "a signal of value 0 does not grow past what the semaphore holds: the frame's signals count from 1");
        for (const SemaphorePoint& earlier : signals_)
            if (earlier.frame == f && earlier.semaphore == sg.semaphore && earlier.value >= sg.value && f == 1)
                report(FindingKind::Semaphore, site,
                       "value " + std::to_string(sg.value) + " does not grow past the earlier signal of " +
                           std::to_string(earlier.value));
        SyncPoint p;
        p.kind = SyncPoint::Kind::SemaphoreSignal;
        p.queue = static_cast<uint32_t>(s.queue);
        p.position = ++position_;
        p.batch = batch;
        p.firstSync = synchronizationScope(sg.stages, ScopeSide::First);
        p.firstAccess = AccessScope::allDeviceAccess();
        const PointId id = addPoint(p, BarrierMemory{true, 0, {}, true});
        signals_.push_back({f, sg.semaphore, sg.value, id, k});
    }
}

/// A timeline wait for value v is satisfied by the first signal of its semaphore that reaches
/// v; signals of one semaphore come in order, so that one happens before the rest.
void FrameBuilder::linkSemaphores() {
    for (const SemaphorePoint& w : waits_) {
        if (w.value == 0) continue;  // reported where it is recorded
        const SemaphorePoint* first = nullptr;
        for (const SemaphorePoint& sg : signals_)
            if (sg.frame == w.frame && sg.semaphore == w.semaphore && sg.value >= w.value &&
                (!first || sg.value < first->value))
                first = &sg;
        if (!first) {
            if (w.frame == 1)
                report(FindingKind::Semaphore,
                       submitSite(w.frame, w.submit,
                                  "wait for " + std::string(toString(w.semaphore)) + "=" + std::to_string(w.value)),
                       "no signal of the frame reaches this value: the wait never ends");
            continue;
        }
        if (first->submit >= w.submit && w.frame == 1)
            report(FindingKind::Semaphore, submitSite(w.frame, w.submit, "wait for " + std::string(toString(w.semaphore)) +
                                                                     "=" + std::to_string(w.value)),
                   "its signal comes in a later submit (" + std::to_string(first->submit) +
                       "): on one queue the frame would never end");
        model_.graph.addEdge(first->point, w.point);
    }
}

FindingSite FrameBuilder::submitSite(uint32_t frame, size_t k, std::string what) const {
    const Submit& s = plan_.submits()[k];
    const int64_t step = s.passes.empty() ? (k == 0 ? -1 : static_cast<int64_t>(plan_.passes().size()))
                                          : static_cast<int64_t>(s.passes.front());
    return {frame, step, "submit " + std::to_string(k) + " (" + std::string(toString(s.queue)) + ")", std::move(what)};
}

/// A semaphore operation's or a barrier's stages must be ones its queue has.
void FrameBuilder::checkQueueStages(uint32_t f, const FindingSite& site, const char* side, VkPipelineStageFlags2 stages,
                                    int64_t resource) {
    if (f != 1 || queue_ == QueueKind::Graphics) return;
    if (const VkPipelineStageFlags2 extra = stages & ~stagesOfQueue(queue_))
        report(FindingKind::InvalidMask, site,
               std::string(side) + " stages " + stageNames(extra) + " are not supported on the " +
                   std::string(toString(queue_)) + " queue",
               resource);
}

void FrameBuilder::resolvePlaces() {
    const HappensBefore& g = model_.graph;
    for (size_t i = 0; i < pending_.size(); ++i) {
        const PlaceSpec& s = pending_[i];
        AccessPlace& place = model_.accesses[i].place;
        switch (s.kind) {
            case PlaceSpec::Kind::Queue: place = g.onQueue(s.queue); break;
            case PlaceSpec::Kind::Inside: place = g.inside(s.point); break;
            case PlaceSpec::Kind::Between: place = g.between(s.release, s.point); break;
            case PlaceSpec::Kind::WaitingFor: place = g.waitingFor(s.point, s.stages); break;
            case PlaceSpec::Kind::Signalling: place = g.signalling(s.point); break;
        }
    }
}

void FrameBuilder::checkTransfersOrdered() {
    for (const Transfer& t : transfers_) {
        if (model_.graph.successors(t.release).test(t.acquire)) continue;
        Finding f;
        f.kind = FindingKind::Unordered;
        f.resources.push_back(t.resource);
        f.resourceNames.emplace_back(plan_.resources()[t.resource].name);
        f.earlier = t.releaseSite;
        f.later = t.acquireSite;
        f.reason = std::string("the release does not happen before its acquire: no chain of barriers and semaphores "
                               "orders them") +
                   (t.transition ? ", and the layout transition between them races both"
                                 : ", so the acquire may take over what was not yet given up");
        reporter_.add(std::move(f));
    }
}

int32_t FrameBuilder::objectOf(uint32_t f, uint32_t r, const FindingSite& site) {
    if (r >= plan_.resources().size()) {
        if (f == 1)
            report(FindingKind::MalformedPlan, site, "resource " + std::to_string(r) + " is not a plan resource");
        return -1;
    }
    return model_.objectOf[f - 1][r];
}

void FrameBuilder::addAccess(ModelAccess a, PlaceSpec spec) {
    model_.accesses.push_back(std::move(a));
    pending_.push_back(spec);
}

PointId FrameBuilder::addPoint(const SyncPoint& p, const BarrierMemory& memory) {
    model_.pointMemory.push_back(memory);
    return model_.graph.add(p);
}

void FrameBuilder::checkMask(uint32_t f, const FindingSite& site, int64_t resource, const char* side,
                             VkPipelineStageFlags2 stages, VkAccessFlags2 access) {
    if (f != 1) return;
    if (const auto s = unmodelledStages(stages))
        report(FindingKind::InvalidMask, site, std::string(side) + " stages " + stageNames(s) + " are not modelled",
               resource);
    if (const auto a = unmodelledAccess(access))
        report(FindingKind::InvalidMask, site, std::string(side) + " access " + accessNames(a) + " is not modelled",
               resource);
    if (const auto a = accessUnsupportedByStages(stages, access))
        report(FindingKind::InvalidMask, site,
               std::string(side) + " access " + accessNames(a) + " is performed by none of its stages " +
                   stageNames(stages),
               resource);
}

void FrameBuilder::report(FindingKind kind, FindingSite site, std::string reason, int64_t resource) {
    reporter_.addAt(kind, std::move(site), std::move(reason), plan_, resource);
}

FindingSite FrameBuilder::stepSite(uint32_t frame, size_t step, std::string what) const {
    if (step >= plan_.passes().size())
        return {frame, static_cast<int64_t>(plan_.passes().size()), "final barriers", std::move(what)};
    return {frame, static_cast<int64_t>(step), std::string(plan_.passes()[step].name), std::move(what)};
}

FrameModel buildFrameModel(const Plan& plan, const GraphDesc& graph, const VerifyOptions& options, Reporter& reporter) {
    FrameModel model(plan.memory().granularity);
    FrameBuilder(plan, graph, options, reporter, model).run();
    return model;
}

}  // namespace skygraph::verifier
