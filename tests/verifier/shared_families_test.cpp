// Queue kinds that share a family but are different queues (CompileOptions::queueFamilies such
// as {0, 0, 1} or {0, 1, 1}, which chooseQueues picks on real devices): ownership belongs to
// the family, but only semaphores order the family's queues. Each plan verifies clean, and
// with the wait the compiler adds for these queues edited out, the verifier reports the race
// that wait prevents.
#include "plan_editor.hpp"
#include "verifier_test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace skygraph::verifier {
namespace {

using detail::PlanEditor;
using test::stepIndex;
using test::submitOf;

test::Compiled compileOn(const char* json, std::array<uint32_t, kQueueKinds> families, bool optimal = false) {
    CompileOptions o;
    o.queueFamilies = families;
    if (optimal) o.layouts = LayoutPolicy::Optimal;
    return test::compileText(json, o);
}

/// The value the submit holding `step` signals.
uint32_t signalAfter(const Plan& plan, size_t step) {
    const Submit& s = plan.submits()[submitOf(plan, step)];
    if (s.signals.empty()) throw std::out_of_range("the step's submit signals nothing");
    return s.signals[0].value;
}

/// The plan with the wait on `semaphore` of the submit holding `step` edited by `edit`, which
/// returns false to drop it.
template <class F>
Plan withWaitEdited(const Plan& plan, size_t step, QueueKind semaphore, F&& edit) {
    Plan edited = plan;
    auto submits = PlanEditor::submits(edited);
    auto& waits = submits.at(submitOf(edited, step)).waits;
    const auto w =
        std::find_if(waits.begin(), waits.end(), [&](const SemaphoreOp& op) { return op.semaphore == semaphore; });
    if (w == waits.end()) throw std::out_of_range("the step's submit does not wait on that semaphore");
    if (!edit(*w)) waits.erase(w);
    PlanEditor::setSubmits(edited, submits);
    return edited;
}

Plan withWaitLowered(const Plan& plan, size_t step, QueueKind semaphore, uint32_t value) {
    return withWaitEdited(plan, step, semaphore, [&](SemaphoreOp& op) {
        op.value = value;
        return true;
    });
}

bool raceBetween(const VerificationReport& r, const char* resource, const char* earlier, const char* later) {
    return std::any_of(r.findings.begin(), r.findings.end(), [&](const Finding& f) {
        return (f.kind == FindingKind::Unordered || f.kind == FindingKind::NotVisible) && !f.resourceNames.empty() &&
               f.resourceNames[0] == resource && f.earlier.pass == earlier && f.later.pass == later;
    });
}

/// Whether `c` verifies clean, and, with the wait on `semaphore` of the submit holding step
/// `releasing` (which releases) lowered to the signal after step `lowerTo`, reports `resource`
/// racing between `earlier` and `later`.
void expectCleanAndRaceWithWaitLowered(const test::Compiled& c, const char* releasing, QueueKind semaphore,
                                       const char* lowerTo, const char* resource, const char* earlier,
                                       const char* later) {
    const VerificationReport clean = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(clean.ok()) << clean.summary();
    const size_t step = stepIndex(c.plan, releasing);
    ASSERT_FALSE(c.plan.submits()[submitOf(c.plan, step)].releases.empty());
    const Plan old = withWaitLowered(c.plan, step, semaphore, signalAfter(c.plan, stepIndex(c.plan, lowerTo)));
    const VerificationReport raced = verifyPlan(old, c.graph);
    EXPECT_TRUE(raceBetween(raced, resource, earlier, later)) << raced.summary();
}

// Graphics and compute on one family, transfer on another. 'img' is read on the graphics queue
// (r0, r1) and then on the compute queue (r2), which therefore releases it to the transfer
// family; the transition to TRANSFER_SRC happens after that release and before the acquire
// (§7.7.4), so the release must follow the graphics reads too: r2 waits for r1, not only for
// the write.
TEST(SharedFamilies, AReleaseFollowsTheReadsOfTheFamilysOtherQueues) {
    const test::Compiled c = compileOn(R"({ "version": 1, "name": "release", "resources": {
        "img": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "sharing": "exclusive" },
        "o0": { "type": "buffer", "size": 256 },
        "o1": { "type": "buffer", "size": 256 },
        "cp": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16] },
        "swapchain": { "type": "image2d", "format": "B8G8R8A8_SRGB", "extent": "output", "external": true,
                       "final": "Present" } },
      "passes": [
        { "name": "c0", "type": "Generic", "queue": "compute", "uses": { "o0": "Write@Compute" } },
        { "name": "w", "type": "Generic", "uses": { "img": "Write@ColorAttachment" } },
        { "name": "r0", "type": "Generic", "uses": [ { "resource": "img", "access": "Read", "stage": "Fragment" },
            { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] },
        { "name": "r1", "type": "Generic", "uses": [ { "resource": "img", "access": "Read", "stage": "Fragment" },
            { "resource": "swapchain", "access": "ReadWrite", "stage": "ColorAttachment" } ] },
        { "name": "r2", "type": "Generic", "queue": "compute",
          "uses": { "img": "Read@Compute", "o1": "Write@Compute", "o0": "Read@Compute" } },
        { "name": "t", "type": "Generic", "queue": "transfer",
          "uses": { "img": "Read@Transfer", "cp": "Write@Transfer" } },
        { "name": "g", "type": "Generic", "uses": [
            { "resource": "o1", "access": "Read", "stage": "Fragment", "as": "storage" },
            { "resource": "cp", "access": "Read", "stage": "Fragment" },
            { "resource": "swapchain", "access": "ReadWrite", "stage": "ColorAttachment" } ] } ] })",
                                       {0, 0, 1}, true);
    // Lowered to the write's signal: the reads on graphics then race the release's transition.
    expectCleanAndRaceWithWaitLowered(c, "r2", QueueKind::Graphics, "w", "img", "r1", "t");
}

