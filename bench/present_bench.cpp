// CPU time per frame of the presented path against the headless one, for the same graph:
// graphs/raster.json with scenes/default.json (feature `ui` off), 2 frames in flight, on one
// Device that presents to a GLFW window (GLFW_NO_API).
//
//   BM_HeadlessFrame/WxH:  Renderer::renderFrame(), the plan compiled with the swapchain target
//                          replaced by an image of the renderer's own (`skygraph render`).
//   BM_PresentedFrame/WxH: glfwPollEvents() + Renderer::renderFrame(Swapchain&): acquire,
//                          record, submit, present (`skygraph view`'s frame without overlay).
//
// Both renderers live on the same Device for the whole run, so repetitions can interleave
// (--benchmark_enable_random_interleaving=true). Google Benchmark's CPU column is the calling
// thread's CPU time: on lavapipe the GPU work runs on the driver's own threads, and fence and
// acquire waits block without burning CPU, so it is the host overhead of a frame.
//
// Needs an X display (xvfb-run). Flags: --size=WxH (repeatable; default 1280x720 and 320x180;
// each size gets its own window and Device). Environment: SKYGRAPH_BENCH_DEVICE picks the
// device, SKYGRAPH_VALIDATION=1 runs under validation; the exit status is 1 when any
// validation message was counted (the ctest smoke run, bench/CMakeLists.txt).
#include "frame_setup.hpp"

#include "app/glfw_presentation.hpp"

#include <skygraph/swapchain.hpp>

#define GLFW_INCLUDE_NONE  // no OpenGL header: the window only gets a Vulkan surface
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <benchmark/benchmark.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

namespace skygraph::bench {
namespace {

const PassLibrary& library() {
    static const PassLibrary l = PassLibrary::withBuiltins();
    return l;
}

/// One window, one presenting Device, and on it a headless and a presented renderer of the
/// same graph at the same size.
struct PresentFixture {
    GLFWwindow* window = nullptr;
    std::unique_ptr<Device> device;
    std::unique_ptr<FrameRenderer> headless;
    std::unique_ptr<FrameRenderer> presented;
    std::unique_ptr<Swapchain> swapchain;
    explicit PresentFixture(Size size) {
        glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
        glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
        window = glfwCreateWindow(int(size.width), int(size.height), "present_bench", nullptr, nullptr);
        if (!window) throw std::runtime_error("glfwCreateWindow failed");
        int fbw = 0, fbh = 0;
        glfwGetFramebufferSize(window, &fbw, &fbh);
        if (uint32_t(fbw) != size.width || uint32_t(fbh) != size.height)
            spdlog::warn("present_bench: the window is {}x{}, not {}", fbw, fbh, size.name());

        DeviceOptions dopts;
        dopts.device = benchDeviceName();
        dopts.presentation = app::glfwPresentation(window);
        device = Device::create(dopts);

        const Size fb{uint32_t(fbw), uint32_t(fbh)};
        headless = std::make_unique<FrameRenderer>(*device, rasterOptions(fb, false, library()), true);
        presented = std::make_unique<FrameRenderer>(*device, rasterOptions(fb, false, library()), false);
        SwapchainOptions so;
        so.width = fb.width;
        so.height = fb.height;
        // FIFO would pace the presented side to a vertical blank (Xvfb has none to wait for,
        // but a real display does); immediate measures the path, not the pacing.
        so.presentMode = PresentMode::Immediate;
        swapchain = Swapchain::create(*device, presented->renderer->compiled(), so);
    }

    ~PresentFixture() { (void)finish(); }
    /// Destroys the renderers and the swapchain, then finishes the device (validation counts
    /// anything left alive) and returns its validation message count; the window goes last.
    uint32_t finish() {
        presented.reset();  // before the swapchain whose images it has views of
        swapchain.reset();
        headless.reset();
        uint32_t messages = 0;
        if (device) {
            device->finish();
            messages = device->messageCount();
            device.reset();
        }
        if (window) glfwDestroyWindow(window);
        window = nullptr;
        return messages;
    }
    PresentFixture(const PresentFixture&) = delete;
    PresentFixture& operator=(const PresentFixture&) = delete;
};

Fixtures<PresentFixture>& fixtures() {
    static Fixtures<PresentFixture> f;
    return f;
}

constexpr int kWarmup = 3;

void headlessFrame(benchmark::State& state, Size size) {
    PresentFixture* fp = fixtures().get(state, size);
    if (!fp) return;
    PresentFixture& f = *fp;
    Renderer& r = *f.headless->renderer;
    f.presented->renderer->waitIdle();  // the other side's frames are done before timing
    for (int i = 0; i < kWarmup; ++i) r.renderFrame();
    for (auto _ : state) r.renderFrame();
    r.waitIdle();
    state.SetLabel("headless");
}

void presentedFrame(benchmark::State& state, Size size) {
    PresentFixture* fp = fixtures().get(state, size);
    if (!fp) return;
    PresentFixture& f = *fp;
    Renderer& r = *f.presented->renderer;
    f.headless->renderer->waitIdle();
    for (int i = 0; i < kWarmup; ++i) {
        glfwPollEvents();
        (void)r.renderFrame(*f.swapchain);
    }
    uint64_t paused = 0;
    for (auto _ : state) {
        glfwPollEvents();
        if (r.renderFrame(*f.swapchain) != PresentStatus::Presented) ++paused;
    }
    r.waitIdle();
    if (paused) {
        fixtures().failed = true;
        state.SkipWithError("frames not presented (the window has no size)");
    }
    state.SetLabel(presentModeName(f.swapchain->presentMode()));
}

}  // namespace
}  // namespace skygraph::bench

int main(int argc, char** argv) {
    using namespace skygraph::bench;
    const std::vector<Size> sizes = takeSizes(argc, argv, {{1280, 720}, {320, 180}});
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
    spdlog::set_level(spdlog::level::warn);
    if (glfwInit() != GLFW_TRUE) {
        std::fprintf(stderr, "present_bench: no display (run it under xvfb-run)\n");
        return 1;
    }
    // Side by side: each size's headless benchmark, then its presented one.
    for (const Size& s : sizes) {
        // Iterations by real time (each frame waits for the GPU): --benchmark_min_time is
        // wall-clock seconds per repetition; the CPU column is still the thread's CPU time.
        benchmark::RegisterBenchmark(("BM_HeadlessFrame/" + s.name()).c_str(), headlessFrame, s)
            ->Unit(benchmark::kMicrosecond)
            ->UseRealTime();
        benchmark::RegisterBenchmark(("BM_PresentedFrame/" + s.name()).c_str(), presentedFrame, s)
            ->Unit(benchmark::kMicrosecond)
            ->UseRealTime();
    }
    int status = 0;
    try {
        if (benchmark::RunSpecifiedBenchmarks() == 0 || fixtures().failed) status = 1;
        bool validated = false;
        uint32_t messages = 0;
        for (auto& [name, f] : fixtures().all()) {
            validated = validated || f->device->validationEnabled();
            messages += f->finish();
        }
        fixtures().all().clear();
        if (validated) {
            std::printf("present_bench: validation: %u message(s)\n", messages);
            if (messages) status = 1;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "present_bench: %s\n", e.what());
        status = 1;
    }
    glfwTerminate();
    benchmark::Shutdown();
    return status;
}
