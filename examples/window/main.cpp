// An application embedding skygraph with a window: it opens a GLFW window, gives skygraph the
// window's surface, registers its own pass type (CheckerPass) beside the built-in ones, loads its
// own graph (window.json) and presents frames until the window is closed or --frames are
// presented. Resizing re-creates the swapchain and recompiles the plan at the new size; a
// minimized window pauses. With --own-swapchain the application creates the swapchain itself
// and hands skygraph its images and semaphores (own_swapchain.cpp). With --validate it runs
// under the Khronos validation layer with synchronization validation and exits 1 if the layer
// reported anything.
#include "checker_pass.hpp"
#include "own_swapchain.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/executor.hpp>
#include <skygraph/pass.hpp>

#define GLFW_INCLUDE_NONE    // no OpenGL header
#define GLFW_INCLUDE_VULKAN  // glfwCreateWindowSurface and glfwGetRequiredInstanceExtensions
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <memory>
#include <stdexcept>
#include <string>

namespace {

using namespace skygraph;

struct Options {
    std::string graph = WINDOW_DATA_DIR "/window.json";
    uint64_t frames = 0;  // 0: until the window is closed
    int width = 320, height = 240;
    bool validate = false;
    bool ownSwapchain = false;
};

constexpr const char* kUsage =
    "usage: window_example [--graph FILE] [--frames N] [--size WxH] [--validate] [--own-swapchain]\n";

Options parseArguments(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
            return argv[++i];
        };
        if (arg == "--graph") o.graph = value();
        else if (arg == "--frames") o.frames = std::stoull(value());
        else if (arg == "--size") {
            const std::string v = value();
            if (std::sscanf(v.c_str(), "%dx%d", &o.width, &o.height) != 2 || o.width < 1 || o.height < 1)
                throw std::invalid_argument("--size: expected WxH, got '" + v + "'");
        } else if (arg == "--validate") o.validate = true;
        else if (arg == "--own-swapchain") o.ownSwapchain = true;
        else throw std::invalid_argument("unknown argument '" + arg + "'");
    }
    return o;
}

std::string glfwError() {
    const char* description = nullptr;
    glfwGetError(&description);
    return description ? description : "no description";
}

/// glfwInit and the window; glfwTerminate.
struct Window {
    GLFWwindow* handle = nullptr;
    Window(int width, int height) {
        if (glfwInit() != GLFW_TRUE) throw std::runtime_error("no display: " + glfwError());
        if (glfwVulkanSupported() != GLFW_TRUE) {
            glfwTerminate();
            throw std::runtime_error("GLFW finds no Vulkan loader: " + glfwError());
        }
        glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);  // Vulkan draws into it, not OpenGL
        glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
        handle = glfwCreateWindow(width, height, "skygraph window example", nullptr, nullptr);
        if (!handle) {
            glfwTerminate();
            throw std::runtime_error("cannot open a window: " + glfwError());
        }
    }
    ~Window() {
        glfwDestroyWindow(handle);
        glfwTerminate();
    }
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;
    [[nodiscard]] VkExtent2D framebufferSize() const {
        int w = 0, h = 0;
        glfwGetFramebufferSize(handle, &w, &h);
        return {uint32_t(std::max(w, 0)), uint32_t(std::max(h, 0))};
    }
};

/// What the window's callbacks reach: whichever of the two presents.
struct Presenter {
    Swapchain* swapchain = nullptr;               // skygraph's
    window_example::OwnSwapchain* own = nullptr;  // the application's
};

void onFramebufferSize(GLFWwindow* window, int width, int height) {
    const auto* p = static_cast<Presenter*>(glfwGetWindowUserPointer(window));
    const auto w = uint32_t(std::max(width, 0)), h = uint32_t(std::max(height, 0));
    if (p->swapchain) p->swapchain->resize(w, h);  // 0x0 (minimized) pauses
    if (p->own) p->own->resize(w, h);
}

void onKey(GLFWwindow* window, int key, int, int action, int) {
    if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS) glfwSetWindowShouldClose(window, GLFW_TRUE);
}

