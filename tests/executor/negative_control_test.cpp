// Negative controls: the oracle can fail. Each test first runs a plan untouched (no messages),
// then drops or weakens one barrier and asserts that synchronization validation reports the
// matching SYNC-HAZARD.
#include "executor_test_util.hpp"

#include "compiled_graph_access.hpp"
#include "plan_editor.hpp"
#include "renderer_access.hpp"

#include <skygraph/scene.hpp>

#include <gtest/gtest-spi.h>

#include <algorithm>

namespace skygraph::test {
namespace {

std::string graph(const std::string& resources, const std::string& passes) {
    return graphWithSwapchain("neg", resources, passes);
}

/// Where the barrier recorded before `pass` for `resource` is: (pass index, index in its
/// batch); fails the test when there is none.
std::pair<size_t, size_t> findBarrier(const Plan& plan, const std::string& pass, const std::string& resource) {
    const int32_t r = plan.resourceIndex(resource);
    for (size_t p = 0; p < plan.passes().size(); ++p) {
        if (plan.passes()[p].name != pass) continue;
        for (size_t i = 0; i < plan.passes()[p].barriers.size(); ++i)
            if (static_cast<int32_t>(plan.passes()[p].barriers[i].resource) == r) return {p, i};
    }
    ADD_FAILURE() << "no barrier before '" << pass << "' for '" << resource << "'\n"
                  << planToText(plan);
    return {plan.passes().size(), 0};
}

/// The barrier itself, editable; nullptr (and a failure) when there is none.
Barrier* barrierOf(Plan& plan, const std::string& pass, const std::string& resource) {
    const auto [p, i] = findBarrier(plan, pass, resource);
    return p < plan.passes().size() ? &detail::PlanEditor::barriersOf(plan, p)[i] : nullptr;
}

void dropBarrier(Plan& plan, const std::string& pass, const std::string& resource) {
    const auto [p, i] = findBarrier(plan, pass, resource);
    ASSERT_LT(p, plan.passes().size());
    detail::PlanEditor::eraseBarrier(plan, p, i);
}

/// "draw" writes tex as a color attachment, "sample" reads it in the fragment shader: the
/// barrier between them is a layout transition, which the two layout controls below break in
/// different ways.
CompiledGraph attachmentThenSampled() {
    return compileText(graph(
        R"("tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" })",
        R"({ "name": "draw", "type": "Generic", "uses": { "tex": "Write@ColorAttachment" } },
           { "name": "sample", "type": "Generic",
             "uses": { "tex": "Read@Fragment", "swapchain": "Write@ColorAttachment" } })"));
}

class NegativeControl : public ExecutorTest {
protected:
    /// Runs `c` untouched and requires silence, then runs `broken` and returns the messages.
    void expectHazard(const CompiledGraph& c, const Plan& broken, const std::string& hazard) {
        {
            Renderer r(sharedDevice(), c, genericOptions());
            for (int i = 0; i < 2; ++i) r.renderFrame();
            r.waitIdle();
        }
        ASSERT_EQ(sharedDevice().messageCount(), 0u)
            << "the intact plan must be clean:\n" << formatMessages(sharedDevice());
        allowMessages();
        {
            Renderer r(sharedDevice(), detail::CompiledGraphAccess::withPlan(c, broken), genericOptions());
            for (int i = 0; i < 2; ++i) r.renderFrame();
            r.waitIdle();
        }
        EXPECT_TRUE(sharedDevice().hasMessage(hazard))
            << "expected " << hazard << "; got:\n" << formatMessages(sharedDevice());
    }
};

/// A buffer written on the compute queue and read on the graphics queue, compiled for the shared
/// device's queue families (so that the Renderer runs the plan as edited).
CompiledGraph computeThenGraphics() {
    GraphDesc g = parseGraph(graph(R"("buf": { "type": "buffer", "size": 256 })",
                                   R"({ "name": "produce", "type": "Generic", "queue": "compute",
                                        "uses": { "buf": "Write@Compute" } },
                                      { "name": "consume", "type": "Generic",
                                        "uses": { "buf": "Read@Fragment", "swapchain": "Write@ColorAttachment" } })"),
                             "<test>", PassRegistry::withBuiltins());
    CompileOptions o = sizedOptions();
    o.memory = sharedDevice().memoryModel();
    o.queueFamilies = sharedDevice().queueFamilies();
    o = headless(g, std::move(o));
    return CompiledGraph(std::move(g), std::move(o));
}

/// The waits of the submit that holds `pass`, edited by `edit`.
template <class Edit>
Plan withWaitsOf(const Plan& plan, const std::string& pass, Edit edit) {
    Plan broken = plan;
    auto submits = detail::PlanEditor::submits(broken);
    for (auto& s : submits)
        for (uint32_t p : s.passes)
            if (plan.passes()[p].name == pass) edit(s.waits);
    detail::PlanEditor::setSubmits(broken, submits);
    return broken;
}

// Two queues (one VkQueue on lavapipe, in submission order): without the semaphore wait the
// graphics queue's read races the compute queue's write.
TEST_F(NegativeControl, DroppedSemaphoreWaitIsReadAfterWrite) {
    const auto c = computeThenGraphics();
    ASSERT_GT(c.plan().submits().size(), 2u);
    const Plan broken = withWaitsOf(c.plan(), "consume", [](std::vector<SemaphoreOp>& waits) {
        ASSERT_EQ(waits.size(), 1u);
        waits.clear();
    });
    expectHazard(c, broken, "SYNC-HAZARD-READ-AFTER-WRITE");
}

// A wait at a stage after the read (COLOR_ATTACHMENT_OUTPUT, logically later than the fragment
// shader) does not hold the read back.
TEST_F(NegativeControl, SemaphoreWaitAtALaterStageIsReadAfterWrite) {
    const auto c = computeThenGraphics();
    const Plan broken = withWaitsOf(c.plan(), "consume", [](std::vector<SemaphoreOp>& waits) {
        ASSERT_EQ(waits.size(), 1u);
        waits[0].stages = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    });
    expectHazard(c, broken, "SYNC-HAZARD-READ-AFTER-WRITE");
}

/// An external input, `lut`, read as storage: in GENERAL during the frame, and moved back to
/// SHADER_READ_ONLY_OPTIMAL, its initial state, by a final barrier.
CompiledGraph externalInputReadAsStorage() {
    return compileText(graph(
        R"("lut": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true })",
        R"({ "name": "apply", "type": "Generic", "uses": [
               { "resource": "lut", "access": "Read", "stage": "Compute", "as": "storage" },
               { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] })"));
}

/// The plan without its final barrier for `resource` (there must be one).
Plan withoutFinalBarrierOf(const Plan& plan, const std::string& resource) {
    Plan broken = plan;
    auto& finals = detail::PlanEditor::finalBarriers(broken);
    const auto r = static_cast<uint32_t>(broken.resourceIndex(resource));
    const auto before = finals.size();
    std::erase_if(finals, [&](const Barrier& b) { return b.resource == r; });
    EXPECT_EQ(finals.size(), before - 1) << planToText(plan);
    return broken;
}

// Without the final barrier back, the second frame's barrier transitions the input from a
// layout it is not in.
TEST_F(NegativeControl, DroppedReturnOfAnExternalInputIsAnInvalidLayout) {
    const auto c = externalInputReadAsStorage();
    expectHazard(c, withoutFinalBarrierOf(c.plan(), "lut"), "InvalidImageLayout");
}

// The executor's own check: a plan that says the input ends the frame in GENERAL (as it would
// without the final barrier back) is refused before anything is recorded, naming it.
TEST_F(NegativeControl, APlanLeavingAnExternalInputInAnotherLayoutIsRefused) {
    const auto c = externalInputReadAsStorage();
    Plan broken = withoutFinalBarrierOf(c.plan(), "lut");
    detail::PlanEditor::resources(broken)[static_cast<size_t>(broken.resourceIndex("lut"))].finalLayout =
        VK_IMAGE_LAYOUT_GENERAL;
    try {
        Renderer r(sharedDevice(), detail::CompiledGraphAccess::withPlan(c, broken), genericOptions());
        FAIL() << "a plan leaving 'lut' in GENERAL was installed";
    } catch (const ExecutorError& e) {
        const std::string what = e.what();
        EXPECT_TRUE(what.starts_with("resource 'lut'")) << what;
        EXPECT_NE(what.find("VK_IMAGE_LAYOUT_GENERAL"), std::string::npos) << what;
    }
}

// RAW: compute writes a storage buffer, the next compute pass reads it.
TEST_F(NegativeControl, DroppedRawBarrierIsReadAfterWrite) {
    const auto c = compileText(graph(
        R"("buf": { "type": "buffer", "size": 256 })",
        R"({ "name": "produce", "type": "Generic", "uses": { "buf": "Write@Compute" } },
           { "name": "consume", "type": "Generic",
             "uses": { "buf": "Read@Compute", "swapchain": "Write@Transfer" } })"));
    Plan broken = c.plan();
    dropBarrier(broken, "consume", "buf");
    expectHazard(c, broken, "SYNC-HAZARD-READ-AFTER-WRITE");
}

// A storage usage of several mips performs every level (one view per mip): dropping the
// barrier that makes the write of mip 1 visible to a read of mips [0, 2) is caught. Before the
// Generic pass bound one view per mip, only the base mip was read and this went unnoticed.
TEST_F(NegativeControl, DroppedBarrierOfAnUpperMipOfAStorageReadIsReadAfterWrite) {
    const auto c = compileText(graph(
        R"("chain": { "type": "image2d", "format": "R32_UINT", "extent": [16, 16], "mips": 2,
                      "clear": { "color": [1, 1, 1, 1] } })",
        R"({ "name": "produce", "type": "Generic",
             "uses": [ { "resource": "chain", "access": "Write", "stage": "Compute", "mips": [1, 1] } ] },
           { "name": "consume", "type": "Generic",
             "uses": [ { "resource": "chain", "access": "Read", "stage": "Compute", "as": "storage", "mips": [0, 2] },
                       { "resource": "swapchain", "access": "Write", "stage": "Transfer" } ] })"));
    Plan broken = c.plan();
    const int32_t chain = broken.resourceIndex("chain");
    bool dropped = false;
    for (size_t p = 0; p < broken.passes().size() && !dropped; ++p) {
        if (broken.passes()[p].name != "consume") continue;
        const auto barriers = detail::PlanEditor::barriersOf(broken, p);
        for (size_t i = 0; i < barriers.size(); ++i)
            if (int32_t(barriers[i].resource) == chain && barriers[i].range.baseMip == 1) {
                detail::PlanEditor::eraseBarrier(broken, p, i);
                dropped = true;
                break;
            }
    }
    ASSERT_TRUE(dropped) << "no barrier for mip 1 before 'consume':\n" << planToText(c.plan());
    expectHazard(c, broken, "SYNC-HAZARD-READ-AFTER-WRITE");
}

// WAR: compute reads a buffer, the next compute pass overwrites it (execution dependency only).
TEST_F(NegativeControl, DroppedWarBarrierIsWriteAfterRead) {
    const auto c = compileText(graph(
        R"("buf": { "type": "buffer", "size": 256 })",
        R"({ "name": "produce", "type": "Generic", "uses": { "buf": "Write@Compute" } },
           { "name": "read", "type": "Generic", "uses": { "buf": "Read@Compute" }, "never_cull": true },
           { "name": "overwrite", "type": "Generic", "uses": { "buf": "Write@Compute" } },
           { "name": "consume", "type": "Generic",
             "uses": { "buf": "Read@Fragment", "swapchain": "Write@ColorAttachment" } })"));
    Plan broken = c.plan();
    dropBarrier(broken, "overwrite", "buf");
    expectHazard(c, broken, "SYNC-HAZARD-WRITE-AFTER-READ");
}

// Layout transition: a color attachment becomes a sampled image. Without the barrier the
// sampled read races the attachment write.
TEST_F(NegativeControl, DroppedLayoutTransitionIsReadAfterWrite) {
    const auto c = attachmentThenSampled();
    Plan broken = c.plan();
    Barrier* b = barrierOf(broken, "sample", "tex");
    ASSERT_NE(b, nullptr);
    ASSERT_NE(b->oldLayout, b->newLayout) << "the control needs a layout transition";
    dropBarrier(broken, "sample", "tex");
    expectHazard(c, broken, "SYNC-HAZARD-READ-AFTER-WRITE");
}

// A layout transition is a write: keeping it but removing its source scope makes it race
// the attachment write before it.
TEST_F(NegativeControl, UnscopedLayoutTransitionIsWriteAfterWrite) {
    const auto c = attachmentThenSampled();
    Plan broken = c.plan();
    Barrier* b = barrierOf(broken, "sample", "tex");
    ASSERT_NE(b, nullptr);
    b->srcStages = VK_PIPELINE_STAGE_2_NONE;
    b->srcAccess = VK_ACCESS_2_NONE;
    expectHazard(c, broken, "SYNC-HAZARD-WRITE-AFTER-WRITE");
}

// WAR through a layout transition: a sampled image is overwritten as an attachment.
TEST_F(NegativeControl, DroppedWarTransitionIsWriteAfterRead) {
    const auto c = compileText(graph(
        R"("tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" },
           "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" })",
        R"({ "name": "draw", "type": "Generic", "uses": { "tex": "Write@ColorAttachment" } },
           { "name": "sample", "type": "Generic",
             "uses": { "tex": "Read@Fragment", "out": "Write@ColorAttachment" } },
           { "name": "redraw", "type": "Generic", "uses": { "tex": "Write@ColorAttachment" } },
           { "name": "show", "type": "Generic",
             "uses": { "tex": "Read@Fragment", "out": "Read@Fragment", "swapchain": "Write@ColorAttachment" } })"));
    Plan broken = c.plan();
    dropBarrier(broken, "redraw", "tex");
    expectHazard(c, broken, "SYNC-HAZARD-WRITE-AFTER-READ");
}

// The setup's mip chain: an uploaded 16x16 texture's levels are downsampled from one another
// by blits. Each blit reads the level the one before wrote; without the barrier between
// (here: the layout transition kept, its source scope emptied) the layer sees the race.
TEST_F(NegativeControl, UnscopedBarrierBetweenTwoDownsamplesIsCaught) {
    const CompiledGraph c = compileText(graph(
        R"("tex": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [16, 16], "mips": "full",
                    "external": true, "initial": "ShaderRead" })",
        R"({ "name": "sample", "type": "Generic", "uses": { "tex": "Read@Fragment", "swapchain": "Write@ColorAttachment" } })"));
    ImageData pixels;
    pixels.width = pixels.height = 16;
    pixels.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    pixels.rgba.assign(16 * 16 * 4, 0.25f);
    const auto run = [&](bool weaken) {
        Renderer r(sharedDevice(), c, genericOptions());
        if (weaken)
            RendererAccess::editSetupPlans(r, [](Plan& setup) {
                for (size_t p = 0; p < setup.passes().size(); ++p)
                    if (setup.passes()[p].name == "downsample tex to mip 2") {
                        Barrier& raw = detail::PlanEditor::barriersOf(setup, p)[1];  // mip 1, written just before
                        raw.srcStages = VK_PIPELINE_STAGE_2_NONE;
                        raw.srcAccess = VK_ACCESS_2_NONE;
                    }
            });
        r.setExternalImage("tex", pixels);
        r.renderFrame();
        r.waitIdle();
        EXPECT_EQ(r.setupPlan().passes().size() > 4, true) << "upload and four downsamples";
    };
    run(false);
    ASSERT_EQ(sharedDevice().messageCount(), 0u) << "the intact setup must be clean:\n" << formatMessages(sharedDevice());
    allowMessages();
    run(true);
    EXPECT_TRUE(sharedDevice().hasMessage("SYNC-HAZARD-WRITE-AFTER-WRITE"))
        << "expected the transition to race the blit that wrote mip 1; got:\n" << formatMessages(sharedDevice());
}

