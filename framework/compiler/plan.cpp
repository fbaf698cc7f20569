// Plan's copies, look-ups and edits (include/skygraph/plan.hpp).
#include <skygraph/plan.hpp>

#include <span>
#include <stdexcept>
#include <vector>

namespace skygraph {

int32_t Plan::resourceIndex(std::string_view n) const noexcept {
    for (size_t i = 0; i < resources.size(); ++i)
        if (resources[i].name == n) return static_cast<int32_t>(i);
    return -1;
}

namespace {
/// `view`, which points into `from`, moved to the same place in `to`.
template <class T, class U>
std::span<T> rebased(std::span<T> view, const std::vector<U>& from, std::vector<U>& to) {
    if (view.empty()) return {};
    return {to.data() + (view.data() - from.data()), view.size()};
}
}  // namespace

Plan::Plan(const Plan& other)
    : graph(other.graph), features(other.features), outputWidth(other.outputWidth),
      outputHeight(other.outputHeight), resources(other.resources), passes(other.passes),
      finalBarriers(other.finalBarriers), inPassBarriers(other.inPassBarriers), culled(other.culled),
      usages_(other.usages_),
      barriers_(other.barriers_), nameTables_(other.nameTables_) {
    for (PlannedPass& p : passes) {
        p.usages = rebased(p.usages, other.usages_, usages_);
        p.barriers = rebased(p.barriers, other.barriers_, barriers_);
    }
}

Plan& Plan::operator=(const Plan& other) {
    if (this != &other) *this = Plan(other);
    return *this;
}

std::span<Barrier> Plan::barriersOf(size_t pass) {
    const std::span<const Barrier> b = passes.at(pass).barriers;
    if (b.empty()) return {};
    return {barriers_.data() + (b.data() - barriers_.data()), b.size()};
}

void Plan::eraseBarrier(size_t pass, size_t i) {
    const std::span<const Barrier> b = passes.at(pass).barriers;
    if (i >= b.size()) throw std::out_of_range("Plan::eraseBarrier: no such barrier");
    const auto at = b.data() - barriers_.data() + static_cast<std::ptrdiff_t>(i);
    barriers_.erase(barriers_.begin() + at);  // no reallocation: earlier views stay put
    passes[pass].barriers = b.size() == 1 ? std::span<const Barrier>{} : std::span<const Barrier>(b.data(), b.size() - 1);
    for (size_t p = pass + 1; p < passes.size(); ++p)
        if (!passes[p].barriers.empty())
            passes[p].barriers = {passes[p].barriers.data() - 1, passes[p].barriers.size()};
}

}  // namespace skygraph
