// What the command line says of a plan's presented images: `check` fails a combination that
// presents nothing, `compile` warns of it. Device-free, so that `compile` has it in a build
// without the executor.
#pragma once

#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

#include <string>

namespace skygraph::app {

/// For a graph that declares presented images, a plan that presents none of them: why (no pass
/// of this combination uses one), naming them. Empty otherwise, and for a graph without any
/// (a bake), whose outputs are exported images.
[[nodiscard]] std::string presentsNothing(const Plan& plan, const GraphDesc& graph);

}  // namespace skygraph::app
