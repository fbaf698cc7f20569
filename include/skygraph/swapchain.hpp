// Presenting frames: a swapchain for the Device's surface (Swapchain), or presentable images and
// semaphores of the application's own (PresentImages, PresentTarget). Either way the plan's
// Present resource (`final: Present`) is the acquired image, and a Renderer renders into it.
#pragma once

#include <skygraph/compiled_graph.hpp>
#include <skygraph/device.hpp>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace skygraph {

/// How finished frames reach the screen (VkPresentModeKHR).
enum class PresentMode : uint8_t {
    Fifo,       ///< Waits for vertical blank; always supported.
    Mailbox,    ///< Waits for vertical blank, the newest frame replacing a queued one.
    Immediate,  ///< Does not wait (may tear).
};

/// "fifo", "mailbox" or "immediate"; a static string.
[[nodiscard]] const char* presentModeName(PresentMode mode) noexcept;

/// What a plan needs of the images it presents: those of its Present resource, the one with
/// `final: Present` (PlannedResource::copies == ResourceCopies::PerFramePresented). A plain
/// value.
struct PresentRequirements {
    std::string resource;                   ///< Its name in the graph.
    VkFormat format = VK_FORMAT_UNDEFINED;  ///< Its format: the swapchain's must be the same.
    /// The image usages its passes make of it (e.g. COLOR_ATTACHMENT, or STORAGE for a compute
    /// pass that writes it).
    VkImageUsageFlags usage = 0;
    VkExtent2D extent{0, 0};  ///< Its extent in the plan.
};

/// The Present resource of `compiled`'s plan and what it needs. Throws ExecutorError when the
/// plan presents no image, presents several, or was compiled with
/// CompileOptions::presentReplacement (the resource then ends in another state).
[[nodiscard]] PresentRequirements presentRequirements(const CompiledGraph& compiled);

/// Presentable images of the application's own (e.g. its VkSwapchainKHR's), for
/// Renderer::setPresentImages. A plain value; the images are borrowed.
struct PresentImages {
    std::vector<VkImage> images;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{0, 0};
    VkImageUsageFlags usage = 0;  ///< What they were created with.
};

/// One frame's image of the PresentImages and its two semaphores, for
/// Renderer::renderFrame(const PresentTarget&). The handles are the application's.
struct PresentTarget {
    uint32_t image = 0;  ///< Index into PresentImages::images.
    /// Signalled when the image may be written (vkAcquireNextImageKHR's semaphore); the frame
    /// waits for it at the stages of the plan's first use of the image.
    VkSemaphore acquired = VK_NULL_HANDLE;
    /// Signalled by the frame when its work is done, the image in PRESENT_SRC_KHR; what
    /// vkQueuePresentKHR waits for. One per image: it is signalled again only when the image
    /// comes back.
    VkSemaphore renderComplete = VK_NULL_HANDLE;
};

struct SwapchainOptions {
    /// The window's size in pixels (its framebuffer size). Where the surface states its size
    /// (X11, Win32), the swapchain takes the surface's. 0x0 (a minimized window) pauses it.
    uint32_t width = 0;
    uint32_t height = 0;
    /// Falls back to Fifo, with a warning in the log, when the surface lacks it.
    PresentMode presentMode = PresentMode::Fifo;
    /// Usages the images get besides the plan's: VK_IMAGE_USAGE_TRANSFER_SRC_BIT lets a plan
    /// compiled with the presented image in CompileOptions::readbacks (a screenshot) run on
    /// these images without re-creating them. Those the surface does not allow, or the device
    /// cannot give images of the plan's format, are left out (with a warning in the log).
    VkImageUsageFlags extraUsage = 0;
};

/// A VkSwapchainKHR for the Device's surface (DeviceOptions::presentation), its images and a
/// render-complete semaphore per image; a Renderer drives it with renderFrame(Swapchain&), which
/// re-creates it when it is out of date, suboptimal or resized. The acquire semaphores are not its
/// own: each renderer has one per frame slot. Owns every handle it creates; borrows the Device,
/// which must outlive it. A Renderer does not keep the Swapchain itself (RendererOptions::presentTo
/// and renderFrame() borrow it for the call), but one that has rendered into it, or was bound to it
/// by presentTo, keeps views of its images until it renders into another swapchain or is destroyed.
/// Either may be destroyed first: destroying the swapchain waits for the Device's queue, and so for
/// every frame into it. After that, until the renderer renders into another swapchain (or is given
/// images by setPresentImages()), rebuilding its plan state in any other way (setGraph(),
/// reloadShaders(), a HotReloader's poll()) would build on the destroyed images: it throws
/// ExecutorError and keeps the plan. So, to replace one (for another present mode, say): destroy
/// it, create the next and pass that to the renderer's next renderFrame(). Not copyable or
/// movable. Used one thread at a time together with the Device and every renderer made with it
/// (Device's comment says why).
class Swapchain {
public:
    /// A swapchain for `device`'s surface, with images for `compiled`'s Present resource: the
    /// same format and every usage its passes need (presentRequirements). The caller owns the
    /// result. Throws ExecutorError when the device has no surface, or the surface cannot give
    /// that format or those usages (naming what it can give).
    static std::unique_ptr<Swapchain> create(Device& device, const CompiledGraph& compiled,
                                             const SwapchainOptions& options);
    /// Waits for the device's queue to be idle (other renderers' work on it included), then
    /// destroys what it owns.
    ~Swapchain();
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;

    /// The window's new size (its framebuffer size callback, say): the next renderFrame
    /// re-creates the swapchain and recompiles the plan at it; 0x0 pauses until a real size.
    void resize(uint32_t width, uint32_t height);
    /// True while the window has no size: renderFrame renders nothing then.
    [[nodiscard]] bool paused() const noexcept;

    /// Owned by this Swapchain; valid until it is re-created (see generation()).
    /// VK_NULL_HANDLE after a re-creation failed, until the next frame's succeeds.
    [[nodiscard]] VkSwapchainKHR handle() const noexcept;
    /// The images of the current swapchain; the span is valid until it is re-created.
    [[nodiscard]] std::span<const VkImage> images() const noexcept;
    [[nodiscard]] VkFormat format() const noexcept;
    /// The extent of the current images (0x0 while paused before the first creation).
    [[nodiscard]] VkExtent2D extent() const noexcept;
    /// The present mode in use: the one asked for, or Fifo when the surface lacks it.
    [[nodiscard]] PresentMode presentMode() const noexcept;
    /// Counts creations: 1 after create(), one more for each re-creation.
    [[nodiscard]] uint64_t generation() const noexcept;

private:
    struct Impl;
    friend struct SwapchainAccess;  // the implementation's own access; not part of the API
    explicit Swapchain(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace skygraph
