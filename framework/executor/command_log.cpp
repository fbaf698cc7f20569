#include "command_log.hpp"

#include <skygraph/plan_format.hpp>

#include <cstdio>
#include <string_view>

namespace skygraph::detail {
namespace {

std::string shortNames(const std::vector<std::string>& names, std::string_view prefix) {
    if (names.empty()) return "NONE";
    std::string out;
    for (std::string n : names) {
        if (n.starts_with(prefix)) n.erase(0, prefix.size());
        if (n.ends_with("_BIT")) n.resize(n.size() - 4);
        out += (out.empty() ? "" : "|") + n;
    }
    return out;
}

std::string shortLayout(VkImageLayout l) {
    std::string n = layoutName(l);
    return n.starts_with("VK_IMAGE_LAYOUT_") ? n.substr(16) : n;
}

std::string rangeText(const VkImageSubresourceRange& r) {
    return "mips[" + std::to_string(r.baseMipLevel) + "+" + std::to_string(r.levelCount) + "] layers[" +
           std::to_string(r.baseArrayLayer) + "+" + std::to_string(r.layerCount) + "]";
}

}  // namespace

template <typename Handle>
std::string CommandLog::name(Handle h) const {
    const auto key = reinterpret_cast<uint64_t>(h);
    if (auto it = names_.find(key); it != names_.end()) return it->second;
    char hex[24];
    std::snprintf(hex, sizeof hex, "0x%llx", static_cast<unsigned long long>(key));
    return hex;
}

std::string CommandLog::barrierLine(const char* kind, const std::string& resource, VkPipelineStageFlags2 srcStages,
                                    VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStages, VkAccessFlags2 dstAccess,
                                    const VkImageSubresourceRange* range, VkImageLayout oldLayout,
                                    VkImageLayout newLayout) {
    std::string line = std::string(kind) + " " + resource;
    if (range) line += " " + rangeText(*range);
    line += " " + shortNames(stageMaskNames(srcStages), "VK_PIPELINE_STAGE_2_") + "/" +
            shortNames(accessMaskNames(srcAccess), "VK_ACCESS_2_") + " -> " +
            shortNames(stageMaskNames(dstStages), "VK_PIPELINE_STAGE_2_") + "/" +
            shortNames(accessMaskNames(dstAccess), "VK_ACCESS_2_");
    if (range) line += " " + shortLayout(oldLayout) + " -> " + shortLayout(newLayout);
    return line;
}

void CommandLog::barriers(const BarrierBatch& batch) {
    for (const VkMemoryBarrier2& b : batch.memory())
        lines_.push_back("barrier " + barrierLine("memory", "-", b.srcStageMask, b.srcAccessMask, b.dstStageMask,
                                                  b.dstAccessMask, nullptr, {}, {}));
    for (const VkBufferMemoryBarrier2& b : batch.buffers())
        lines_.push_back("barrier " + barrierLine("buffer", name(b.buffer), b.srcStageMask, b.srcAccessMask,
                                                  b.dstStageMask, b.dstAccessMask, nullptr, {}, {}));
    for (const VkImageMemoryBarrier2& b : batch.images())
        lines_.push_back("barrier " + barrierLine("image", name(b.image), b.srcStageMask, b.srcAccessMask,
                                                  b.dstStageMask, b.dstAccessMask, &b.subresourceRange, b.oldLayout,
                                                  b.newLayout));
}

void CommandLog::beginLabel(const char* n) { lines_.push_back(std::string("begin label ") + n); }
void CommandLog::endLabel() { lines_.emplace_back("end label"); }
void CommandLog::resetQueries(VkQueryPool, uint32_t count) { lines_.push_back("reset " + std::to_string(count) + " queries"); }
void CommandLog::timestamp(VkPipelineStageFlags2 stage, VkQueryPool, uint32_t query) {
    lines_.push_back("timestamp " + std::to_string(query) + " at " +
                     shortNames(stageMaskNames(stage), "VK_PIPELINE_STAGE_2_"));
}

void CommandLog::clearColor(VkImage image, VkImageLayout layout, const VkClearColorValue&,
                            const VkImageSubresourceRange& range) {
    lines_.push_back("clear color " + name(image) + " " + rangeText(range) + " in " + shortLayout(layout));
}

void CommandLog::clearDepthStencil(VkImage image, VkImageLayout layout, const VkClearDepthStencilValue&,
                                   const VkImageSubresourceRange& range) {
    lines_.push_back("clear depth " + name(image) + " " + rangeText(range) + " in " + shortLayout(layout));
}

void CommandLog::copyBufferToImage(VkBuffer from, VkImage to, VkImageLayout layout,
                                   std::span<const VkBufferImageCopy> regions) {
    lines_.push_back("copy " + name(from) + " -> " + name(to) + " in " + shortLayout(layout) + ", " +
                     std::to_string(regions.size()) + " region(s)");
}

void CommandLog::copyImageToBuffer(VkImage from, VkImageLayout layout, VkBuffer to,
                                   std::span<const VkBufferImageCopy> regions) {
    lines_.push_back("copy " + name(from) + " in " + shortLayout(layout) + " -> " + name(to) + ", " +
                     std::to_string(regions.size()) + " region(s)");
}

void CommandLog::copyBuffer(VkBuffer from, VkBuffer to, std::span<const VkBufferCopy> regions) {
    lines_.push_back("copy " + name(from) + " -> " + name(to) + ", " + std::to_string(regions.size()) + " region(s)");
}

void CommandLog::beginRenderPass(const VkRenderPassBeginInfo& info) {
    lines_.push_back("begin render pass " + std::to_string(info.renderArea.extent.width) + "x" +
                     std::to_string(info.renderArea.extent.height));
}
void CommandLog::endRenderPass() { lines_.emplace_back("end render pass"); }
void CommandLog::bindPipeline(VkPipelineBindPoint point, VkPipeline) {
    lines_.push_back(point == VK_PIPELINE_BIND_POINT_COMPUTE ? "bind compute pipeline" : "bind graphics pipeline");
}
void CommandLog::pushDescriptors(VkPipelineBindPoint, VkPipelineLayout, std::span<const VkWriteDescriptorSet> writes) {
    lines_.push_back("push " + std::to_string(writes.size()) + " descriptor(s)");
}
void CommandLog::pushConstants(VkPipelineLayout, VkShaderStageFlags, const uint32_t (&)[4]) {
    lines_.emplace_back("push constants");
}
void CommandLog::bindVertexBuffers(std::span<const VkBuffer> buffers, std::span<const VkDeviceSize>) {
    lines_.push_back("bind " + std::to_string(buffers.size()) + " vertex buffer(s)");
}
void CommandLog::bindIndexBuffer(VkBuffer buffer) { lines_.push_back("bind index buffer " + name(buffer)); }
void CommandLog::dispatch(uint32_t x, uint32_t y) {
    lines_.push_back("dispatch " + std::to_string(x) + "x" + std::to_string(y));
}
void CommandLog::draw(uint32_t vertices, uint32_t instances) {
    lines_.push_back("draw " + std::to_string(vertices) + " x" + std::to_string(instances));
}
void CommandLog::drawIndexed(uint32_t indices, uint32_t instances) {
    lines_.push_back("draw indexed " + std::to_string(indices) + " x" + std::to_string(instances));
}
void CommandLog::drawIndirect(VkBuffer buffer, bool indexed) {
    lines_.push_back(std::string(indexed ? "draw indexed indirect " : "draw indirect ") + name(buffer));
}
void CommandLog::recordPass(PassImplementation&, RecordContext& context) {
    lines_.push_back("record pass " + std::string(context.pass ? context.pass->name : "?"));
}

}  // namespace skygraph::detail
