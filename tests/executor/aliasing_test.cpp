// Transient memory on the device: the renderer allocates each heap of the plan's memory layout
// once per frame slot and binds every placed transient into its slot's heap at its offset,
// after checking the device's requirements against its placement. A plan placed with other
// requirements than the device's is compiled again, and one handed in placed wrongly is refused.
#include "executor_test_util.hpp"

#include "compiled_graph_access.hpp"
#include "renderer_access.hpp"

#include <algorithm>
#include <filesystem>
#include <set>

namespace skygraph::test {
namespace {

const std::filesystem::path kDeferred = std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "deferred.json";

/// graphs/deferred.json compiled headless at `size` with `o`'s memory settings and the shared
/// device's memory model unless `o` names another.
CompiledGraph deferred(uint32_t size, CompileOptions o = {}) {
    GraphDesc graph = loadGraphFile(kDeferred, PassRegistry::withBuiltins());
    o.outputWidth = o.outputHeight = size;
    if (!o.memory) o.memory = sharedDevice().memoryModel();
    o = headless(graph, std::move(o));
    return CompiledGraph(std::move(graph), std::move(o));
}

/// Answers as the estimate does, but with every size cut to 256 bytes at an alignment of 1:
/// a model that placements made with cannot hold the real images.
class TooSmallModel final : public MemoryModel {
public:
    MemoryRequirements requirements(const MemoryQuery&) const override { return {256, 1, ~0u}; }
    uint64_t bufferImageGranularity() const override { return 1; }
    std::string name() const override { return "too small"; }
};

using Aliasing = ExecutorTest;

// The deferred frame's 22 transients share memory: several frames with two in flight, under
// synchronization validation (QUEUE_SUBMIT included), with each slot's heaps smaller than the
// transients' memory laid end to end.
TEST_F(Aliasing, TheDeferredFrameRendersInHeapsSmallerThanItsTransients) {
    CompileOptions perFrame;
    perFrame.shareTransientsAcrossFrames = false;  // a copy of the heaps per frame slot, counted below
    const CompiledGraph c = deferred(64, perFrame);
    const MemoryLayout& layout = c.plan().memory();
    EXPECT_EQ(layout.model, sharedDevice().name());
    ASSERT_FALSE(layout.heaps.empty());
    EXPECT_TRUE(std::any_of(layout.placements.begin(), layout.placements.end(),
                            [](const MemoryPlacement& p) { return !p.aliases.empty(); }))
        << "nothing takes over memory: the test would show nothing";

    Renderer r(sharedDevice(), c, genericOptions(2));
    EXPECT_EQ(r.compiled().options().memory, sharedDevice().memoryModel()) << "compiled with it: not again";
    for (int i = 0; i < 5; ++i) r.renderFrame();
    const ImageData img = r.readback();
    r.waitIdle();
    EXPECT_EQ(img.width, 64u);

    const RendererMemory memory = RendererAccess::memory(r);
    ASSERT_EQ(memory.heaps.size(), 2 * layout.heaps.size()) << "one allocation per heap per frame slot";
    for (size_t i = 0; i < memory.heaps.size(); ++i) {
        EXPECT_EQ(memory.heaps[i].bytes, layout.heaps[i % layout.heaps.size()].bytes);
        EXPECT_EQ(memory.heaps[i].name, "heap " + std::to_string(i % layout.heaps.size()) + "#" +
                                            std::to_string(i / layout.heaps.size()));
    }
    // Every transient copy is in its frame slot's heap at its offset, needing no more than
    // its placement; the ones that share bytes are never alive together (the compiler's
    // promise, checked here on what was bound).
    ASSERT_EQ(memory.placed.size(), 2 * layout.placements.size());
    VkDeviceSize unaliased = 0;
    for (const RendererMemory::Placed& p : memory.placed) {
        const int32_t index = c.plan().resourceIndex(p.resource);
        ASSERT_GE(index, 0);
        const MemoryPlacement& placement = layout.placements.at(c.plan().resources()[size_t(index)].placement);
        EXPECT_EQ(p.memory, memory.heaps.at(p.copy * layout.heaps.size() + placement.heap).memory) << p.resource;
        EXPECT_EQ(p.offset, placement.offset) << p.resource;
        EXPECT_LE(p.bytes, placement.bytes) << p.resource;
        if (p.copy == 0) unaliased += p.bytes;
    }
    EXPECT_LT(memory.heapBytes() / 2, unaliased) << "each slot's heaps against its transients end to end";
    EXPECT_LT(memory.heapBytes() / 2, layout.unaliasedBytes);
    EXPECT_EQ(memory.heapBytes() / 2, layout.heapBytes());
    for (const RendererMemory::Allocation& own : memory.own)
        EXPECT_TRUE(own.name.starts_with("taa_history") || own.name.starts_with("swapchain")) << own.name;
}

// With CompileOptions::shareTransientsAcrossFrames (the default) the frames in flight share one set of heaps:
// one allocation per heap, one copy of each transient, and each frame's first uses of the bytes
// wait for the previous frame's last uses (the plan's barriers), silently under validation.
TEST_F(Aliasing, TheFramesInFlightCanShareOneSetOfHeaps) {
    CompileOptions o;
    o.shareTransientsAcrossFrames = true;
    const CompiledGraph c = deferred(64, o);
    ASSERT_TRUE(c.plan().memory().sharedAcrossFrames);
    Renderer r(sharedDevice(), c, genericOptions(2));
    for (int i = 0; i < 5; ++i) r.renderFrame();
    r.waitIdle();
    const RendererMemory memory = RendererAccess::memory(r);
    EXPECT_EQ(memory.heaps.size(), c.plan().memory().heaps.size());
    EXPECT_EQ(memory.heapBytes(), c.plan().memory().heapBytes());
    EXPECT_EQ(memory.placed.size(), c.plan().memory().placements.size()) << "one copy of each transient";
    for (const RendererMemory::Placed& p : memory.placed) EXPECT_EQ(p.copy, 0u) << p.resource;
}

// The compiler's estimate is not the device: the renderer compiles such a graph again with the
// device's memory model, and reports the plan that runs.
TEST_F(Aliasing, APlanPlacedWithTheEstimateIsCompiledAgainWithTheDevicesModel) {
    CompileOptions o;
    o.memory = estimatedMemory();
    const CompiledGraph estimated = deferred(64, o);
    EXPECT_EQ(estimated.plan().memory().model, "estimate");
    Renderer r(sharedDevice(), estimated, genericOptions(2));
    EXPECT_EQ(r.compiled().options().memory, sharedDevice().memoryModel());
    EXPECT_EQ(r.plan().memory().model, sharedDevice().name());
    EXPECT_NE(r.plan().memory(), estimated.plan().memory());
    r.renderFrame();
    // A resize keeps the device's model: it compiles with the running options.
    r.resize(96, 96);
    EXPECT_EQ(r.plan().memory().model, sharedDevice().name());
    r.renderFrame();
    r.waitIdle();
}

// The negative control of the requirement check: a plan whose placements were made with
// requirements smaller than the device's, handed in as if compiled with the device's model
// (the test seam), is refused before anything is bound, naming a resource.
TEST_F(Aliasing, APlanPlacedWithOtherRequirementsIsRefusedNamingTheResource) {
    const CompiledGraph onDevice = deferred(64);
    CompileOptions o;
    o.memory = std::make_shared<TooSmallModel>();
    const CompiledGraph tooSmall = deferred(64, o);
    ASSERT_EQ(tooSmall.plan().resources().size(), onDevice.plan().resources().size());
    try {
        Renderer r(sharedDevice(), detail::CompiledGraphAccess::withPlan(onDevice, tooSmall.plan()), genericOptions(2));
        FAIL() << "a plan placed with 256-byte requirements was bound";
    } catch (const ExecutorError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("does not fit its place in heap"), std::string::npos) << what;
        EXPECT_NE(what.find("the device needs"), std::string::npos) << what;
        EXPECT_NE(what.find("'too small'"), std::string::npos) << what;
        EXPECT_TRUE(what.starts_with("resource '")) << what;
    }
}

// After the frame, a transient holds what the resource that took over its memory left there:
// reading it is refused; one whose memory nothing takes over can still be read.
TEST_F(Aliasing, ReadingATransientWhoseMemoryIsTakenOverIsRefused) {
    const CompiledGraph c = deferred(64);
    std::set<uint32_t> takenOver;
    for (const MemoryPlacement& p : c.plan().memory().placements) takenOver.insert(p.aliases.begin(), p.aliases.end());
    ASSERT_FALSE(takenOver.empty());
    std::string kept;
    for (const MemoryPlacement& p : c.plan().memory().placements) {
        const PlannedResource& res = c.plan().resources()[p.resource];
        const ResourceDesc& d = c.graph().resources[res.decl];
        if (!takenOver.count(p.resource) && d.isImage()) kept = d.name;
    }
    Renderer r(sharedDevice(), c, genericOptions(2));
    r.renderFrame();
    const std::string lost(c.plan().resources()[*takenOver.begin()].name);
    try {
        (void)r.readImage(lost);
        FAIL() << "'" << lost << "' was read after its memory was taken over";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("takes over its memory"), std::string::npos) << e.what();
    }
    ASSERT_FALSE(kept.empty()) << "every transient image of the deferred frame is taken over";
    EXPECT_FALSE(r.readImage(kept).empty()) << kept;
    r.waitIdle();
}

}  // namespace
}  // namespace skygraph::test