// Compute and transfer on one family. 'img' is read on the compute queue (c0, c1), last on the
// transfer queue (t), which hands it back to the graphics family at the frame's end with the
// transition to its final layout: that release must follow c1's read too.
TEST(SharedFamilies, AHandBackAtTheFramesEndFollowsTheReadsOfTheFamilysOtherQueues) {
    const test::Compiled c = compileOn(R"({ "version": 1, "name": "handback", "resources": {
        "img": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "final": "ShaderRead" },
        "o1": { "type": "buffer", "size": 256 },
        "o2": { "type": "buffer", "size": 256 },
        "cp": { "type": "buffer", "size": 1024 },
        "swapchain": { "type": "image2d", "format": "B8G8R8A8_SRGB", "extent": "output", "external": true,
                       "final": "Present" } },
      "passes": [
        { "name": "w", "type": "Generic", "uses": { "img": "Write@ColorAttachment" } },
        { "name": "c0", "type": "Generic", "queue": "compute",
          "uses": { "img": "Read@Compute", "o1": "Write@Compute" } },
        { "name": "c1", "type": "Generic", "queue": "compute",
          "uses": { "img": "Read@Compute", "o2": "Write@Compute" } },
        { "name": "t", "type": "Generic", "queue": "transfer",
          "uses": { "img": "Read@Transfer", "cp": "Write@Transfer" } },
        { "name": "g", "type": "Generic", "uses": [
            { "resource": "o1", "access": "Read", "stage": "Fragment", "as": "storage" },
            { "resource": "o2", "access": "Read", "stage": "Fragment", "as": "storage" },
            { "resource": "cp", "access": "Read", "stage": "Fragment", "as": "storage" },
            { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] } ] })",
                                       {0, 1, 1});
    // Lowered to c0's signal (the acquire from the graphics family): c1's read then races.
    expectCleanAndRaceWithWaitLowered(c, "t", QueueKind::Compute, "c0", "img", "c1", "final barriers");
}

