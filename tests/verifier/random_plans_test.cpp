// Random Generic graphs (tests/executor/random_graph_generator.hpp) compile to plans that
// verify with no findings. tools/verify-random-plans.sh
// runs the same for many more seeds.
#include "verifier_test_util.hpp"

#include <gtest/gtest.h>

namespace skygraph::verifier {
namespace {

TEST(RandomPlans, ThreeHundredSeedsVerify) {
    test::RandomResult result;
    for (uint32_t seed = 1; seed <= 300; ++seed) test::verifyRandomGraph(seed, result);
    EXPECT_GE(result.plans, 900u);
    EXPECT_GT(result.aliasingPlans, 300u);  // the suite exercises memory aliasing
    for (const test::RandomFailure& f : result.failures)
        ADD_FAILURE() << "seed " << f.seed << " (" << f.variant << "): " << f.detail << "\n" << f.json;
}

}  // namespace
}  // namespace skygraph::verifier
