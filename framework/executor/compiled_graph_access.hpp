// Test-only: hands the executor a plan that a test weakened on purpose (a dropped or narrowed
// barrier that synchronization validation must catch). Not part of the embedding API, which
// runs only what CompiledGraph compiles.
#pragma once

#include <skygraph/compiled_graph.hpp>

#include <utility>

namespace skygraph::detail {

struct CompiledGraphAccess {
    /// `compiled` running `edited` instead of its own plan. `edited` must be a copy of
    /// compiled.plan() changed in place (detail::PlanEditor), so that it describes the
    /// same graph. A resize() compiles the graph again and drops the edit, and so does a
    /// Renderer given `compiled` compiled with another memory model than its device's
    /// (CompileOptions::memory): compile with Device::memoryModel() before editing.
    [[nodiscard]] static CompiledGraph withPlan(CompiledGraph compiled, Plan edited) {
        compiled.plan_ = std::move(edited);
        return compiled;
    }
};

}  // namespace skygraph::detail
