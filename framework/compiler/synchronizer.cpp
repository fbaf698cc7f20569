// Scheduled passes -> barriers, in phases over the plan's accesses (Synchronizer::run): the
// first sweep records every usage and joins read runs (synchronizer_accesses.cpp); a backward
// one gives multi-subresource reads their run scopes; the transients are placed
// (synchronizer_memory.cpp); the barrier sweep settles layouts and attachment ops and writes
// the barriers (synchronizer_barriers.cpp); the frame's boundaries get their final barriers
// and copies (synchronizer_boundaries.cpp). The rules themselves live beside it: one
// subresource's hazards in barrier_rules.hpp, the layout of a run of reads in read_runs.hpp,
// merging of ranges in barrier_merge.hpp.
#include "synchronizer.hpp"

#include "synchronizer_state.hpp"

#include <string>
#include <utility>

namespace skygraph {
namespace sync {

Plan Synchronizer::run(const Schedule& schedule) {
    detail::PlanBuilder::graph(plan_) = graph_.name;
    detail::PlanBuilder::layouts(plan_) = layouts_;
    usages_ = &detail::PlanBuilder::usages(plan_);
    for (const std::string& name : options_.readbacks)  // compile() checked the names
        readbacks_.push_back(static_cast<uint32_t>(graph_.findResource(name) - graph_.resources.data()));
    planAccesses(schedule);
    if (layouts_ == LayoutPolicy::Optimal) joinReadRunsOptimally();
    computeRunScopes();  // while planAccesses' usages are in cache
    planMemory();
    emitSteps();
    finishResources();
    decideCopies();
    return std::move(plan_);
}

}  // namespace sync

Plan synchronize(const GraphIndex& index, const Schedule& schedule, const CompileOptions& options) {
    return sync::Synchronizer(index, options).run(schedule);
}

}  // namespace skygraph
