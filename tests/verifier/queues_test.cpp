// Plans on several queues: the verifier follows happens-before through semaphore signals and
// waits and through queue family ownership transfers, and catches each of them missing or
// wrong: a dropped wait, a wait at the wrong stages or for a value too low or never signalled,
// a dropped release, an acquire turned into a plain barrier, an acquire that orders nothing.
#include "plan_editor.hpp"
#include "verifier_test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>

namespace skygraph::verifier {
namespace {

using detail::PlanEditor;
using test::hasFinding;
using test::stepIndex;
using test::submitOf;

test::Compiled async(std::array<uint32_t, kQueueKinds> families = {0, 1, 2}) {
    CompileOptions o;
    o.queueFamilies = families;
    return test::compileShipped("async.json", o);
}

bool anyFinding(const VerificationReport& r, std::initializer_list<FindingKind> kinds, const char* resource) {
    return std::any_of(kinds.begin(), kinds.end(), [&](FindingKind k) { return hasFinding(r, k, resource); });
}

TEST(Queues, AsyncFrameVerifiesWithSeparateFamiliesAndWithOne) {
    for (const auto& families : {std::array<uint32_t, kQueueKinds>{0, 1, 2}, std::array<uint32_t, kQueueKinds>{0, 0, 0}}) {
        const test::Compiled c = async(families);
        ASSERT_GT(c.plan.submits().size(), 3u);
        const VerificationReport r = verifyPlan(c.plan, c.graph);
        EXPECT_TRUE(r.ok()) << r.summary();
    }
}

TEST(Queues, DroppedWaitIsCaught) {
    // sky (graphics) reads depth after ssao (compute) moved it to DEPTH_READ_ONLY.
    test::Compiled c = async();
    auto submits = PlanEditor::submits(c.plan);
    auto& waits = submits.at(submitOf(c.plan, stepIndex(c.plan, "sky"))).waits;
    ASSERT_EQ(waits.size(), 1u);
    waits.clear();
    PlanEditor::setSubmits(c.plan, submits);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(anyFinding(r, {FindingKind::Unordered, FindingKind::NotVisible}, "depth")) << r.summary();
}

TEST(Queues, WaitAtTheWrongStageIsCaught) {
    // The graphics queue's waits at COLOR_ATTACHMENT_OUTPUT only: lighting's reads at
    // FRAGMENT_SHADER, logically earlier, are not held back (a wait at EARLY_FRAGMENT_TESTS, as
    // sky's, or VERTEX_SHADER would hold them: later stages wait too).
    test::Compiled c = async();
    auto submits = PlanEditor::submits(c.plan);
    for (auto& s : submits)
        if (s.queue == QueueKind::Graphics && !s.passes.empty())
            for (SemaphoreOp& w : s.waits) w.stages = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    PlanEditor::setSubmits(c.plan, submits);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(anyFinding(r, {FindingKind::Unordered, FindingKind::NotVisible}, "ssao")) << r.summary();
    EXPECT_TRUE(anyFinding(r, {FindingKind::Unordered, FindingKind::NotVisible}, "lights")) << r.summary();
    EXPECT_TRUE(anyFinding(r, {FindingKind::Unordered, FindingKind::NotVisible}, "depth")) << r.summary();
}

TEST(Queues, WaitForTooLowAValueIsCaught) {
    // tonemap waits for the histogram's signal (compute=2); compute=1 is ssao's.
    test::Compiled c = async();
    auto submits = PlanEditor::submits(c.plan);
    auto& waits = submits.at(submitOf(c.plan, stepIndex(c.plan, "tonemap"))).waits;
    ASSERT_EQ(waits.size(), 1u);
    ASSERT_EQ(waits[0].value, 2u);
    waits[0].value = 1;
    PlanEditor::setSubmits(c.plan, submits);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(anyFinding(r, {FindingKind::Unordered, FindingKind::NotVisible}, "histogram")) << r.summary();
}

// Values count a frame's signals from 1 on top of the frames before: a wait for 0 is already
// satisfied, so tonemap would race the histogram, and a signal of 0 does not grow. (A wait
// for 0 was linked to the frame's first signal and passed.)
TEST(Queues, WaitForValueZeroAndSignalOfZeroAreCaught) {
    test::Compiled c = async();
    auto submits = PlanEditor::submits(c.plan);
    submits.at(submitOf(c.plan, stepIndex(c.plan, "tonemap"))).waits.at(0).value = 0;
    PlanEditor::setSubmits(c.plan, submits);
    VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(anyFinding(r, {FindingKind::Unordered, FindingKind::NotVisible}, "histogram")) << r.summary();
    EXPECT_GE(r.count(FindingKind::Semaphore), 1u) << r.summary();
    EXPECT_NE(r.summary().find("a wait for value 0 waits for nothing"), std::string::npos) << r.summary();
    // Every value one lower: the compute queue signals 0 first, and its waiters wait for 0.
    test::Compiled lower = async();
    submits = PlanEditor::submits(lower.plan);
    for (auto& s : submits) {
        for (auto& w : s.waits)
            if (w.semaphore == QueueKind::Compute) --w.value;
        for (auto& sg : s.signals)
            if (sg.semaphore == QueueKind::Compute) --sg.value;
    }
    PlanEditor::setSubmits(lower.plan, submits);
    r = verifyPlan(lower.plan, lower.graph);
    EXPECT_NE(r.summary().find("a signal of value 0 does not grow"), std::string::npos) << r.summary();
}

TEST(Queues, WaitForAValueNeverSignalledIsCaught) {
    test::Compiled c = async();
    auto submits = PlanEditor::submits(c.plan);
    submits.at(submitOf(c.plan, stepIndex(c.plan, "tonemap"))).waits.at(0).value = 9;
    PlanEditor::setSubmits(c.plan, submits);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_GE(r.count(FindingKind::Semaphore), 1u) << r.summary();
}

TEST(Queues, DroppedReleaseIsCaught) {
    // ssao moves from the compute family to the graphics family for lighting.
    test::Compiled c = async();
    auto submits = PlanEditor::submits(c.plan);
    auto& releases = submits.at(submitOf(c.plan, stepIndex(c.plan, "ssao"))).releases;
    const auto before = releases.size();
    releases.erase(std::remove_if(releases.begin(), releases.end(),
                                  [&](const Barrier& b) { return c.plan.resources()[b.resource].name == "ssao"; }),
                   releases.end());
    ASSERT_EQ(releases.size() + 1, before);
    PlanEditor::setSubmits(c.plan, submits);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::Ownership, "ssao")) << r.summary();
}

