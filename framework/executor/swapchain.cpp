// The swapchain for the Device's surface: creation for a plan's Present resource, re-creation,
// acquire and present; and where the present semaphores' stages come from.
#include "swapchain.hpp"

#include "renderer_impl.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>

namespace skygraph {

using namespace detail;

namespace detail {

namespace {
const Presentation& presentationOf(const Plan& plan, uint32_t resource) {
    for (const Presentation& p : plan.presentations())
        if (p.resource == resource) return p;
    throw ExecutorError("the plan does not present resource " + std::to_string(resource) +
                        " (it was compiled to read it back instead)");
}
}  // namespace

VkPipelineStageFlags2 acquireWaitStages(const Plan& plan, uint32_t resource) {
    return presentationOf(plan, resource).acquireWaitStages;
}

VkPipelineStageFlags2 presentSignalStages(const Plan& plan, uint32_t resource) {
    return presentationOf(plan, resource).renderCompleteStages;
}

int32_t presentResource(const Plan& plan) {
    int32_t found = -1;
    for (size_t i = 0; i < plan.resources().size(); ++i) {
        if (plan.resources()[i].copies != ResourceCopies::PerFramePresented) continue;
        if (found >= 0)
            throw ExecutorError("the plan presents two images, '" + std::string(plan.resources()[size_t(found)].name) +
                                "' and '" + std::string(plan.resources()[i].name) + "'; a frame presents one");
        found = int32_t(i);
    }
    return found;
}

}  // namespace detail

namespace {

VkPresentModeKHR vulkanMode(PresentMode m) {
    switch (m) {
        case PresentMode::Fifo: return VK_PRESENT_MODE_FIFO_KHR;
        case PresentMode::Mailbox: return VK_PRESENT_MODE_MAILBOX_KHR;
        case PresentMode::Immediate: return VK_PRESENT_MODE_IMMEDIATE_KHR;
    }
    return VK_PRESENT_MODE_FIFO_KHR;
}

}  // namespace

const char* presentModeName(PresentMode mode) noexcept {
    switch (mode) {
        case PresentMode::Fifo: return "fifo";
        case PresentMode::Mailbox: return "mailbox";
        case PresentMode::Immediate: return "immediate";
    }
    return "fifo";
}

PresentRequirements presentRequirements(const CompiledGraph& compiled) {
    const Plan& plan = compiled.plan();
    const int32_t index = presentResource(plan);
    if (index < 0) throw ExecutorError("graph '" + compiled.graph().name + "' presents nothing: no resource has `final: Present`");
    const PlannedResource& res = plan.resources()[size_t(index)];
    const ResourceDesc& desc = compiled.graph().resources.at(res.decl);
    if (res.finalLayout != VK_IMAGE_LAYOUT_PRESENT_SRC_KHR)
        throw ExecutorError("'" + desc.name + "' is not presented: the plan was compiled with "
                            "CompileOptions::presentReplacement, for rendering headless");
    PresentRequirements r;
    r.resource = desc.name;
    r.format = desc.format.format;
    r.usage = planImageUsage(plan, uint32_t(index));
    const auto ext = desc.extent.resolve(compiled.outputWidth(), compiled.outputHeight());
    r.extent = {ext[0], ext[1]};
    return r;
}

Swapchain::Impl::Impl(Device& d, PresentRequirements r, const SwapchainOptions& o)
    : use(DeviceAccess::impl(d), DeviceUser::Swapchain), device(d), dev(DeviceAccess::impl(d)), requirements(std::move(r)), requested(o.presentMode),
      wanted{o.width, o.height}, extraUsage(o.extraUsage) {}

Swapchain::Impl::~Impl() {
    if (dev.queue) vkQueueWaitIdle(dev.queue);
}

bool Swapchain::Impl::needsRecreate(const PresentRequirements& plan) const noexcept {
    return stale || surfaceEmpty || !swapchain || plan.format != requirements.format ||
           (plan.usage & ~requirements.usage) != 0 || wanted.width != extent.width || wanted.height != extent.height;
}

namespace detail {

SurfaceSupport surfaceSupportFor(const DeviceAccess::Impl& dev, const PresentRequirements& plan,
                                 VkImageUsageFlags extraUsage) {
    const VkPhysicalDevice pd = dev.physical;
    const VkSurfaceKHR surface = dev.surface;
    VkSurfaceCapabilitiesKHR caps;
    vk::check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(pd, surface, &caps), "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
    uint32_t n = 0;
    vk::check(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, nullptr), "vkGetPhysicalDeviceSurfaceFormatsKHR");
    std::vector<VkSurfaceFormatKHR> formats(n);
    vk::check(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, formats.data()),
              "vkGetPhysicalDeviceSurfaceFormatsKHR");
    const auto format = std::find_if(formats.begin(), formats.end(), [&](const VkSurfaceFormatKHR& f) {
        return f.format == plan.format && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
    });
    if (format == formats.end()) {
        std::string have;
        for (const VkSurfaceFormatKHR& f : formats) have += (have.empty() ? "" : ", ") + formatName(f.format);
        throw UnsupportedResourceError("the surface cannot present " + formatName(plan.format) +
                                           ", the format of the plan's Present resource '" + plan.resource +
                                           "'; it presents " + (have.empty() ? "none" : have),
                                       plan.resource);
    }
    if ((plan.usage & ~caps.supportedUsageFlags) != 0)
        throw UnsupportedResourceError("the surface's images cannot be used as the plan uses '" + plan.resource +
                                           "' (image usage " + vk::imageUsageText(plan.usage) +
                                           ", the surface allows " + vk::imageUsageText(caps.supportedUsageFlags) + ")",
                                       plan.resource);
    // The images a swapchain implies must be ones the device can make (the spec's
    // VkSwapchainCreateInfoKHR imageFormat rule): a surface may list a format and a usage
    // that the format does not support together.
    const auto makes = [&](VkImageUsageFlags usage) {
        VkImageFormatProperties props;
        return vkGetPhysicalDeviceImageFormatProperties(pd, plan.format, VK_IMAGE_TYPE_2D, VK_IMAGE_TILING_OPTIMAL,
                                                        usage, 0, &props) == VK_SUCCESS;
    };
    if (!makes(plan.usage))
        throw UnsupportedResourceError("the device cannot make " + formatName(plan.format) + " images with usage " +
                                           vk::imageUsageText(plan.usage) +
                                           " for the swapchain, as the plan uses its Present resource '" +
                                           plan.resource + "'",
                                       plan.resource);
    // Extra usage the surface or the format cannot give is left out, a bit at a time (recreate
    // warns).
    VkImageUsageFlags usage = plan.usage;
    for (VkImageUsageFlags bit = 1; bit != 0 && bit <= extraUsage; bit <<= 1)
        if ((extraUsage & caps.supportedUsageFlags & bit) != 0 && makes(usage | bit)) usage |= bit;
    return {*format, usage};
}

}  // namespace detail

