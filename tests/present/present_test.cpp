// Presentation under validation + synchronization validation (QUEUE_SUBMIT included), in a GLFW
// window on the X server the test runs under (xvfb-run): frames through the executor's
// Swapchain, re-creation on resize, pausing at 0x0, the application's own swapchain images,
// and the negative controls that prove the checks can fail (the acquire wait left out, or at
// stages after the image's first use).
#include "renderer_access.hpp"
#include "compiled_graph_access.hpp"
#include "plan_editor.hpp"

#include "generic_passes.hpp"

#include "app/live_graph.hpp"
#include "app/procedural_environment.hpp"

#include <skygraph/compiled_graph.hpp>
#include <skygraph/compiler.hpp>
#include <skygraph/device.hpp>
#include <skygraph/image_data.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/swapchain.hpp>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>

#include <unistd.h>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace skygraph::test {
namespace {

std::string formatMessages(const Device& d) {
    std::string s;
    for (const auto& m : d.messages()) s += "  [" + m.idName + "] " + m.message.substr(0, 800) + "\n";
    return s;
}

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

/// A window, a presenting device with validation, per test.
class Present : public ::testing::Test {
protected:
    void SetUp() override {
        ASSERT_EQ(glfwInit(), GLFW_TRUE) << "no X server: run under xvfb-run";
        glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
        window_ = glfwCreateWindow(96, 64, "skygraph present test", nullptr, nullptr);
        ASSERT_NE(window_, nullptr);
        DeviceOptions o;
        o.validation = true;
        o.logMessages = std::getenv("SKYGRAPH_TEST_QUIET") == nullptr;
        o.device = "llvmpipe";
        PresentationOptions p;
        uint32_t n = 0;
        const char** names = glfwGetRequiredInstanceExtensions(&n);
        for (uint32_t i = 0; i < n; ++i) p.instanceExtensions.emplace_back(names[i]);
        GLFWwindow* window = window_;
        p.createSurface = [window](VkInstance instance) {
            VkSurfaceKHR surface = VK_NULL_HANDLE;
            glfwCreateWindowSurface(instance, window, nullptr, &surface);
            return surface;
        };
        o.presentation = std::move(p);
        device_ = Device::create(o);
    }
    void TearDown() override {
        // Negative controls check and clear the messages they expect; anything else fails.
        if (device_) expectSilent();
        device_.reset();
        if (window_) glfwDestroyWindow(window_);
        glfwTerminate();
    }

    /// Renders `frames` frames through `swapchain`, polling the window's events between.
    static void present(Renderer& renderer, Swapchain& swapchain, int frames) {
        for (int i = 0; i < frames; ++i) {
            glfwPollEvents();
            EXPECT_EQ(renderer.renderFrame(swapchain), PresentStatus::Presented);
        }
        renderer.waitIdle();
    }

    void expectSilent() { EXPECT_EQ(device_->messageCount(), 0u) << formatMessages(*device_); }

