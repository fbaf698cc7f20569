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

std::string hexWord(uint32_t w) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%08x", w);
    return text;
}

std::string rangeText(const VkImageSubresourceRange& r) {
    return "mips[" + std::to_string(r.baseMipLevel) + "+" + std::to_string(r.levelCount) + "] layers[" +
           std::to_string(r.baseArrayLayer) + "+" + std::to_string(r.layerCount) + "]";
}

std::string ownershipText(uint32_t srcFamily, uint32_t dstFamily) {
    if (srcFamily == VK_QUEUE_FAMILY_IGNORED && dstFamily == VK_QUEUE_FAMILY_IGNORED) return "";
    const auto family = [](uint32_t f) { return f == VK_QUEUE_FAMILY_IGNORED ? std::string("ignored") : std::to_string(f); };
    return " family " + family(srcFamily) + " -> " + family(dstFamily);
}

std::string aspectText(VkImageAspectFlags aspects) {
    std::string s;
    if (aspects & VK_IMAGE_ASPECT_COLOR_BIT) s += "|COLOR";
    if (aspects & VK_IMAGE_ASPECT_DEPTH_BIT) s += "|DEPTH";
    if (aspects & VK_IMAGE_ASPECT_STENCIL_BIT) s += "|STENCIL";
    if (aspects & ~VkImageAspectFlags(VK_IMAGE_ASPECT_COLOR_BIT | VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT))
        s += "|other";
    return " aspect " + (s.empty() ? std::string("none") : s.substr(1));
}

std::string bytesText(VkDeviceSize offset, VkDeviceSize size) {
    return " bytes " + std::to_string(offset) + "+" + (size == VK_WHOLE_SIZE ? std::string("whole") : std::to_string(size));
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
                                                  b.dstStageMask, b.dstAccessMask, nullptr, {}, {}) +
                         bytesText(b.offset, b.size) + ownershipText(b.srcQueueFamilyIndex, b.dstQueueFamilyIndex));
    for (const VkImageMemoryBarrier2& b : batch.images())
        lines_.push_back("barrier " + barrierLine("image", name(b.image), b.srcStageMask, b.srcAccessMask,
                                                  b.dstStageMask, b.dstAccessMask, &b.subresourceRange, b.oldLayout,
                                                  b.newLayout) +
                         aspectText(b.subresourceRange.aspectMask) +
                         ownershipText(b.srcQueueFamilyIndex, b.dstQueueFamilyIndex));
}

void CommandLog::beginLabel(const char* n) { lines_.push_back(std::string("begin label ") + n); }
void CommandLog::endLabel() { lines_.emplace_back("end label"); }
void CommandLog::resetQueries(VkQueryPool, uint32_t count) { lines_.push_back("reset " + std::to_string(count) + " queries"); }
void CommandLog::timestamp(VkPipelineStageFlags2 stage, VkQueryPool, uint32_t query) {
    lines_.push_back("timestamp " + std::to_string(query) + " at " +
                     shortNames(stageMaskNames(stage), "VK_PIPELINE_STAGE_2_"));
}

void CommandLog::clearColor(VkImage image, VkImageLayout layout, const VkClearColorValue& value,
                            const VkImageSubresourceRange& range) {
    std::string words;
    for (const uint32_t w : value.uint32) words += " " + hexWord(w);
    lines_.push_back("clear color " + name(image) + " " + rangeText(range) + " in " + shortLayout(layout) + " to" +
                     words);
}

void CommandLog::clearDepthStencil(VkImage image, VkImageLayout layout, const VkClearDepthStencilValue& value,
                                   const VkImageSubresourceRange& range) {
    char text[64];
    std::snprintf(text, sizeof text, " to depth %g stencil 0x%x", static_cast<double>(value.depth), value.stencil);
    lines_.push_back("clear depth " + name(image) + " " + rangeText(range) + " in " + shortLayout(layout) + text);
}

void CommandLog::fillBuffer(VkBuffer buffer, VkDeviceSize offset, VkDeviceSize size, uint32_t word) {
    lines_.push_back("fill " + name(buffer) + " from " + std::to_string(offset) + " " +
                     (size == VK_WHOLE_SIZE ? std::string("to the end") : std::to_string(size) + " bytes") + " with " +
                     hexWord(word));
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

void CommandLog::blitImage(VkImage image, VkImageLayout fromLayout, VkImageLayout toLayout, const VkImageBlit& region) {
    lines_.push_back("blit " + name(image) + " mip " + std::to_string(region.srcSubresource.mipLevel) + " in " +
                     shortLayout(fromLayout) + " -> mip " + std::to_string(region.dstSubresource.mipLevel) + " in " +
                     shortLayout(toLayout) + ", linear");
}

void CommandLog::beginRenderPass(const VkRenderPassBeginInfo& info) {
    lines_.push_back("begin render pass " + std::to_string(info.renderArea.extent.width) + "x" +
                     std::to_string(info.renderArea.extent.height));
}
void CommandLog::endRenderPass() { lines_.emplace_back("end render pass"); }
void CommandLog::recordPass(PassImplementation& pass, RecordContext& context) {
    lines_.push_back("record pass " + std::string(context.pass ? context.pass->name : "?"));
    context.cmd = VK_NULL_HANDLE;
    pass.record(context);
}

void CommandLog::recordPassBeforeRenderPass(PassImplementation& pass, RecordContext& context) {
    lines_.push_back("record pass " + std::string(context.pass ? context.pass->name : "?") + " before its render pass");
    context.cmd = VK_NULL_HANDLE;
    pass.recordBeforeRenderPass(context);
}

}  // namespace skygraph::detail
