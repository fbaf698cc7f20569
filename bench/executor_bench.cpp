// CPU cost of recording (and submitting) a frame: the framework's Renderer against a
// hand-written recording of the same commands and barriers, in the same process, on the same
// handles. Validation is off. Run: build/.../executor_bench --benchmark_counters_tabular=true
#include "generic_pass.hpp"
#include "renderer_access.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/device.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/pipeline_builder.hpp>
#include <skygraph/renderer.hpp>

#include <benchmark/benchmark.h>
#include <spdlog/spdlog.h>

#include <cstdlib>
#include <memory>

namespace skygraph {
namespace {

constexpr const char* kGraph = R"({
  "version": 1, "name": "bench",
  "resources": {
    "depth": { "type": "image2d", "format": "D32_SFLOAT", "extent": "output", "clear": { "depth": 0.0 } },
    "hdr":   { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output",
               "clear": { "color": [0, 0, 0, 1] } },
    "bloom": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output/2" },
    "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",
                   "external": true, "final": "Present" }
  },
  "passes": [
    { "name": "forward", "type": "Generic", "uses": { "depth": "Write@DepthAttachment", "hdr": "Write@ColorAttachment" } },
    { "name": "skybox", "type": "Generic", "uses": { "depth": "Read@DepthAttachment", "hdr": "ReadWrite@ColorAttachment" } },
    { "name": "bloom", "type": "Generic", "uses": { "hdr": "Read@Compute", "bloom": "Write@Compute" } },
    { "name": "tonemap", "type": "Generic",
      "uses": { "hdr": "Read@Fragment", "bloom": "Read@Fragment", "swapchain": "Write@ColorAttachment" } }
  ] })";

struct Fixture {
    PassLibrary library = PassLibrary::withBuiltins();  // Generic records every pass
    std::unique_ptr<Device> device;
    std::unique_ptr<Renderer> renderer;
    HandFrame hand;
    std::vector<passes::GenericHandles> generic;  ///< Parallel to hand.passes.
    PFN_vkCmdPushDescriptorSetKHR pushDescriptors = nullptr;
    VkCommandPool pool = VK_NULL_HANDLE;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    VkQueryPool queries = VK_NULL_HANDLE;
    PFN_vkCmdBeginDebugUtilsLabelEXT beginLabel = nullptr;
    PFN_vkCmdEndDebugUtilsLabelEXT endLabel = nullptr;
    std::vector<std::string> names;

    Fixture() {
        spdlog::set_level(spdlog::level::warn);
        DeviceOptions d;
        d.validation = false;
        if (const char* name = std::getenv("SKYGRAPH_BENCH_DEVICE")) d.device = name;
        device = Device::create(d);
        const auto registry = PassRegistry::withBuiltins();
        GraphDesc graph = parseGraph(kGraph, "<bench>", registry);
        CompileOptions co;  // no read-backs: both sides record the same commands
        co.presentReplacement = ExternalState::TransferSrc;
        co.outputWidth = 64;
        co.outputHeight = 64;
        CompiledGraph compiled(std::move(graph), co);
        for (const auto& p : compiled.plan().passes()) names.emplace_back(p.name);
        RendererOptions ro;
        ro.framesInFlight = 2;
        ro.passes = &library;
        renderer = std::make_unique<Renderer>(*device, std::move(compiled), ro);
        hand = RendererAccess::handFrame(*renderer, 0);
        for (const HandPass& p : hand.passes) {
            const auto* pass = dynamic_cast<const passes::GenericPass*>(p.implementation);
            if (!pass) throw ExecutorError("the hand recording covers Generic passes only");
            generic.push_back(pass->handles(0));
            if (generic.back().recordsMore) throw ExecutorError("the hand recording covers draws and dispatches only");
        }
        pushDescriptors = pushDescriptorFunction(device->device());

        const VkDevice vkd = device->device();
        VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO, nullptr, 0,
                                    device->queueFamily()};
        vkCreateCommandPool(vkd, &pci, nullptr, &pool);
        VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO, nullptr, pool,
                                       VK_COMMAND_BUFFER_LEVEL_PRIMARY, 1};
        vkAllocateCommandBuffers(vkd, &ai, &cmd);
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO, nullptr, 0};
        vkCreateFence(vkd, &fci, nullptr, &fence);
        VkQueryPoolCreateInfo qci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO, nullptr, 0,
                                  VK_QUERY_TYPE_TIMESTAMP, 2 * static_cast<uint32_t>(hand.passes.size()), 0};
        vkCreateQueryPool(vkd, &qci, nullptr, &queries);
        beginLabel = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(
            vkGetInstanceProcAddr(device->instance(), "vkCmdBeginDebugUtilsLabelEXT"));
        endLabel = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(
            vkGetInstanceProcAddr(device->instance(), "vkCmdEndDebugUtilsLabelEXT"));
    }
    ~Fixture() {
        renderer->waitIdle();
        vkDeviceWaitIdle(device->device());
        vkDestroyQueryPool(device->device(), queries, nullptr);
        vkDestroyFence(device->device(), fence, nullptr);
        vkDestroyCommandPool(device->device(), pool, nullptr);
        renderer.reset();
        device.reset();
    }
    Fixture(const Fixture&) = delete;
    Fixture& operator=(const Fixture&) = delete;
};

