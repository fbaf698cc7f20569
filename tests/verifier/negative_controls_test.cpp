// Negative controls: a compiled plan that verifies, weakened on purpose (PlanEditor), must give
// the finding the weakening causes. Several are hazards the validation layer cannot see:
// between differently described aliased resources, and a storage write-after-write between
// dispatches.
#include "fixture_graphs.hpp"
#include "plan_editor.hpp"
#include "verifier_test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string_view>

namespace skygraph::verifier {
namespace {

using detail::PlanEditor;
using test::barrierOn;
using test::hasFinding;
using test::stepIndex;

/// The plan verifies as compiled: the control's finding comes from the edit.
void expectClean(const test::Compiled& c) {
    const VerificationReport report = verifyPlan(c.plan, c.graph);
    ASSERT_TRUE(report.ok()) << report.summary();
}

/// The aliasing barrier in step `step`.
size_t aliasingBarrier(const Plan& plan, size_t step) {
    const auto barriers = plan.passes()[step].barriers;
    for (size_t i = 0; i < barriers.size(); ++i)
        if (barriers[i].aliasing) return i;
    throw std::out_of_range("no aliasing barrier");
}

// An external input read as storage leaves the frame in GENERAL unless its final barrier moves
// it back to the ShaderRead state the next frame expects (one copy, shared by the frames).
TEST(NegativeControls, DroppedReturnOfAnExternalInput) {
    test::Compiled c = test::compileText(R"({"version": 1, "name": "input", "resources": {
        "lut": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true},
        "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true, "final": "TransferSrc"}},
      "passes": [{"name": "apply", "type": "Generic", "uses": [
        {"resource": "lut", "access": "Read", "stage": "Compute", "as": "storage"},
        {"resource": "out", "access": "Write", "stage": "ColorAttachment"}]}]})");
    expectClean(c);
    auto& finals = PlanEditor::finalBarriers(c.plan);
    const auto lut = static_cast<uint32_t>(c.plan.resourceIndex("lut"));
    const auto before = finals.size();
    std::erase_if(finals, [&](const Barrier& b) { return b.resource == lut; });
    ASSERT_EQ(finals.size(), before - 1);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::FinalLayout, "lut")) << r.summary();
}

TEST(NegativeControls, DroppedAliasingBarrier) {
    test::Compiled c = test::compileText(test::fixtures::kAliasAfterRead);
    expectClean(c);
    const size_t step = stepIndex(c.plan, "write_b");
    PlanEditor::eraseBarrier(c.plan, step, aliasingBarrier(c.plan, step));
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    // Nothing orders b's write after a's read, and b is used without leaving UNDEFINED.
    EXPECT_TRUE(hasFinding(r, FindingKind::Unordered, "b")) << r.summary();
    EXPECT_TRUE(hasFinding(r, FindingKind::AliasNotInitialized, "b")) << r.summary();
    EXPECT_TRUE(hasFinding(r, FindingKind::LayoutMismatch, "b")) << r.summary();
}

TEST(NegativeControls, AliasingBarrierWithoutItsSourceStage) {
    test::Compiled c = test::compileText(test::fixtures::kAliasAfterRead);
    expectClean(c);
    const size_t step = stepIndex(c.plan, "write_b");
    Barrier& b = PlanEditor::barriersOf(c.plan, step)[aliasingBarrier(c.plan, step)];
    ASSERT_EQ(b.srcStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    b.srcStages &= ~VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::Unordered, "a")) << r.summary();  // read_a -> b's transition
}

TEST(NegativeControls, AliasingBarrierWithoutThePredecessorsWriteAccess) {
    test::Compiled c = test::compileText(test::fixtures::kAliasAfterWrite);
    expectClean(c);
    const size_t step = stepIndex(c.plan, "write_b");
    Barrier& b = PlanEditor::barriersOf(c.plan, step)[aliasingBarrier(c.plan, step)];
    ASSERT_EQ(b.srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    b.srcAccess = 0;  // still an execution dependency, no longer a memory dependency
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::NotAvailable, "a")) << r.summary();
    EXPECT_FALSE(hasFinding(r, FindingKind::Unordered)) << r.summary();
}

TEST(NegativeControls, AliasingBarrierNotFromUndefined) {
    test::Compiled c = test::compileText(test::fixtures::kAliasAfterRead);
    expectClean(c);
    const size_t step = stepIndex(c.plan, "write_b");
    Barrier& b = PlanEditor::barriersOf(c.plan, step)[aliasingBarrier(c.plan, step)];
    ASSERT_EQ(b.oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    b.oldLayout = b.newLayout;
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::AliasNotInitialized, "b")) << r.summary();
    EXPECT_TRUE(hasFinding(r, FindingKind::BadOldLayout, "b")) << r.summary();
}

