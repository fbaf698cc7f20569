// The layouts knob (CompileOptions::layouts, the graph file's "layouts"; docs/barriers.md,
// rule 4): runs of reads whose readers want different layouts, compiled both ways. Every
// expected barrier below is written out by hand from the Vulkan 1.3 memory model (chapter 7,
// "Synchronization and Cache Control"):
// - a read after a write needs the write made available (source: the writer's stages and
//   write access) and visible to the reader (destination: its stages and access), §7.1.1;
// - a layout transition is a read-write of the subresource, §7.6.2: before a later reader of
//   the same run of reads it waits for the reads since the last write (or the last transition,
//   which itself waited for the ones before: an execution dependency chain, §7.1), with no
//   source access, since the barrier before the first read already made the write available;
//   its destination makes the write and the transition visible to the next reader only;
// - the next write waits for the reads since the last transition (write after read: execution
//   only), which chain after every earlier read of the run.
#include <skygraph/compiler.hpp>
#include <skygraph/plan_format.hpp>

#include "plan_queries.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace skygraph {
namespace {

using test::barriersOf;
using test::pass;
using test::registry;

/// A graph file of these resources and passes, with `top` (e.g. R"("layouts": "optimal",)")
/// among the root's keys.
std::string graphText(const std::string& resources, const std::string& passes, const std::string& top = "") {
    return R"({"version": 1, "name": "t", )" + top + R"("resources": {)" + resources + R"(}, "passes": [)" +
           passes + "]}";
}

/// Compiled for one frame (frames sharing transients' memory add rule 16's first barriers,
/// which aliasing_rules_test.cpp covers), with the layouts policy `policy` when given.
Plan compileWith(const std::string& text, std::optional<LayoutPolicy> policy) {
    CompileOptions options;
    options.shareTransientsAcrossFrames = false;
    options.layouts = policy;
    return compile(parseGraph(text, "layouts.json", registry()), options);
}

VkImageLayout layoutIn(const Plan& plan, const std::string& passName, const std::string& resource) {
    for (const auto& u : pass(plan, passName).usages)
        if (plan.resources()[u.resource].name == resource) return u.layout;
    throw std::runtime_error("pass " + passName + " does not use " + resource);
}

struct Expected {
    VkPipelineStageFlags2 srcStages;
    VkAccessFlags2 srcAccess;
    VkPipelineStageFlags2 dstStages;
    VkAccessFlags2 dstAccess;
    VkImageLayout oldLayout, newLayout;
};

/// `b` with the stages, accesses and layouts of `e`, written with the names a reviewer checks.
void expectBarrier(const Barrier& b, const Expected& e, const std::string& what) {
    SCOPED_TRACE(what);
    EXPECT_EQ(b.srcStages, e.srcStages);
    EXPECT_EQ(b.srcAccess, e.srcAccess);
    EXPECT_EQ(b.dstStages, e.dstStages);
    EXPECT_EQ(b.dstAccess, e.dstAccess);
    EXPECT_EQ(b.oldLayout, e.oldLayout);
    EXPECT_EQ(b.newLayout, e.newLayout);
    EXPECT_FALSE(b.aliasing);
}

size_t barrierCount(const Plan& plan) {
    size_t n = plan.finalBarriers().size() + plan.inPassBarriers().size();
    for (const auto& p : plan.passes()) n += p.barriers.size();
    return n;
}

constexpr VkPipelineStageFlags2 kTransfer = VK_PIPELINE_STAGE_2_TRANSFER_BIT;
constexpr VkPipelineStageFlags2 kCompute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkPipelineStageFlags2 kFragment = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
constexpr VkPipelineStageFlags2 kColorOutput = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
constexpr VkAccessFlags2 kTransferRead = VK_ACCESS_2_TRANSFER_READ_BIT;
constexpr VkAccessFlags2 kSampledRead = VK_ACCESS_2_SHADER_SAMPLED_READ_BIT;
constexpr VkAccessFlags2 kStorageRead = VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
constexpr VkAccessFlags2 kStorageWrite = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
constexpr VkAccessFlags2 kColorWrite = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
constexpr VkImageLayout kGeneral = VK_IMAGE_LAYOUT_GENERAL;
constexpr VkImageLayout kTransferSrc = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
constexpr VkImageLayout kShaderRead = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
constexpr VkImageLayout kColorAttachment = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;

constexpr const char* kImage = R"("img": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16]},)"
                               R"("copy": {"type": "buffer", "size": 1024})";

/// A compute shader writes the image as storage; a copy, a compute sample and a compute
/// storage load read it, in that order; a draw then overwrites it.
const std::string kTransferThenCompute = graphText(kImage, R"(
    {"name": "produce", "type": "Generic", "uses": {"img": "Write@Compute"}},
    {"name": "copy_out", "type": "Generic", "never_cull": true, "uses": {"img": "Read@Transfer", "copy": "Write@Transfer"}},
    {"name": "sample", "type": "Generic", "never_cull": true, "uses": [{"resource": "img", "access": "Read", "stage": "Compute", "as": "sampled"}]},
    {"name": "load", "type": "Generic", "never_cull": true, "uses": [{"resource": "img", "access": "Read", "stage": "Compute", "as": "storage"}]},
    {"name": "redraw", "type": "Generic", "never_cull": true, "uses": {"img": "Write@ColorAttachment"}})");

TEST(LayoutPolicy, FewestBarriersKeepsATransferAndComputeRunInGeneral) {
    const Plan plan = compileWith(kTransferThenCompute, LayoutPolicy::FewestBarriers);
    for (const char* reader : {"copy_out", "sample", "load"}) EXPECT_EQ(layoutIn(plan, reader, "img"), kGeneral) << reader;
    // One barrier before the run's first read makes the storage write visible to all three
    // readers; the image stays in the GENERAL it was written in.
    const auto first = barriersOf(plan, "copy_out", "img");
    ASSERT_EQ(first.size(), 1u);
    expectBarrier(first[0], {kCompute, kStorageWrite, kTransfer | kCompute, kTransferRead | kSampledRead | kStorageRead,
                             kGeneral, kGeneral},
                  "the run's one barrier");
    EXPECT_TRUE(barriersOf(plan, "sample", "img").empty());
    EXPECT_TRUE(barriersOf(plan, "load", "img").empty());
    // The draw waits for every reader of the run (write after read) and discards.
    const auto redraw = barriersOf(plan, "redraw", "img");
    ASSERT_EQ(redraw.size(), 1u);
    expectBarrier(redraw[0], {kTransfer | kCompute, 0, kColorOutput, kColorWrite, VK_IMAGE_LAYOUT_UNDEFINED, kColorAttachment},
                  "the overwrite");
}

TEST(LayoutPolicy, OptimalGivesEachReaderItsLayoutWithTransitionsBetween) {
    const Plan plan = compileWith(kTransferThenCompute, LayoutPolicy::Optimal);
    EXPECT_EQ(layoutIn(plan, "copy_out", "img"), kTransferSrc);
    EXPECT_EQ(layoutIn(plan, "sample", "img"), kShaderRead);
    EXPECT_EQ(layoutIn(plan, "load", "img"), kGeneral);  // storage images have no other layout

    // Read after write: the storage write made available, visible to the copy only (the
    // compute readers come after transitions of their own).
    const auto copy = barriersOf(plan, "copy_out", "img");
    ASSERT_EQ(copy.size(), 1u);
    expectBarrier(copy[0], {kCompute, kStorageWrite, kTransfer, kTransferRead, kGeneral, kTransferSrc}, "before the copy");
    // The transition waits for the copy's read (its source: execution only, the write is
    // already available) and makes the contents visible to the sampler.
    const auto sample = barriersOf(plan, "sample", "img");
    ASSERT_EQ(sample.size(), 1u);
    expectBarrier(sample[0], {kTransfer, 0, kCompute, kSampledRead, kTransferSrc, kShaderRead}, "before the sample");
    // And again for the storage load: it waits for the sample (which ran after the copy).
    const auto load = barriersOf(plan, "load", "img");
    ASSERT_EQ(load.size(), 1u);
    expectBarrier(load[0], {kCompute, 0, kCompute, kStorageRead, kShaderRead, kGeneral}, "before the load");
    // The overwrite waits for the reads since the last transition; the copy and the sample are
    // ordered before them through the transitions' chain.
    const auto redraw = barriersOf(plan, "redraw", "img");
    ASSERT_EQ(redraw.size(), 1u);
    expectBarrier(redraw[0], {kCompute, 0, kColorOutput, kColorWrite, VK_IMAGE_LAYOUT_UNDEFINED, kColorAttachment},
                  "the overwrite");

    EXPECT_EQ(barrierCount(plan), barrierCount(compileWith(kTransferThenCompute, LayoutPolicy::FewestBarriers)) + 2)
        << "two transitions more: into SHADER_READ_ONLY_OPTIMAL and into GENERAL";
}

/// A draw renders the image; a fragment shader samples it, a copy reads it, and a second
/// fragment shader samples it again; a draw then overwrites it.
const std::string kFragmentAndTransfer = graphText(kImage, R"(
    {"name": "draw", "type": "Generic", "uses": {"img": "Write@ColorAttachment"}},
    {"name": "sample", "type": "Generic", "never_cull": true, "uses": {"img": "Read@Fragment"}},
    {"name": "copy_out", "type": "Generic", "never_cull": true, "uses": {"img": "Read@Transfer", "copy": "Write@Transfer"}},
    {"name": "sample_again", "type": "Generic", "never_cull": true, "uses": {"img": "Read@Fragment"}},
    {"name": "redraw", "type": "Generic", "never_cull": true, "uses": {"img": "Write@ColorAttachment"}})");

TEST(LayoutPolicy, FewestBarriersKeepsAFragmentAndTransferRunInGeneral) {
    const Plan plan = compileWith(kFragmentAndTransfer, LayoutPolicy::FewestBarriers);
    for (const char* reader : {"sample", "copy_out", "sample_again"})
        EXPECT_EQ(layoutIn(plan, reader, "img"), kGeneral) << reader;
    const auto first = barriersOf(plan, "sample", "img");
    ASSERT_EQ(first.size(), 1u);
    expectBarrier(first[0], {kColorOutput, kColorWrite, kFragment | kTransfer, kSampledRead | kTransferRead,
                             kColorAttachment, kGeneral},
                  "the run's one barrier");
    EXPECT_TRUE(barriersOf(plan, "copy_out", "img").empty());
    EXPECT_TRUE(barriersOf(plan, "sample_again", "img").empty());
    const auto redraw = barriersOf(plan, "redraw", "img");
    ASSERT_EQ(redraw.size(), 1u);
    expectBarrier(redraw[0], {kFragment | kTransfer, 0, kColorOutput, kColorWrite, VK_IMAGE_LAYOUT_UNDEFINED, kColorAttachment},
                  "the overwrite");
}

TEST(LayoutPolicy, OptimalTransitionsBetweenSamplingAndTheCopyAndBack) {
    const Plan plan = compileWith(kFragmentAndTransfer, LayoutPolicy::Optimal);
    EXPECT_EQ(layoutIn(plan, "sample", "img"), kShaderRead);
    EXPECT_EQ(layoutIn(plan, "copy_out", "img"), kTransferSrc);
    EXPECT_EQ(layoutIn(plan, "sample_again", "img"), kShaderRead);
    const auto sample = barriersOf(plan, "sample", "img");
    ASSERT_EQ(sample.size(), 1u);
    expectBarrier(sample[0], {kColorOutput, kColorWrite, kFragment, kSampledRead, kColorAttachment, kShaderRead},
                  "before the first sample");
    const auto copy = barriersOf(plan, "copy_out", "img");
    ASSERT_EQ(copy.size(), 1u);
    expectBarrier(copy[0], {kFragment, 0, kTransfer, kTransferRead, kShaderRead, kTransferSrc}, "before the copy");
    // The second sample is in the first one's layout, but the copy's transition rewrote the
    // image since: it needs a transition back, visible to it, after the copy's read.
    const auto again = barriersOf(plan, "sample_again", "img");
    ASSERT_EQ(again.size(), 1u);
    expectBarrier(again[0], {kTransfer, 0, kFragment, kSampledRead, kTransferSrc, kShaderRead}, "before the second sample");
    const auto redraw = barriersOf(plan, "redraw", "img");
    ASSERT_EQ(redraw.size(), 1u);
    expectBarrier(redraw[0], {kFragment, 0, kColorOutput, kColorWrite, VK_IMAGE_LAYOUT_UNDEFINED, kColorAttachment},
                  "the overwrite");
}

TEST(LayoutPolicy, OptimalSplitsARunPerSubresourceAndMissesNoLaterReader) {
    // Two layers. A copy reads both, a compute shader samples layer 1, a second copy reads
    // both again: on layer 0 the copies form one run (one barrier), on layer 1 the sample
    // comes between, so the second copy needs a transition back there, and only there.
    const std::string text = graphText(
        R"("arr": {"type": "image2d_array", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "layers": 2},)"
        R"("copy": {"type": "buffer", "size": 4096})",
        R"(
        {"name": "produce", "type": "Generic", "uses": {"arr": "Write@Compute"}},
        {"name": "copy_1", "type": "Generic", "never_cull": true, "uses": {"arr": "Read@Transfer", "copy": "Write@Transfer"}},
        {"name": "sample", "type": "Generic", "never_cull": true, "uses": [{"resource": "arr", "access": "Read", "stage": "Compute", "layers": [1, 1]}]},
        {"name": "copy_2", "type": "Generic", "never_cull": true, "uses": {"arr": "Read@Transfer", "copy": "ReadWrite@Transfer"}},
        {"name": "redraw", "type": "Generic", "never_cull": true, "uses": {"arr": "Write@Compute"}})");
    const Plan optimal = compileWith(text, LayoutPolicy::Optimal);
    const auto first = barriersOf(optimal, "copy_1", "arr");
    ASSERT_EQ(first.size(), 1u) << "both layers alike: one barrier";
    expectBarrier(first[0], {kCompute, kStorageWrite, kTransfer, kTransferRead, kGeneral, kTransferSrc}, "before copy_1");
    EXPECT_EQ(first[0].range, (SubresourceRange{0, 1, 0, 2}));
    const auto sample = barriersOf(optimal, "sample", "arr");
    ASSERT_EQ(sample.size(), 1u);
    expectBarrier(sample[0], {kTransfer, 0, kCompute, kSampledRead, kTransferSrc, kShaderRead}, "before the sample");
    EXPECT_EQ(sample[0].range, (SubresourceRange{0, 1, 1, 1}));
    const auto second = barriersOf(optimal, "copy_2", "arr");
    ASSERT_EQ(second.size(), 1u) << "layer 0 is still in TRANSFER_SRC_OPTIMAL and visible to copies";
    expectBarrier(second[0], {kCompute, 0, kTransfer, kTransferRead, kShaderRead, kTransferSrc}, "before copy_2");
    EXPECT_EQ(second[0].range, (SubresourceRange{0, 1, 1, 1}));
    // The overwrite waits for the copy on both layers: on layer 1 the copy is the only read
    // since the last transition; on layer 0 both copies ran since the first barrier.
    const auto redraw = barriersOf(optimal, "redraw", "arr");
    ASSERT_EQ(redraw.size(), 1u);
    expectBarrier(redraw[0], {kTransfer, 0, kCompute, kStorageWrite, VK_IMAGE_LAYOUT_UNDEFINED, kGeneral}, "the overwrite");
    EXPECT_EQ(redraw[0].range, (SubresourceRange{0, 1, 0, 2}));

    // FewestBarriers: GENERAL throughout, one barrier per layer before the first copy (layer 1
    // also has the sampler among its readers), nothing between the reads.
    const Plan fewest = compileWith(text, LayoutPolicy::FewestBarriers);
    const auto runs = barriersOf(fewest, "copy_1", "arr");
    ASSERT_EQ(runs.size(), 2u);
    for (const Barrier& b : runs) {
        const bool layer1 = b.range == SubresourceRange{0, 1, 1, 1};
        EXPECT_TRUE(layer1 || b.range == (SubresourceRange{0, 1, 0, 1}));
        expectBarrier(b, {kCompute, kStorageWrite, kTransfer | (layer1 ? kCompute : 0),
                          kTransferRead | (layer1 ? kSampledRead : 0), kGeneral, kGeneral},
                      layer1 ? "layer 1" : "layer 0");
    }
    EXPECT_TRUE(barriersOf(fewest, "sample", "arr").empty());
    EXPECT_TRUE(barriersOf(fewest, "copy_2", "arr").empty());
}

TEST(LayoutPolicy, OptimalKeepsADepthTestAndSamplingInTheDepthReadOnlyLayout) {
    // DEPTH_READ_ONLY_OPTIMAL is optimal for both a depth test and sampling (§12.4), so the
    // two reads stay one run with no transition between, under either policy.
    const std::string text = graphText(
        R"("depth": {"type": "image2d", "format": "D32_SFLOAT", "extent": [16, 16]},)"
        R"("color": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16]})",
        R"(
        {"name": "prepass", "type": "Generic", "uses": {"depth": "Write@DepthAttachment"}},
        {"name": "test", "type": "Generic", "never_cull": true, "uses": {"depth": "Read@DepthAttachment", "color": "Write@ColorAttachment"}},
        {"name": "sample", "type": "Generic", "never_cull": true, "uses": {"depth": "Read@Fragment"}})");
    for (const LayoutPolicy policy : {LayoutPolicy::FewestBarriers, LayoutPolicy::Optimal}) {
        SCOPED_TRACE(std::string(toString(policy)));
        const Plan plan = compileWith(text, policy);
        EXPECT_EQ(layoutIn(plan, "test", "depth"), VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL);
        EXPECT_EQ(layoutIn(plan, "sample", "depth"), VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL);
        EXPECT_TRUE(barriersOf(plan, "sample", "depth").empty());
    }
}

TEST(LayoutPolicy, OptimalLeavesAgreeingReadersAsFewestBarriersDoes) {
    // Readers that want the same layout: the policies give the same plan, barrier for barrier.
    const std::string text = graphText(kImage, R"(
        {"name": "draw", "type": "Generic", "uses": {"img": "Write@ColorAttachment"}},
        {"name": "sample_fragment", "type": "Generic", "never_cull": true, "uses": {"img": "Read@Fragment"}},
        {"name": "sample_compute", "type": "Generic", "never_cull": true, "uses": {"img": "Read@Compute"}},
        {"name": "redraw", "type": "Generic", "never_cull": true, "uses": {"img": "Write@ColorAttachment"}})");
    const Plan fewest = compileWith(text, LayoutPolicy::FewestBarriers);
    const Plan optimal = compileWith(text, LayoutPolicy::Optimal);
    ASSERT_EQ(fewest.passes().size(), optimal.passes().size());
    for (size_t i = 0; i < fewest.passes().size(); ++i) {
        const auto& a = fewest.passes()[i].barriers;
        const auto& b = optimal.passes()[i].barriers;
        EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << fewest.passes()[i].name;
    }
}

TEST(LayoutPolicy, OptimalLeavesNoShippedReaderInGeneralUnlessItLoadsStorage) {
    // Every shipped graph under every feature combination, read back as headless runs do: no
    // read of an image but a storage load is left in GENERAL, and FewestBarriers still has
    // some there (graphs/deferred.json's TAA result: copied, then sampled).
    size_t generalUnderFewest = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs")) {
        if (entry.path().extension() != ".json") continue;
        const GraphDesc graph = loadGraphFile(entry.path(), registry());
        for (uint64_t mask = 0; mask < (uint64_t(1) << graph.features.size()); ++mask) {
            CompileOptions options;
            for (size_t i = 0; i < graph.features.size(); ++i) options.features[graph.features[i].name] = (mask >> i) & 1;
            for (const LayoutPolicy policy : {LayoutPolicy::FewestBarriers, LayoutPolicy::Optimal}) {
                options.layouts = policy;
                const Plan plan = compile(graph, options);
                for (const PlannedPass& p : plan.passes())
                    for (const PlannedUsage& u : p.usages) {
                        const bool general = u.usage.access == Access::Read && u.usage.as != BindAs::Storage &&
                                             u.layout == VK_IMAGE_LAYOUT_GENERAL;
                        if (policy == LayoutPolicy::FewestBarriers) generalUnderFewest += general;
                        else EXPECT_FALSE(general) << entry.path().filename() << " mask " << mask << ": " << p.name
                                                   << " reads " << plan.resources()[u.resource].name << " in GENERAL";
                    }
            }
        }
    }
    EXPECT_GT(generalUnderFewest, 0u);
}

