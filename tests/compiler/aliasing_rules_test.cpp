// Rule 16 of docs/barriers.md, aliasing barriers, and clobbering, on graphs written here. Each
// expectation was checked against the spec's "Memory Aliasing" section (a use of memory that
// another resource wrote must be separated from it by a memory dependency, a read by an
// execution dependency; the barrier must contain every subresource that overlaps; an image
// whose memory an alias wrote starts from UNDEFINED) and its chapter on synchronization.
#include <skygraph/compiler.hpp>

#include "plan_queries.hpp"

#include <gtest/gtest.h>

#include <initializer_list>
#include <memory>
#include <stdexcept>
#include <string>

namespace skygraph {
namespace {

using test::barriersOf;
using test::pass;
using test::registry;

std::vector<uint32_t> ids(std::span<const uint32_t> aliases) { return {aliases.begin(), aliases.end()}; }

/// Options for one frame on its own: each frame in flight with heaps of its own, so that a
/// resource's first barrier shows what it takes over within the frame alone.
CompileOptions oneFrame() {
    CompileOptions o;
    o.shareTransientsAcrossFrames = false;
    return o;
}

Plan compileGraph(const std::string& resources, const std::string& passes, CompileOptions options = oneFrame()) {
    const std::string text = R"({"version": 1, "name": "t", "resources": {)" + resources + R"(}, "passes": [)" +
                             passes + "]}";
    return compile(parseGraph(text, "aliasing.json", registry()), options);
}

const MemoryPlacement& placementOf(const Plan& plan, const std::string& resource) {
    const int32_t r = plan.resourceIndex(resource);
    if (r < 0 || plan.resources()[r].placement == PlannedResource::kNoPlacement)
        throw std::runtime_error("no placement for " + resource);
    return plan.memory().placements[plan.resources()[r].placement];
}

// Two same-sized transients with disjoint lifetimes: `a` is written by compute and sampled by
// a fragment shader, then `b` is written as a color attachment into the same memory.
constexpr const char* kTwo = R"(
    "a": {"type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [64, 64]},
    "b": {"type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [64, 64]},
    "mid": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64]},
    "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64], "external": true, "final": "TransferSrc"})";
constexpr const char* kTwoPasses = R"(
    {"name": "make_a", "type": "Generic", "uses": {"a": "Write@Compute"}},
    {"name": "use_a", "type": "Generic", "uses": {"a": "Read@Fragment", "mid": "Write@ColorAttachment"}},
    {"name": "make_b", "type": "Generic", "uses": {"mid": "Read@Fragment", "b": "Write@ColorAttachment"}},
    {"name": "use_b", "type": "Generic", "uses": {"b": "Read@Fragment", "out": "Write@ColorAttachment"}})";

TEST(AliasingRules, ATakenOverResourceWaitsForItsPredecessorsLastWriteAndReads) {
    const Plan plan = compileGraph(kTwo, kTwoPasses);
    ASSERT_EQ(ids(placementOf(plan, "b").aliases), std::vector<uint32_t>{uint32_t(plan.resourceIndex("a"))});
    EXPECT_EQ(placementOf(plan, "a").offset, placementOf(plan, "b").offset);
    const auto b = barriersOf(plan, "make_b", "b");
    ASSERT_EQ(b.size(), 1u);
    EXPECT_TRUE(b[0].aliasing);
    // a's last use read it after a barrier made its write available, but that barrier named
    // a's subresources, not every one that overlaps b: this one repeats the write (stage and
    // access) and waits for the read, so it is the whole memory dependency.
    EXPECT_EQ(b[0].srcStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(b[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(b[0].dstStages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
    EXPECT_EQ(b[0].dstAccess, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    EXPECT_EQ(b[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(b[0].newLayout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    // Without aliasing, b's first use needs nothing before it (rule 6).
    CompileOptions off = oneFrame();
    off.aliasing = false;
    const Plan apart = compileGraph(kTwo, kTwoPasses, off);
    const auto first = barriersOf(apart, "make_b", "b");
    ASSERT_EQ(first.size(), 1u);
    EXPECT_FALSE(first[0].aliasing);
    EXPECT_EQ(first[0].srcStages, 0u);
    EXPECT_EQ(apart.memory().heapBytes(), apart.memory().unaliasedBytes);
    EXPECT_LT(plan.memory().heapBytes(), plan.memory().unaliasedBytes);
}

TEST(AliasingRules, AnUnreadWriteOfThePredecessorIsAMemoryDependency) {
    // `a` is written last by a pass that also writes `mid` (which is read), and nothing reads
    // that write of `a`: its availability is this barrier's to perform.
    const Plan plan = compileGraph(kTwo, R"(
        {"name": "make_a", "type": "Generic", "uses": {"a": "Write@Compute"}},
        {"name": "use_a", "type": "Generic", "uses": {"a": "ReadWrite@Compute", "mid": "Write@Compute"}},
        {"name": "make_b", "type": "Generic", "uses": {"mid": "Read@Fragment", "b": "Write@ColorAttachment"}},
        {"name": "use_b", "type": "Generic", "uses": {"b": "Read@Fragment", "out": "Write@ColorAttachment"}})");
    const auto b = barriersOf(plan, "make_b", "b");
    ASSERT_EQ(b.size(), 1u);
    EXPECT_TRUE(b[0].aliasing);
    EXPECT_EQ(b[0].srcStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(b[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(b[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
}

TEST(AliasingRules, TheAliasingBarrierCoversEverySubresource) {
    // `chain` takes over `a`'s memory, and its first pass writes only mip 0: that pass's batch
    // still transitions all its mips (one barrier, merged), so that it contains every
    // subresource that overlaps. The later mips then need no barrier before their writes: the
    // transition was ordered before every compute shader after it.
    const Plan plan = compileGraph(R"(
        "a": {"type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [64, 64]},
        "mid": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64]},
        "chain": {"type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [64, 64], "mips": 3},
        "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64], "external": true, "final": "TransferSrc"})",
                                   R"(
        {"name": "make_a", "type": "Generic", "uses": {"a": "Write@Compute"}},
        {"name": "use_a", "type": "Generic", "uses": {"a": "Read@Compute", "mid": "Write@Compute"}},
        {"name": "mip0", "type": "Generic", "uses": [{"resource": "mid", "access": "Read", "stage": "Compute"},
                                                     {"resource": "chain", "access": "Write", "stage": "Compute", "mips": [0, 1]}]},
        {"name": "mip1", "type": "Generic", "uses": [{"resource": "chain", "access": "Read", "stage": "Compute", "mips": [0, 1]},
                                                     {"resource": "chain", "access": "Write", "stage": "Compute", "mips": [1, 1]}]},
        {"name": "mip2", "type": "Generic", "uses": [{"resource": "chain", "access": "Read", "stage": "Compute", "mips": [1, 1]},
                                                     {"resource": "chain", "access": "Write", "stage": "Compute", "mips": [2, 1]}]},
        {"name": "use", "type": "Generic", "uses": [{"resource": "chain", "access": "Read", "stage": "Fragment"},
                                                    {"resource": "out", "access": "Write", "stage": "ColorAttachment"}]})");
    ASSERT_EQ(ids(placementOf(plan, "chain").aliases), std::vector<uint32_t>{uint32_t(plan.resourceIndex("a"))});
    const auto first = barriersOf(plan, "mip0", "chain");
    ASSERT_EQ(first.size(), 1u);
    EXPECT_TRUE(first[0].aliasing);
    EXPECT_EQ(first[0].range, (SubresourceRange{0, 3, 0, 1}));
    EXPECT_EQ(first[0].srcStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(first[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT) << "a's write, repeated";
    EXPECT_EQ(first[0].dstStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(first[0].dstAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(first[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(first[0].newLayout, VK_IMAGE_LAYOUT_GENERAL);
    const auto second = barriersOf(plan, "mip1", "chain");
    ASSERT_EQ(second.size(), 1u) << "only mip 0's read: mip 1 was transitioned for compute writes already";
    EXPECT_FALSE(second[0].aliasing);
    EXPECT_EQ(second[0].range, (SubresourceRange{0, 1, 0, 1}));
}

TEST(AliasingRules, AFirstStepInSeveralLayoutsTakesGeneralUnderOneBarrier) {
    // `b`'s first pass writes layer 0 as a colour attachment and layer 1 in a dispatch. One
    // barrier per layout would each contain only part of b; so the pass uses both in GENERAL
    // (which a colour attachment accepts) after one barrier over both layers, whose
    // destination is the whole pass's.
    const Plan plan = compileGraph(R"(
        "a": {"type": "image2d_array", "format": "R16G16B16A16_SFLOAT", "extent": [64, 64], "layers": 2},
        "b": {"type": "image2d_array", "format": "R16G16B16A16_SFLOAT", "extent": [64, 64], "layers": 2},
        "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64], "external": true, "final": "TransferSrc"})",
                                   R"(
        {"name": "make_a", "type": "Generic", "uses": {"a": "Write@Compute"}},
        {"name": "use_a", "type": "Generic", "uses": [{"resource": "a", "access": "Read", "stage": "Fragment", "layers": [0, 1]},
                                                      {"resource": "out", "access": "Write", "stage": "ColorAttachment"}]},
        {"name": "make_b", "type": "Generic", "uses": [{"resource": "b", "access": "Write", "stage": "ColorAttachment", "layers": [0, 1]},
                                                       {"resource": "b", "access": "Write", "stage": "Compute", "layers": [1, 1]}]},
        {"name": "use_b", "type": "Generic", "uses": {"b": "Read@Fragment", "out": "ReadWrite@ColorAttachment"}})");
    ASSERT_EQ(ids(placementOf(plan, "b").aliases), std::vector<uint32_t>{uint32_t(plan.resourceIndex("a"))});
    const auto b = barriersOf(plan, "make_b", "b");
    ASSERT_EQ(b.size(), 1u);
    EXPECT_TRUE(b[0].aliasing);
    EXPECT_EQ(b[0].range, (SubresourceRange{0, 1, 0, 2}));
    // a's layer 1 was written and never read: the write is repeated, with the read of layer 0.
    EXPECT_EQ(b[0].srcStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(b[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(b[0].dstStages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(b[0].dstAccess, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(b[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(b[0].newLayout, VK_IMAGE_LAYOUT_GENERAL);
    for (const PlannedUsage& u : pass(plan, "make_b").usages) EXPECT_EQ(u.layout, VK_IMAGE_LAYOUT_GENERAL);
    // Taking over no memory (each frame in flight with heaps of its own, alone in them), the
    // pass keeps each usage's own layout, aliasing or not. With the frames sharing the heaps
    // b takes over its own bytes from the previous frame, and the pass takes GENERAL.
    const std::string alone = R"(
        "b": {"type": "image2d_array", "format": "R16G16B16A16_SFLOAT", "extent": [64, 64], "layers": 2},
        "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64], "external": true, "final": "TransferSrc"})";
    const std::string alonePasses = R"(
        {"name": "make_b", "type": "Generic", "uses": [{"resource": "b", "access": "Write", "stage": "ColorAttachment", "layers": [0, 1]},
                                                       {"resource": "b", "access": "Write", "stage": "Compute", "layers": [1, 1]}]},
        {"name": "use_b", "type": "Generic", "uses": {"b": "Read@Fragment", "out": "Write@ColorAttachment"}})";
    CompileOptions off = oneFrame();
    off.aliasing = false;
    const CompileOptions on = oneFrame();
    for (const CompileOptions* o : std::initializer_list<const CompileOptions*>{&off, &on}) {
        const Plan apart = compileGraph(alone, alonePasses, *o);
        EXPECT_EQ(pass(apart, "make_b").usages[0].layout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        EXPECT_EQ(pass(apart, "make_b").usages[1].layout, VK_IMAGE_LAYOUT_GENERAL);
        EXPECT_EQ(barriersOf(apart, "make_b", "b").size(), 2u);
    }
    const CompileOptions shared;
    ASSERT_TRUE(shared.shareTransientsAcrossFrames && shared.aliasing);
    const Plan sharedPlan = compileGraph(alone, alonePasses, shared);
    EXPECT_EQ(ids(placementOf(sharedPlan, "b").previousFrameAliases),
              std::vector<uint32_t>{uint32_t(sharedPlan.resourceIndex("b"))});
    const auto fromPreviousFrame = barriersOf(sharedPlan, "make_b", "b");
    ASSERT_EQ(fromPreviousFrame.size(), 1u);
    EXPECT_TRUE(fromPreviousFrame[0].aliasing);
    EXPECT_EQ(fromPreviousFrame[0].newLayout, VK_IMAGE_LAYOUT_GENERAL);
}

TEST(AliasingRules, ATakenOverResourceWaitsForEveryEarlierUseOfItsBytes) {
    // x is drawn and sampled, y takes over its bytes (compute), z takes over y's: z's barrier
    // names y's uses and, through what y waited for, x's too. y alone would order x before z,
    // but a barrier on y covers y's bytes only, and x's may reach past them.
    const Plan plan = compileGraph(R"(
        "x": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64]},
        "y": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64]},
        "z": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64]},
        "m1": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64]},
        "m2": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64]},
        "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64], "external": true, "final": "TransferSrc"})",
                                   R"(
        {"name": "make_x", "type": "Generic", "uses": {"x": "Write@ColorAttachment"}},
        {"name": "use_x", "type": "Generic", "uses": {"x": "Read@Fragment", "m1": "Write@ColorAttachment"}},
        {"name": "make_y", "type": "Generic", "uses": {"m1": "Read@Compute", "y": "Write@Compute"}},
        {"name": "use_y", "type": "Generic", "uses": {"y": "Read@Compute", "m2": "Write@Compute"}},
        {"name": "make_z", "type": "Generic", "uses": {"m2": "Read@Transfer", "z": "Write@Transfer"}},
        {"name": "use_z", "type": "Generic", "uses": {"z": "Read@Fragment", "out": "Write@ColorAttachment"}})");
    ASSERT_EQ(ids(placementOf(plan, "y").aliases), std::vector<uint32_t>{uint32_t(plan.resourceIndex("x"))});
    ASSERT_EQ(ids(placementOf(plan, "z").aliases), std::vector<uint32_t>{uint32_t(plan.resourceIndex("y"))});
    const auto z = barriersOf(plan, "make_z", "z");
    ASSERT_EQ(z.size(), 1u);
    EXPECT_EQ(z[0].srcStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT |
                                  VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
    EXPECT_EQ(z[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
}

TEST(AliasingRules, AliasFalseAndExternalsNeverShare) {
    const std::string resources = std::string(kTwo).replace(std::string(kTwo).find("\"extent\": [64, 64]},"), 20,
                                                             "\"extent\": [64, 64], \"alias\": false},");
    const Plan plan = compileGraph(resources, kTwoPasses);
    EXPECT_FALSE(placementOf(plan, "a").aliasable);
    EXPECT_TRUE(placementOf(plan, "b").aliases.empty());
    EXPECT_NE(placementOf(plan, "a").offset, placementOf(plan, "b").offset);
    for (const auto& b : barriersOf(plan, "make_b", "b")) EXPECT_FALSE(b.aliasing);
    EXPECT_EQ(plan.resources()[plan.resourceIndex("out")].placement, PlannedResource::kNoPlacement);
    EXPECT_THROW(compileGraph(R"("x": {"type": "buffer", "size": 16, "external": true, "alias": false})",
                              R"({"name": "p", "type": "Generic", "uses": {"x": "Read@Compute"}})"),
                 GraphError);
}

TEST(AliasingRules, FramesSharingTheHeapsWaitForThePreviousFramesLastUses) {
    CompileOptions o;
    o.shareTransientsAcrossFrames = true;
    const Plan plan = compileGraph(kTwo, kTwoPasses, o);
    EXPECT_TRUE(plan.memory().sharedAcrossFrames);
    const uint32_t a = uint32_t(plan.resourceIndex("a")), b = uint32_t(plan.resourceIndex("b"));
    const uint32_t mid = uint32_t(plan.resourceIndex("mid"));
    for (const char* r : {"a", "b", "mid"})
        EXPECT_EQ(plan.resources()[plan.resourceIndex(r)].copies, ResourceCopies::SharedTransient) << r;
    EXPECT_EQ(plan.resources()[plan.resourceIndex("out")].copies, ResourceCopies::SharedExported);
    // a and b share bytes, and b holds them when the frame ends: the next frame's a waits for
    // every use of them in the frame before, b's (its color write and the fragment read) and,
    // through what b waited for, a's own compute write; mid holds its own bytes across frames.
    EXPECT_TRUE(placementOf(plan, "a").aliases.empty());
    EXPECT_EQ(ids(placementOf(plan, "a").previousFrameAliases), std::vector<uint32_t>{b});
    EXPECT_EQ(ids(placementOf(plan, "b").aliases), std::vector<uint32_t>{a});
    EXPECT_TRUE(placementOf(plan, "b").previousFrameAliases.empty()) << "its bytes were a's earlier in the frame";
    EXPECT_EQ(ids(placementOf(plan, "mid").previousFrameAliases), std::vector<uint32_t>{mid});
    const auto first = barriersOf(plan, "make_a", "a");
    ASSERT_EQ(first.size(), 1u);
    EXPECT_TRUE(first[0].aliasing);
    constexpr VkPipelineStageFlags2 drawnThenSampled =
        VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
    EXPECT_EQ(first[0].srcStages, drawnThenSampled | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(first[0].srcAccess, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(first[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    // mid is drawn (use_a) and sampled (make_b) every frame: the next frame's draw waits for both.
    const auto midFirst = barriersOf(plan, "use_a", "mid");
    ASSERT_EQ(midFirst.size(), 1u);
    EXPECT_TRUE(midFirst[0].aliasing);
    EXPECT_EQ(midFirst[0].srcStages, drawnThenSampled);
    EXPECT_EQ(midFirst[0].srcAccess, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    // Without sharing, each frame has copies of its own and the frame's first uses wait for
    // nothing of the previous frame.
    const Plan apart = compileGraph(kTwo, kTwoPasses);
    EXPECT_EQ(apart.resources()[apart.resourceIndex("a")].copies, ResourceCopies::PerFrameTransient);
    EXPECT_EQ(barriersOf(apart, "make_a", "a")[0].srcStages, 0u);
}

TEST(AliasingRules, APredecessorsUnreadWriteInThePreviousFrameIsAMemoryDependency) {
    // `a` is last written by a pass that also writes what the frame exports, and nothing
    // reads that write: the next frame's first write of `a` waits for it with its access.
    CompileOptions o;
    o.shareTransientsAcrossFrames = true;
    const Plan plan = compileGraph(kTwo, R"(
        {"name": "make_a", "type": "Generic", "uses": {"a": "Write@Compute"}},
        {"name": "last", "type": "Generic", "uses": {"a": "ReadWrite@Compute", "out": "Write@Compute"}})", o);
    const auto first = barriersOf(plan, "make_a", "a");
    ASSERT_EQ(first.size(), 1u);
    EXPECT_EQ(first[0].srcStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(first[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

TEST(Clobbering, EveryTransientIsPoisonedAndItsFirstWriteKeepsWhatItDoesNotWrite) {
    CompileOptions o = oneFrame();
    o.clobberTransients = true;
    const Plan plan = compileGraph(kTwo, kTwoPasses, o);
    std::vector<std::string> clobbered;
    for (const PlannedPass& p : plan.passes())
        if (p.type == "Clobber") {
            ASSERT_EQ(p.usages.size(), 1u);
            EXPECT_EQ(p.declIndex, -1);
            EXPECT_EQ(toString(p.usages[0].usage), "Write@Transfer");
            EXPECT_EQ(p.usages[0].layout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
            clobbered.emplace_back(p.name);
        }
    EXPECT_EQ(clobbered, (std::vector<std::string>{"clobber a", "clobber mid", "clobber b"}))
        << "transients only: `out` is external";
    // make_b's color write now loads the poison and keeps it where it draws nothing.
    const PlannedUsage* target = nullptr;
    for (const PlannedUsage& u : pass(plan, "make_b").usages)
        if (plan.resources()[u.resource].name == "b") target = &u;
    ASSERT_NE(target, nullptr);
    EXPECT_EQ(target->load, LoadOp::Load);
    EXPECT_TRUE(target->access & VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT);
    const auto b = barriersOf(plan, "make_b", "b");
    ASSERT_EQ(b.size(), 1u);
    EXPECT_EQ(b[0].oldLayout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL) << "not UNDEFINED, which could drop the poison";
    EXPECT_EQ(b[0].srcStages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);
    EXPECT_EQ(b[0].srcAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    EXPECT_EQ(b[0].dstAccess, VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    // The aliasing barrier moved to the clobber, the resource's first use now.
    const auto aliasing = barriersOf(plan, "clobber b", "b");
    ASSERT_EQ(aliasing.size(), 1u);
    EXPECT_TRUE(aliasing[0].aliasing);
    EXPECT_EQ(aliasing[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(aliasing[0].dstStages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);
    // Without clobbering, the same write discards (rule 6).
    const Plan plain = compileGraph(kTwo, kTwoPasses);
    for (const PlannedUsage& u : pass(plain, "make_b").usages)
        if (plain.resources()[u.resource].name == "b") {
            EXPECT_EQ(u.load, LoadOp::DontCare);
        }
}

/// A model an embedder might get wrong: answers `answer` for every resource.
class FixedModel : public MemoryModel {
public:
    FixedModel(MemoryRequirements answer, uint64_t granularity) : answer_(answer), granularity_(granularity) {}
    MemoryRequirements requirements(const MemoryQuery&) const override { return answer_; }
    uint64_t bufferImageGranularity() const override { return granularity_; }
    std::string name() const override { return "fixed"; }

private:
    MemoryRequirements answer_;
    uint64_t granularity_;
};

TEST(MemoryModelAnswers, ThatCannotBePlacedAreErrorsNamingTheModelAndTheResource) {
    const auto compileWith = [](MemoryRequirements answer, uint64_t granularity) {
        CompileOptions o = oneFrame();
        o.memory = std::make_shared<FixedModel>(answer, granularity);
        return compileGraph(kTwo, kTwoPasses, o);
    };
    EXPECT_NO_THROW(compileWith({65536, 4096, 1u}, 1024)) << "the control: a placeable answer";
    const struct {
        MemoryRequirements answer;
        uint64_t granularity;
        const char* says;
    } bad[] = {
        {{0, 4096, 1u}, 1024, "a size of 0 bytes"},
        {{uint64_t(1) << 60, 4096, 1u}, 1024, "a size of 1152921504606846976 bytes"},
        {{65536, 0, 1u}, 1024, "an alignment of 0, not a power of two"},
        {{65536, 96, 1u}, 1024, "an alignment of 96, not a power of two"},
        {{65536, 4096, 0u}, 1024, "no memory type"},
        {{65536, 4096, 1u}, 1000, "a bufferImageGranularity of 1000, not a power of two"},
    };
    for (const auto& c : bad) {
        try {
            (void)compileWith(c.answer, c.granularity);
            ADD_FAILURE() << "accepted: " << c.says;
        } catch (const GraphError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("aliasing.json"), std::string::npos) << what;
            EXPECT_NE(what.find("memory model 'fixed'"), std::string::npos) << what;
            EXPECT_NE(what.find(c.says), std::string::npos) << what;
            if (c.granularity == 1024) {
                EXPECT_NE(what.find("resources.a"), std::string::npos) << what;
            }
        }
    }
}

}  // namespace
}  // namespace skygraph
