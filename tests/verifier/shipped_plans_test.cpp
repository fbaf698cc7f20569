// Every shipped graph under every combination of its features verifies with no findings:
// aliasing on, at the default output size and a small one, presenting and headless (the
// Present target read back), with and without clobbered transients, best-fit and first-use
// placement.
#include "plan_editor.hpp"
#include "verifier_test_util.hpp"

#include <gtest/gtest.h>

namespace skygraph::verifier {
namespace {

using test::registry;

struct Size {
    uint32_t width, height;
};

TEST(ShippedPlans, VerifyUnderEveryFeatureCombination) {
    size_t plans = 0;
    for (const auto& path : test::shippedGraphs()) {
        const GraphDesc graph = loadGraphFile(path, registry());
        for (const FeatureValues& features : test::featureCombinations(graph)) {
            for (const Size size : {Size{1920, 1080}, Size{64, 48}}) {
                for (const bool headlessRun : {false, true}) {
                    CompileOptions co;
                    co.features = features;
                    co.outputWidth = size.width;
                    co.outputHeight = size.height;
                    co.clobberTransients = headlessRun;
                    co.placement = headlessRun ? MemoryStrategy::FirstUseOrder : MemoryStrategy::BestFitBySize;
                    if (headlessRun) co = test::headless(graph, co);
                    const Plan plan = compile(graph, co);
                    const VerificationReport report = verifyPlan(plan, graph);
                    std::string name = path.filename().string();
                    for (const auto& [f, on] : features) name += " " + f + (on ? "=on" : "=off");
                    EXPECT_TRUE(report.ok()) << name << " at " << size.width << "x" << size.height
                                             << (headlessRun ? " headless" : "") << "\n"
                                             << test::describe(report.findings);
                    ++plans;
                }
            }
        }
    }
    EXPECT_GT(plans, 100u);
}

/// The loop above runs with the default, frames in flight sharing the heaps; here each frame
/// has heaps of its own, so first uses wait for nothing of the previous frame. And the shared
/// check can fail: without what it waits for of the previous frame, a first barrier lets the
/// next frame's shadow map overwrite memory the last frame's post-processing may still use.
TEST(ShippedPlans, HeapsPerFrameVerifyAndSharedOnesCanFail) {
    for (const std::filesystem::path& path : test::shippedGraphs()) {
        const GraphDesc graph = loadGraphFile(path, registry());
        for (const FeatureValues& features : test::featureCombinations(graph)) {
            CompileOptions co;
            co.features = features;
            co.shareTransientsAcrossFrames = false;
            const Plan plan = compile(graph, co);
            for (const MemoryPlacement& p : plan.memory().placements) EXPECT_TRUE(p.previousFrameAliases.empty());
            const VerificationReport report = verifyPlan(plan, graph);
            EXPECT_TRUE(report.ok()) << path.filename() << " with heaps per frame\n" << report.summary();
        }
    }
    CompileOptions sharing;
    sharing.shareTransientsAcrossFrames = true;
    test::Compiled c = test::compileShipped("deferred.json", sharing);
    const uint32_t shadow = static_cast<uint32_t>(c.plan.resourceIndex("shadow_map"));
    ASSERT_FALSE(c.plan.memory().placements[c.plan.resources()[shadow].placement].previousFrameAliases.empty());
    size_t edited = 0;
    for (Barrier& b : detail::PlanEditor::barriersOf(c.plan, 0))
        if (b.resource == shadow && b.aliasing) {
            b.srcStages = 0;
            b.srcAccess = 0;
            ++edited;
        }
    ASSERT_EQ(edited, 1u);
    EXPECT_FALSE(verifyPlan(c.plan, c.graph).ok());
}

/// The verifier sees the aliasing it is there for: the deferred frame shares memory.
TEST(ShippedPlans, DeferredFrameAliases) {
    const GraphDesc graph =
        loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs/deferred.json", registry());
    const Plan plan = compile(graph);
    size_t aliased = 0;
    for (const MemoryPlacement& p : plan.memory().placements) aliased += !p.aliases.empty();
    EXPECT_GT(aliased, 3u);
    const VerificationReport report = verifyPlan(plan, graph);
    EXPECT_TRUE(report.ok()) << report.summary();
    EXPECT_GT(report.pairsChecked, 100u);
}

}  // namespace
}  // namespace skygraph::verifier