    GLFWwindow* window_ = nullptr;
    std::unique_ptr<Device> device_;
};

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

TEST_F(Present, ResizeRecreatesTheSwapchainAndRecompiles) {
    auto swapchain = Swapchain::create(*device_, raster(96, 64), {96, 64, PresentMode::Fifo});
    Renderer renderer(*device_, raster(96, 64), genericOptions(2));
    glfwSetWindowUserPointer(window_, swapchain.get());
    glfwSetFramebufferSizeCallback(window_, [](GLFWwindow* w, int width, int height) {
        static_cast<Swapchain*>(glfwGetWindowUserPointer(w))->resize(uint32_t(width), uint32_t(height));
    });
    present(renderer, *swapchain, 4);
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{{130, 90}, {40, 30}}) {
        glfwSetWindowSize(window_, w, h);
        // The X server answers the resize asynchronously; wait for the size to arrive.
        for (int i = 0; i < 200; ++i) {
            int fw = 0, fh = 0;
            glfwWaitEventsTimeout(0.01);
            glfwGetFramebufferSize(window_, &fw, &fh);
            if (fw == w && fh == h) break;
        }
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
    // The compute tonemap's target edited to R8G8B8A8_UNORM (a storage image): lavapipe's X11
    // surface offers B8G8R8A8 only.
    GraphDesc graph = loadGraphFile(std::string(SKYGRAPH_SOURCE_DIR) + "/graphs/raster.json",
                                    PassRegistry::withBuiltins());
    for (ResourceDesc& r : graph.resources)
        if (r.name == "swapchain_storage") r.format = *findFormat(VK_FORMAT_R8G8B8A8_UNORM);
    CompileOptions o;
    o.outputWidth = 96;
    o.outputHeight = 64;
    o.features = {{"compute_tonemap", true}};
    const CompiledGraph compiled(std::move(graph), o);
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

/// The application's own swapchain: its images given with setPresentImages, its semaphores
/// in each PresentTarget, its present.
TEST_F(Present, OwnSwapchainImagesAndSemaphores) {
    const VkDevice vkd = device_->device();
    VkSurfaceCapabilitiesKHR caps;
    ASSERT_EQ(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(device_->physicalDevice(), device_->surface(), &caps),
              VK_SUCCESS);
    const CompiledGraph compiled = raster(caps.currentExtent.width, caps.currentExtent.height);
    const PresentRequirements need = presentRequirements(compiled);
    VkSwapchainCreateInfoKHR ci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    ci.surface = device_->surface();
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
        renderer.setPresentImages(images);
        for (int frame = 0; frame < 12; ++frame) {
            const uint32_t slot = renderer.waitForFrameSlot();  // acquired[slot] is free again
            uint32_t image = 0;
            ASSERT_EQ(vkAcquireNextImageKHR(vkd, swapchain, UINT64_MAX, acquired[slot], VK_NULL_HANDLE, &image),
                      VK_SUCCESS);
            renderer.renderFrame(PresentTarget{image, acquired[slot], done[image]});
            VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
            pi.waitSemaphoreCount = 1;
            pi.pWaitSemaphores = &done[image];
            pi.swapchainCount = 1;
            pi.pSwapchains = &swapchain;
            pi.pImageIndices = &image;
            ASSERT_EQ(vkQueuePresentKHR(device_->queue(), &pi), VK_SUCCESS);
        }
        EXPECT_THROW(renderer.renderFrame(PresentTarget{n, acquired[0], done[0]}), ExecutorError);
        renderer.waitIdle();
        vkQueueWaitIdle(device_->queue());
    }
    for (auto s : acquired) vkDestroySemaphore(vkd, s, nullptr);
    for (auto s : done) vkDestroySemaphore(vkd, s, nullptr);
    vkDestroySwapchainKHR(vkd, swapchain, nullptr);
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

// `skygraph view`'s environment change (LiveGraph::setEnvironmentFile): a file of the running
// one's size is re-baked on the compute queue beside the presented frames and swapped in
// between two of them, with no rebuild and no validation message.
/// `skygraph view`'s LiveGraph of graphs/raster.json with `scene`, presenting to a 96x64
/// window, two frames in flight, screenshots allowed; frame() polls and presents one frame.
struct LiveWindow {
    LiveWindow(Device& device, const std::string& scene) : LiveWindow(device, options(scene)) {}
    LiveWindow(Device& device, app::RenderOptions o)
        : live(device, std::move(o), 96, 64, false),
          swapchain(Swapchain::create(device, live.renderer().compiled(), swapchainOptions())) {
        live.presentTo(*swapchain);
    }
    static SwapchainOptions swapchainOptions() {
        SwapchainOptions o{96, 64, PresentMode::Fifo};
        o.extraUsage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT;  // screenshots read the presented image back, as in the view
        return o;
    }
    static app::RenderOptions options(const std::string& scene) {
        static const PassLibrary library = PassLibrary::withBuiltins();
        const std::filesystem::path root = SKYGRAPH_SOURCE_DIR;
        app::RenderOptions o;
        o.graph = root / "graphs/raster.json";
        o.scene = root / scene;
        o.framesInFlight = 2;
        o.passes = &library;
        return o;
    }
    void frame() {
        glfwPollEvents();
        live.poll();
        EXPECT_EQ(live.renderFrame(*swapchain), PresentStatus::Presented);
    }
    /// The next presented frame, read back as the view's screenshots are.
    ImageData screen() {
        EXPECT_TRUE(live.beginScreenshot()) << live.error();
        frame();
        live.renderer().waitIdle();
        ImageData image = live.renderer().readback();
        (void)live.finishScreenshot({});  // writes nothing (false), compiles the plan back
        EXPECT_EQ(live.error(), "");
        return image;
    }
    /// Presents frames until the re-bake under way is swapped in, 100 at most; how many.
    int framesUntilRebaked() {
        int frames = 0;
        for (; live.rebaking() && frames < 100; ++frames) frame();
        return frames;
    }
    app::LiveGraph live;
    std::unique_ptr<Swapchain> swapchain;
};

/// The mean of an image's colour channels.
double meanColour(const ImageData& image) {
    double sum = 0.0;
    for (size_t i = 0; i < image.rgba.size(); ++i) sum += i % 4 == 3 ? 0.0 : image.rgba[i];
    return sum / (double(image.rgba.size()) * 0.75);
}

/// An environment file in the temporary folder, every texel `texel`; its path.
std::filesystem::path writeUniformSky(const std::string& name, uint32_t width, uint32_t height,
                                      std::array<float, 4> texel) {
    ImageData sky;
    sky.width = width;
    sky.height = height;
    sky.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    for (uint32_t i = 0; i < width * height; ++i) sky.rgba.insert(sky.rgba.end(), texel.begin(), texel.end());
    const std::filesystem::path file = std::filesystem::temp_directory_path() / name;
    writeHdr(file, sky);
    return file;
}

TEST_F(Present, AnEnvironmentChangeIsRebakedBesideTheFrames) {
    LiveWindow w(*device_, "scenes/studio.json");
    app::LiveGraph& live = w.live;
    for (int i = 0; i < 3; ++i) w.frame();
    const Renderer* running = &live.renderer();
    const uint32_t reloads = live.reloads();
    const std::filesystem::path file =
        loadSceneFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "scenes/studio.json").environment->file;
    ASSERT_TRUE(live.setEnvironmentFile(file)) << live.error();
    EXPECT_TRUE(live.rebaking());
    const int frames = w.framesUntilRebaked();
    EXPECT_FALSE(live.rebaking()) << "not swapped in after " << frames << " frames";
    EXPECT_GE(frames, 1);
    EXPECT_EQ(&live.renderer(), running) << "the change rebuilt the renderer";
    EXPECT_EQ(live.reloads(), reloads + 1);
    for (int i = 0; i < 3; ++i) w.frame();
    live.renderer().waitIdle();
    expectSilent();
}

// A file of another size than the running equirect is resampled to it and re-baked beside
// the frames too: no rebuild, no hitch, no validation message.
TEST_F(Present, AnEnvironmentFileOfAnotherSizeIsResampledAndRebakedBesideTheFrames) {
    LiveWindow w(*device_, "scenes/studio.json");
    app::LiveGraph& live = w.live;
    for (int i = 0; i < 3; ++i) w.frame();
    const Renderer* running = &live.renderer();
    const uint32_t reloads = live.reloads();
    const auto equirect = live.renderer().graph().findResource("equirect")->extent.resolve(96, 64);
    // Neither the running size nor a multiple of it.
    const std::filesystem::path file =
        writeUniformSky("skygraph-other-size.hdr", equirect[0] / 2 + 3, equirect[1] / 2 + 1, {0.5f, 1.0f, 2.0f, 1.0f});
    ASSERT_TRUE(live.setEnvironmentFile(file)) << live.error();
    EXPECT_TRUE(live.rebaking()) << "re-baked beside the frames, not rebuilt";
    const int frames = w.framesUntilRebaked();
    EXPECT_FALSE(live.rebaking()) << "not swapped in after " << frames << " frames";
    EXPECT_EQ(&live.renderer(), running) << "the change rebuilt the renderer";
    EXPECT_EQ(live.reloads(), reloads + 1);
    for (int i = 0; i < 3; ++i) w.frame();
    live.renderer().waitIdle();
    std::filesystem::remove(file);
    expectSilent();
}

// The procedural sky has a skybox of its own (the scene's feature environment_file): a file
// loaded in its place rebuilds the plan, so that the sky drawn is the file's, as the lighting is.
TEST_F(Present, AnEnvironmentFileInPlaceOfTheProceduralSkyRebuildsWithItsSkybox) {
    LiveWindow w(*device_, "scenes/default.json");
    app::LiveGraph& live = w.live;
    for (int i = 0; i < 3; ++i) w.frame();
    ASSERT_TRUE(live.scene()->environment->procedural);
    ASSERT_FALSE(live.feature("environment_file"));
    const std::filesystem::path file =
        loadSceneFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "scenes/studio.json").environment->file;
    ASSERT_TRUE(live.setEnvironmentFile(file)) << live.error();
    EXPECT_FALSE(live.rebaking()) << "re-baked beside the frames under the procedural sky's skybox";
    EXPECT_TRUE(live.feature("environment_file"));
    EXPECT_FALSE(live.scene()->environment->procedural);
    for (int i = 0; i < 3; ++i) w.frame();
    live.renderer().waitIdle();
    expectSilent();
}

