#include <skygraph/feature_combinations.hpp>

#include <algorithm>
#include <array>
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

std::vector<FeatureValues> pairwiseFeatureCombinations(const GraphDesc& graph) {
    const size_t n = graph.features.size();
    if (n == 0) return {FeatureValues{}};
    // uncovered[i][j][a*2+b]: features i < j have not yet been seen with values a and b.
    std::vector<std::vector<std::array<bool, 4>>> uncovered(n, std::vector<std::array<bool, 4>>(n, {true, true, true, true}));
    size_t left = n * (n - 1) / 2 * 4;
    std::vector<std::vector<bool>> rows;
    const auto cover = [&](const std::vector<bool>& row) {
        for (size_t i = 0; i < n; ++i)
            for (size_t j = i + 1; j < n; ++j) {
                bool& u = uncovered[i][j][size_t(row[i]) * 2 + row[j]];
                if (u) --left;
                u = false;
            }
        rows.push_back(row);
    };
    std::vector<bool> defaults(n);
    for (size_t i = 0; i < n; ++i) defaults[i] = graph.features[i].defaultValue;
    cover(defaults);
    std::vector<bool> inverted(n);
    for (size_t i = 0; i < n; ++i) inverted[i] = !defaults[i];
    cover(inverted);  // with one feature, both values; with more, a start on every pair
    while (left > 0) {
        // Greedy, feature by feature: seed the row with the first uncovered pair, then give each
        // other feature the value that covers more pairs with those already chosen.
        std::vector<bool> row(n);
        std::vector<bool> chosen(n, false);
        const auto seed = [&] {
            for (size_t i = 0; i < n; ++i)
                for (size_t j = i + 1; j < n; ++j)
                    for (size_t v = 0; v < 4; ++v)
                        if (uncovered[i][j][v]) {
                            row[i] = (v >> 1) != 0;
                            row[j] = (v & 1u) != 0;
                            chosen[i] = chosen[j] = true;
                            return;
                        }
        };
        seed();
        for (size_t k = 0; k < n; ++k) {
            if (chosen[k]) continue;
            size_t gain[2] = {0, 0};
            for (size_t value = 0; value < 2; ++value)
                for (size_t o = 0; o < n; ++o) {
                    if (!chosen[o]) continue;
                    const size_t i = std::min(k, o), j = std::max(k, o);
                    const bool a = i == k ? bool(value) : row[i], b = j == k ? bool(value) : row[j];
                    gain[value] += uncovered[i][j][size_t(a) * 2 + b];
                }
            row[k] = gain[1] > gain[0];
            chosen[k] = true;
        }
        cover(row);
    }
    std::vector<FeatureValues> out;
    for (const std::vector<bool>& row : rows) {
        FeatureValues values = toValues(graph, row);
        bool duplicate = false;
        for (const FeatureValues& o : out) duplicate |= o == values;
        if (!duplicate) out.push_back(std::move(values));
    }
    return out;
}

}  // namespace skygraph
