// `skygraph view`: the frame of `render`, presented in a GLFW window.
#include "view.hpp"

#include "command_exit.hpp"

#include <skygraph/compiled_graph.hpp>
#include <skygraph/device.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/swapchain.hpp>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

namespace skygraph::app {
namespace {

std::string& glfwLastError() {
    static std::string text;
    return text;
}

void onGlfwError(int code, const char* description) {
    glfwLastError() = description ? description : "error " + std::to_string(code);
}

volatile std::sig_atomic_t stopRequested = 0;
void onStopSignal(int) { stopRequested = 1; }

/// glfwInit / glfwTerminate, and the window.
struct Glfw {
    bool ok = false;
    GLFWwindow* window = nullptr;
    Glfw() { ok = glfwInit() == GLFW_TRUE; }
    ~Glfw() {
        if (window) glfwDestroyWindow(window);
        if (ok) glfwTerminate();
    }
    Glfw(const Glfw&) = delete;
    Glfw& operator=(const Glfw&) = delete;
};

/// Left-drag orbits the camera about the point it looks at; the wheel moves it closer.
struct Orbit {
    Vec3 target{};
    double distance = 1.0;
    bool dragging = false;
    double lastX = 0.0, lastY = 0.0;

    explicit Orbit(const SceneCamera& c) {
        distance = std::max(0.5, std::hypot(c.position[0], c.position[1], c.position[2]));
        const Vec3 f = cameraForward(c);
        for (size_t i = 0; i < 3; ++i) target[i] = c.position[i] + f[i] * distance;
    }
    void place(SceneCamera& c) const {
        const Vec3 f = cameraForward(c);
        for (size_t i = 0; i < 3; ++i) c.position[i] = target[i] - f[i] * distance;
    }
};

/// What the window's callbacks reach (glfwSetWindowUserPointer).
struct ViewState {
    Swapchain* swapchain = nullptr;
    Scene* scene = nullptr;
    std::optional<Orbit> orbit;
    bool cameraMoved = false;
};

ViewState& stateOf(GLFWwindow* w) { return *static_cast<ViewState*>(glfwGetWindowUserPointer(w)); }

void onFramebufferSize(GLFWwindow* w, int width, int height) {
    ViewState& s = stateOf(w);
    if (s.swapchain) s.swapchain->resize(uint32_t(std::max(width, 0)), uint32_t(std::max(height, 0)));
}

void onKey(GLFWwindow* w, int key, int, int action, int) {
    if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS) glfwSetWindowShouldClose(w, GLFW_TRUE);
}

void onMouseButton(GLFWwindow* w, int button, int action, int) {
    ViewState& s = stateOf(w);
    if (!s.orbit || button != GLFW_MOUSE_BUTTON_LEFT) return;
    s.orbit->dragging = action == GLFW_PRESS;
    glfwGetCursorPos(w, &s.orbit->lastX, &s.orbit->lastY);
}

void onCursor(GLFWwindow* w, double x, double y) {
    ViewState& s = stateOf(w);
    if (!s.orbit || !s.orbit->dragging) return;
    SceneCamera& c = s.scene->camera;
    c.yawDeg -= (x - s.orbit->lastX) * 0.3;
    c.pitchDeg = std::clamp(c.pitchDeg - (y - s.orbit->lastY) * 0.3, -89.0, 89.0);
    s.orbit->lastX = x;
    s.orbit->lastY = y;
    s.orbit->place(c);
    s.cameraMoved = true;
}

void onScroll(GLFWwindow* w, double, double dy) {
    ViewState& s = stateOf(w);
    if (!s.orbit) return;
    s.orbit->distance = std::clamp(s.orbit->distance * std::pow(0.9, dy), 0.2, 1000.0);
    s.orbit->place(s.scene->camera);
    s.cameraMoved = true;
}

}  // namespace

