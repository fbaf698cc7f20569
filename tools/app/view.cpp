// `skygraph view`: the frame of `render`, presented in a GLFW window.
#include "view.hpp"

#include "command_exit.hpp"
#include "glfw_presentation.hpp"
#include "view_overlay.hpp"
#include "live_graph.hpp"
#include "render.hpp"

#include "shipped_names.hpp"

#include <skygraph/compiled_graph.hpp>
#include <skygraph/compiler.hpp>
#include <skygraph/device.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/swapchain.hpp>

#define GLFW_INCLUDE_NONE  // no OpenGL header: the window only gets a Vulkan surface
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <utility>

namespace skygraph::app {
namespace {

using shipped::kOverlayFeature;

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
    const ViewOverlay* overlay = nullptr;
    Scene* scene = nullptr;
    std::optional<Orbit> orbit;
    bool cameraMoved = false;
    bool overlayVisible = false;
    bool toggleOverlay = false;    // F1
    bool screenshotWanted = false;  // F12
};

ViewState& stateOf(GLFWwindow* w) { return *static_cast<ViewState*>(glfwGetWindowUserPointer(w)); }

void onFramebufferSize(GLFWwindow* w, int width, int height) {
    ViewState& s = stateOf(w);
    if (s.swapchain) s.swapchain->resize(uint32_t(std::max(width, 0)), uint32_t(std::max(height, 0)));
}

void onKey(GLFWwindow* w, int key, int, int action, int) {
    if (action != GLFW_PRESS) return;
    ViewState& s = stateOf(w);
    if (key == GLFW_KEY_ESCAPE) glfwSetWindowShouldClose(w, GLFW_TRUE);
    if (key == GLFW_KEY_F1) s.toggleOverlay = true;
    if (key == GLFW_KEY_F12) s.screenshotWanted = true;
}

void onMouseButton(GLFWwindow* w, int button, int action, int) {
    ViewState& s = stateOf(w);
    if (!s.orbit || button != GLFW_MOUSE_BUTTON_LEFT) return;
    if (action == GLFW_PRESS && s.overlayVisible && s.overlay->wantsMouse()) return;
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
    if (!s.orbit || (s.overlayVisible && s.overlay->wantsMouse())) return;
    s.orbit->distance = std::clamp(s.orbit->distance * std::pow(0.9, dy), 0.2, 1000.0);
    s.orbit->place(s.scene->camera);
    s.cameraMoved = true;
}

/// Logs how long after the save that caused it the first frame of a reloaded plan was
/// presented (docs/performance.md reports it).
void reportReloadLatency(LiveGraph& live) {
    LiveGraph::Reload& reload = live.lastReload();
    if (!reload.pending) return;
    reload.pending = false;
    const auto ms = [](auto duration) { return std::chrono::duration<double, std::milli>(duration).count(); };
    const auto presented = std::filesystem::file_time_type::clock::now();
    spdlog::info("reload: first frame of the new plan presented {:.1f} ms after the save (noticed after {:.1f} ms, "
                 "rebuilt in {:.1f} ms, its first frame submitted and presented {:.1f} ms later)",
                 ms(presented - reload.saved), ms(reload.noticed - reload.saved), ms(reload.rebuilt - reload.noticed),
                 ms(presented - reload.rebuilt));
}

/// Throws what is wrong with the inputs (graph, scene, environment file, features), as
/// `render` would say it. Called where no window can be had: a broken input would otherwise go
/// unnoticed behind "no display". Quietly: loading them is a check here, not progress.
void refuseBrokenInputs(const RenderOptions& frame) {
    struct Quiet {
        spdlog::level::level_enum level = spdlog::get_level();
        Quiet() { spdlog::set_level(std::max(level, spdlog::level::warn)); }
        ~Quiet() { spdlog::set_level(level); }
    } quiet;
    const FrameInputs inputs = loadFrameInputs(frame);
    (void)compile(inputs.graph, inputs.compile);
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
            refuseBrokenInputs(fo);
            std::cerr << "skygraph view: no display (" << glfwLastError()
                      << "); render to a file without one: skygraph render\n";
            return 1;
        }
        if (glfwVulkanSupported() != GLFW_TRUE) {
            refuseBrokenInputs(fo);
            std::cerr << "skygraph view: GLFW finds no Vulkan loader (" << glfwLastError()
                      << "); render to a file instead: skygraph render\n";
            return 1;
        }
        glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
        glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
        const std::string title = "skygraph view: " + (fo.graph.empty() ? std::string("built-in raster graph")
                                                                         : fo.graph.filename().string());
        glfw.window = glfwCreateWindow(int(fo.width), int(fo.height), title.c_str(), nullptr, nullptr);
        if (!glfw.window) {
            refuseBrokenInputs(fo);
            std::cerr << "skygraph view: cannot open a window (" << glfwLastError()
                      << "); render to a file instead: skygraph render\n";
            return 1;
        }
        GLFWwindow* window = glfw.window;
        int fbw = 0, fbh = 0;
        glfwGetFramebufferSize(window, &fbw, &fbh);

