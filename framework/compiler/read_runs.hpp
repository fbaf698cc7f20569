// Rule 4 of docs/barriers.md: the layout that a run of reads shares. Internal to the
// synchronizer (synchronizer_accesses.cpp), which adds every access of the plan in order.
#pragma once

#include "subresources.hpp"
#include "vulkan_state.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace skygraph::sync {

/// Rule 4: reads of overlapping subresources of an image with no write between form a run,
/// and the run gets one layout that serves all its readers. Accesses join runs as they are
/// added in plan order (union-find over access indices, so runs never span resources), each
/// read bringing its own layout; when two runs join, so do their layouts. commonReadLayout
/// is commutative and associative, so the order of joining does not matter: once every
/// access is in, a read's run layout is final.
///
/// Under LayoutPolicy::Optimal a read joins the open run of a subresource only when one
/// layout is optimal for both (optimalCommonReadLayout); otherwise it opens a run of its own
/// there, and the synchronizer transitions the subresource between the two. Every run's
/// layout is then optimal for each of its readers, and which runs join depends on plan order
/// only, which is fixed.
class ReadRuns {
public:
    /// Room for `accesses` accesses (no more may be added: add() does not check) over
    /// `subresources` subresources.
    void allocate(size_t accesses, size_t subresources) {
        nodes_ = std::make_unique_for_overwrite<Node[]>(accesses);
        open_.assign(subresources, kNoRun);
    }
    /// Adds access k, the next (`own`: the layout of an image read, UNDEFINED otherwise). An
    /// image's access then visits each subresource it touches (`sub`: flat index), with
    /// visit() under LayoutPolicy::FewestBarriers and visitOptimal() under Optimal: the same
    /// for every access of a plan. (Two functions rather than a test of the policy per read,
    /// which costs FewestBarriers half a percent of a compile.)
    void add(uint32_t k, VkImageLayout own) { nodes_[k] = {k, own}; }
    [[gnu::always_inline]] void visit(uint32_t k, size_t sub, bool read) {
        uint32_t& open = open_[sub];
        if (read && open != kNoRun) unite(open, k);
        open = read ? k : kNoRun;  // a write ends the run
    }
    /// visitOptimal() of every subresource of `range` of a resource whose grid is `grid` and
    /// whose subresources start at flat index `firstCell`. Out of line (read_runs.cpp): inlined
    /// beside visit(), it changes how the compiler builds FewestBarriers' sweep, at a cost of
    /// half a percent of a compile.
    void visitOptimal(uint32_t k, size_t firstCell, const SubresourceGrid& grid, const SubresourceRange& range,
                      bool read);
    /// The layout of read k's run, once every access is added.
    VkImageLayout layout(uint32_t k) { return nodes_[find(k)].layout; }

private:
    uint32_t find(uint32_t a) {
        while (nodes_[a].parent != a) a = nodes_[a].parent = nodes_[nodes_[a].parent].parent;
        return a;
    }
    [[gnu::always_inline]] void unite(uint32_t a, uint32_t b) {
        const uint32_t from = find(a), to = find(b);
        if (from == to) return;
        nodes_[from].parent = to;
        const VkImageLayout joined = nodes_[from].layout;
        VkImageLayout& l = nodes_[to].layout;
        if (l == joined) return;  // most runs: readers that agree (commonReadLayout is out of line)
        // Only image reads join runs, and each brings a read layout (the loader rejects image
        // usages without one), so UNDEFINED is never met here; it is kept as the identity so
        // that a hand-built graph cannot make the result depend on the order of joining.
        l = l == VK_IMAGE_LAYOUT_UNDEFINED ? joined
            : joined == VK_IMAGE_LAYOUT_UNDEFINED ? l
                                                  : commonReadLayout(l, joined);
    }

    /// Whether the runs of accesses a and b have a layout optimal for the readers of both.
    bool haveOptimalCommonLayout(uint32_t a, uint32_t b) {
        const VkImageLayout la = nodes_[find(a)].layout, lb = nodes_[find(b)].layout;
        return la == VK_IMAGE_LAYOUT_UNDEFINED || lb == VK_IMAGE_LAYOUT_UNDEFINED ||
               optimalCommonReadLayout(la, lb) != VK_IMAGE_LAYOUT_UNDEFINED;
    }

    struct Node {
        uint32_t parent;
        VkImageLayout layout;  // meaningful at run roots
    };
    static constexpr uint32_t kNoRun = ~0u;
    std::unique_ptr<Node[]> nodes_;      // per access
    std::vector<uint32_t> open_;         // per subresource: the latest read of its open run
};

}  // namespace skygraph::sync
