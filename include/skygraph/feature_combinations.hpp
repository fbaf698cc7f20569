// Which feature values to check a graph under: every combination, or a pairwise covering set
// for graphs with too many features to try them all. Device-free.
#pragma once

#include <skygraph/condition.hpp>
#include <skygraph/graph.hpp>

#include <cstddef>
#include <vector>

namespace skygraph {

/// Every combination of `graph`'s features (2^n of them; one, the empty set, without
/// features), in binary counting order over the declared features, the first declared being
/// the most significant. Throws std::length_error naming the graph for more than 16 features.
[[nodiscard]] std::vector<FeatureValues> allFeatureCombinations(const GraphDesc& graph);

/// A set of combinations in which every pair of features takes each of its four value pairs
/// at least once (and, with one feature, each value), starting from the graph's defaults.
/// The fewest combinations any such set has, which grow with log n, not 2^n: 12 features
/// need 7, 30,000 need 19. Deterministic for a graph.
[[nodiscard]] std::vector<FeatureValues> pairwiseFeatureCombinations(const GraphDesc& graph);

}  // namespace skygraph
