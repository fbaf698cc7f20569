// The executor's recording, read without a device: every shipped graph under every feature
// combination (and headless, with its read-back), recorded into a CommandLog with stand-in
// handles and stand-in recording code, records exactly the plan's barriers in the plan's order
// — each pass's batch before it, a ReadWrite transfer's in-pass barrier where the pass asks for
// it, the final barriers last — and no other barrier. On lavapipe, synchronization validation
// is the oracle for the same frames, recorded by the passes' real code.
#include "command_log.hpp"
#include "renderer_impl.hpp"

#include <skygraph/compiled_graph.hpp>
#include <skygraph/compiler.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace skygraph::detail {
namespace {

namespace fs = std::filesystem;

constexpr uint32_t kSlots = 2;

/// Stands in for every pass's recording code, recording like a pass with a ReadWrite transfer:
/// says in the log what it records ("copy out", "copy in") and asks for the plan's in-pass
/// barriers between the two (RecordContext::recordInPassBarriers), the only barrier a pass may
/// record. `log` is the log being recorded into.
class StandInPass final : public PassImplementation {
public:
    explicit StandInPass(CommandLog* const& log) : log_(log) {}
    void createPipelines(const PipelineContext&) override {}
    void recordBeforeRenderPass(const RecordContext& c) override { log_->note(who(c) + ": before its render pass"); }
    void record(const RecordContext& c) override {
        log_->note(who(c) + ": copy out");
        c.recordInPassBarriers();
        log_->note(who(c) + ": copy in");
    }

private:
    static std::string who(const RecordContext& c) {
        return std::string(c.pass->name) + " (slot " + std::to_string(c.frameSlot) + ")";
    }
    CommandLog* const& log_;
};

/// A plan's state as the executor builds it, with stand-in handles instead of Vulkan objects:
/// image r's copy c is handle 0x1000 * (r + 1) + c, and is named "<resource>#<c>" in the log.
struct StandIn {
    explicit StandIn(CompiledGraph compiled) : state(std::move(compiled)) {
        const Plan& plan = state.plan;
        for (uint32_t i = 0; i < plan.resources().size(); ++i) {
            ResourceState r;
            r.desc = &state.graph.resources[plan.resources()[i].decl];
            r.isImage = r.desc->isImage();
            r.perSlot = perFrameInFlight(plan.resources()[i].copies);
            r.aspect = r.isImage ? aspectOf(r.desc->format) : 0;
            r.format = r.desc->format.format;
            const auto [w, h] = r.desc->extent.resolve(plan.outputWidth(), plan.outputHeight());
            r.width = w;
            r.height = h;
            for (uint32_t c = 0; c < (r.perSlot ? kSlots : 1); ++c) {
                const uint64_t handle = 0x1000 * (uint64_t(i) + 1) + c;
                names[handle] = std::string(plan.resources()[i].name) + "#" + std::to_string(c);
                if (r.isImage) {
                    ImageCopy copy;
                    copy.image = reinterpret_cast<VkImage>(handle);
                    r.images.push_back(std::move(copy));
                } else {
                    OwnedBuffer b;
                    b.buffer = owned::Buffer(VK_NULL_HANDLE, reinterpret_cast<VkBuffer>(handle));
                    r.buffers.push_back(std::move(b));
                }
            }
            state.resources.push_back(std::move(r));
        }
        for (const PlannedPass& pass : plan.passes()) {
            PassState ps;
            ps.pass = &pass;
            ps.label = pass.name;
            ps.kind = stepKindOf(pass);
            if (ps.kind == StepKind::Pass) {
                ps.implementation = std::make_unique<StandInPass>(log);
                ps.attachments = attachmentsOf(pass, state.resources);
            }
            ps.slots.resize(kSlots);
            for (uint32_t slot = 0; slot < kSlots; ++slot) {
                translatePassBarriers(state, ps, slot);
                if (ps.attachments.any()) ps.slots[slot].extent = framebufferExtent(pass, ps.attachments, state.resources);
            }
            state.passes.push_back(std::move(ps));
        }
        translateFinalBarriers(state, kSlots);
        for (uint32_t step = 0; step < plan.passes().size(); ++step) {
            if (state.passes[step].kind != StepKind::Readback) continue;
            ReadbackTarget t;
            t.step = step;
            t.resource = plan.passes()[step].usages[0].resource;
            for (uint32_t slot = 0; slot < kSlots; ++slot) {
                const uint64_t handle = 0x900000 + 0x10 * step + slot;
                names[handle] = "host#" + std::to_string(slot);
                OwnedBuffer b;
                b.buffer = owned::Buffer(VK_NULL_HANDLE, reinterpret_cast<VkBuffer>(handle));
                t.perSlot.push_back(std::move(b));
            }
            state.readbacks.push_back(std::move(t));
        }
    }
    ~StandIn() {
        // The stand-ins are not Vulkan objects: nothing to destroy.
        for (ResourceState& r : state.resources)
            for (OwnedBuffer& b : r.buffers) (void)b.buffer.release();
        for (ReadbackTarget& t : state.readbacks)
            for (OwnedBuffer& b : t.perSlot) (void)b.buffer.release();
    }
    StandIn(const StandIn&) = delete;
    StandIn& operator=(const StandIn&) = delete;

