// Every check can fail: for each kind of finding, a plan (compiled, then edited where the
// compiler would not produce the problem) that gives it. And the tables the checks stand on.
#include "fixture_graphs.hpp"
#include "happens_before.hpp"
#include "plan_editor.hpp"
#include "sync_tables.hpp"
#include "verifier_test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace skygraph::verifier {
namespace {

using detail::PlanEditor;
using test::barrierOn;
using test::hasFinding;
using test::stepIndex;
using test::usageOf;

// ---- the tables ----

TEST(SyncTables, FirstScopesIncludeLogicallyEarlierStages) {
    const StageSet s = synchronizationScope(VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, ScopeSide::First);
    EXPECT_TRUE(s.has(Stage::FragmentShader));
    EXPECT_TRUE(s.has(Stage::EarlyFragmentTests));
    EXPECT_TRUE(s.has(Stage::VertexShader));
    EXPECT_TRUE(s.has(Stage::DrawIndirect));
    EXPECT_FALSE(s.has(Stage::LateFragmentTests));
    EXPECT_FALSE(s.has(Stage::ComputeShader));
    EXPECT_FALSE(s.has(Stage::Copy));
}

TEST(SyncTables, SecondScopesIncludeLogicallyLaterStages) {
    const StageSet compute = synchronizationScope(VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, ScopeSide::Second);
    EXPECT_EQ(compute, only(Stage::ComputeShader));
    const StageSet indirect = synchronizationScope(VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, ScopeSide::Second);
    EXPECT_TRUE(indirect.has(Stage::ComputeShader));  // in the compute pipeline too
    EXPECT_TRUE(indirect.has(Stage::ColorAttachmentOutput));
    EXPECT_FALSE(indirect.has(Stage::Copy));
}

TEST(SyncTables, TopAndBottomOfPipe) {
    EXPECT_TRUE(synchronizationScope(VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, ScopeSide::First).empty());
    EXPECT_EQ(synchronizationScope(VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, ScopeSide::Second), allDeviceStages());
    EXPECT_EQ(synchronizationScope(VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, ScopeSide::First), allDeviceStages());
    EXPECT_TRUE(synchronizationScope(VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, ScopeSide::Second).empty());
    EXPECT_TRUE(accessScope(VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, VK_ACCESS_2_MEMORY_READ_BIT).empty());
}

TEST(SyncTables, AccessAliasesAndSupport) {
    const AccessScope shaderRead = accessScope(VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_READ_BIT);
    EXPECT_TRUE(
        shaderRead.contains(accessScope(VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT)));
    EXPECT_TRUE(
        shaderRead.contains(accessScope(VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT)));
    EXPECT_FALSE(
        shaderRead.contains(accessScope(VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_UNIFORM_READ_BIT)));
    const AccessScope allWrites = accessScope(VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT);
    EXPECT_TRUE(
        allWrites.contains(accessScope(VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT)));
    EXPECT_TRUE(allWrites.contains(accessScope(VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT)));
    EXPECT_FALSE(allWrites.contains(accessScope(VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT)));
    // A clear never reads; copies do.
    EXPECT_TRUE(accessScope(VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_READ_BIT).empty());
    EXPECT_EQ(accessUnsupportedByStages(VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT),
              VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
}

TEST(SyncTables, AccessScopesAreNotExpandedByLogicalOrder) {
    const AccessScope late =
        accessScope(VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
    EXPECT_FALSE(late.contains(
        accessScope(VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT)));
}

TEST(HappensBeforeGraph, ChainsAcrossBatchesOnly) {
    HappensBefore g;
    SyncPoint p;
    p.firstSync = synchronizationScope(VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, ScopeSide::First);
    p.secondSync = synchronizationScope(VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, ScopeSide::Second);
    p.position = 1;
    p.batch = 1;
    const PointId a = g.add(p);
    const PointId sameBatch = g.add(p);
    p.position = 2;
    p.batch = 2;
    const PointId next = g.add(p);
    p.position = 3;
    p.batch = 3;
    p.firstSync = synchronizationScope(VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, ScopeSide::First);
    const PointId unrelated = g.add(p);
    p.position = 4;
    p.batch = 4;
    p.firstSync = synchronizationScope(VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, ScopeSide::First);
    const PointId everything = g.add(p);
    g.finalize();
    EXPECT_FALSE(g.successors(a).test(sameBatch));
    EXPECT_TRUE(g.successors(a).test(next));
    EXPECT_FALSE(g.successors(next).test(unrelated));
    EXPECT_TRUE(g.successors(unrelated).test(everything));  // ALL_COMMANDS covers earlier barriers
}

/// How a second queue joins the graph: its points sit in its own submission order, and a
/// semaphore signal on one queue reaches the wait on the other through an explicit edge.
TEST(HappensBeforeGraph, SemaphoreEdgesJoinQueues) {
    HappensBefore g;
    SyncPoint barrier;  // queue 0: a compute write's barrier, then the signal
    barrier.firstSync = synchronizationScope(VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, ScopeSide::First);
    barrier.secondSync = synchronizationScope(VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, ScopeSide::Second);
    barrier.position = 2;
    barrier.batch = 1;
    const PointId first = g.add(barrier);
    SyncPoint signal;
    signal.kind = SyncPoint::Kind::SemaphoreSignal;
    signal.firstSync = synchronizationScope(VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, ScopeSide::First);
    signal.position = 3;
    signal.batch = 2;
    const PointId signalled = g.add(signal);
    SyncPoint wait;  // queue 1: the wait, then a barrier before a transfer
    wait.kind = SyncPoint::Kind::SemaphoreWait;
    wait.queue = 1;
    wait.secondSync = synchronizationScope(VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, ScopeSide::Second);
    wait.position = 1;
    wait.batch = 3;
    const PointId waited = g.add(wait);
    g.addEdge(signalled, waited);
    g.finalize();
    QueuePlace write{0, 1, 0, true, only(Stage::ComputeShader)};
    QueuePlace copy{1, 2, 0, true, only(Stage::Copy)};
    QueuePlace unrelated{1, 2, 0, true, only(Stage::ComputeShader)};
    EXPECT_TRUE(g.successors(first).test(waited));
    EXPECT_TRUE(g.happensBefore(g.onQueue(write), g.onQueue(copy)));
    EXPECT_FALSE(g.happensBefore(g.onQueue(write), g.onQueue(unrelated)));  // the wait covers transfers only
}

// ---- each kind of finding ----

TEST(ChecksFail, MalformedPlanIsReportedNotCrashed) {
    test::Compiled c = test::compileShipped("raster.json");
    const size_t forward = stepIndex(c.plan, "forward_ibl");
    PlanEditor::usagesOf(c.plan, forward)[0].resource = 999;
    PlanEditor::barriersOf(c.plan, forward)[0].resource = 999;
    PlanEditor::usagesOf(c.plan, stepIndex(c.plan, "tonemap"))[0].range = {7, 1, 0, 1};
    PlanEditor::presentations(c.plan).push_back({999, 0, 0});
    PlanEditor::inPassBarriers(c.plan).push_back({999, 0, {}});
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_GE(r.count(FindingKind::MalformedPlan), 4u) << r.summary();
    // Against a graph that lacks every resource the plan names.
    const VerificationReport empty = verifyPlan(c.plan, GraphDesc{});
    EXPECT_GE(empty.count(FindingKind::MalformedPlan), c.plan.resources().size()) << empty.summary();
    MemoryLayout& m = PlanEditor::memory(c.plan);
    m.placements.push_back({});
    m.placements.back().resource = 0;
    m.placements.back().heap = 77;
    EXPECT_TRUE(hasFinding(verifyPlan(c.plan, c.graph), FindingKind::MalformedPlan));
}

// A resource's lifetime must lie within the plan's passes, and its decl must be the graph
// resource of its name: verified against another graph, every check would read others' shapes.
TEST(ChecksFail, ALifetimeOrADeclThatIsNotTheResourcesIsMalformed) {
    test::Compiled c = test::compileShipped("raster.json");
    EXPECT_TRUE(verifyPlan(c.plan, c.graph).ok());
    std::vector<PlannedResource>& resources = PlanEditor::resources(c.plan);
    ASSERT_GE(resources.size(), 2u);
    const PlannedResource first = resources[0], second = resources[1];
    const auto malformed = [](const VerificationReport& report, const std::string& words) {
        return std::any_of(report.findings.begin(), report.findings.end(), [&](const Finding& f) {
            return f.kind == FindingKind::MalformedPlan && f.reason.find(words) != std::string::npos;
        });
    };
    resources[0].lastPass = 999;
    VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(malformed(r, "its lifetime, passes")) << r.summary();
    resources[0] = first;
    resources[0].firstPass = resources[0].lastPass + 1;
    r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(malformed(r, "its lifetime, passes")) << r.summary();
    resources[0] = first;
    std::swap(resources[0].decl, resources[1].decl);
    r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(malformed(r, "is the graph's '" + std::string(second.name) + "', not '" + std::string(first.name) + "'"))
        << r.summary();
}

/// Plans edited at random (indices, ranges, kinds, layouts, masks, placements) give findings,
/// never a crash or an exception.
TEST(ChecksFail, GarbageNeverCrashes) {
    const test::Compiled shipped[] = {test::compileShipped("raster.json"), test::compileShipped("deferred.json")};
    std::mt19937 rng(7);
    const auto any = [&](uint32_t n) { return static_cast<uint32_t>(rng() % n); };
    for (int round = 0; round < 300; ++round) {
        test::Compiled c = shipped[round % 2];
        Plan& plan = c.plan;
        const auto steps = static_cast<uint32_t>(plan.passes().size());
        const auto resources = static_cast<uint32_t>(plan.resources().size());
        for (int edit = 0; edit < 3; ++edit) {
            const uint32_t step = any(steps);
            const auto usages = PlanEditor::usagesOf(plan, step);
            const auto barriers = PlanEditor::barriersOf(plan, step);
            switch (any(8)) {
                case 0:
                    if (!usages.empty()) usages[any(uint32_t(usages.size()))].resource = any(resources + 3);
                    break;
                case 1:
                    if (!usages.empty())
                        usages[any(uint32_t(usages.size()))].range = {any(20), any(20), any(3000), any(3)};
                    break;
                case 2:
                    if (!usages.empty())
                        usages[any(uint32_t(usages.size()))].usage = {Access(any(4)), skygraph::Stage(any(10)),
                                                                      BindAs(any(6))};
                    break;
                case 3:
                    if (!barriers.empty()) barriers[any(uint32_t(barriers.size()))].resource = any(resources + 3);
                    break;
                case 4:
                    if (!barriers.empty()) barriers[any(uint32_t(barriers.size()))].kind = BarrierKind(any(4));
                    break;
                case 5:
                    if (!barriers.empty()) {
                        Barrier& b = barriers[any(uint32_t(barriers.size()))];
                        b.range = {any(20), any(20), any(10), ~0u};
                        b.oldLayout = VkImageLayout(any(12));
                        b.srcStages = (uint64_t(rng()) << 32) | rng();
                    }
                    break;
                case 6: {
                    MemoryLayout& m = PlanEditor::memory(plan);
                    if (!m.placements.empty()) {
                        MemoryPlacement& p = m.placements[any(uint32_t(m.placements.size()))];
                        p.resource = any(resources + 2);
                        p.heap = any(3);
                        p.offset = ~uint64_t(0) - any(100);
                    }
                    break;
                }
                default: {
                    auto& r = PlanEditor::resources(plan)[any(resources)];
                    r.decl = any(uint32_t(c.graph.resources.size()) + 2);
                    r.placement = any(40);
                    PlanEditor::presentations(plan).push_back({any(resources + 2), 0, 0});
                    PlanEditor::inPassBarriers(plan).push_back({any(steps + 1), any(5), {}});
                }
            }
        }
        EXPECT_NO_THROW((void)verifyPlan(plan, c.graph));
    }
    EXPECT_TRUE(verifyPlan(Plan{}, GraphDesc{}).ok());
}

TEST(ChecksFail, InvalidMask) {
    test::Compiled c = test::compileText(test::fixtures::kStorageWriteAfterWrite);
    const size_t step = stepIndex(c.plan, "second");
    PlanEditor::barriersOf(c.plan, step)[0].srcAccess = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;  // at COMPUTE_SHADER
    EXPECT_TRUE(hasFinding(verifyPlan(c.plan, c.graph), FindingKind::InvalidMask));
}

TEST(ChecksFail, UsageScope) {
    test::Compiled c = test::compileText(test::fixtures::kStorageWriteAfterWrite);
    const size_t step = stepIndex(c.plan, "second");
    PlanEditor::usagesOf(c.plan, step)[0].access = VK_ACCESS_2_SHADER_STORAGE_READ_BIT;  // a Write usage
    EXPECT_TRUE(hasFinding(verifyPlan(c.plan, c.graph), FindingKind::UsageScope, "buf"));
}

TEST(ChecksFail, LayoutNotAllowed) {
    test::Compiled c = test::compileShipped("raster.json");
    const size_t step = stepIndex(c.plan, "tonemap");
    PlanEditor::usagesOf(c.plan, step)[usageOf(c.plan, step, "hdr_color")].layout =
        VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    EXPECT_TRUE(hasFinding(verifyPlan(c.plan, c.graph), FindingKind::LayoutNotAllowed, "hdr_color"));
}

// A stencil-only attachment is written in STENCIL_ATTACHMENT_OPTIMAL and read in
// STENCIL_READ_ONLY_OPTIMAL (Vulkan 1.3 §12.4): the verifier knew only the depth layouts and
// failed every S8_UINT attachment that validation accepts. A depth-only one may not take them.
TEST(ChecksFail, StencilOnlyAttachmentsTakeTheStencilLayouts) {
    test::Compiled c = test::compileText(R"({ "version": 1, "name": "stencil", "resources": {
        "st": { "type": "image2d", "format": "S8_UINT", "extent": "output", "clear": { "stencil": 1 } },
        "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output", "external": true,
                 "final": "ShaderRead" } },
      "passes": [
        { "name": "mask", "type": "Generic",
          "uses": { "st": "Write@DepthAttachment", "out": "Write@ColorAttachment" } },
        { "name": "test", "type": "Generic",
          "uses": { "st": "Read@DepthAttachment", "out": "ReadWrite@ColorAttachment" } } ] })");
    const size_t mask = stepIndex(c.plan, "mask"), test = stepIndex(c.plan, "test");
    EXPECT_EQ(c.plan.passes()[mask].usages[usageOf(c.plan, mask, "st")].layout,
              VK_IMAGE_LAYOUT_STENCIL_ATTACHMENT_OPTIMAL);
    EXPECT_EQ(c.plan.passes()[test].usages[usageOf(c.plan, test, "st")].layout,
              VK_IMAGE_LAYOUT_STENCIL_READ_ONLY_OPTIMAL);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(r.ok()) << r.summary();
    PlanEditor::usagesOf(c.plan, test)[usageOf(c.plan, test, "st")].layout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    EXPECT_TRUE(hasFinding(verifyPlan(c.plan, c.graph), FindingKind::LayoutNotAllowed, "st"));
    // A stencil layout names an aspect a depth-only image lacks.
    test::Compiled raster = test::compileShipped("raster.json");
    const size_t forward = stepIndex(raster.plan, "forward_ibl");
    PlanEditor::usagesOf(raster.plan, forward)[usageOf(raster.plan, forward, "depth")].layout =
        VK_IMAGE_LAYOUT_STENCIL_ATTACHMENT_OPTIMAL;
    EXPECT_TRUE(hasFinding(verifyPlan(raster.plan, raster.graph), FindingKind::LayoutNotAllowed, "depth"));
}