TEST(Queues, AcquireTurnedIntoAPlainBarrierIsCaught) {
    // normals: written on graphics, read by ssao on compute through a transfer.
    test::Compiled c = async();
    const size_t step = stepIndex(c.plan, "ssao");
    bool edited = false;
    for (Barrier& b : PlanEditor::barriersOf(c.plan, step))
        if (c.plan.resources()[b.resource].name == "normals" && b.transfersOwnership()) {
            b.srcQueue = b.dstQueue;
            edited = true;
        }
    ASSERT_TRUE(edited);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::Ownership, "normals")) << r.summary();
}

/// The normals release (graphics -> compute, for ssao) edited by `edit`, and the report.
VerificationReport verifyWithNormalsReleaseEdited(const std::function<void(Barrier&)>& edit) {
    test::Compiled c = async();
    auto submits = PlanEditor::submits(c.plan);
    size_t edited = 0;
    for (auto& s : submits)
        for (Barrier& b : s.releases)
            if (c.plan.resources()[b.resource].name == "normals") {
                EXPECT_EQ(b.oldLayout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
                EXPECT_EQ(b.newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
                edit(b);
                ++edited;
            }
    EXPECT_EQ(edited, 1u);
    PlanEditor::setSubmits(c.plan, submits);
    return verifyPlan(c.plan, c.graph);
}

// The two halves of an ownership transfer name the same layouts and range (§7.7.4): the
// transition happens once, and a release that says otherwise than its acquire leaves the image
// in a layout neither says. The acquire alone is what the rest of the walk follows, so the
// release is compared with it.
TEST(Queues, AReleaseWhoseLayoutsDifferFromItsAcquiresIsCaught) {
    const VerificationReport newLayout =
        verifyWithNormalsReleaseEdited([](Barrier& b) { b.newLayout = VK_IMAGE_LAYOUT_GENERAL; });
    EXPECT_TRUE(hasFinding(newLayout, FindingKind::Ownership, "normals")) << newLayout.summary();

    // A release from a layout the image is not in is also a bad oldLayout of its own.
    const VerificationReport oldLayout =
        verifyWithNormalsReleaseEdited([](Barrier& b) { b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL; });
    EXPECT_TRUE(hasFinding(oldLayout, FindingKind::Ownership, "normals")) << oldLayout.summary();
    EXPECT_TRUE(hasFinding(oldLayout, FindingKind::BadOldLayout, "normals")) << oldLayout.summary();
}

// The release is where the writes before a transfer are made available (§7.7.4: the
// acquire's source access scope is ignored), and its source stages are what the semaphore
// signal after it waits for.
TEST(Queues, AReleaseWhoseSourceScopeMissesTheWritesIsCaught) {
    const VerificationReport noAccess = verifyWithNormalsReleaseEdited([](Barrier& b) { b.srcAccess = 0; });
    EXPECT_TRUE(anyFinding(noAccess, {FindingKind::NotAvailable, FindingKind::NotVisible}, "normals"))
        << noAccess.summary();
    const VerificationReport noStages = verifyWithNormalsReleaseEdited([](Barrier& b) {
        b.srcStages = VK_PIPELINE_STAGE_2_NONE;
        b.srcAccess = 0;
    });
    EXPECT_TRUE(hasFinding(noStages, FindingKind::Unordered, "normals")) << noStages.summary();
}

// A transfer's layout transition happens after the release, so every read before it must be
// in the release's source scope: reads in one layout follow each other with no barrier
// between, and the world outside the frame reads an input in its initial state. Narrowed to
// its last reader's stages (COMPUTE_SHADER), the release of 'tex' leaves the fragment reads,
// the frame's and the outside world's, racing the transition to GENERAL.
TEST(Queues, AReleaseWaitsForEveryReadBeforeTheTransition) {
    CompileOptions o;
    o.queueFamilies = {0, 1, 2};
    const test::Compiled intact = test::compileText(R"({ "version": 1, "name": "reads", "resources": {
        "tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true,
                 "initial": "ShaderRead", "final": "ShaderRead", "sharing": "exclusive" } },
      "passes": [
        { "name": "sample", "type": "Generic", "never_cull": true, "uses": { "tex": "Read@Fragment" } },
        { "name": "reduce", "type": "Generic", "never_cull": true, "uses": { "tex": "Read@Compute" } },
        { "name": "edit", "type": "Generic", "queue": "compute", "uses": { "tex": "ReadWrite@Compute" } } ] })",
                                                    o);
    const VerificationReport clean = verifyPlan(intact.plan, intact.graph);
    EXPECT_TRUE(clean.ok()) << clean.summary();
    const auto isTheRelease = [](const Barrier& b) {
        return b.srcQueue == QueueKind::Graphics && b.oldLayout != b.newLayout;
    };
    size_t releases = 0;
    for (const Submit& s : intact.plan.submits())
        for (const Barrier& b : s.releases)
            if (isTheRelease(b)) {
                ++releases;
                const VkPipelineStageFlags2 readers =
                    VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
                EXPECT_EQ(b.srcStages & readers, readers) << b.srcStages;
            }
    ASSERT_EQ(releases, 1u);

    test::Compiled lastReaderOnly = intact;
    auto submits = PlanEditor::submits(lastReaderOnly.plan);
    for (auto& s : submits)
        for (Barrier& b : s.releases)
            if (isTheRelease(b)) b.srcStages = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    PlanEditor::setSubmits(lastReaderOnly.plan, submits);
    const VerificationReport raced = verifyPlan(lastReaderOnly.plan, lastReaderOnly.graph);
    for (const char* reader : {"sample", "outside the frame"})
        EXPECT_TRUE(std::any_of(raced.findings.begin(), raced.findings.end(), [&](const Finding& f) {
            return f.kind == FindingKind::Unordered && f.earlier.pass == reader;
        })) << reader << "\n" << raced.summary();
}

