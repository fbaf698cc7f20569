// Device selection when presenting: the reasons a device cannot be used, worked out without a
// device (device_selection.hpp), the error messages that name the device, and the same end to
// end with a real window that lavapipe cannot present to: Mesa's X11 presentation supports
// only TrueColor and DirectColor windows, so a window on an 8-bit (PseudoColor) screen of an
// X server of the test's own is a real surface that no queue family of lavapipe presents to.
#include "device_selection.hpp"

#include <skygraph/device.hpp>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace skygraph::test {
namespace {

using detail::DeviceCandidate;
using detail::noDeviceMessage;
using detail::PhysicalDeviceFacts;
using detail::QueueFamilyFacts;
using detail::unsuitableReason;

/// Vulkan 1.3, push descriptors, synchronization2, separate depth/stencil layouts, timeline
/// semaphores, VK_KHR_swapchain; `families` as given.
PhysicalDeviceFacts capable(std::vector<QueueFamilyFacts> families) {
    PhysicalDeviceFacts f;
    f.apiVersion = VK_API_VERSION_1_3;
    f.pushDescriptor = f.synchronization2 = f.swapchain = true;
    f.separateDepthStencilLayouts = f.timelineSemaphore = true;
    f.families = std::move(families);
    return f;
}

constexpr QueueFamilyFacts kTransferOnly{false, true, true};
constexpr QueueFamilyFacts kRendersNoPresent{true, true, false};
constexpr QueueFamilyFacts kRendersAndPresents{true, true, true};

TEST(DeviceSelectionReason, TheFirstRenderingFamilyThatPresents) {
    uint32_t family = 99;
    EXPECT_EQ(unsuitableReason(capable({kTransferOnly, kRendersNoPresent, kRendersAndPresents}), true, family), "");
    EXPECT_EQ(family, 2u);
    // Headless: presenting does not matter; the first family that renders.
    EXPECT_EQ(unsuitableReason(capable({kTransferOnly, kRendersNoPresent, kRendersAndPresents}), false, family), "");
    EXPECT_EQ(family, 1u);
}

TEST(DeviceSelectionReason, NoFamilyPresentsToTheSurface) {
    uint32_t family = 0;
    // A transfer family that presents does not count: the frame's queue must present.
    const std::string why = unsuitableReason(capable({kTransferOnly, kRendersNoPresent}), true, family);
    EXPECT_NE(why.find("cannot present to the surface"), std::string::npos) << why;
    EXPECT_EQ(unsuitableReason(capable({kTransferOnly, kRendersNoPresent}), false, family), "");
}

TEST(DeviceSelectionReason, EveryOtherReason) {
    uint32_t family = 0;
    PhysicalDeviceFacts f = capable({kRendersAndPresents});
    f.swapchain = false;
    EXPECT_EQ(unsuitableReason(f, true, family), "cannot present: it lacks VK_KHR_swapchain");
    EXPECT_EQ(unsuitableReason(f, false, family), "");  // headless needs no swapchain
    f = capable({QueueFamilyFacts{true, false, true}});
    EXPECT_EQ(unsuitableReason(f, false, family), "has no graphics+compute queue with timestamps");
    f = capable({kRendersAndPresents});
    f.synchronization2 = false;
    EXPECT_EQ(unsuitableReason(f, false, family), "lacks synchronization2");
    // Found while choosing, so that another device that has them is chosen instead.
    f = capable({kRendersAndPresents});
    f.separateDepthStencilLayouts = false;
    EXPECT_EQ(unsuitableReason(f, false, family), "lacks separateDepthStencilLayouts");
    f = capable({kRendersAndPresents});
    f.timelineSemaphore = false;
    EXPECT_EQ(unsuitableReason(f, false, family), "lacks timelineSemaphore");
    f = capable({kRendersAndPresents});
    f.missingExtension = "VK_EXT_conditional_rendering";
    EXPECT_EQ(unsuitableReason(f, false, family),
              "lacks VK_EXT_conditional_rendering, which DeviceOptions::deviceExtensions asks for");
    f = capable({kRendersAndPresents});
    f.pushDescriptor = false;
    EXPECT_EQ(unsuitableReason(f, false, family), "lacks VK_KHR_push_descriptor");
    f = capable({kRendersAndPresents});
    f.apiVersion = VK_API_VERSION_1_2;
    EXPECT_EQ(unsuitableReason(f, true, family), "does not support Vulkan 1.3");
}

const std::string kNoPresent = "cannot present to the surface: no graphics+compute queue family of it presents there";

TEST(DeviceSelectionMessage, TheSelectedDeviceIsNamedWithItsReason) {
    const std::vector<DeviceCandidate> one{{0, "llvmpipe (LLVM 15.0.6, 256 bits)", "CPU", true, kNoPresent}};
    EXPECT_EQ(noDeviceMessage("", true, one),
              "the only Vulkan device, 0 'llvmpipe (LLVM 15.0.6, 256 bits)', " + kNoPresent);
    const std::vector<DeviceCandidate> two{{0, "Some GPU", "discrete GPU", false, ""},
                                           {1, "llvmpipe", "CPU", true, kNoPresent}};
    EXPECT_EQ(noDeviceMessage("llvm", true, two), "--device 'llvm' selects Vulkan device 1 'llvmpipe', which " + kNoPresent);
    EXPECT_EQ(noDeviceMessage("1", true, two), "--device '1' selects Vulkan device 1 'llvmpipe', which " + kNoPresent);
}

TEST(DeviceSelectionMessage, NoneCanPresentListsEachWithItsReason) {
    const std::vector<DeviceCandidate> two{{0, "Some GPU", "discrete GPU", true, "cannot present: it lacks VK_KHR_swapchain"},
                                           {1, "llvmpipe", "CPU", true, kNoPresent}};
    EXPECT_EQ(noDeviceMessage("", true, two),
              "no suitable Vulkan device to present to the window:\n"
              "  0 'Some GPU' (discrete GPU) cannot present: it lacks VK_KHR_swapchain\n"
              "  1 'llvmpipe' (CPU) " + kNoPresent);
    // A filter that matches two of three: those two with reasons, then every device.
    const std::vector<DeviceCandidate> three{{0, "GPU A", "discrete GPU", true, "lacks synchronization2"},
                                             {1, "GPU B", "discrete GPU", true, kNoPresent},
                                             {2, "llvmpipe", "CPU", false, ""}};
    EXPECT_EQ(noDeviceMessage("gpu", true, three),
              "no suitable Vulkan device matches --device 'gpu' to present to the window:\n"
              "  0 'GPU A' (discrete GPU) lacks synchronization2\n"
              "  1 'GPU B' (discrete GPU) " + kNoPresent + "\n"
              "available devices:\n  0: GPU A (discrete GPU)\n  1: GPU B (discrete GPU)\n  2: llvmpipe (CPU)");
}

TEST(DeviceSelectionMessage, NoMatchIsOneLineListingTheDevices) {
    const std::vector<DeviceCandidate> two{{0, "Some GPU", "discrete GPU", false, ""}, {1, "llvmpipe", "CPU", false, ""}};
    EXPECT_EQ(noDeviceMessage("nvidia", true, two),
              "no Vulkan device matches --device 'nvidia'; available devices: 0: Some GPU (discrete GPU), 1: llvmpipe (CPU)");
    EXPECT_EQ(noDeviceMessage("", false, {}), "no Vulkan physical devices found");
}

/// An X server of the test's own with an 8-bit PseudoColor screen (Xvfb -displayfd picks a
/// free display); DISPLAY points at it while this lives.
class PseudoColorServer {
public:
    PseudoColorServer() {
        int fds[2];
        if (pipe(fds) != 0) return;
        const std::string fd = std::to_string(fds[1]);
        std::vector<std::string> args{"Xvfb", "-displayfd", fd, "-screen", "0", "320x240x8", "-nolisten", "tcp"};
        std::vector<char*> argv;
        for (std::string& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        const int spawned = posix_spawnp(&pid_, "Xvfb", nullptr, nullptr, argv.data(), environ);
        close(fds[1]);
        if (spawned != 0) {
            pid_ = -1;
            close(fds[0]);
            return;
        }
        std::string number;
        char c = 0;
        while (read(fds[0], &c, 1) == 1 && c != '\n') number += c;
        close(fds[0]);
        if (number.empty()) return;
        if (const char* d = std::getenv("DISPLAY")) previous_ = d;
        setenv("DISPLAY", (":" + number).c_str(), 1);
        display_ = ":" + number;
    }
    ~PseudoColorServer() {
        if (previous_) setenv("DISPLAY", previous_->c_str(), 1);
        else unsetenv("DISPLAY");
        if (pid_ > 0) {
            kill(pid_, SIGTERM);
            waitpid(pid_, nullptr, 0);
        }
    }
    const std::string& display() const { return display_; }

private:
    pid_t pid_ = -1;
    std::string display_;
    std::optional<std::string> previous_;
};

/// Device::create presenting to `window` (on the PseudoColor screen); the ExecutorError's message.
std::string presentingDeviceError(GLFWwindow* window, const std::string& device) {
    DeviceOptions o;
    o.device = device;
    o.validation = true;
    o.logMessages = std::getenv("SKYGRAPH_TEST_QUIET") == nullptr;
    PresentationOptions p;
    uint32_t n = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&n);
    for (uint32_t i = 0; i < n; ++i) p.instanceExtensions.emplace_back(names[i]);
    p.createSurface = [window](VkInstance instance) {
        VkSurfaceKHR surface = VK_NULL_HANDLE;
        glfwCreateWindowSurface(instance, window, nullptr, &surface);
        return surface;
    };
    o.presentation = std::move(p);
    try {
        (void)Device::create(o);
        ADD_FAILURE() << "a device was made that presents to an 8-bit PseudoColor window";
    } catch (const ExecutorError& e) {
        return e.what();
    }
    return {};
}

void onGlfwError(int code, const char* description) {
    ADD_FAILURE() << "GLFW error " << code << ": " << (description ? description : "");
}

TEST(PresentDevice, ADeviceThatCannotPresentToTheWindowIsNamed) {
    const std::vector<std::string> devices = Device::listDevices();
    ASSERT_EQ(devices.size(), 1u) << "expects lavapipe alone (VK_ICD_FILENAMES)";
    ASSERT_NE(devices[0].find("llvmpipe"), std::string::npos) << devices[0];
    PseudoColorServer server;
    ASSERT_FALSE(server.display().empty()) << "could not start Xvfb";
    const std::string name = devices[0].substr(3, devices[0].rfind(" (") - 3);  // "0: NAME (CPU)"
    // One window for the three devices: connecting to the server once is what a loaded
    // machine (parallel tests) does reliably.
    glfwSetErrorCallback(onGlfwError);
    ASSERT_EQ(glfwInit(), GLFW_TRUE);
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(64, 64, "skygraph: cannot present", nullptr, nullptr);
    ASSERT_NE(window, nullptr);
    // The only device, by index and by name: one line naming it and saying why.
    for (const std::string& filter : {std::string(), std::string("0"), std::string("llvmpipe")}) {
        const std::string what = presentingDeviceError(window, filter);
        SCOPED_TRACE("--device '" + filter + "': " + what);
        EXPECT_NE(what.find("0 '" + name + "'"), std::string::npos);
        EXPECT_NE(what.find(kNoPresent), std::string::npos);
        EXPECT_EQ(what.find('\n'), std::string::npos);
    }
    glfwDestroyWindow(window);
    glfwTerminate();
}

}  // namespace
}  // namespace skygraph::test
