// Presentation under validation + synchronization validation (QUEUE_SUBMIT included), in a GLFW
// window on the X server the test runs under (xvfb-run): frames through the executor's
// Swapchain, re-creation on resize, pausing at 0x0, the application's own swapchain images,
// and the negative controls that prove the checks can fail (the acquire wait left out, or at
// stages after the image's first use). `skygraph view`'s live graph: live_graph_test.cpp.
#include "present_fixture.hpp"
#include "renderer_access.hpp"
#include "compiled_graph_access.hpp"
#include "plan_editor.hpp"

#include "generic_passes.hpp"
#include "throwing_pass.hpp"

#include <skygraph/compiled_graph.hpp>
#include <skygraph/compiler.hpp>
#include <skygraph/device.hpp>
#include <skygraph/image_data.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/swapchain.hpp>


#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>

#include <unistd.h>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace skygraph::test {
namespace {

/// graphs/raster.json at `width` x `height`, compiled to present (every pass runs as Generic).
CompiledGraph raster(uint32_t width, uint32_t height, FeatureValues features = {}) {
    GraphDesc graph = loadGraphFile(std::string(SKYGRAPH_SOURCE_DIR) + "/graphs/raster.json",
                                    PassRegistry::withBuiltins());
    CompileOptions o;
    o.outputWidth = width;
    o.outputHeight = height;
    o.features = std::move(features);
    return CompiledGraph(std::move(graph), o);
}

/// Resizes `window` and waits (2 s at most) for the X server, which answers asynchronously, to
/// give it that size.
void resizeWindow(GLFWwindow* window, int width, int height) {
    glfwSetWindowSize(window, width, height);
    for (int i = 0; i < 200; ++i) {
        int fw = 0, fh = 0;
        glfwWaitEventsTimeout(0.01);
        glfwGetFramebufferSize(window, &fw, &fh);
        if (fw == width && fh == height) return;
    }
}

/// Options (two frames in flight) for a renderer made for a window that already presents
/// into `swapchain` (RendererOptions::presentTo).
RendererOptions presentingTo(Swapchain& swapchain) {
    RendererOptions options = genericOptions(2);
    options.presentTo = &swapchain;
    return options;
}

/// raster.json with the compute tonemap on, its target `swapchain_storage` edited to
/// R8G8B8A8_UNORM (a storage image): lavapipe's X11 surface offers B8G8R8A8 only.
CompiledGraph rasterPresentingAFormatTheSurfaceLacks(uint32_t width, uint32_t height) {
    GraphDesc graph = loadGraphFile(std::string(SKYGRAPH_SOURCE_DIR) + "/graphs/raster.json",
                                    PassRegistry::withBuiltins());
    for (ResourceDesc& r : graph.resources)
        if (r.name == "swapchain_storage") r.format = *findFormat(VK_FORMAT_R8G8B8A8_UNORM);
    CompileOptions o;
    o.outputWidth = width;
    o.outputHeight = height;
    o.features = {{"compute_tonemap", true}};
    return CompiledGraph(std::move(graph), o);
}

/// What the application does after renderFrame: presents `image` once `rendered` is signalled.
VkResult presentImage(VkQueue queue, VkSwapchainKHR swapchain, uint32_t image, VkSemaphore rendered) {
    VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    pi.waitSemaphoreCount = 1;
    pi.pWaitSemaphores = &rendered;
    pi.swapchainCount = 1;
    pi.pSwapchains = &swapchain;
    pi.pImageIndices = &image;
    return vkQueuePresentKHR(queue, &pi);
}

TEST(PresentDevice, ASurfaceThatCannotBeMadeIsAnError) {
    DeviceOptions o;
    o.device = "llvmpipe";
    o.presentation = PresentationOptions{{}, [](VkInstance) { return VkSurfaceKHR(VK_NULL_HANDLE); }};
    EXPECT_THROW((void)Device::create(o), ExecutorError);
    o.presentation = PresentationOptions{{"VK_KHR_surface", "VK_KHR_no_such_surface"},
                                         [](VkInstance) { return VkSurfaceKHR(VK_NULL_HANDLE); }};
    try {
        (void)Device::create(o);
        FAIL() << "no error";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("VK_KHR_no_such_surface"), std::string::npos) << e.what();
    }
}

TEST(PresentDevice, AHeadlessDeviceHasNoSurfaceAndMakesNoSwapchain) {
    DeviceOptions o;
    o.device = "llvmpipe";
    o.validation = true;
    o.logMessages = std::getenv("SKYGRAPH_TEST_QUIET") == nullptr;
    auto device = Device::create(o);
    EXPECT_EQ(device->surface(), VK_NULL_HANDLE);
    EXPECT_THROW((void)Swapchain::create(*device, raster(32, 32), {32, 32, PresentMode::Fifo}), ExecutorError);
    EXPECT_EQ(device->messageCount(), 0u) << formatMessages(*device);
}

TEST_F(Present, DeviceHasSurfaceAndSwapchainTakesPlanFormat) {
    ASSERT_NE(device_->surface(), VK_NULL_HANDLE);
    const CompiledGraph compiled = raster(96, 64);
    const PresentRequirements need = presentRequirements(compiled);
    EXPECT_EQ(need.resource, "swapchain");
    EXPECT_EQ(need.format, VK_FORMAT_B8G8R8A8_SRGB);
    EXPECT_TRUE(need.usage & VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT);
    auto swapchain = Swapchain::create(*device_, compiled, {96, 64, PresentMode::Fifo});
    EXPECT_EQ(swapchain->format(), VK_FORMAT_B8G8R8A8_SRGB);
    EXPECT_EQ(swapchain->extent().width, 96u);
    EXPECT_EQ(swapchain->extent().height, 64u);
    EXPECT_GE(swapchain->images().size(), 2u);
    EXPECT_EQ(swapchain->generation(), 1u);
    expectSilent();
}