// Compute and transfer on one family: the transfer queue (t) acquires 'buf' from the graphics
// family, and the compute queue reads it after. Only the acquire makes it the family's, so c
// waits for t, not only for the write on the graphics queue.
TEST(SharedFamilies, AnAcquireOrdersLaterUsesOnTheFamilysOtherQueues) {
    const test::Compiled c = compileOn(R"({ "version": 1, "name": "acquire", "resources": {
        "buf": { "type": "buffer", "size": 256, "sharing": "exclusive" },
        "cp": { "type": "buffer", "size": 256 },
        "o1": { "type": "buffer", "size": 256 },
        "swapchain": { "type": "image2d", "format": "B8G8R8A8_SRGB", "extent": "output", "external": true,
                       "final": "Present" } },
      "passes": [
        { "name": "w", "type": "Generic", "uses": { "buf": "Write@Compute" } },
        { "name": "t", "type": "Generic", "queue": "transfer",
          "uses": { "buf": "Read@Transfer", "cp": "Write@Transfer" } },
        { "name": "c", "type": "Generic", "queue": "compute", "uses": [
            { "resource": "buf", "access": "Read", "stage": "Compute", "as": "uniform" },
            { "resource": "o1", "access": "Write", "stage": "Compute" } ] },
        { "name": "g", "type": "Generic", "uses": [
            { "resource": "o1", "access": "Read", "stage": "Fragment", "as": "storage" },
            { "resource": "cp", "access": "Read", "stage": "Fragment", "as": "storage" },
            { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] } ] })",
                                       {0, 1, 1});
    const VerificationReport clean = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(clean.ok()) << clean.summary();
    const Plan old =
        withWaitEdited(c.plan, stepIndex(c.plan, "c"), QueueKind::Transfer, [](SemaphoreOp&) { return false; });
    const VerificationReport raced = verifyPlan(old, c.graph);
    EXPECT_TRUE(raceBetween(raced, "buf", "t", "c")) << raced.summary();
}

// Graphics and compute on one family, transfer on another: the compute queue acquires 'buf'
// from the transfer family, and the graphics queue reads it after, which must wait for that
// acquire rather than for the upload on the transfer queue.
TEST(SharedFamilies, AnAcquireOrdersLaterUsesOnTheFamilysOtherQueuesAcrossTheGraphicsQueue) {
    const test::Compiled c = compileOn(R"({ "version": 1, "name": "acquire", "resources": {
        "buf": { "type": "buffer", "size": 256, "sharing": "exclusive" },
        "o1": { "type": "buffer", "size": 256, "sharing": "exclusive" },
        "swapchain": { "type": "image2d", "format": "B8G8R8A8_SRGB", "extent": "output", "external": true,
                       "final": "Present" } },
      "passes": [
        { "name": "up", "type": "Generic", "queue": "transfer", "uses": { "buf": "Write@Transfer" } },
        { "name": "c", "type": "Generic", "queue": "compute", "uses": [
            { "resource": "buf", "access": "Read", "stage": "Compute", "as": "uniform" },
            { "resource": "o1", "access": "Write", "stage": "Compute" } ] },
        { "name": "g", "type": "Generic", "uses": [
            { "resource": "buf", "access": "Read", "stage": "Vertex", "as": "uniform" },
            { "resource": "o1", "access": "Read", "stage": "Fragment", "as": "storage" },
            { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] } ] })",
                                       {0, 0, 1});
    const VerificationReport clean = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(clean.ok()) << clean.summary();
    // g waits for c for 'o1' too, but at FRAGMENT_SHADER alone: the vertex read of 'buf' is not
    // in that wait's scope.
    const Plan old = withWaitEdited(c.plan, stepIndex(c.plan, "g"), QueueKind::Compute, [](SemaphoreOp& op) {
        EXPECT_NE(op.stages & VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT, 0u);
        op.stages = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
        return true;
    });
    const VerificationReport raced = verifyPlan(old, c.graph);
    EXPECT_TRUE(raceBetween(raced, "buf", "c", "g")) << raced.summary();
}

}  // namespace
}  // namespace skygraph::verifier