Fixture& fixture() {
    static Fixture f;
    return f;
}

void barrier(VkCommandBuffer cmd, const std::vector<VkImageMemoryBarrier2>& i,
             const std::vector<VkBufferMemoryBarrier2>& b, const std::vector<VkMemoryBarrier2>& m) {
    if (i.empty() && b.empty() && m.empty()) return;
    VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    di.memoryBarrierCount = static_cast<uint32_t>(m.size());
    di.pMemoryBarriers = m.data();
    di.bufferMemoryBarrierCount = static_cast<uint32_t>(b.size());
    di.pBufferMemoryBarriers = b.data();
    di.imageMemoryBarrierCount = static_cast<uint32_t>(i.size());
    di.pImageMemoryBarriers = i.data();
    vkCmdPipelineBarrier2(cmd, &di);
}

/// The hand-written frame: the same barriers, render passes, binds, pushes and draws.
void recordByHand(Fixture& f, VkCommandBuffer cmd, bool instrumented) {
    if (instrumented) vkCmdResetQueryPool(cmd, f.queries, 0, 2 * static_cast<uint32_t>(f.hand.passes.size()));
    uint32_t q = 0;
    for (size_t i = 0; i < f.hand.passes.size(); ++i) {
        const HandPass& p = f.hand.passes[i];
        const passes::GenericHandles& g = f.generic[i];
        if (instrumented && f.beginLabel) {
            VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
            label.pLabelName = f.names[i].c_str();
            f.beginLabel(cmd, &label);
        }
        barrier(cmd, p.imageBarriers, p.bufferBarriers, p.memoryBarriers);
        if (instrumented) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, f.queries, q++);
        if (g.computePipeline) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, g.computePipeline);
            f.pushDescriptors(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, g.computeLayout, 0,
                              static_cast<uint32_t>(g.computeWrites.size()), g.computeWrites.data());
            const uint32_t pc[4] = {g.computeExtent.width, g.computeExtent.height, 0, 0};
            vkCmdPushConstants(cmd, g.computeLayout, VK_SHADER_STAGE_COMPUTE_BIT, 0, 16, pc);
            vkCmdDispatch(cmd, (g.computeExtent.width + 7) / 8, (g.computeExtent.height + 7) / 8, 1);
        }
        if (g.graphicsPipeline) {
            VkRenderPassBeginInfo rbi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
            rbi.renderPass = p.renderPass;
            rbi.framebuffer = p.framebuffer;
            rbi.renderArea = {{0, 0}, p.extent};
            rbi.clearValueCount = static_cast<uint32_t>(p.clearValues.size());
            rbi.pClearValues = p.clearValues.data();
            vkCmdBeginRenderPass(cmd, &rbi, VK_SUBPASS_CONTENTS_INLINE);
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, g.graphicsPipeline);
            const VkViewport vp{0, 0, float(p.extent.width), float(p.extent.height), 0, 1};
            const VkRect2D sc{{0, 0}, p.extent};
            vkCmdSetViewport(cmd, 0, 1, &vp);
            vkCmdSetScissor(cmd, 0, 1, &sc);
            if (!g.graphicsWrites.empty())
                f.pushDescriptors(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, g.graphicsLayout, 0,
                                  static_cast<uint32_t>(g.graphicsWrites.size()), g.graphicsWrites.data());
            const uint32_t pc[4] = {p.extent.width, p.extent.height, 0, 0};
            vkCmdPushConstants(cmd, g.graphicsLayout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                               0, 16, pc);
            vkCmdDraw(cmd, 3, g.instances, 0, 0);
            vkCmdEndRenderPass(cmd);
        }
        if (instrumented) {
            vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, f.queries, q++);
            if (f.endLabel) f.endLabel(cmd);
        }
    }
    barrier(cmd, f.hand.finalImageBarriers, f.hand.finalBufferBarriers, f.hand.finalMemoryBarriers);
}