TEST_F(Present, FramesThroughTheSwapchainAreSilent) {
    for (const uint32_t inFlight : {1u, 2u, 3u}) {
        SCOPED_TRACE("frames in flight " + std::to_string(inFlight));
        auto swapchain = Swapchain::create(*device_, raster(96, 64), {96, 64, PresentMode::Fifo});
        Renderer renderer(*device_, raster(96, 64), genericOptions(inFlight));
        present(renderer, *swapchain, 12);
        EXPECT_EQ(renderer.frameCount(), 12u);
    }
    expectSilent();
}

TEST_F(Present, MailboxAndImmediateAreSilent) {
    for (const PresentMode mode : {PresentMode::Mailbox, PresentMode::Immediate}) {
        SCOPED_TRACE(presentModeName(mode));
        auto swapchain = Swapchain::create(*device_, raster(96, 64), {96, 64, mode});
        EXPECT_EQ(swapchain->presentMode(), mode);  // lavapipe on X11 has both
        Renderer renderer(*device_, raster(96, 64), genericOptions(2));
        present(renderer, *swapchain, 8);
    }
    expectSilent();
}

// Another present mode is another swapchain: one renderer presents into the next after the
// last is destroyed, though the new one may have the old one's address.
TEST_F(Present, ARendererGoesOnInASwapchainMadeAfterItsLastWasDestroyed) {
    const CompiledGraph compiled = raster(96, 64);
    Renderer renderer(*device_, compiled, genericOptions(2));
    std::unique_ptr<Swapchain> swapchain;
    for (const PresentMode mode : {PresentMode::Fifo, PresentMode::Immediate, PresentMode::Mailbox, PresentMode::Fifo}) {
        swapchain.reset();  // freed just before the next is made, which then tends to get its address
        swapchain = Swapchain::create(*device_, compiled, {96, 64, mode});
        present(renderer, *swapchain, 4);  // ends with waitIdle()
    }
    expectSilent();
}

// Between destroying its swapchain and rendering into the next, a renderer that rebuilt its
// plan state made views of the destroyed swapchain's images: it refuses instead, and keeps
// its plan until the next swapchain comes.
TEST_F(Present, ARebuildAfterTheSwapchainIsDestroyedIsRefusedUntilTheNext) {
    const CompiledGraph compiled = raster(96, 64);
    Renderer renderer(*device_, compiled, genericOptions(2));
    auto swapchain = Swapchain::create(*device_, compiled, {96, 64, PresentMode::Fifo});
    present(renderer, *swapchain, 1);
    swapchain.reset();
    for (const auto& rebuild : std::vector<std::function<void()>>{[&] { renderer.setGraph(compiled); },
                                                                  [&] { renderer.reloadShaders(); }}) {
        try {
            rebuild();
            ADD_FAILURE() << "the plan state was built on a destroyed swapchain's images";
        } catch (const ExecutorError& e) {
            EXPECT_NE(std::string(e.what()).find("the swapchain this renderer presents into was destroyed"),
                      std::string::npos)
                << e.what();
        }
    }
    swapchain = Swapchain::create(*device_, compiled, {96, 64, PresentMode::Fifo});
    present(renderer, *swapchain, 2);
    renderer.setGraph(compiled);
    present(renderer, *swapchain, 1);
    expectSilent();
}

// An import while the swapchain is destroyed: the renderer made its passes' framebuffers again
// from the destroyed images' views (a segmentation fault inside the validation layer). The
// import waits for the plan state of the next swapchain, and its frames sample it.
TEST_F(Present, AnImportWhileTheSwapchainIsDestroyedWaitsForTheNext) {
    CompileOptions o;
    o.outputWidth = 96;
    o.outputHeight = 64;
    const CompiledGraph producerGraph(parseGraph(R"({ "version": 1, "name": "producer", "resources": {
        "shared": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true, "final": "ShaderRead" } },
      "passes": [ { "name": "paint", "type": "Generic", "uses": { "shared": "Write@ColorAttachment" } } ] })",
                                                 "producer.json", PassRegistry::withBuiltins()),
                                      o);
    const CompiledGraph consumerGraph(parseGraph(R"({ "version": 1, "name": "consumer", "resources": {
        "shared": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true },
        "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true, "final": "Present" } },
      "passes": [ { "name": "show", "type": "Generic", "uses": { "shared": "Read@Fragment", "swapchain": "Write@ColorAttachment" } } ] })",
                                                 "consumer.json", PassRegistry::withBuiltins()),
                                      o);
    Renderer producer(*device_, producerGraph, genericOptions(1));
    producer.renderFrame();
    producer.waitIdle();
    Renderer consumer(*device_, consumerGraph, genericOptions(2));
    auto swapchain = Swapchain::create(*device_, consumerGraph, {96, 64, PresentMode::Fifo});
    present(consumer, *swapchain, 2);
    swapchain.reset();
    consumer.importImage("shared", producer.shareImage("shared"));
    swapchain = Swapchain::create(*device_, consumerGraph, {96, 64, PresentMode::Fifo});
    present(consumer, *swapchain, 2);
    expectSilent();
}

