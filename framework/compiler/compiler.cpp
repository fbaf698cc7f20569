#include "scheduler.hpp"
#include "synchronizer.hpp"
#include "validation.hpp"

#include <skygraph/compiler.hpp>

#include <algorithm>

namespace skygraph {

namespace {

/// A copy of `graph` with `outputs` and `exports` applied (checkOutputNames has found them).
GraphDesc withExports(const GraphDesc& graph, const CompileOptions& options) {
    GraphDesc copy = graph;
    if (options.outputs)
        for (ResourceDesc& r : copy.resources)
            if (!options.outputs->count(r.name)) r.final = ExternalState::None;
    for (const auto& [name, state] : options.exports) {
        // A plain reference: clang 14 (the fuzz build) cannot capture structured bindings.
        const std::string& wanted = name;
        auto it = std::find_if(copy.resources.begin(), copy.resources.end(),
                               [&](const ResourceDesc& r) { return r.name == wanted; });
        if (!it->isExported()) it->final = state;
    }
    return copy;
}

}  // namespace

Plan compile(const GraphDesc& graph, const CompileOptions& options) {
    if (!options.exports.empty() || options.outputs) {
        checkOutputNames(graph, options);
        CompileOptions rest = options;
        rest.exports.clear();
        rest.outputs.reset();
        return compile(withExports(graph, options), rest);
    }
    Diagnostics problems;
    FeatureValues features = checkedFeatures(graph, options, problems);
    const GraphIndex index(graph, features, options.outputWidth, options.outputHeight);
    validate(index, features, options, std::move(problems));
    Schedule schedule = schedulePasses(index, features, options.cull);
    Plan plan = synchronize(index, schedule, options);
    plan.features = std::move(features);
    plan.culled = std::move(schedule.culled);
    return plan;
}

}  // namespace skygraph