    /// What the log must say for a batch of plan barriers in frame slot `slot`, worked out from
    /// the plan alone: memory, then buffer, then image barriers, each in plan order (one
    /// vkCmdPipelineBarrier2 takes them as three arrays).
    std::vector<std::string> expected(std::span<const Barrier> batch, uint32_t slot) const {
        std::vector<std::string> out;
        for (const BarrierKind kind : {BarrierKind::Memory, BarrierKind::Buffer, BarrierKind::Image})
            for (const Barrier& b : batch) {
                if (b.kind != kind) continue;
                const ResourceState& r = state.resources[b.resource];
                const std::string name = std::string(state.plan.resources()[b.resource].name) + "#" +
                                         std::to_string(r.perSlot ? slot : 0);
                const VkImageSubresourceRange range{r.aspect, b.range.baseMip, b.range.mipCount, b.range.baseLayer,
                                                    b.range.layerCount};
                const char* word = kind == BarrierKind::Memory ? "memory" : kind == BarrierKind::Buffer ? "buffer" : "image";
                std::string line = "barrier " + CommandLog::barrierLine(word, kind == BarrierKind::Memory ? "-" : name,
                                                                        b.srcStages, b.srcAccess, b.dstStages, b.dstAccess,
                                                                        kind == BarrierKind::Image ? &range : nullptr,
                                                                        b.oldLayout, b.newLayout);
                // The fields barrierLine() leaves out, spelled here from the plan and the graph
                // (not with the log's own helpers): a whole buffer, the image's aspects from its
                // format, and queue families only for an ownership transfer.
                const FormatInfo& format = r.desc->format;
                if (kind == BarrierKind::Buffer) line += " bytes 0+whole";
                if (kind == BarrierKind::Image)
                    line += format.hasDepth && format.hasStencil ? " aspect DEPTH|STENCIL"
                            : format.hasDepth                    ? " aspect DEPTH"
                            : format.hasStencil                  ? " aspect STENCIL"
                                                                 : " aspect COLOR";
                if (kind != BarrierKind::Memory && b.transfersOwnership()) {
                    const auto& families = state.plan.queueFamilies();
                    line += " family " + std::to_string(families[static_cast<size_t>(b.srcQueue)]) + " -> " +
                            std::to_string(families[static_cast<size_t>(b.dstQueue)]);
                }
                out.push_back(std::move(line));
            }
        return out;
    }

