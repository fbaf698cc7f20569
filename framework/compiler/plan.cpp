// Plan's copies and look-ups. How a plan's storage is laid out, and why: plan_builder.hpp.
#include <skygraph/plan.hpp>

#include <span>
#include <vector>

namespace skygraph {

int32_t Plan::resourceIndex(std::string_view n) const noexcept {
    for (size_t i = 0; i < resources_.size(); ++i)
        if (resources_[i].name == n) return static_cast<int32_t>(i);
    return -1;
}

namespace {
/// `view`, which points into `from`, moved to the same place in `to`.
template <class T, class U>
std::span<T> rebased(std::span<T> view, const std::vector<U>& from, std::vector<U>& to) {
    if (view.empty()) return {};
    return {to.data() + (view.data() - from.data()), view.size()};
}
}  // namespace

Plan::Plan(const Plan& other)
    : graph_(other.graph_), features_(other.features_), outputWidth_(other.outputWidth_),
      outputHeight_(other.outputHeight_), layouts_(other.layouts_), resources_(other.resources_), passes_(other.passes_),
      finalBarriers_(other.finalBarriers_), inPassBarriers_(other.inPassBarriers_), culled_(other.culled_),
      presentations_(other.presentations_), memory_(other.memory_), submits_(other.submits_),
      queueFamilies_(other.queueFamilies_),
      passQueues_(other.passQueues_), concurrent_(other.concurrent_), submitPasses_(other.submitPasses_),
      semaphoreOps_(other.semaphoreOps_), releases_(other.releases_), usages_(other.usages_),
      barriers_(other.barriers_), nameTables_(other.nameTables_) {
    for (PlannedPass& p : passes_) {
        p.usages = rebased(p.usages, other.usages_, usages_);
        p.barriers = rebased(p.barriers, other.barriers_, barriers_);
    }
    for (Submit& s : submits_) {
        s.passes = rebased(s.passes, other.submitPasses_, submitPasses_);
        s.waits = rebased(s.waits, other.semaphoreOps_, semaphoreOps_);
        s.signals = rebased(s.signals, other.semaphoreOps_, semaphoreOps_);
        s.releases = rebased(s.releases, other.releases_, releases_);
    }
}

Plan& Plan::operator=(const Plan& other) {
    if (this != &other) *this = Plan(other);
    return *this;
}

}  // namespace skygraph