TEST(LayoutPolicy, TheGraphFileSetsItAndTheOptionOverridesIt) {
    const std::string resources = kImage;
    const std::string passes = R"(
        {"name": "draw", "type": "Generic", "uses": {"img": "Write@ColorAttachment"}},
        {"name": "sample", "type": "Generic", "never_cull": true, "uses": {"img": "Read@Fragment"}},
        {"name": "copy_out", "type": "Generic", "never_cull": true, "uses": {"img": "Read@Transfer", "copy": "Write@Transfer"}})";
    const GraphDesc unset = parseGraph(graphText(resources, passes), "layouts.json", registry());
    const GraphDesc fewestFile =
        parseGraph(graphText(resources, passes, R"("layouts": "fewest-barriers", )"), "layouts.json", registry());
    const GraphDesc optimalFile =
        parseGraph(graphText(resources, passes, R"("layouts": "optimal", )"), "layouts.json", registry());
    EXPECT_EQ(unset.layouts, LayoutPolicy::FewestBarriers);
    EXPECT_EQ(fewestFile.layouts, LayoutPolicy::FewestBarriers);
    EXPECT_EQ(optimalFile.layouts, LayoutPolicy::Optimal);

    const auto copyLayout = [](const GraphDesc& g, std::optional<LayoutPolicy> option) {
        CompileOptions o;
        o.layouts = option;
        const Plan plan = compile(g, o);
        return std::pair{plan.layouts(), layoutIn(plan, "copy_out", "img")};
    };
    using Result = std::pair<LayoutPolicy, VkImageLayout>;
    const Result fewest{LayoutPolicy::FewestBarriers, kGeneral};
    const Result optimal{LayoutPolicy::Optimal, kTransferSrc};
    // Unset, the file decides (and a file without the key is FewestBarriers).
    EXPECT_EQ(copyLayout(unset, std::nullopt), fewest);
    EXPECT_EQ(copyLayout(fewestFile, std::nullopt), fewest);
    EXPECT_EQ(copyLayout(optimalFile, std::nullopt), optimal);
    // Set, the option wins either way.
    EXPECT_EQ(copyLayout(optimalFile, LayoutPolicy::FewestBarriers), fewest);
    EXPECT_EQ(copyLayout(unset, LayoutPolicy::Optimal), optimal);
    EXPECT_EQ(copyLayout(fewestFile, LayoutPolicy::Optimal), optimal);
}

TEST(LayoutPolicy, PlansStateThePolicyOnlyWhenItIsNotTheDefault) {
    const Plan fewest = compileWith(kTransferThenCompute, LayoutPolicy::FewestBarriers);
    const Plan optimal = compileWith(kTransferThenCompute, LayoutPolicy::Optimal);
    EXPECT_FALSE(planToJson(fewest).contains("layouts"));
    EXPECT_EQ(planToJson(optimal).value("layouts", ""), "optimal");
    EXPECT_EQ(planToText(fewest).find("layouts:"), std::string::npos);
    EXPECT_NE(planToText(optimal).find("\noutput: 1920x1080\nlayouts: optimal\n"), std::string::npos)
        << planToText(optimal);
    // A copy of a plan keeps it.
    const Plan copy = optimal;
    EXPECT_EQ(copy.layouts(), LayoutPolicy::Optimal);
}

}  // namespace
}  // namespace skygraph