TEST(ChecksFail, BadOldLayout) {
    test::Compiled c = test::compileShipped("raster.json");
    const size_t step = stepIndex(c.plan, "tonemap");
    PlanEditor::barriersOf(c.plan, step)[barrierOn(c.plan, step, "hdr_color")].oldLayout =
        VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    EXPECT_TRUE(hasFinding(verifyPlan(c.plan, c.graph), FindingKind::BadOldLayout, "hdr_color"));
}

TEST(ChecksFail, UndefinedContents) {
    test::Compiled c = test::compileShipped("raster.json");
    // forward_ibl's colour is loaded by skybox: a DONT_CARE store would throw it away.
    const size_t step = stepIndex(c.plan, "forward_ibl");
    PlanEditor::usagesOf(c.plan, step)[usageOf(c.plan, step, "hdr_color")].store = StoreOp::DontCare;
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::UndefinedContents, "hdr_color")) << r.summary();
}

// STORE_OP_NONE keeps contents only where the render pass writes nothing; after forward_ibl's
// writes it discards them as DONT_CARE does, and skybox loads undefined depth and colour. (It
// passed as "touches nothing".) On a read-only attachment it keeps them: the compiled plan's
// own NONE stores verify.
TEST(ChecksFail, UndefinedContentsAfterANoneStoreOfAWrite) {
    for (const char* resource : {"hdr_color", "depth"}) {
        test::Compiled edited = test::compileShipped("raster.json");
        const size_t step = stepIndex(edited.plan, "forward_ibl");
        PlanEditor::usagesOf(edited.plan, step)[usageOf(edited.plan, step, resource)].store = StoreOp::None;
        const VerificationReport r = verifyPlan(edited.plan, edited.graph);
        EXPECT_TRUE(hasFinding(r, FindingKind::UndefinedContents, resource)) << r.summary();
        EXPECT_NE(r.summary().find("the NONE store op after a write"), std::string::npos) << r.summary();
    }
    const test::Compiled c = test::compileShipped("raster.json");
    bool noneStore = false;
    for (const PlannedPass& p : c.plan.passes())
        for (const PlannedUsage& u : p.usages) noneStore |= u.store == StoreOp::None;
    EXPECT_TRUE(noneStore) << "raster.json's plan no longer has a NONE store to verify";
    EXPECT_TRUE(verifyPlan(c.plan, c.graph).ok()) << verifyPlan(c.plan, c.graph).summary();
}

