// Filling sampled images that passes own (RecordContext::fillSampledImages) with the
// compiler's steps and barriers, as a setup plan is recorded, but into the frame's command
// buffer: a model's textures are ready in the frame that first draws it.
#include "renderer_impl.hpp"

#include <skygraph/diagnostics.hpp>

#include <algorithm>

namespace skygraph::detail {

VkImageBlit downsampleRegion(VkImageAspectFlags aspect, uint32_t width, uint32_t height, const SubresourceRange& from,
                             const SubresourceRange& to) {
    const auto extent = [&](uint32_t mip) {
        return VkOffset3D{int32_t(std::max(width >> mip, 1u)), int32_t(std::max(height >> mip, 1u)), 1};
    };
    VkImageBlit region{};
    region.srcSubresource = {aspect, from.baseMip, from.baseLayer, from.layerCount};
    region.srcOffsets[1] = extent(from.baseMip);
    region.dstSubresource = {aspect, to.baseMip, to.baseLayer, to.layerCount};
    region.dstOffsets[1] = extent(to.baseMip);
    return region;
}

void recordSampledImageFills(CommandSink& sink, std::span<const SampledImageFill> fills,
                             const std::array<uint32_t, kQueueKinds>& families, const std::function<void(Plan&)>* edit) {
    if (fills.empty()) return;
    std::vector<SampledImageShape> shapes;
    for (const SampledImageFill& f : fills) {
        if (!f.image || !f.staging)
            throw ExecutorError("fillSampledImages: image '" + f.shape.name + "' has no image or no staging buffer");
        shapes.push_back(f.shape);
    }
    Plan plan;
    try {
        plan = planSampledImageUploads(shapes);
    } catch (const GraphError& e) {
        throw ExecutorError(std::string("fillSampledImages: ") + e.what());
    }
    if (edit && *edit) (*edit)(plan);
    // The plan's resources are the shapes, in order.
    const auto target = [&](uint32_t r) { return BarrierTarget{fills[r].image, VK_NULL_HANDLE, VK_IMAGE_ASPECT_COLOR_BIT}; };
    for (const PlannedPass& step : plan.passes()) {
        if (const BarrierBatch before(step.barriers, target, families); !before.empty()) sink.barriers(before);
        const PlannedUsage& u = step.usages[0];
        const SampledImageFill& f = fills[u.resource];
        if (step.type == "Downsample") {
            sink.blitImage(f.image, step.usages[1].layout, u.layout,
                           downsampleRegion(VK_IMAGE_ASPECT_COLOR_BIT, f.shape.width, f.shape.height,
                                            step.usages[1].range, u.range));
        } else {
            VkBufferImageCopy region{};
            region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            region.imageExtent = {f.shape.width, f.shape.height, 1};
            sink.copyBufferToImage(f.staging, f.image, u.layout, {&region, 1});
        }
    }
    if (const BarrierBatch after(plan.finalBarriers(), target, families); !after.empty()) sink.barriers(after);
}

}  // namespace skygraph::detail