TEST_F(Present, ResizeRecreatesTheSwapchainAndRecompiles) {
    auto swapchain = Swapchain::create(*device_, raster(96, 64), {96, 64, PresentMode::Fifo});
    Renderer renderer(*device_, raster(96, 64), genericOptions(2));
    glfwSetWindowUserPointer(window_, swapchain.get());
    glfwSetFramebufferSizeCallback(window_, [](GLFWwindow* w, int width, int height) {
        static_cast<Swapchain*>(glfwGetWindowUserPointer(w))->resize(uint32_t(width), uint32_t(height));
    });
    present(renderer, *swapchain, 4);
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{{130, 90}, {40, 30}}) {
        resizeWindow(window_, w, h);
        present(renderer, *swapchain, 4);
        EXPECT_EQ(renderer.compiled().outputWidth(), uint32_t(w));
        EXPECT_EQ(renderer.compiled().outputHeight(), uint32_t(h));
        EXPECT_EQ(swapchain->extent().width, uint32_t(w));
        EXPECT_EQ(swapchain->extent().height, uint32_t(h));
    }
    EXPECT_GE(swapchain->generation(), 3u);
    expectSilent();
}

TEST_F(Present, ZeroSizePausesUntilTheWindowHasASize) {
    auto swapchain = Swapchain::create(*device_, raster(96, 64), {96, 64, PresentMode::Fifo});
    Renderer renderer(*device_, raster(96, 64), genericOptions(2));
    present(renderer, *swapchain, 2);
    swapchain->resize(0, 0);
    EXPECT_TRUE(swapchain->paused());
    EXPECT_EQ(renderer.renderFrame(*swapchain), PresentStatus::Paused);
    EXPECT_EQ(renderer.renderFrame(*swapchain), PresentStatus::Paused);
    EXPECT_EQ(renderer.frameCount(), 2u);
    swapchain->resize(96, 64);
    EXPECT_FALSE(swapchain->paused());
    present(renderer, *swapchain, 2);
    EXPECT_EQ(renderer.frameCount(), 4u);
    expectSilent();
}

TEST_F(Present, HeadlessRenderFrameRefusesOncePresenting) {
    auto swapchain = Swapchain::create(*device_, raster(96, 64), {96, 64, PresentMode::Fifo});
    Renderer renderer(*device_, raster(96, 64), genericOptions(2));
    present(renderer, *swapchain, 1);
    EXPECT_THROW(renderer.renderFrame(), ExecutorError);
    EXPECT_THROW(renderer.resize(50, 50), ExecutorError);  // the swapchain decides the size
    present(renderer, *swapchain, 1);
    expectSilent();
}

TEST_F(Present, AFormatTheSurfaceLacksIsAClearError) {
    const CompiledGraph compiled = rasterPresentingAFormatTheSurfaceLacks(96, 64);
    EXPECT_EQ(presentRequirements(compiled).resource, "swapchain_storage");
    EXPECT_TRUE(presentRequirements(compiled).usage & VK_IMAGE_USAGE_STORAGE_BIT);
    try {
        (void)Swapchain::create(*device_, compiled, {96, 64, PresentMode::Fifo});
        FAIL() << "no error";
    } catch (const ExecutorError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("R8G8B8A8_UNORM"), std::string::npos) << what;
        EXPECT_NE(what.find("swapchain_storage"), std::string::npos) << what;
        EXPECT_NE(what.find("B8G8R8A8_UNORM"), std::string::npos) << what;
    }
}

TEST_F(Present, AHeadlessPlanIsNotPresented) {
    GraphDesc graph = loadGraphFile(std::string(SKYGRAPH_SOURCE_DIR) + "/graphs/raster.json",
                                    PassRegistry::withBuiltins());
    CompileOptions o;
    o.outputWidth = 96;
    o.outputHeight = 64;
    o.presentReplacement = ExternalState::TransferSrc;
    EXPECT_THROW((void)presentRequirements(CompiledGraph(std::move(graph), o)), ExecutorError);
}

/// A swapchain an application makes for the plan's present images, FIFO at the surface's size.
VkSwapchainCreateInfoKHR ownSwapchainInfo(const Device& device, const VkSurfaceCapabilitiesKHR& caps,
                                          const PresentRequirements& need, VkSwapchainKHR old = VK_NULL_HANDLE) {
    VkSwapchainCreateInfoKHR ci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    ci.surface = device.surface();
    ci.minImageCount = caps.minImageCount + 1;
    ci.imageFormat = need.format;
    ci.imageColorSpace = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
    ci.imageExtent = caps.currentExtent;
    ci.imageArrayLayers = 1;
    ci.imageUsage = need.usage;
    ci.preTransform = caps.currentTransform;
    ci.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    ci.presentMode = VK_PRESENT_MODE_FIFO_KHR;
    ci.clipped = VK_TRUE;
    ci.oldSwapchain = old;
    return ci;
}