int run(const Options& options) {
    // The application's pass type beside skygraph's, and its own graph file. A graph error
    // names the file, the JSON path, the pass and the resource.
    PassLibrary library = PassLibrary::withBuiltins();
    library.add(window_example::checkerPassType(), window_example::makeCheckerPass);
    GraphDesc graph = loadGraphFile(options.graph, library.registry());

    Window window(options.width, options.height);
    const VkExtent2D size = window.framebufferSize();

    // Compiled to present: the graph's `final: Present` resource is the swapchain image.
    CompileOptions compileOptions;
    compileOptions.outputWidth = std::max(size.width, 1u);
    compileOptions.outputHeight = std::max(size.height, 1u);
    CompiledGraph compiled(std::move(graph), compileOptions);

    // The device gets the window system's instance extensions and makes the surface with
    // GLFW; it owns the surface from then on.
    DeviceOptions deviceOptions;
    deviceOptions.validation = options.validate;
    PresentationOptions presentation;
    uint32_t extensionCount = 0;
    const char** extensions = glfwGetRequiredInstanceExtensions(&extensionCount);
    presentation.instanceExtensions.assign(extensions, extensions + extensionCount);
    presentation.createSurface = [&window](VkInstance instance) {
        VkSurfaceKHR surface = VK_NULL_HANDLE;
        if (glfwCreateWindowSurface(instance, window.handle, nullptr, &surface) != VK_SUCCESS)
            throw std::runtime_error("glfwCreateWindowSurface: " + glfwError());
        return surface;
    };
    deviceOptions.presentation = std::move(presentation);
    const std::unique_ptr<Device> device = Device::create(deviceOptions);

    // Either skygraph's swapchain or the application's own. Both outlive the renderer, which
    // keeps views of their images.
    RendererOptions rendererOptions;
    rendererOptions.passes = &library;
    rendererOptions.shaderDir = SKYGRAPH_PACKAGE_SHADER_DIR;  // the linked package's shaders
    std::unique_ptr<Swapchain> swapchain;
    std::unique_ptr<window_example::OwnSwapchain> own;
    if (options.ownSwapchain)
        own = std::make_unique<window_example::OwnSwapchain>(*device, presentRequirements(compiled),
                                                             rendererOptions.framesInFlight, size.width, size.height);
    else
        swapchain = Swapchain::create(*device, compiled, {size.width, size.height, PresentMode::Fifo});
    Renderer renderer(*device, std::move(compiled), rendererOptions);

    Presenter presenter{swapchain.get(), own.get()};
    glfwSetWindowUserPointer(window.handle, &presenter);
    glfwSetFramebufferSizeCallback(window.handle, onFramebufferSize);
    glfwSetKeyCallback(window.handle, onKey);

    uint64_t presented = 0;
    while (!glfwWindowShouldClose(window.handle) && (options.frames == 0 || presented < options.frames)) {
        const bool paused = swapchain ? swapchain->paused() : own->paused();
        if (paused) glfwWaitEventsTimeout(0.1);  // minimized: nothing to render until it has a size
        else glfwPollEvents();
        const bool shown = swapchain ? renderer.renderFrame(*swapchain) == PresentStatus::Presented
                                     : own->renderFrame(renderer);
        if (shown) ++presented;
    }
    renderer.waitIdle();

    const VkExtent2D last = swapchain ? swapchain->extent() : own->extent();
    std::printf("window_example: %llu frames presented (%s swapchain), last at %ux%u on %s; validation: ",
                static_cast<unsigned long long>(presented), own ? "own" : "skygraph's", last.width, last.height,
                device->name().c_str());
    if (!device->validationEnabled()) {
        std::printf("off\n");
        return 0;
    }
    std::printf("%u message(s)\n", device->messageCount());
    for (const auto& m : device->messages()) std::fprintf(stderr, "%s: %s\n", m.idName.c_str(), m.message.c_str());
    return device->messageCount() == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    Options options;
    try {
        options = parseArguments(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "window_example: %s\n%s", e.what(), kUsage);
        return 2;
    }
    try {
        return run(options);
    } catch (const GraphError& e) {
        std::fprintf(stderr, "%s\n", e.diagnostics().format().c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "window_example: %s\n", e.what());
    }
    return 1;
}