/// graphs/ibl.json as EnvironmentBaker runs it beside the frames: the equirect copied in on the
/// transfer queue, every other pass on the compute queue, three families.
test::Compiled backgroundBake() {
    GraphDesc graph = loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "ibl.json", test::registry());
    for (PassDesc& pass : graph.passes)
        if (pass.queue == QueueKind::Graphics) pass.queue = QueueKind::Compute;
    CompileOptions o;
    o.features = {{"streamed_equirect", true}};
    o.queueFamilies = {0, 1, 2};
    Plan plan = compile(graph, o);
    return {std::move(graph), std::move(plan)};
}

// Validation layer 1.3.239 reports the acquire of the equirect after the compute queue's wait
// at COMPUTE_SHADER as a write-after-write on separate families (docs/queues.md): the
// verifier is the oracle there, and it must also catch that order missing.
TEST(Queues, TheBackgroundBakesTransferUploadVerifiesAndItsOrderIsChecked) {
    const test::Compiled intact = backgroundBake();
    const size_t upload = stepIndex(intact.plan, "upload_equirect");
    const size_t toCube = stepIndex(intact.plan, "equirect_to_cube");
    ASSERT_EQ(intact.plan.submits()[submitOf(intact.plan, upload)].queue, QueueKind::Transfer);
    ASSERT_EQ(intact.plan.submits()[submitOf(intact.plan, toCube)].queue, QueueKind::Compute);
    const VerificationReport clean = verifyPlan(intact.plan, intact.graph);
    EXPECT_TRUE(clean.ok()) << clean.summary();

    test::Compiled noWait = backgroundBake();
    auto submits = PlanEditor::submits(noWait.plan);
    auto& waits = submits.at(submitOf(noWait.plan, toCube)).waits;
    const auto before = waits.size();
    std::erase_if(waits, [](const SemaphoreOp& w) { return w.semaphore == QueueKind::Transfer; });
    ASSERT_EQ(waits.size() + 1, before);
    PlanEditor::setSubmits(noWait.plan, submits);
    const VerificationReport unordered = verifyPlan(noWait.plan, noWait.graph);
    EXPECT_TRUE(anyFinding(unordered, {FindingKind::Unordered, FindingKind::NotVisible, FindingKind::Ownership},
                           "equirect"))
        << unordered.summary();

    test::Compiled noRelease = backgroundBake();
    submits = PlanEditor::submits(noRelease.plan);
    auto& releases = submits.at(submitOf(noRelease.plan, upload)).releases;
    ASSERT_EQ(releases.size(), 1u);
    releases.clear();
    PlanEditor::setSubmits(noRelease.plan, submits);
    const VerificationReport unreleased = verifyPlan(noRelease.plan, noRelease.graph);
    EXPECT_TRUE(hasFinding(unreleased, FindingKind::Ownership, "equirect")) << unreleased.summary();
}

