// Which passes run: feature conditions first, then culling of passes whose output nobody
// reads. Also the "read with no source" check, which the loader and the compiler share.
#pragma once

#include "graph_index.hpp"

#include <skygraph/condition.hpp>
#include <skygraph/diagnostics.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

#include <optional>
#include <vector>

namespace skygraph {

struct Schedule {
    std::vector<uint32_t> passes;     ///< Indices into GraphDesc::passes, in execution order.
    std::vector<CulledPass> culled;   ///< In file order.
    /// Of the scheduled passes, exactly: the synchronizer sizes its per-access arrays from it.
    size_t usages = 0;
};

/// Adds a diagnostic for every read of a subresource that no earlier active pass wrote and
/// that is neither `clear` nor `external`. `features` only words the message (which writer a
/// feature switched off); which passes are active comes from `index`.
void checkReadsHaveSources(const GraphIndex& index, const std::optional<FeatureValues>& features,
                           Diagnostics& out);
/// The same for the loader: every pass active, at a default output size. For a loaded graph
/// only: every usage must name one of its resources (compile() checks a GraphDesc built in
/// code first; see GraphIndex::invalidUses).
void checkReadsHaveSources(const GraphDesc& graph, const std::optional<FeatureValues>& features,
                           Diagnostics& out, uint32_t outputWidth = 1920,
                           uint32_t outputHeight = 1080);

/// Applies conditions (the index's active passes) and (when `cull`) removes passes that
/// contribute nothing to an exported resource, giving a reason for each removed pass.
[[nodiscard]] Schedule schedulePasses(const GraphIndex& index, const FeatureValues& features, bool cull);

}  // namespace skygraph
