// One focused test per synchronization rule. Each expectation below was checked against the
// Vulkan spec's memory model (chapter "Synchronization and Cache Control"): a RAW or WAW needs
// an availability + visibility operation, a WAR only an execution dependency, and an image
// layout transition is itself a write ordered by the barrier that performs it.
#include <skygraph/compiler.hpp>
#include <skygraph/plan_format.hpp>

#include "plan_queries.hpp"
#include "usage_fit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace skygraph {
namespace {

using test::barriersOf;
using test::pass;
using test::registry;

/// Builds a graph file from resources and passes JSON fragments, then compiles it.
Plan compileGraph(const std::string& resources, const std::string& passes,
                  CompileOptions options = {}, const std::string& features = "{}") {
    // The rules are stated for one frame; what frames sharing the heaps add is rule 16's, in
    // aliasing_rules_test.cpp.
    options.shareTransientsAcrossFrames = false;
    const std::string text = R"({"version": 1, "name": "t", "features": )" + features +
                             R"(, "resources": {)" + resources + R"(}, "passes": [)" + passes + "]}";
    return compile(parseGraph(text, "rules.json", registry()), options);
}

CompileOptions noCulling() {
    CompileOptions o;
    o.cull = false;
    return o;
}

constexpr const char* kColor = R"("color": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16]})";
constexpr const char* kOut = R"("out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true, "final": "TransferSrc"})";
constexpr const char* kBuf = R"("buf": {"type": "buffer", "size": 256})";
constexpr const char* kSink = R"("sink": {"type": "buffer", "size": 64, "external": true, "final": "ShaderRead"})";

