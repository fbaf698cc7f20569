#include "queue_schedule.hpp"

#include "plan_builder.hpp"
#include "queue_scopes.hpp"

#include <algorithm>
#include <iterator>
#include <span>
#include <utility>

namespace skygraph {
namespace {

size_t slot(QueueKind q) { return static_cast<size_t>(q); }
QueueKind kindAt(size_t i) { return static_cast<QueueKind>(i); }
constexpr size_t kGraphics = static_cast<size_t>(QueueKind::Graphics);

class SubmitWriter {
public:
    SubmitWriter(QueueSchedule schedule, Plan& plan) : s_(std::move(schedule)), plan_(plan) {
        s_.signals[kGraphics].insert(kFrameStart);
    }

    void run() {
        placeBarriers();
        using Draft = detail::PlanBuilder::SubmitDraft;
        auto& passes = detail::PlanBuilder::passes(plan_);
        std::vector<Draft> drafts;
        Draft start{QueueKind::Graphics, {}, {}, {}, {}};
        start.signals.push_back({QueueKind::Graphics, valueOf(kGraphics, kFrameStart), VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT});
        for (const PendingRelease& r : s_.releases)
            if (r.source == kFrameStart) start.releases.push_back(r.barrier);
        drafts.push_back(std::move(start));
        std::array<int32_t, kQueueKinds> open{-1, -1, -1};  // each queue's open draft
        std::vector<uint8_t> presented(plan_.resources().size(), 0);
        for (const Presentation& p : plan_.presentations()) presented[p.resource] = 1;
        bool acquireSeen = false;
        for (uint32_t i = 0; i < passes.size(); ++i) {
            const QueueKind queue = s_.queues[i];
            const size_t q = slot(queue);
            if (open[q] >= 0 && !s_.waits[i].empty()) open[q] = -1;
            if (open[q] < 0) {
                drafts.push_back({queue, {}, {}, {}, {}});
                open[q] = static_cast<int32_t>(drafts.size() - 1);
            }
            Draft& d = drafts[static_cast<size_t>(open[q])];
            if (d.passes.empty()) d.waits = semaphoreWaits(s_.waits[i]);
            d.passes.push_back(i);
            if (!acquireSeen)
                for (const PlannedUsage& u : passes[i].usages)
                    if (presented[u.resource]) d.waitsForAcquire = acquireSeen = true;
            if (s_.signals[q].count(static_cast<int32_t>(i))) {
                for (const PendingRelease& r : s_.releases)
                    if (r.source == static_cast<int32_t>(i)) d.releases.push_back(r.barrier);
                d.signals.push_back({queue, valueOf(q, static_cast<int32_t>(i)),
                                     simplified(s_.signalStages[i] & queueStages(queue))});
                open[q] = -1;
            }
        }
        drafts.push_back({QueueKind::Graphics, {}, semaphoreWaits(s_.endWaits), {}, {}});
        detail::PlanBuilder::setSubmits(plan_, drafts);
        detail::PlanBuilder::passQueues(plan_) = std::move(s_.queues);
    }

private:
    /// The passes' barriers, end to end in the plan's one array.
    void placeBarriers() {
        auto& passes = detail::PlanBuilder::passes(plan_);
        auto& barriers = detail::PlanBuilder::barriers(plan_);
        barriers.clear();
        size_t total = 0;
        for (const auto& b : s_.barriers) total += b.size();
        barriers.reserve(total);  // the spans below must not move
        for (size_t i = 0; i < passes.size(); ++i) {
            const size_t at = barriers.size();
            const auto& own = s_.barriers[i];
            barriers.insert(barriers.end(), own.begin(), own.end());
            passes[i].barriers = own.empty() ? std::span<const Barrier>{}
                                             : std::span<const Barrier>(barriers.data() + at, own.size());
        }
    }

    /// A queue's timeline counts its signals: the value after pass `source` is its rank.
    uint32_t valueOf(size_t queue, int32_t source) const {
        const auto& s = s_.signals[queue];
        return static_cast<uint32_t>(std::distance(s.begin(), s.find(source))) + 1;
    }

    /// One wait per semaphore: for the latest value needed, at every stage that needs it.
    std::vector<SemaphoreOp> semaphoreWaits(const std::vector<QueueWait>& waits) const {
        std::vector<SemaphoreOp> ops;
        for (const QueueWait& w : waits) {
            const uint32_t v = valueOf(w.queue, w.source);
            auto it = std::find_if(ops.begin(), ops.end(),
                                   [&](const SemaphoreOp& o) { return o.semaphore == kindAt(w.queue); });
            if (it == ops.end()) {
                ops.push_back({kindAt(w.queue), v, w.stages});
            } else {
                it->value = std::max(it->value, v);
                it->stages |= w.stages;
            }
        }
        for (SemaphoreOp& op : ops) op.stages = simplified(op.stages);
        return ops;
    }

    QueueSchedule s_;
    Plan& plan_;
};

}  // namespace

void writeSubmits(QueueSchedule schedule, Plan& plan) { SubmitWriter(std::move(schedule), plan).run(); }

}  // namespace skygraph
