// GenericPass: the recording code of the pass type Generic, and of every pass type that has
// none of its own (the renderer runs those with its PassLibrary's "Generic"). It performs
// every access its usages declare (docs/executor.md, "The Generic pass"): generated shaders
// that read and write what the usages bind, copies for transfers, a draw into its attachments.
#pragma once

#include "generic_program.hpp"

#include <skygraph/pass.hpp>
#include <skygraph/pipeline_builder.hpp>
#include <skygraph/vk_handles.hpp>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <tuple>
#include <vector>

namespace skygraph::passes {

/// The handles GenericPass records one frame slot with, for a benchmark that records the same
/// commands by hand. Borrowed from the pass: valid while it lives.
struct GenericHandles {
    VkPipeline graphicsPipeline = VK_NULL_HANDLE;  ///< Null when the pass does not draw.
    VkPipelineLayout graphicsLayout = VK_NULL_HANDLE;
    std::span<const VkWriteDescriptorSet> graphicsWrites;
    uint32_t instances = 1;  ///< Of the draw: one per attachment layer.
    VkPipeline computePipeline = VK_NULL_HANDLE;  ///< Null when the pass does not dispatch.
    VkPipelineLayout computeLayout = VK_NULL_HANDLE;
    std::span<const VkWriteDescriptorSet> computeWrites;
    VkExtent2D computeExtent{0, 0};  ///< Invocations; the dispatch covers it in 8x8 groups.
    /// The pass also copies, binds vertex, index or indirect buffers, or draws in a render
    /// pass of its own (no attachments): more than a draw and a dispatch.
    bool recordsMore = false;
};

class GenericPass final : public PassImplementation {
public:
    /// Reads `desc`'s params, strictly for the type Generic (a malformed one is an
    /// ExecutorError naming the pass); other types that run as Generic ignore malformed ones.
    explicit GenericPass(const PassDesc& desc);
    ~GenericPass() override;

    void createPipelines(const PipelineContext& context) override;
    /// Copies and dispatch, outside the executor's render pass.
    void recordBeforeRenderPass(const RecordContext& context) override;
    /// The draw; for a pass without attachments, also its copies and dispatch first.
    void record(const RecordContext& context) override;

    /// Frame slot `frameSlot`'s handles, once createPipelines has run. Throws
    /// std::out_of_range for a slot the pass was not built for.
    [[nodiscard]] GenericHandles handles(uint32_t frameSlot) const;

private:
    struct Built;
    struct Slot;
    void recordCopiesAndDispatch(const RecordContext& context, const Slot& slot) const;
    void recordDraw(const RecordContext& context, const Slot& slot, VkExtent2D extent) const;

    GenericParams params_;
    std::unique_ptr<Built> built_;  ///< Replaced whole by createPipelines, only once it succeeded.
};

}  // namespace skygraph::passes
