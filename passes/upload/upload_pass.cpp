// UploadPass: one copy from the staging buffer the application staged for this frame
// (Renderer::stageUpload) into the target. The plan's barriers put the target in
// TRANSFER_DST_OPTIMAL before it and hand it on (across queues too) after it.
#include "../builtin_passes.hpp"
#include "texel_encoding.hpp"

#include <skygraph/device.hpp>

#include <string>

namespace skygraph::passes {
namespace {

class UploadPass final : public PassImplementation {
public:
    explicit UploadPass(const PassDesc&) {}

    void createPipelines(const PipelineContext& ctx) override {
        const BoundResource& target = ctx.resources[0];
        const SubresourceRange& range = target.usage->range;
        const uint32_t layers = target.desc->layers;
        // A copy of mip 0 alone, declared as a write of more, would leave the other levels
        // undefined while the plan calls them written.
        if (target.desc->isImage() &&
            (range.baseMip != 0 || range.mipCount != 1 || range.baseLayer != 0 || range.layerCount != layers))
            throw ExecutorError("pass '" + ctx.desc->name + "' (UploadPass): its usage of '" + target.desc->name +
                                "' must cover mip 0 of every layer and nothing else (\"mips\": [0, 1])");
    }

    void record(const RecordContext& ctx) override {
        const BoundResource& target = ctx.resources[0];
        const StagingBuffer* staged = ctx.staged ? ctx.staged(target.desc->name) : nullptr;
        const std::string what = "pass '" + ctx.desc->name + "' (UploadPass): ";
        if (!staged)
            throw ExecutorError(what + "no pixels staged for '" + target.desc->name +
                                "' this frame (Renderer::stageUpload before each frame)");
        if (!target.image) {
            const VkBufferCopy region{0, 0, target.size};
            vkCmdCopyBuffer(ctx.cmd, staged->buffer(), target.buffer, 1, &region);
            return;
        }
        VkBufferImageCopy region{};
        region.imageSubresource = {detail::copyAspectOf(target.desc->format), 0, 0, target.usage->range.layerCount};
        region.imageExtent = {target.extent.width, target.extent.height, 1};
        vkCmdCopyBufferToImage(ctx.cmd, staged->buffer(), target.image, target.usage->layout, 1, &region);
    }

    [[nodiscard]] bool keepsSlotHandles() const noexcept override { return false; }
};

}  // namespace

std::unique_ptr<PassImplementation> makeUploadPass(const PassDesc& desc) { return std::make_unique<UploadPass>(desc); }

}  // namespace skygraph::passes
