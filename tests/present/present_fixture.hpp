// The fixture of the tests that present: a GLFW window on the X server the test runs under
// (xvfb-run) and a presenting lavapipe device with validation, synchronization validation and
// its QUEUE_SUBMIT check; any message the test does not expect fails it.
#pragma once

#include <skygraph/device.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/swapchain.hpp>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>

namespace skygraph::test {

inline std::string formatMessages(const Device& d) {
    std::string s;
    for (const auto& m : d.messages()) s += "  [" + m.idName + "] " + m.message.substr(0, 800) + "\n";
    return s;
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

}  // namespace skygraph::test