    PlanState state;
    std::map<uint64_t, std::string> names;
    CommandLog* log = nullptr;  ///< Where the stand-in passes write: the log being recorded into.
};

std::vector<std::string> barrierLines(const std::vector<std::string>& log) {
    std::vector<std::string> out;
    for (const std::string& line : log)
        if (line.starts_with("barrier ")) out.push_back(line);
    return out;
}

/// The plan's barriers of frame slot `slot` in the order a frame records them: submit by
/// submit, each pass's batch and in-pass barriers, then the submit's ownership releases; the
/// final barriers last.
std::vector<std::string> planBarriers(const StandIn& s, uint32_t slot) {
    std::vector<std::string> out;
    const Plan& plan = s.state.plan;
    const auto add = [&](std::span<const Barrier> barriers) {
        for (const std::string& l : s.expected(barriers, slot)) out.push_back(l);
    };
    for (const Submit& submit : plan.submits()) {
        for (const uint32_t i : submit.passes) {
            add(plan.passes()[i].barriers);
            std::vector<Barrier> inPass;
            for (const InPassBarrier& ib : plan.inPassBarriers())
                if (ib.pass == i) inPass.push_back(ib.barrier);
            add(inPass);
        }
        add(submit.releases);
    }
    add(plan.finalBarriers());
    return out;
}

const PassRegistry& registry() {
    static const PassRegistry r = PassRegistry::withBuiltins();
    return r;
}

/// Every shipped graph under every feature combination, as it renders headless.
std::vector<CompiledGraph> shippedCases() {
    std::vector<CompiledGraph> cases;
    for (const char* file : {"raster.json", "pathtrace.json", "ibl.json", "deferred.json", "async.json"}) {
        const GraphDesc g = loadGraphFile(fs::path(SKYGRAPH_SOURCE_DIR) / "graphs" / file, registry());
        for (size_t mask = 0; mask < (size_t(1) << g.features.size()); ++mask) {
            CompileOptions o;
            for (size_t f = 0; f < g.features.size(); ++f) o.features[g.features[f].name] = (mask >> f) & 1;
            o.presentReplacement = ExternalState::TransferSrc;
            o.outputWidth = 128;  // deferred.json's output/2 chains have 6 levels
            o.outputHeight = 96;
            if (g.findResource("swapchain")) o.readbacks = {"swapchain"};
            cases.emplace_back(g, o);
        }
    }
    return cases;
}

TEST(CommandLog, EveryShippedPlanIsRecordedWithExactlyItsOwnBarriers) {
    size_t plans = 0, barriers = 0, transfers = 0;
    for (const CompiledGraph& compiled : shippedCases()) {
        StandIn s(compiled);
        for (uint32_t slot = 0; slot < kSlots; ++slot) {
            CommandLog log(s.names);
            s.log = &log;
            FrameRecording r;
            r.slot = slot;
            recordFrame(log, s.state, r);
            const auto recorded = barrierLines(log.lines());
            const auto expected = planBarriers(s, slot);
            ASSERT_EQ(recorded, expected) << "graph " << compiled.graph().name << ", slot " << slot;
            barriers += recorded.size();
            transfers += static_cast<size_t>(std::count_if(recorded.begin(), recorded.end(), [](const std::string& l) {
                return l.find(" family ") != std::string::npos;
            }));
        }
        ++plans;
    }
    EXPECT_EQ(plans, 128u + 2u + 2u + 16u + 1u);
    EXPECT_GT(barriers, 500u) << "the plans' barriers were all compared";
    EXPECT_GT(transfers, 0u) << "async.json's ownership transfers were compared, families included";
}

TEST(CommandLog, IntegerImagesAreClearedToTheIntegersTheirClearNames) {
    const GraphDesc g = parseGraph(R"({"version": 1, "name": "t", "resources": {
        "ids": {"type": "image2d", "format": "R32_UINT", "extent": [4, 4], "clear": {"color": [7, 0, 0, 1]}},
        "offsets": {"type": "image2d", "format": "R32_SINT", "extent": [4, 4], "clear": {"color": [-2, 3, 0, 1]}},
        "out": {"type": "buffer", "size": 64, "external": true, "final": "General"}},
      "passes": [
        {"name": "use", "type": "Generic",
         "uses": {"ids": "Read@Transfer", "offsets": "Read@Compute", "out": "Write@Compute"}}]})",
                                   "ints.json", registry());
    StandIn s(CompiledGraph(g, CompileOptions{}));
    CommandLog log(s.names);
    s.log = &log;
    FrameRecording r;
    recordFrame(log, s.state, r);
    std::vector<std::string> clears;
    for (const std::string& line : log.lines())
        if (line.starts_with("clear color")) clears.push_back(line.substr(line.find(" to ")));
    // As float bits they would be 0x40e00000 and 0xc0000000.
    EXPECT_EQ(clears, (std::vector<std::string>{" to 0x00000007 0x00000000 0x00000000 0x00000001",
                                                " to 0xfffffffe 0x00000003 0x00000000 0x00000001"}));
}

