// ReadRuns' joining under LayoutPolicy::Optimal, in a file of its own: read_runs.hpp says why.
#include "read_runs.hpp"

namespace skygraph::sync {

void ReadRuns::visitOptimal(uint32_t k, size_t firstCell, const SubresourceGrid& grid, const SubresourceRange& range,
                            bool read) {
    grid.forEach(range, [&](size_t sub) {
        uint32_t& open = open_[firstCell + sub];
        if (read && open != kNoRun && haveOptimalCommonLayout(open, k)) unite(open, k);
        open = read ? k : kNoRun;  // a write ends the run, and so does a read in another layout
    });
}

}  // namespace skygraph::sync
