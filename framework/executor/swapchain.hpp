// Private to the executor: a Swapchain's state, which Renderer::renderFrame(Swapchain&) drives
// (acquire, present, re-create), and where the present semaphores' stages come from.
#pragma once

#include "device_access.hpp"
#include "vk_util.hpp"

#include <skygraph/plan.hpp>
#include <skygraph/swapchain.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace skygraph {

namespace detail {

/// The stages the frame waits for the acquire semaphore of its Present resource `resource`
/// in, as the plan states them (Presentation::acquireWaitStages). Throws ExecutorError when
/// the plan does not present it.
[[nodiscard]] VkPipelineStageFlags2 acquireWaitStages(const Plan& plan, uint32_t resource);
/// The stages the frame signals that image's render-complete semaphore in, as the plan
/// states them (Presentation::renderCompleteStages).
[[nodiscard]] VkPipelineStageFlags2 presentSignalStages(const Plan& plan, uint32_t resource);

/// What the device's surface gives `plan`'s Present resource: the surface format, and the image
/// usage a swapchain is made with (the plan's, and `extraUsage`, SwapchainOptions::extraUsage,
/// when the surface and the format allow all of it).
struct SurfaceSupport {
    VkSurfaceFormatKHR format{};
    VkImageUsageFlags usage = 0;
};
/// Throws UnsupportedResourceError naming the resource and what the surface can give when it cannot
/// present that format (in sRGB nonlinear colour space) or with that usage, or when the device
/// cannot make images of that format with that usage.
[[nodiscard]] SurfaceSupport surfaceSupportFor(const DeviceAccess::Impl& dev, const PresentRequirements& plan,
                                               VkImageUsageFlags extraUsage);

/// The Present resource of `plan` (index into its resources), or -1 when it presents nothing.
/// Throws ExecutorError when it presents several.
[[nodiscard]] int32_t presentResource(const Plan& plan);

}  // namespace detail

struct Swapchain::Impl {
    detail::DeviceUse use;
    Device& device;
    DeviceAccess::Impl& dev;
    PresentRequirements requirements;
    PresentMode requested = PresentMode::Fifo;
    PresentMode mode = PresentMode::Fifo;
    VkExtent2D wanted{0, 0};  ///< The window's size, from create() or resize().
    VkImageUsageFlags extraUsage = 0;  ///< SwapchainOptions::extraUsage.
    VkExtent2D extent{0, 0};  ///< The images'.
    owned::Swapchain swapchain;
    /// The swapchains re-creations replaced: kept until the renderer no longer holds views of
    /// their images (releaseRetired). Several when a re-creation or the bind after one failed.
    std::vector<owned::Swapchain> retired;
    std::vector<VkImage> images;
    /// One per image. The acquire semaphores are the renderers' (FrameSlot::acquire): only a
    /// renderer's own slot fence says when its last wait on one has run.
    std::vector<owned::Semaphore> renderComplete;
    uint64_t generation = 0;
    /// Unique in the process to the current images: what a renderer bound to them knows them
    /// by, since a swapchain made after this one is destroyed can have its address.
    uint64_t imagesId = 0;
    /// Expires with the swapchain: a renderer still bound to its images learns that they are
    /// gone before it would build views of them again.
    std::shared_ptr<const bool> lifetime = std::make_shared<const bool>(true);
    bool stale = false;  ///< Out of date, suboptimal or resized: re-create before the next frame.
    bool surfaceEmpty = false;  ///< The last re-creation found the surface 0x0.

    Impl(Device& d, PresentRequirements r, const SwapchainOptions& o);
    ~Impl();

    /// Whether the next frame must re-create first (stale, resized, or other requirements).
    [[nodiscard]] bool needsRecreate(const PresentRequirements& plan) const noexcept;
    /// The window or the surface has no size: nothing can be presented.
    [[nodiscard]] bool paused() const noexcept { return wanted.width == 0 || wanted.height == 0 || surfaceEmpty; }
    /// (Re-)creates the swapchain for `plan`'s Present resource at the wanted extent (the
    /// surface's current extent where it states one). Nothing submitted may still use the old
    /// images: the caller has waited. The old swapchain is retired, not destroyed.
    void recreate(const PresentRequirements& plan);
    void releaseRetired() noexcept { retired.clear(); }
    /// vkAcquireNextImageKHR with `semaphore`: VK_SUCCESS, VK_SUBOPTIMAL_KHR (marks it stale;
    /// the image is acquired) or VK_ERROR_OUT_OF_DATE_KHR (marks it stale; nothing acquired).
    /// Throws ExecutorError for any other failure.
    VkResult acquire(VkSemaphore semaphore, uint32_t& image);
    /// vkQueuePresentKHR of `image`, waiting for its render-complete semaphore; out of date or
    /// suboptimal marks it stale. Throws ExecutorError for any other failure.
    void present(uint32_t image);
};

struct SwapchainAccess {
    /// The swapchain's state type, for the executor's sources that hold or pass it.
    using Impl = Swapchain::Impl;

    /// The swapchain's state; valid while `swapchain` lives.
    [[nodiscard]] static Impl& impl(Swapchain& swapchain) noexcept { return *swapchain.impl_; }
};

}  // namespace skygraph
