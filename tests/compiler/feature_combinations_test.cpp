// Which feature combinations `skygraph check` tries: all of them, or a pairwise covering set
// whose property is checked exhaustively, and whose size is the least any covering set can have.
#include <skygraph/feature_combinations.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

namespace skygraph {
namespace {

GraphDesc graphWith(size_t features, bool defaultsOn = false) {
    GraphDesc g;
    g.name = "g";
    for (size_t i = 0; i < features; ++i) g.features.push_back({"f" + std::to_string(i), defaultsOn && i % 2 == 0});
    return g;
}

TEST(FeatureCombinations, AllCountsInBinaryWithTheFirstFeatureMostSignificant) {
    const auto all = allFeatureCombinations(graphWith(3));
    ASSERT_EQ(all.size(), 8u);
    EXPECT_EQ(all[1], (FeatureValues{{"f0", false}, {"f1", false}, {"f2", true}}));
    EXPECT_EQ(all[4], (FeatureValues{{"f0", true}, {"f1", false}, {"f2", false}}));
    EXPECT_EQ(allFeatureCombinations(graphWith(0)), std::vector<FeatureValues>{FeatureValues{}});
    EXPECT_THROW((void)allFeatureCombinations(graphWith(17)), std::length_error);
}

/// The fewest combinations in which every pair of n two-valued features takes all four value
/// pairs (Katona; Kleitman and Spencer): the least k with C(k - 1, ceil(k / 2)) >= n, counted
/// here from the table of those binomials rather than by the implementation's formula.
size_t fewestPairwiseRows(size_t n) {
    if (n == 1) return 2;
    // Up to this many features, this many rows: C(3,2), C(4,3), C(5,3), C(6,4), C(7,4), ...
    const std::pair<size_t, size_t> table[] = {{3, 4}, {4, 5}, {10, 6}, {15, 7}, {35, 8}, {56, 9},
                                               {126, 10}, {210, 11}, {462, 12}};
    for (const auto& [most, rows] : table)
        if (n <= most) return rows;
    ADD_FAILURE() << n << " features: past the table";
    return 0;
}

TEST(FeatureCombinations, PairwiseCoversEveryPairOfValuesAndStartsFromTheDefaults) {
    std::vector<size_t> sizes;
    for (size_t n = 1; n <= 16; ++n) sizes.push_back(n);
    for (const size_t n : {35u, 36u, 57u, 300u}) sizes.push_back(n);
    for (const size_t n : sizes)
    for (const bool defaultsOn : {true, false}) {
        const GraphDesc g = graphWith(n, defaultsOn);
        const auto rows = pairwiseFeatureCombinations(g);
        EXPECT_EQ(rows, pairwiseFeatureCombinations(g)) << n << ": not deterministic";
        EXPECT_EQ(rows.front(), g.defaultFeatures()) << n;
        std::set<FeatureValues> distinct(rows.begin(), rows.end());
        EXPECT_EQ(distinct.size(), rows.size()) << n;
        EXPECT_EQ(rows.size(), fewestPairwiseRows(n)) << n << " features";
        // Flat, feature by feature: 300 features have 44,850 pairs.
        std::vector<std::vector<bool>> on(n, std::vector<bool>(rows.size()));
        for (size_t i = 0; i < n; ++i)
            for (size_t r = 0; r < rows.size(); ++r) on[i][r] = rows[r].at(g.features[i].name);
        for (size_t i = 0; i < n; ++i) {
            EXPECT_NE(std::count(on[i].begin(), on[i].end(), true), 0) << n << " features: f" << i << " never on";
            EXPECT_NE(std::count(on[i].begin(), on[i].end(), false), 0) << n << " features: f" << i << " never off";
            for (size_t j = i + 1; j < n; ++j) {
                bool seen[4] = {};
                for (size_t r = 0; r < rows.size(); ++r) seen[on[i][r] * 2 + on[j][r]] = true;
                ASSERT_TRUE(seen[0] && seen[1] && seen[2] && seen[3]) << n << " features: f" << i << ", f" << j;
            }
        }
    }
    EXPECT_EQ(pairwiseFeatureCombinations(graphWith(0)).size(), 1u);
}

/// A graph of thousands of features (the loader sets no limit) gets a few dozen combinations
/// at most, at once: C(18, 10) = 43,758 columns suffice for 30,000 features in 19 rows.
TEST(FeatureCombinations, PairwiseOfThousandsOfFeaturesIsNineteenCombinations) {
    const auto rows = pairwiseFeatureCombinations(graphWith(30000, true));
    EXPECT_EQ(rows.size(), 19u);
    EXPECT_EQ(rows.front(), graphWith(30000, true).defaultFeatures());
}

}  // namespace
}  // namespace skygraph