void Swapchain::Impl::recreate(const PresentRequirements& plan) {
    const VkPhysicalDevice pd = dev.physical;
    const VkSurfaceKHR surface = dev.surface;
    surfaceEmpty = false;
    if (wanted.width == 0 || wanted.height == 0) return;  // the window has no size: paused
    VkSurfaceCapabilitiesKHR caps;
    vk::check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(pd, surface, &caps), "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
    // The surface's size where it states one (X11, Win32); the window's otherwise (Wayland).
    VkExtent2D e = caps.currentExtent.width != UINT32_MAX ? caps.currentExtent : wanted;
    if (caps.currentExtent.width == UINT32_MAX) {
        e.width = std::clamp(e.width, caps.minImageExtent.width, caps.maxImageExtent.width);
        e.height = std::clamp(e.height, caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    if (e.width == 0 || e.height == 0) {
        surfaceEmpty = true;  // e.g. minimized on Win32: paused until the surface has a size
        return;
    }
    wanted = e;

    const SurfaceSupport support = surfaceSupportFor(dev, plan, extraUsage);
    if (const VkImageUsageFlags missing = extraUsage & ~support.usage; missing != 0)
        spdlog::warn("the swapchain's images cannot have usage {} besides the plan's",
                     vk::imageUsageText(missing));
    const VkImageUsageFlags usage = support.usage;

    uint32_t n = 0;
    vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, nullptr);
    std::vector<VkPresentModeKHR> modes(n);
    vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, modes.data());
    mode = requested;
    if (std::find(modes.begin(), modes.end(), vulkanMode(requested)) == modes.end()) {
        spdlog::warn("the surface has no present mode {}: presenting with fifo", presentModeName(requested));
        mode = PresentMode::Fifo;
    }

    VkSwapchainCreateInfoKHR ci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    ci.surface = surface;
    ci.minImageCount = caps.minImageCount + 1;
    if (caps.maxImageCount != 0) ci.minImageCount = std::min(ci.minImageCount, caps.maxImageCount);
    ci.imageFormat = support.format.format;
    ci.imageColorSpace = support.format.colorSpace;
    ci.imageExtent = e;
    ci.imageArrayLayers = 1;
    ci.imageUsage = usage;
    ci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ci.preTransform = caps.currentTransform;
    ci.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    for (uint32_t bit = 1; bit != 0 && !(caps.supportedCompositeAlpha & ci.compositeAlpha); bit <<= 1)
        ci.compositeAlpha = VkCompositeAlphaFlagBitsKHR(bit);
    ci.presentMode = vulkanMode(mode);
    ci.clipped = VK_TRUE;
    ci.oldSwapchain = swapchain.get();
    VkSwapchainKHR created;
    const VkResult made = vkCreateSwapchainKHR(dev.device, &ci, nullptr, &created);
    // The old swapchain is retired by the call even when it fails (the spec): it is never
    // acquired from or passed as oldSwapchain again, and the next frame tries again from none.
    if (swapchain) retired.push_back(std::move(swapchain));
    if (made != VK_SUCCESS) stale = true;
    vk::check(made, "vkCreateSwapchainKHR");
    swapchain = owned::Swapchain(dev.device, created);

    vkGetSwapchainImagesKHR(dev.device, created, &n, nullptr);
    images.resize(n);
    vkGetSwapchainImagesKHR(dev.device, created, &n, images.data());
    renderComplete.clear();
    for (uint32_t i = 0; i < n; ++i) renderComplete.push_back(vk::makeBinarySemaphore(dev.device));
    requirements = plan;
    requirements.usage = usage;
    extent = e;
    stale = false;
    ++generation;
    static std::atomic<uint64_t> lastImagesId{0};
    imagesId = ++lastImagesId;
    spdlog::info("swapchain: {} images of {} at {}, present mode {}", n, formatName(ci.imageFormat), vk::extentText(e),
                 presentModeName(mode));
}

