// What a Device needs to present to a GLFW window: GLFW's instance extensions and a surface
// made for the window. Application code (GLFW lives in tools/, never in the libraries).
#pragma once

#include <skygraph/device.hpp>

#define GLFW_INCLUDE_NONE  // no OpenGL header: the window only gets a Vulkan surface
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <string>

namespace skygraph::app {

/// DeviceOptions::presentation for `window`, which must outlive the Device. createSurface
/// throws ExecutorError with GLFW's reason when the surface cannot be made.
inline PresentationOptions glfwPresentation(GLFWwindow* window) {
    PresentationOptions presentation;
    uint32_t count = 0;
    const char** extensions = glfwGetRequiredInstanceExtensions(&count);
    for (uint32_t i = 0; i < count; ++i) presentation.instanceExtensions.emplace_back(extensions[i]);
    presentation.createSurface = [window](VkInstance instance) {
        VkSurfaceKHR surface = VK_NULL_HANDLE;
        if (const VkResult r = glfwCreateWindowSurface(instance, window, nullptr, &surface); r != VK_SUCCESS) {
            const char* why = nullptr;
            glfwGetError(&why);
            throw ExecutorError("glfwCreateWindowSurface: " + (why ? std::string(why) : "VkResult " + std::to_string(r)));
        }
        return surface;
    };
    return presentation;
}

}  // namespace skygraph::app
