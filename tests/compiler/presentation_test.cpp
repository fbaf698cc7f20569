// The semaphore stages a presented frame's submit uses. Checked against the Vulkan spec's
// swapchain rules: the acquire semaphore's wait must cover the stage whose barrier moves the
// image out of UNDEFINED (that barrier's first scope chains with the wait's second), and the
// render-complete signal must follow the final transition to PRESENT_SRC_KHR: the barrier's
// destination stages are the signal's, so the two chain.
#include <skygraph/compiler.hpp>

#include <gtest/gtest.h>

#include <string>

namespace skygraph {
namespace {

GraphDesc presented(const std::string& usage) {
    static const PassRegistry registry = PassRegistry::withBuiltins();
    return parseGraph(R"({"version": 1, "name": "p", "resources": {
        "target": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output", "external": true, "final": "Present"}},
      "passes": [{"name": "draw", "type": "Generic", "uses": {"target": ")" + usage + R"("}}]})",
                      "present.json", registry);
}

CompileOptions at16() {
    CompileOptions o;
    o.outputWidth = 16;
    o.outputHeight = 16;
    return o;
}

TEST(Presentation, WaitsOnTheAcquireWhereTheImageIsFirstUsed) {
    for (const auto& [usage, stage] :
         {std::pair{"Write@ColorAttachment", VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT},
          std::pair{"Write@Compute", VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT}}) {
        const Plan plan = compile(presented(usage), at16());
        ASSERT_EQ(plan.presentations().size(), 1u) << usage;
        const Presentation& p = plan.presentations()[0];
        EXPECT_EQ(plan.resources()[p.resource].name, "target");
        EXPECT_EQ(p.acquireWaitStages, stage) << usage;
        EXPECT_EQ(p.renderCompleteStages, stage) << usage;
        // The transition out of UNDEFINED waits in the acquire's stages, so the wait covers it.
        const Barrier& first = plan.passes()[0].barriers[0];
        EXPECT_EQ(first.oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
        EXPECT_EQ(first.srcStages, p.acquireWaitStages) << usage;
        ASSERT_EQ(plan.finalBarriers().size(), 1u);
        EXPECT_EQ(plan.finalBarriers()[0].newLayout, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
        EXPECT_EQ(plan.finalBarriers()[0].srcStages, stage) << usage;
        EXPECT_EQ(plan.finalBarriers()[0].dstStages, p.renderCompleteStages) << usage;
        EXPECT_EQ(plan.finalBarriers()[0].dstAccess, VK_ACCESS_2_NONE) << "the present reads through the semaphore";
    }
}

TEST(Presentation, NoneWhenThePresentedImageIsReadBackInstead) {
    CompileOptions o = at16();
    o.presentReplacement = ExternalState::TransferSrc;
    o.readbacks = {"target"};
    const Plan plan = compile(presented("Write@ColorAttachment"), o);
    EXPECT_TRUE(plan.presentations().empty());
    const Plan copy = plan;  // copies keep what they have
    EXPECT_TRUE(copy.presentations().empty());
    EXPECT_EQ(plan.finalBarriers()[0].newLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    const Plan shown = compile(presented("Write@ColorAttachment"), at16());
    const Plan shownCopy = shown;
    ASSERT_EQ(shownCopy.presentations().size(), 1u);
    EXPECT_EQ(shownCopy.presentations()[0], shown.presentations()[0]);
}

}  // namespace
}  // namespace skygraph