// The bake's products are exported and used on the compute queue only: the graphics family,
// which owns them between frames, takes them back at the frame's end; an acquire turned into
// a plain barrier there is caught.
TEST(Queues, TheBackgroundBakeHandsItsProductsBackToTheGraphicsFamily) {
    test::Compiled c = backgroundBake();
    for (const char* product : {"environment", "irradiance", "prefiltered", "brdf_lut"}) {
        bool handedBack = false;
        for (const Barrier& b : c.plan.finalBarriers())
            handedBack |= c.plan.resources()[b.resource].name == product && b.transfersOwnership() &&
                          b.srcQueue == QueueKind::Compute && b.dstQueue == QueueKind::Graphics;
        EXPECT_TRUE(handedBack) << product;
    }
    EXPECT_TRUE(verifyPlan(c.plan, c.graph).ok()) << verifyPlan(c.plan, c.graph).summary();
    for (Barrier& b : PlanEditor::finalBarriers(c.plan))
        if (c.plan.resources()[b.resource].name == "environment" && b.transfersOwnership()) b.srcQueue = b.dstQueue;
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(hasFinding(r, FindingKind::Ownership, "environment")) << r.summary();
}

// The halves of a transfer name the same range (§7.7.4): a hand-back release of part of the
// environment cube, its layouts those of the acquire, is caught.
TEST(Queues, AReleaseWhoseRangeAloneDiffersFromItsAcquiresIsCaught) {
    test::Compiled c = backgroundBake();
    size_t edited = 0;
    for (Barrier& b : PlanEditor::finalBarriers(c.plan))
        if (c.plan.resources()[b.resource].name == "environment" && b.transfersOwnership() &&
            b.srcQueue == QueueKind::Compute) {
            ASSERT_EQ(b.range.layerCount, 6u);
            b.range.layerCount = 5;
            ++edited;
        }
    ASSERT_GE(edited, 1u);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    // The sixth layer is left released too; the finding asserted is the halves' disagreement.
    EXPECT_TRUE(std::any_of(r.findings.begin(), r.findings.end(), [](const Finding& f) {
        return f.kind == FindingKind::Ownership && f.reason.find("of one ownership transfer disagree") != std::string::npos &&
               f.earlier.what.find("release") != std::string::npos;
    })) << r.summary();
}