// A transient's contents start undefined in every frame, whether the frames share its heap
// or each has its own: a buffer (no layout transition to discard them) read before anything
// wrote it in the frame.
TEST(ChecksFail, UndefinedContentsOfATransientBufferInSharedAndPerFrameHeaps) {
    for (const bool shared : {true, false}) {
        CompileOptions options;
        options.shareTransientsAcrossFrames = shared;
        test::Compiled c = test::compileShipped("deferred.json", options);
        ASSERT_EQ(c.plan.resources()[static_cast<size_t>(c.plan.resourceIndex("light_grid"))].copies,
                  shared ? ResourceCopies::SharedTransient : ResourceCopies::PerFrameTransient);
        const size_t step = stepIndex(c.plan, "light_culling");
        EXPECT_TRUE(verifyPlan(c.plan, c.graph).ok()) << verifyPlan(c.plan, c.graph).summary();
        PlanEditor::usagesOf(c.plan, step)[usageOf(c.plan, step, "light_grid")].usage.access = Access::ReadWrite;
        const VerificationReport r = verifyPlan(c.plan, c.graph);
        EXPECT_TRUE(hasFinding(r, FindingKind::UndefinedContents, "light_grid")) << (shared ? "shared " : "per frame ")
                                                                                   << r.summary();
    }
}

