// Which passes run: feature conditions first, then culling of passes whose output nobody
// reads.
#pragma once

#include "graph_index.hpp"

#include <skygraph/condition.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

#include <string>
#include <vector>

namespace skygraph {

struct Schedule {
    std::vector<uint32_t> passes;     ///< Indices into GraphDesc::passes, in execution order.
    std::vector<CulledPass> culled;   ///< In file order.
    /// Of the scheduled passes, exactly: the synchronizer sizes its per-access arrays from it.
    size_t usages = 0;
};

/// Why a pass whose `if` is `c` is off under `features`: "feature 'sky' is off" or
/// "condition 'a && !b' is false (a=on, b=on)".
[[nodiscard]] std::string conditionReason(const Condition& c, const FeatureValues& features);

/// Applies conditions (the index's active passes) and (when `cull`) removes passes that
/// contribute nothing to an exported resource, giving a reason for each removed pass.
[[nodiscard]] Schedule schedulePasses(const GraphIndex& index, const FeatureValues& features, bool cull);

}  // namespace skygraph
