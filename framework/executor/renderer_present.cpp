// Renderer::Impl: frames into presentable images, a Swapchain's (acquire, render, present,
// re-create) or the application's own.
#include "renderer_impl.hpp"
#include "swapchain.hpp"

#include <optional>

namespace skygraph {

using namespace detail;

void Renderer::Impl::describePresent(PlanState& s) const {
    s.presentResource = -1;
    s.presentImages = 1;
    s.presentsWithoutImages = -1;
    if (!present) {
        const int32_t index = presentResource(s.plan);
        if (index >= 0 && s.plan.resources()[size_t(index)].finalLayout == VK_IMAGE_LAYOUT_PRESENT_SRC_KHR)
            s.presentsWithoutImages = index;
        return;
    }
    const PresentImages& p = present->images;
    if (presentSwapchainDestroyed())
        throw ExecutorError("the swapchain this renderer presents into was destroyed: its plan state is built again "
                            "only by rendering into another one, renderFrame(Swapchain&)");
    const int32_t index = presentResource(s.plan);
    if (index < 0)
        throw ExecutorError("graph '" + s.graph.name + "' presents nothing (no resource has `final: Present`), "
                            "but the renderer renders into present images");
    const PlannedResource& res = s.plan.resources()[size_t(index)];
    const ResourceDesc& desc = s.graph.resources.at(res.decl);
    const std::string what = "present resource '" + desc.name + "': ";
    if (res.finalLayout != VK_IMAGE_LAYOUT_PRESENT_SRC_KHR)
        throw ExecutorError(what + "the plan was compiled with CompileOptions::presentReplacement, for rendering "
                                   "headless; compile it to present");
    // Awaiting a re-created swapchain: its images will have another format and usage, but the
    // window's extent.
    const bool checksImages = !present->awaitingImages;
    // What the declaration alone decides is refused at it (UnsupportedResourceError): the
    // application names the graph file's line to change.
    const auto refuse = [&](const std::string& problem) { throw UnsupportedResourceError(what + problem, desc.name); };
    if (checksImages && p.format != desc.format.format)
        refuse("its format is " + std::string(desc.format.name) + ", the present images' is " + formatName(p.format));
    const auto ext = desc.extent.resolve(s.outputWidth(), s.outputHeight());
    const bool otherSize = ext[0] != p.extent.width || ext[1] != p.extent.height;
    const bool followsWindow = desc.extent.relativeToOutput && desc.extent.divisor == 1;
    const bool severalSubresources = desc.layers > 1 || desc.mipCount(s.outputWidth(), s.outputHeight()) > 1;
    if (otherSize || severalSubresources) {
        const std::string problem = "the plan's is " + std::to_string(ext[0]) + "x" + std::to_string(ext[1]) +
                                    ", the present images are " + vk::extentText(p.extent) + " (one mip, one layer)";
        // An image that follows the window was compiled at another output size: the caller's doing.
        if (followsWindow && !severalSubresources) throw ExecutorError(what + problem);
        refuse(problem + (otherSize && !followsWindow
                              ? "; a presented image follows the window: give it \"extent\": \"output\""
                              : ""));
    }
    const VkImageUsageFlags need = planImageUsage(s.plan, uint32_t(index));
    if (checksImages && (need & ~p.usage) != 0)
        refuse("the plan needs image usage " + vk::imageUsageText(need) + ", the present images were created with " +
               vk::imageUsageText(p.usage));
    if (!checksImages) return;  // a stand-in takes the images' place
    s.presentResource = index;
    s.presentImages = static_cast<uint32_t>(p.images.size());
}

bool Renderer::Impl::needsOtherSwapchainImages(const CompiledGraph& compiled) const {
    if (!present || !present->swapchain) return false;
    const Plan& plan = compiled.plan();
    const int32_t index = presentResource(plan);
    // A plan that presents nothing, or was compiled headless, is refused by describePresent.
    if (index < 0 || plan.resources()[size_t(index)].finalLayout != VK_IMAGE_LAYOUT_PRESENT_SRC_KHR) return false;
    // The binding's swapchain may be gone (a renderer outlives it): the device's surface answers.
    return needsOtherImages(presentRequirements(compiled), present->images.format, present->images.usage);
}

bool Renderer::Impl::needsOtherImages(const PresentRequirements& need, VkFormat format, VkImageUsageFlags usage) const {
    if (need.format == format && (need.usage & ~usage) == 0) return false;
    (void)surfaceSupportFor(dev, need, 0);
    return true;
}

bool Renderer::Impl::presents(uint32_t index) const {
    return present && int32_t(index) == presentResource(state->plan);
}

void Renderer::Impl::bindPresentImages(PresentImages images, const SwapchainAccess::Impl* swapchain) {
    if (images.images.empty()) throw ExecutorError("setPresentImages: no images");
    if (images.extent.width == 0 || images.extent.height == 0) throw ExecutorError("setPresentImages: 0x0 images");
    for (size_t i = 0; i < images.images.size(); ++i)
        if (images.images[i] == VK_NULL_HANDLE)
            throw ExecutorError("setPresentImages: image " + std::to_string(i) + " is VK_NULL_HANDLE");
    std::optional<CompiledGraph> next = atPresentExtent(state->compiled, images.extent);
    std::optional<PresentBinding> previous = std::move(present);
    present = PresentBinding{std::move(images), swapchain, swapchain ? swapchain->imagesId : 0,
                             swapchain ? swapchain->lifetime : nullptr};
    try {
        waitIdle();
        auto built = build(std::move(*next));  // throws: the old plan and binding stay
        replaceState(std::move(built));
    } catch (...) {
        present = std::move(previous);
        throw;
    }
}

uint32_t Renderer::Impl::waitForFrameSlot() {
    const auto slot = static_cast<uint32_t>(frameIndex % frames.size());
    waitSlot(frames[slot]);
    return slot;
}

void Renderer::Impl::renderFrame(const PresentTarget& target) {
    if (!present) throw ExecutorError("renderFrame(PresentTarget): no present images (setPresentImages)");
    if (present->awaitingImages)
        throw ExecutorError("renderFrame(PresentTarget): the plan presents another format or usage than the "
                            "swapchain's images have; renderFrame(Swapchain&) re-creates them");
    if (target.image >= state->presentImages)
        throw ExecutorError("renderFrame(PresentTarget): image " + std::to_string(target.image) + " of " +
                            std::to_string(state->presentImages));
    if (!target.acquired || !target.renderComplete)
        throw ExecutorError("renderFrame(PresentTarget): both semaphores are needed");
    const uint32_t slot = waitForFrameSlot();
    submitFrame(slot, slot * state->presentImages + target.image, &target);
}

PresentStatus Renderer::Impl::renderFrame(Swapchain& swapchain) {
    SwapchainAccess::Impl& sc = SwapchainAccess::impl(swapchain);
    if (&sc.device != &device) throw ExecutorError("renderFrame: the swapchain was made for another device");
    // An out-of-date acquire re-creates and tries again; the surface changing size faster
    // than that is not presented this time.
    for (int attempt = 0; attempt < 3; ++attempt) {
        const PresentRequirements need = presentRequirements(state->compiled);
        if (sc.needsRecreate(need)) {
            // Nothing may use the old images: every frame and every present is done.
            waitIdle();
            vk::check(vkQueueWaitIdle(dev.queue), "vkQueueWaitIdle");
            sc.recreate(need);
        }
        if (sc.paused()) return PresentStatus::Paused;
        if (!present || present->imagesId != sc.imagesId || present->awaitingImages) {
            bindPresentImages(PresentImages{sc.images, sc.requirements.format, sc.extent, sc.requirements.usage}, &sc);
            sc.releaseRetired();  // no view of its images is left
        }
        const uint32_t slot = waitForFrameSlot();
        detail::FrameSlot& f = frames[slot];
        if (!f.acquire) f.acquire = vk::makeBinarySemaphore(vkd);
        const VkSemaphore acquired = f.acquire.get();
        uint32_t image = 0;
        if (sc.acquire(acquired, image) == VK_ERROR_OUT_OF_DATE_KHR) continue;
        const PresentTarget target{image, acquired, sc.renderComplete.at(image).get()};
        try {
            submitFrame(slot, slot * state->presentImages + image, &target);
        } catch (...) {
            // The image stays acquired, and only a present or the swapchain's end gives it
            // back: the next frame re-creates the swapchain.
            sc.stale = true;
            throw;
        }
        sc.present(image);
        return PresentStatus::Presented;
    }
    return PresentStatus::Paused;
}

}  // namespace skygraph