TEST(ChecksFail, PresentLayoutAndFinalLayout) {
    test::Compiled c = test::compileShipped("raster.json");
    for (Barrier& b : PlanEditor::finalBarriers(c.plan))
        if (b.newLayout == VK_IMAGE_LAYOUT_PRESENT_SRC_KHR) b.newLayout = b.oldLayout;
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::PresentLayout, "swapchain")) << r.summary();
    EXPECT_TRUE(hasFinding(r, FindingKind::FinalLayout, "swapchain")) << r.summary();
}

TEST(ChecksFail, PlacementInvalid) {
    test::Compiled c = test::compileShipped("deferred.json");
    MemoryLayout& m = PlanEditor::memory(c.plan);
    ASSERT_FALSE(m.placements.empty());
    m.placements[0].offset = m.heaps[m.placements[0].heap].bytes;
    EXPECT_TRUE(hasFinding(verifyPlan(c.plan, c.graph), FindingKind::PlacementInvalid));
}

// A resource in a heap that may be allocated in a memory type it cannot live in (the executor
// refuses to bind it there): none of the heap's types, or only some of them.
TEST(ChecksFail, PlacementInvalidForItsHeapsMemoryType) {
    const test::Compiled intact = test::compileShipped("deferred.json");
    ASSERT_TRUE(verifyPlan(intact.plan, intact.graph).ok());
    for (const bool some : {false, true}) {
        test::Compiled c = intact;
        MemoryLayout& m = PlanEditor::memory(c.plan);
        ASSERT_FALSE(m.placements.empty());
        MemoryHeap& heap = m.heaps[m.placements[0].heap];
        if (some) heap.memoryTypeBits |= 0x2;  // the placement keeps the estimate's one type, 0x1
        else m.placements[0].requirements.memoryTypeBits = ~heap.memoryTypeBits;
        const VerificationReport r = verifyPlan(c.plan, c.graph);
        ASSERT_GE(r.findings.size(), 1u) << r.summary();
        EXPECT_EQ(r.findings[0].kind, FindingKind::PlacementInvalid);
        EXPECT_NE(r.findings[0].reason.find("may be allocated in a memory type it cannot live in"), std::string::npos)
            << r.summary();
    }
}

