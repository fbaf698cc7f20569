// GPU time of the ImGui pass: graphs/raster.json with scenes/default.json rendered headless
// (as `skygraph render` does) with feature `ui` on, so the `ui` pass (ImGuiPass) records the
// current Dear ImGui context's draw data over the tonemapped frame. Each iteration builds an
// ImGui frame (no platform backend: io.DisplaySize is the output size), renders one frame and
// reads Renderer::lastTimings() (GPU timestamps around each pass; it waits for the frame).
//
//   BM_UiFrame/<content>/WxH, content:
//     off      the feature `ui` off (no ImGui pass): the frame without an overlay
//     empty    `ui` on, an ImGui frame that draws nothing (the pass records its render pass only)
//     overlay  a window like `skygraph view`'s overlay (tools/app/view_overlay.cpp): graph name,
//              feature checkboxes, exposure and rotation sliders, a text field, buttons, the
//              plan's pass timings in a table
//     demo     ImGui::ShowDemoWindow() and ImGui::ShowStyleEditor(), two 900x1000 windows: a
//              heavy case
//
// Counters (per repetition, the median over its frames): ui_ms (the `ui` pass), frame_ms (the
// sum of every pass's time), the draw data's vertices and indices, and triangle_px (its
// triangles' area in pixels, overdraw counted). The iteration time includes the wait for each
// frame and is not the figure to read.
//
// Flags: --size=WxH (repeatable; default 1920x1080). Environment: SKYGRAPH_BENCH_DEVICE picks
// the device, SKYGRAPH_VALIDATION=1 runs under validation; the exit status is 1 when any
// validation message was counted (the ctest smoke run, bench/CMakeLists.txt). Needs no display.
#include "frame_setup.hpp"

#include <benchmark/benchmark.h>
#include <imgui.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <memory>
#include <string>
#include <vector>

