// Regression graphs for hazards the verifier catches: the smallest graph that shows each, and
// the compiler rule that keeps it covered (docs/barriers.md: rule 16, rule 8, rule 5).
//
// PartialAliasBarrier: `a` (two mips) has mip 0 written by a dispatch and then sampled; the
// barrier between names mip 0 alone. `b` then takes over a's memory, and its aliasing barrier
// waits for the sampling with an execution dependency only (COMPUTE_SHADER / NONE), trusting
// the earlier barrier to have made the write available. Every subresource of a non-linear
// image overlaps all of its memory, and the spec's Memory Aliasing section asks a barrier
// used between aliases to contain every overlapping subresource, so the write reaches b's
// layout transition through a barrier that does not qualify. Either the aliasing barrier
// repeats the predecessors' last writes in its source scope (their stages and write access;
// it names every subresource of b), or the barrier that made them available names all of a.
//
// Readers outside the frame: an external buffer arrives as ShaderRead, so readers outside the
// frame may still be reading it in FRAGMENT_SHADER|COMPUTE_SHADER (docs/barriers.md, rule 8;
// the ibl worked example waits for exactly them). The frame reads it in a draw, then writes it
// in a dispatch whose barrier (FRAGMENT_SHADER / NONE -> COMPUTE_SHADER) waits for the draw
// alone: a compute reader outside the frame is not waited for. The source should be the reads
// since the last write including the initial state's readers (FRAGMENT_SHADER|COMPUTE_SHADER).
//
// An export after a transition: an image exported as ShaderRead is written by a dispatch,
// then sampled by a draw whose barrier moves it GENERAL -> SHADER_READ_ONLY_OPTIMAL with
// FRAGMENT_SHADER as its destination. The final barrier that makes it visible to
// FRAGMENT_SHADER|COMPUTE_SHADER sources from the dispatch (COMPUTE_SHADER /
// SHADER_STORAGE_WRITE), which the transition is not ordered before: a compute reader after
// the frame can overlap the transition. Its source should include the stages the transition
// was made visible to (FRAGMENT_SHADER), so that it chains after it.
//
// A first step in several layouts: a resource taking over memory whose first pass writes one
// layer as a colour attachment and another in a dispatch got one aliasing barrier per layout,
// each containing part of it, and an earlier holder's write that nothing read was made
// available by neither (NotAvailable). Its first step now takes GENERAL throughout, with one
// barrier over the whole image.
#include "fixture_graphs.hpp"
#include "verifier_test_util.hpp"

#include <gtest/gtest.h>

namespace skygraph::verifier {
namespace {

TEST(CompilerRegressions, WriteMadeAvailableOnlyByAPartialBarrierBeforeAliasing) {
    const test::Compiled c = test::compileText(test::fixtures::kPartialAvailabilityBeforeAliasing);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(r.ok()) << r.summary();
}

TEST(CompilerRegressions, WriteWaitsOnlyForTheFramesOwnReads) {
    const test::Compiled c = test::compileText(test::fixtures::kWriteAfterOutsideReaders);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(r.ok()) << r.summary();
}

TEST(CompilerRegressions, FinalBarrierChainsAfterTheTransitionOfASampledExport) {
    const test::Compiled c = test::compileText(test::fixtures::kExportAfterSampling);
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(r.ok()) << r.summary();
}

TEST(CompilerRegressions, AFirstStepInSeveralLayoutsTakesOverMemoryWithOneBarrier) {
    const test::Compiled c = test::compileText(test::fixtures::kMixedLayoutsTakingOverMemory);
    const PlannedResource& b = c.plan.resources()[c.plan.resourceIndex("b")];
    ASSERT_NE(b.placement, PlannedResource::kNoPlacement);
    ASSERT_FALSE(c.plan.memory().placements[b.placement].aliases.empty()) << "b takes over a's memory";
    const VerificationReport r = verifyPlan(c.plan, c.graph);
    EXPECT_TRUE(r.ok()) << r.summary();
}

}  // namespace
}  // namespace skygraph::verifier