int viewCommand(const ViewOptions& options) {
    try {
        const RenderOptions& fo = options.frame;
        if (fo.graph.empty() && fo.graphText.empty()) {
            std::cerr << "skygraph view: no graph file given\n";
            return 1;
        }
        if (fo.width == 0 || fo.height == 0) {
            std::cerr << "skygraph view: --width and --height must be at least 1\n";
            return 1;
        }
        glfwSetErrorCallback(onGlfwError);
        Glfw glfw;
        if (!glfw.ok) {
            std::cerr << "skygraph view: no display (" << glfwLastError()
                      << "); render to a file without one: skygraph render\n";
            return 1;
        }
        if (glfwVulkanSupported() != GLFW_TRUE) {
            std::cerr << "skygraph view: GLFW finds no Vulkan loader (" << glfwLastError()
                      << "); render to a file instead: skygraph render\n";
            return 1;
        }
        FrameInputs inputs = loadFrameInputs(fo);

        glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
        glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
        const std::string title = "skygraph view: " + inputs.graph.name;
        glfw.window = glfwCreateWindow(int(fo.width), int(fo.height), title.c_str(), nullptr, nullptr);
        if (!glfw.window) {
            std::cerr << "skygraph view: cannot open a window (" << glfwLastError()
                      << "); render to a file instead: skygraph render\n";
            return 1;
        }
        GLFWwindow* window = glfw.window;
        int fbw = 0, fbh = 0;
        glfwGetFramebufferSize(window, &fbw, &fbh);

        CompileOptions co = inputs.compile;  // presented: the Present resource stays Present
        co.outputWidth = uint32_t(std::max(fbw, 1));
        co.outputHeight = uint32_t(std::max(fbh, 1));
        CompiledGraph compiled(inputs.graph, co);
        for (const auto& c : compiled.plan().culled()) spdlog::info("culled {}: {}", c.name, c.reason);

        DeviceOptions dopts;
        dopts.device = fo.device;
        dopts.validation = fo.validate;
        PresentationOptions presentation;
        uint32_t extensionCount = 0;
        const char** extensions = glfwGetRequiredInstanceExtensions(&extensionCount);
        for (uint32_t i = 0; i < extensionCount; ++i) presentation.instanceExtensions.emplace_back(extensions[i]);
        presentation.createSurface = [window](VkInstance instance) {
            VkSurfaceKHR surface = VK_NULL_HANDLE;
            if (glfwCreateWindowSurface(instance, window, nullptr, &surface) != VK_SUCCESS)
                throw std::runtime_error("glfwCreateWindowSurface: " + glfwLastError());
            return surface;
        };
        dopts.presentation = std::move(presentation);
        auto device = Device::create(dopts);

        uint64_t presented = 0;
        VkExtent2D lastExtent{};
        PresentMode lastMode = options.presentMode;
        {
            SwapchainOptions so;
            so.width = uint32_t(std::max(fbw, 0));
            so.height = uint32_t(std::max(fbh, 0));
            so.presentMode = options.presentMode;
            const std::unique_ptr<Swapchain> swapchain = Swapchain::create(*device, compiled, so);
            const FrameEnvironment environment = bakeFrameEnvironment(*device, compiled.plan(), inputs, fo);
            RendererOptions ropts;
            ropts.framesInFlight = fo.framesInFlight;
            ropts.passes = inputs.passes;
            Renderer renderer(*device, std::move(compiled), ropts);
            attachFrameInputs(renderer, inputs, environment);

            ViewState state;
            state.swapchain = swapchain.get();
            if (inputs.scene && options.orbit) {
                state.scene = &*inputs.scene;
                state.orbit.emplace(inputs.scene->camera);
            }
            glfwSetWindowUserPointer(window, &state);
            glfwSetFramebufferSizeCallback(window, onFramebufferSize);
            glfwSetKeyCallback(window, onKey);
            glfwSetMouseButtonCallback(window, onMouseButton);
            glfwSetCursorPosCallback(window, onCursor);
            glfwSetScrollCallback(window, onScroll);
            stopRequested = 0;
            const auto previousInt = std::signal(SIGINT, onStopSignal);
            const auto previousTerm = std::signal(SIGTERM, onStopSignal);

            while (!glfwWindowShouldClose(window) && !stopRequested) {
                if (swapchain->paused()) glfwWaitEventsTimeout(0.1);  // no size: nothing to render
                else glfwPollEvents();
                if (state.cameraMoved) {
                    renderer.frameData().set(*inputs.scene);
                    state.cameraMoved = false;
                }
                if (renderer.renderFrame(*swapchain) == PresentStatus::Presented) ++presented;
                if (options.frames != 0 && presented >= options.frames) break;
            }
            renderer.waitIdle();
            std::signal(SIGINT, previousInt);
            std::signal(SIGTERM, previousTerm);
            for (const auto& t : renderer.lastTimings()) spdlog::info("pass {:<24} {:8.3f} ms (GPU)", t.pass, t.milliseconds);
            lastExtent = swapchain->extent();
            lastMode = swapchain->presentMode();
            glfwSetWindowUserPointer(window, nullptr);  // `state` ends here
        }
        // The renderer and the swapchain are gone: destroying the device now lets validation
        // report (and count) any Vulkan object still alive, a leak, before the exit status.
        device->finish();
        std::cout << "skygraph view: " << presented << " frames presented, last at " << lastExtent.width << "x"
                  << lastExtent.height << " (" << presentModeName(lastMode) << "); validation: ";
        if (device->validationEnabled()) {
            std::cout << device->messageCount() << " message(s)\n";
        } else
            std::cout << "off\n";
        std::cout.flush();
        return validationExit(*device, "skygraph view");
    } catch (...) {
        return exitForCurrentException("skygraph view");
    }
}

}  // namespace skygraph::app
