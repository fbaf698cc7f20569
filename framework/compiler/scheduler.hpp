// Which passes run: feature conditions first, then culling of passes whose output nobody
// reads. Also the "read with no source" check, which the loader and the compiler share.
#pragma once

#include "subresources.hpp"

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
    size_t usages = 0;                ///< Of the scheduled passes (for reserving).
};

/// Passes whose `if` is true under `features`; nullopt features means every pass.
[[nodiscard]] std::vector<bool> activePasses(const GraphDesc& graph,
                                             const std::optional<FeatureValues>& features);

/// Adds a diagnostic for every read of a subresource that no earlier active pass wrote and
/// that is neither `clear` nor `external`.
void checkReadsHaveSources(const GraphDesc& graph, const std::optional<FeatureValues>& features,
                           Diagnostics& out, uint32_t outputWidth = 1920,
                           uint32_t outputHeight = 1080);
/// The same, for a caller that already has `activePasses(graph, features)` and the graph's
/// grids (compile() shares them between every sweep).
void checkReadsHaveSources(const GraphDesc& graph, const std::optional<FeatureValues>& features,
                           const std::vector<bool>& active, const SubresourceGrids& grids,
                           Diagnostics& out);

/// Applies conditions (`active`, from activePasses) and (when `cull`) removes passes that
/// contribute nothing to an exported resource, giving a reason for each removed pass.
[[nodiscard]] Schedule schedulePasses(const GraphDesc& graph, const FeatureValues& features,
                                      const std::vector<bool>& active,
                                      const SubresourceGrids& grids, bool cull);

}  // namespace skygraph
