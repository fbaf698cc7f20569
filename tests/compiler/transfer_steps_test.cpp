// The steps the compiler adds around a frame's passes: per-frame read-backs, the in-pass barrier
// of a ReadWrite transfer, the setup before the first frame, reading an image back on request,
// and which resources need a copy per frame in flight. Each expectation was checked against the
// Vulkan spec's memory model: a host read after a device write needs a memory dependency into
// the host domain (dstStage HOST, HOST_READ); a write after a read in one pass only an
// execution dependency.
#include <skygraph/compiler.hpp>
#include <skygraph/plan_format.hpp>
#include <skygraph/transfer_plans.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace skygraph {
namespace {

const PassRegistry& registry() {
    static const PassRegistry r = PassRegistry::withBuiltins();
    return r;
}

GraphDesc graphOf(const std::string& resources, const std::string& passes) {
    return parseGraph(R"({"version": 1, "name": "t", "resources": {)" + resources + R"(}, "passes": [)" + passes + "]}",
                      "steps.json", registry());
}

constexpr const char* kColor = R"("color": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16]})";
constexpr const char* kOut = R"("out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true, "final": "TransferSrc"})";
constexpr const char* kTexture = R"("tex": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "mips": "full", "external": true})";
constexpr const char* kVertices = R"("verts": {"type": "buffer", "size": 64, "external": true})";

std::string messageOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const GraphError& e) {
        return e.what();
    }
    return "";
}