/// A write made available only by a barrier that names part of its image before another
/// resource takes over the memory: the aliasing barrier repeats the write (rule 16); without
/// its source access, only the partial barrier is left.
TEST(ChecksFail, PartialAliasBarrier) {
    test::Compiled c = test::compileText(test::fixtures::kPartialAvailabilityBeforeAliasing);
    ASSERT_TRUE(verifyPlan(c.plan, c.graph).ok());
    size_t edited = 0;
    for (size_t step = 0; step < c.plan.passes().size(); ++step)
        for (Barrier& b : PlanEditor::barriersOf(c.plan, step))
            if (b.aliasing) {
                b.srcAccess = 0;
                ++edited;
            }
    ASSERT_EQ(edited, 1u);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    ASSERT_EQ(r.findings.size(), 1u) << r.summary();
    EXPECT_EQ(r.findings[0].kind, FindingKind::PartialAliasBarrier);
    EXPECT_EQ(r.findings[0].earlier.pass, "write_a");
    EXPECT_EQ(r.findings[0].later.pass, "write_b");
}

/// State carried from one frame to the next: without its final barrier, the path tracer's
/// accumulation is left in the layout the tonemapper read it in, and the next frame's
/// dispatch is not ordered after that read.
TEST(ChecksFail, SecondFrame) {
    test::Compiled c = test::compileShipped("pathtrace.json");
    std::vector<Barrier>& final = PlanEditor::finalBarriers(c.plan);
    const uint32_t accumulation = static_cast<uint32_t>(c.plan.resourceIndex("accumulation"));
    std::erase_if(final, [&](const Barrier& b) { return b.resource == accumulation; });
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    const bool crossesFrames = std::any_of(r.findings.begin(), r.findings.end(), [](const Finding& f) {
        return f.kind == FindingKind::Unordered && f.earlier.frame == 1 && f.later.frame == 2;
    });
    EXPECT_TRUE(crossesFrames) << r.summary();
    EXPECT_TRUE(hasFinding(r, FindingKind::LayoutMismatch, "accumulation")) << r.summary();
    VerifyOptions oneFrame;
    oneFrame.consecutiveFrames = false;
    EXPECT_FALSE(hasFinding(verifyPlan(c.plan, c.graph, oneFrame), FindingKind::Unordered)) << r.summary();
}