        DeviceOptions dopts;
        dopts.device = fo.device;
        dopts.validation = fo.validate;
        dopts.presentation = glfwPresentation(window);
        auto device = Device::create(dopts);

        uint64_t presented = 0;
        uint32_t reloads = 0;
        std::optional<SequenceStats> sequence;  // of an environment sequence, when one played
        VkExtent2D lastExtent{};
        PresentMode lastMode = options.presentMode;
        {
            // The window's callbacks first: the overlay's GLFW backend chains them.
            ViewState state;
            glfwSetWindowUserPointer(window, &state);
            glfwSetFramebufferSizeCallback(window, onFramebufferSize);
            glfwSetKeyCallback(window, onKey);
            glfwSetMouseButtonCallback(window, onMouseButton);
            glfwSetCursorPosCallback(window, onCursor);
            glfwSetScrollCallback(window, onScroll);
            // The overlay's context exists before the renderers whose ImGuiPass draws it, and
            // outlives them (declared first, destroyed last).
            std::optional<ViewOverlay> overlay;
            if (options.overlay) overlay.emplace(window);
            state.overlay = overlay ? &*overlay : nullptr;
            // The swapchain outlives the renderers that render into it: declared before them.
            std::unique_ptr<Swapchain> swapchain;
            LiveGraph live(*device, fo, uint32_t(std::max(fbw, 1)), uint32_t(std::max(fbh, 1)), options.overlay);

            SwapchainOptions so;
            so.width = uint32_t(std::max(fbw, 0));
            so.height = uint32_t(std::max(fbh, 0));
            so.presentMode = options.presentMode;
            so.extraUsage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT;  // screenshots read the presented image back
            try {
                swapchain = Swapchain::create(*device, live.renderer().compiled(), so);
            } catch (const UnsupportedResourceError& e) {  // the surface cannot present the graph's image
                throwAtDeclaration(live.renderer().graph(), e);
            }
            state.swapchain = swapchain.get();
            live.presentTo(*swapchain);
            if (live.scene() && options.orbit) {
                state.scene = live.scene();
                state.orbit.emplace(state.scene->camera);
            }
            stopRequested = 0;
            const auto previousInt = std::signal(SIGINT, onStopSignal);
            const auto previousTerm = std::signal(SIGTERM, onStopSignal);

            uint32_t screenshots = 0;
            double frameMs = 0.0;
            const auto playbackStart = std::chrono::steady_clock::now();
            while (!glfwWindowShouldClose(window) && !stopRequested) {
                const auto start = std::chrono::steady_clock::now();
                if (swapchain->paused()) glfwWaitEventsTimeout(0.1);  // no size: nothing to render
                else glfwPollEvents();
                if (live.poll() && live.sceneReplaced() && state.orbit) state.orbit.emplace(state.scene->camera);
                live.playSequence(std::chrono::duration<double>(start - playbackStart).count());
                if (std::exchange(state.toggleOverlay, false) && overlay && live.declares(kOverlayFeature))
                    live.setFeature(std::string(kOverlayFeature), !live.feature(kOverlayFeature));
                state.overlayVisible = overlay && live.feature(kOverlayFeature);
                if (state.overlayVisible) overlay->frame(live, frameMs);
                if (state.cameraMoved) {
                    live.sceneChanged();
                    state.cameraMoved = false;
                }
                // A paused window presents nothing: the screenshot waits for a frame.
                const bool screenshot = !swapchain->paused() && std::exchange(state.screenshotWanted, false) &&
                                        live.beginScreenshot();
                if (live.renderFrame(*swapchain) == PresentStatus::Presented) {
                    ++presented;
                    if (screenshot) live.finishScreenshot("skygraph-view-" + std::to_string(++screenshots) + ".png");
                    reportReloadLatency(live);
                } else if (screenshot) {
                    live.finishScreenshot({});  // nothing presented: compiles the plan back
                }
                frameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
                if (options.frames != 0 && presented >= options.frames) break;
            }
            Renderer& renderer = live.renderer();
            renderer.waitIdle();
            std::signal(SIGINT, previousInt);
            std::signal(SIGTERM, previousTerm);
            for (const auto& t : renderer.lastTimings()) spdlog::info("pass {:<24} {:8.3f} ms (GPU)", t.pass, t.milliseconds);
            lastExtent = swapchain->extent();
            lastMode = swapchain->presentMode();
            reloads = live.reloads();
            if (const SequencePlayer* player = live.sequence()) sequence = player->stats();
            glfwSetWindowUserPointer(window, nullptr);  // `state` ends here
        }
        // The renderers, the swapchain and the overlay are gone: destroying the device now
        // lets validation report (and count) any Vulkan object still alive, a leak, before the
        // exit status.
        device->finish();
        std::cout << "skygraph view: " << presented << " frames presented, last at " << lastExtent.width << "x"
                  << lastExtent.height << " (" << presentModeName(lastMode) << "), " << reloads
                  << " reload(s); ";
        if (sequence)
            std::cout << "sequence: " << sequence->shown << " frame(s) shown (" << sequence->late << " late), "
                      << sequence->dropped << " dropped (" << sequence->failed << " unreadable); ";
        std::cout << "validation: ";
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