/// The application's own swapchain: its images given with setPresentImages, its semaphores
/// in each PresentTarget, its present.
TEST_F(Present, OwnSwapchainImagesAndSemaphores) {
    const VkDevice vkd = device_->device();
    VkSurfaceCapabilitiesKHR caps;
    ASSERT_EQ(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(device_->physicalDevice(), device_->surface(), &caps),
              VK_SUCCESS);
    const CompiledGraph compiled = raster(caps.currentExtent.width, caps.currentExtent.height);
    const PresentRequirements need = presentRequirements(compiled);
    const VkSwapchainCreateInfoKHR ci = ownSwapchainInfo(*device_, caps, need);
    VkSwapchainKHR swapchain;
    ASSERT_EQ(vkCreateSwapchainKHR(vkd, &ci, nullptr, &swapchain), VK_SUCCESS);
    uint32_t n = 0;
    vkGetSwapchainImagesKHR(vkd, swapchain, &n, nullptr);
    PresentImages images;
    images.images.resize(n);
    vkGetSwapchainImagesKHR(vkd, swapchain, &n, images.images.data());
    images.format = need.format;
    images.extent = caps.currentExtent;
    images.usage = need.usage;
    const uint32_t inFlight = 2;
    std::vector<VkSemaphore> acquired(inFlight), done(n);
    VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    for (auto& s : acquired) vkCreateSemaphore(vkd, &sci, nullptr, &s);
    for (auto& s : done) vkCreateSemaphore(vkd, &sci, nullptr, &s);
    {
        Renderer renderer(*device_, compiled, genericOptions(inFlight));
        // Images made without a usage the plan needs are refused, the usages named.
        PresentImages unusable = images;
        unusable.usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        try {
            renderer.setPresentImages(unusable);
            ADD_FAILURE() << "present images without COLOR_ATTACHMENT usage were taken";
        } catch (const UnsupportedResourceError& e) {
            EXPECT_EQ(e.resource(), "swapchain");
            const std::string message = e.what();
            const size_t needs = message.find("needs image usage "), made = message.find("were created with");
            ASSERT_NE(needs, std::string::npos) << message;
            EXPECT_NE(message.substr(needs, made - needs).find("COLOR_ATTACHMENT"), std::string::npos) << message;
            EXPECT_NE(std::string(e.what()).find("were created with TRANSFER_DST"), std::string::npos) << e.what();
        }
        renderer.setPresentImages(images);
        for (int frame = 0; frame < 12; ++frame) {
            const uint32_t slot = renderer.waitForFrameSlot();  // acquired[slot] is free again
            uint32_t image = 0;
            ASSERT_EQ(vkAcquireNextImageKHR(vkd, swapchain, UINT64_MAX, acquired[slot], VK_NULL_HANDLE, &image),
                      VK_SUCCESS);
            renderer.renderFrame(PresentTarget{image, acquired[slot], done[image]});
            ASSERT_EQ(presentImage(device_->queue(), swapchain, image, done[image]), VK_SUCCESS);
        }
        // The renderer cannot re-create the application's images: a graph presenting another
        // format is refused, and the old plan stays.
        try {
            renderer.setGraph(raster(caps.currentExtent.width, caps.currentExtent.height, {{"compute_tonemap", true}}));
            ADD_FAILURE() << "a graph presenting another format than the application's images was installed";
        } catch (const UnsupportedResourceError& e) {  // the declaration decides it: named there
            EXPECT_EQ(e.resource(), "swapchain_storage");
            EXPECT_NE(std::string(e.what()).find("its format is B8G8R8A8_UNORM, the present images' is B8G8R8A8_SRGB"),
                      std::string::npos)
                << e.what();
        }
        EXPECT_EQ(presentRequirements(renderer.compiled()).format, VK_FORMAT_B8G8R8A8_SRGB);
        EXPECT_THROW(renderer.renderFrame(PresentTarget{n, acquired[0], done[0]}), ExecutorError);
        renderer.waitIdle();
        vkQueueWaitIdle(device_->queue());
    }
    for (auto s : acquired) vkDestroySemaphore(vkd, s, nullptr);
    for (auto s : done) vkDestroySemaphore(vkd, s, nullptr);
    vkDestroySwapchainKHR(vkd, swapchain, nullptr);
    expectSilent();
}

/// A graph of one ThrowingPass that draws the presented image, compiled to present at
/// `width` x `height` with `library`'s declarations.
CompiledGraph throwingGraph(const PassLibrary& library, uint32_t width, uint32_t height) {
    GraphDesc graph = parseGraph(R"({ "version": 1, "name": "throwing", "resources": {
        "swapchain": { "type": "image2d", "format": "B8G8R8A8_SRGB", "extent": "output",
                       "external": true, "final": "Present" } },
      "passes": [ { "name": "draw", "type": "ThrowingPass", "uses": { "swapchain": "Write@ColorAttachment" },
                    "params": { "color": [0.2, 0.4, 0.6, 1] } } ] })",
                                 "throwing.json", library.registry());
    CompileOptions o;
    o.outputWidth = width;
    o.outputHeight = height;
    return CompiledGraph(std::move(graph), o);
}

// A pass that throws while a frame is recorded: the image acquired for it is not presented,
// its acquire semaphore is waited for all the same, and the next frame re-creates the
// swapchain, which gives the image back; more such frames than the swapchain has images
// leave it presenting, under validation.
TEST_F(Present, AFrameWhosePassThrowsLeavesTheSwapchainPresenting) {
    const PassLibrary library = throwingPassLibrary();
    const CompiledGraph compiled = throwingGraph(library, 96, 64);
    auto swapchain = Swapchain::create(*device_, compiled, {96, 64, PresentMode::Fifo});
    RendererOptions ro = genericOptions(2);
    ro.passes = &library;
    Renderer renderer(*device_, compiled, ro);
    const size_t images = swapchain->images().size();
    for (size_t round = 0; round <= images; ++round) {
        SCOPED_TRACE("round " + std::to_string(round));
        glfwPollEvents();
        EXPECT_EQ(renderer.renderFrame(*swapchain), PresentStatus::Presented);
        renderer.frameData().set(ThrowWhileRecording{true});
        EXPECT_THROW((void)renderer.renderFrame(*swapchain), PassThrew);
        renderer.frameData().set(ThrowWhileRecording{false});
        EXPECT_EQ(renderer.renderFrame(*swapchain), PresentStatus::Presented);
    }
    renderer.waitIdle();
    EXPECT_EQ(renderer.frameCount(), 2 * (images + 1));
    EXPECT_EQ(swapchain->generation(), 2 + images) << "re-created after each frame that threw";
    expectSilent();
}

