#include "own_swapchain.hpp"

#include <algorithm>
#include <string>

namespace window_example {
namespace {

using skygraph::ExecutorError;

void check(VkResult result, const char* what) {
    if (result != VK_SUCCESS) throw ExecutorError(std::string(what) + " failed: VkResult " + std::to_string(result));
}

VkSemaphore newSemaphore(VkDevice device) {
    const VkSemaphoreCreateInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO, nullptr, 0};
    VkSemaphore semaphore = VK_NULL_HANDLE;
    check(vkCreateSemaphore(device, &info, nullptr, &semaphore), "vkCreateSemaphore");
    return semaphore;
}

}  // namespace

OwnSwapchain::OwnSwapchain(skygraph::Device& device, skygraph::PresentRequirements need, uint32_t framesInFlight,
                           uint32_t width, uint32_t height)
    : device_(device), need_(std::move(need)), wanted_{width, height} {
    try {
        for (uint32_t i = 0; i < framesInFlight; ++i) acquired_.push_back(newSemaphore(device_.device()));
        if (!paused()) create();
    } catch (...) {
        release();  // what was made so far
        throw;
    }
}

OwnSwapchain::~OwnSwapchain() { release(); }

void OwnSwapchain::release() noexcept {
    const VkDevice vkd = device_.device();
    vkQueueWaitIdle(device_.queue());  // the last present's wait on renderComplete_ is done
    destroyRetired();
    for (VkSemaphore s : renderComplete_) vkDestroySemaphore(vkd, s, nullptr);
    for (VkSemaphore s : acquired_) vkDestroySemaphore(vkd, s, nullptr);
    renderComplete_.clear();
    acquired_.clear();
    if (swapchain_) vkDestroySwapchainKHR(vkd, swapchain_, nullptr);
    swapchain_ = VK_NULL_HANDLE;
}

void OwnSwapchain::resize(uint32_t width, uint32_t height) {
    wanted_ = {width, height};
    stale_ = true;
}

void OwnSwapchain::create() {
    const VkPhysicalDevice physical = device_.physicalDevice();
    const VkSurfaceKHR surface = device_.surface();
    VkSurfaceCapabilitiesKHR caps;
    check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(physical, surface, &caps),
          "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
    // X11 and Win32 state the surface's size; elsewhere the window's framebuffer size is it.
    VkExtent2D extent = caps.currentExtent;
    if (extent.width == UINT32_MAX) {
        extent.width = std::clamp(wanted_.width, caps.minImageExtent.width, caps.maxImageExtent.width);
        extent.height = std::clamp(wanted_.height, caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    if (extent.width == 0 || extent.height == 0) return;  // minimized: try again on the next resize

    uint32_t count = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &count, nullptr);
    std::vector<VkSurfaceFormatKHR> formats(count);
    vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &count, formats.data());
    const bool formatOk = std::any_of(formats.begin(), formats.end(), [&](const VkSurfaceFormatKHR& f) {
        return f.format == need_.format && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
    });
    if (!formatOk)
        throw ExecutorError("the surface cannot present VkFormat " + std::to_string(need_.format) + " of '" +
                            need_.resource + "'");
    if ((need_.usage & ~caps.supportedUsageFlags) != 0)
        throw ExecutorError("the surface's images cannot have the usage '" + need_.resource + "' needs");

    VkSwapchainCreateInfoKHR info{};
    info.sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR;
    info.surface = surface;
    info.minImageCount = caps.maxImageCount == 0 ? caps.minImageCount + 1
                                                 : std::min(caps.minImageCount + 1, caps.maxImageCount);
    info.imageFormat = need_.format;
    info.imageColorSpace = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
    info.imageExtent = extent;
    info.imageArrayLayers = 1;
    info.imageUsage = need_.usage;  // every usage the plan's passes make of the Present resource
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    for (uint32_t bit = 1; bit != 0 && !(caps.supportedCompositeAlpha & info.compositeAlpha); bit <<= 1)
        info.compositeAlpha = VkCompositeAlphaFlagBitsKHR(bit);
    info.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // always supported
    info.clipped = VK_TRUE;
    info.oldSwapchain = swapchain_;
    VkSwapchainKHR created = VK_NULL_HANDLE;
    check(vkCreateSwapchainKHR(device_.device(), &info, nullptr, &created), "vkCreateSwapchainKHR");

    // The old swapchain and its semaphores stay until the renderer has let go of its images.
    destroyRetired();
    retired_ = swapchain_;
    retiredSemaphores_ = std::move(renderComplete_);
    renderComplete_.clear();
    swapchain_ = created;
    vkGetSwapchainImagesKHR(device_.device(), swapchain_, &count, nullptr);
    images_.resize(count);
    vkGetSwapchainImagesKHR(device_.device(), swapchain_, &count, images_.data());
    for (uint32_t i = 0; i < count; ++i) renderComplete_.push_back(newSemaphore(device_.device()));
    extent_ = extent;
    wanted_ = extent;
    stale_ = false;
    ++generation_;
}

