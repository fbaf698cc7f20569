// Staging buffers of one size, reused once nothing else holds them: what a thread that stages
// pixels again and again (a bake's start(), a sequence's decoding) keeps, so that staging
// allocates nothing after the first few and frees no host-visible memory where a bake lets go.
#pragma once

#include <skygraph/device.hpp>
#include <skygraph/staging_buffer.hpp>

#include <algorithm>
#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace skygraph::app {

/// The bytes of a width x height RGBA32F image (HdrImage's pixels): what an equirect stages.
[[nodiscard]] inline VkDeviceSize rgba32fBytes(uint32_t width, uint32_t height) noexcept {
    return VkDeviceSize(width) * height * 4 * sizeof(float);
}

/// Owns its buffers; `device` must outlive it and them. Use from one thread: only that thread
/// copies the pool's pointers, so a buffer the pool alone holds (use_count() 1) is one that
/// every frame and bake has let go of, a bake only once its copy had run. Not copyable.
class StagingPool {
public:
    StagingPool(Device& device, VkDeviceSize bytes) : device_(device), bytes_(bytes) {}
    StagingPool(const StagingPool&) = delete;
    StagingPool& operator=(const StagingPool&) = delete;

    /// `pixels` copied into a free buffer of the pool, or a new one. Throws ExecutorError for
    /// pixels of another size than the pool's, or when a new buffer cannot be made.
    [[nodiscard]] std::shared_ptr<const StagingBuffer> stage(std::span<const float> pixels) {
        if (pixels.size_bytes() != bytes_)
            throw ExecutorError("staging " + std::to_string(pixels.size_bytes()) + " bytes in a pool of " +
                                std::to_string(bytes_) + "-byte buffers");
        auto free = std::find_if(buffers_.begin(), buffers_.end(), &StagingBuffer::reusable);
        if (free == buffers_.end()) free = buffers_.insert(buffers_.end(), StagingBuffer::create(device_, bytes_));
        std::memcpy((*free)->bytes().data(), pixels.data(), bytes_);
        return *free;
    }
    /// Each buffer's size, which every stage() must fill.
    [[nodiscard]] VkDeviceSize bufferBytes() const noexcept { return bytes_; }
    /// The buffers made so far.
    [[nodiscard]] size_t size() const noexcept { return buffers_.size(); }

private:
    Device& device_;
    VkDeviceSize bytes_;
    std::vector<std::shared_ptr<StagingBuffer>> buffers_;
};

}  // namespace skygraph::app