/// Two placements of resources that are in use at the same time moved onto the same bytes.
TEST(NegativeControls, OverlappingLivePlacements) {
    test::Compiled c = test::compileShipped("deferred.json");
    const auto resources = c.plan.resources();
    MemoryLayout& memory = PlanEditor::memory(c.plan);
    bool edited = false;
    for (size_t i = 0; i < memory.placements.size() && !edited; ++i)
        for (size_t j = i + 1; j < memory.placements.size() && !edited; ++j) {
            MemoryPlacement& x = memory.placements[i];
            MemoryPlacement& y = memory.placements[j];
            const PlannedResource& rx = resources[x.resource];
            const PlannedResource& ry = resources[y.resource];
            const bool live = rx.firstPass <= ry.lastPass && ry.firstPass <= rx.lastPass;
            if (!live || x.heap != y.heap || x.offset + y.bytes > memory.heaps[x.heap].bytes) continue;
            y.offset = x.offset;
            edited = true;
        }
    ASSERT_TRUE(edited);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::LiveOverlap)) << r.summary();
}

/// The light grid (a buffer: no layout) written by a dispatch and read by the lighting draw.
/// Another barrier of the same batch (ssao's, COMPUTE_SHADER -> FRAGMENT_SHADER) still orders
/// the read after the write, but only the dropped one made the write available.
TEST(NegativeControls, DroppedReadAfterWriteBarrier) {
    test::Compiled c = test::compileShipped("deferred.json");
    const size_t step = stepIndex(c.plan, "lighting_ssao");
    PlanEditor::eraseBarrier(c.plan, step, barrierOn(c.plan, step, "light_grid"));
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::NotAvailable, "light_grid")) << r.summary();
    EXPECT_FALSE(hasFinding(r, FindingKind::Unordered, "light_grid")) << r.summary();
    // Without that other barrier's help: the fixture's draw reads what a dispatch wrote.
    test::Compiled small = test::compileText(test::fixtures::kStorageWriteAfterWrite);
    const size_t present = stepIndex(small.plan, "present");
    PlanEditor::eraseBarrier(small.plan, present, barrierOn(small.plan, present, "buf"));
    const VerificationReport s = verifyPlan(small.plan, small.graph);
    EXPECT_TRUE(hasFinding(s, FindingKind::Unordered, "buf")) << s.summary();
}

TEST(NegativeControls, DroppedWriteAfterReadBarrier) {
    test::Compiled c = test::compileText(test::fixtures::kWriteAfterRead);
    expectClean(c);
    const size_t step = stepIndex(c.plan, "write");
    const Barrier& b = c.plan.passes()[step].barriers[barrierOn(c.plan, step, "buf")];
    ASSERT_EQ(b.srcAccess, 0u);  // execution only
    PlanEditor::eraseBarrier(c.plan, step, barrierOn(c.plan, step, "buf"));
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::Unordered, "buf")) << r.summary();
}

TEST(NegativeControls, WrongUsageLayout) {
    test::Compiled c = test::compileShipped("raster.json");
    const size_t step = stepIndex(c.plan, "tonemap");
    PlannedUsage& u = PlanEditor::usagesOf(c.plan, step)[test::usageOf(c.plan, step, "hdr_color")];
    ASSERT_EQ(u.layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    u.layout = VK_IMAGE_LAYOUT_GENERAL;  // allowed for sampling, but not the layout it is in
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::LayoutMismatch, "hdr_color")) << r.summary();
    EXPECT_FALSE(hasFinding(r, FindingKind::LayoutNotAllowed)) << r.summary();
}

TEST(NegativeControls, MissingHostMemoryBarrier) {
    const test::Compiled shipped = test::compileShipped("raster.json");
    test::Compiled c = test::compileShipped("raster.json", test::headless(shipped.graph, CompileOptions{}));
    expectClean(c);
    std::vector<Barrier>& final = PlanEditor::finalBarriers(c.plan);
    const auto memoryBarrier =
        std::find_if(final.begin(), final.end(), [](const Barrier& b) { return b.kind == BarrierKind::Memory; });
    ASSERT_NE(memoryBarrier, final.end());
    final.erase(memoryBarrier);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    const bool hostRead = std::any_of(r.findings.begin(), r.findings.end(), [](const Finding& f) {
        return f.kind == FindingKind::NotVisible && f.later.pass == "host";
    });
    EXPECT_TRUE(hostRead) << r.summary();
}