// An acquire is all that orders the acquiring queue's later accesses after a transfer
// (§7.7.4): the verifier models one without a layout transition as an access too, which later
// accesses must follow. An input read last on the compute queue is handed back to the graphics
// family at the frame's end by an acquire alone; with an empty destination scope the next
// frame's graphics read races it, which the verifier did not see while it modelled only
// acquires that change the layout.
TEST(Queues, AnAcquireWithoutATransitionIsAnAccessLaterUsesFollow) {
    CompileOptions o;
    o.queueFamilies = {0, 1, 2};
    test::Compiled c = test::compileText(R"({ "version": 1, "name": "handback", "resources": {
        "tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true,
                 "initial": "ShaderRead", "sharing": "exclusive" },
        "a": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true,
               "final": "ShaderRead" },
        "b": { "type": "buffer", "size": 64, "external": true, "final": "General" } },
      "passes": [
        { "name": "draw", "type": "Generic", "uses": { "tex": "Read@Fragment", "a": "Write@ColorAttachment" } },
        { "name": "reduce", "type": "Generic", "queue": "compute",
          "uses": { "tex": "Read@Compute", "b": "Write@Compute" } } ] })",
                                         o);
    VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(r.ok()) << r.summary();
    bool edited = false;
    for (Barrier& b : PlanEditor::finalBarriers(c.plan))
        if (c.plan.resources()[b.resource].name == "tex" && b.transfersOwnership()) {
            b.dstStages = VK_PIPELINE_STAGE_2_NONE;
            b.dstAccess = VK_ACCESS_2_NONE;
            edited = true;
        }
    ASSERT_TRUE(edited);
    r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(anyFinding(r, {FindingKind::Unordered, FindingKind::NotVisible}, "tex")) << r.summary();
}

// The executor waits for the swapchain's acquire in the submit that has waitsForAcquire (the
// one of the image's first use), not the frame's first: a wait at the wrong stages there is
// not made good by the submits before it and their signals.
TEST(Queues, TheAcquireWaitIsWhereTheSubmitThatWaitsForItIs) {
    const test::Compiled intact = async();
    ASSERT_EQ(intact.plan.presentations().size(), 1u);
    ASSERT_FALSE(intact.plan.submits()[0].waitsForAcquire);
    for (const VkPipelineStageFlags2 stages : {VkPipelineStageFlags2{VK_PIPELINE_STAGE_2_NONE},
                                               VkPipelineStageFlags2{VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT}}) {
        test::Compiled c = intact;
        PlanEditor::presentations(c.plan)[0].acquireWaitStages = stages;
        const VerificationReport r = verifyPlan(c.plan, c.graph);
        EXPECT_TRUE(std::any_of(r.findings.begin(), r.findings.end(), [](const Finding& f) {
            return f.kind == FindingKind::Unordered && f.earlier.pass == "presentation engine";
        })) << "acquireWaitStages " << stages << "\n" << r.summary();
    }
}

