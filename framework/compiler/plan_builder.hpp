// The compiler's access to a Plan's storage (see include/skygraph/plan.hpp): the synchronizer
// fills the usage and barrier arrays and hands over the name tables, then points each pass into them.
#pragma once

#include <skygraph/plan.hpp>

#include <memory>
#include <string>
#include <vector>

namespace skygraph::detail {

struct PlanBuilder {
    static std::vector<PlannedUsage>& usages(Plan& p) noexcept { return p.usages_; }
    static std::vector<Barrier>& barriers(Plan& p) noexcept { return p.barriers_; }
    /// Keeps `names` alive as long as the plan (and its copies): the plan's names view it.
    static void keepNames(Plan& p, std::shared_ptr<const std::string> names) {
        p.nameTables_.push_back(std::move(names));
    }
    /// Lets `to` view the names that `from` views.
    static void shareNames(Plan& to, const Plan& from) {
        to.nameTables_.insert(to.nameTables_.end(), from.nameTables_.begin(), from.nameTables_.end());
    }
};

}  // namespace skygraph::detail