TEST_F(NegativeControl, UnscopedBarrierInAModelTexturesMipChainIsCaught) {
    // The forward pass fills a glTF model's textures with the compiler's steps
    // (planSampledImageUploads) in the frame that first draws it.
    const PassLibrary library = PassLibrary::withBuiltins();
    const Scene scene = loadSceneFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "tests/passes/scenes/box_textured_gltf.json");
    GraphDesc g = loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs/raster.json", library.registry());
    CompileOptions co = sizedOptions();
    co.features = sceneFeatures(scene);
    co = headless(g, std::move(co));
    const CompiledGraph c(std::move(g), std::move(co));
    const auto run = [&](bool weaken) {
        RendererOptions ro;
        ro.passes = &library;
        Renderer r(sharedDevice(), c, ro);
        bool edited = false;
        if (weaken)
            RendererAccess::editSampledImagePlans(r, [&](Plan& fill) {
                for (size_t p = 0; p < fill.passes().size(); ++p)
                    if (fill.passes()[p].name.find("to mip 2") != std::string_view::npos && !edited) {
                        Barrier& raw = detail::PlanEditor::barriersOf(fill, p)[1];  // mip 1, written just before
                        raw.srcStages = VK_PIPELINE_STAGE_2_NONE;
                        raw.srcAccess = VK_ACCESS_2_NONE;
                        edited = true;
                    }
            });
        r.frameData().set(scene);
        r.renderFrame();
        r.waitIdle();
        EXPECT_EQ(edited, weaken) << "a texture with at least three mips";
    };
    run(false);
    ASSERT_EQ(sharedDevice().messageCount(), 0u) << "the intact fill must be clean:\n" << formatMessages(sharedDevice());
    allowMessages();
    run(true);
    EXPECT_TRUE(sharedDevice().hasMessage("SYNC-HAZARD-WRITE-AFTER-WRITE"))
        << "expected the transition to race the blit that wrote mip 1; got:\n" << formatMessages(sharedDevice());
}