// A rebuild while an environment file is still decoding (a checkbox clicked meanwhile) builds
// with that file rather than dropping it.
TEST_F(Present, ARebuildWhileAnEnvironmentFileDecodesBuildsWithTheFile) {
    LiveWindow w(*device_, "scenes/studio.json");
    app::LiveGraph& live = w.live;
    for (int i = 0; i < 3; ++i) w.frame();
    const std::filesystem::path file = writeUniformSky(
        "skygraph-decoding-" + std::to_string(::getpid()) + ".hdr", 64, 32, {0.75f, 0.75f, 0.75f, 0.75f});
    ASSERT_TRUE(live.setEnvironmentFile(file)) << live.error();
    ASSERT_TRUE(live.rebaking()) << "decoding beside the frames";
    ASSERT_TRUE(live.setFeature("skybox", false)) << live.error();
    EXPECT_FALSE(live.rebaking());
    EXPECT_EQ(live.scene()->environment->file, file) << "the rebuild dropped the file";
    EXPECT_TRUE(live.error().empty()) << live.error();
    for (int i = 0; i < 3; ++i) w.frame();
    live.renderer().waitIdle();
    std::filesystem::remove(file);
    expectSilent();
}

// The file is decoded on a thread of its own: setEnvironmentFile returns at once, and a file
// that cannot be read is reported once its decoding fails, naming it; the sky stays as it was.
TEST_F(Present, AnUnreadableEnvironmentFileIsReportedAndTheSkyStays) {
    LiveWindow w(*device_, "scenes/studio.json");
    app::LiveGraph& live = w.live;
    for (int i = 0; i < 3; ++i) w.frame();
    const Renderer* running = &live.renderer();
    const uint32_t reloads = live.reloads();
    const std::filesystem::path file = std::filesystem::temp_directory_path() / "skygraph-unreadable.exr";
    std::ofstream(file) << "not an EXR file";
    ASSERT_TRUE(live.setEnvironmentFile(file)) << live.error();
    EXPECT_TRUE(live.rebaking()) << "decoding beside the frames";
    const int frames = w.framesUntilRebaked();
    EXPECT_FALSE(live.rebaking()) << "still loading after " << frames << " frames";
    EXPECT_NE(live.error().find(file.string()), std::string::npos) << live.error();
    EXPECT_EQ(&live.renderer(), running) << "nothing was rebuilt";
    EXPECT_EQ(live.reloads(), reloads);
    for (int i = 0; i < 3; ++i) w.frame();
    live.renderer().waitIdle();
    std::filesystem::remove(file);
    expectSilent();
}