void setCounters(benchmark::State& state) {
    const auto passes = static_cast<double>(fixture().hand.passes.size());
    state.counters["passes"] = passes;
    state.counters["per_pass"] = benchmark::Counter(
        passes * static_cast<double>(state.iterations()),
        benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

/// Every recording starts the same way on both sides, so they differ only in what they record.
/// `vkd` is fetched once, outside the timed loop.
void beginCommandBuffer(VkDevice vkd, Fixture& f) {
    vkResetCommandPool(vkd, f.pool, 0);
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vkBeginCommandBuffer(f.cmd, &bi);
}

/// Recording alone: one loop for both sides, so only `record` differs between them.
template <class Record>
void recordOnly(benchmark::State& state, Record record) {
    Fixture& f = fixture();
    const VkDevice vkd = f.device->device();
    for (auto _ : state) {
        beginCommandBuffer(vkd, f);
        record(f);
        vkEndCommandBuffer(f.cmd);
    }
    setCounters(state);
}

void BM_Record_Framework(benchmark::State& state) {
    recordOnly(state, [](Fixture& f) { RendererAccess::recordInto(*f.renderer, f.cmd, 0); });
}
BENCHMARK(BM_Record_Framework);

void BM_Record_Hand(benchmark::State& state) {
    recordOnly(state, [](Fixture& f) { recordByHand(f, f.cmd, false); });
}
BENCHMARK(BM_Record_Hand);

// Record + submit with labels and timestamps; waiting for the GPU is excluded from timing.
void BM_RecordSubmit_Framework(benchmark::State& state) {
    Fixture& f = fixture();
    for (auto _ : state) {
        f.renderer->renderFrame();
        state.PauseTiming();
        f.renderer->waitIdle();
        state.ResumeTiming();
    }
    setCounters(state);
}
BENCHMARK(BM_RecordSubmit_Framework);

void BM_RecordSubmit_Hand(benchmark::State& state) {
    Fixture& f = fixture();
    const VkDevice vkd = f.device->device();
    for (auto _ : state) {
        vkResetFences(vkd, 1, &f.fence);
        beginCommandBuffer(vkd, f);
        recordByHand(f, f.cmd, true);
        vkEndCommandBuffer(f.cmd);
        VkCommandBufferSubmitInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
        cbi.commandBuffer = f.cmd;
        VkSubmitInfo2 si{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
        si.commandBufferInfoCount = 1;
        si.pCommandBufferInfos = &cbi;
        vkQueueSubmit2(f.device->queue(), 1, &si, f.fence);
        state.PauseTiming();
        vkWaitForFences(vkd, 1, &f.fence, VK_TRUE, UINT64_MAX);
        state.ResumeTiming();
    }
    setCounters(state);
}
BENCHMARK(BM_RecordSubmit_Hand);

}  // namespace
}  // namespace skygraph

BENCHMARK_MAIN();
