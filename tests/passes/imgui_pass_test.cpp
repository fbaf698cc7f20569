// ImGuiPass on lavapipe under validation + synchronization validation (ExecutorTest fails on
// any message): it draws the current Dear ImGui context's draw data over its target, nothing
// without a context, and refuses a second renderer recording the same context (the backend's
// vertex buffers are rotated without a fence of their own).
#include "pass_test_util.hpp"

#include <skygraph/pass.hpp>

#include <imgui.h>

namespace skygraph::test {
namespace {

constexpr uint32_t kWidth = 64, kHeight = 32;

const char* kGraph = R"({
  "version": 1, "name": "overlay",
  "resources": {
    "target": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 32],
               "clear": {"color": [0.0, 0.0, 0.0, 1.0]}}
  },
  "passes": [
    {"name": "ui", "type": "ImGuiPass", "uses": {"target": "ReadWrite@ColorAttachment"}}
  ]
})";

class ImGuiPassTest : public ExecutorTest {
protected:
    void SetUp() override {
        ExecutorTest::SetUp();
        library_ = PassLibrary::withBuiltins();
        graph_ = parseGraph(kGraph, "overlay.json", library_.registry());
    }
    void TearDown() override {
        renderers_.clear();  // their ImGuiPasses go before the context
        if (context_) ImGui::DestroyContext(context_);
        ExecutorTest::TearDown();
    }

    /// A context whose frame is a white rectangle over the left half of the target.
    void drawLeftHalfWhite() {
        context_ = ImGui::CreateContext();
        ImGuiIO& io = ImGui::GetIO();
        io.IniFilename = nullptr;
        io.DisplaySize = ImVec2(float(kWidth), float(kHeight));
        io.Fonts->Build();
        ImGui::NewFrame();
        ImGui::GetForegroundDrawList()->AddRectFilled(ImVec2(0, 0), ImVec2(kWidth / 2.0f, float(kHeight)),
                                                      IM_COL32_WHITE);
        ImGui::Render();
    }

    Renderer& renderer() {
        CompileOptions co;
        co.outputWidth = kWidth;
        co.outputHeight = kHeight;
        co.readbacks = {"target"};
        RendererOptions ro;
        ro.passes = &library_;
        renderers_.push_back(std::make_unique<Renderer>(sharedDevice(), CompiledGraph(graph_, co), ro));
        return *renderers_.back();
    }

    PassLibrary library_;
    GraphDesc graph_;
    ImGuiContext* context_ = nullptr;
    std::vector<std::unique_ptr<Renderer>> renderers_;
};

float red(const ImageData& image, uint32_t x, uint32_t y) { return image.rgba[4 * (size_t(y) * image.width + x)]; }

TEST_F(ImGuiPassTest, DrawsTheContextsDrawDataOverItsTarget) {
    drawLeftHalfWhite();
    Renderer& r = renderer();
    r.renderFrame();
    r.renderFrame();  // the second frame draws with the font atlas the first one uploaded
    const ImageData image = r.readback();
    for (uint32_t y = 0; y < kHeight; y += 7)
        for (uint32_t x = 0; x < kWidth; x += 5) {
            SCOPED_TRACE("pixel " + std::to_string(x) + ", " + std::to_string(y));
            EXPECT_FLOAT_EQ(red(image, x, y), x < kWidth / 2 ? 1.0f : 0.0f);
        }
}

TEST_F(ImGuiPassTest, WithoutAContextTheTargetPassesThrough) {
    ASSERT_EQ(ImGui::GetCurrentContext(), nullptr);
    Renderer& r = renderer();
    r.renderFrame();
    const ImageData image = r.readback();
    for (uint32_t i = 0; i < kWidth * kHeight; ++i) EXPECT_FLOAT_EQ(image.rgba[4 * i], 0.0f) << "pixel " << i;
}

TEST_F(ImGuiPassTest, ASecondRendererRecordingTheSameContextIsRefused) {
    drawLeftHalfWhite();
    Renderer& first = renderer();
    first.renderFrame();
    Renderer& second = renderer();
    try {
        second.renderFrame();
        FAIL() << "two renderers recorded one Dear ImGui context";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("another ImGuiPass records the same Dear ImGui context"),
                  std::string::npos)
            << e.what();
    }
    first.renderFrame();  // the first still draws
    EXPECT_FLOAT_EQ(red(first.readback(), 1, 1), 1.0f);
}

}  // namespace
}  // namespace skygraph::test