// The same with the application's own swapchain: the renderer waits for the acquire semaphore
// of the frame that threw, so that the application may acquire with it again once the frame
// slot comes round, and signals no render-complete semaphore; the application gives the image
// back by re-creating its swapchain.
TEST_F(Present, AFrameWhosePassThrowsWaitsForTheApplicationsAcquireSemaphore) {
    const VkDevice vkd = device_->device();
    VkSurfaceCapabilitiesKHR caps;
    ASSERT_EQ(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(device_->physicalDevice(), device_->surface(), &caps),
              VK_SUCCESS);
    const PassLibrary library = throwingPassLibrary();
    const CompiledGraph compiled = throwingGraph(library, caps.currentExtent.width, caps.currentExtent.height);
    const PresentRequirements need = presentRequirements(compiled);
    VkSwapchainKHR swapchain = VK_NULL_HANDLE;
    PresentImages images;
    std::vector<VkSemaphore> done;
    VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    // A new swapchain (the old one retired) with a render-complete semaphore per image.
    const auto recreate = [&] {
        const VkSwapchainCreateInfoKHR ci = ownSwapchainInfo(*device_, caps, need, swapchain);
        VkSwapchainKHR next = VK_NULL_HANDLE;
        ASSERT_EQ(vkCreateSwapchainKHR(vkd, &ci, nullptr, &next), VK_SUCCESS);
        vkDestroySwapchainKHR(vkd, swapchain, nullptr);  // its presents are done: the queue is idle
        swapchain = next;
        uint32_t n = 0;
        vkGetSwapchainImagesKHR(vkd, swapchain, &n, nullptr);
        images = PresentImages{std::vector<VkImage>(n), need.format, caps.currentExtent, need.usage};
        vkGetSwapchainImagesKHR(vkd, swapchain, &n, images.images.data());
        for (VkSemaphore s : done) vkDestroySemaphore(vkd, s, nullptr);
        done.assign(n, VK_NULL_HANDLE);
        for (auto& s : done) vkCreateSemaphore(vkd, &sci, nullptr, &s);
    };
    recreate();
    const uint32_t inFlight = 2;
    std::vector<VkSemaphore> acquired(inFlight);
    for (auto& s : acquired) vkCreateSemaphore(vkd, &sci, nullptr, &s);
    {
        RendererOptions ro = genericOptions(inFlight);
        ro.passes = &library;
        Renderer renderer(*device_, compiled, ro);
        renderer.setPresentImages(images);
        const auto frame = [&](bool throws) {
            const uint32_t slot = renderer.waitForFrameSlot();
            uint32_t image = 0;
            ASSERT_EQ(vkAcquireNextImageKHR(vkd, swapchain, UINT64_MAX, acquired[slot], VK_NULL_HANDLE, &image),
                      VK_SUCCESS);
            renderer.frameData().set(ThrowWhileRecording{throws});
            if (throws) {
                EXPECT_THROW(renderer.renderFrame(PresentTarget{image, acquired[slot], done[image]}), PassThrew);
                return;
            }
            renderer.renderFrame(PresentTarget{image, acquired[slot], done[image]});
            ASSERT_EQ(presentImage(device_->queue(), swapchain, image, done[image]), VK_SUCCESS);
        };
        for (int round = 0; round < 3; ++round) {
            SCOPED_TRACE("round " + std::to_string(round));
            frame(false);
            frame(true);
            frame(false);  // the slot of the frame that threw, its acquire semaphore again
            renderer.waitIdle();
            vkQueueWaitIdle(device_->queue());
            recreate();
            renderer.setPresentImages(images);
            frame(false);
        }
        renderer.waitIdle();
        vkQueueWaitIdle(device_->queue());
        EXPECT_EQ(renderer.frameCount(), 9u);
    }
    for (auto s : acquired) vkDestroySemaphore(vkd, s, nullptr);
    for (auto s : done) vkDestroySemaphore(vkd, s, nullptr);
    vkDestroySwapchainKHR(vkd, swapchain, nullptr);
    expectSilent();
}

// A renderer made for a window another one presents to (RendererOptions::presentTo) while
// that one's frames are in flight presents beside them silently. It acquires with semaphores
// of its own (a semaphore the first renderer's frames may still wait on would break
// VUID-vkAcquireNextImageKHR-semaphore-01779), but this test is no oracle for that: with one
// semaphore per swapchain slot shared on purpose, lavapipe and layer 1.3.239 report nothing.
TEST_F(Present, ASecondRendererPresentsWhileTheFirstsFramesAreInFlight) {
    auto swapchain = Swapchain::create(*device_, raster(96, 64), {96, 64, PresentMode::Fifo});
    auto first = std::make_unique<Renderer>(*device_, raster(96, 64), genericOptions(2));
    for (int i = 0; i < 2; ++i) ASSERT_EQ(first->renderFrame(*swapchain), PresentStatus::Presented);
    Renderer second(*device_, raster(96, 64), presentingTo(*swapchain));
    EXPECT_EQ(second.renderFrame(*swapchain), PresentStatus::Presented);
    first.reset();
    present(second, *swapchain, 2);
    expectSilent();
}

// Two renderers present into one window, and the second re-creates the swapchain for a new
// size: the first's images are gone. Its rebuilds (reloadShaders, as a HotReloader's poll
// makes, setGraph, resize) made views of the destroyed images (a crash in the driver); they
// now render into a stand-in until its next frame binds the new images, silently.
TEST_F(Present, RebuildsAfterAnotherRendererRecreatedTheSwapchainMakeNoViewOfItsOldImages) {
    auto swapchain = Swapchain::create(*device_, raster(96, 64), {96, 64, PresentMode::Fifo});
    Renderer first(*device_, raster(96, 64), genericOptions(2));
    present(first, *swapchain, 1);
    Renderer second(*device_, raster(96, 64), presentingTo(*swapchain));
    present(second, *swapchain, 1);
    for (int rebuild = 0; rebuild < 3; ++rebuild) {
        const uint32_t width = rebuild % 2 ? 96 : 40, height = rebuild % 2 ? 64 : 30;
        swapchain->resize(width, height);
        resizeWindow(window_, int(width), int(height));
        const uint64_t generation = swapchain->generation();
        present(second, *swapchain, 1);
        ASSERT_GT(swapchain->generation(), generation) << "the second renderer re-created the swapchain";
        if (rebuild == 0) first.reloadShaders();
        if (rebuild == 1) first.setGraph(raster(96, 64));
        if (rebuild == 2) first.resize(first.compiled().outputWidth(), first.compiled().outputHeight());
        present(first, *swapchain, 2);
        EXPECT_EQ(first.compiled().outputWidth(), width);
    }
    expectSilent();
}

