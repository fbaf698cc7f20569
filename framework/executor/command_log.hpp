// A CommandSink that writes every command down as one line of text instead of recording it:
// a frame's commands and barriers, read by tests without a device. Handles are printed by the
// names given to them (e.g. "hdr_color#1" for frame slot 1's copy), or in hex.
#pragma once

#include "command_sink.hpp"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace skygraph::detail {

class CommandLog final : public CommandSink {
public:
    /// `names`: what to call each handle (VkImage, VkBuffer, ... as an integer).
    explicit CommandLog(std::map<uint64_t, std::string> names = {}) : names_(std::move(names)) {}

    /// Every command so far, one per line, in order. Barriers are "barrier " followed by
    /// barrierLine()'s text, then " bytes OFFSET+SIZE" for a buffer and " aspect COLOR|..." for
    /// an image, and " family S -> D" for an ownership transfer, one line per barrier of a
    /// batch. Clears and fills end in the value they write: colours as four 32-bit words in
    /// hex, "depth D stencil S", a fill's word.
    [[nodiscard]] const std::vector<std::string>& lines() const noexcept { return lines_; }
    /// How a barrier reads in the log, e.g. "image out mips[0+1] layers[0+1]
    /// COLOR_ATTACHMENT_OUTPUT/COLOR_ATTACHMENT_WRITE -> TRANSFER/TRANSFER_READ
    /// COLOR_ATTACHMENT_OPTIMAL -> TRANSFER_SRC_OPTIMAL", with `resource` as its handle's name.
    [[nodiscard]] static std::string barrierLine(const char* kind, const std::string& resource, VkPipelineStageFlags2 srcStages,
                                                 VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStages,
                                                 VkAccessFlags2 dstAccess, const VkImageSubresourceRange* range,
                                                 VkImageLayout oldLayout, VkImageLayout newLayout);

    void barriers(const BarrierBatch& batch) override;
    void beginLabel(const char* name) override;
    void endLabel() override;
    void resetQueries(VkQueryPool pool, uint32_t count) override;
    void timestamp(VkPipelineStageFlags2 stage, VkQueryPool pool, uint32_t query) override;
    void clearColor(VkImage image, VkImageLayout layout, const VkClearColorValue& value,
                    const VkImageSubresourceRange& range) override;
    void clearDepthStencil(VkImage image, VkImageLayout layout, const VkClearDepthStencilValue& value,
                           const VkImageSubresourceRange& range) override;
    void copyBufferToImage(VkBuffer from, VkImage to, VkImageLayout layout,
                           std::span<const VkBufferImageCopy> regions) override;
    void copyImageToBuffer(VkImage from, VkImageLayout layout, VkBuffer to,
                           std::span<const VkBufferImageCopy> regions) override;
    void copyBuffer(VkBuffer from, VkBuffer to, std::span<const VkBufferCopy> regions) override;
    void blitImage(VkImage image, VkImageLayout fromLayout, VkImageLayout toLayout, const VkImageBlit& region) override;
    void fillBuffer(VkBuffer buffer, VkDeviceSize offset, VkDeviceSize size, uint32_t word) override;
    void beginRenderPass(const VkRenderPassBeginInfo& info) override;
    void endRenderPass() override;
    /// Writes "record pass NAME" (NAME "before its render pass"), then lets `pass` record
    /// with no command buffer: only stand-ins for recording code, which record through the
    /// context (recordInPassBarriers) and note(), can be logged.
    void recordPass(PassImplementation& pass, RecordContext& context) override;
    void recordPassBeforeRenderPass(PassImplementation& pass, RecordContext& context) override;

    /// Writes `line` down as it is: what a stand-in pass says it records.
    void note(std::string line) { lines_.push_back(std::move(line)); }

private:
    template <typename Handle>
    std::string name(Handle h) const;
    std::map<uint64_t, std::string> names_;
    std::vector<std::string> lines_;
};

}  // namespace skygraph::detail