/// The acquire wait must come before the swapchain image's first barrier can start, and the
/// render-complete signal after its final transition.
TEST(ChecksFail, PresentationSemaphores) {
    test::Compiled c = test::compileShipped("raster.json");
    {
        test::Compiled late = c;
        PlanEditor::presentations(late.plan)[0].acquireWaitStages = VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT;
        const VerificationReport r = verifyPlan(late.plan, late.graph);
        EXPECT_TRUE(std::any_of(r.findings.begin(), r.findings.end(), [](const Finding& f) {
            return f.kind == FindingKind::Unordered && f.earlier.pass == "presentation engine";
        })) << r.summary();
    }
    {
        test::Compiled early = c;
        PlanEditor::presentations(early.plan)[0].renderCompleteStages = VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT;
        const VerificationReport r = verifyPlan(early.plan, early.graph);
        EXPECT_TRUE(std::any_of(r.findings.begin(), r.findings.end(), [](const Finding& f) {
            return f.kind == FindingKind::Unordered && f.later.pass == "presentation engine";
        })) << r.summary();
    }
}

/// A ReadWrite copy is a copy out and then a copy in: without the in-pass barrier between
/// them, nothing orders the write after the read.
TEST(ChecksFail, InPassBarrier) {
    test::Compiled c = test::compileText(test::fixtures::kWriteAfterRead);
    ASSERT_TRUE(verifyPlan(c.plan, c.graph).ok());
    ASSERT_EQ(c.plan.inPassBarriers().size(), 1u);
    PlanEditor::inPassBarriers(c.plan).clear();
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    ASSERT_EQ(r.findings.size(), 1u) << r.summary();
    EXPECT_EQ(r.findings[0].kind, FindingKind::Unordered);
    EXPECT_EQ(r.findings[0].earlier.step, r.findings[0].later.step) << r.summary();
}

