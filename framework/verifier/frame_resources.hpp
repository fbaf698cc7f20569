// The plan's resources as the verifier sees them: their shapes from the graph, whether they
// come from or go to the world outside the frame, and their places in the per-frame heaps.
// Whatever does not fit (a decl past the graph's resources, a placement outside its heap) is
// reported here and left out.
#pragma once

#include "memory_map.hpp"
#include "report.hpp"

#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

#include <optional>
#include <string>
#include <vector>

namespace skygraph::verifier {

struct ResourceShape {
    bool valid = false;  ///< Its decl names a graph resource: the rest of this is meaningful.
    bool image = false;
    bool shared = false;     ///< One copy across frames (SharedExported, SharedReadOnly).
    bool external = false;   ///< Comes from outside the frame.
    bool exported = false;   ///< Goes to the world outside the frame (final state, read-back, export).
    bool presented = false;  ///< A Presentation's image: the presentation engine is its outside.
    ExternalState initialState = ExternalState::None, finalState = ExternalState::None;
    uint32_t mips = 1, layers = 1;  ///< Resolved at the plan's output size.
    std::optional<uint32_t> heap;   ///< Its placement's heap, when it has a valid one.
    ByteRange bytes;                ///< Its placement's bytes.
};

/// One ResourceShape per Plan::resources() entry.
[[nodiscard]] std::vector<ResourceShape> describeResources(const Plan& plan, const GraphDesc& graph,
                                                           Reporter& reporter);

/// "mips[0+1] layers[2+3]".
[[nodiscard]] std::string rangeText(const SubresourceRange& r);
/// Whether `r` is a non-empty range inside a resource of `mips` x `layers`.
[[nodiscard]] bool rangeInside(const SubresourceRange& r, uint32_t mips, uint32_t layers);

}  // namespace skygraph::verifier
