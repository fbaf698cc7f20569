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
    model_.graph.finalize();
    resolvePlaces();
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
    recordOutsideReadsBefore(f);
    const std::vector<Presented> presented = recordAcquires(f);
    const auto passes = plan_.passes();
    for (size_t i = 0; i < passes.size(); ++i) {
        recordBatch(f, i, pointers(passes[i].barriers), -1, "barrier", ++position_);
        // The accesses, then the in-pass barriers, then the copies in of ReadWrite transfers.
        const uint64_t usagesAt = ++position_;
        position_ += 2;
        const std::vector<TimelineItem> copyIns = recordUsages(f, i, usagesAt);
        recordInPassBatch(f, i, usagesAt + 1);
        model_.timeline.insert(model_.timeline.end(), copyIns.begin(), copyIns.end());
    }
    recordBatch(f, passes.size(), pointers(plan_.finalBarriers()), -1, "final barrier", ++position_);
    model_.timeline.push_back({TimelineItem::Kind::FrameEnd, f, 0, nullptr, nullptr, false, false,
                               stepSite(f, passes.size(), "end of frame")});
    recordOutsideReadsAfter(f);
    recordPresentsAndFence(f, presented);
}

void FrameBuilder::resolvePlaces() {
    const HappensBefore& g = model_.graph;
    for (size_t i = 0; i < pending_.size(); ++i) {
        const PlaceSpec& s = pending_[i];
        AccessPlace& place = model_.accesses[i].place;
        switch (s.kind) {
            case PlaceSpec::Kind::Queue: place = g.onQueue(s.queue); break;
            case PlaceSpec::Kind::Inside: place = g.inside(s.point); break;
            case PlaceSpec::Kind::WaitingFor: place = g.waitingFor(s.point, s.stages); break;
            case PlaceSpec::Kind::Signalling: place = g.signalling(s.point); break;
        }
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
