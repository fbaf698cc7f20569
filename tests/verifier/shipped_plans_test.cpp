// Every shipped graph under every combination of its features verifies with no findings:
// aliasing on, at the default output size and a small one, presenting and headless (the
// Present target read back), with and without clobbered transients, best-fit and first-use
// placement, and under both layouts policies (runs of reads in one layout, or each reader in
// its optimal one with transitions between).
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
                    for (const LayoutPolicy layouts : {LayoutPolicy::FewestBarriers, LayoutPolicy::Optimal}) {
                        CompileOptions co;
                        co.features = features;
                        co.layouts = layouts;
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
                                                 << (headlessRun ? " headless" : "") << ", layouts "
                                                 << toString(layouts) << "\n"
                                                 << test::describe(report.findings);
                        ++plans;
                    }
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

/// Under LayoutPolicy::Optimal the deferred frame's TAA result is copied (TRANSFER_SRC_OPTIMAL)
/// and then sampled (SHADER_READ_ONLY_OPTIMAL): the transition between the two reads is a
/// write the loop above checks like any other. Without the copy in its source scope, it would
/// rewrite the image under the copy's read, and without the sampler in its destination the
/// sampler could read before the transition: the verifier reports both.
TEST(ShippedPlans, OptimalLayoutTransitionsBetweenReadsAreChecked) {
    CompileOptions co;
    co.layouts = LayoutPolicy::Optimal;
    co.features = {{"bloom", false}};
    const test::Compiled c = test::compileShipped("deferred.json", co);
    ASSERT_TRUE(verifyPlan(c.plan, c.graph).ok());
    const size_t step = test::stepIndex(c.plan, "luminance_histogram");
    const size_t at = test::barrierOn(c.plan, step, "taa_resolved");
    const Barrier& transition = c.plan.passes()[step].barriers[at];
    ASSERT_EQ(transition.oldLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    ASSERT_EQ(transition.newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    ASSERT_EQ(transition.srcStages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);

    Plan noWait = c.plan;
    detail::PlanEditor::barriersOf(noWait, step)[at].srcStages = VK_PIPELINE_STAGE_2_NONE;
    const VerificationReport unordered = verifyPlan(noWait, c.graph);
    EXPECT_GT(unordered.count(FindingKind::Unordered), 0u) << unordered.summary();

    Plan notToTheSampler = c.plan;
    detail::PlanEditor::barriersOf(notToTheSampler, step)[at].dstStages = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
    EXPECT_FALSE(verifyPlan(notToTheSampler, c.graph).ok()) << "the compute sampler is outside the destination";
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
