// Passes on several queues (docs/queues.md), each expectation written out by hand from the
// Vulkan 1.3 memory model: a semaphore signal's first scope holds the signalling queue's
// earlier work at its stages and makes every write available; a wait's second scope holds
// the waiting queue's later work at its stages (vkQueueSubmit2) and makes them visible there
// (§7.4); an exclusive resource that keeps its contents across queue families moves with a
// release on the old family's queue and an identical acquire on the new one, the layout
// transition happening once between them (§7.7.4); a transition from UNDEFINED discards the
// contents and needs no transfer.
#include <skygraph/compiler.hpp>
#include <skygraph/diagnostics.hpp>
#include <skygraph/plan_format.hpp>

#include "plan_queries.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <span>
#include <string>

namespace skygraph {
namespace {

using test::barriersOf;
using test::registry;

constexpr VkPipelineStageFlags2 kAll = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
constexpr VkPipelineStageFlags2 kCompute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkPipelineStageFlags2 kFragment = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;

std::string graphText(const std::string& resources, const std::string& passes) {
    return R"({"version": 1, "name": "q", "resources": {)" + resources + R"(}, "passes": [)" + passes + "]}";
}

Plan compileText(const std::string& json, std::array<uint32_t, kQueueKinds> families = {0, 1, 2}) {
    CompileOptions o;
    o.queueFamilies = families;
    o.outputWidth = o.outputHeight = 16;
    return compile(parseGraph(json, "<test>", registry()), o);
}

/// The submit that holds pass `name`.
const Submit& submitOf(const Plan& plan, const std::string& name) {
    for (const Submit& s : plan.submits())
        for (uint32_t p : s.passes)
            if (plan.passes()[p].name == name) return s;
    throw std::runtime_error("no submit holds " + name);
}

const std::string kAoThenShade = graphText(
    R"("ao": {"type": "image2d", "format": "R8_UNORM", "extent": [16, 16]},
       "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true, "final": "TransferSrc"})",
    R"({"name": "ao", "type": "Generic", "queue": "compute", "uses": {"ao": "Write@Compute"}},
       {"name": "shade", "type": "Generic", "uses": {"ao": "Read@Fragment", "out": "Write@ColorAttachment"}})");

TEST(QueueRules, ComputeToGraphicsReadAfterWriteWaitsAndTransfersOwnership) {
    const Plan plan = compileText(kAoThenShade);
    SCOPED_TRACE(planToText(plan));
    ASSERT_EQ(plan.submits().size(), 4u);  // frame start, ao, shade, frame end
    // The frame starts on the graphics queue; the compute queue's first submit waits for it.
    EXPECT_EQ(plan.submits()[0].queue, QueueKind::Graphics);
    EXPECT_TRUE(plan.submits()[0].passes.empty());
    ASSERT_EQ(plan.submits()[0].signals.size(), 1u);
    EXPECT_EQ(plan.submits()[0].signals[0], (SemaphoreOp{QueueKind::Graphics, 1, kAll}));
    const Submit& ao = submitOf(plan, "ao");
    EXPECT_EQ(ao.queue, QueueKind::Compute);
    ASSERT_EQ(ao.waits.size(), 1u);
    EXPECT_EQ(ao.waits[0], (SemaphoreOp{QueueKind::Graphics, 1, kAll}));
    // The release: after ao's storage write, GENERAL -> SHADER_READ_ONLY, no destination.
    ASSERT_EQ(ao.releases.size(), 1u);
    const Barrier& release = ao.releases[0];
    EXPECT_EQ(release.srcQueue, QueueKind::Compute);
    EXPECT_EQ(release.dstQueue, QueueKind::Graphics);
    EXPECT_EQ(release.srcStages, kCompute);
    EXPECT_EQ(release.srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(release.dstStages, 0u);
    EXPECT_EQ(release.dstAccess, 0u);
    EXPECT_EQ(release.oldLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(release.newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    // ao is the compute queue's last pass: the frame's end waits for all of it.
    ASSERT_EQ(ao.signals.size(), 1u);
    EXPECT_EQ(ao.signals[0], (SemaphoreOp{QueueKind::Compute, 1, kAll}));
    // shade waits where it samples ao, then acquires it with the same layouts.
    const Submit& shade = submitOf(plan, "shade");
    ASSERT_EQ(shade.waits.size(), 1u);
    EXPECT_EQ(shade.waits[0], (SemaphoreOp{QueueKind::Compute, 1, kFragment}));
    const auto acquire = barriersOf(plan, "shade", "ao");
    ASSERT_EQ(acquire.size(), 1u);
    EXPECT_EQ(acquire[0].srcQueue, QueueKind::Compute);
    EXPECT_EQ(acquire[0].dstQueue, QueueKind::Graphics);
    EXPECT_EQ(acquire[0].oldLayout, release.oldLayout);
    EXPECT_EQ(acquire[0].newLayout, release.newLayout);
    EXPECT_EQ(acquire[0].range, release.range);
    EXPECT_EQ(acquire[0].dstStages, kFragment);
    EXPECT_EQ(acquire[0].dstAccess, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    EXPECT_EQ(acquire[0].srcStages & kFragment, kFragment) << "the wait's stages chain into the transition";
    EXPECT_NE(acquire[0].srcAccess & VK_ACCESS_2_MEMORY_READ_BIT, 0u);
    // The frame ends on the graphics queue after everything on the compute queue.
    const Submit& end = plan.submits().back();
    EXPECT_TRUE(end.passes.empty());
    ASSERT_EQ(end.waits.size(), 1u);
    EXPECT_EQ(end.waits[0], (SemaphoreOp{QueueKind::Compute, 1, kAll}));
}

TEST(QueueRules, OneQueueFamilyKeepsTheSemaphoresAndDropsTheTransfers) {
    const Plan plan = compileText(kAoThenShade, {0, 0, 0});
    SCOPED_TRACE(planToText(plan));
    EXPECT_EQ(plan.submits().size(), 4u);
    EXPECT_TRUE(submitOf(plan, "ao").releases.empty());
    const auto b = barriersOf(plan, "shade", "ao");
    ASSERT_EQ(b.size(), 1u);
    EXPECT_FALSE(b[0].transfersOwnership());
    // The transition happens on the graphics queue after the wait.
    EXPECT_EQ(b[0].oldLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(b[0].newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(submitOf(plan, "shade").waits[0], (SemaphoreOp{QueueKind::Compute, 1, kFragment}));
}

TEST(QueueRules, GraphicsToComputeWriteAfterReadWaitsWithoutATransfer) {
    const Plan plan = compileText(graphText(
        R"("tex": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true, "final": "General"})",
        R"({"name": "sample", "type": "Generic", "uses": {"tex": "Read@Fragment"}, "never_cull": true},
           {"name": "rewrite", "type": "Generic", "queue": "compute", "uses": {"tex": "Write@Compute"}})"));
    SCOPED_TRACE(planToText(plan));
    // rewrite waits for sample's read (execution only) where it writes.
    const Submit& rewrite = submitOf(plan, "rewrite");
    ASSERT_EQ(rewrite.waits.size(), 1u);
    EXPECT_EQ(rewrite.waits[0].semaphore, QueueKind::Graphics);
    EXPECT_EQ(rewrite.waits[0].stages, kAll) << "merged with the wait for the frame's start";
    // The compute queue's first wait also stands for the frame's start: all stages.
    const Submit& sample = submitOf(plan, "sample");
    ASSERT_EQ(sample.signals.size(), 1u);
    EXPECT_EQ(sample.signals[0].stages, kAll);
    EXPECT_EQ(rewrite.waits[0].value, sample.signals[0].value);
    // A Write discards the contents (UNDEFINED -> GENERAL): no ownership transfer.
    const auto b = barriersOf(plan, "rewrite", "tex");
    ASSERT_EQ(b.size(), 1u);
    EXPECT_FALSE(b[0].transfersOwnership());
    EXPECT_EQ(b[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(b[0].newLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(b[0].srcStages & ~(kCompute | VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT), 0u)
        << "a compute queue's barrier keeps only stages the compute queue has";
    // tex is external: the frame hands it back to the graphics family at its end.
    bool handedBack = false;
    for (const Barrier& f : plan.finalBarriers())
        handedBack |= plan.resources()[f.resource].name == "tex" && f.srcQueue == QueueKind::Compute &&
                      f.dstQueue == QueueKind::Graphics;
    EXPECT_TRUE(handedBack);
    bool released = false;
    for (const Barrier& r : rewrite.releases)
        released |= plan.resources()[r.resource].name == "tex" && r.srcQueue == QueueKind::Compute;
    EXPECT_TRUE(released);
}

TEST(QueueRules, TransferQueueUploadIsWaitedForWhereItIsRead) {
    const Plan plan = compileText(graphText(
        R"("verts": {"type": "buffer", "size": 4096},
           "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true, "final": "TransferSrc"})",
        R"({"name": "upload", "type": "Generic", "queue": "transfer", "uses": {"verts": "Write@Transfer"}},
           {"name": "draw", "type": "Generic", "uses": {"verts": "Read@VertexInput", "out": "Write@ColorAttachment"}})"));
    SCOPED_TRACE(planToText(plan));
    const uint32_t verts = static_cast<uint32_t>(plan.resourceIndex("verts"));
    EXPECT_TRUE(plan.concurrent(verts)) << "buffers default to concurrent sharing";
    EXPECT_TRUE(submitOf(plan, "upload").releases.empty());
    const Submit& draw = submitOf(plan, "draw");
    ASSERT_EQ(draw.waits.size(), 1u);
    EXPECT_EQ(draw.waits[0].semaphore, QueueKind::Transfer);
    EXPECT_EQ(draw.waits[0].stages, VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT);
    EXPECT_EQ(submitOf(plan, "upload").waits[0], (SemaphoreOp{QueueKind::Graphics, 1, kAll}));
}

TEST(QueueRules, ExclusiveImageChangesFamilyBothWays) {
    const Plan plan = compileText(graphText(
        R"("img": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16]},
           "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true, "final": "TransferSrc"})",
        R"({"name": "draw", "type": "Generic", "uses": {"img": "Write@ColorAttachment"}},
           {"name": "blur", "type": "Generic", "queue": "compute", "uses": {"img": "ReadWrite@Compute"}},
           {"name": "show", "type": "Generic", "uses": {"img": "Read@Fragment", "out": "Write@ColorAttachment"}})"));
    SCOPED_TRACE(planToText(plan));
    EXPECT_FALSE(plan.concurrent(static_cast<uint32_t>(plan.resourceIndex("img"))));
    // graphics -> compute: released after draw, acquired before blur, COLOR_ATTACHMENT -> GENERAL.
    const Submit& draw = submitOf(plan, "draw");
    ASSERT_EQ(draw.releases.size(), 1u);
    EXPECT_EQ(draw.releases[0].srcQueue, QueueKind::Graphics);
    EXPECT_EQ(draw.releases[0].srcStages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
    EXPECT_EQ(draw.releases[0].srcAccess, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    const auto toCompute = barriersOf(plan, "blur", "img");
    ASSERT_EQ(toCompute.size(), 1u);
    EXPECT_EQ(toCompute[0].srcQueue, QueueKind::Graphics);
    EXPECT_EQ(toCompute[0].dstQueue, QueueKind::Compute);
    EXPECT_EQ(toCompute[0].oldLayout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    EXPECT_EQ(toCompute[0].newLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(draw.releases[0].oldLayout, toCompute[0].oldLayout);
    EXPECT_EQ(draw.releases[0].newLayout, toCompute[0].newLayout);
    // blur's wait is the compute queue's first: it also stands for the frame's start (every
    // earlier access of the graphics queue), so the signal it waits for holds every stage.
    ASSERT_EQ(draw.signals.size(), 1u);
    EXPECT_EQ(draw.signals[0].stages, kAll);
    // compute -> graphics: released after blur, acquired before show, GENERAL -> SHADER_READ_ONLY.
    const Submit& blur = submitOf(plan, "blur");
    ASSERT_EQ(blur.releases.size(), 1u);
    EXPECT_EQ(blur.releases[0].srcQueue, QueueKind::Compute);
    EXPECT_EQ(blur.releases[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    const auto toGraphics = barriersOf(plan, "show", "img");
    ASSERT_EQ(toGraphics.size(), 1u);
    EXPECT_EQ(toGraphics[0].srcQueue, QueueKind::Compute);
    EXPECT_EQ(toGraphics[0].dstQueue, QueueKind::Graphics);
    EXPECT_EQ(toGraphics[0].oldLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(toGraphics[0].newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(blur.releases[0].newLayout, toGraphics[0].newLayout);
    ASSERT_EQ(submitOf(plan, "show").waits.size(), 1u);
    EXPECT_EQ(submitOf(plan, "show").waits[0].semaphore, QueueKind::Compute);
    EXPECT_EQ(submitOf(plan, "show").waits[0].stages, kFragment);
}

// An exclusive image whose first pass, on the compute queue, uses one of its mips: the
// aliasing barrier there moves every mip from UNDEFINED, so the compute family owns the others
// too, unused. Their release went to the frame's start, a graphics submit, where a release
// from the compute family cannot be recorded (§7.7.4: on a queue of the source family); it
// follows the barrier on the compute queue instead.
TEST(QueueRules, AReleaseIsRecordedOnTheQueueOfTheFamilyThatOwnsTheResource) {
    const Plan plan = compileText(graphText(
        R"("img": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "mips": 2})",
        R"({"name": "mip0", "type": "Generic", "queue": "compute", "never_cull": true,
            "uses": [{"resource": "img", "access": "Write", "stage": "Compute", "mips": [0, 1]}]},
           {"name": "all", "type": "Generic", "never_cull": true, "uses": {"img": "Write@Compute"}})"));
    SCOPED_TRACE(planToText(plan));
    size_t releases = 0;
    for (const Submit& s : plan.submits())
        for (const Barrier& b : s.releases) {
            EXPECT_EQ(b.srcQueue, s.queue) << "a release from the " << toString(b.srcQueue) << " family on the "
                                           << toString(s.queue) << " queue";
            ++releases;
        }
    const Submit& mip0 = submitOf(plan, "mip0");
    ASSERT_EQ(mip0.releases.size(), 2u);  // each mip: a transfer per barrier range
    for (const Barrier& b : mip0.releases) {
        EXPECT_EQ(b.srcQueue, QueueKind::Compute);
        EXPECT_EQ(b.dstQueue, QueueKind::Graphics);
        EXPECT_EQ(b.srcStages, kCompute);
    }
    EXPECT_EQ(releases, 2u);
    // The graphics submit that acquires them waits for the compute queue's signal after mip0.
    const Submit& all = submitOf(plan, "all");
    ASSERT_EQ(all.waits.size(), 1u);
    EXPECT_EQ(all.waits[0].semaphore, QueueKind::Compute);
    ASSERT_EQ(mip0.signals.size(), 1u);
    EXPECT_EQ(all.waits[0].value, mip0.signals[0].value);
}

// An acquire is all that orders the acquiring queue's later work after a transfer (§7.7.4:
// through its second synchronization scope). Handed back to the graphics family at the frame's
// end, an exclusive input already in its final layout got an acquire that waited in no stage,
// so the next frame's sampling on the graphics queue raced it; it now waits where the state it
// is left in is used. Within the frame, an acquire for the first of a run of reads on its queue
// waits for the later readers of the run too, as they share its barrier.
TEST(QueueRules, AnAcquireWaitsWhereItsQueueUsesTheResourceNext) {
    const Plan handBack = compileText(graphText(
        R"("tex": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true,
                   "initial": "ShaderRead", "sharing": "exclusive"},
           "a": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true,
                 "final": "ShaderRead"},
           "b": {"type": "buffer", "size": 64, "external": true, "final": "General"})",
        R"({"name": "draw", "type": "Generic", "uses": {"tex": "Read@Fragment", "a": "Write@ColorAttachment"}},
           {"name": "reduce", "type": "Generic", "queue": "compute", "uses": {"tex": "Read@Compute", "b": "Write@Compute"}})"));
    SCOPED_TRACE(planToText(handBack));
    const auto finals = handBack.finalBarriers();
    const auto tex = std::find_if(finals.begin(), finals.end(), [&](const Barrier& b) {
        return handBack.resources()[b.resource].name == "tex" && b.transfersOwnership();
    });
    ASSERT_NE(tex, finals.end());
    EXPECT_EQ(tex->srcQueue, QueueKind::Compute);
    EXPECT_EQ(tex->dstStages, kFragment | kCompute);
    EXPECT_EQ(tex->dstAccess, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);

    const Plan run = compileText(graphText(
        R"("img": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "sharing": "exclusive"},
           "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true, "final": "TransferSrc"})",
        R"({"name": "draw", "type": "Generic", "uses": {"img": "Write@ColorAttachment"}},
           {"name": "measure", "type": "Generic", "queue": "compute", "never_cull": true, "uses": {"img": "Read@Compute"}},
           {"name": "cull", "type": "Generic", "never_cull": true, "uses": {"img": "Read@Compute"}},
           {"name": "show", "type": "Generic", "uses": {"img": "Read@Fragment", "out": "Write@ColorAttachment"}})"));
    SCOPED_TRACE(planToText(run));
    const auto acquire = barriersOf(run, "cull", "img");
    ASSERT_EQ(acquire.size(), 1u);
    EXPECT_TRUE(acquire[0].transfersOwnership());
    EXPECT_EQ(acquire[0].dstStages, kCompute | kFragment);
}

// External resources are owned by the graphics family between frames: used on the compute
// queue alone, they still change family at the frame's start and back at its end (an image
// written from UNDEFINED needs no acquire: its contents are discarded).
TEST(QueueRules, AnExternalResourceUsedOnlyOffTheGraphicsQueueChangesFamilyBothWays) {
    const Plan plan = compileText(graphText(
        R"("buf": {"type": "buffer", "size": 256, "external": true, "final": "ShaderRead"},
           "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true, "final": "TransferSrc"})",
        R"({"name": "a", "type": "Generic", "queue": "compute", "uses": {"buf": "Read@Compute", "out": "Write@Compute"}})"));
    const auto transfer = [&](std::span<const Barrier> barriers, const char* name, QueueKind from, QueueKind to) {
        return std::any_of(barriers.begin(), barriers.end(), [&](const Barrier& b) {
            return plan.resources()[b.resource].name == name && b.transfersOwnership() && b.srcQueue == from &&
                   b.dstQueue == to;
        });
    };
    EXPECT_TRUE(transfer(plan.passes()[0].barriers, "buf", QueueKind::Graphics, QueueKind::Compute));
    EXPECT_FALSE(transfer(plan.passes()[0].barriers, "out", QueueKind::Graphics, QueueKind::Compute));
    for (const char* name : {"buf", "out"})
        EXPECT_TRUE(transfer(plan.finalBarriers(), name, QueueKind::Compute, QueueKind::Graphics)) << name;
    EXPECT_FALSE(plan.concurrent(0));
    // One family: nothing to transfer.
    const Plan one = compileText(graphText(
        R"("buf": {"type": "buffer", "size": 256, "external": true, "final": "ShaderRead"})",
        R"({"name": "a", "type": "Generic", "queue": "compute", "uses": {"buf": "Read@Compute"}})"), {0, 0, 0});
    for (const Barrier& b : one.finalBarriers()) EXPECT_FALSE(b.transfersOwnership());
}

TEST(QueueRules, ConcurrentSharingReplacesTheTransfersWithSemaphoresOnly) {
    const Plan plan = compileText(graphText(
        R"("img": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "sharing": "concurrent"},
           "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true, "final": "TransferSrc"})",
        R"({"name": "draw", "type": "Generic", "uses": {"img": "Write@ColorAttachment"}},
           {"name": "blur", "type": "Generic", "queue": "compute", "uses": {"img": "ReadWrite@Compute"}},
           {"name": "show", "type": "Generic", "uses": {"img": "Read@Fragment", "out": "Write@ColorAttachment"}})"));
    SCOPED_TRACE(planToText(plan));
    EXPECT_TRUE(plan.concurrent(static_cast<uint32_t>(plan.resourceIndex("img"))));
    for (const Submit& s : plan.submits()) EXPECT_TRUE(s.releases.empty());
    EXPECT_FALSE(barriersOf(plan, "blur", "img").at(0).transfersOwnership());
    ASSERT_FALSE(submitOf(plan, "show").waits.empty());
    EXPECT_EQ(submitOf(plan, "show").waits[0].semaphore, QueueKind::Compute);
}

TEST(QueueRules, AllGraphicsPlanIsOneSubmitWithoutSemaphores) {
    const Plan plan = compileText(graphText(
        R"("out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true, "final": "TransferSrc"})",
        R"({"name": "draw", "type": "Generic", "uses": {"out": "Write@ColorAttachment"}})"));
    ASSERT_EQ(plan.submits().size(), 1u);
    EXPECT_TRUE(plan.submits()[0].waits.empty());
    EXPECT_TRUE(plan.submits()[0].signals.empty());
    EXPECT_EQ(plan.submits()[0].passes.size(), plan.passes().size());
}

/// The GraphError's one diagnostic.
Diagnostic errorOf(const std::string& json) {
    try {
        (void)parseGraph(json, "queues.json", registry());
    } catch (const GraphError& e) {
        EXPECT_EQ(e.diagnostics().size(), 1u) << e.what();
        return e.diagnostics().items().at(0);
    }
    ADD_FAILURE() << "no error";
    return {};
}

TEST(QueueRules, AQueueThatCannotPerformAUsageIsRefusedNamingPassQueueAndResource) {
    const Diagnostic d = errorOf(graphText(
        R"("out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true, "final": "TransferSrc"})",
        R"({"name": "draw", "type": "Generic", "queue": "compute", "uses": {"out": "Write@ColorAttachment"}})"));
    EXPECT_EQ(d.file, "queues.json");
    EXPECT_EQ(d.jsonPath, "passes[0].queue");
    EXPECT_EQ(d.pass, "draw");
    EXPECT_EQ(d.resource, "out");
    EXPECT_NE(d.message.find("runs on the compute queue"), std::string::npos) << d.message;
    EXPECT_NE(d.message.find("needs the graphics queue"), std::string::npos) << d.message;
}

TEST(QueueRules, EveryUsageTheQueueCannotPerformIsNamed) {
    try {
        (void)parseGraph(graphText(R"("out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16],
                                              "external": true, "final": "TransferSrc"},
                                      "buf": {"type": "buffer", "size": 64, "external": true})",
                                   R"({"name": "draw", "type": "Generic", "queue": "transfer",
                                       "uses": {"buf": "Read@Compute", "out": "Write@ColorAttachment"}})"),
                         "queues.json", registry());
        FAIL() << "no error";
    } catch (const GraphError& e) {
        ASSERT_EQ(e.diagnostics().size(), 2u) << e.what();
        EXPECT_EQ(e.diagnostics().items()[0].resource, "buf") << e.what();
        EXPECT_EQ(e.diagnostics().items()[1].resource, "out") << e.what();
    }
}

TEST(QueueRules, TheTransferQueueTakesCopiesOnly) {
    const Diagnostic d = errorOf(graphText(R"("buf": {"type": "buffer", "size": 64})",
                                           R"({"name": "fill", "type": "Generic", "queue": "transfer", "never_cull": true,
                                               "uses": {"buf": "Write@Compute"}})"));
    EXPECT_EQ(d.jsonPath, "passes[0].queue");
    EXPECT_NE(d.message.find("needs the compute queue or the graphics queue"), std::string::npos) << d.message;
}

TEST(QueueRules, CopiesOfADepthImageOffTheGraphicsQueueAreRefused) {
    const Diagnostic d = errorOf(graphText(
        R"("depth": {"type": "image2d", "format": "D32_SFLOAT", "extent": [16, 16], "external": true, "final": "TransferSrc"})",
        R"({"name": "copy", "type": "Generic", "queue": "compute", "uses": {"depth": "ReadWrite@Transfer"}})"));
    EXPECT_EQ(d.jsonPath, "passes[0].queue");
    EXPECT_EQ(d.resource, "depth");
    EXPECT_NE(d.message.find("need the graphics queue"), std::string::npos) << d.message;
}

TEST(QueueRules, AnUnknownQueueIsRefused) {
    const Diagnostic d = errorOf(graphText(R"("buf": {"type": "buffer", "size": 64})",
                                           R"({"name": "fill", "type": "Generic", "queue": "video", "never_cull": true,
                                               "uses": {"buf": "Write@Transfer"}})"));
    EXPECT_EQ(d.jsonPath, "passes[0].queue");
    EXPECT_NE(d.message.find("\"video\""), std::string::npos) << d.message;
}

TEST(QueueRules, APassTypeMayRefuseAQueue) {
    PassRegistry r = registry();
    PassTypeInfo blit;
    blit.name = "Blit";
    blit.slots = {{"src", Stage::Transfer, {Access::Read}}, {"dst", Stage::Transfer, {Access::Write}}};
    blit.queues = {QueueKind::Graphics};
    r.add(blit);
    try {
        (void)parseGraph(graphText(R"("a": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true},
                                      "b": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true, "final": "TransferSrc"})",
                                   R"({"name": "copy", "type": "Blit", "queue": "transfer", "uses": {"a": "Read@Transfer", "b": "Write@Transfer"}})"),
                         "blit.json", r);
        FAIL() << "no error";
    } catch (const GraphError& e) {
        const Diagnostic& d = e.diagnostics().items().at(0);
        EXPECT_EQ(d.jsonPath, "passes[0].queue");
        EXPECT_EQ(d.pass, "copy");
        EXPECT_NE(d.message.find("records only on: graphics"), std::string::npos) << d.message;
    }
}

TEST(QueueRules, APresentedImageUsedOffTheGraphicsQueueIsRefused) {
    try {
        (void)compileText(graphText(
            R"("swapchain": {"type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true, "final": "Present"})",
            R"({"name": "fill", "type": "Generic", "queue": "compute", "uses": {"swapchain": "Write@Compute"}})"));
        FAIL() << "no error";
    } catch (const GraphError& e) {
        const Diagnostic& d = e.diagnostics().items().at(0);
        EXPECT_EQ(d.pass, "fill");
        EXPECT_EQ(d.resource, "swapchain");
        EXPECT_EQ(d.jsonPath, "passes[0].queue");
    }
}

}  // namespace
}  // namespace skygraph