/// graphs/raster.json and graphs/ibl.json copied into a new folder (`prefix` and the process
/// id) of the temporary folder, for a test that saves them; the folder.
std::filesystem::path copyOfTheGraphs(const std::string& prefix) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    for (const char* graph : {"raster.json", "ibl.json"})
        std::filesystem::copy_file(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / graph, dir / graph);
    return dir;
}

/// A LiveWindow's options with the copy's raster.json as the graph.
app::RenderOptions optionsForTheCopy(const std::filesystem::path& dir, const std::string& scene) {
    app::RenderOptions o = LiveWindow::options(scene);
    o.graph = dir / "raster.json";
    return o;
}

// A saved graph that does not load keeps its message on screen while an environment file is
// loaded and re-baked beside the frames: the save is still not built.
TEST_F(Present, ASaveThatDidNotBuildKeepsItsMessageThroughAnEnvironmentChange) {
    const std::filesystem::path root = SKYGRAPH_SOURCE_DIR;
    const std::filesystem::path dir = copyOfTheGraphs("skygraph-save-");
    LiveWindow w(*device_, optionsForTheCopy(dir, "scenes/studio.json"));
    app::LiveGraph& live = w.live;
    for (int i = 0; i < 3; ++i) w.frame();
    std::ofstream(dir / "raster.json", std::ios::trunc) << "{ \"version\": 1, \"passes\": [ ";
    w.frame();
    ASSERT_NE(live.error().find("raster.json"), std::string::npos) << live.error();
    const std::filesystem::path file = loadSceneFile(root / "scenes/studio.json").environment->file;
    ASSERT_TRUE(live.setEnvironmentFile(file)) << live.error();
    const int frames = w.framesUntilRebaked();
    EXPECT_FALSE(live.rebaking()) << "not swapped in after " << frames << " frames";
    EXPECT_NE(live.error().find("raster.json"), std::string::npos) << "the save's message went: " << live.error();
    live.renderer().waitIdle();
    std::filesystem::remove_all(dir);
    expectSilent();
}

