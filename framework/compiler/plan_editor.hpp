// Test-only: weakens a plan on purpose, for negative controls (a dropped or narrowed barrier
// that synchronization validation or the plan verifier must catch). Not installed: only test
// targets have framework/compiler on their include path.
#pragma once

#include <skygraph/plan.hpp>

#include <cstddef>
#include <span>
#include <vector>

namespace skygraph::detail {

struct PlanEditor {
    /// Pass `pass`'s barriers, editable in place. Throws std::out_of_range for no such pass.
    [[nodiscard]] static std::span<Barrier> barriersOf(Plan& plan, size_t pass) { return plan.barriersOf(pass); }

    /// Removes barrier `i` of pass `pass`; the other passes' barriers stay as they are.
    /// Throws std::out_of_range for no such pass or barrier.
    static void eraseBarrier(Plan& plan, size_t pass, size_t i) { plan.eraseBarrier(pass, i); }

    /// The barriers after the last pass, editable (they view nothing: erase freely).
    [[nodiscard]] static std::vector<Barrier>& finalBarriers(Plan& plan) noexcept { return plan.finalBarriers; }
};

}  // namespace skygraph::detail