TEST(BarrierRules, ReadAfterWriteIsAMemoryDependency) {
    const Plan plan = compileGraph(std::string(kBuf) + "," + kSink, R"(
        {"name": "w", "type": "Generic", "uses": {"buf": "Write@Compute"}},
        {"name": "r", "type": "Generic", "uses": {"buf": "Read@Fragment", "sink": "Write@Fragment"}})");
    ASSERT_EQ(pass(plan, "w").barriers.size(), 0u) << "a buffer's first write needs nothing";
    const auto& b = pass(plan, "r").barriers;
    ASSERT_EQ(b.size(), 2u);
    EXPECT_EQ(b[0].kind, BarrierKind::Buffer);
    EXPECT_EQ(b[0].srcStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(b[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(b[0].dstStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
    EXPECT_EQ(b[0].dstAccess, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

TEST(BarrierRules, WriteAfterWriteIsAMemoryDependency) {
    const Plan plan = compileGraph(std::string(kBuf) + "," + kSink, R"(
        {"name": "w1", "type": "Generic", "uses": {"buf": "Write@Compute"}},
        {"name": "w2", "type": "Generic", "uses": {"buf": "Write@Transfer"}},
        {"name": "r", "type": "Generic", "uses": {"buf": "Read@Compute", "sink": "Write@Compute"}})",
        noCulling());
    const auto& b = pass(plan, "w2").barriers;
    ASSERT_EQ(b.size(), 1u);
    EXPECT_EQ(b[0].srcStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(b[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(b[0].dstStages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);
    EXPECT_EQ(b[0].dstAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
}

TEST(BarrierRules, WriteAfterReadIsExecutionOnly) {
    const Plan plan = compileGraph(std::string(kBuf) + "," + kSink, R"(
        {"name": "w1", "type": "Generic", "uses": {"buf": "Write@Compute"}},
        {"name": "r", "type": "Generic", "uses": {"buf": "Read@Vertex", "sink": "Write@Compute"}},
        {"name": "w2", "type": "Generic", "uses": {"buf": "Write@Compute"}},
        {"name": "r2", "type": "Generic", "uses": {"buf": "Read@Compute", "sink": "ReadWrite@Compute"}})");
    const auto& b = pass(plan, "w2").barriers;
    ASSERT_EQ(b.size(), 1u);
    EXPECT_EQ(b[0].srcStages, VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT);
    EXPECT_EQ(b[0].srcAccess, 0u) << "WAR needs no availability operation";
    EXPECT_EQ(b[0].dstStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(b[0].dstAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

TEST(BarrierRules, ReadAfterReadInTheSameLayoutNeedsNoBarrier) {
    const Plan plan = compileGraph(std::string(kColor) + "," + kSink, R"(
        {"name": "w", "type": "Generic", "uses": {"color": "Write@ColorAttachment"}},
        {"name": "r1", "type": "Generic", "uses": {"color": "Read@Fragment", "sink": "Write@Fragment"}},
        {"name": "r2", "type": "Generic", "uses": {"color": "Read@Fragment", "sink": "ReadWrite@Fragment"}})");
    ASSERT_EQ(barriersOf(plan, "r1", "color").size(), 1u);
    EXPECT_TRUE(barriersOf(plan, "r2", "color").empty());
}

TEST(BarrierRules, ReadRunAcrossStagesSharesOneLayoutAndOneBarrier) {
    // A sampled read then a transfer read of the same image: one layout (GENERAL) serves
    // both, made visible to both stages by a single barrier before the first.
    const Plan plan = compileGraph(std::string(kColor) + "," + kSink + "," + kBuf, R"(
        {"name": "w", "type": "Generic", "uses": {"color": "Write@ColorAttachment"}},
        {"name": "sample", "type": "Generic", "uses": {"color": "Read@Fragment", "sink": "Write@Fragment"}},
        {"name": "copy", "type": "Generic", "uses": {"color": "Read@Transfer", "buf": "Write@Transfer"}},
        {"name": "use", "type": "Generic", "uses": {"buf": "Read@Compute", "sink": "ReadWrite@Compute"}},
        {"name": "rewrite", "type": "Generic", "never_cull": true, "uses": {"color": "Write@ColorAttachment"}})");
    const auto first = barriersOf(plan, "sample", "color");
    ASSERT_EQ(first.size(), 1u);
    EXPECT_EQ(first[0].oldLayout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    EXPECT_EQ(first[0].newLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(first[0].dstStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT);
    EXPECT_EQ(first[0].dstAccess, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT);
    for (const auto& b : pass(plan, "copy").barriers) EXPECT_NE(plan.resources()[b.resource].name, "color");
    // The next writer waits for every reader of the run, with no memory dependency.
    const auto next = barriersOf(plan, "rewrite", "color");
    ASSERT_EQ(next.size(), 1u);
    EXPECT_EQ(next[0].srcStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT);
    EXPECT_EQ(next[0].srcAccess, 0u);
    EXPECT_EQ(next[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED) << "Write discards";
}

TEST(BarrierRules, DepthTestAndSamplingShareTheDepthReadOnlyLayout) {
    const Plan plan = compileGraph(
        R"("depth": {"type": "image2d", "format": "D32_SFLOAT", "extent": [16, 16]},)" + std::string(kColor) +
            "," + kOut,
        R"(
        {"name": "z", "type": "Generic", "uses": {"depth": "Write@DepthAttachment"}},
        {"name": "test", "type": "Generic", "uses": {"depth": "Read@DepthAttachment", "color": "Write@ColorAttachment"}},
        {"name": "fog", "type": "Generic", "uses": {"depth": "Read@Fragment", "color": "Read@Fragment", "out": "Write@ColorAttachment"}})");
    const auto b = barriersOf(plan, "test", "depth");
    ASSERT_EQ(b.size(), 1u);
    EXPECT_EQ(b[0].newLayout, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL);
    EXPECT_EQ(b[0].dstStages, VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT |
                                  VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT |
                                  VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
    EXPECT_TRUE(barriersOf(plan, "fog", "depth").empty());
}

TEST(BarrierRules, FirstUseDiscardsOnlyForWrite) {
    const Plan plan = compileGraph(std::string(kColor) + "," + kOut, R"(
        {"name": "w", "type": "Generic", "uses": {"color": "Write@Compute"}},
        {"name": "rw", "type": "Generic", "uses": {"color": "ReadWrite@Compute", "out": "Write@Transfer"}})");
    const auto& w = pass(plan, "w").barriers;
    ASSERT_EQ(w.size(), 1u);
    EXPECT_EQ(w[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(w[0].newLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(w[0].srcStages, 0u) << "nothing earlier in the frame to wait for";
    // A ReadWrite keeps contents: same layout, memory dependency, no UNDEFINED.
    const auto& rw = pass(plan, "rw").barriers;
    ASSERT_GE(rw.size(), 1u);
    EXPECT_EQ(rw[0].oldLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(rw[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(rw[0].dstAccess, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

TEST(BarrierRules, ClearByAttachmentLoadOp) {
    const Plan plan = compileGraph(
        R"("color": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "clear": {"color": [0,0,0,1]}},)" +
            std::string(kOut),
        R"({"name": "blend", "type": "Generic", "uses": {"color": "ReadWrite@ColorAttachment"}},
           {"name": "copy", "type": "Generic", "uses": {"color": "Read@Transfer", "out": "Write@Transfer"}})");
    const auto& u = pass(plan, "blend").usages[0];
    EXPECT_EQ(u.load, LoadOp::Clear);
    EXPECT_EQ(u.store, StoreOp::Store);
    ASSERT_EQ(plan.passes().size(), 2u) << "no Clear pass when the load op clears";
}

TEST(BarrierRules, ClearBeforeANonAttachmentFirstUseIsAClearPass) {
    const Plan plan = compileGraph(
        R"("color": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "clear": {"color": [1,0,0,1]}},)" +
            std::string(kOut),
        R"({"name": "show", "type": "Generic", "uses": {"color": "Read@Fragment", "out": "Write@ColorAttachment"}})");
    ASSERT_EQ(plan.passes().size(), 2u);
    EXPECT_EQ(plan.passes()[0].type, "Clear");
    ASSERT_EQ(plan.passes()[0].barriers.size(), 1u);
    EXPECT_EQ(plan.passes()[0].barriers[0].newLayout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    const auto& b = plan.passes()[1].barriers;
    ASSERT_GE(b.size(), 1u);
    EXPECT_EQ(b[0].srcStages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);
    EXPECT_EQ(b[0].srcAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    EXPECT_EQ(b[0].newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

TEST(BarrierRules, ExternalContentsAreVisibleToTheirDeclaredScope) {
    const std::string tex = R"("tex": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true})";
    // Default initial state ShaderRead: fragment sampling needs nothing...
    Plan plan = compileGraph(tex + "," + kOut,
                             R"({"name": "p", "type": "Generic", "uses": {"tex": "Read@Fragment", "out": "Write@ColorAttachment"}})");
    EXPECT_TRUE(barriersOf(plan, "p", "tex").empty());
    // ...but vertex sampling is outside that scope and gets an execution + visibility barrier.
    plan = compileGraph(tex + "," + kOut,
                        R"({"name": "p", "type": "Generic", "uses": {"tex": "Read@Vertex", "out": "Write@ColorAttachment"}})");
    const auto b = barriersOf(plan, "p", "tex");
    ASSERT_EQ(b.size(), 1u);
    EXPECT_EQ(b[0].oldLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(b[0].newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(b[0].dstStages, VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT);
}

TEST(BarrierRules, ExportedResourcesEndInTheirFinalState) {
    const Plan plan = compileGraph(
        R"("sc": {"type": "image2d", "format": "B8G8R8A8_SRGB", "extent": [16, 16], "external": true, "final": "Present"})",
        R"({"name": "p", "type": "Generic", "uses": {"sc": "Write@ColorAttachment"}})");
    ASSERT_EQ(plan.passes()[0].barriers.size(), 1u);
    const auto& first = plan.passes()[0].barriers[0];
    EXPECT_EQ(first.oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    // Chains with the acquire semaphore, which waits in the first use's stage.
    EXPECT_EQ(first.srcStages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
    EXPECT_EQ(first.srcAccess, 0u);
    ASSERT_EQ(plan.finalBarriers().size(), 1u);
    const auto& fin = plan.finalBarriers()[0];
    EXPECT_EQ(fin.newLayout, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
    EXPECT_EQ(fin.srcAccess, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    // Chains with the render-complete signal, which is in the last use's stages (rule 15).
    EXPECT_EQ(fin.dstStages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
    EXPECT_EQ(fin.dstAccess, 0u);

    CompileOptions headless;
    headless.presentReplacement = ExternalState::TransferSrc;
    const Plan h = compileGraph(
        R"("sc": {"type": "image2d", "format": "B8G8R8A8_SRGB", "extent": [16, 16], "external": true, "final": "Present"})",
        R"({"name": "p", "type": "Generic", "uses": {"sc": "Write@ColorAttachment"}})", headless);
    ASSERT_EQ(h.finalBarriers().size(), 1u);
    EXPECT_EQ(h.finalBarriers()[0].newLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    EXPECT_EQ(h.finalBarriers()[0].dstStages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);
    EXPECT_EQ(h.finalBarriers()[0].dstAccess, VK_ACCESS_2_TRANSFER_READ_BIT);
    // Next frame: the readback copy read it last, so the first write waits for transfer (WAR).
    EXPECT_EQ(h.passes()[0].barriers[0].srcStages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);
}

// Rules 8 and 9: an external input that is not exported arrives in its `initial` state every
// frame, so a frame that leaves it in another layout moves it back, and one that only samples
// it in that state needs nothing.
TEST(BarrierRules, ExternalInputsGoBackToTheirInitialState) {
    const std::string lut = R"("lut": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true})";
    const auto readAs = [&](const std::string& access, const std::string& stage, const std::string& as) {
        return compileGraph(lut + "," + kOut, R"({"name": "p", "type": "Generic", "uses": [
            {"resource": "lut", "access": ")" + access + R"(", "stage": ")" + stage + R"(")" + as + R"(},
            {"resource": "out", "access": "Write", "stage": "ColorAttachment"}]})");
    };
    const auto finalsOf = [](const Plan& plan, const std::string& name) {
        std::vector<Barrier> found;
        for (const Barrier& b : plan.finalBarriers())
            if (b.resource == static_cast<uint32_t>(plan.resourceIndex(name))) found.push_back(b);
        return found;
    };

    // Read as storage: GENERAL during the frame, then back to SHADER_READ_ONLY_OPTIMAL, visible
    // to the ShaderRead scope. The frame wrote nothing, so the barrier has no source access.
    Plan plan = readAs("Read", "Compute", R"(, "as": "storage")");
    auto fin = finalsOf(plan, "lut");
    ASSERT_EQ(fin.size(), 1u) << planToText(plan);
    EXPECT_EQ(fin[0].oldLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(fin[0].newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_TRUE(fin[0].srcStages & VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(fin[0].srcAccess, 0u);
    EXPECT_EQ(fin[0].dstStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(fin[0].dstAccess, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    const PlannedResource& res = plan.resources()[static_cast<size_t>(plan.resourceIndex("lut"))];
    EXPECT_EQ(res.finalLayout, res.initialLayout);
    EXPECT_EQ(res.copies, ResourceCopies::SharedReadOnly);

    // A copy source: TRANSFER_SRC_OPTIMAL, then back, after the copy.
    plan = readAs("Read", "Transfer", "");
    fin = finalsOf(plan, "lut");
    ASSERT_EQ(fin.size(), 1u) << planToText(plan);
    EXPECT_EQ(fin[0].oldLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    EXPECT_EQ(fin[0].newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_TRUE(fin[0].srcStages & VK_PIPELINE_STAGE_2_TRANSFER_BIT);

    // Written as storage: the write is made visible to the ShaderRead scope too (rule 1).
    plan = readAs("Write", "Compute", R"(, "as": "storage")");
    fin = finalsOf(plan, "lut");
    ASSERT_EQ(fin.size(), 1u) << planToText(plan);
    EXPECT_EQ(fin[0].oldLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(fin[0].newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(fin[0].srcStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(fin[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);

    // Sampled where its state promises: nothing to undo.
    plan = readAs("Read", "Fragment", "");
    EXPECT_TRUE(finalsOf(plan, "lut").empty()) << planToText(plan);

    // A buffer (no layout) written as storage: the barrier is the write's memory dependency
    // alone, made visible to the ShaderRead scope the next frame finds it in.
    plan = compileGraph(R"("data": {"type": "buffer", "size": 256, "external": true},)" + std::string(kOut),
                        R"({"name": "p", "type": "Generic", "uses": {"data": "Write@Compute", "out": "Write@ColorAttachment"}})");
    fin = finalsOf(plan, "data");
    ASSERT_EQ(fin.size(), 1u) << planToText(plan);
    EXPECT_EQ(fin[0].kind, BarrierKind::Buffer);
    EXPECT_EQ(fin[0].srcStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(fin[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(fin[0].dstStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(fin[0].dstAccess, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);

    // An image arriving in Present that is not presented (no `final`): the barrier back to
    // PRESENT_SRC_KHR ends in its first use's stages, where the next frame's first barrier
    // starts.
    plan = compileGraph(
        R"("shown": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true, "initial": "Present"},)" +
            std::string(kOut),
        R"({"name": "p", "type": "Generic", "uses": {"shown": "Read@Fragment", "out": "Write@ColorAttachment"}})");
    fin = finalsOf(plan, "shown");
    ASSERT_EQ(fin.size(), 1u) << planToText(plan);
    EXPECT_EQ(fin[0].newLayout, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
    EXPECT_EQ(fin[0].dstStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
    const auto first = barriersOf(plan, "p", "shown");
    ASSERT_EQ(first.size(), 1u);
    EXPECT_EQ(first[0].srcStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
}

TEST(BarrierRules, PersistentAccumulationChainsAcrossFrames) {
    const Plan plan = compileGraph(
        R"("acc": {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": [16, 16], "external": true, "final": "General"})",
        R"({"name": "trace", "type": "Generic", "uses": {"acc": "ReadWrite@Compute"}})");
    EXPECT_TRUE(plan.passes()[0].barriers.empty())
        << "last frame's final barrier already made the writes visible to this use";
    ASSERT_EQ(plan.finalBarriers().size(), 1u);
    EXPECT_EQ(plan.finalBarriers()[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(plan.finalBarriers()[0].dstStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(plan.finalBarriers()[0].dstAccess,
              VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

TEST(BarrierRules, PersistentFinalBarrierWaitsForThisFramesReaders) {
    // The next frame's first use writes, so last frame's readers are a WAR source for it.
    const Plan plan = compileGraph(
        R"("acc": {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": [16, 16], "external": true, "final": "General"},)" +
            std::string(kOut),
        R"({"name": "trace", "type": "Generic", "uses": {"acc": "ReadWrite@Compute"}},
           {"name": "show", "type": "Generic", "uses": {"acc": "Read@Fragment", "out": "Write@ColorAttachment"}})");
    std::vector<Barrier> fin;
    for (const auto& b : plan.finalBarriers())
        if (plan.resources()[b.resource].name == "acc") fin.push_back(b);
    ASSERT_EQ(fin.size(), 1u);
    EXPECT_EQ(fin[0].srcStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
    EXPECT_EQ(fin[0].srcAccess, 0u) << "the compute write was made available before the read";
    EXPECT_EQ(fin[0].dstStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(fin[0].newLayout, VK_IMAGE_LAYOUT_GENERAL);
}

TEST(BarrierRules, MipChainWrittenOneLevelAtATime) {
    std::string passes =
        R"({"name": "base", "type": "Generic", "uses": [{"resource": "chain", "access": "Write", "stage": "Compute", "mips": [0, 1]}]})";
    for (int m = 1; m < 4; ++m)
        passes += R"(, {"name": "mip)" + std::to_string(m) + R"(", "type": "Generic", "uses": [
            {"resource": "chain", "access": "Read", "stage": "Compute", "mips": [)" + std::to_string(m - 1) + R"(, 1]},
            {"resource": "chain", "access": "Write", "stage": "Compute", "mips": [)" + std::to_string(m) + R"(, 1]}]})";
    const Plan plan = compileGraph(
        R"("chain": {"type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [16, 16], "mips": 4, "external": true, "final": "ShaderRead"})",
        passes);
    ASSERT_EQ(plan.passes().size(), 4u);
    for (int m = 1; m < 4; ++m) {
        const auto& b = plan.passes()[m].barriers;
        ASSERT_EQ(b.size(), 2u) << "mip" << m;
        EXPECT_EQ(b[0].range.baseMip, uint32_t(m - 1));
        EXPECT_EQ(b[0].range.mipCount, 1u);
        EXPECT_EQ(b[0].oldLayout, VK_IMAGE_LAYOUT_GENERAL);
        EXPECT_EQ(b[0].newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        EXPECT_EQ(b[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
        EXPECT_EQ(b[1].range.baseMip, uint32_t(m));
        EXPECT_EQ(b[1].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
        EXPECT_EQ(b[1].newLayout, VK_IMAGE_LAYOUT_GENERAL);
    }
    // Final: mips 0-2 are already SHADER_READ_ONLY (visible to compute only); mip 3 is
    // GENERAL. The two groups cannot merge, so there are exactly two final barriers.
    ASSERT_EQ(plan.finalBarriers().size(), 2u);
    EXPECT_EQ(plan.finalBarriers()[0].range.baseMip, 0u);
    EXPECT_EQ(plan.finalBarriers()[0].range.mipCount, 3u);
    EXPECT_EQ(plan.finalBarriers()[0].oldLayout, plan.finalBarriers()[0].newLayout);
    EXPECT_EQ(plan.finalBarriers()[1].range.baseMip, 3u);
    EXPECT_EQ(plan.finalBarriers()[1].oldLayout, VK_IMAGE_LAYOUT_GENERAL);
}

TEST(BarrierRules, SubresourceRangesMergeWhenTheyAgree) {
    const Plan plan = compileGraph(
        R"("cube": {"type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [8, 8], "mips": 2, "external": true, "final": "ShaderRead"})",
        R"({"name": "faces", "type": "Generic", "uses": [
             {"resource": "cube", "access": "Write", "stage": "Compute", "mips": [0, 1], "layers": [0, 3]},
             {"resource": "cube", "access": "Write", "stage": "Compute", "mips": [0, 1], "layers": [3, 3]},
             {"resource": "cube", "access": "Write", "stage": "Compute", "mips": [1, 1]}]})");
    ASSERT_EQ(plan.passes()[0].barriers.size(), 1u) << "three usages, one rectangle of 2 mips x 6 layers";
    EXPECT_EQ(plan.passes()[0].barriers[0].range, (SubresourceRange{0, 2, 0, 6}));
    ASSERT_EQ(plan.finalBarriers().size(), 1u);
}

TEST(Culling, AConditionOfNoFeatureIsAlwaysFalse) {
    const Plan plan = compileGraph(std::string(kColor) + "," + kOut, R"(
        {"name": "draw", "type": "Generic", "uses": {"color": "Write@ColorAttachment"}},
        {"name": "never", "type": "Generic", "if": "false", "uses": {"color": "ReadWrite@ColorAttachment"}},
        {"name": "copy", "type": "Generic", "uses": {"color": "Read@Transfer", "out": "Write@Transfer"}})");
    ASSERT_EQ(plan.culled().size(), 1u);
    EXPECT_EQ(plan.culled()[0].reason, "condition 'false' is always false");
}

// A condition written over several lines keeps its reason on one line: a text plan's `culled:`
// line, a DOT label and a log line each show the line breaks escaped.
TEST(Culling, AReasonShowsTheConditionsLineBreaksEscaped) {
    CompileOptions options;
    options.features = {{"fx", false}};
    const Plan plan = compileGraph(std::string(kColor) + "," + kOut, R"(
        {"name": "draw", "type": "Generic", "uses": {"color": "Write@ColorAttachment"}},
        {"name": "both", "type": "Generic", "if": "fx &&\r\n!other", "uses": {"color": "ReadWrite@Compute"}},
        {"name": "copy", "type": "Generic", "uses": {"color": "Read@Transfer", "out": "Write@Transfer"}})",
        options, R"({"fx": true, "other": false})");
    ASSERT_EQ(plan.culled().size(), 1u);
    EXPECT_EQ(plan.culled()[0].reason, "condition 'fx &&\\u000d\\u000a!other' is false (fx=off, other=off)");
}

TEST(Culling, ReasonsForEveryRemovedPass) {
    CompileOptions options;
    options.features = {{"fx", false}};
    const Plan plan = compileGraph(std::string(kColor) + "," + kOut + "," + kBuf, R"(
        {"name": "unused", "type": "Generic", "uses": {"buf": "Write@Compute"}},
        {"name": "draw", "type": "Generic", "uses": {"color": "Write@ColorAttachment"}},
        {"name": "fx", "type": "Generic", "if": "fx", "uses": {"color": "ReadWrite@Compute"}},
        {"name": "both", "type": "Generic", "if": "fx && !other", "uses": {"color": "ReadWrite@Compute"}},
        {"name": "copy", "type": "Generic", "uses": {"color": "Read@Transfer", "out": "Write@Transfer"}},
        {"name": "sidefx", "type": "Generic", "never_cull": true, "uses": {"buf": "Write@Compute"}})",
        options, R"({"fx": true, "other": false})");
    ASSERT_EQ(plan.culled().size(), 3u);
    EXPECT_EQ(plan.culled()[0].name, "unused");
    EXPECT_NE(plan.culled()[0].reason.find("no later pass that runs reads 'buf'"), std::string::npos) << plan.culled()[0].reason;
    EXPECT_EQ(plan.culled()[1].name, "fx");
    EXPECT_EQ(plan.culled()[1].reason, "feature 'fx' is off");
    EXPECT_EQ(plan.culled()[2].name, "both");
    EXPECT_EQ(plan.culled()[2].reason, "condition 'fx && !other' is false (fx=off, other=off)");
    ASSERT_EQ(plan.passes().size(), 3u);
    EXPECT_EQ(plan.passes()[2].name, "sidefx") << "never_cull keeps a pass with side effects";

    options.cull = false;
    const Plan all = compileGraph(std::string(kColor) + "," + kBuf,
                                  R"({"name": "unused", "type": "Generic", "uses": {"buf": "Write@Compute"}},
                                     {"name": "fx", "type": "Generic", "if": "fx", "uses": {"buf": "Write@Compute"}})",
                                  options, R"({"fx": true})");
    ASSERT_EQ(all.passes().size(), 1u) << "culling off still honours `if`";
    ASSERT_EQ(all.culled().size(), 1u);
}

TEST(Culling, ExportingAnIntermediateKeepsItsWriterAndEndsInTheExportedState) {
    CompileOptions options;
    options.exports = {{"color", ExternalState::TransferSrc}};
    const Plan plan = compileGraph(std::string(kColor) + "," + kOut, R"(
        {"name": "draw", "type": "Generic", "uses": {"color": "Write@ColorAttachment"}},
        {"name": "copy", "type": "Generic", "uses": {"color": "Read@Fragment", "out": "Write@ColorAttachment"}})",
                                   options);
    ASSERT_EQ(plan.passes().size(), 2u);
    bool found = false;
    for (const auto& b : plan.finalBarriers())
        if (plan.resources()[b.resource].name == "color") {
            found = true;
            EXPECT_EQ(b.newLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
            EXPECT_EQ(b.srcStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT) << "waits for the sampling read";
        }
    EXPECT_TRUE(found);
    options.exports = {{"nosuch", ExternalState::TransferSrc}};
    EXPECT_THROW((void)compileGraph(std::string(kColor) + "," + kOut,
                                    R"({"name": "p", "type": "Generic", "uses": {"out": "Write@ColorAttachment"}})",
                                    options),
                 GraphError);
}

TEST(Culling, UnusedResourcesAreNeverCreated) {
    const Plan plan = compileGraph(std::string(kColor) + "," + kOut + "," + kBuf,
                                   R"({"name": "p", "type": "Generic", "uses": {"out": "Write@ColorAttachment"}})");
    ASSERT_EQ(plan.resources().size(), 1u);
    EXPECT_EQ(plan.resources()[0].name, "out");
    EXPECT_EQ(plan.resourceIndex("buf"), -1);
}

// An exported resource is live at the end: a pass whose write of it is culled lost it to a
// later pass writing it over, which is what its reason says (not that nothing is exported).
TEST(Culling, AWriteOfAnExportedResourceWrittenOverSaysSo) {
    const Plan plan = compileGraph(std::string(kColor) + "," + kOut, R"(
        {"name": "w1", "type": "Generic", "uses": {"out": "Write@Compute", "color": "Write@Compute"}},
        {"name": "w2", "type": "Generic", "uses": {"out": "Write@Compute"}})");
    ASSERT_EQ(plan.culled().size(), 1u);
    EXPECT_EQ(plan.culled()[0].reason,
              "nothing reads what it writes: no later pass that runs reads 'color' and none of it is exported; a later "
              "pass that runs writes over what it writes of 'out' before anything reads it");
}

// The same of a resource that is not exported but read later: what the culled pass wrote, a
// later pass wrote over before the read (it said that nothing reads it).
TEST(Culling, AWriteWrittenOverBeforeALaterReadSaysSo) {
    const Plan plan = compileGraph(std::string(kColor) + "," + kOut, R"(
        {"name": "w1", "type": "Generic", "uses": {"color": "Write@Compute"}},
        {"name": "w2", "type": "Generic", "uses": {"color": "Write@Compute"}},
        {"name": "r", "type": "Generic", "uses": {"color": "Read@Compute", "out": "Write@Compute"}})");
    ASSERT_EQ(plan.culled().size(), 1u);
    EXPECT_EQ(plan.culled()[0].name, "w1");
    EXPECT_EQ(plan.culled()[0].reason,
              "nothing reads what it writes: a later pass that runs writes over what it writes of 'color' before "
              "anything reads it");
}

TEST(Reordering, SkyboxAfterTonemappingIsCulledWithItsReason) {
    const std::string resources = R"(
        "depth": {"type": "image2d", "format": "D32_SFLOAT", "extent": "output", "clear": {"depth": 0.0}},
        "hdr_color": {"type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output", "clear": {"color": [0,0,0,1]}},
        "swapchain": {"type": "image2d", "format": "B8G8R8A8_SRGB", "extent": "output", "external": true, "final": "Present"})";
    const Plan plan = compileGraph(resources, R"(
        {"name": "forward", "type": "ForwardPass", "uses": {"depth": "Write@DepthAttachment", "hdr_color": "Write@ColorAttachment"}},
        {"name": "tonemap", "type": "TonemappingPass", "uses": {"hdr_color": "Read@Fragment", "swapchain": "Write@ColorAttachment"}},
        {"name": "skybox", "type": "SkyboxPass", "uses": {"depth": "Read@DepthAttachment", "hdr_color": "ReadWrite@ColorAttachment"}})");
    ASSERT_EQ(plan.culled().size(), 1u);
    EXPECT_EQ(plan.culled()[0].name, "skybox");
    EXPECT_EQ(plan.culled()[0].reason,
              "nothing reads what it writes: no later pass that runs reads 'hdr_color' and none of it is exported");
    ASSERT_EQ(plan.passes().size(), 2u);
    // Forward's depth is now read by nobody: its store is dropped.
    EXPECT_EQ(plan.passes()[0].usages[0].store, StoreOp::DontCare);
    // The tonemap barrier now comes from forward's write.
    const auto& b = plan.passes()[1].barriers[0];
    EXPECT_EQ(plan.resources()[b.resource].name, "hdr_color");
    EXPECT_EQ(b.srcAccess, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
}

}  // namespace
}  // namespace skygraph

namespace skygraph {
namespace {

// CompileOptions::outputs: a consumer keeps only the products it samples. On the shipped
// environment graph, a skybox-only scene needs the cube alone, so the IBL passes go; the
// equirect's upload (streamed_equirect) feeds the cube, so it stays.
TEST(Culling, OutputsKeepOnlyTheProductsAConsumerNeeds) {
    const GraphDesc ibl = loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "ibl.json",
                                        PassRegistry::withBuiltins());
    auto culledNames = [](const Plan& p) {
        std::set<std::string> names;
        for (const auto& c : p.culled()) names.insert(c.name);
        return names;
    };
    const FeatureValues streamed{{"streamed_equirect", true}};
    CompileOptions cubeOnly;
    cubeOnly.features = streamed;
    cubeOnly.outputs = std::set<std::string, std::less<>>{"environment"};
    const Plan sky = compile(ibl, cubeOnly);
    EXPECT_EQ(culledNames(sky), (std::set<std::string>{"irradiance", "prefilter", "brdf_lut"}));
    EXPECT_EQ(sky.resourceIndex("irradiance"), -1) << "an unused product is never created";
    ASSERT_GE(sky.resourceIndex("environment"), 0);
    // The one product asked for, and the streamed equirect, an external input that goes back
    // to the state it arrives in.
    for (const auto& b : sky.finalBarriers())
        EXPECT_TRUE(sky.resources()[b.resource].name == "environment" || sky.resources()[b.resource].name == "equirect")
            << sky.resources()[b.resource].name;

    CompileOptions everything;
    everything.features = streamed;
    const Plan all = compile(ibl, everything);
    EXPECT_TRUE(all.culled().empty());
    CompileOptions none;
    none.features = streamed;
    none.outputs = std::set<std::string, std::less<>>{};
    EXPECT_EQ(compile(ibl, none).passes().size(), 0u) << "nothing asked for, nothing runs";
    CompileOptions unknown;
    unknown.outputs = std::set<std::string, std::less<>>{"enviroment"};
    EXPECT_THROW((void)compile(ibl, unknown), GraphError);
}

}  // namespace
}  // namespace skygraph

namespace skygraph {
namespace {

/// The formatted diagnostics of compiling `graph`; empty when it compiles.
std::string compileErrorText(const GraphDesc& graph) {
    try {
        (void)compile(graph);
    } catch (const GraphError& e) {
        return e.diagnostics().format();
    }
    return {};
}

// An output-sized full chain has its length only at compile time, where a read of levels no
// pass writes is found: the message names the levels, as the loader's does for a fixed extent
// (it said "no earlier pass writes it" of a read whose first level was written).
TEST(Ranges, AReadOfAnOutputChainNamesTheLevelsNoPassWrites) {
    const GraphDesc g = parseGraph(
        R"({"version": 1, "name": "t", "resources": {
              "img": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output", "mips": "full" },
              "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true,
                       "final": "ShaderRead" } },
            "passes": [
              { "name": "w", "type": "Generic", "uses": [
                  { "resource": "img", "access": "Write", "stage": "Compute", "mips": [0, 1] } ] },
              { "name": "r", "type": "Generic", "uses": [
                  { "resource": "img", "access": "Read", "stage": "Compute", "mips": [0, 3] },
                  { "resource": "out", "access": "Write", "stage": "ColorAttachment" } ] } ]})",
        "chain.json", registry());
    const std::string text = compileErrorText(g);
    EXPECT_NE(text.find("passes[1].uses[0]: pass 'r', resource 'img': reads 'img' (Read@Compute as sampled) but no earlier "
                        "pass writes mips 1 and 2 of it"),
              std::string::npos)
        << text;
}

// A level that the resolved chain does not have is an error at compile time, naming the pass
// and resource, also when an embedder shrank the image after loading (as `skygraph cubemap
// --size 32` does with ibl.json, whose chain is written for 256).
TEST(Ranges, LevelsPastTheChainAreAnErrorNotAClippedPlan) {
    GraphDesc ibl = loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "ibl.json",
                                  PassRegistry::withBuiltins());
    EXPECT_NO_THROW((void)compile(ibl));
    for (auto& r : ibl.resources)
        if (r.name == "environment") r.extent = Extent{false, 1, 32, 32};  // 6 levels, the graph writes 9
    const std::string text = compileErrorText(ibl);
    ASSERT_FALSE(text.empty()) << "expected a GraphError";
    EXPECT_NE(text.find(".mips: pass 'environment_mip6'"), std::string::npos) << "at the usage's mips: " << text;
    EXPECT_NE(text.find("resource 'environment'"), std::string::npos) << text;
    EXPECT_NE(text.find("32x32 image has 6 mip level(s)"), std::string::npos) << text;
    EXPECT_EQ(text.find("environment_mip5'"), std::string::npos) << "mip 5 exists: " << text;
}

// The loader never writes an empty range, but an embedder's GraphDesc can: compile() names it
// rather than planning a usage that touches nothing (every sweep assumes at least one
// subresource).
TEST(Ranges, AnEmptyRangeFromCodeIsAnError) {
    for (const bool emptyMips : {true, false}) {
        GraphDesc ibl = loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "ibl.json",
                                      PassRegistry::withBuiltins());
        std::string passName, resourceName;
        for (auto& pass : ibl.passes)
            for (auto& use : pass.uses)
                if (passName.empty() && use.usage.range) {
                    (emptyMips ? use.usage.range->mipCount : use.usage.range->layerCount) = 0;
                    passName = pass.name;
                    resourceName = ibl.resources[use.resource].name;
                }
        ASSERT_FALSE(passName.empty()) << "ibl.json has ranged usages";
        const std::string text = compileErrorText(ibl);
        ASSERT_FALSE(text.empty()) << "expected a GraphError";
        EXPECT_NE(text.find("uses an empty range"), std::string::npos) << text;
        EXPECT_NE(text.find((emptyMips ? ".mips: pass '" : ".layers: pass '") + passName + "'"), std::string::npos)
            << text;
        EXPECT_NE(text.find("resource '" + resourceName + "'"), std::string::npos) << text;
    }
}

// The loader keeps extents, layers, mips and sizes within their limits; a GraphDesc built in
// code may not, and compile() names the resource rather than dividing by zero or indexing an
// empty grid (a division by zero crashed it before).
TEST(GraphsFromCode, ShapesPastTheLoadersLimitsAreErrors) {
    const GraphDesc raster = loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "raster.json",
                                           PassRegistry::withBuiltins());
    const auto imageNamed = [](GraphDesc& g, const std::string& name) -> ResourceDesc& {
        return *std::find_if(g.resources.begin(), g.resources.end(), [&](const ResourceDesc& r) { return r.name == name; });
    };
    const std::vector<std::pair<std::function<void(ResourceDesc&)>, std::string>> cases{
        {[](ResourceDesc& r) { r.extent.divisor = 0; }, "divisor must be between 1 and 4096, not 0"},
        {[](ResourceDesc& r) { r.extent = Extent{false, 1, 0, 0}; }, "fixed extent must be between 1 and 16384 each way, not 0x0"},
        {[](ResourceDesc& r) { r.extent = Extent{false, 1, 16385, 8}; }, "not 16385x8"},
        {[](ResourceDesc& r) { r.layers = 0; }, "layers must be between 1 and 2048, not 0"},
        {[](ResourceDesc& r) { r.mips = 16; }, "mips must be at most 15"},
        // What the loader says of a file's shapes and states (the executor then made invalid
        // Vulkan objects: a cube of one layer, an image of no format, a transient presented).
        {[](ResourceDesc& r) { r.layers = 2; }, "an image2d has 1 layer, not 2; use image2d_array"},
        {[](ResourceDesc& r) { r.type = ResourceType::Cube; },
         "a cube has 6 layers of square faces of a fixed extent, not 1 layer(s) of the output's extent"},
        {[](ResourceDesc& r) { r.format = FormatInfo{}; }, "an image needs a format"},
        // A FormatInfo put together in code: the compiler takes aspects and sizes from its
        // fields (a depth flag on a colour format gave its barriers the depth aspect).
        {[](ResourceDesc& r) { r.format.hasDepth = true; },
         "its FormatInfo disagrees with its format R16G16B16A16_SFLOAT: hasDepth true where it is false (take it "
         "from findFormat())"},
        {[](ResourceDesc& r) { r.format.bytesPerTexel = 4; }, "bytesPerTexel 4 where it is 8"},
        {[](ResourceDesc& r) { r.format.srgb = r.format.hasStencil = true; },
         "hasStencil true where it is false, srgb true where it is false"},
        {[](ResourceDesc& r) { r.format.storageCapable = false; }, "storageCapable false where it is true"},
        {[](ResourceDesc& r) { r.format.name = "RGBA16F"; }, "name \"RGBA16F\" where it is \"R16G16B16A16_SFLOAT\""},
        {[](ResourceDesc& r) { r.format = FormatInfo{"R8G8B8_UNORM", VK_FORMAT_R8G8B8_UNORM, 3}; },
         "its format, VkFormat 23, is not one skygraph knows"},
        {[](ResourceDesc& r) { r.format.format = static_cast<VkFormat>(1000156000); }, "VkFormat 1000156000, is not"},
        {[](ResourceDesc& r) { r.final = ExternalState::Present; },
         "only an external image (the swapchain's) can be presented"},
        {[](ResourceDesc& r) { r.clear = ClearValue{true}; }, "clears to a color, not a depth value"},
        // States the loader never leaves so: an external image left without one came in
        // UNDEFINED every frame (its contents discarded) and its final barrier went to
        // UNDEFINED; a cleared external one was overwritten every frame.
        {[](ResourceDesc& r) { r.initial = ExternalState::ShaderRead; },
         "only external resources arrive in a state; its initial is ShaderRead"},
        {[](ResourceDesc& r) { r.external = true; }, "an external resource arrives in a state: give it an initial"},
        {[](ResourceDesc& r) {
             r.external = true;
             r.initial = ExternalState::ShaderRead;
             r.clear = ClearValue{};
         },
         "an external resource arrives with contents; it is not cleared"},
        // A clear value its format does not hold, which Vulkan would clamp or overflow.
        {[](ResourceDesc& r) { r.clear = ClearValue{.color = {70000, 0, 0, 1}}; },
         "its clear color [70000, 0, 0, 1] must hold four numbers in [-65504, 65504], the range of the format "
         "R16G16B16A16_SFLOAT (a clear would not write any other value as given)"},
        {[](ResourceDesc& r) { r.clear = ClearValue{.color = {0, std::numeric_limits<float>::quiet_NaN(), 0, 1}}; },
         "its clear color [0, nan, 0, 1] must hold four numbers in [-65504, 65504]"},
        {[](ResourceDesc& r) {
             r.format = *findFormat("R8G8B8A8_UNORM");
             r.clear = ClearValue{.color = {0, 0, 1.01f, 1}};
         },
         "must hold four numbers in [0, 1], the range of the format R8G8B8A8_UNORM"},
        {[](ResourceDesc& r) {
             r.format = *findFormat("R32_UINT");
             r.clear = ClearValue{.color = {1.5f, 0, 0, 1}};
         },
         "its clear color [1.5, 0, 0, 1] must hold four integers in [0, 16777216], the range of the format R32_UINT"},
        {[](ResourceDesc& r) {
             r.format = *findFormat("D32_SFLOAT");
             r.clear = ClearValue{.isDepth = true, .depth = 2.0f};
         },
         "its clear depth 2 must be in [0, 1] and its stencil 0 at most 255"},
        {[](ResourceDesc& r) {
             r.format = *findFormat("D24_UNORM_S8_UINT");
             r.clear = ClearValue{.isDepth = true, .stencil = 256};
         },
         "its clear depth 0 must be in [0, 1] and its stencil 256 at most 255"},
    };
    for (const auto& [edit, words] : cases) {
        GraphDesc g = raster;
        edit(imageNamed(g, "hdr_color"));
        const std::string text = compileErrorText(g);
        EXPECT_NE(text.find(words), std::string::npos) << text;
        EXPECT_NE(text.find("resources.hdr_color"), std::string::npos) << text;
        EXPECT_NE(text.find("resource 'hdr_color'"), std::string::npos) << text;
    }
    GraphDesc g = raster;
    ResourceDesc buffer;
    buffer.name = "empty";
    buffer.type = ResourceType::Buffer;
    g.resources.push_back(buffer);
    EXPECT_NE(compileErrorText(g).find("a buffer's size must be between 1 and 2147483648 bytes, not 0"), std::string::npos);
    g.resources.back().sizeBytes = 16;
    g.resources.back().final = ExternalState::TransferSrc;
    EXPECT_NE(compileErrorText(g).find("a buffer cannot start or end as Present or TransferSrc"), std::string::npos);
    g.resources.back().final = ExternalState::None;
    g.resources.back().clear = ClearValue{};
    EXPECT_NE(compileErrorText(g).find("a buffer cannot be cleared by the graph"), std::string::npos);
    EXPECT_EQ(compileErrorText(raster), "") << "the graph as loaded compiles";
    // A FormatInfo of the same fields whose name is text of the caller's own is the same format.
    g = raster;
    const std::string ownName = "R16G16B16A16_SFLOAT";
    imageNamed(g, "hdr_color").format.name = ownName;
    EXPECT_EQ(compileErrorText(g), "");
}

// The loader only writes resource indices it resolved, but an embedder's GraphDesc can name one
// past the graph's resources: compile() names the pass and the usage's JSON path rather than
// reading past the end of its per-resource tables (under ASan, a heap overflow without it).
TEST(GraphsFromCode, AResourceIndexPastTheGraphIsAnError) {
    GraphDesc raster = loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "raster.json",
                                     PassRegistry::withBuiltins());
    ASSERT_GE(raster.passes.size(), 2u);
    UsageDecl& use = raster.passes[1].uses.at(0);
    use.resource = static_cast<uint32_t>(raster.resources.size());  // the first index past the end
    const std::string text = compileErrorText(raster);
    ASSERT_FALSE(text.empty()) << "expected a GraphError";
    EXPECT_NE(text.find(raster.usageJsonPath(1, 0)), std::string::npos) << text;
    EXPECT_NE(text.find("pass '" + raster.passes[1].name + "'"), std::string::npos) << text;
    EXPECT_NE(text.find("names resource index " + std::to_string(use.resource) + ", but the graph has " +
                        std::to_string(raster.resources.size()) + " resource(s)"),
              std::string::npos)
        << text;
}

// A usage's layers past its image, from code: the index walked the layers as written, past the
// image's subresources (a heap overflow: glibc aborted at 4096 layers, ASan caught 3), before
// compile() named the range.
TEST(GraphsFromCode, LayersPastTheImageAreAnErrorNotAnOverflow) {
    for (const auto& [base, count] : {std::pair{0u, 4096u}, {0u, 3u}, {7u, 1u}, {1u, ~0u}}) {
        GraphDesc g = parseGraph(
            R"({"version": 1, "name": "t", "resources": {
                  "img": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "mips": 2 },
                  "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true,
                           "final": "ShaderRead" } },
                "passes": [
                  { "name": "w", "type": "Generic", "uses": { "img": "Write@Compute" } },
                  { "name": "r", "type": "Generic", "uses": { "img": "Read@Fragment", "out": "Write@ColorAttachment" } } ]})",
            "layers.json", registry());
        g.passes[0].uses.at(0).usage.range = SubresourceRange{0, 1, base, count};
        const std::string text = compileErrorText(g);
        ASSERT_FALSE(text.empty()) << "expected a GraphError";
        EXPECT_NE(text.find(g.usageJsonPath(0, 0) + ".layers: pass 'w', resource 'img'"), std::string::npos) << text;
        EXPECT_NE(text.find("uses layers [" + std::to_string(base) + ", " + std::to_string(count) +
                            "] but the image has 1 layer(s)"),
                  std::string::npos)
            << text;
    }
}

// The loader refuses `mips` or `layers` on a buffer's usage. From code, compile() read the
// buffer's mip count through its (unused) extent, and a divisor of 0 ended it by SIGFPE.
TEST(GraphsFromCode, ARangeOnABufferIsAnError) {
    GraphDesc g = parseGraph(
        R"({"version": 1, "name": "t", "resources": {
              "buf": { "type": "buffer", "size": 256 },
              "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true,
                       "final": "ShaderRead" } },
            "passes": [
              { "name": "w", "type": "Generic", "uses": { "buf": "Write@Compute" } },
              { "name": "r", "type": "Generic", "uses": { "buf": "Read@Fragment", "out": "Write@ColorAttachment" } } ]})",
        "buffer.json", registry());
    g.resources[0].mips = 0;
    g.resources[0].extent.divisor = 0;
    g.passes[1].uses.at(0).usage.range = SubresourceRange{0, 1, 0, 1};
    const std::string text = compileErrorText(g);
    EXPECT_NE(text.find(g.usageJsonPath(1, 0) + ": pass 'r', resource 'buf': buffers have no mips or layers"),
              std::string::npos)
        << text;
}

// The loader's attachment limits hold for a GraphDesc built in code: two depth attachments were
// planned as both the pass's depth attachment, and nine colour attachments past every device's
// maxColorAttachments.
TEST(GraphsFromCode, AttachmentsPastWhatAPassRendersToAreErrors) {
    // Passes p and q test depth d0 and d1 (cleared); `colors` renders to `count` targets.
    const auto graphText = [](int count) {
        std::string resources = R"("d0": { "type": "image2d", "format": "D32_SFLOAT", "extent": [8, 8], "clear": {"depth": 0} },
              "d1": { "type": "image2d", "format": "D32_SFLOAT", "extent": [8, 8], "clear": {"depth": 0} })";
        std::string colors;
        for (int i = 0; i < count; ++i) {
            const std::string c = "c" + std::to_string(i);
            resources += R"(, ")" + c + R"(": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], )" +
                         R"("external": true, "final": "ShaderRead" })";
            colors += (colors.empty() ? "" : ", ") + std::string(R"(")") + c + R"(": "Write@ColorAttachment")";
        }
        return R"({"version": 1, "name": "t", "resources": {)" + resources + R"(},
            "passes": [
              { "name": "p", "type": "Generic", "uses": { "d0": "ReadWrite@DepthAttachment" } },
              { "name": "q", "type": "Generic", "uses": { "d1": "ReadWrite@DepthAttachment" } },
              { "name": "colors", "type": "Generic", "uses": {)" + colors + "} } ]}";
    };
    // As a file: refused by the loader (the ninth colour attachment).
    EXPECT_THROW((void)parseGraph(graphText(9), "many.json", registry()), GraphError);
    GraphDesc g = parseGraph(graphText(8), "many.json", registry());
    EXPECT_EQ(compileErrorText(g), "") << "eight colour attachments and one depth attachment a pass";
    g.passes[0].uses.push_back(g.passes[1].uses[0]);
    std::string errors = compileErrorText(g);
    EXPECT_NE(errors.find(g.usageJsonPath(0, 1) + ": pass 'p', resource 'd1': a pass renders to one depth attachment, "
                                                  "and " + g.usageJsonPath(0, 0) + " is its depth attachment"),
              std::string::npos)
        << errors;
    g.passes[0].uses.pop_back();
    ResourceDesc c8 = g.resources[g.passes[2].uses.back().resource];  // as c7
    c8.name = "c8";
    g.resources.push_back(c8);
    UsageDecl ninth = g.passes[2].uses.back();
    ninth.resource = static_cast<uint32_t>(g.resources.size() - 1);
    g.passes[2].uses.push_back(ninth);
    errors = compileErrorText(g);
    EXPECT_NE(errors.find(g.usageJsonPath(2, 8) + ": pass 'colors', resource 'c8': a pass renders to at most 8 colour "
                                                  "attachments"),
              std::string::npos)
        << errors;
}

/// Two Generic passes: `w` writes img, then `r` samples it and writes the exported `out`;
/// r's `uses` is written as an object, or as an array when `readerUsesArray`.
GraphDesc writerThenReader(bool readerUsesArray = false) {
    const std::string readerUses =
        readerUsesArray ? R"([ { "resource": "img", "access": "Read", "stage": "Fragment" },
                               { "resource": "out", "access": "Write", "stage": "ColorAttachment" } ])"
                        : R"({ "img": "Read@Fragment", "out": "Write@ColorAttachment" })";
    const std::string text =
        R"({"version": 1, "name": "t", "resources": {
              "img": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8] },
              "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true,
                       "final": "ShaderRead" } },
            "passes": [
              { "name": "w", "type": "Generic", "uses": { "img": "Write@ColorAttachment" } },
              { "name": "r", "type": "Generic", "uses": )" + readerUses + " } ]}";
    return parseGraph(text, "rules.json", registry());
}

// What the loader refuses of a pass, a GraphDesc built in code can hold: compile() names each
// with the loader's words (before, a queue past its enum crashed the queue schedule, a pass on
// a queue that cannot perform its usages compiled into a plan the verifier rejects, a
// condition naming no declared feature culled its pass silently, and too many mips for a
// fixed extent went to vkCreateImage).
TEST(GraphsFromCode, PassesTheLoaderWouldRefuseAreErrors) {
    const GraphDesc raster = loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "raster.json",
                                           PassRegistry::withBuiltins());
    size_t tonemap = 0;
    while (tonemap < raster.passes.size() && raster.passes[tonemap].name != "tonemap") ++tonemap;
    ASSERT_LT(tonemap, raster.passes.size());
    const std::string at = raster.passes[tonemap].jsonPath;
    GraphDesc g = raster;
    g.passes[tonemap].queue = static_cast<QueueKind>(7);
    std::string text = compileErrorText(g);
    EXPECT_NE(text.find(at + ".queue: pass 'tonemap': its queue (7) is not a value of its enum"), std::string::npos) << text;
    g = raster;
    g.passes[tonemap].queue = QueueKind::Transfer;
    text = compileErrorText(g);
    EXPECT_NE(text.find(at + ".queue: pass 'tonemap', resource 'swapchain': runs on the transfer queue, but its use "
                             "of 'swapchain' (Write@ColorAttachment) needs the graphics queue"),
              std::string::npos)
        << text;
    g = raster;
    std::string error;
    g.passes[tonemap].condition = *Condition::parse("skybox && typo_feature", error);
    text = compileErrorText(g);
    EXPECT_NE(text.find(at + ".if: pass 'tonemap': unknown feature 'typo_feature'; the graph declares:"), std::string::npos)
        << text;
    GraphDesc fixed = parseGraph(
        R"({"version": 1, "name": "t", "resources": {
              "img": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "mips": 4 },
              "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true,
                       "final": "ShaderRead" } },
            "passes": [
              { "name": "w", "type": "Generic", "uses": { "img": "Write@Compute" } },
              { "name": "r", "type": "Generic", "uses": { "img": "Read@Fragment", "out": "Write@ColorAttachment" } } ]})",
        "rules.json", registry());
    ResourceDesc& img = *std::find_if(fixed.resources.begin(), fixed.resources.end(),
                                      [](const ResourceDesc& r) { return r.name == "img"; });
    img.mips = 5;  // an 8x8 image has 4
    text = compileErrorText(fixed);
    EXPECT_NE(text.find("resources.img.mips: resource 'img': 5 levels is more than a 8x8 image has (4)"), std::string::npos)
        << text;
    img.mips = 4;
    EXPECT_EQ(compileErrorText(fixed), "");
}

// A pass renders into one framebuffer. Attachments of two sizes were cropped to the smaller,
// and of two layer counts made an invalid framebuffer that crashed `render`; both meet only at
// an output size (mips included), where compile() names them.
TEST(Attachments, OfDifferentSizesOrLayerCountsAreRefusedAtTheOutputSize) {
    // The pass writes "sc" and then the usage `use` of the resource `resource`.
    const auto graph = [](const std::string& resource, const std::string& use) {
        return parseGraph(R"({"version": 1, "name": "t", "resources": {
              "sc": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true,
                      "final": "ShaderRead" }, )" + resource + R"( },
            "passes": [ { "name": "p", "type": "Generic", "uses": [
              { "resource": "sc", "access": "Write", "stage": "ColorAttachment" }, )" + use + R"( ] } ]})",
                          "shapes.json", registry());
    };
    const std::string array =
        R"("arr": { "type": "image2d_array", "format": "R8G8B8A8_UNORM", "extent": "output", "layers": 2 })";
    std::string text =
        compileErrorText(graph(array, R"({ "resource": "arr", "access": "Write", "stage": "ColorAttachment" })"));
    EXPECT_NE(text.find("shapes.json: passes[0].uses[1]: pass 'p', resource 'arr': its attachments differ in shape: "
                        "'sc' 1920x1080 (1 layer) and 'arr' 1920x1080 (2 layers) at output 1920x1080; a pass renders "
                        "into attachments of one size and layer count"),
              std::string::npos)
        << text;
    text = compileErrorText(
        graph(R"("depth": { "type": "image2d", "format": "D32_SFLOAT", "extent": "output/2",
                            "clear": { "depth": 0.0 } })",
              R"({ "resource": "depth", "access": "Write", "stage": "DepthAttachment" })"));
    EXPECT_NE(text.find("passes[0].uses[1]: pass 'p', resource 'depth': its attachments differ in shape: 'sc' "
                        "1920x1080 (1 layer) and 'depth' 960x540 (1 layer)"),
              std::string::npos)
        << text;
    // One layer of the array, or mip 1 of an image twice the size, is the same shape.
    EXPECT_EQ(compileErrorText(graph(
                  array, R"({ "resource": "arr", "access": "Write", "stage": "ColorAttachment", "layers": [1, 1] })")),
              "");
    EXPECT_EQ(compileErrorText(graph(
                  R"("big": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [3840, 2160], "mips": 2 })",
                  R"({ "resource": "big", "access": "Write", "stage": "ColorAttachment", "mips": [1, 1] })")),
              "");
}

// More of what a GraphDesc built in code can hold: enum fields outside their enums (a final
// state past them left an image in UNDEFINED), and two resources of one name that options
// name (a read-back and an export of one name took different resources).
TEST(GraphsFromCode, EnumsOutsideAndAmbiguousNamesAreErrors) {
    GraphDesc g = writerThenReader();
    ResourceDesc& out = g.resources[1];
    out.final = static_cast<ExternalState>(9);
    const std::string text = compileErrorText(g);
    EXPECT_NE(text.find("resources.out: resource 'out': its type (0), initial (3) and final (9) states or sharing (0) "
                        "hold a value outside its enum"),
              std::string::npos)
        << text;
    out.final = ExternalState::ShaderRead;
    out.sharing = static_cast<Sharing>(5);
    EXPECT_NE(compileErrorText(g).find("sharing (5) hold a value outside its enum"), std::string::npos);
    out.sharing = Sharing::Auto;
    out.type = static_cast<ResourceType>(9);
    EXPECT_NE(compileErrorText(g).find("its type (9)"), std::string::npos);
    out.type = ResourceType::Image2D;
    ASSERT_EQ(compileErrorText(g), "");

    const auto optionsError = [&](const CompileOptions& o) {
        try {
            (void)compile(g, o);
        } catch (const GraphError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    CompileOptions o;
    o.placement = static_cast<MemoryStrategy>(9);
    EXPECT_NE(optionsError(o).find("CompileOptions::placement (9) is not a value of its enum"), std::string::npos);
    o = {};
    o.layouts = static_cast<LayoutPolicy>(4);
    EXPECT_NE(optionsError(o).find("CompileOptions::layouts (4) is not a value of its enum"), std::string::npos);
    o = {};
    o.presentReplacement = static_cast<ExternalState>(7);
    EXPECT_NE(optionsError(o).find("CompileOptions::presentReplacement (7) is not a value of its enum"),
              std::string::npos);
    g.layouts = static_cast<LayoutPolicy>(3);
    EXPECT_NE(optionsError({}).find("the graph's layouts (3) is not a value of its enum"), std::string::npos);
    g.layouts = LayoutPolicy::FewestBarriers;

    g.resources.push_back(g.resources[0]);  // a second 'img'
    o = {};
    o.readbacks = {"img"};
    EXPECT_NE(optionsError(o).find("resource 'img': 2 resources are named 'img': the options that name it cannot tell "
                                   "which"),
              std::string::npos)
        << optionsError(o);
}

// The compiler's table answers as the rule it is built from, for every subject and every byte
// value of a usage's three fields (values past an enum do not fit).
TEST(UsageFit, TheTableAnswersAsTheRule) {
    for (uint32_t row = 0; row < 16; ++row)
        for (uint32_t stage = 0; stage < 256; ++stage)
            for (uint32_t access = 0; access < 256; access += (access < 8 ? 1 : 61))
                for (uint32_t as = 0; as < 256; as += (as < 8 ? 1 : 83)) {
                    const UsageSubject subject{(row & 1) != 0, (row & 2) != 0, (row & 4) != 0, (row & 8) != 0};
                    const UsageMode mode{static_cast<Access>(access), static_cast<Stage>(stage), static_cast<BindAs>(as)};
                    ASSERT_EQ(usageFits(fitRow(subject), mode), usageMisfit(subject, mode) == UsageMisfit::Fits)
                        << "row " << row << " stage " << stage << " access " << access << " as " << as;
                }
}

// The loader refuses a usage its resource cannot have; a GraphDesc built in code can hold one,
// and compile() names it with the loader's words (a buffer as an attachment made the executor
// build a framebuffer of a buffer; a stage past its enum read past the synchronizer's table).
TEST(GraphsFromCode, UsagesTheirResourceCannotHaveAreErrors) {
    const GraphDesc base = writerThenReader();
    const auto withBuffer = [](GraphDesc& g) {
        ResourceDesc buffer;
        buffer.name = "buf";
        buffer.type = ResourceType::Buffer;
        buffer.sizeBytes = 64;
        buffer.clear.reset();
        g.resources.push_back(buffer);
        return static_cast<uint32_t>(g.resources.size() - 1);
    };
    struct Case {
        std::function<void(GraphDesc&)> edit;
        std::string words, path, resource;
    };
    const std::vector<Case> cases{
        {[&](GraphDesc& g) { g.passes[0].uses[0].resource = withBuffer(g); },
         "a buffer cannot be an attachment (Write@ColorAttachment)", "passes[0].uses.buf", "buf"},
        {[](GraphDesc& g) { g.passes[0].uses[0].usage.stage = Stage::DepthAttachment; },
         "format R8G8B8A8_UNORM has no depth or stencil; it cannot be a depth attachment", "passes[0].uses.img",
         "img"},
        {[](GraphDesc& g) { g.passes[1].uses[0].usage.access = Access::Write; },
         "a sampled image is read-only", "passes[1].uses.img", "img"},
        {[](GraphDesc& g) { g.passes[1].uses[0].usage.as = BindAs::Uniform; },
         "images cannot be uniform buffers", "passes[1].uses.img", "img"},
        {[](GraphDesc& g) {
             g.passes[1].uses[0].usage.stage = Stage::VertexInput;
             g.passes[1].uses[0].usage.as = BindAs::Default;
         },
         "VertexInput reads buffers, not images", "passes[1].uses.img", "img"},
        {[](GraphDesc& g) { g.passes[1].uses[1].usage.as = BindAs::Index; },
         "`as: index` applies to VertexInput only", "passes[1].uses.out", "out"},
        {[](GraphDesc& g) { g.resources[0].mips = 2; },
         "an attachment renders to one mip level", "passes[0].uses.img", "img"},
        {[](GraphDesc& g) { g.passes[0].uses[0].usage.range = SubresourceRange{0, 2, 0, 1}; },
         "an attachment renders to one mip level", "passes[0].uses.img", "img"},
        {[](GraphDesc& g) { g.passes[1].uses[0].usage.stage = static_cast<Stage>(8); },
         "stage (8)", "passes[1].uses.img", "img"},
        {[](GraphDesc& g) { g.passes[1].uses[0].usage.access = static_cast<Access>(3); },
         "access (3)", "passes[1].uses.img", "img"},
        {[](GraphDesc& g) { g.passes[1].uses[0].usage.as = static_cast<BindAs>(5); },
         "binding (5)", "passes[1].uses.img", "img"},
        // A pass switched off is checked too, as the loader checks it.
        {[&](GraphDesc& g) {
             g.features.push_back({"extra", false});
             std::string error;
             PassDesc extra = g.passes[0];
             extra.name = "extra";
             extra.jsonPath.clear();
             extra.condition = *Condition::parse("extra", error);
             extra.uses[0].resource = withBuffer(g);
             g.passes.push_back(extra);
         },
         "a buffer cannot be an attachment", "pass 'extra'", "buf"},
    };
    for (const Case& c : cases) {
        GraphDesc g = base;
        c.edit(g);
        const std::string text = compileErrorText(g);
        EXPECT_NE(text.find(c.words), std::string::npos) << c.words << ": " << text;
        EXPECT_NE(text.find(c.path), std::string::npos) << c.words << ": " << text;
        EXPECT_NE(text.find("resource '" + c.resource + "'"), std::string::npos) << c.words << ": " << text;
    }
    // One mip of a chain as an attachment fits, as in a file.
    GraphDesc chain = base;
    chain.resources[0].mips = 2;
    chain.passes[0].uses[0].usage.range = SubresourceRange{1, 1, 0, 1};
    chain.passes[1].uses[0].usage.range = SubresourceRange{1, 1, 0, 1};
    EXPECT_EQ(compileErrorText(chain), "");
}

// A pass's reads are sourced by earlier passes only, whichever order its usages come in. The
// loader refuses a pass that uses a subresource twice; a GraphDesc built in code can have one
// that writes an image and then reads it, and that read has no source.
TEST(GraphsFromCode, APassDoesNotSourceItsOwnReads) {
    GraphDesc graph = writerThenReader();
    EXPECT_EQ(compileErrorText(graph), "");  // as loaded: w's write sources r's read
    // w then writes img and reads it in one pass; r no longer reads it.
    UsageDecl read = graph.passes[1].uses.at(0);
    ASSERT_EQ(read.usage.access, Access::Read);
    graph.passes[1].uses.erase(graph.passes[1].uses.begin());
    graph.passes[0].uses.push_back(read);
    const std::string errors = compileErrorText(graph);
    EXPECT_NE(errors.find("passes[0].uses.img"), std::string::npos) << errors;
    EXPECT_NE(errors.find("pass 'w'"), std::string::npos) << errors;
    EXPECT_NE(errors.find("no earlier pass writes it"), std::string::npos) << errors;
}

// A pass that reads a subresource and also writes it (only a GraphDesc built in code can
// hold one) is refused as the loader refuses it, whichever order its usages come in: a render
// pass cannot sample its own attachment, and no barrier orders a pass after itself.
TEST(GraphsFromCode, APassThatReadsAndWritesOneSubresourceIsAnError) {
    GraphDesc graph = writerThenReader();
    ASSERT_EQ(graph.passes[1].uses.at(0).usage.access, Access::Read);
    for (const bool writeFirst : {false, true}) {
        GraphDesc g = graph;
        UsageDecl write = g.passes[1].uses.at(0);
        write.usage.access = Access::Write;
        write.usage.stage = Stage::Compute;
        write.usage.as = BindAs::Storage;
        auto& uses = g.passes[1].uses;
        uses.insert(writeFirst ? uses.begin() : uses.begin() + 1, write);
        const std::string text = compileErrorText(g);
        // Both usages' paths are passes[1].uses.img (written by name): the other is named by index.
        EXPECT_NE(text.find("passes[1].uses.img: pass 'r', resource 'img': overlaps the pass's usage 0 of it; one pass "
                            "may use each subresource once"),
                  std::string::npos)
            << "writeFirst=" << writeFirst << ": " << text;
    }
}

// Usages' JSON paths are derived from where they sit: by resource name when the file writes
// `uses` as an object, by index when as an array, and from the pass's index when a pass built
// in code has no path of its own.
TEST(GraphsFromCode, UsageJsonPathsAreDerivedFromTheirPlace) {
    GraphDesc graph = writerThenReader(/*readerUsesArray=*/true);
    EXPECT_EQ(graph.usageJsonPath(0, 0), "passes[0].uses.img");
    EXPECT_EQ(graph.usageJsonPath(1, 1), "passes[1].uses[1]");
    EXPECT_EQ(graph.resources.at(1).jsonPath(), "resources.out");
    PassDesc built = graph.passes[1];
    built.jsonPath.clear();
    built.usesByName = true;
    built.uses[0].resource = 7;  // not there: worded by index
    graph.passes.push_back(built);
    EXPECT_EQ(graph.usageJsonPath(2, 0), "passes[2].uses[0]");
    EXPECT_EQ(graph.usageJsonPath(2, 1), "passes[2].uses.out");
    EXPECT_THROW((void)graph.usageJsonPath(2, 2), std::out_of_range);
}

// Slot names are interned per graph: a usage's slot is an id, and an id the graph did not hand
// out (only a GraphDesc built in code can have one) is a GraphError naming the usage.
TEST(GraphsFromCode, SlotsAreInternedAndAnUnknownSlotIdIsAnError) {
    GraphDesc raster = loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "raster.json",
                                     PassRegistry::withBuiltins());
    ASSERT_FALSE(raster.slotNames.empty());
    const SlotId depth = raster.internSlot("depth");
    EXPECT_EQ(raster.slotName(depth), "depth");
    EXPECT_EQ(raster.internSlot("depth"), depth);  // interned once
    EXPECT_EQ(raster.internSlot(""), 0u);
    EXPECT_EQ(raster.slotName(0), "");
    const size_t names = raster.slotNames.size();
    const SlotId fresh = raster.internSlot("a slot no pass type has");
    EXPECT_EQ(fresh, names + 1);
    EXPECT_EQ(raster.slotName(fresh), "a slot no pass type has");
    EXPECT_THROW((void)raster.slotName(fresh + 1), std::out_of_range);

    UsageDecl& use = raster.passes.at(1).uses.at(0);
    use.slot = fresh + 1;
    const std::string text = compileErrorText(raster);
    ASSERT_FALSE(text.empty()) << "expected a GraphError";
    EXPECT_NE(text.find(raster.usageJsonPath(1, 0)), std::string::npos) << text;
    EXPECT_NE(text.find("names slot id " + std::to_string(fresh + 1) + ", but the graph has " +
                        std::to_string(fresh) + " slot name(s)"),
              std::string::npos)
        << text;
}

// Subresources are numbered with 32 bits: a GraphDesc built in code whose images have more
// layers than that together is an error naming the resource, not a wrapped index.
TEST(GraphsFromCode, MoreSubresourcesThanTheBoundIsAnError) {
    // Each within the limits (15 levels of 2048 layers), together past 2^24 subresources.
    GraphDesc raster = loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "raster.json",
                                     PassRegistry::withBuiltins());
    ResourceDesc big;
    big.type = ResourceType::Image2DArray;
    big.format = *findFormat(VK_FORMAT_R8_UNORM);
    big.extent = Extent{false, 1, 16384, 16384};
    big.mips = 15;
    big.layers = 2048;
    big.external = true;
    big.initial = ExternalState::ShaderRead;
    const size_t count = (size_t(1) << 24) / (15 * 2048) + 1;
    for (size_t i = 0; i < count; ++i) {
        big.name = "big" + std::to_string(i);
        raster.resources.push_back(big);
    }
    const std::string text = compileErrorText(raster);
    ASSERT_FALSE(text.empty()) << "expected a GraphError";
    EXPECT_NE(text.find("resource 'big" + std::to_string(count - 1) + "'"), std::string::npos) << text;
    EXPECT_NE(text.find("more than 16777216 subresources (mip levels x layers) together"), std::string::npos) << text;
    // One resource past the layer limit is refused by the limits first.
    raster.resources.resize(raster.resources.size() - count);
    raster.resources[0].layers = UINT32_MAX;
    EXPECT_NE(compileErrorText(raster).find("layers must be between 1 and 2048, not 4294967295"), std::string::npos);
}

// A planned usage keeps how it was written (access, stage, binding) and the range the compiler
// resolved: the written range where there is one, the whole resource where there is none.
TEST(Ranges, APlannedUsageKeepsItsModeAndTheResolvedRange) {
    const Plan plan = compileGraph(
        R"("chain": {"type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [16, 16], "mips": 4, "external": true, "final": "ShaderRead"})",
        R"({"name": "all", "type": "Generic", "uses": [{"resource": "chain", "access": "Write", "stage": "Compute", "as": "storage"}]},
           {"name": "one", "type": "Generic", "never_cull": true, "uses": [{"resource": "chain", "access": "Read", "stage": "Fragment", "mips": [2, 1]}]})");
    const auto& all = pass(plan, "all").usages;
    ASSERT_EQ(all.size(), 1u);
    EXPECT_EQ(all[0].usage, (UsageMode{Access::Write, Stage::Compute, BindAs::Storage}));
    EXPECT_EQ(all[0].range, (SubresourceRange{0, 4, 0, 1}));
    const auto& one = pass(plan, "one").usages;
    ASSERT_EQ(one.size(), 1u);
    // The loader settles the binding the file left out (docs/graph-format.md, "Usages").
    EXPECT_EQ(one[0].usage, (UsageMode{Access::Read, Stage::Fragment, BindAs::Sampled}));
    EXPECT_EQ(one[0].range, (SubresourceRange{2, 1, 0, 1}));
    EXPECT_EQ(toString(one[0].usage), "Read@Fragment as sampled");
    EXPECT_EQ(toString(all[0].usage), "Write@Compute as storage");
}

// What a shader binds a usage as when the file (or a GraphDesc built in code) leaves it out.
TEST(UsageModes, ADefaultBindingResolvesByResourceAndAccess) {
    EXPECT_EQ(resolvedBinding({Access::Read, Stage::Fragment, BindAs::Default}, true), BindAs::Sampled);
    EXPECT_EQ(resolvedBinding({Access::Write, Stage::Compute, BindAs::Default}, true), BindAs::Storage);
    EXPECT_EQ(resolvedBinding({Access::ReadWrite, Stage::Compute, BindAs::Default}, true), BindAs::Storage);
    EXPECT_EQ(resolvedBinding({Access::Read, Stage::Compute, BindAs::Default}, false), BindAs::Storage);
    EXPECT_EQ(resolvedBinding({Access::Read, Stage::Fragment, BindAs::Uniform}, false), BindAs::Uniform);
    EXPECT_EQ(resolvedBinding({Access::Read, Stage::Compute, BindAs::Storage}, true), BindAs::Storage);
    EXPECT_EQ(resolvedBinding({Access::Read, Stage::Transfer, BindAs::Default}, true), BindAs::Default)
        << "only shader stages bind";
}

// Rule 8: an external resource arrives with readers outside the frame in its initial state's
// scope (ShaderRead: fragment and compute shaders). A write after the frame's own reads must
// wait for those outside readers too, not only for the frame's reads.
TEST(BarrierRules, AWriteAfterTheFramesReadsStillWaitsForTheReadersOutside) {
    const Plan plan = compileGraph(R"("buf": {"type": "buffer", "size": 256, "external": true, "final": "ShaderRead"},)" +
                                       std::string(kOut),
                                   R"(
        {"name": "read", "type": "Generic", "uses": {"buf": "Read@Fragment", "out": "Write@ColorAttachment"}},
        {"name": "write", "type": "Generic", "uses": {"buf": "Write@Compute"}})");
    const auto b = barriersOf(plan, "write", "buf");
    ASSERT_EQ(b.size(), 1u);
    EXPECT_EQ(b[0].srcStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT)
        << "the draw that read it, and whatever read it outside the frame";
    EXPECT_EQ(b[0].srcAccess, 0u) << "write after read: an execution dependency";
}

// Rule 5: a layout transition made for a read is the last write. A final barrier that makes the
// contents visible to more stages afterwards must chain after that transition (through the
// stages it was made visible to), not only after the write before it.
TEST(BarrierRules, AFinalBarrierAfterAReadsTransitionChainsAfterIt) {
    const Plan plan = compileGraph(
        R"("img": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "final": "ShaderRead"},)" +
            std::string(kOut),
        R"(
        {"name": "write", "type": "Generic", "uses": {"img": "Write@Compute"}},
        {"name": "sample", "type": "Generic", "uses": {"img": "Read@Fragment", "out": "Write@ColorAttachment"}})");
    const auto sampled = barriersOf(plan, "sample", "img");
    ASSERT_EQ(sampled.size(), 1u);
    EXPECT_EQ(sampled[0].oldLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(sampled[0].newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(sampled[0].dstStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
    const Barrier* final = nullptr;
    for (const Barrier& b : plan.finalBarriers())
        if (plan.resources()[b.resource].name == "img") final = &b;
    ASSERT_NE(final, nullptr);
    EXPECT_TRUE(final->srcStages & VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT) << "chains after the transition";
    EXPECT_TRUE(final->srcStages & VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT) << "and repeats the write (rule 1)";
    EXPECT_EQ(final->srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(final->dstStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
}

// Rule 8: a persistent external (`final: General`) hands each frame's contents to the next
// frame's first uses: the final barrier's destination covers the first use of every
// subresource, not only the first pass's (here mip 1 is first sampled two passes later).
TEST(BarrierRules, APersistentResourceIsHandedToTheFirstUseOfEverySubresource) {
    const Plan plan = compileGraph(
        R"("state": {"type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [16, 16], "mips": 2, "external": true, "final": "General"},)" +
            std::string(kOut),
        R"(
        {"name": "accumulate", "type": "Generic", "uses": [{"resource": "state", "access": "ReadWrite", "stage": "Compute", "mips": [0, 1]}]},
        {"name": "downsample", "type": "Generic", "uses": [{"resource": "state", "access": "Read", "stage": "Compute", "mips": [0, 1]},
                                                          {"resource": "out", "access": "Write", "stage": "Compute"}]},
        {"name": "show", "type": "Generic", "uses": [{"resource": "state", "access": "Read", "stage": "Fragment", "mips": [1, 1]},
                                                    {"resource": "out", "access": "ReadWrite", "stage": "ColorAttachment"}]})");
    VkPipelineStageFlags2 finalDst = 0;
    for (const Barrier& b : plan.finalBarriers())
        if (plan.resources()[b.resource].name == "state") finalDst |= b.dstStages;
    EXPECT_EQ(finalDst, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
    // The next frame's first barrier of mip 1 sources from the same stages: the two chain.
    const auto shown = barriersOf(plan, "show", "state");
    ASSERT_EQ(shown.size(), 1u);
    EXPECT_EQ(shown[0].range, (SubresourceRange{1, 1, 0, 1}));
    EXPECT_TRUE(shown[0].srcStages & VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
}

}  // namespace
}  // namespace skygraph