// graphs/ibl.json beside the graph is part of the frame's graphs: a save of it builds and bakes
// again, and one that does not load is reported while the frames go on.
TEST_F(Present, ASavedEnvironmentGraphBakesTheEnvironmentAgain) {
    const std::filesystem::path dir = copyOfTheGraphs("skygraph-ibl-save-");
    std::string ibl;
    {
        std::ifstream in(dir / "ibl.json");
        ibl.assign(std::istreambuf_iterator<char>(in), {});
    }
    LiveWindow w(*device_, optionsForTheCopy(dir, "scenes/studio.json"));
    app::LiveGraph& live = w.live;
    const ImageData lit = w.screen();
    const Renderer* running = &live.renderer();
    const uint32_t reloads = live.reloads();

    std::ofstream(dir / "ibl.json", std::ios::trunc) << "{ \"version\": 1, \"passes\": [ ";
    w.frame();
    EXPECT_NE(live.error().find((dir / "ibl.json").string()), std::string::npos) << live.error();
    EXPECT_EQ(&live.renderer(), running) << "a graph that does not load replaced the running frames";

    // The irradiance integrated from 4 samples instead of 1024: the spheres' diffuse light changes.
    const std::string samples = "\"IrradiancePass\",\n      \"uses\": {\n        \"environment\": \"Read@Compute\",\n"
                                "        \"irradiance\": \"Write@Compute\"\n      },\n      \"params\": {\n        \"samples\": 1024";
    ASSERT_NE(ibl.find(samples), std::string::npos);
    ibl.replace(ibl.find(samples) + samples.size() - 4, 4, "4");
    std::ofstream(dir / "ibl.json", std::ios::trunc) << ibl;
    w.frame();
    EXPECT_EQ(live.error(), "");
    EXPECT_NE(&live.renderer(), running) << "the saved environment graph was not built";
    EXPECT_EQ(live.reloads(), reloads + 1);
    EXPECT_NE(w.screen().rgba, lit.rgba) << "the environment was not baked from the saved graph";
    live.renderer().waitIdle();
    std::filesystem::remove_all(dir);
    expectSilent();
}

// An environment graph saved beside the graph after the view started is built as a save of it.
TEST_F(Present, AnEnvironmentGraphSavedBesideTheGraphLaterIsBuilt) {
    const std::filesystem::path dir = copyOfTheGraphs("skygraph-ibl-later-");
    std::filesystem::rename(dir / "ibl.json", dir / "ibl.json.away");
    LiveWindow w(*device_, optionsForTheCopy(dir, "scenes/studio.json"));
    app::LiveGraph& live = w.live;
    const ImageData unlit = w.screen();
    const Renderer* running = &live.renderer();
    const uint32_t reloads = live.reloads();
    std::filesystem::rename(dir / "ibl.json.away", dir / "ibl.json");
    w.frame();
    EXPECT_EQ(live.error(), "");
    EXPECT_NE(&live.renderer(), running) << "the environment graph saved later was not built";
    EXPECT_EQ(live.reloads(), reloads + 1);
    EXPECT_NE(w.screen().rgba, unlit.rgba) << "the environment was not baked";
    live.renderer().waitIdle();
    std::filesystem::remove_all(dir);
    expectSilent();
}