TEST(CommandLog, AFramesStepsComeInPlanOrderWithTheirCommands) {
    const GraphDesc g = parseGraph(R"({"version": 1, "name": "t", "resources": {
        "color": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "clear": {"color": [0, 0, 0, 1]}},
        "canvas": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [4, 2]},
        "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true, "final": "TransferSrc"}},
      "passes": [
        {"name": "edit", "type": "Generic", "uses": {"color": "ReadWrite@Transfer"}},
        {"name": "blit", "type": "Generic", "uses": {"color": "Read@Transfer", "out": "Write@Transfer"}},
        {"name": "draw", "type": "Generic", "never_cull": true, "uses": {"canvas": "Write@ColorAttachment"}}]})",
                                   "log.json", registry());
    CompileOptions o;
    o.readbacks = {"out"};
    o.shareTransientsAcrossFrames = false;  // slot 1 records its own copies (#1)
    StandIn s(CompiledGraph(g, o));
    CommandLog log(s.names);
    s.log = &log;
    FrameRecording r;
    r.slot = 1;
    recordFrame(log, s.state, r);
    std::vector<std::string> commands;
    for (const std::string& line : log.lines())
        if (!line.starts_with("barrier ")) commands.push_back(line);
    // color is transient (slot 1's copy); out is exported (one copy); the host copy is slot 1's.
    // A pass's recording code gets the slot it records; a graphics pass records part of its work
    // before the render pass the executor begins for it, the rest inside.
    EXPECT_EQ(commands, (std::vector<std::string>{
                            "clear color color#1 mips[0+1] layers[0+1] in TRANSFER_DST_OPTIMAL to 0x00000000 0x00000000 0x00000000 0x3f800000",
                            "record pass edit",
                            "edit (slot 1): copy out",
                            "edit (slot 1): copy in",
                            "record pass blit",
                            "blit (slot 1): copy out",
                            "blit (slot 1): copy in",
                            "record pass draw before its render pass",
                            "draw (slot 1): before its render pass",
                            "begin render pass 4x2",
                            "record pass draw",
                            "draw (slot 1): copy out",
                            "draw (slot 1): copy in",
                            "end render pass",
                            "copy out#0 in TRANSFER_SRC_OPTIMAL -> host#1, 1 region(s)",
                        }));
    // The in-pass barrier sits where edit asked for it, between its copy out and copy in; the
    // other passes have none.
    const auto& lines = log.lines();
    const auto out = std::find(lines.begin(), lines.end(), "edit (slot 1): copy out");
    ASSERT_NE(out, lines.end());
    EXPECT_TRUE((out + 1)->starts_with("barrier image color#1 mips[0+1] layers[0+1] TRANSFER/NONE -> TRANSFER/TRANSFER_WRITE"))
        << *(out + 1);
    EXPECT_EQ(*(out + 2), "edit (slot 1): copy in");
    for (const char* pass : {"blit", "draw"}) {
        const auto copyOut = std::find(lines.begin(), lines.end(), std::string(pass) + " (slot 1): copy out");
        ASSERT_NE(copyOut, lines.end());
        EXPECT_EQ(*(copyOut + 1), std::string(pass) + " (slot 1): copy in");
    }
}

