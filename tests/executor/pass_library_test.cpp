// Pass implementations from a PassLibrary: the executor begins the render pass made from the
// plan, hands the pass its resources by slot, and records the plan's barriers around it.
#include "executor_test_util.hpp"

#include <skygraph/pass.hpp>
#include <skygraph/shader_compiler.hpp>

#include <nlohmann/json.hpp>

namespace skygraph::test {
namespace {

/// Clears its `target` attachment to params.color inside the executor's render pass.
class FillPass final : public PassImplementation {
public:
    explicit FillPass(const PassDesc& d) {
        const auto c = d.params.value("color", std::vector<float>{0, 0, 0, 1});
        for (size_t i = 0; i < 4 && i < c.size(); ++i) color_[i] = c[i];
    }
    void createPipelines(const PipelineContext& ctx) override {
        if (ctx.renderPass == VK_NULL_HANDLE) throw std::runtime_error("no render pass");
        if (ctx.resources.size() != 1 || ctx.resources[0].view == VK_NULL_HANDLE)
            throw std::runtime_error("target not bound");
        // The shader compiler is available to passes; compile something to prove it works.
        const auto spirv = ctx.shaders->compile(VK_SHADER_STAGE_COMPUTE_BIT,
                                                "#version 450\nlayout(local_size_x = 1) in;\nvoid main() {}\n",
                                                "fill.comp");
        if (spirv.empty()) throw std::runtime_error("no SPIR-V");
        ++pipelinesCreated;
    }
    void record(const RecordContext& ctx) override {
        const BoundResource* target = ctx.slot("target");
        ASSERT_NE(target, nullptr);
        EXPECT_EQ(ctx.renderArea.width, target->extent.width);
        VkClearAttachment a{VK_IMAGE_ASPECT_COLOR_BIT, 0, {}};
        std::memcpy(a.clearValue.color.float32, color_, sizeof color_);
        const VkClearRect rect{{{0, 0}, ctx.renderArea}, 0, 1};
        vkCmdClearAttachments(ctx.cmd, 1, &a, 1, &rect);
    }
    static inline int pipelinesCreated = 0;

private:
    float color_[4] = {0, 0, 0, 1};
};

/// Fails to build its pipelines: installing a plan with it must fail cleanly.
class BrokenPass final : public PassImplementation {
public:
    void createPipelines(const PipelineContext&) override { throw std::runtime_error("shader exploded"); }
    void record(const RecordContext&) override {}
};

PassLibrary library() {
    PassLibrary lib;
    PassTypeInfo fill;
    fill.name = "Fill";
    SlotDecl target;
    target.name = "target";
    target.stage = Stage::ColorAttachment;
    target.accesses = {Access::Write};
    fill.slots = {target};
    lib.add(fill, [](const PassDesc& d) { return std::make_unique<FillPass>(d); });
    PassTypeInfo broken = fill;
    broken.name = "Broken";
    lib.add(broken, [](const PassDesc&) { return std::make_unique<BrokenPass>(); });
    PassTypeInfo generic;
    generic.name = "Generic";
    generic.acceptsAnyUsage = true;
    lib.add(generic, [](const PassDesc&) -> std::unique_ptr<PassImplementation> { return nullptr; });
    return lib;
}

std::string graphText(const std::string& type) {
    return R"({ "version": 1, "name": "lib", "resources": {
      "tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" },
      "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",
                     "external": true, "final": "Present" } },
      "passes": [
        { "name": "fill", "type": ")" + type + R"(", "uses": { "tex": "Write@ColorAttachment" },
          "params": { "color": [0.25, 0.5, 0, 1] } },
        { "name": "show", "type": "Generic",
          "uses": { "tex": "Read@Fragment", "swapchain": "Write@ColorAttachment" },
          "params": { "color": [0, 0, 0.5, 0] } } ] })";
}

TEST_F(ExecutorTest, PassLibraryImplementationRecordsInsideRenderPass) {
    const PassLibrary lib = library();
    GraphDesc graph = parseGraph(graphText("Fill"), "<lib>", lib.registry());
    const CompileOptions co = headless(graph);
    RendererOptions o;
    o.passes = &lib;
    FillPass::pipelinesCreated = 0;
    Renderer r(sharedDevice(), CompiledGraph(std::move(graph), co), o);
    EXPECT_EQ(FillPass::pipelinesCreated, 1);
    for (int i = 0; i < 3; ++i) r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 5, 5, 0.25, 0.5, 0.5, 1.0);
    r.waitIdle();
}

TEST_F(ExecutorTest, PassLibraryPipelineFailureIsAnErrorAndKeepsOldPlan) {
    const PassLibrary lib = library();
    GraphDesc good = parseGraph(graphText("Fill"), "<lib>", lib.registry());
    GraphDesc bad = parseGraph(graphText("Broken"), "<lib>", lib.registry());
    const CompileOptions co = headless(good);
    RendererOptions o;
    o.passes = &lib;
    Renderer r(sharedDevice(), CompiledGraph(std::move(good), co), o);
    try {
        r.setGraph(CompiledGraph(std::move(bad), co));
        FAIL() << "expected ExecutorError";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("shader exploded"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("pass 'fill'"), std::string::npos) << e.what();
    }
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 1, 1, 0.25, 0.5, 0.5, 1.0);
    r.waitIdle();
}

}  // namespace
}  // namespace skygraph::test
