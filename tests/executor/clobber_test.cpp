// Clobbering (CompileOptions::clobberTransients) on the device: a Clobber step fills a
// transient with poison before the first use that discards it, so a pass that reads what it
// declared it discards changes the frame. The negative control is such a pass: it declares
// Write@ColorAttachment and draws half its target.
#include "executor_test_util.hpp"

#include "poison.hpp"

#include <skygraph/pass.hpp>

#include <cmath>
#include <cstring>

namespace skygraph::test {
namespace {

/// Declares Write@ColorAttachment on `target` (it discards the contents) but clears only the
/// left half of it to params.color, inside the executor's render pass: the right half keeps
/// whatever the memory held.
class HalfFillPass final : public PassImplementation {
public:
    explicit HalfFillPass(const PassDesc& d) {
        const auto c = d.params.value("color", std::vector<float>{0, 0, 0, 1});
        for (size_t i = 0; i < 4 && i < c.size(); ++i) color_[i] = c[i];
    }
    void createPipelines(const PipelineContext&) override {}
    void record(const RecordContext& ctx) override {
        VkClearAttachment a{VK_IMAGE_ASPECT_COLOR_BIT, 0, {}};
        std::memcpy(a.clearValue.color.float32, color_, sizeof color_);
        const VkClearRect rect{{{0, 0}, {ctx.renderArea.width / 2, ctx.renderArea.height}}, 0, 1};
        vkCmdClearAttachments(ctx.cmd, 1, &a, 1, &rect);
    }

private:
    float color_[4] = {0, 0, 0, 1};
};

PassLibrary library() {
    PassLibrary lib = PassLibrary::withBuiltins();
    PassTypeInfo half;
    half.name = "HalfFill";
    SlotDecl target;
    target.name = "target";
    target.stage = Stage::ColorAttachment;
    target.accesses = {Access::Write};
    half.slots = {target};
    lib.add(half, [](const PassDesc& d) { return std::make_unique<HalfFillPass>(d); });
    return lib;
}

/// `tex`, a transient with no clear, is drawn half by "half" and shown whole by "show".
constexpr const char* kGraph = R"({ "version": 1, "name": "half", "resources": {
      "tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" },
      "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",
                     "external": true, "final": "Present" } },
      "passes": [
        { "name": "half", "type": "HalfFill", "uses": { "tex": "Write@ColorAttachment" },
          "params": { "color": [0, 0.5, 0, 1] } },
        { "name": "show", "type": "Generic",
          "uses": { "tex": "Read@Fragment", "swapchain": "Write@ColorAttachment" },
          "params": { "color": [0, 0, 0, 0] } } ] })";

ImageData renderHalf(const PassLibrary& lib, bool clobber) {
    GraphDesc graph = parseGraph(kGraph, "<half>", lib.registry());
    CompileOptions o = sizedOptions();
    o.memory = sharedDevice().memoryModel();
    o.aliasing = clobber;
    o.clobberTransients = clobber;
    o = headless(graph, std::move(o));
    RendererOptions ro;
    ro.passes = &lib;
    Renderer r(sharedDevice(), CompiledGraph(std::move(graph), std::move(o)), ro);
    for (int i = 0; i < 3; ++i) r.renderFrame();
    ImageData img = r.readback();
    r.waitIdle();
    return img;
}

using Clobber = ExecutorTest;

TEST_F(Clobber, APassThatDrawsHalfOfWhatItDiscardsShowsThePoison) {
    const PassLibrary lib = library();
    const ImageData plain = renderHalf(lib, false);
    const ImageData clobbered = renderHalf(lib, true);
    ASSERT_EQ(plain.rgba.size(), clobbered.rgba.size());
    // The drawn half is the same; the other half is the poison of an UNORM target, magenta,
    // where without clobbering it is whatever the memory held.
    EXPECT_PIXEL_NEAR(clobbered, 2, 8, 0.0, 0.5, 0.0, 1.0);
    EXPECT_PIXEL_NEAR(plain, 2, 8, 0.0, 0.5, 0.0, 1.0);
    EXPECT_PIXEL_NEAR(clobbered, 13, 8, 1.0, 0.0, 1.0, 1.0);
    EXPECT_NE(std::memcmp(plain.rgba.data(), clobbered.rgba.data(), plain.rgba.size() * sizeof(float)), 0)
        << "clobbering did not change what a pass that reads what it discards renders";
}

// The poison of each kind of format (poison.hpp), as the Clobber step records it.
TEST(Poison, IsNaNWhereTheFormatHoldsItAndRecognisableElsewhere) {
    const auto of = [](const char* name) { return detail::poisonFor(*findFormat(name)); };
    for (const char* f : {"R16G16B16A16_SFLOAT", "R32_SFLOAT", "B10G11R11_UFLOAT_PACK32"})
        for (const float c : of(f).color.float32) EXPECT_TRUE(std::isnan(c)) << f;
    for (const char* f : {"R8G8B8A8_UNORM", "R8G8B8A8_SNORM", "B8G8R8A8_SRGB", "A2B10G10R10_UNORM_PACK32"}) {
        const VkClearColorValue c = of(f).color;
        EXPECT_EQ((std::array{c.float32[0], c.float32[1], c.float32[2], c.float32[3]}),
                  (std::array{1.0f, 0.0f, 1.0f, 1.0f}))
            << f;
    }
    for (const char* f : {"R32_UINT", "R32_SINT", "R32G32B32A32_UINT"})
        for (const uint32_t c : of(f).color.uint32) EXPECT_EQ(c, 0xDEADBEEFu) << f;
    for (const char* f : {"D32_SFLOAT", "D24_UNORM_S8_UINT", "D16_UNORM", "S8_UINT"}) {
        EXPECT_EQ(of(f).depthStencil.depth, 0.5f) << f;
        EXPECT_EQ(of(f).depthStencil.stencil, 0x5Au) << f;
    }
    float word;
    std::memcpy(&word, &detail::kPoisonBufferWord, 4);
    EXPECT_TRUE(std::isnan(word));
}

}  // namespace
}  // namespace skygraph::test