// setGraph on a presenting renderer compiles the graph at the present images' extent, as the
// constructor does with RendererOptions::presentTo; resize() to another size still throws.
TEST_F(Present, SetGraphCompilesAtThePresentImagesExtent) {
    auto swapchain = Swapchain::create(*device_, raster(96, 64), {96, 64, PresentMode::Fifo});
    Renderer renderer(*device_, raster(96, 64), genericOptions(2));
    present(renderer, *swapchain, 2);
    renderer.setGraph(raster(50, 40));
    EXPECT_EQ(renderer.compiled().outputWidth(), 96u);
    EXPECT_EQ(renderer.compiled().outputHeight(), 64u);
    present(renderer, *swapchain, 2);
    EXPECT_EQ(swapchain->generation(), 1u) << "the swapchain's images were kept";
    EXPECT_THROW(renderer.resize(50, 40), ExecutorError);
    present(renderer, *swapchain, 1);
    expectSilent();
}

// A graph compiled with another device's memory model is placed with this device's at the
// present images' extent in one compile: the other device may be gone, and its model throws
// once it is.
TEST_F(Present, SetGraphOfAPlanFromAFinishedDeviceCompilesWithThisDevicesModel) {
    auto swapchain = Swapchain::create(*device_, raster(96, 64), {96, 64, PresentMode::Fifo});
    Renderer renderer(*device_, raster(96, 64), genericOptions(2));
    present(renderer, *swapchain, 1);
    DeviceOptions o;
    o.validation = true;
    o.device = "llvmpipe";
    auto other = Device::create(o);
    GraphDesc graph = loadGraphFile(std::string(SKYGRAPH_SOURCE_DIR) + "/graphs/raster.json",
                                    PassRegistry::withBuiltins());
    CompileOptions elsewhere;
    elsewhere.outputWidth = 50;
    elsewhere.outputHeight = 40;
    elsewhere.memory = other->memoryModel();
    CompiledGraph compiled(std::move(graph), elsewhere);
    EXPECT_EQ(other->messageCount(), 0u) << formatMessages(*other);
    other.reset();
    renderer.setGraph(std::move(compiled));
    EXPECT_EQ(renderer.compiled().outputWidth(), 96u);
    EXPECT_EQ(renderer.compiled().options().memory, device_->memoryModel());
    present(renderer, *swapchain, 2);
}

// A graph edit that presents another format and usage (raster.json's compute tonemap writes
// the UNORM storage image `swapchain_storage` instead of the sRGB attachment `swapchain`)
// re-creates the renderer's swapchain at the next frame, and back again.
TEST_F(Present, SetGraphToAnotherPresentFormatRecreatesTheSwapchain) {
    auto swapchain = Swapchain::create(*device_, raster(96, 64), {96, 64, PresentMode::Fifo});
    Renderer renderer(*device_, raster(96, 64), genericOptions(2));
    present(renderer, *swapchain, 2);
    ASSERT_EQ(swapchain->format(), VK_FORMAT_B8G8R8A8_SRGB);
    {
        // One whose presented image is not the window's size is refused here, not by the frame
        // that would bind it.
        std::ifstream file(std::string(SKYGRAPH_SOURCE_DIR) + "/graphs/raster.json");
        std::string text{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
        const std::string from = R"("swapchain_storage": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output")";
        ASSERT_NE(text.find(from), std::string::npos);
        text.replace(text.find(from), from.size(),
                     R"("swapchain_storage": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": [50, 40])");
        CompileOptions o;
        o.outputWidth = 96;
        o.outputHeight = 64;
        o.features = {{"compute_tonemap", true}};
        try {
            renderer.setGraph(CompiledGraph(parseGraph(text, "raster.json", PassRegistry::withBuiltins()), o));
            ADD_FAILURE() << "a presented image of 50x40 was taken for a 96x64 window";
        } catch (const UnsupportedResourceError& e) {  // the declaration decides it: named there
            EXPECT_EQ(e.resource(), "swapchain_storage");
            EXPECT_NE(std::string(e.what()).find("the plan's is 50x40, the present images are 96x64 (one mip, one "
                                                 "layer); a presented image follows the window: give it \"extent\": "
                                                 "\"output\""),
                      std::string::npos)
                << e.what();
        }
        EXPECT_EQ(presentRequirements(renderer.compiled()).resource, "swapchain");
    }
    renderer.setGraph(raster(96, 64, {{"compute_tonemap", true}}));
    EXPECT_EQ(presentRequirements(renderer.compiled()).resource, "swapchain_storage");
    EXPECT_EQ(swapchain->generation(), 1u) << "re-created by the next frame, not by setGraph";
    // Until then the renderer still presents: what a presenting renderer refuses stays refused,
    // and another graph is still compiled at the window's extent and checked against the surface.
    EXPECT_THROW(renderer.renderFrame(), ExecutorError);
    EXPECT_THROW(renderer.resize(50, 40), ExecutorError);
    try {
        (void)renderer.shareImage("swapchain_storage");
        ADD_FAILURE() << "the stand-in for the presented image was shared";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("is the presented image"), std::string::npos) << e.what();
    }
    try {
        renderer.renderFrame(PresentTarget{0, VK_NULL_HANDLE, VK_NULL_HANDLE});
        ADD_FAILURE() << "a frame into the stand-in was rendered";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("renderFrame(Swapchain&) re-creates them"), std::string::npos)
            << e.what();
    }
    EXPECT_THROW(renderer.setGraph(rasterPresentingAFormatTheSurfaceLacks(96, 64)), ExecutorError);
    renderer.setGraph(raster(50, 40, {{"compute_tonemap", true}}));
    EXPECT_EQ(renderer.compiled().outputWidth(), 96u);
    EXPECT_EQ(renderer.compiled().outputHeight(), 64u);
    present(renderer, *swapchain, 3);
    EXPECT_EQ(swapchain->format(), VK_FORMAT_B8G8R8A8_UNORM);
    EXPECT_EQ(swapchain->generation(), 2u);
    renderer.setGraph(raster(96, 64));
    present(renderer, *swapchain, 3);
    EXPECT_EQ(swapchain->format(), VK_FORMAT_B8G8R8A8_SRGB);
    EXPECT_EQ(swapchain->generation(), 3u);
    expectSilent();
}