void OwnSwapchain::destroyRetired() noexcept {
    for (VkSemaphore s : retiredSemaphores_) vkDestroySemaphore(device_.device(), s, nullptr);
    retiredSemaphores_.clear();
    if (retired_) vkDestroySwapchainKHR(device_.device(), retired_, nullptr);
    retired_ = VK_NULL_HANDLE;
}

bool OwnSwapchain::renderFrame(skygraph::Renderer& renderer) {
    const VkDevice vkd = device_.device();
    if (paused()) return false;
    if (stale_ || !swapchain_) {
        // Nothing may use the old images or semaphores any more: every frame and present is done.
        renderer.waitIdle();
        check(vkQueueWaitIdle(device_.queue()), "vkQueueWaitIdle");
        create();
        if (!swapchain_ || stale_) return false;  // the surface has no size yet
    }
    if (bound_ != &renderer || boundGeneration_ != generation_) {
        // The renderer renders into these images from now on (recompiling at their extent).
        renderer.setPresentImages({images_, need_.format, extent_, need_.usage});
        bound_ = &renderer;
        boundGeneration_ = generation_;
        destroyRetired();  // the renderer has no view of the old images left
    }

    // The slot's previous frame is done, so the semaphore it waited for can be signalled again.
    const uint32_t slot = renderer.waitForFrameSlot();
    const VkSemaphore acquired = acquired_.at(slot);
    uint32_t image = 0;
    VkResult result = vkAcquireNextImageKHR(vkd, swapchain_, UINT64_MAX, acquired, VK_NULL_HANDLE, &image);
    if (result == VK_ERROR_OUT_OF_DATE_KHR) {  // nothing acquired, the semaphore stays unsignalled
        stale_ = true;
        return false;
    }
    if (result == VK_SUBOPTIMAL_KHR) stale_ = true;  // acquired all the same: render and present it
    else check(result, "vkAcquireNextImageKHR");

    // Waits for `acquired` where the plan first uses the image, leaves it in PRESENT_SRC_KHR
    // and signals renderComplete_[image].
    try {
        renderer.renderFrame(skygraph::PresentTarget{image, acquired, renderComplete_[image]});
    } catch (...) {
        // Nothing signals renderComplete_[image], so the image must not be presented: it stays
        // acquired until the next call re-creates the swapchain and hands the renderer the new
        // images.
        stale_ = true;
        throw;
    }

    VkPresentInfoKHR present{};
    present.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR;
    present.waitSemaphoreCount = 1;
    present.pWaitSemaphores = &renderComplete_[image];
    present.swapchainCount = 1;
    present.pSwapchains = &swapchain_;
    present.pImageIndices = &image;
    result = vkQueuePresentKHR(device_.queue(), &present);
    if (result == VK_ERROR_OUT_OF_DATE_KHR || result == VK_SUBOPTIMAL_KHR) stale_ = true;
    else check(result, "vkQueuePresentKHR");
    return true;
}

}  // namespace window_example
