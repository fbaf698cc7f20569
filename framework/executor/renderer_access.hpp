// Internal: what benchmarks reach inside a Renderer: recording its plan into their own command
// buffer, and the handles it records with, for the benchmark's hand-written recording of the
// same commands; and what the presentation tests weaken on purpose. Not part of the public API
// (bench/ and tests/ include it from framework/executor).
#pragma once

#include <skygraph/renderer.hpp>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace skygraph {

class PassImplementation;  // skygraph/pass.hpp

/// What the executor records around one pass, as plain Vulkan handles and arrays: the plan's
/// barrier batch and, for a graphics pass, its render pass. What the pass records inside is
/// its recording code's (`implementation`).
struct HandPass {
    std::vector<VkImageMemoryBarrier2> imageBarriers;
    std::vector<VkBufferMemoryBarrier2> bufferBarriers;
    std::vector<VkMemoryBarrier2> memoryBarriers;
    VkRenderPass renderPass = VK_NULL_HANDLE;  ///< Null for passes without attachments.
    VkFramebuffer framebuffer = VK_NULL_HANDLE;
    VkExtent2D extent{};
    std::vector<VkClearValue> clearValues;
    PassImplementation* implementation = nullptr;  ///< The renderer's; valid like the handles.
};

struct HandFrame {
    std::vector<HandPass> passes;
    std::vector<VkImageMemoryBarrier2> finalImageBarriers;
    std::vector<VkBufferMemoryBarrier2> finalBufferBarriers;
    std::vector<VkMemoryBarrier2> finalMemoryBarriers;
};

/// Where a renderer's plan resources live in device memory (RendererAccess::memory): the
/// heaps its placed transients share and the memory of its other resources. Handles are the
/// renderer's, valid while its plan state is not rebuilt.
struct RendererMemory {
    struct Allocation {
        std::string name;  ///< "heap 0#1" (heap 0 of frame slot 1), or the resource copy's name.
        VkDeviceMemory memory = VK_NULL_HANDLE;
        VkDeviceSize bytes = 0;
    };
    /// A transient bound into a heap.
    struct Placed {
        std::string resource;
        uint32_t copy = 0;  ///< The frame slot whose heap it is in.
        VkDeviceMemory memory = VK_NULL_HANDLE;
        VkDeviceSize offset = 0;
        VkDeviceSize bytes = 0;  ///< What the device requires for it (vkGet*MemoryRequirements).
    };
    std::vector<Allocation> heaps;  ///< Every heap of every frame slot, slot after slot.
    std::vector<Allocation> own;    ///< Resource copies with memory of their own (not present images).
    std::vector<Placed> placed;

    [[nodiscard]] VkDeviceSize heapBytes() const noexcept {
        VkDeviceSize sum = 0;
        for (const Allocation& a : heaps) sum += a.bytes;
        return sum;
    }
    [[nodiscard]] VkDeviceSize ownBytes() const noexcept {
        VkDeviceSize sum = 0;
        for (const Allocation& a : own) sum += a.bytes;
        return sum;
    }
};

struct RendererAccess {
    /// The renderer's state type (renderer_impl.hpp defines it), for the executor's sources that
    /// hold or pass it outside Renderer's own members.
    using Impl = Renderer::Impl;

    /// Records `renderer`'s current plan for frame slot `slot` into `cmd` (begun by the
    /// caller), without labels or timestamps (its Readback steps included). For benchmarks that
    /// compare against hand recording. Throws ExecutorError for a slot out of range.
    static void recordInto(Renderer& renderer, VkCommandBuffer cmd, uint32_t slot);
    /// Copies the handles of frame slot `slot`. They stay valid while `renderer` lives and is
    /// not resized. Throws ExecutorError for plans with steps the compiler inserted (clears,
    /// read-backs), which the hand recording does not cover.
    static HandFrame handFrame(Renderer& renderer, uint32_t slot);

    /// Test-only, for negative controls of presentation: the stages the next presented frames
    /// wait for the acquire semaphore in, in place of the plan's (acquireWaitStages); 0 leaves
    /// the wait out. std::nullopt: the plan's again.
    static void overrideAcquireWait(Renderer& renderer, std::optional<VkPipelineStageFlags2> stages);
    /// Test-only: the stages the next presented frames signal the render-complete semaphore in,
    /// in place of presentSignalStages. std::nullopt: presentSignalStages again.
    static void overrideRenderCompleteSignal(Renderer& renderer, std::optional<VkPipelineStageFlags2> stages);
    /// Test-only: the frame (counted from 0, as frameCount() counts) whose timings
    /// completedTimings() holds; none when it holds none.
    [[nodiscard]] static std::optional<uint64_t> timingsFrame(const Renderer& renderer);
    /// Test-only, for negative controls of setup plans (uploads and their mip chains): `edit`
    /// changes each setup plan after the compiler made it and before it is recorded. Empty:
    /// none again.
    static void editSetupPlans(Renderer& renderer, std::function<void(Plan&)> edit);
    /// Test-only, the same for the plans that fill passes' sampled images
    /// (RecordContext::fillSampledImages).
    static void editSampledImagePlans(Renderer& renderer, std::function<void(Plan&)> edit);

    /// Test-only, and for memory measurements: the device memory of the current plan state.
    [[nodiscard]] static RendererMemory memory(const Renderer& renderer);
};

}  // namespace skygraph