/// A pass whose pipelines cannot be made: a plan state that fails to build.
class Unbuildable : public PassImplementation {
public:
    void createPipelines(const PipelineContext&) override { throw std::runtime_error("no pipelines, as asked"); }
    void record(const RecordContext&) override {}
};

// A graph of another present format whose build fails leaves the renderer bound to its
// swapchain's images, presenting the old plan.
TEST_F(Present, AFailedSetGraphToAnotherPresentFormatKeepsTheSwapchainsImages) {
    PassLibrary library = PassLibrary::genericOnly();
    PassTypeInfo info;
    info.name = "Unbuildable";
    info.acceptsAnyUsage = true;
    library.add(std::move(info), [](const PassDesc&) { return std::make_unique<Unbuildable>(); });
    RendererOptions ro = genericOptions(2);
    ro.passes = &library;
    auto swapchain = Swapchain::create(*device_, raster(96, 64), {96, 64, PresentMode::Fifo});
    Renderer renderer(*device_, raster(96, 64), ro);
    present(renderer, *swapchain, 2);
    GraphDesc unorm = parseGraph(R"({ "version": 1, "name": "unbuildable", "resources": {
        "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",
                       "external": true, "final": "Present" } },
      "passes": [ { "name": "draw", "type": "Unbuildable", "uses": { "swapchain": "Write@ColorAttachment" } } ] })",
                                 "unbuildable.json", library.registry());
    CompileOptions o;
    o.outputWidth = 96;
    o.outputHeight = 64;
    try {
        renderer.setGraph(CompiledGraph(std::move(unorm), o));
        FAIL() << "a graph whose pipelines cannot be made was installed";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("no pipelines, as asked"), std::string::npos) << e.what();
    }
    EXPECT_EQ(renderer.compiled().graph().name, "raster");
    EXPECT_THROW(renderer.renderFrame(), ExecutorError) << "still presenting";
    present(renderer, *swapchain, 2);
    EXPECT_EQ(swapchain->generation(), 1u) << "the old images are still bound";
    EXPECT_EQ(swapchain->format(), VK_FORMAT_B8G8R8A8_SRGB);
    expectSilent();
}

// A format the surface cannot present fails setGraph itself, and the old plan presents on.
TEST_F(Present, SetGraphToAFormatTheSurfaceLacksKeepsTheOldPlan) {
    auto swapchain = Swapchain::create(*device_, raster(96, 64), {96, 64, PresentMode::Fifo});
    Renderer renderer(*device_, raster(96, 64), genericOptions(2));
    present(renderer, *swapchain, 2);
    try {
        renderer.setGraph(rasterPresentingAFormatTheSurfaceLacks(96, 64));
        FAIL() << "a graph presenting a format the surface lacks was installed";
    } catch (const ExecutorError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("the surface cannot present R8G8B8A8_UNORM"), std::string::npos) << what;
        EXPECT_NE(what.find("'swapchain_storage'"), std::string::npos) << what;
    }
    EXPECT_EQ(presentRequirements(renderer.compiled()).resource, "swapchain");
    present(renderer, *swapchain, 2);
    EXPECT_EQ(swapchain->generation(), 1u);
    expectSilent();
}

// A renderer made for a window (RendererOptions::presentTo) with a graph presenting a format
// the surface lacks throws as it is made, as setGraph does, not at its first frame: the view's
// reload of such a save keeps the running renderer instead of ending at that frame.
TEST_F(Present, ARendererForAWindowRefusesAFormatTheSurfaceLacksAsItIsMade) {
    auto swapchain = Swapchain::create(*device_, raster(96, 64), {96, 64, PresentMode::Fifo});
    Renderer first(*device_, raster(96, 64), genericOptions(2));
    present(first, *swapchain, 2);
    try {
        Renderer second(*device_, rasterPresentingAFormatTheSurfaceLacks(96, 64), presentingTo(*swapchain));
        FAIL() << "a renderer presenting a format the surface lacks was made";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("the surface cannot present R8G8B8A8_UNORM"), std::string::npos)
            << e.what();
    }
    present(first, *swapchain, 2);
    EXPECT_EQ(swapchain->generation(), 1u);
    expectSilent();
}

// --- Negative controls: the same frames, weakened on purpose, must be reported. ------------