/// Exports are read after the frame in their final state: a final barrier that does not make
/// the frame's writes visible to that state's scope leaves the reader outside the frame short.
TEST(ChecksFail, ExportReadAfterTheFrame) {
    test::Compiled c = test::compileShipped("ibl.json");
    ASSERT_FALSE(c.plan.finalBarriers().empty());
    for (Barrier& b : PlanEditor::finalBarriers(c.plan)) b.dstAccess = 0;
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    const bool outside = std::any_of(r.findings.begin(), r.findings.end(), [](const Finding& f) {
        return f.kind == FindingKind::NotVisible && f.later.pass == "outside the frame";
    });
    EXPECT_TRUE(outside) << r.summary();
}

/// A shared external arrives in its initial state, which readers outside the frame may still
/// be reading in: the frame's first writes wait for them (the ibl worked example of
/// docs/barriers.md waits for FRAGMENT_SHADER|COMPUTE_SHADER samplers of the cube).
TEST(ChecksFail, FirstWriteWaitsForReadersOutsideTheFrame) {
    test::Compiled c = test::compileShipped("ibl.json");
    ASSERT_TRUE(verifyPlan(c.plan, c.graph).ok());
    const auto outsideScope = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    size_t edited = 0;
    for (size_t step = 0; step < c.plan.passes().size(); ++step)
        for (Barrier& b : PlanEditor::barriersOf(c.plan, step))
            if (b.srcStages == outsideScope && b.srcAccess == 0) {
                b.srcStages = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
                ++edited;
            }
    ASSERT_GT(edited, 0u);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    const bool outside = std::any_of(r.findings.begin(), r.findings.end(), [](const Finding& f) {
        return f.kind == FindingKind::Unordered && f.earlier.pass == "outside the frame";
    });
    EXPECT_TRUE(outside) << r.summary();
}

}  // namespace
}  // namespace skygraph::verifier
