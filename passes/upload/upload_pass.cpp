// UploadPass: one copy from the staging buffer the application staged for this frame
// (Renderer::stageUpload) into the target. The plan's barriers put the target in
// TRANSFER_DST_OPTIMAL before it and hand it on (across queues too) after it.
#include "../builtin_passes.hpp"
#include "texel_encoding.hpp"
#include "upload_rules.hpp"

#include <skygraph/device.hpp>

#include <string>

namespace skygraph::passes {
namespace {

class UploadPass final : public PassImplementation {
public:
    explicit UploadPass(const PassDesc&) {}

    void createPipelines(const PipelineContext& ctx) override {
        // A graph built in code has not been through the loader's check.
        const BoundResource& target = ctx.resources[0];
        if (const auto problem = uploadTargetProblem(*target.desc, target.usage->range))
            throw ExecutorError("pass '" + ctx.desc->name + "': " + *problem);
    }

    void record(const RecordContext& ctx) override {
        const BoundResource& target = ctx.resources[0];
        const StagingBuffer* staged = ctx.staged ? ctx.staged(target.desc->name) : nullptr;
        const std::string what = "pass '" + ctx.desc->name + "' (UploadPass): ";
        if (!staged)
            throw ExecutorError(what + "no pixels staged for '" + target.desc->name +
                                "' this frame (Renderer::stageUpload before each frame)");
        // stageUpload() checked the size against the plan of its day; a resize or a new graph
        // since may have grown the target, and the copy would read past the buffer.
        const VkDeviceSize needed = target.image ? detail::uploadBytes(target.desc->format, target.extent.width,
                                                                       target.extent.height, target.usage->range.layerCount)
                                                 : target.size;
        if (staged->size() != needed)
            throw ExecutorError(what + "the pixels staged for '" + target.desc->name + "' are " +
                                std::to_string(staged->size()) + " bytes, and it takes " + std::to_string(needed) +
                                " now (staged before a resize or a new graph: stage again)");
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