// The environment is baked once, by a renderer of its own: an edit to one of its shaders (the
// watcher sees every edit in the shader folder) bakes it again in a rebuild. A broken one is
// reported and the frames go on; an edit to a frame shader only reloads the frame's pipelines.
TEST_F(Present, AnEditedEnvironmentShaderBakesTheEnvironmentAgain) {
    namespace fs = std::filesystem;
    const fs::path shaders = fs::temp_directory_path() / ("skygraph-shaders-" + std::to_string(::getpid()));
    fs::remove_all(shaders);
    fs::copy(fs::path(SKYGRAPH_SOURCE_DIR) / "shaders", shaders, fs::copy_options::recursive);
    // Restored however the test ends: later tests must read the real shaders.
    struct ShaderDirForTheTest {
        explicit ShaderDirForTheTest(const fs::path& dir) : dir_(dir) {
            if (const char* before = std::getenv("SKYGRAPH_SHADER_DIR")) previous_ = before;
            setenv("SKYGRAPH_SHADER_DIR", dir.c_str(), 1);
        }
        ~ShaderDirForTheTest() {
            if (previous_) setenv("SKYGRAPH_SHADER_DIR", previous_->c_str(), 1);
            else unsetenv("SKYGRAPH_SHADER_DIR");
            std::error_code ignored;
            fs::remove_all(dir_, ignored);
        }
        fs::path dir_;
        std::optional<std::string> previous_;
    };
    {
        const ShaderDirForTheTest shaderDir(shaders);
        LiveWindow w(*device_, "scenes/studio.json");
        app::LiveGraph& live = w.live;
        const ImageData lit = w.screen();
        const Renderer* running = &live.renderer();
        uint32_t reloads = live.reloads();

        std::ofstream(shaders / "passes/tonemap.frag", std::ios::app) << "\n// an edit to a frame shader\n";
        w.frame();
        EXPECT_EQ(&live.renderer(), running) << "a frame shader's edit baked the environment again";
        EXPECT_EQ(live.reloads(), reloads + 1);
        const ImageData same = w.screen();
        EXPECT_EQ(same.rgba, lit.rgba) << "a comment in a frame shader changed the frame";

        const fs::path cube = shaders / "passes/ibl/equirect_to_cube.comp";
        std::string source;
        {
            std::ifstream in(cube);
            source.assign(std::istreambuf_iterator<char>(in), {});
        }
        std::ofstream(cube, std::ios::app) << "\nthis is not GLSL\n";
        w.frame();
        EXPECT_EQ(&live.renderer(), running) << "a bake that failed replaced the running frames";
        EXPECT_NE(live.error().find("equirect_to_cube.comp"), std::string::npos) << live.error();
        // A checkbox meanwhile rebuilds from the running bake's shaders, as from the frame's.
        const bool compute = live.feature("compute_tonemap");
        ASSERT_TRUE(live.setFeature("compute_tonemap", !compute)) << live.error();
        ASSERT_TRUE(live.setFeature("compute_tonemap", compute)) << live.error();
        EXPECT_NE(live.error().find("equirect_to_cube.comp"), std::string::npos) << "the broken shader's message went";
        running = &live.renderer();
        reloads = live.reloads();
        std::ofstream(cube, std::ios::trunc) << source;  // undone: the bake that runs is on disk again
        w.frame();
        EXPECT_EQ(&live.renderer(), running) << "undoing the edit baked the environment again";
        EXPECT_EQ(live.error(), "") << "the undone edit's message stayed";

        // The environment cube black: the spheres lose their light; the sky, drawn from the
        // equirect (the scene's "sampling"), stays.
        const std::string sample = "vec4(sum / float(n * n), 1.0)";
        ASSERT_NE(source.find(sample), std::string::npos);
        source.replace(source.find(sample), sample.size(), "vec4(0.0, 0.0, 0.0, 1.0)");
        std::ofstream(cube, std::ios::trunc) << source;
        w.frame();
        EXPECT_NE(&live.renderer(), running) << "the edited environment shader was not baked";
        EXPECT_EQ(live.error(), "");
        EXPECT_EQ(live.reloads(), reloads + 2) << "the undo's reload and the bake";
        const ImageData dark = w.screen();
        EXPECT_LT(meanColour(dark), 0.9 * meanColour(lit)) << "the spheres are still lit by the old bake";
        live.renderer().waitIdle();
    }
    expectSilent();
}

// Moving the procedural sky's sun re-bakes its lighting beside the frames as a file change
// does; a second move while the first bake runs is baked after it, and nothing rebuilds.
TEST_F(Present, MovingTheSunRebakesTheSkysLightingBesideTheFrames) {
    LiveWindow w(*device_, "scenes/default.json");
    app::LiveGraph& live = w.live;
    for (int i = 0; i < 3; ++i) w.frame();
    const Renderer* running = &live.renderer();
    const uint32_t reloads = live.reloads();
    ASSERT_TRUE(live.setSunDirection({0.0, 1.0, 0.0})) << live.error();
    EXPECT_TRUE(live.rebaking());
    ASSERT_TRUE(live.setSunDirection({0.6, 0.8, 0.0})) << "queued behind the running bake";
    EXPECT_EQ(live.scene()->environment->sunDirection, (Vec3{0.6, 0.8, 0.0})) << "the skybox's sun moves at once";
    int frames = 0;
    while ((live.rebaking() || live.reloads() < reloads + 2) && frames < 200) {
        w.frame();
        ++frames;
    }
    EXPECT_FALSE(live.rebaking()) << "not swapped in after " << frames << " frames";
    EXPECT_EQ(live.reloads(), reloads + 2) << "two bakes: the first move, then the latest";
    EXPECT_EQ(&live.renderer(), running) << "moving the sun rebuilt the renderer";
    for (int i = 0; i < 3; ++i) w.frame();
    live.renderer().waitIdle();
    expectSilent();
}

