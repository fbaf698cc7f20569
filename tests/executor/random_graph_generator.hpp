// Seeded random Generic graphs that are valid by construction, for the random-graph suite
// (random_graph_test.cpp), tools/random-graphs.sh and the barrier-minimality oracle.
#pragma once

#include <skygraph/condition.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace skygraph::test {

/// What the generator may produce; the defaults cover the whole vocabulary.
struct RandomGraphShape {
    uint32_t minPasses = 2;
    uint32_t maxPasses = 8;
    uint32_t maxResources = 6;
    uint32_t maxUsagesPerPass = 3;
    /// The output size the renderer will use: attachment extents are matched against it.
    uint32_t outputSize = 16;
    /// Chains of short-lived transients without `clear` after the random passes, which the
    /// present pass depends on instead of an image of theirs: the first link reads nothing,
    /// each link writes the next transient whole (an attachment or a storage image) from the
    /// one before, and the present pass reads the last. The transients of the chains share
    /// memory with each other and with the other passes' transients, and are clobbered when
    /// clobbering is on, while the read-back depends on them alone: the random passes' own
    /// results need not be deterministic (a Generic pass may read, clamped, texels another
    /// invocation of it writes). Such a graph is valid in generation order only.
    uint32_t chains = 0;
    /// Chains may have buffer links too, so that buffers take over images' memory and images
    /// buffers'. Off by default: Khronos validation 1.3.239 tracks buffers and optimal images
    /// in separate address spaces, so a barrier on one does not reach the other's accesses
    /// there, and it reports hazards that a chain through a buffer orders.
    bool chainBuffers = false;
};

/// One generated graph. Every resource is cleared or external, so a read always has a
/// source and any order of `passes` is a valid frame: `json(order)` writes them reordered.
struct RandomGraph {
    uint32_t seed = 0;
    std::string resources;            ///< The "resources" object's members, JSON.
    std::vector<std::string> passes;  ///< One JSON object per pass, generation order.
    std::string present;              ///< The last pass: writes the exported swapchain.
    /// Feature overrides to compile with (the file's defaults are random too).
    FeatureValues features;

    /// The graph file with the passes in generation order.
    [[nodiscard]] std::string json() const;
    /// The graph file with passes[order[i]] at position i (`order` is a permutation; for a
    /// graph with chains, only the generation order is valid).
    [[nodiscard]] std::string json(const std::vector<size_t>& order) const;
    /// A seeded permutation of the passes, for the reordering check.
    [[nodiscard]] std::vector<size_t> shuffledOrder(uint32_t salt) const;
};

/// `graph` with each of its passes (not the present pass) put on a random queue that can run
/// it (docs/queues.md): compute for passes of compute, indirect and copy usages, transfer for
/// copies alone (of images without depth or stencil), else graphics; half of those that could
/// leave the graphics queue do. Seeded by the graph's seed and `salt`.
[[nodiscard]] RandomGraph withRandomQueues(const RandomGraph& graph, uint32_t salt = 0);

/// The graph for `seed`: resources of every type (image2d color and depth/stencil, cube,
/// image2d_array, buffer) with mips and layers, usages drawn from every stage, access and
/// binding that the resource allows, on random subresource ranges; passes behind random
/// feature conditions, some culled, some never_cull.
[[nodiscard]] RandomGraph generateRandomGraph(uint32_t seed, const RandomGraphShape& shape = {});

}  // namespace skygraph::test
