#include "plan_builder.hpp"
#include "queue_planner.hpp"
#include "scheduler.hpp"
#include "synchronizer.hpp"
#include "validation.hpp"

#include <skygraph/compiler.hpp>

#include <algorithm>

namespace skygraph {

namespace {

/// A copy of `graph` with `outputs`, `exports` and `readbacks` applied (checkOutputNames has
/// found them): a read-back copies the image out after the frame, so it leaves it TransferSrc
/// unless the graph exports it anyway; an external image goes back to its `initial` state,
/// in which the next frame finds it (one arriving as presented is read back only by a plan
/// that replaces Present, and is left in the replacement, as it arrives there).
GraphDesc withExports(const GraphDesc& graph, const CompileOptions& options) {
    GraphDesc copy = graph;
    if (options.outputs)
        for (ResourceDesc& r : copy.resources)
            if (!options.outputs->count(r.name)) r.final = ExternalState::None;
    auto resource = [&](const std::string& name) {
        return std::find_if(copy.resources.begin(), copy.resources.end(),
                            [&](const ResourceDesc& r) { return r.name == name; });
    };
    for (const auto& [name, state] : options.exports) {
        auto it = resource(name);
        if (!it->isExported()) it->final = state;
    }
    for (const std::string& name : options.readbacks) {
        auto it = resource(name);
        if (it->isExported()) continue;
        if (!it->external) it->final = ExternalState::TransferSrc;
        else it->final = it->initial == ExternalState::Present ? options.presentReplacement : it->initial;
    }
    return copy;
}

/// compile() once the options' exports, outputs and read-backs are in the graph.
Plan compileExported(const GraphDesc& graph, const CompileOptions& options) {
    Diagnostics problems;
    FeatureValues features = checkedFeatures(graph, options, problems);
    const GraphIndex index(graph, features, options.outputWidth, options.outputHeight, options.presentReplacement);
    validate(index, features, options, std::move(problems));
    Schedule schedule = schedulePasses(index, features, options.cull);
    checkReadbacksHaveSources(index, schedule, options);
    Plan plan = synchronize(index, schedule, options);
    planQueues(index, options, plan);
    detail::PlanBuilder::features(plan) = std::move(features);
    detail::PlanBuilder::setOutputExtent(plan, options.outputWidth, options.outputHeight);
    detail::PlanBuilder::culled(plan) = std::move(schedule.culled);
    return plan;
}

}  // namespace

Plan compile(const GraphDesc& graph, const CompileOptions& options) {
    if (options.exports.empty() && !options.outputs && options.readbacks.empty() &&
        options.presentReplacement != ExternalState::None)
        return compileExported(graph, options);
    checkOutputNames(graph, options);
    CompileOptions rest = options;
    rest.exports.clear();
    rest.outputs.reset();
    // Kept: the synchronizer inserts the read-back steps; they are exported now.
    rest.readbacks = options.readbacks;
    return compileExported(withExports(graph, options), rest);
}

}  // namespace skygraph