/// Renders frames with the acquire wait at `stages` (0: no wait) and returns what validation said.
std::vector<ValidationMessage> framesWithAcquireWait(Device& device, VkPipelineStageFlags2 stages) {
    auto swapchain = Swapchain::create(device, raster(96, 64), {96, 64, PresentMode::Fifo});
    Renderer renderer(device, raster(96, 64), genericOptions(2));
    RendererAccess::overrideAcquireWait(renderer, stages);
    for (int i = 0; i < 8; ++i) {
        glfwPollEvents();
        (void)renderer.renderFrame(*swapchain);
    }
    renderer.waitIdle();
    return device.messages();
}

bool reported(const std::vector<ValidationMessage>& messages, const std::string& id, const std::string& text = {}) {
    for (const auto& m : messages)
        if (m.idName.find(id) != std::string::npos && m.message.find(text) != std::string::npos) return true;
    return false;
}

TEST_F(Present, NegativeControlTheIntactFrameIsSilent) {
    const CompiledGraph compiled = raster(96, 64);
    const int32_t index = compiled.plan().resourceIndex("swapchain");
    ASSERT_GE(index, 0);
    // The plan's own wait: where the swapchain is first used, the tonemap's colour output.
    EXPECT_EQ(compiled.plan().resources()[size_t(index)].firstStages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
    const auto messages = framesWithAcquireWait(*device_, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
    EXPECT_TRUE(messages.empty()) << formatMessages(*device_);
}

TEST_F(Present, NegativeControlNoAcquireWaitIsReported) {
    const auto messages = framesWithAcquireWait(*device_, 0);
    EXPECT_TRUE(reported(messages, "SYNC-HAZARD-WRITE-AFTER-PRESENT")) << formatMessages(*device_);
    device_->clearMessages();  // expected: TearDown fails on any other
}

TEST_F(Present, NegativeControlAcquireWaitAfterTheFirstUseIsReported) {
    // Waiting at the end of the pipeline leaves the layout transition before the colour
    // output (the first use) unordered after the acquire.
    const auto messages = framesWithAcquireWait(*device_, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT);
    EXPECT_TRUE(reported(messages, "SYNC-HAZARD-WRITE-AFTER-READ", "PRESENT_ACQUIRE")) << formatMessages(*device_);
    device_->clearMessages();  // expected: TearDown fails on any other
}

// --- The final barrier's destination (docs/barriers.md, rule 15) ---------------------------

uint32_t validationLayerVersion() {
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    for (const auto& l : layers)
        if (std::string(l.layerName) == "VK_LAYER_KHRONOS_validation") return l.specVersion;
    return 0;
}

/// `compiled` with its final barrier to PRESENT_SRC_KHR given destination stages `dst`, or
/// dropped when `dst` is nullopt.
CompiledGraph withPresentBarrier(const Device& device, const CompiledGraph& compiled,
                                 std::optional<VkPipelineStageFlags2> dst) {
    // Compiled with the device's memory model: a renderer recompiles any other plan, which
    // would drop the edit.
    CompileOptions options = compiled.options();
    options.memory = device.memoryModel();
    const CompiledGraph onDevice(compiled.graph(), options);
    Plan plan = onDevice.plan();
    auto& finals = detail::PlanEditor::finalBarriers(plan);
    for (auto it = finals.begin(); it != finals.end(); ++it) {
        if (it->newLayout != VK_IMAGE_LAYOUT_PRESENT_SRC_KHR) continue;
        if (dst) it->dstStages = *dst;
        else finals.erase(it);
        break;
    }
    return detail::CompiledGraphAccess::withPlan(onDevice, std::move(plan));
}

/// Presents 6 frames of `compiled`; the device's messages are left to read.
void presentFrames(Device& device, const CompiledGraph& compiled) {
    auto swapchain = Swapchain::create(device, compiled, {96, 64, PresentMode::Fifo});
    Renderer renderer(device, compiled, genericOptions(2));
    for (int i = 0; i < 6; ++i) (void)renderer.renderFrame(*swapchain);
    renderer.waitIdle();
}

TEST_F(Present, TheFinalBarrierChainsWithTheRenderCompleteSignal) {
    // The plan's barrier to PRESENT_SRC_KHR has the signal's stages as its destination: silent.
    const CompiledGraph compiled = raster(96, 64);
    const Presentation& p = compiled.plan().presentations()[0];
    EXPECT_EQ(p.renderCompleteStages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
    presentFrames(*device_, compiled);
    expectSilent();
    // Destination NONE is also correct by the spec, but layers before 1.3.278 leave layout
    // transitions out of a signal's scope and report it: the reason the plan gives one.
    device_->clearMessages();
    presentFrames(*device_, withPresentBarrier(*device_, compiled, VK_PIPELINE_STAGE_2_NONE));
    if (validationLayerVersion() < VK_MAKE_API_VERSION(0, 1, 3, 278)) {
        EXPECT_TRUE(reported(device_->messages(), "SYNC-HAZARD-PRESENT-AFTER-WRITE", "")) << formatMessages(*device_);
    } else {
        // Newer layers follow the spec here: the control cannot fail them, so say that it ran.
        EXPECT_FALSE(reported(device_->messages(), "SYNC-HAZARD-PRESENT-AFTER-WRITE", "")) << formatMessages(*device_);
    }
    device_->clearMessages();
}

TEST_F(Present, NegativeControlNoPresentBarrierIsReported) {
    // Without the final barrier the image is presented in COLOR_ATTACHMENT_OPTIMAL.
    presentFrames(*device_, withPresentBarrier(*device_, raster(96, 64), std::nullopt));
    EXPECT_TRUE(reported(device_->messages(), "VUID-VkPresentInfoKHR-pImageIndices-01296")) << formatMessages(*device_);
    device_->clearMessages();
}

}  // namespace
}  // namespace skygraph::test