// 'buf' moves from the compute family to the graphics family: released after 'a' (compute),
// acquired before 'g' (graphics). Between a release and its acquire no family owns it:
// "access after a release operation has undefined results" (§7.7.4), whoever accesses it.
const char* const kBufferHandedToGraphics = R"({ "version": 1, "name": "handover", "resources": {
    "buf": { "type": "buffer", "size": 256, "sharing": "exclusive" },
    "o0": { "type": "buffer", "size": 256 },
    "o2": { "type": "buffer", "size": 256 },
    "o3": { "type": "buffer", "size": 256 },
    "swapchain": { "type": "image2d", "format": "B8G8R8A8_SRGB", "extent": "output", "external": true,
                   "final": "Present" } },
  "passes": [
    { "name": "a", "type": "Generic", "queue": "compute", "uses": { "buf": "Write@Compute", "o0": "Write@Compute" } },
    { "name": "x", "type": "Generic",
      "uses": [ { "resource": "o0", "access": "Read", "stage": "Fragment", "as": "storage" },
        { "resource": "o2", "access": "Write", "stage": "Fragment", "as": "storage" } ] },
    { "name": "b", "type": "Generic", "queue": "compute",
      "uses": { "BUF_USE": "o2": "Read@Compute", "o3": "Write@Compute" } },
    { "name": "g", "type": "Generic",
      "uses": [ { "resource": "buf", "access": "Read", "stage": "Fragment", "as": "storage" },
        { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] },
    { "name": "h", "type": "Generic",
      "uses": [ { "resource": "o3", "access": "Read", "stage": "Fragment", "as": "storage" },
        { "resource": "swapchain", "access": "ReadWrite", "stage": "ColorAttachment" } ] } ] })";

test::Compiled bufferHandedToGraphics(bool usedByB) {
    std::string json = kBufferHandedToGraphics;
    json.replace(json.find("\"BUF_USE\": "), 11, usedByB ? "\"buf\": \"ReadWrite@Compute\", " : "");
    return test::compileText(json, CompileOptions{});
}

/// Moves the plan's one release of 'buf' to the submit that holds step `to`.
void moveBufferRelease(test::Compiled& c, size_t to) {
    auto submits = PlanEditor::submits(c.plan);
    std::vector<Barrier> moved;
    for (auto& s : submits)
        for (auto it = s.releases.begin(); it != s.releases.end();)
            if (c.plan.resources()[it->resource].name == "buf") {
                moved.push_back(*it);
                it = s.releases.erase(it);
            } else {
                ++it;
            }
    ASSERT_EQ(moved.size(), 1u);
    auto& target = submits.at(submitOf(c.plan, to)).releases;
    target.insert(target.end(), moved.begin(), moved.end());
    PlanEditor::setSubmits(c.plan, submits);
}

/// The handover plan (b using 'buf' or not), which verifies clean, with its release of 'buf'
/// moved to the submit that holds step `to`, and the report.
VerificationReport withBufferReleaseMoved(bool usedByB, const char* to) {
    test::Compiled c = bufferHandedToGraphics(usedByB);
    const VerificationReport clean = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(clean.ok()) << clean.summary();
    EXPECT_NE(submitOf(c.plan, stepIndex(c.plan, "a")), submitOf(c.plan, stepIndex(c.plan, "b")));
    moveBufferRelease(c, stepIndex(c.plan, to));
    return verifyPlan(c.plan, c.graph);
}

// A buffer's release moved to a later compute submit, whose signal g's submit does not wait
// for: the release no longer happens before its acquire, with no transition between them.
TEST(Queues, ABufferReleaseThatDoesNotHappenBeforeItsAcquireIsCaught) {
    const VerificationReport r = withBufferReleaseMoved(false, "b");
    EXPECT_TRUE(std::any_of(r.findings.begin(), r.findings.end(), [](const Finding& f) {
        return f.kind == FindingKind::Unordered && f.resourceNames == std::vector<std::string>{"buf"} &&
               f.earlier.pass == "b" && f.later.pass == "g" &&
               f.reason.find("release does not happen before its acquire") != std::string::npos;
    })) << r.summary();
}

// A buffer's release moved before the compute queue's last use of it: b reads and writes it
// after its family gave it up.
TEST(Queues, AUseAfterTheReleaseIsCaught) {
    const VerificationReport r = withBufferReleaseMoved(true, "a");
    EXPECT_TRUE(std::any_of(r.findings.begin(), r.findings.end(), [](const Finding& f) {
        return f.kind == FindingKind::Ownership && f.resourceNames == std::vector<std::string>{"buf"} &&
               f.earlier.pass == "b" && f.reason.find("after its release") != std::string::npos;
    })) << r.summary();
}

TEST(Queues, BarrierStagesTheQueueLacksAreCaught) {
    test::Compiled c = async();
    const size_t step = stepIndex(c.plan, "histogram");
    PlanEditor::barriersOf(c.plan, step)[0].srcStages |= VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_GE(r.count(FindingKind::InvalidMask), 1u) << r.summary();
}

}  // namespace
}  // namespace skygraph::verifier