VkResult Swapchain::Impl::acquire(VkSemaphore semaphore, uint32_t& image) {
    const VkResult r = vkAcquireNextImageKHR(dev.device, swapchain.get(), kWaitForever, semaphore, VK_NULL_HANDLE, &image);
    if (r == VK_SUBOPTIMAL_KHR || r == VK_ERROR_OUT_OF_DATE_KHR) {
        stale = true;
        return r;
    }
    vk::check(r, "vkAcquireNextImageKHR");
    return r;
}

void Swapchain::Impl::present(uint32_t image) {
    const VkSemaphore wait = renderComplete.at(image).get();
    const VkSwapchainKHR handle = swapchain.get();
    VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    pi.waitSemaphoreCount = 1;
    pi.pWaitSemaphores = &wait;
    pi.swapchainCount = 1;
    pi.pSwapchains = &handle;
    pi.pImageIndices = &image;
    const VkResult r = vkQueuePresentKHR(dev.queue, &pi);
    if (r == VK_SUBOPTIMAL_KHR || r == VK_ERROR_OUT_OF_DATE_KHR) {
        stale = true;
        return;
    }
    vk::check(r, "vkQueuePresentKHR");
}

Swapchain::Swapchain(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Swapchain::~Swapchain() = default;

std::unique_ptr<Swapchain> Swapchain::create(Device& device, const CompiledGraph& compiled,
                                             const SwapchainOptions& options) {
    PresentRequirements requirements = presentRequirements(compiled);
    // First: its DeviceUse refuses a finished device, whose surface is gone too.
    auto impl = std::make_unique<Impl>(device, requirements, options);
    if (!device.surface())
        throw ExecutorError("device '" + device.name() +
                            "' has no surface: create it with DeviceOptions::presentation");
    impl->recreate(requirements);
    return std::unique_ptr<Swapchain>(new Swapchain(std::move(impl)));
}

void Swapchain::resize(uint32_t width, uint32_t height) {
    impl_->wanted = {width, height};
    impl_->stale = true;
}
bool Swapchain::paused() const noexcept { return impl_->paused(); }
VkSwapchainKHR Swapchain::handle() const noexcept { return impl_->swapchain.get(); }
std::span<const VkImage> Swapchain::images() const noexcept { return impl_->images; }
VkFormat Swapchain::format() const noexcept { return impl_->requirements.format; }
VkExtent2D Swapchain::extent() const noexcept { return impl_->extent; }
PresentMode Swapchain::presentMode() const noexcept { return impl_->mode; }
uint64_t Swapchain::generation() const noexcept { return impl_->generation; }

}  // namespace skygraph