namespace skygraph::bench {
namespace {

const PassLibrary& library() {
    static const PassLibrary l = PassLibrary::withBuiltins();
    return l;
}

enum class Content { Off, Empty, Overlay, Demo };
constexpr std::array<const char*, 4> kContentNames{"off", "empty", "overlay", "demo"};

/// What the overlay's widgets edit, kept between frames.
struct OverlayState {
    std::map<std::string, bool> features{{"geometry", true},         {"skybox", true},
                                         {"environment_file", false}, {"sample_cubemap", true},
                                         {"compute_tonemap", false},  {"ui", true}};
    float exposure = 0.0f;
    float rotation = 0.0f;
    std::array<char, 256> environment{"scenes/studio.exr"};
};

/// Comparable to ViewOverlay::frame: one auto-sized window at the top left with three open
/// sections.
void drawOverlay(OverlayState& s, const Renderer& renderer, double frameMs) {
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
    ImGui::SetNextWindowSizeConstraints(ImVec2(260, 0), ImVec2(420, 10000));
    ImGui::Begin("skygraph", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove);
    ImGui::TextUnformatted(renderer.graph().name.c_str());
    if (ImGui::CollapsingHeader("Features", ImGuiTreeNodeFlags_DefaultOpen))
        for (auto& [name, on] : s.features) ImGui::Checkbox(name.c_str(), &on);
    if (ImGui::CollapsingHeader("Scene", ImGuiTreeNodeFlags_DefaultOpen)) {
        ImGui::SliderFloat("exposure (EV)", &s.exposure, -10.0f, 10.0f, "%.2f");
        ImGui::SliderFloat("sky rotation", &s.rotation, -180.0f, 180.0f, "%.1f deg");
        ImGui::InputText("environment", s.environment.data(), s.environment.size());
        ImGui::Button("load file");
        ImGui::SameLine();
        ImGui::Button("procedural sky");
    }
    if (ImGui::CollapsingHeader("Plan", ImGuiTreeNodeFlags_DefaultOpen)) {
        const Plan& plan = renderer.plan();
        ImGui::Text("%zu passes, %zu culled; CPU %.2f ms/frame", plan.passes().size(), plan.culled().size(),
                    frameMs);
        if (ImGui::BeginTable("timings", 2, ImGuiTableFlags_SizingFixedFit)) {
            for (const PassTiming& t : renderer.completedTimings()) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(t.pass.c_str());
                ImGui::TableNextColumn();
                ImGui::Text("%7.3f ms GPU", t.milliseconds);
            }
            ImGui::EndTable();
        }
        for (const CulledPass& c : plan.culled()) ImGui::TextDisabled("culled %s: %s", c.name.c_str(), c.reason.c_str());
    }
    ImGui::End();
}

/// Two large windows side by side: the demo window and one holding the style editor (every
/// colour and size of the style as a widget), each 900x1000 (clipped to smaller outputs).
void drawDemo() {
    ImGui::SetNextWindowPos(ImVec2(20, 20), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(900, 1000), ImGuiCond_Always);
    ImGui::ShowDemoWindow();
    ImGui::SetNextWindowPos(ImVec2(940, 20), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(900, 1000), ImGuiCond_Always);
    ImGui::Begin("Style editor");
    ImGui::ShowStyleEditor();
    ImGui::End();
}

/// The ImGui context (created before the renderers, whose ImGuiPass takes the current one)
/// and, on one headless Device, a renderer of raster.json with `ui` on and one with it off.
struct ImGuiFixture {
    std::unique_ptr<Device> device;
    std::unique_ptr<FrameRenderer> withUi;
    std::unique_ptr<FrameRenderer> withoutUi;
    OverlayState overlay;
    Size size;
    explicit ImGuiFixture(Size s) : size(s) {
        DeviceOptions dopts;
        dopts.device = benchDeviceName();
        device = Device::create(dopts);
        withUi = std::make_unique<FrameRenderer>(*device, rasterOptions(size, true, library()), true);
        withoutUi = std::make_unique<FrameRenderer>(*device, rasterOptions(size, false, library()), true);
    }
    ~ImGuiFixture() { (void)finish(); }
    /// Destroys the renderers, then finishes the device (validation counts anything left
    /// alive) and returns its validation message count.
    uint32_t finish() {
        withUi.reset();  // its ImGuiPass shuts the Vulkan backend down on the context
        withoutUi.reset();
        if (!device) return 0;
        device->finish();
        const uint32_t messages = device->messageCount();
        device.reset();
        return messages;
    }
    ImGuiFixture(const ImGuiFixture&) = delete;
    ImGuiFixture& operator=(const ImGuiFixture&) = delete;
};

Fixtures<ImGuiFixture>& fixtures() {
    static Fixtures<ImGuiFixture> f;
    return f;
}

/// Validation over the fixtures finished so far.
bool validated = false;
uint32_t messages = 0;

/// Finishes and destroys every fixture but the one of `keep` (all of them without one).
void retireFixturesOtherThan(std::optional<Size> keep) {
    auto& all = fixtures().all();
    for (auto it = all.begin(); it != all.end();) {
        if (keep && it->first == keep->name()) {
            ++it;
            continue;
        }
        validated = validated || (it->second->device && it->second->device->validationEnabled());
        messages += it->second->finish();
        it = all.erase(it);
    }
}

/// One ImGui frame of `content` at the fixture's size.
void buildImGuiFrame(ImGuiFixture& f, Content content, double frameMs) {
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(float(f.size.width), float(f.size.height));
    io.DeltaTime = 1.0f / 60.0f;
    ImGui::NewFrame();
    if (content == Content::Overlay) drawOverlay(f.overlay, *f.withUi->renderer, frameMs);
    if (content == Content::Demo) drawDemo();
    ImGui::Render();
}

/// The draw data's triangles' area in pixels: the fragments the pass shades before the
/// scissor, overdraw counted (device-independent, so a GPU time divides by it).
double trianglePixels(const ImDrawData* d) {
    double area = 0.0;
    if (!d) return area;
    for (int l = 0; l < d->CmdListsCount; ++l) {
        const ImDrawList* list = d->CmdLists[l];
        for (int i = 0; i + 2 < list->IdxBuffer.Size; i += 3) {
            const ImVec2 a = list->VtxBuffer[list->IdxBuffer[i]].pos;
            const ImVec2 b = list->VtxBuffer[list->IdxBuffer[i + 1]].pos;
            const ImVec2 c = list->VtxBuffer[list->IdxBuffer[i + 2]].pos;
            area += 0.5 * std::abs(double(b.x - a.x) * double(c.y - a.y) - double(c.x - a.x) * double(b.y - a.y));
        }
    }
    return area;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void uiFrame(benchmark::State& state, Size size, Content content) {
    // One fixture at a time: the ImGui context's backend serves one device (and renderer).
    retireFixturesOtherThan(size);
    ImGuiFixture* fp = fixtures().get(state, size);
    if (!fp) return;
    ImGuiFixture& f = *fp;
    Renderer& r = content == Content::Off ? *f.withoutUi->renderer : *f.withUi->renderer;
    (content == Content::Off ? *f.withUi->renderer : *f.withoutUi->renderer).waitIdle();
    // Warm-up: the first frames upload the font atlas and settle the demo's windows.
    for (int i = 0; i < 3; ++i) {
        buildImGuiFrame(f, content, 0.0);
        r.renderFrame();
        (void)r.lastTimings();
    }
    std::vector<double> ui, frame;
    double vertices = 0, indices = 0, pixels = 0;
    for (auto _ : state) {
        buildImGuiFrame(f, content, 0.0);
        r.renderFrame();
        double total = 0.0, pass = 0.0;
        for (const PassTiming& t : r.lastTimings()) {
            total += t.milliseconds;
            if (t.pass == "ui") pass = t.milliseconds;
        }
        ui.push_back(pass);
        frame.push_back(total);
        const ImDrawData* d = ImGui::GetDrawData();
        vertices = d ? d->TotalVtxCount : 0;
        indices = d ? d->TotalIdxCount : 0;
    }
    pixels = trianglePixels(ImGui::GetDrawData());
    state.counters["ui_ms"] = median(ui);
    state.counters["frame_ms"] = median(frame);
    state.counters["vertices"] = vertices;
    state.counters["indices"] = indices;
    state.counters["triangle_px"] = pixels;
    state.SetLabel(kContentNames[size_t(content)]);
}

}  // namespace
}  // namespace skygraph::bench