// An environment sequence plays beside the frames: each frame due is decoded on the stream's
// thread, baked beside the frames and swapped in, and the sky fades to it from the frame
// before over one frame of the sequence; over an unreadable frame the sky holds the last one
// (never black), and playback loops. Nothing rebuilds, and validation stays silent.
TEST_F(Present, AnEnvironmentSequencePlaysBesideTheFramesAndHoldsOverAnUnreadableFrame) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "skygraph-present-sequence";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string pattern = (dir / "sky_%02d.exr").string();
    app::writeProceduralSkySequence(pattern, 4, 64);  // the sun circles the sky: frame 0 ahead, 1 to the right
    std::ofstream(sequenceFrameFile(pattern, 2), std::ios::binary) << "not an EXR";
    std::ofstream(dir / "scene.json") << R"({"environment": {"sequence": "sky_%02d.exr", "fps": 10}})";
    LiveWindow w(*device_, (dir / "scene.json").string());
    app::LiveGraph& live = w.live;
    ASSERT_NE(live.sequence(), nullptr);
    const Renderer* running = &live.renderer();
    const uint32_t reloads = live.reloads();
    const auto screen = [&] { return w.screen(); };
    const auto difference = [](const ImageData& a, const ImageData& b) {
        double most = 0.0;
        for (size_t i = 0; i < a.rgba.size() && i < b.rgba.size(); ++i) most = std::max(most, double(std::abs(a.rgba[i] - b.rgba[i])));
        return most;
    };
    /// Plays at `seconds` until `done` holds, for 300 frames at most.
    const auto playUntil = [&](double seconds, auto done) {
        for (int i = 0; i < 300 && !done(live.sequence()->stats()); ++i) {
            w.frame();
            live.playSequence(seconds);
        }
        EXPECT_TRUE(done(live.sequence()->stats())) << "at " << seconds << " s";
    };
    for (int i = 0; i < 3; ++i) w.frame();
    live.playSequence(0.0);  // playback starts: frame 0, baked with the renderer, is on screen
    const ImageData first = screen();

    playUntil(0.1, [](const app::SequenceStats& s) { return s.current == 1u; });
    EXPECT_LT(difference(first, screen()), 1e-6) << "the fade starts from the frame shown before";
    w.frame();
    live.playSequence(0.15);  // half way: the fade lasts one frame of the sequence
    const ImageData half = screen();

    playUntil(0.2, [](const app::SequenceStats& s) { return s.failed == 1u; });
    const ImageData second = screen();
    EXPECT_GT(meanColour(second), 0.05) << "a sky, not black";
    EXPECT_GT(difference(first, second), 0.2) << "the sun left the view: the sky changed with the frame";
    EXPECT_GT(difference(first, half), 0.05) << "half way, neither frame";
    EXPECT_GT(difference(half, second), 0.05) << "half way, neither frame";
    for (int i = 0; i < 3; ++i) {
        w.frame();
        live.playSequence(0.25);
    }
    EXPECT_EQ(live.sequence()->stats().current, 1u) << "the sky holds frame 1 over the unreadable frame 2";
    EXPECT_EQ(difference(second, screen()), 0.0);

    playUntil(0.3, [](const app::SequenceStats& s) { return s.current == 3u; });
    playUntil(0.45, [](const app::SequenceStats& s) { return s.current == 0u && s.shown == 4u; });  // looped
    const app::SequenceStats stats = live.sequence()->stats();
    w.frame();
    live.playSequence(0.58);  // the fade from frame 3 is over; frame 1 is due, and fades in from frame 0 if swapped in
    EXPECT_LT(difference(first, screen()), 1e-6) << "frame 0 again, as at the start";
    EXPECT_EQ(stats.shown, 4u) << "frames 0, 1, 3 and 0 again";
    EXPECT_EQ(stats.dropped, 1u);
    EXPECT_EQ(stats.late, 0u) << "playback's clock waited for every bake";
    EXPECT_EQ(&live.renderer(), running) << "playback rebuilt the renderer";
    EXPECT_EQ(live.reloads(), reloads) << "a sequence's frames are not reloads";
    live.renderer().waitIdle();
    std::filesystem::remove_all(dir);
    expectSilent();
}