TEST(Readback, IsAStepAfterTheLastPassWithAHostBarrierAtTheEnd) {
    const GraphDesc g = graphOf(std::string(kColor) + "," + kOut, R"(
        {"name": "draw", "type": "Generic", "uses": {"color": "Write@ColorAttachment"}},
        {"name": "blit", "type": "Generic", "uses": {"color": "Read@Fragment", "out": "Write@ColorAttachment"}})");
    CompileOptions o;
    o.readbacks = {"out"};
    const Plan plan = compile(g, o);
    ASSERT_EQ(plan.passes().size(), 3u);
    const PlannedPass& step = plan.passes()[2];
    EXPECT_EQ(step.name, "read back out");
    EXPECT_EQ(step.type, "Readback");
    EXPECT_EQ(step.declIndex, -1);
    ASSERT_EQ(step.usages.size(), 1u);
    EXPECT_EQ(step.usages[0].layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    EXPECT_EQ(step.usages[0].range, (SubresourceRange{0, 1, 0, 1}));
    // RAW after `blit`'s attachment write: a memory dependency, and the layout transition.
    ASSERT_EQ(step.barriers.size(), 1u);
    EXPECT_EQ(step.barriers[0].srcStages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
    EXPECT_EQ(step.barriers[0].srcAccess, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    EXPECT_EQ(step.barriers[0].dstStages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);
    EXPECT_EQ(step.barriers[0].dstAccess, VK_ACCESS_2_TRANSFER_READ_BIT);
    EXPECT_EQ(step.barriers[0].oldLayout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    EXPECT_EQ(step.barriers[0].newLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    bool host = false;
    for (const Barrier& b : plan.finalBarriers())
        host = host || (b.kind == BarrierKind::Memory && b.srcStages == VK_PIPELINE_STAGE_2_TRANSFER_BIT &&
                        b.srcAccess == VK_ACCESS_2_TRANSFER_WRITE_BIT && b.dstStages == VK_PIPELINE_STAGE_2_HOST_BIT &&
                        b.dstAccess == VK_ACCESS_2_HOST_READ_BIT);
    EXPECT_TRUE(host) << "the copy must be made available to the host";
}

TEST(Readback, JoinsTheReadRunOfTheImageItCopies) {
    const GraphDesc g = graphOf(std::string(kColor) + "," + kOut, R"(
        {"name": "draw", "type": "Generic", "uses": {"color": "Write@ColorAttachment"}},
        {"name": "blit", "type": "Generic", "uses": {"color": "Read@Fragment", "out": "Write@ColorAttachment"}})");
    CompileOptions o;
    o.readbacks = {"color"};
    const Plan plan = compile(g, o);
    // Rule 4: the sampled read and the copy read one layout that serves both, made visible to
    // both by the one barrier before `blit`.
    EXPECT_EQ(plan.passes()[2].usages[0].layout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_TRUE(plan.passes()[2].barriers.empty());
    bool visibleToCopy = false;
    for (const Barrier& b : plan.passes()[1].barriers)
        visibleToCopy = visibleToCopy || (plan.resources()[b.resource].name == "color" &&
                                          (b.dstAccess & VK_ACCESS_2_TRANSFER_READ_BIT) != 0);
    EXPECT_TRUE(visibleToCopy);
}

TEST(Readback, KeepsItsWritersFromBeingCulled) {
    const GraphDesc g = graphOf(std::string(kColor) + "," + kOut, R"(
        {"name": "draw", "type": "Generic", "uses": {"color": "Write@ColorAttachment"}},
        {"name": "other", "type": "Generic", "uses": {"out": "Write@ColorAttachment"}})");
    ASSERT_EQ(compile(g).passes().size(), 1u) << "without a read-back, `draw` feeds nothing";
    CompileOptions o;
    o.readbacks = {"color"};
    EXPECT_EQ(compile(g, o).passes().size(), 3u);
}

// The renderer keeps an external image for the next frame as this one leaves it: one read
// back goes back to the state it arrives in, where a transient read back stays TransferSrc.
TEST(Readback, LeavesAnExternalImageInTheStateItArrivesIn) {
    const GraphDesc g = graphOf(std::string(kTexture) + "," + kOut, R"(
        {"name": "blit", "type": "Generic", "uses": {"tex": "Read@Compute", "out": "Write@Compute"}})");
    CompileOptions o;
    o.readbacks = {"tex"};
    const Plan plan = compile(g, o);
    const PlannedResource& tex = plan.resources()[plan.resourceIndex("tex")];
    EXPECT_EQ(tex.initialLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(tex.finalLayout, tex.initialLayout);
    EXPECT_EQ(plan.passes().back().name, "read back tex");
}

// An external image that arrives as presented, and is not exported, must be found so by the
// next frame: left TransferSrc after its read-back, it arrived in a layout it was not in (the
// plan verifier's BadOldLayout and FinalLayout). Exported Present it would be presented. So
// it is read back only where Present is replaced (headless), which leaves it as it arrived.
TEST(Readback, AnImageArrivingAsPresentedIsReadBackOnlyWherePresentIsReplaced) {
    const GraphDesc g = graphOf(std::string(kOut) + R"(, "shown": {"type": "image2d", "format": "R8G8B8A8_UNORM",
        "extent": [16, 16], "mips": 2, "external": true, "initial": "Present"})", R"(
        {"name": "blit", "type": "Generic", "uses": {"shown": "Read@Compute", "out": "Write@Compute"}})");
    CompileOptions o;
    o.readbacks = {"shown"};
    const std::string message = messageOf([&] { (void)compile(g, o); });
    EXPECT_NE(message.find("resources.shown.initial: resource 'shown': cannot read back 'shown': it arrives as "
                           "presented and is not exported"),
              std::string::npos)
        << message;
    o.presentReplacement = ExternalState::TransferSrc;
    const Plan plan = compile(g, o);
    const PlannedResource& shown = plan.resources()[plan.resourceIndex("shown")];
    EXPECT_EQ(shown.initialLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    EXPECT_EQ(shown.finalLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    EXPECT_TRUE(plan.presentations().empty());
    EXPECT_EQ(plan.passes().back().name, "read back shown");
}

// A code-built graph has not been through the loader, which refuses the same at `initial`.
TEST(ExternalStates, AnExportedExternalMustArriveInTheStateItIsLeftIn) {
    GraphDesc g = graphOf(std::string(kTexture) + "," + kOut, R"(
        {"name": "blit", "type": "Generic", "uses": {"tex": "Read@Compute", "out": "Write@Compute"}})");
    g.resources[g.findResource("tex") - g.resources.data()].final = ExternalState::General;
    const std::string message = messageOf([&] { (void)compile(g); });
    EXPECT_NE(message.find("resources.tex: resource 'tex': an external resource is kept for the next frame as this "
                           "frame leaves it, in its final state General, so it must arrive in that state too, not "
                           "ShaderRead"),
              std::string::npos)
        << message;
    const std::string file = R"({"version": 1, "name": "t", "resources": {)" + std::string(kOut) +
                             R"(, "acc": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16],
                                 "external": true, "initial": "ShaderRead", "final": "General"}},
                             "passes": [{"name": "w", "type": "Generic", "uses": {"acc": "ReadWrite@Compute",
                                         "out": "Write@Compute"}}]})";
    // A buffer is named for the same reason, not as one left in an image layout.
    GraphDesc withBuffer = graphOf(std::string(kVertices) + "," + kOut, R"(
        {"name": "w", "type": "Generic", "uses": {"verts": "Read@Compute", "out": "Write@Compute"}})");
    CompileOptions exportsIt;
    exportsIt.exports = {{"verts", ExternalState::General}};
    const std::string buffer = messageOf([&] { (void)compile(withBuffer, exportsIt); });
    EXPECT_NE(buffer.find("resource 'verts': an external resource is kept for the next frame"), std::string::npos)
        << buffer;
    const std::string loaded = messageOf([&] { (void)parseGraph(file, "steps.json", registry()); });
    EXPECT_NE(loaded.find("steps.json: resources.acc.initial: resource 'acc': an external resource is kept"),
              std::string::npos)
        << loaded;
    // Arriving as presented is no exception: left ShaderRead, the next frame found it in
    // SHADER_READ_ONLY_OPTIMAL where the plan's first barrier said PRESENT_SRC_KHR.
    std::string presented = file;
    presented.replace(presented.find(R"("initial": "ShaderRead")"), std::string(R"("initial": "ShaderRead")").size(),
                      R"("initial": "Present")");
    const std::string fromPresent = messageOf([&] { (void)parseGraph(presented, "steps.json", registry()); });
    EXPECT_NE(fromPresent.find("resources.acc.initial: resource 'acc': an external resource is kept for the next "
                               "frame as this frame leaves it, in its final state General, so it must arrive in "
                               "that state too, not Present"),
              std::string::npos)
        << fromPresent;
}

// The setup and read plans index the graph by the frame plan's records: another graph is
// refused, naming both, rather than read out of range.
TEST(Setup, APlanOfAnotherGraphIsAnError) {
    const GraphDesc g = graphOf(std::string(kTexture) + "," + kOut, R"(
        {"name": "blit", "type": "Generic", "uses": {"tex": "Read@Compute", "out": "Write@Compute"}})");
    const Plan frame = compile(g);
    GraphDesc other;
    other.name = "other";
    EXPECT_NE(messageOf([&] { (void)planSetup(other, frame); })
                  .find("the plan of graph 't' was not compiled from this graph ('other')"),
              std::string::npos);
    EXPECT_NE(messageOf([&] { (void)planImageRead(other, frame, "out"); }).find("was not compiled from this graph"),
              std::string::npos);
}

TEST(Readback, BadNamesAreErrorsNamingTheResource) {
    const GraphDesc g = graphOf(std::string(kColor) + "," + kOut + R"(, "buf": {"type": "buffer", "size": 64})", R"(
        {"name": "draw", "type": "Generic", "uses": {"out": "Write@ColorAttachment", "buf": "Write@Compute"}})");
    CompileOptions o;
    o.readbacks = {"nope"};
    EXPECT_NE(messageOf([&] { (void)compile(g, o); }).find("cannot read back 'nope': no such resource"), std::string::npos);
    o.readbacks = {"buf"};
    EXPECT_NE(messageOf([&] { (void)compile(g, o); }).find("'buf': it is a buffer"), std::string::npos);
    o.readbacks = {"color"};
    EXPECT_NE(messageOf([&] { (void)compile(g, o); }).find("cannot read back 'color': no pass that runs writes it"),
              std::string::npos);
}

// A read-back copies mip 0 of layer 0. A cube whose passes wrote only faces 1 to 5 was read
// back from its unwritten first face, silently: the check asked whether any pass wrote the
// resource at all.
TEST(Readback, OfASubresourceNoPassWritesIsRefused) {
    const GraphDesc g = graphOf(R"("sky": {"type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [16, 16]})", R"(
        {"name": "faces", "type": "Generic",
         "uses": [{"resource": "sky", "access": "Write", "stage": "Compute", "layers": [1, 5]}]})");
    CompileOptions o;
    o.readbacks = {"sky"};
    EXPECT_NE(messageOf([&] { (void)compile(g, o); })
                  .find("resources.sky: resource 'sky': cannot read back 'sky': it copies mip 0 of layer 0, which "
                        "no pass that runs writes, and it is neither external nor `clear`"),
              std::string::npos)
        << messageOf([&] { (void)compile(g, o); });
    const GraphDesc all = graphOf(R"("sky": {"type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [16, 16]})", R"(
        {"name": "faces", "type": "Generic", "uses": {"sky": "Write@Compute"}})");
    EXPECT_NO_THROW((void)compile(all, o));
}

TEST(InPassBarrier, OrdersAReadWriteTransfersCopyInAfterItsCopyOut) {
    const GraphDesc g = graphOf(std::string(kColor) + "," + kOut, R"(
        {"name": "draw", "type": "Generic", "uses": {"color": "Write@ColorAttachment"}},
        {"name": "edit", "type": "Generic", "uses": {"color": "ReadWrite@Transfer", "out": "Write@Transfer"}})");
    CompileOptions o;
    o.cull = false;
    const Plan plan = compile(g, o);
    ASSERT_EQ(plan.inPassBarriers().size(), 1u);
    const InPassBarrier& ib = plan.inPassBarriers()[0];
    EXPECT_EQ(plan.passes()[ib.pass].name, "edit");
    EXPECT_EQ(plan.resources()[plan.passes()[ib.pass].usages[ib.usage].resource].name, "color");
    EXPECT_EQ(ib.barrier.srcStages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);
    EXPECT_EQ(ib.barrier.srcAccess, 0u) << "write-after-read: execution only";
    EXPECT_EQ(ib.barrier.dstStages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);
    EXPECT_EQ(ib.barrier.dstAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    EXPECT_EQ(ib.barrier.oldLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(ib.barrier.newLayout, VK_IMAGE_LAYOUT_GENERAL);
}

// The frame expects a General resource's contents visible where it first uses each of its
// subresources (the synchronizer's boundary scope), and there is no barrier before a pass that
// is the first to touch a layer. Layer 1 is first used by the second pass's fragment shader:
// the setup's last barrier must reach it as well as the first pass's compute shader.
TEST(Setup, AGeneralResourceIsReadyForTheFirstUseOfEachSubresource) {
    const GraphDesc g = graphOf(R"("acc": {"type": "image2d_array", "format": "R16G16B16A16_SFLOAT",
        "extent": [16, 16], "layers": 2, "external": true, "final": "General"})", R"(
        {"name": "a", "type": "Generic", "uses": [{"resource": "acc", "access": "ReadWrite", "stage": "Compute",
                                                   "layers": [0, 1]}]},
        {"name": "b", "type": "Generic", "uses": [{"resource": "acc", "access": "ReadWrite", "stage": "Fragment",
                                                   "layers": [1, 1]}]})");
    const Plan frame = compile(g);
    EXPECT_TRUE(frame.passes()[1].barriers.empty()) << planToText(frame);
    const Plan setup = planSetup(g, frame);
    ASSERT_EQ(setup.finalBarriers().size(), 1u) << planToText(setup);
    const Barrier& ready = setup.finalBarriers()[0];
    EXPECT_EQ(ready.range, (SubresourceRange{0, 1, 0, 2}));
    EXPECT_EQ(ready.newLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(ready.dstStages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
    EXPECT_EQ(ready.dstAccess, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

TEST(Setup, EveryExternalThatArrivesInAStateIsSetUpAndNothingElse) {
    const GraphDesc g = graphOf(std::string(kTexture) + "," + kOut + "," + kColor + "," + kVertices, R"(
        {"name": "draw", "type": "Generic", "uses": {"tex": "Read@Fragment", "verts": "Read@VertexInput", "color": "Write@ColorAttachment"}},
        {"name": "copy", "type": "Generic", "uses": {"color": "Read@Transfer", "out": "Write@Transfer"}})");
    const Plan frame = compile(g);
    const Plan setup = planSetup(g, frame, SetupOptions{{"tex"}, {}});
    std::vector<std::string> names;
    for (const PlannedPass& p : setup.passes()) names.emplace_back(std::string(p.name) + ":" + std::string(p.type));
    EXPECT_EQ(names, (std::vector<std::string>{"upload tex:Upload", "downsample tex to mip 1:Downsample",
                                               "downsample tex to mip 2:Downsample", "downsample tex to mip 3:Downsample",
                                               "downsample tex to mip 4:Downsample", "initialize verts:Upload",
                                               "initialize out:Clear"}));
    // tex (16x16, 5 mips): mip 0 uploaded from UNDEFINED; each downsample step writes level m
    // (UNDEFINED -> TRANSFER_DST, nothing to wait for) and reads level m - 1, which the step
    // before wrote (read-after-write, TRANSFER_DST -> TRANSFER_SRC).
    ASSERT_EQ(setup.passes()[0].barriers.size(), 1u);
    EXPECT_EQ(setup.passes()[0].barriers[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(setup.passes()[0].barriers[0].range, (SubresourceRange{0, 1, 0, 1}));
    for (uint32_t m = 1; m < 5; ++m) {
        const PlannedPass& step = setup.passes()[m];
        ASSERT_EQ(step.usages.size(), 2u);
        EXPECT_EQ(step.usages[0].range, (SubresourceRange{m, 1, 0, 1}));
        EXPECT_EQ(step.usages[1].range, (SubresourceRange{m - 1, 1, 0, 1}));
        ASSERT_EQ(step.barriers.size(), 2u) << step.name;
        const Barrier& into = step.barriers[0];
        EXPECT_EQ(into.range, (SubresourceRange{m, 1, 0, 1}));
        EXPECT_EQ(into.srcStages, 0u);
        EXPECT_EQ(into.oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
        EXPECT_EQ(into.newLayout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        EXPECT_EQ(into.dstAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
        const Barrier& raw = step.barriers[1];
        EXPECT_EQ(raw.range, (SubresourceRange{m - 1, 1, 0, 1}));
        EXPECT_EQ(raw.srcStages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);
        EXPECT_EQ(raw.srcAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
        EXPECT_EQ(raw.dstStages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);
        EXPECT_EQ(raw.dstAccess, VK_ACCESS_2_TRANSFER_READ_BIT);
        EXPECT_EQ(raw.oldLayout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        EXPECT_EQ(raw.newLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    }
    // A buffer's first write needs no barrier; its final one makes the fill visible where its
    // `initial` state (ShaderRead by default) says.
    EXPECT_TRUE(setup.passes()[5].barriers.empty());
    bool sawTex = false, sawVerts = false;
    for (const Barrier& b : setup.finalBarriers()) {
        const std::string_view name = setup.resources()[b.resource].name;
        if (name == "tex") {
            // One per level: the last was written (TRANSFER_DST, its write made visible), the
            // others were last read (TRANSFER_SRC, execution only: their writes were made
            // available by the barrier before that read).
            const bool last = b.range.baseMip == 4;
            sawTex = sawTex || last;
            EXPECT_EQ(b.range.mipCount, 1u);
            EXPECT_EQ(b.oldLayout, last ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
            EXPECT_EQ(b.srcAccess, last ? VK_ACCESS_2_TRANSFER_WRITE_BIT : VK_ACCESS_2_NONE);
            EXPECT_EQ(b.newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
            EXPECT_EQ(b.dstStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
            EXPECT_EQ(b.dstAccess, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
        }
        if (name == "verts") {
            sawVerts = true;
            EXPECT_EQ(b.kind, BarrierKind::Buffer);
            EXPECT_EQ(b.srcAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
            EXPECT_EQ(b.dstStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
            EXPECT_EQ(b.dstAccess, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
        }
    }
    EXPECT_TRUE(sawTex && sawVerts);
    // An imported image is another renderer's to set up.
    EXPECT_EQ(planSetup(g, frame, SetupOptions{{}, {"tex"}}).passes().size(), 2u);
}

TEST(Setup, BadUploadsAreErrorsNamingTheResource) {
    const GraphDesc g = graphOf(std::string(kTexture) + "," + kOut + "," + kColor + "," + kVertices, R"(
        {"name": "draw", "type": "Generic", "uses": {"tex": "Read@Fragment", "verts": "Read@VertexInput", "out": "Write@ColorAttachment", "color": "Write@ColorAttachment"}})");
    const Plan frame = compile(g);
    EXPECT_NE(messageOf([&] { (void)planSetup(g, frame, {{"nope"}, {}}); }).find("cannot upload 'nope': no such resource"),
              std::string::npos);
    EXPECT_NE(messageOf([&] { (void)planSetup(g, frame, {{"color"}, {}}); }).find("'color': it is not external"),
              std::string::npos);
    EXPECT_NE(messageOf([&] { (void)planSetup(g, frame, {{"verts"}, {}}); }).find("'verts': it is a buffer"),
              std::string::npos);
    EXPECT_NE(messageOf([&] { (void)planSetup(g, frame, {{"tex"}, {"tex"}}); }).find("imported"), std::string::npos);
}

TEST(SampledImageUploads, UploadMipZeroDownsampleTheRestAndLeaveEveryMipReadyToSample) {
    const SampledImageShape shapes[] = {{"albedo", *findFormat("R8G8B8A8_SRGB"), 4, 2},
                                        {"one", *findFormat("R8G8B8A8_UNORM"), 1, 1}};
    const Plan plan = planSampledImageUploads(shapes);
    std::vector<std::string> names;
    for (const PlannedPass& p : plan.passes()) names.emplace_back(std::string(p.name) + ":" + std::string(p.type));
    // albedo: 4x2, 2x1, 1x1. one: a single level, nothing to downsample.
    EXPECT_EQ(names, (std::vector<std::string>{"upload albedo:Upload", "downsample albedo to mip 1:Downsample",
                                               "downsample albedo to mip 2:Downsample", "upload one:Upload"}));
    ASSERT_EQ(plan.resources().size(), 2u);
    EXPECT_EQ(plan.resources()[0].name, "albedo");
    // Each upload: UNDEFINED -> TRANSFER_DST of mip 0 alone, nothing before it to wait for.
    for (const size_t i : {size_t(0), size_t(3)}) {
        ASSERT_EQ(plan.passes()[i].barriers.size(), 1u);
        const Barrier& b = plan.passes()[i].barriers[0];
        EXPECT_EQ(b.srcStages, 0u);
        EXPECT_EQ(b.oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
        EXPECT_EQ(b.newLayout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        EXPECT_EQ(b.dstStages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);  // ALL_TRANSFER: copies and blits
        EXPECT_EQ(b.dstAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
        EXPECT_EQ(b.range, (SubresourceRange{0, 1, 0, 1}));
    }
    // Downsample to mip m: m becomes TRANSFER_DST from UNDEFINED; m - 1, just written, becomes
    // TRANSFER_SRC after that write (read-after-write).
    for (uint32_t m = 1; m < 3; ++m) {
        const PlannedPass& step = plan.passes()[m];
        ASSERT_EQ(step.barriers.size(), 2u);
        EXPECT_EQ(step.barriers[0].range, (SubresourceRange{m, 1, 0, 1}));
        EXPECT_EQ(step.barriers[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
        EXPECT_EQ(step.barriers[1].range, (SubresourceRange{m - 1, 1, 0, 1}));
        EXPECT_EQ(step.barriers[1].srcAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
        EXPECT_EQ(step.barriers[1].dstAccess, VK_ACCESS_2_TRANSFER_READ_BIT);
        EXPECT_EQ(step.barriers[1].newLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    }
    // The finals: every level of both images to SHADER_READ_ONLY for fragment and compute
    // sampling; the levels last written make that write visible, those last read (the blits'
    // sources) need only the execution dependency.
    std::vector<std::pair<std::string, uint32_t>> finals;
    for (const Barrier& b : plan.finalBarriers()) {
        const std::string name(plan.resources()[b.resource].name);
        finals.emplace_back(name, b.range.baseMip);
        const bool written = name == "one" || b.range.baseMip == 2;
        EXPECT_EQ(b.range.mipCount, 1u);
        EXPECT_EQ(b.oldLayout, written ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
        EXPECT_EQ(b.srcAccess, written ? VK_ACCESS_2_TRANSFER_WRITE_BIT : VK_ACCESS_2_NONE);
        EXPECT_NE(b.srcStages & VK_PIPELINE_STAGE_2_TRANSFER_BIT, 0u);
        EXPECT_EQ(b.newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        EXPECT_EQ(b.dstStages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
        EXPECT_EQ(b.dstAccess, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    }
    std::sort(finals.begin(), finals.end());
    EXPECT_EQ(finals, (std::vector<std::pair<std::string, uint32_t>>{{"albedo", 0}, {"albedo", 1}, {"albedo", 2}, {"one", 0}}));
}

TEST(SampledImageUploads, BadShapesAreErrorsNamingTheImage) {
    const FormatInfo rgba = *findFormat("R8G8B8A8_UNORM");
    const auto problem = [&](std::vector<SampledImageShape> shapes) {
        return messageOf([&] { (void)planSampledImageUploads(shapes); });
    };
    EXPECT_NE(problem({}).find("no images"), std::string::npos);
    EXPECT_NE(problem({{"a", rgba, 2, 2}, {"a", rgba, 2, 2}}).find("'a': another image has that name"), std::string::npos);
    EXPECT_NE(problem({{"d", *findFormat("D32_SFLOAT"), 2, 2}}).find("'d': its format is not a colour format"),
              std::string::npos);
    EXPECT_NE(problem({{"z", rgba, 0, 2}}).find("'z': 0x2 is outside 1..16384"), std::string::npos);
    EXPECT_NE(problem({{"big", rgba, 16385, 1}}).find("'big': 16385x1"), std::string::npos);
    FormatInfo wide = rgba;
    wide.bytesPerTexel = 8;
    const std::string widened = problem({{"w", wide, 2, 2}});
    EXPECT_NE(widened.find("images.w: resource 'w': cannot upload 'w': its FormatInfo is not the one findFormat() "
                           "gives for its format"),
              std::string::npos)
        << widened;
}

TEST(ImageRead, CopiesEveryLevelAndReturnsTheImageToTheLayoutTheFrameLeftIt) {
    const GraphDesc g = graphOf(std::string(kTexture) + "," + kOut, R"(
        {"name": "draw", "type": "Generic", "uses": {"tex": "Read@Fragment", "out": "Write@ColorAttachment"}})");
    const Plan frame = compile(g);
    const Plan read = planImageRead(g, frame, "tex");
    ASSERT_EQ(read.passes().size(), 1u);
    EXPECT_EQ(read.passes()[0].type, "Readback");
    EXPECT_EQ(read.passes()[0].usages[0].range, (SubresourceRange{0, 5, 0, 1}));
    ASSERT_EQ(read.passes()[0].barriers.size(), 1u);
    EXPECT_EQ(read.passes()[0].barriers[0].oldLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(read.passes()[0].barriers[0].newLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    EXPECT_EQ(read.passes()[0].barriers[0].dstAccess, VK_ACCESS_2_TRANSFER_READ_BIT);
    ASSERT_EQ(read.finalBarriers().size(), 2u);
    EXPECT_EQ(read.finalBarriers()[0].oldLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    EXPECT_EQ(read.finalBarriers()[0].newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(read.finalBarriers()[0].dstAccess, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    EXPECT_EQ(read.finalBarriers()[1].kind, BarrierKind::Memory);
    EXPECT_EQ(read.finalBarriers()[1].dstStages, VK_PIPELINE_STAGE_2_HOST_BIT);
    EXPECT_NE(messageOf([&] { (void)planImageRead(g, frame, "nope"); }).find("cannot read 'nope'"), std::string::npos);
}

// An output is handed on whole, and a `clear` one needs no writer: where no pass that runs
// uses it (its user switched off, or culled for writing nothing), a Clear after the last pass
// makes it. Before, the plan left the output out, silently. The Clear's barrier starts from
// UNDEFINED (nothing before it in the frame; each frame has its own copy) and orders nothing
// before it; the final barrier makes the transfer write available to the exported state's
// scope, with the transition to its layout.
TEST(ClearOutputs, OneNoPassThatRunsUsesIsClearedAfterTheLastPass) {
    // `look` reads `shown` where feature f is on; `peek` reads it and writes nothing (culled).
    const GraphDesc g = parseGraph(R"({"version": 1, "name": "t", "features": {"f": true},
        "resources": {
          "shown": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "final": "ShaderRead",
                    "clear": {"color": [1, 0, 0, 1]}},
          "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true, "final": "TransferSrc"}},
        "passes": [
          {"name": "look", "type": "Generic", "if": "f", "uses": {"shown": "Read@Compute", "out": "Write@Compute"}},
          {"name": "peek", "type": "Generic", "uses": {"shown": "Read@Fragment"}},
          {"name": "draw", "type": "Generic", "if": "!f", "uses": {"out": "Write@Compute"}}]})",
                                   "clear_output.json", registry());
    // Used: cleared before its first use, as every `clear` resource is.
    CompileOptions on;
    on.features = {{"f", true}};
    const Plan used = compile(g, on);
    ASSERT_EQ(used.passes().size(), 2u) << planToText(used);
    EXPECT_EQ(used.passes()[0].name, "clear shown");
    EXPECT_EQ(used.passes()[1].name, "look");
    // Unused by the passes that run: cleared after the last one, and handed on.
    CompileOptions off;
    off.features = {{"f", false}};
    const Plan plan = compile(g, off);
    ASSERT_EQ(plan.passes().size(), 2u) << planToText(plan);
    EXPECT_EQ(plan.passes()[0].name, "draw");
    const PlannedPass& clear = plan.passes()[1];
    EXPECT_EQ(clear.name, "clear shown");
    EXPECT_EQ(clear.type, "Clear");
    const int32_t shown = plan.resourceIndex("shown");
    ASSERT_GE(shown, 0);
    ASSERT_EQ(clear.barriers.size(), 1u);
    const Barrier& start = clear.barriers[0];
    EXPECT_EQ(start.resource, uint32_t(shown));
    EXPECT_EQ(start.oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(start.newLayout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    EXPECT_EQ(start.srcStages, VK_PIPELINE_STAGE_2_NONE);  // its frame's own copy: the fence ordered the last
    EXPECT_EQ(start.dstStages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);
    EXPECT_EQ(start.dstAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const auto finals = plan.finalBarriers();
    const auto final = std::find_if(finals.begin(), finals.end(), [&](const Barrier& b) { return b.resource == uint32_t(shown); });
    ASSERT_NE(final, finals.end());
    EXPECT_TRUE(final->srcStages & VK_PIPELINE_STAGE_2_TRANSFER_BIT);
    EXPECT_EQ(final->srcAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    EXPECT_EQ(final->oldLayout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    EXPECT_EQ(final->newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(final->dstAccess, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    bool culled = false;
    for (const auto& c : plan.culled()) culled |= c.name == "peek";
    EXPECT_TRUE(culled) << planToText(plan);
}

TEST(Copies, EachResourceSaysWhyItHasOneCopyOrOnePerFrameInFlight) {
    const GraphDesc g = graphOf(std::string(kTexture) + "," + kOut + "," + kColor +
                                    R"(, "scratch": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true},
                                        "screen": {"type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true, "final": "Present"})",
                                R"(
        {"name": "draw", "type": "Generic", "uses": {"tex": "Read@Fragment", "color": "Write@ColorAttachment", "scratch": "Write@ColorAttachment"}},
        {"name": "copy", "type": "Generic", "uses": {"color": "Read@Transfer", "out": "Write@Transfer", "screen": "Write@Transfer"}})");
    CompileOptions o;
    o.cull = false;
    const Plan plan = compile(g, o);
    auto copies = [&](const char* name) {
        const int32_t i = plan.resourceIndex(name);
        if (i < 0) throw std::out_of_range(std::string("no plan resource ") + name);
        return plan.resources()[size_t(i)].copies;
    };
    EXPECT_EQ(copies("color"), ResourceCopies::SharedTransient) << "the frames share the transients' heaps";
    o.shareTransientsAcrossFrames = false;
    EXPECT_EQ(compile(g, o).resources()[size_t(plan.resourceIndex("color"))].copies, ResourceCopies::PerFrameTransient);
    EXPECT_EQ(copies("screen"), ResourceCopies::PerFramePresented);
    EXPECT_EQ(copies("scratch"), ResourceCopies::PerFrameWrittenNotExported);
    EXPECT_EQ(copies("out"), ResourceCopies::SharedExported);
    EXPECT_EQ(copies("tex"), ResourceCopies::SharedReadOnly);
}

}  // namespace
}  // namespace skygraph
