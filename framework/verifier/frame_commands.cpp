// What the queue records for each step: its barrier batch, its accesses (a ReadWrite transfer
// as a copy out and a copy in around the step's in-pass barriers), and a read-back's copy into
// host memory.
#include "frame_builder.hpp"

#include <skygraph/usage.hpp>

#include <algorithm>

namespace skygraph::verifier {

void FrameBuilder::recordBatch(uint32_t f, size_t step, const std::vector<const Barrier*>& barriers, int64_t inPassStep,
                               const char* label, uint64_t position, bool releases) {
    const uint64_t batch = ++batch_;
    std::vector<BatchEntry> entries;
    for (size_t k = 0; k < barriers.size(); ++k) {
        const Barrier& b = *barriers[k];
        std::string what = std::string(b.aliasing ? "aliasing " : "") + label + " " + std::to_string(k);
        if (b.kind == BarrierKind::Image)
            what +=
                " (" + layoutNameShort(b.oldLayout) + " -> " + layoutNameShort(b.newLayout) + ") " + rangeText(b.range);
        if (b.kind == BarrierKind::Memory) what += " (memory)";
        const FindingSite site = stepSite(f, step, what);
        BarrierMemory memory;
        int32_t object = -1;
        if (b.kind == BarrierKind::Memory) {
            memory.all = true;
        } else {
            object = objectOf(f, b.resource, site);
            if (object < 0) continue;
            const ResourceShape& s = shapes_[b.resource];
            if ((b.kind == BarrierKind::Image) != s.image) {
                if (f == 1)
                    report(
                        FindingKind::MalformedPlan, site,
                        b.kind == BarrierKind::Image ? "an image barrier on a buffer" : "a buffer barrier on an image",
                        b.resource);
                continue;
            }
            if (s.image && !rangeInside(b.range, s.mips, s.layers)) {
                if (f == 1)
                    report(FindingKind::MalformedPlan, site,
                           rangeText(b.range) + " is not inside the resource's " + std::to_string(s.mips) + " mips x " +
                               std::to_string(s.layers) + " layers",
                           b.resource);
                continue;
            }
            memory.object = static_cast<uint32_t>(object);
            memory.range = s.image ? b.range : model_.memory.object(memory.object).whole();
            memory.wholeObject = !s.image;
        }
        const int64_t resource = b.kind == BarrierKind::Memory ? -1 : int64_t(b.resource);
        checkMask(f, site, resource, "source", b.srcStages, b.srcAccess);
        checkMask(f, site, resource, "destination", b.dstStages, b.dstAccess);
        checkQueueStages(f, site, "source", b.srcStages, resource);
        checkQueueStages(f, site, "destination", b.dstStages, resource);
        if (f == 1 && b.transfersOwnership() && (releases ? b.srcQueue : b.dstQueue) != queue_)
            report(FindingKind::Ownership, site,
                   std::string(releases ? "a release" : "an acquire") + " of a transfer from the " +
                       std::string(toString(b.srcQueue)) + " to the " + std::string(toString(b.dstQueue)) +
                       " queue recorded on the " + std::string(toString(queue_)) + " queue",
                   resource);
        const bool image = b.kind == BarrierKind::Image;
        if (image && (b.newLayout == VK_IMAGE_LAYOUT_UNDEFINED || b.newLayout == VK_IMAGE_LAYOUT_PREINITIALIZED) &&
            f == 1)
            report(FindingKind::MalformedPlan, site, "newLayout must not be UNDEFINED or PREINITIALIZED", resource);
        SyncPoint p;
        p.queue = static_cast<uint32_t>(queue_);
        p.position = position;
        p.batch = batch;
        p.firstSync = synchronizationScope(b.srcStages, ScopeSide::First);
        // A release ends in its source stages, where a later signal of its queue takes it up
        // (its destination scope is ignored); the acquire after the wait makes it visible.
        p.secondSync = synchronizationScope(releases ? b.srcStages : b.dstStages, ScopeSide::Second);
        p.firstAccess = accessScope(b.srcStages, b.srcAccess);
        p.secondAccess = accessScope(b.dstStages, b.dstAccess);
        p.inPassStep = inPassStep;
        const PointId id = addPoint(p, memory);
        if (object < 0) continue;
        entries.push_back({id, &b, static_cast<uint32_t>(object)});
        if (!image && !b.transfersOwnership()) continue;  // buffers: only their ownership matters here
        TimelineItem item;
        item.kind = TimelineItem::Kind::Barrier;
        item.frame = f;
        item.object = static_cast<uint32_t>(object);
        item.barrier = &b;
        item.site = site;
        item.queue = queue_;
        item.release = releases;
        model_.timeline.push_back(item);
        if (releases) releases_.push_back({static_cast<uint32_t>(object), b.srcQueue, b.dstQueue, b.range, id, site, f});
        // The transition of an ownership transfer happens once, after its release and before
        // its acquire is done (§7.7.4): the accesses before it must happen before the release
        // and their writes be available there (the acquire's source scope counts for
        // nothing), and the accesses after it follow the acquire. An acquire without one
        // still changes what the queue may access: later accesses must follow it as they
        // would a transition, so it is modelled as one, in the acquire.
        const bool transition = image && b.oldLayout != b.newLayout;
        if ((transition || b.transfersOwnership()) && !releases) {
            ModelAccess t;
            t.kind = ModelAccess::Kind::Transition;
            t.object = static_cast<uint32_t>(object);
            t.cells = b.range;
            t.writes = true;
            t.anchor = id;
            t.frame = f;
            t.site = site;
            t.site.what = (transition ? "layout transition of " : "ownership acquire of ") + t.site.what;
            PlaceSpec place{PlaceSpec::Kind::Inside, {}, id, {}};
            // Its release names the same range (a release that differs is reported with the
            // layouts); without one it is placed in the acquire.
            const auto release = std::find_if(releases_.rbegin(), releases_.rend(), [&](const PendingRelease& r) {
                return r.object == t.object && r.from == b.srcQueue && r.to == b.dstQueue &&
                       (!image || r.range == b.range);  // a buffer barrier is always of all of it
            });
            // Every transfer's release must happen before its acquire, with or without a transition
            // between them (§7.7.4: the acquire takes over what the release gave up).
            if (b.transfersOwnership() && release != releases_.rend()) {
                if (transition) {
                    place = {PlaceSpec::Kind::Between, {}, id, {}, release->point};
                    t.anchor = release->point;
                    t.doneAt = id;
                }
                if (release->frame == 1)
                    transfers_.push_back({release->point, id, release->site, site, b.resource, transition});
                releases_.erase(std::next(release).base());
            }
            addAccess(std::move(t), place);
        }
    }
    markWholeObjects(entries);
}

/// Barriers of one batch with the same scopes on the same resource act together: when
/// they name all of it between them, each counts as naming all of it.
void FrameBuilder::markWholeObjects(const std::vector<BatchEntry>& entries) {
    for (const BatchEntry& e : entries) {
        BarrierMemory& m = model_.pointMemory[e.point];
        if (m.wholeObject) continue;
        const MemoryObject& o = model_.memory.object(e.object);
        std::vector<uint8_t> covered(o.cellCount(), 0);
        for (const BatchEntry& other : entries) {
            const Barrier& a = *e.barrier;
            const Barrier& b = *other.barrier;
            if (other.object != e.object || a.srcStages != b.srcStages || a.srcAccess != b.srcAccess ||
                a.dstStages != b.dstStages || a.dstAccess != b.dstAccess)
                continue;
            const SubresourceRange& r = model_.pointMemory[other.point].range;
            for (uint32_t mip = r.baseMip; mip < r.baseMip + r.mipCount; ++mip)
                for (uint32_t layer = r.baseLayer; layer < r.baseLayer + r.layerCount; ++layer)
                    covered[o.cell(mip, layer)] = 1;
        }
        m.wholeObject = std::all_of(covered.begin(), covered.end(), [](uint8_t c) { return c != 0; });
    }
}

std::vector<TimelineItem> FrameBuilder::recordUsages(uint32_t f, size_t step, uint64_t position) {
    std::vector<TimelineItem> copyIns;
    const PlannedPass& pass = plan_.passes()[step];
    const bool readback = pass.declIndex < 0 && pass.type == "Readback";
    for (size_t u = 0; u < pass.usages.size(); ++u) {
        const PlannedUsage& usage = pass.usages[u];
        std::string what = "usage " + std::to_string(u) + " " + toString(usage.usage);
        const FindingSite site = stepSite(f, step, what);
        const int32_t object = objectOf(f, usage.resource, site);
        if (object < 0) continue;
        const ResourceShape& s = shapes_[usage.resource];
        if (s.image && !rangeInside(usage.range, s.mips, s.layers)) {
            if (f == 1)
                report(FindingKind::MalformedPlan, site,
                       rangeText(usage.range) + " is not inside the resource's " + std::to_string(s.mips) + " mips x " +
                           std::to_string(s.layers) + " layers",
                       usage.resource);
            continue;
        }
        checkMask(f, site, usage.resource, "usage", usage.stages, usage.access);
        const RequiredScope required = requiredScope(usage, s.image);
        if (f == 1) {
            if (!accessScopeStages(required.stages).within(accessScopeStages(usage.stages)))
                report(FindingKind::UsageScope, site,
                       "its stages " + stageNames(usage.stages) + " miss " + stageNames(required.stages),
                       usage.resource);
            const uint32_t missing = accessTypes(required.access).bits & ~accessTypes(usage.access).bits;
            if (missing)
                report(FindingKind::UsageScope, site,
                       "its access " + accessNames(usage.access) + " misses part of " + accessNames(required.access) +
                           " (what it and its load/store ops do)",
                       usage.resource);
        }
        ModelAccess a;
        a.object = static_cast<uint32_t>(object);
        a.cells = s.image ? usage.range : model_.memory.object(a.object).whole();
        a.performs = accessScope(usage.stages | required.stages, usage.access | required.access);
        a.frame = f;
        QueuePlace q;
        q.queue = static_cast<uint32_t>(queue_);
        q.position = position;
        q.step = static_cast<int64_t>(step);
        q.stages = accessScopeStages(usage.stages | required.stages);
        TimelineItem item;
        item.kind = TimelineItem::Kind::Usage;
        item.frame = f;
        item.object = a.object;
        item.usage = &usage;
        item.queue = queue_;
        const bool copyPair = usage.usage.stage == skygraph::Stage::Transfer && usage.usage.access == Access::ReadWrite;
        if (copyPair) {
            ModelAccess in = a;
            AccessScope reads = a.performs;
            for (uint32_t& bits : reads.accessAt) bits &= ~writeAccessTypes().bits;
            a.kind = ModelAccess::Kind::CopyOut;
            a.performs = reads;
            a.site = stepSite(f, step, what + " (copy out)");
            q.outsideInPassOrder = false;
            in.kind = ModelAccess::Kind::CopyIn;
            in.performs = in.performs.writesOnly();
            in.writes = !in.performs.empty();
            in.site = stepSite(f, step, what + " (copy in)");
            QueuePlace qin = q;
            qin.position = position + 2;  // after the in-pass barriers at position + 1
            item.copyOut = true;
            item.site = a.site;
            model_.timeline.push_back(item);
            TimelineItem itemIn = item;
            itemIn.copyOut = false;
            itemIn.copyIn = true;
            itemIn.site = in.site;
            copyIns.push_back(itemIn);
            addAccess(std::move(a), {PlaceSpec::Kind::Queue, q, 0, {}});
            addAccess(std::move(in), {PlaceSpec::Kind::Queue, qin, 0, {}});
        } else {
            a.writes = !a.performs.writesOnly().empty();
            a.site = site;
            item.site = site;
            model_.timeline.push_back(item);
            addAccess(std::move(a), {PlaceSpec::Kind::Queue, q, 0, {}});
        }
        if (readback) recordReadbackCopy(f, step, u, q);
    }
    return copyIns;
}

void FrameBuilder::recordInPassBatch(uint32_t f, size_t step, uint64_t position) {
    std::vector<const Barrier*> inPass;
    for (const InPassBarrier& ib : plan_.inPassBarriers()) {
        if (ib.pass >= plan_.passes().size() || ib.usage >= plan_.passes()[ib.pass].usages.size()) {
            if (f == 1 && step == 0)
                report(FindingKind::MalformedPlan, {1, -1, "in-pass barriers", ""},
                       "pass " + std::to_string(ib.pass) + " usage " + std::to_string(ib.usage) + " does not exist");
            continue;
        }
        if (ib.pass == step) inPass.push_back(&ib.barrier);
    }
    recordBatch(f, step, inPass, static_cast<int64_t>(step), "in-pass barrier", position);
}

/// A read-back copies into host-visible memory of its own, which the host reads after
/// the frame's fence.
void FrameBuilder::recordReadbackCopy(uint32_t f, size_t step, size_t usage, const QueuePlace& q) {
    MemoryObject o;
    o.kind = MemoryObject::Kind::HostCopy;
    o.frame = f;
    o.name = "host copy of " + std::string(plan_.passes()[step].name);
    const uint32_t object = model_.memory.add(std::move(o));
    ModelAccess w;
    w.kind = ModelAccess::Kind::ReadbackCopy;
    w.object = object;
    w.cells = {0, 1, 0, 1};
    w.performs = accessScope(VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    w.writes = true;
    w.frame = f;
    w.site = stepSite(f, step, "usage " + std::to_string(usage) + " (its copy into host memory)");
    QueuePlace place = q;
    place.stages = accessScopeStages(VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT);
    addAccess(std::move(w), {PlaceSpec::Kind::Queue, place, 0, {}});
    hostCopies_.push_back(object);
}

}  // namespace skygraph::verifier
