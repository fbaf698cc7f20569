// The second way to present: the application creates and owns the VkSwapchainKHR, its images
// and its semaphores, and the renderer renders into them (Renderer::setPresentImages and
// Renderer::renderFrame(const PresentTarget&)). The first way, skygraph::Swapchain, does all
// of this itself; main.cpp uses either behind the same three calls (resize, paused,
// renderFrame).
#pragma once

#include <skygraph/executor.hpp>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <vector>

namespace window_example {

/// A swapchain for `device.surface()` with images for a plan's Present resource, one acquire
/// semaphore per frame slot and one render-complete semaphore per image. Owns all of them;
/// borrows the Device, which must outlive it. It must itself outlive every Renderer bound to
/// it (one renderFrame() was given), since such a renderer keeps views of its images:
/// destroy the renderers first, as main.cpp does. Not copyable.
class OwnSwapchain {
public:
    /// Creates it at the surface's size (`width` x `height`, the window's framebuffer size, where
    /// the surface does not state one) with `need`'s format and usage; `framesInFlight` is the
    /// renderer's RendererOptions::framesInFlight. Throws skygraph::ExecutorError when the
    /// surface cannot give them.
    OwnSwapchain(skygraph::Device& device, skygraph::PresentRequirements need, uint32_t framesInFlight,
                 uint32_t width, uint32_t height);
    /// Waits for the queue to be idle (the last present), then destroys what it owns.
    ~OwnSwapchain();
    OwnSwapchain(const OwnSwapchain&) = delete;
    OwnSwapchain& operator=(const OwnSwapchain&) = delete;

    /// The window's new framebuffer size: the next renderFrame re-creates the swapchain; 0x0
    /// (minimized) pauses it.
    void resize(uint32_t width, uint32_t height);
    [[nodiscard]] bool paused() const noexcept { return wanted_.width == 0 || wanted_.height == 0; }
    [[nodiscard]] VkExtent2D extent() const noexcept { return extent_; }

    /// One frame: re-creates the swapchain when it is stale (and hands `renderer` the new
    /// images), acquires an image, has `renderer` render into it, and presents it. Returns
    /// false, rendering nothing, while paused or when the acquire found the swapchain out of
    /// date. Throws skygraph::ExecutorError for any other Vulkan failure. What the renderer's
    /// frame throws (a pass's exception, say) passes on, the image unpresented; the next call
    /// re-creates the swapchain, which gives that image back.
    bool renderFrame(skygraph::Renderer& renderer);

private:
    void create();
    void destroyRetired() noexcept;
    void release() noexcept;

    skygraph::Device& device_;
    skygraph::PresentRequirements need_;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    std::vector<VkImage> images_;
    std::vector<VkSemaphore> acquired_;        // one per frame slot
    std::vector<VkSemaphore> renderComplete_;  // one per image
    VkExtent2D wanted_{0, 0}, extent_{0, 0};
    bool stale_ = false;                 // out of date, suboptimal or resized: re-create
    uint64_t generation_ = 0;            // counts creations
    uint64_t boundGeneration_ = 0;       // the generation the renderer renders into
    skygraph::Renderer* bound_ = nullptr;
    // The previous swapchain and its semaphores, kept until the renderer has the new images.
    VkSwapchainKHR retired_ = VK_NULL_HANDLE;
    std::vector<VkSemaphore> retiredSemaphores_;
};

}  // namespace window_example
