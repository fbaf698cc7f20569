#include "scheduler.hpp"
#include "synchronizer.hpp"

#include <skygraph/compiler.hpp>

namespace skygraph {

Plan compile(const GraphDesc& graph, const CompileOptions& options) {
    Diagnostics diags;
    FeatureValues features = graph.defaultFeatures();
    for (const auto& [name, value] : options.features) {
        if (!features.count(name)) {
            std::string known;
            for (const auto& f : graph.features) known += (known.empty() ? "" : ", ") + f.name;
            diags.add({graph.file, "features", "", "",
                       "unknown feature '" + name + "'; the graph declares: " +
                           (known.empty() ? "none" : known)});
            continue;
        }
        features[name] = value;
    }
    if (options.outputWidth == 0 || options.outputHeight == 0)
        diags.add({graph.file, "", "", "", "the output extent must not be zero"});
    if (diags.empty())
        checkReadsHaveSources(graph, features, diags, options.outputWidth, options.outputHeight);
    if (!diags.empty()) throw GraphError(std::move(diags));

    const Schedule schedule =
        schedulePasses(graph, features, options.cull, options.outputWidth, options.outputHeight);
    Plan plan = synchronize(graph, schedule, options);
    plan.features = std::move(features);
    plan.culled = schedule.culled;
    return plan;
}

}  // namespace skygraph
