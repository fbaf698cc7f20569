#include <skygraph/feature_combinations.hpp>

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace skygraph {
namespace {

FeatureValues toValues(const GraphDesc& graph, const std::vector<bool>& on) {
    FeatureValues values;
    for (size_t i = 0; i < graph.features.size(); ++i) values[graph.features[i].name] = on[i];
    return values;
}

}  // namespace

std::vector<FeatureValues> allFeatureCombinations(const GraphDesc& graph) {
    const size_t n = graph.features.size();
    if (n > 16)
        throw std::length_error("graph '" + graph.name + "' has " + std::to_string(n) +
                                " features: all 2^" + std::to_string(n) + " combinations are too many; check pairwise");
    std::vector<FeatureValues> out;
    for (size_t mask = 0; mask < (size_t(1) << n); ++mask) {
        std::vector<bool> on(n);
        for (size_t i = 0; i < n; ++i) on[i] = (mask >> (n - 1 - i) & 1u) != 0;
        out.push_back(toValues(graph, on));
    }
    return out;
}

/// Kleitman and Spencer's construction of the smallest binary covering array of strength 2:
/// with k rows, give each feature a distinct column that is 0 in the first row and has
/// exactly ceil(k/2) ones in the other k - 1. Row 0 gives every pair (0, 0); two distinct sets
/// of ones of one size each have a row the other lacks, which gives (1, 0) and (0, 1); and two
/// sets of ceil(k/2) among k - 1 rows must share one, which gives (1, 1). The least k with
/// C(k - 1, ceil(k/2)) columns to give is the fewest rows any covering set has. Each feature's
/// column is read relative to its default, which keeps every pair's four values and makes row
/// 0 the defaults.
std::vector<FeatureValues> pairwiseFeatureCombinations(const GraphDesc& graph) {
    const size_t n = graph.features.size();
    if (n == 0) return {FeatureValues{}};
    const auto choose = [](uint64_t from, uint64_t pick) {
        uint64_t c = 1;  // exact: each step's product is divisible by i
        for (uint64_t i = 1; i <= pick; ++i) c = c * (from - pick + i) / i;
        return c;
    };
    uint64_t rows = 2;
    while (choose(rows - 1, (rows + 1) / 2) < n) ++rows;
    const uint64_t ones = (rows + 1) / 2;
    // Columns in increasing numeric order of their bits (bit r - 1 for row r): deterministic.
    std::vector<uint64_t> columns;
    columns.reserve(n);
    for (uint64_t column = (uint64_t(1) << ones) - 1; columns.size() < n;) {
        columns.push_back(column);
        const uint64_t lowest = column & -column, ripple = column + lowest;  // Gosper's next subset
        column = ripple | (((column ^ ripple) >> 2) / lowest);
    }
    std::vector<FeatureValues> out;
    for (uint64_t r = 0; r < rows; ++r) {
        std::vector<bool> on(n);
        for (size_t i = 0; i < n; ++i)
            on[i] = graph.features[i].defaultValue != (r > 0 && (columns[i] >> (r - 1) & 1u) != 0);
        FeatureValues values = toValues(graph, on);
        if (std::find(out.begin(), out.end(), values) == out.end()) out.push_back(std::move(values));
    }
    return out;
}

}  // namespace skygraph
