// Which feature combinations `skygraph check` tries: all of them, or a pairwise covering set
// whose property is checked exhaustively for every graph size up to 14 features.
#include <skygraph/feature_combinations.hpp>

#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

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

TEST(FeatureCombinations, PairwiseCoversEveryPairOfValuesAndStartsFromTheDefaults) {
    for (size_t n = 1; n <= 14; ++n)
    for (const bool defaultsOn : {true, false}) {
        const GraphDesc g = graphWith(n, defaultsOn);
        const auto rows = pairwiseFeatureCombinations(g);
        EXPECT_EQ(rows, pairwiseFeatureCombinations(g)) << n << ": not deterministic";
        EXPECT_EQ(rows.front(), g.defaultFeatures()) << n;
        std::set<FeatureValues> distinct(rows.begin(), rows.end());
        EXPECT_EQ(distinct.size(), rows.size()) << n;
        for (size_t i = 0; i < n; ++i) {
            std::set<bool> single;
            for (const auto& r : rows) single.insert(r.at(g.features[i].name));
            EXPECT_EQ(single.size(), 2u) << n << " features: f" << i << " takes one value only";
            for (size_t j = i + 1; j < n; ++j) {
                std::set<std::pair<bool, bool>> seen;
                for (const auto& r : rows) seen.insert({r.at(g.features[i].name), r.at(g.features[j].name)});
                EXPECT_EQ(seen.size(), 4u) << n << " features: f" << i << ", f" << j;
            }
        }
        if (n >= 6) {
            EXPECT_LT(rows.size(), size_t(1) << n) << n;
        }
        EXPECT_LE(rows.size(), 14u) << n << " features need " << rows.size() << " combinations";
    }
    EXPECT_EQ(pairwiseFeatureCombinations(graphWith(0)).size(), 1u);
}

}  // namespace
}  // namespace skygraph