// Clobbering: each transient without `clear` is filled with its format's poison (poison.hpp) by
// a Clobber step before the pass that first writes it, in the frame slot's copy, and the
// frame's barriers are still exactly the plan's.
TEST(CommandLog, ClobberStepsFillEachTransientWithItsPoison) {
    const GraphDesc g = parseGraph(R"({"version": 1, "name": "poison", "resources": {
        "hdr": {"type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [8, 8]},
        "ldr": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "mips": 2},
        "ids": {"type": "image2d", "format": "R32_UINT", "extent": [8, 8]},
        "depth": {"type": "image2d", "format": "D24_UNORM_S8_UINT", "extent": [8, 8]},
        "buf": {"type": "buffer", "size": 64},
        "kept": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "clear": {"color": [0, 0, 0, 1]}},
        "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true, "final": "TransferSrc"}},
      "passes": [
        {"name": "draw", "type": "Generic", "uses": {"hdr": "Write@ColorAttachment", "depth": "Write@DepthAttachment"}},
        {"name": "compute", "type": "Generic", "uses": [
            {"resource": "hdr", "access": "Read", "stage": "Compute"},
            {"resource": "ldr", "access": "Write", "stage": "Compute", "mips": [0, 1]},
            {"resource": "ids", "access": "Write", "stage": "Compute"},
            {"resource": "buf", "access": "Write", "stage": "Compute"},
            {"resource": "kept", "access": "ReadWrite", "stage": "Compute"}]},
        {"name": "show", "type": "Generic", "uses": [
            {"resource": "ldr", "access": "Read", "stage": "Fragment", "mips": [0, 1]},
            {"resource": "ids", "access": "Read", "stage": "Fragment"},
            {"resource": "buf", "access": "Read", "stage": "Fragment"},
            {"resource": "depth", "access": "Read", "stage": "Fragment"},
            {"resource": "kept", "access": "Read", "stage": "Fragment"},
            {"resource": "out", "access": "Write", "stage": "ColorAttachment"}]}]})",
                                   "poison.json", registry());
    CompileOptions o;
    o.clobberTransients = true;
    o.shareTransientsAcrossFrames = false;  // slot 1 records its own copies (#1)
    StandIn s(CompiledGraph(g, o));
    CommandLog log(s.names);
    s.log = &log;
    FrameRecording r;
    r.slot = 1;
    recordFrame(log, s.state, r);
    EXPECT_EQ(barrierLines(log.lines()), planBarriers(s, 1));
    const auto& lines = log.lines();
    const auto at = [&](const std::string& line) {
        const auto it = std::find(lines.begin(), lines.end(), line);
        EXPECT_NE(it, lines.end()) << "no line '" << line << "' in\n" << ::testing::PrintToString(lines);
        return it - lines.begin();
    };
    const std::string nan = " to 0x7fc00000 0x7fc00000 0x7fc00000 0x7fc00000";
    const auto draw = at("record pass draw"), compute = at("record pass compute");
    EXPECT_LT(at("clear color hdr#1 mips[0+1] layers[0+1] in TRANSFER_DST_OPTIMAL" + nan), draw);
    EXPECT_LT(at("clear depth depth#1 mips[0+1] layers[0+1] in TRANSFER_DST_OPTIMAL to depth 0.5 stencil 0x5a"), draw);
    // Every mip, though the first write covers one: a later read of the other would show it.
    EXPECT_LT(at("clear color ldr#1 mips[0+2] layers[0+1] in TRANSFER_DST_OPTIMAL to 0x3f800000 0x00000000 "
                 "0x3f800000 0x3f800000"),
              compute);
    EXPECT_LT(at("clear color ids#1 mips[0+1] layers[0+1] in TRANSFER_DST_OPTIMAL to 0xdeadbeef 0xdeadbeef "
                 "0xdeadbeef 0xdeadbeef"),
              compute);
    EXPECT_LT(at("fill buf#1 from 0 to the end with 0x7fc00000"), compute);
    // A cleared transient gets its clear, not poison; the external output neither.
    EXPECT_EQ(std::count_if(lines.begin(), lines.end(), [](const std::string& l) {
                  return l.starts_with("clear color kept#1") &&
                         l.ends_with("0x00000000 0x00000000 0x00000000 0x3f800000");
              }),
              1);
    EXPECT_EQ(std::count_if(lines.begin(), lines.end(),
                            [](const std::string& l) { return l.starts_with("clear color out#"); }),
              0);
}

}  // namespace
}  // namespace skygraph::detail