int main(int argc, char** argv) {
    using namespace skygraph::bench;
    const std::vector<Size> sizes = takeSizes(argc, argv, {{1920, 1080}});
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
    spdlog::set_level(spdlog::level::warn);
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    ImGui::StyleColorsDark();
    io.Fonts->Build();  // NewFrame wants the atlas; the ImGuiPass uploads it
    for (const Size& s : sizes)
        for (Content c : {Content::Off, Content::Empty, Content::Overlay, Content::Demo})
            benchmark::RegisterBenchmark(
                ("BM_UiFrame/" + std::string(kContentNames[size_t(c)]) + "/" + s.name()).c_str(), uiFrame, s, c)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();  // iterations wait for the GPU: min_time counts real time
    int status = 0;
    try {
        if (benchmark::RunSpecifiedBenchmarks() == 0 || fixtures().failed) status = 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "imgui_bench: %s\n", e.what());
        status = 1;
    }
    try {
        retireFixturesOtherThan(std::nullopt);  // before the context their ImGuiPasses draw goes
    } catch (const std::exception& e) {
        std::fprintf(stderr, "imgui_bench: %s\n", e.what());
        status = 1;
    }
    fixtures().all().clear();
    if (validated) {
        std::printf("imgui_bench: validation: %u message(s)\n", messages);
        if (messages) status = 1;
    }
    ImGui::DestroyContext();
    benchmark::Shutdown();
    return status;
}