/// Renders attachmentThenSampled() without the barrier before "sample": messages that no
/// test's own check sees, as a suite's SetUpTestSuite or a plain TEST would leave them.
void leaveAHazardBehind() {
    const CompiledGraph c = attachmentThenSampled();
    Plan broken = c.plan();
    dropBarrier(broken, "sample", "tex");
    Renderer r(sharedDevice(), detail::CompiledGraphAccess::withPlan(c, broken), genericOptions());
    for (int i = 0; i < 2; ++i) r.renderFrame();
    r.waitIdle();
}

/// The fixture's own check can fail: messages left by work outside any test's check fail the
/// next test's SetUp, and are cleared for it.
TEST(ExecutorTestFixture, MessagesLeftBeforeATestFailItsSetUp) {
    leaveAHazardBehind();
    ASSERT_GT(sharedDevice().messageCount(), 0u) << "the dropped barrier must be reported";
    struct NextTest : ExecutorTest {
        void TestBody() override {}
        void setUp() { SetUp(); }
    };
    EXPECT_NONFATAL_FAILURE(NextTest().setUp(), "messages from work before this test");
    EXPECT_EQ(sharedDevice().messageCount(), 0u);
}

/// Only the layer's advice for a copy that reads in GENERAL is explained by the layouts
/// policies; the explanation is checked against the device's real warning text.
TEST_F(ExecutorTest, ACopyReadingInGeneralIsTheOnlyExplainedPerformanceWarning) {
    // A copy and a sampler read one image with no write between: under fewest-barriers the
    // run stays in GENERAL, and the layer advises TRANSFER_SRC_OPTIMAL for the copy.
    const CompiledGraph c = compileText(graph(
        R"("img":  { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" },
           "copy": { "type": "buffer", "size": 4096 })",
        R"({ "name": "produce", "type": "Generic", "uses": { "img": "Write@Compute" } },
           { "name": "copy_out", "type": "Generic", "never_cull": true, "uses": { "img": "Read@Transfer", "copy": "Write@Transfer" } },
           { "name": "sample", "type": "Generic", "uses": { "img": "Read@Fragment", "swapchain": "Write@ColorAttachment" } })"));
    {
        Renderer r(sharedDevice(), c, genericOptions());
        r.renderFrame();
        r.waitIdle();
    }
    ASSERT_GT(sharedDevice().performanceWarningCount(), 0u) << "the layer no longer advises on a copy in GENERAL";
    EXPECT_EQ(unexplainedPerformanceWarnings(sharedDevice()), "");
}

}  // namespace
}  // namespace skygraph::test
