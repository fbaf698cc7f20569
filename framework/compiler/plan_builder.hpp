// The compiler's access to a Plan's storage (see include/skygraph/plan.hpp): the synchronizer
// fills the usage and barrier arrays and the slot table, then points each pass into them.
#pragma once

#include <skygraph/plan.hpp>

#include <memory>
#include <string>
#include <vector>

namespace skygraph::detail {

struct PlanBuilder {
    static std::vector<PlannedUsage>& usages(Plan& p) noexcept { return p.usages_; }
    static std::vector<Barrier>& barriers(Plan& p) noexcept { return p.barriers_; }
    static void setSlotNames(Plan& p, std::shared_ptr<const std::string> names) noexcept {
        p.slotNames_ = std::move(names);
    }
};

}  // namespace skygraph::detail
