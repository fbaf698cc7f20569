// Pixels in host-visible memory, written by the application on any thread and copied into a
// plan's image by the graph's own UploadPass (Renderer::stageUpload), on whichever queue the
// graph puts that pass: a transfer queue copies beside the frames.
#pragma once

#include <skygraph/device.hpp>

#include <vulkan/vulkan_core.h>

#include <atomic>
#include <cstddef>
#include <memory>
#include <span>

namespace skygraph {

/// A VkBuffer in host-visible, host-coherent memory, mapped for its whole life. Create it with
/// StagingBuffer::create(), which may be called on any thread; the Device must outlive it. Its
/// bytes may be written from any thread while no frame that copies them may run: hand it to
/// Renderer::stageUpload() through a std::shared_ptr, and the renderer holds that pointer
/// until the frame has copied it. The renderer lets go on its own thread, so a writer on
/// another thread learns that the buffer is its again from reusable(), not from use_count()
/// alone, which is a relaxed read that orders nothing. Not copyable.
class StagingBuffer {
public:
    /// `bytes` (> 0) of host-visible memory on `device`. Throws ExecutorError for 0 bytes, or
    /// when no memory type fits or the allocation fails.
    [[nodiscard]] static std::shared_ptr<StagingBuffer> create(Device& device, VkDeviceSize bytes);
    ~StagingBuffer();
    StagingBuffer(const StagingBuffer&) = delete;
    StagingBuffer& operator=(const StagingBuffer&) = delete;

    /// The mapped bytes, valid for the buffer's life.
    [[nodiscard]] std::span<std::byte> bytes() noexcept;
    [[nodiscard]] std::span<const std::byte> bytes() const noexcept;
    [[nodiscard]] VkDeviceSize size() const noexcept;
    /// The buffer, with TRANSFER_SRC usage, for recording code that copies from it. Owned by
    /// this StagingBuffer and valid for its life; do not destroy it.
    [[nodiscard]] VkBuffer buffer() const noexcept;

    /// Whether `buffer`, the caller's only pointer to it, is the caller's again: no renderer
    /// holds it (use_count() is 1), so every frame that copied it has finished. True comes
    /// with an acquire fence after that read, which orders the renderer's letting go (a
    /// release) before the caller's next writes to bytes(): call it on the thread that writes
    /// next, and write only after it returned true. A copy of the pointer kept elsewhere
    /// counts as a holder.
    [[nodiscard]] static bool reusable(const std::shared_ptr<StagingBuffer>& buffer) noexcept {
        if (!buffer || buffer.use_count() != 1) return false;
        std::atomic_thread_fence(std::memory_order_acquire);
        return true;
    }

private:
    friend class Renderer;  // refuses a buffer of another device
    [[nodiscard]] VkDevice device() const noexcept;
    struct Impl;
    explicit StagingBuffer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace skygraph