/// Sets oldLayout UNDEFINED on the final barriers of image `resource`; how many there were.
size_t discardInFinalBarriers(Plan& plan, std::string_view resource) {
    size_t edited = 0;
    for (Barrier& b : PlanEditor::finalBarriers(plan))
        if (b.kind == BarrierKind::Image && plan.resources()[b.resource].name == resource) {
            b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
            ++edited;
        }
    return edited;
}

// A final barrier from UNDEFINED moves an export into its final layout with its contents
// discarded: whoever takes it after the frame (a sampler of the bake's products, the read-back
// of a headless frame) gets garbage, although every layout is right.
TEST(NegativeControls, FinalBarrierThatDiscardsAnExport) {
    test::Compiled ibl = test::compileShipped("ibl.json");
    expectClean(ibl);
    ASSERT_GE(discardInFinalBarriers(ibl.plan, "irradiance"), 1u);
    VerificationReport r = verifyPlan(ibl.plan, ibl.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::UndefinedContents, "irradiance")) << r.summary();

    const test::Compiled shipped = test::compileShipped("raster.json");
    test::Compiled headless = test::compileShipped("raster.json", test::headless(shipped.graph, CompileOptions{}));
    expectClean(headless);
    ASSERT_GE(discardInFinalBarriers(headless.plan, "swapchain"), 1u);
    r = verifyPlan(headless.plan, headless.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::UndefinedContents, "swapchain")) << r.summary();
}

// An external input exported through CompileOptions::exports (the file gives it no `final`)
// is taken after the frame as any export is: the plan says so (ResourceCopies::SharedExported),
// and a final barrier that discards it is caught against the file's graph.
TEST(NegativeControls, FinalBarrierThatDiscardsAnInputExportedThroughTheOptions) {
    CompileOptions o;
    o.exports = {{"canvas", ExternalState::ShaderRead}};
    test::Compiled c = test::compileText(R"({ "version": 1, "name": "exported-input", "resources": {
        "canvas": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true,
                    "initial": "ShaderRead" },
        "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true,
                 "final": "ShaderRead" } },
      "passes": [
        { "name": "paint", "type": "Generic", "uses": { "canvas": "Write@ColorAttachment" } },
        { "name": "show", "type": "Generic", "uses": { "canvas": "Read@Fragment", "out": "Write@ColorAttachment" } } ] })",
                                         o);
    ASSERT_EQ(c.graph.resources[0].final, ExternalState::None);
    expectClean(c);
    ASSERT_GE(discardInFinalBarriers(c.plan, "canvas"), 1u);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::UndefinedContents, "canvas")) << r.summary();
}

/// Two dispatches writing one storage buffer with nothing between them: a write-after-write
/// the validation layer does not report.
TEST(NegativeControls, StorageWriteAfterWriteBetweenDispatches) {
    test::Compiled c = test::compileText(test::fixtures::kStorageWriteAfterWrite);
    expectClean(c);
    const size_t step = stepIndex(c.plan, "second");
    {
        test::Compiled dropped = c;
        PlanEditor::eraseBarrier(dropped.plan, step, barrierOn(dropped.plan, step, "buf"));
        const VerificationReport r = verifyPlan(dropped.plan, dropped.graph);
        ASSERT_EQ(r.findings.size(), 1u) << r.summary();
        EXPECT_EQ(r.findings[0].kind, FindingKind::Unordered);
        EXPECT_NE(r.findings[0].reason.find("write-after-write"), std::string::npos) << r.summary();
    }
    {
        // Kept as an execution dependency, the first write is never made available.
        test::Compiled executionOnly = c;
        PlanEditor::barriersOf(executionOnly.plan, step)[barrierOn(executionOnly.plan, step, "buf")].srcAccess = 0;
        const VerificationReport r = verifyPlan(executionOnly.plan, executionOnly.graph);
        EXPECT_TRUE(hasFinding(r, FindingKind::NotAvailable, "buf")) << r.summary();
    }
    {
        // Available, but not visible to the second write.
        test::Compiled notVisible = c;
        PlanEditor::barriersOf(notVisible.plan, step)[barrierOn(notVisible.plan, step, "buf")].dstAccess = 0;
        const VerificationReport r = verifyPlan(notVisible.plan, notVisible.graph);
        EXPECT_TRUE(hasFinding(r, FindingKind::NotVisible, "buf")) << r.summary();
    }
}

}  // namespace
}  // namespace skygraph::verifier