// A rebuild (a checkbox, F1, a saved graph) goes on with playback: it bakes the environment
// from the frame on screen, or from the one being baked, and the clock and the stats carry on.
TEST_F(Present, AnEnvironmentSequencePlaysOnThroughARebuild) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "skygraph-present-sequence-rebuild";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    app::writeProceduralSkySequence((dir / "sky_%02d.exr").string(), 4, 64);  // the sun circles the sky
    std::ofstream(dir / "scene.json") << R"({"environment": {"sequence": "sky_%02d.exr", "fps": 10}})";
    LiveWindow w(*device_, (dir / "scene.json").string());
    app::LiveGraph& live = w.live;
    ASSERT_NE(live.sequence(), nullptr);
    const auto playUntil = [&](double seconds, auto done) {
        for (int i = 0; i < 300 && !done(live.sequence()->stats()); ++i) {
            w.frame();
            live.playSequence(seconds);
        }
        EXPECT_TRUE(done(live.sequence()->stats())) << "at " << seconds << " s";
    };
    const auto difference = [](const ImageData& a, const ImageData& b) {
        double most = 0.0;
        for (size_t i = 0; i < a.rgba.size() && i < b.rgba.size(); ++i) most = std::max(most, double(std::abs(a.rgba[i] - b.rgba[i])));
        return most;
    };
    for (int i = 0; i < 3; ++i) w.frame();
    live.playSequence(0.0);
    const ImageData first = w.screen();
    playUntil(0.1, [](const app::SequenceStats& s) { return s.current == 1u; });

    // Off and on again: two rebuilds, each baking frame 1, the frame on screen.
    const uint32_t reloads = live.reloads();
    ASSERT_TRUE(live.setFeature("compute_tonemap", !live.feature("compute_tonemap"))) << live.error();
    ASSERT_TRUE(live.setFeature("compute_tonemap", !live.feature("compute_tonemap"))) << live.error();
    EXPECT_EQ(live.reloads(), reloads + 2);
    ASSERT_NE(live.sequence(), nullptr);
    for (int i = 0; i < 3; ++i) {
        w.frame();
        live.playSequence(0.15);  // frame 1's time still: nothing to bake
    }
    EXPECT_FALSE(live.rebaking());
    app::SequenceStats stats = live.sequence()->stats();
    EXPECT_EQ(stats.current, 1u) << "playback started again";
    EXPECT_EQ(stats.shown, 2u);
    EXPECT_EQ(stats.dropped, 0u);
    EXPECT_GT(difference(first, w.screen()), 0.2) << "the rebuild baked frame 0, not the frame on screen";

    // A rebuild while frame 2 is being baked bakes frame 2 itself.
    for (int i = 0; i < 300 && !live.rebaking(); ++i) {
        w.frame();
        live.playSequence(0.2);
    }
    ASSERT_TRUE(live.rebaking()) << "frame 2's bake never started";
    ASSERT_TRUE(live.setFeature("compute_tonemap", !live.feature("compute_tonemap"))) << live.error();
    EXPECT_FALSE(live.rebaking());
    stats = live.sequence()->stats();
    EXPECT_EQ(stats.current, 2u);
    EXPECT_EQ(stats.shown, 3u);
    playUntil(0.3, [](const app::SequenceStats& s) { return s.current == 3u; });
    stats = live.sequence()->stats();
    EXPECT_EQ(stats.shown, 4u) << "frames 0, 1, 2 and 3";
    EXPECT_EQ(stats.dropped, 0u);

    // The frame on screen cannot be read now: the rebuild bakes the first frame, and playback
    // starts again from it rather than refusing the rebuild.
    std::ofstream(sequenceFrameFile((dir / "sky_%02d.exr").string(), 3), std::ios::trunc) << "not an EXR";
    ASSERT_TRUE(live.setFeature("compute_tonemap", !live.feature("compute_tonemap"))) << live.error();
    EXPECT_EQ(live.error(), "");
    ASSERT_NE(live.sequence(), nullptr);
    EXPECT_EQ(live.sequence()->stats().current, 0u);
    EXPECT_EQ(live.sequence()->stats().shown, 1u);
    live.renderer().waitIdle();
    std::filesystem::remove_all(dir);
    expectSilent();
}

}  // namespace
}  // namespace skygraph::test
