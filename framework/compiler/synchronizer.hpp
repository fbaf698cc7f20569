// Scheduled passes -> barriers. Whole-frame state tracking per subresource, in the spirit of
// Granite's render graph, with the Vulkan memory model's rules spelled out in docs/barriers.md.
#pragma once

#include "scheduler.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/plan.hpp>

namespace skygraph {

/// Builds the plan's passes (inserting Clear passes where a `clear` resource is first used
/// outside an attachment), their usages with load/store ops, every barrier batch, the final
/// barriers and the resource lifetimes. `index` is the graph's, at the options' output size.
[[nodiscard]] Plan synchronize(const GraphIndex& index, const Schedule& schedule,
                               const CompileOptions& options);

}  // namespace skygraph
