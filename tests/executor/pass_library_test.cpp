// Pass implementations from a PassLibrary: the executor begins the render pass made from the
// plan, hands the pass its resources by slot, and records the plan's barriers around it. A
// type without recording code runs with the library's Generic; without a library, or without
// a Generic in it, such a pass is an error that says so.
#include "executor_test_util.hpp"

#include <skygraph/pass.hpp>
#include <skygraph/pipeline_builder.hpp>
#include <skygraph/shader_compiler.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <type_traits>

#include <unistd.h>

#include <nlohmann/json.hpp>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

namespace skygraph::test {
namespace {

/// Clears its `target` attachment to params.color inside the executor's render pass. With a
/// shader file, compiles it (from the renderer's shader directory) for its pipelines.
class FillPass final : public PassImplementation {
public:
    explicit FillPass(const PassDesc& d, std::string shaderFile = {}) : shaderFile_(std::move(shaderFile)) {
        const auto c = d.params.value("color", std::vector<float>{0, 0, 0, 1});
        for (size_t i = 0; i < 4 && i < c.size(); ++i) color_[i] = c[i];
    }
    void createPipelines(const PipelineContext& ctx) override {
        if (ctx.renderPass == VK_NULL_HANDLE) throw std::runtime_error("no render pass");
        if (ctx.resources.size() != 1 || ctx.resources[0].view == VK_NULL_HANDLE)
            throw std::runtime_error("target not bound");
        // The shader compiler is available to passes; compile something to prove it works.
        const auto spirv = shaderFile_.empty()
                               ? ctx.shaders->compile(VK_SHADER_STAGE_COMPUTE_BIT,
                                                      "#version 450\nlayout(local_size_x = 1) in;\nvoid main() {}\n",
                                                      "fill.comp")
                               : compileShader(*ctx.shaders, VK_SHADER_STAGE_COMPUTE_BIT, shaderFile_);
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
    std::string shaderFile_;
    float color_[4] = {0, 0, 0, 1};
};

/// Fails to build its pipelines: installing a plan with it must fail cleanly.
class BrokenPass final : public PassImplementation {
public:
    void createPipelines(const PipelineContext&) override { throw std::runtime_error("shader exploded"); }
    void record(const RecordContext&) override {}
};

/// One required slot, "target", that `stage` writes.
PassTypeInfo fillType(Stage stage = Stage::ColorAttachment) {
    PassTypeInfo fill;
    fill.name = "Fill";
    SlotDecl target;
    target.name = "target";
    target.stage = stage;
    target.accesses = {Access::Write};
    fill.slots = {target};
    return fill;
}

/// The built-in passes (Generic for "show"), the two above, and FileFill: Fill compiling
/// fill.comp from the shader directory.
PassLibrary library() {
    PassLibrary lib = PassLibrary::withBuiltins();
    lib.add(fillType(), [](const PassDesc& d) { return std::make_unique<FillPass>(d); });
    PassTypeInfo fileFill = fillType();
    fileFill.name = "FileFill";
    lib.add(fileFill, [](const PassDesc& d) { return std::make_unique<FillPass>(d, "fill.comp"); });
    PassTypeInfo broken = fillType();
    broken.name = "Broken";
    lib.add(broken, [](const PassDesc&) { return std::make_unique<BrokenPass>(); });
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

// A GraphDesc built in code names its usages' slots itself: a renderer refuses, by name, a
// usage that fills no declared slot or fills one with another usage, and a required slot left
// empty (before, the pass's recording code found no slot, and a built-in one crashed on it).
TEST_F(ExecutorTest, APlanWhoseUsagesDoNotFillTheirTypesSlotsIsRefusedByName) {
    PassLibrary lib = library();
    PassTypeInfo pair = fillType();
    pair.name = "Pair";
    SlotDecl extra;
    extra.name = "extra";
    extra.stage = Stage::Fragment;
    extra.accesses = {Access::Read};
    extra.optional = true;  // as the graph is loaded; the library's declaration requires it
    pair.slots.push_back(extra);
    PassRegistry loading = lib.registry();
    loading.add(pair);
    pair.slots.back().optional = false;
    lib.add(pair, [](const PassDesc& d) { return std::make_unique<FillPass>(d); });
    const auto error = [&](const std::string& type, const std::function<void(GraphDesc&)>& edit) -> std::string {
        GraphDesc g = parseGraph(graphText(type), "<lib>", loading);
        edit(g);
        const CompileOptions co = headless(g);
        RendererOptions o;
        o.passes = &lib;
        try {
            Renderer r(sharedDevice(), CompiledGraph(std::move(g), co), o);
        } catch (const ExecutorError& e) {
            // Where the graph declares the pass comes first, as in the compiler's messages.
            const std::string what = e.what();
            const std::string at = "<lib>: passes[" + std::string(what.find("pass 'show'") != std::string::npos ? "1" : "0") +
                                   "]: ";
            EXPECT_TRUE(what.starts_with(at)) << what;
            return what.starts_with(at) ? what.substr(at.size()) : what;
        }
        return "accepted";
    };
    EXPECT_EQ(error("Fill", [](GraphDesc&) {}), "accepted");
    EXPECT_EQ(error("Fill", [](GraphDesc& g) { g.passes[0].uses[0].slot = 0; }),
              "pass 'fill', resource 'tex': fills no slot of type 'Fill'");
    EXPECT_EQ(error("Fill", [](GraphDesc& g) { g.passes[0].uses[0].slot = g.internSlot("other"); }),
              "pass 'fill', resource 'tex': fills 'other', which type 'Fill' does not declare");
    EXPECT_EQ(error("Fill", [](GraphDesc& g) { g.passes[0].uses[0].usage.stage = Stage::Compute; }),
              "pass 'fill', resource 'tex': fills slot 'target' (Write@ColorAttachment) as Write@Compute");
    EXPECT_EQ(error("Pair", [](GraphDesc&) {}),
              "pass 'fill': type 'Pair' needs slot 'extra' (Read@Fragment); no usage fills it");
    // Generic takes any usage: a slot named in code is a mistake, as the loader says of a file.
    const auto nameSlotOfTex = [](GraphDesc& g) {
        for (UsageDecl& u : g.passes[1].uses)
            if (g.resources[u.resource].name == "tex") u.slot = g.internSlot("target");
    };
    EXPECT_EQ(error("Fill", nameSlotOfTex),
              "pass 'show', resource 'tex': fills slot 'target', but type 'Generic' takes any usage and has no slots");
}

// A slot that binds a cube binds a cube view, of every face: a GraphDesc built in code that
// narrows the usage to some faces is refused as the loader refuses it in a file (the renderer
// made a 2D array view, which the shader's samplerCube cannot read).
TEST_F(ExecutorTest, ACubeSlotFilledWithSomeFacesIsRefusedByName) {
    const PassLibrary lib = library();
    GraphDesc g = parseGraph(R"({ "version": 1, "name": "faces", "resources": {
        "sky": { "type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [8, 8], "external": true },
        "depth": { "type": "image2d", "format": "D32_SFLOAT", "extent": "output", "clear": { "depth": 0.0 } },
        "color": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output", "external": true,
                   "final": "TransferSrc" } },
      "passes": [ { "name": "forward", "type": "ForwardPass", "uses": {
          "color": "Write@ColorAttachment", "depth": "Write@DepthAttachment" } } ] })",
                             "<faces>", lib.registry());
    UsageDecl faces;
    faces.resource = static_cast<uint32_t>(g.findResource("sky") - g.resources.data());
    faces.usage.access = Access::Read;
    faces.usage.stage = Stage::Fragment;
    faces.usage.as = BindAs::Sampled;
    faces.usage.range = SubresourceRange{0, 1, 0, 3};
    faces.slot = g.internSlot("environment");
    g.passes[0].uses.push_back(faces);
    const CompileOptions co = headless(g);
    RendererOptions o;
    o.passes = &lib;
    try {
        Renderer r(sharedDevice(), CompiledGraph(std::move(g), co), o);
        ADD_FAILURE() << "a cube slot was filled with three faces";
    } catch (const ExecutorError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "<faces>: passes[0]: pass 'forward', resource 'sky': fills slot 'environment', which binds the whole "
                  "cube, with layers [0, 3] of it");
    }
}

// A GraphDesc built in code skips the loader, which runs a type's validators: a renderer runs
// them too, and refuses by name what they refuse (before, params out of their declared range
// rendered silently with other values).
TEST_F(ExecutorTest, APassWhoseParamsOrUsagesItsTypeRefusesIsRefusedByName) {
    PassLibrary lib = library();
    PassTypeInfo checked = fillType();
    checked.name = "Checked";
    PassRegistry loading = lib.registry();
    loading.add(checked);  // as the graph is built: nothing checked
    checked.validateParams = [](const nlohmann::json& params) {
        std::vector<ParamError> errors;
        if (params.contains("color") && params["color"][0].get<double>() > 0.2)
            errors.push_back(ParamError::forKey("color", "red must be at most 0.2"));
        return errors;
    };
    checked.validateUsages = [](const PassDesc&, const GraphDesc&) {
        return std::vector<UsageError>{{0, "wants a float target"}};
    };
    checked.validatePlannedPass = [](const PlannedPass& pass, const Plan&) {
        return std::vector<UsageError>{{0, "wants to run after '" + std::string(pass.name) + "'"}};
    };
    lib.add(checked, [](const PassDesc& d) { return std::make_unique<FillPass>(d); });
    GraphDesc g = parseGraph(graphText("Checked"), "<lib>", loading);
    const CompileOptions co = headless(g);
    RendererOptions o;
    o.passes = &lib;
    std::string error = "accepted";
    try {
        Renderer r(sharedDevice(), CompiledGraph(std::move(g), co), o);
    } catch (const ExecutorError& e) {
        error = e.what();
    }
    EXPECT_EQ(error, "<lib>: passes[0]: pass 'fill': params.color: red must be at most 0.2; pass 'fill', resource "
                     "'tex': wants a float target; pass 'fill', resource 'tex': wants to run after 'fill'");
}

/// The error of setGraph() to a graph whose "fill" pass is of `type`, on a renderer of the
/// graph with Fill, which must keep rendering its old plan; empty when setGraph succeeds.
std::string setGraphError(const PassLibrary& lib, const std::string& type) {
    GraphDesc good = parseGraph(graphText("Fill"), "<lib>", lib.registry());
    const CompileOptions co = headless(good);
    RendererOptions o;
    o.passes = &lib;
    Renderer r(sharedDevice(), CompiledGraph(std::move(good), co), o);
    std::string error;
    try {
        r.setGraph(CompiledGraph(parseGraph(graphText(type), "<lib>", lib.registry()), co));
    } catch (const ExecutorError& e) {
        error = e.what();
    }
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 1, 1, 0.25, 0.5, 0.5, 1.0);
    r.waitIdle();
    return error;
}

TEST_F(ExecutorTest, PassLibraryPipelineFailureIsAnErrorAndKeepsOldPlan) {
    const std::string e = setGraphError(library(), "Broken");
    EXPECT_NE(e.find("shader exploded"), std::string::npos) << e;
    EXPECT_NE(e.find("pass 'fill'"), std::string::npos) << e;
}

/// A new, empty shader folder for FileFill's shader, with the include its "show" needs.
std::filesystem::path fileFillShaderDir(const std::string& prefix) {
    const auto dir = std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    std::filesystem::copy_file(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "shaders" / "generic_common.glsl",
                               dir / "generic_common.glsl");
    return dir;
}

TEST_F(ExecutorTest, AShaderFileBrokenOnDiskFailsOnlyTheCallsThatReadShadersAgain) {
    const auto dir = fileFillShaderDir("skygraph_sources_");
    const auto shader = dir / "fill.comp";
    const auto write = [&](const std::string& text) { std::ofstream(shader, std::ios::binary | std::ios::trunc) << text; };
    write("#version 450\nlayout(local_size_x = 1) in;\nvoid main() {}\n");
    const PassLibrary lib = library();
    const GraphDesc graph = parseGraph(graphText("FileFill"), "<lib>", lib.registry());
    const CompileOptions co = headless(graph);
    RendererOptions o;
    o.passes = &lib;
    o.shaderDir = dir;
    Renderer r(sharedDevice(), CompiledGraph(graph, co), o);
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 5, 5, 0.25, 0.5, 0.5, 1.0);

    write("this is not glsl");
    // A resize, a graph installed with its cached shaders: built from the source that ran.
    EXPECT_NO_THROW(r.resize(24, 24));
    EXPECT_NO_THROW(r.setGraph(CompiledGraph(graph, co)));
    // Reading the shaders again fails, and the old pipelines and their sources stay.
    EXPECT_THROW(r.reloadShaders(), ExecutorError);
    EXPECT_THROW(r.setGraph(CompiledGraph(graph, co), Renderer::ShaderSources::Reread), ExecutorError);
    EXPECT_NO_THROW(r.resize(20, 20));
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 19, 19, 0.25, 0.5, 0.5, 1.0);
    // A renderer made to replace this one builds from its sources; one that reads the shader
    // directory does not build.
    EXPECT_THROW(Renderer(sharedDevice(), CompiledGraph(graph, co), o), ExecutorError);
    RendererOptions replacing = o;
    replacing.shaderDir = dir / "elsewhere";  // unused: the sources' directory is r's
    replacing.shaderCompiler = r.shaderCompiler();
    {
        Renderer replacement(sharedDevice(), CompiledGraph(graph, co), replacing);
        replacement.renderFrame();
        EXPECT_PIXEL_NEAR(replacement.readback(), 5, 5, 0.25, 0.5, 0.5, 1.0);
        EXPECT_THROW(replacement.reloadShaders(), ExecutorError) << "its reload reads the directory";
        replacement.waitIdle();
    }

    write("#version 450\nlayout(local_size_x = 2) in;\nvoid main() {}\n");
    EXPECT_NO_THROW(r.reloadShaders());
    write("this is not glsl");
    EXPECT_NO_THROW(r.resize(16, 16));
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 15, 15, 0.25, 0.5, 0.5, 1.0);
    r.waitIdle();
    std::filesystem::remove_all(dir);
}

// The compiler a renderer built with keeps the sources it read after the renderer is gone: a
// renderer made from it later (RendererOptions::shaderCompiler) builds from them while the
// file on disk is broken, as one made from a running renderer's compiler does.
TEST_F(ExecutorTest, ARendererBuildsFromTheKeptSourcesOfOneThatIsGone) {
    const auto dir = fileFillShaderDir("skygraph_kept_sources_");
    std::ofstream(dir / "fill.comp") << "#version 450\nlayout(local_size_x = 1) in;\nvoid main() {}\n";
    const PassLibrary lib = library();
    const GraphDesc graph = parseGraph(graphText("FileFill"), "<lib>", lib.registry());
    const CompileOptions co = headless(graph);
    RendererOptions o;
    o.passes = &lib;
    o.shaderDir = dir;
    std::shared_ptr<ShaderCompiler> kept;
    {
        Renderer first(sharedDevice(), CompiledGraph(graph, co), o);
        kept = first.shaderCompiler();
        first.waitIdle();
    }
    std::ofstream(dir / "fill.comp", std::ios::trunc) << "this is not glsl";
    EXPECT_THROW(Renderer(sharedDevice(), CompiledGraph(graph, co), o), ExecutorError) << "it reads the directory";
    RendererOptions later = o;
    later.shaderDir = dir / "elsewhere";  // unused: the sources' directory is the compiler's
    later.shaderCompiler = kept;
    Renderer r(sharedDevice(), CompiledGraph(graph, co), later);
    EXPECT_EQ(r.shaderDir(), dir);
    EXPECT_EQ(r.shaderCompiler(), kept);
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 5, 5, 0.25, 0.5, 0.5, 1.0);
    EXPECT_THROW(r.reloadShaders(), ExecutorError) << "its reload reads the directory";
    EXPECT_EQ(r.shaderCompiler(), kept) << "a failed reload keeps the sources that ran";
    r.waitIdle();
    std::filesystem::remove_all(dir);
}

TEST_F(ExecutorTest, APassWithoutRecordingCodeNeedsAPassLibrary) {
    const PassLibrary lib = library();
    GraphDesc graph = parseGraph(graphText("Fill"), "<lib>", lib.registry());
    const CompileOptions co = headless(graph);
    try {
        Renderer r(sharedDevice(), CompiledGraph(std::move(graph), co), RendererOptions{});
        FAIL() << "expected ExecutorError";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("pass 'fill'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("RendererOptions::passes"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("PassLibrary::withBuiltins()"), std::string::npos) << e.what();
    }
}

TEST_F(ExecutorTest, ATypeWithoutRecordingCodeRunsWithTheLibrarysGeneric) {
    // A library of Fill alone: "show" (type Generic) has no recording code and no Generic to
    // run with; with Generic added it renders.
    PassLibrary fillOnly;
    fillOnly.add(fillType(), [](const PassDesc& d) { return std::make_unique<FillPass>(d); });
    const PassLibrary lib = library();
    GraphDesc graph = parseGraph(graphText("Fill"), "<lib>", lib.registry());
    const CompileOptions co = headless(graph);
    RendererOptions o;
    o.passes = &fillOnly;
    try {
        Renderer r(sharedDevice(), CompiledGraph(graph, co), o);
        FAIL() << "expected ExecutorError";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("pass 'show'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("no 'Generic'"), std::string::npos) << e.what();
    }
    const PassLibrary builtins = PassLibrary::withBuiltins();
    fillOnly.add(*builtins.registry().find("Generic"), *builtins.factory("Generic"));
    Renderer r(sharedDevice(), CompiledGraph(std::move(graph), co), o);
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 3, 3, 0.25, 0.5, 0.5, 1.0);
    r.waitIdle();
}

/// Builds its pipeline from `recipe`'s shaders: the vertex shader of the fullscreen triangle
/// unless `vertex` is false, a fragment shader only when `fragment` is, and `notSpirv` words
/// in place of the vertex shader when it is set; `adjust` changes the recipe last.
class RecipePass final : public PassImplementation {
public:
    RecipePass(bool vertex, bool fragment, bool notSpirv, bool renderPass = true,
               std::function<void(GraphicsPipelineRecipe&)> adjust = {})
        : vertex_(vertex), fragment_(fragment), notSpirv_(notSpirv), renderPass_(renderPass),
          adjust_(std::move(adjust)) {}
    void createPipelines(const PipelineContext& ctx) override {
        GraphicsPipelineRecipe recipe;
        if (vertex_) recipe.vertex = compileShader(*ctx.shaders, VK_SHADER_STAGE_VERTEX_BIT, "passes/fullscreen.vert");
        if (notSpirv_) recipe.vertex = {1, 2, 3, 4};
        if (fragment_)
            recipe.fragment = ctx.shaders->compile(VK_SHADER_STAGE_FRAGMENT_BIT,
                                                   "#version 450\nlayout(location = 0) in vec2 uv;\n"
                                                   "layout(location = 0) out vec4 o;\n"
                                                   "void main() { o = vec4(uv, 1, 1); }\n",
                                                   "white.frag");
        recipe.renderPass = renderPass_ ? ctx.renderPass : VK_NULL_HANDLE;
        if (adjust_) adjust_(recipe);
        pipeline_ = createGraphicsPipeline(ctx.device, recipe);
    }
    void record(const RecordContext& ctx) override {
        vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
        const VkViewport viewport{0, 0, float(ctx.renderArea.width), float(ctx.renderArea.height), 0, 1};
        const VkRect2D scissor{{0, 0}, ctx.renderArea};
        vkCmdSetViewport(ctx.cmd, 0, 1, &viewport);
        vkCmdSetScissor(ctx.cmd, 0, 1, &scissor);
        vkCmdDraw(ctx.cmd, 3, 1, 0, 0);
    }

private:
    bool vertex_, fragment_, notSpirv_, renderPass_;
    std::function<void(GraphicsPipelineRecipe&)> adjust_;
    GraphicsPipeline pipeline_;
};

/// The renderer's result for a graph whose "fill" pass is of `type`, from `lib`: the error
/// message, or empty when it renders (a frame, read back).
std::string renderError(const PassLibrary& lib, const std::string& type) {
    GraphDesc graph = parseGraph(graphText(type), "<lib>", lib.registry());
    const CompileOptions co = headless(graph);
    RendererOptions o;
    o.passes = &lib;
    try {
        Renderer r(sharedDevice(), CompiledGraph(std::move(graph), co), o);
        r.renderFrame();
        (void)r.readback();
        r.waitIdle();
    } catch (const ExecutorError& e) {
        // Without where the graph declares the pass, which what the renderer refuses before
        // the first frame begins with (APlanWhoseUsagesDoNotFillTheirTypesSlotsIsRefusedByName).
        const std::string what = e.what(), at = "<lib>: passes[0]: ";
        return what.starts_with(at) ? what.substr(at.size()) : what;
    }
    return {};
}

/// Calls fillSampledImages, with nothing to fill, before its render pass or from record()
/// (inside the render pass of a graphics pass; a compute pass has no other place).
class SampledFillPass final : public PassImplementation {
public:
    explicit SampledFillPass(bool fromRecord) : fromRecord_(fromRecord) {}
    void createPipelines(const PipelineContext&) override {}
    void recordBeforeRenderPass(const RecordContext& ctx) override {
        if (!fromRecord_) ctx.fillSampledImages({});
    }
    void record(const RecordContext& ctx) override {
        if (fromRecord_) ctx.fillSampledImages({});
    }

private:
    bool fromRecord_;
};

// Copies, blits and barriers inside a render pass are invalid Vulkan: a pass calling
// fillSampledImages from record() is told where to call it instead.
TEST_F(ExecutorTest, FillingSampledImagesInsideTheRenderPassIsRefusedByPass) {
    PassLibrary lib = library();
    for (const bool inside : {true, false}) {
        PassTypeInfo info = fillType();
        info.name = inside ? "FillsInside" : "FillsBefore";
        lib.add(info, [inside](const PassDesc&) { return std::make_unique<SampledFillPass>(inside); });
    }
    EXPECT_EQ(renderError(lib, "FillsInside"),
              "pass 'fill': fillSampledImages was called inside the render pass: call it from recordBeforeRenderPass");
    EXPECT_EQ(renderError(lib, "FillsBefore"), "");
    EXPECT_EQ(sharedDevice().messageCount(), 0u) << formatMessages(sharedDevice());

    // The blits and the fragment shader's wait need the graphics queue.
    PassTypeInfo compute = fillType(Stage::Compute);
    compute.name = "FillsOnCompute";
    lib.add(compute, [](const PassDesc&) { return std::make_unique<SampledFillPass>(true); });
    GraphDesc graph = parseGraph(R"({ "version": 1, "name": "lib", "resources": {
          "img": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8] } },
        "passes": [ { "name": "fill", "type": "FillsOnCompute", "queue": "compute", "never_cull": true,
                      "uses": { "img": "Write@Compute" } } ] })",
                                 "<lib>", lib.registry());
    const CompileOptions co = headless(graph);
    RendererOptions o;
    o.passes = &lib;
    Renderer r(sharedDevice(), CompiledGraph(std::move(graph), co), o);
    try {
        r.renderFrame();
        ADD_FAILURE() << "sampled images were filled on the compute queue";
    } catch (const ExecutorError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "pass 'fill': fillSampledImages needs the graphics queue, and the pass runs on the compute queue");
    }
    r.waitIdle();
}

// What an application's pass code throws, from its factory or through the pipeline builder,
// comes out of the renderer as an ExecutorError naming the pass; the pipeline builder refuses
// empty or foreign shader code (which a driver may crash on) and a missing render pass, and
// builds a pipeline without a fragment stage.
TEST_F(ExecutorTest, ErrorsOfAPassesOwnCodeNameThePass) {
    PassLibrary lib = library();
    PassTypeInfo throwing = fillType();
    throwing.name = "ThrowingFactory";
    lib.add(throwing, [](const PassDesc& d) -> std::unique_ptr<PassImplementation> {
        (void)d.params.json().at("strength");  // nlohmann throws: the key is missing
        return nullptr;
    });
    const std::pair<const char*, std::function<std::unique_ptr<PassImplementation>(const PassDesc&)>> recipes[] = {
        {"NoVertex", [](const PassDesc&) { return std::make_unique<RecipePass>(false, true, false); }},
        {"NotSpirv", [](const PassDesc&) { return std::make_unique<RecipePass>(true, true, true); }},
        {"DepthOnly", [](const PassDesc&) { return std::make_unique<RecipePass>(true, false, false); }},
        {"NoRenderPass", [](const PassDesc&) { return std::make_unique<RecipePass>(true, true, false, false); }},
        {"OddPushConstants",
         [](const PassDesc&) {
             return std::make_unique<RecipePass>(true, true, false, true,
                                                 [](GraphicsPipelineRecipe& r) { r.pushConstantBytes = 6; });
         }},
        {"TwoBlendsForOne",
         [](const PassDesc&) {
             return std::make_unique<RecipePass>(true, true, false, true, [](GraphicsPipelineRecipe& r) {
                 r.blends.resize(2);
                 for (auto& b : r.blends) b.colorWriteMask = 0xf;
             });
         }},
        {"OneBlendForOne",
         [](const PassDesc&) {
             return std::make_unique<RecipePass>(true, true, false, true, [](GraphicsPipelineRecipe& r) {
                 r.blends.resize(1);
                 r.blends[0].colorWriteMask = 0xf;
                 r.pushConstantBytes = 8;
             });
         }},
    };
    for (const auto& [name, factory] : recipes) {
        PassTypeInfo info = fillType();
        info.name = name;
        lib.add(info, factory);
    }
    std::string e = renderError(lib, "ThrowingFactory");
    EXPECT_TRUE(e.starts_with("pass 'fill': making the implementation of type 'ThrowingFactory': ")) << e;
    EXPECT_NE(e.find("strength"), std::string::npos) << e;
    e = renderError(lib, "NoVertex");
    EXPECT_EQ(e, "pass 'fill': creating pipelines: createGraphicsPipeline: the recipe has no vertex shader");
    e = renderError(lib, "NotSpirv");
    EXPECT_EQ(e, "pass 'fill': creating pipelines: createGraphicsPipeline: the recipe's vertex shader is not SPIR-V");
    e = renderError(lib, "NoRenderPass");
    EXPECT_TRUE(e.starts_with("pass 'fill': creating pipelines: createGraphicsPipeline: the recipe has no render pass"))
        << e;
    // Vulkan takes push constants in words and a blend state per attachment: the builder
    // says so rather than handing the driver a recipe it may crash on.
    e = renderError(lib, "OddPushConstants");
    EXPECT_EQ(e, "pass 'fill': creating pipelines: createGraphicsPipeline: the recipe's pushConstantBytes (6) is not "
                 "a multiple of 4");
    e = renderError(lib, "TwoBlendsForOne");
    EXPECT_EQ(e, "pass 'fill': creating pipelines: createGraphicsPipeline: the recipe has 2 blend state(s) for 1 "
                 "color attachment(s); give one per attachment of the subpass");
    EXPECT_EQ(renderError(lib, "OneBlendForOne"), "");
    // No fragment stage: the color attachment keeps what it had, and nothing is reported.
    EXPECT_EQ(renderError(lib, "DepthOnly"), "");
    EXPECT_EQ(sharedDevice().messageCount(), 0u) << formatMessages(sharedDevice());

    // setGraph keeps the old plan, and says the same.
    e = setGraphError(lib, "ThrowingFactory");
    EXPECT_NE(e.find("pass 'fill': making the implementation"), std::string::npos) << e;
}

// A pass type's validators are the application's code too: what they throw is a GraphError
// at the pass's params or uses, naming the pass, not a JSON syntax error.
TEST(PassValidators, AValidatorThatThrowsIsReportedAtThePass) {
    PassRegistry registry = PassRegistry::withBuiltins();
    PassTypeInfo params = fillType();
    params.name = "StrictParams";
    params.validateParams = [](const nlohmann::json& p) {
        (void)p.at("strength").get<double>();
        return std::vector<ParamError>{};
    };
    registry.add(params);
    PassTypeInfo usages = fillType();
    usages.name = "StrictUsages";
    usages.validateUsages = [](const PassDesc&, const GraphDesc&) -> std::vector<UsageError> {
        throw std::runtime_error("cannot tell");
    };
    registry.add(usages);
    // Something other than a std::exception is named as such, not let through untyped.
    PassTypeInfo oddParams = fillType();
    oddParams.name = "OddParams";
    oddParams.validateParams = [](const nlohmann::json&) -> std::vector<ParamError> { throw 42; };
    registry.add(oddParams);
    PassTypeInfo oddUsages = fillType();
    oddUsages.name = "OddUsages";
    oddUsages.validateUsages = [](const PassDesc&, const GraphDesc&) -> std::vector<UsageError> { throw 42; };
    registry.add(oddUsages);
    const std::pair<const char*, const char*> cases[] = {
        {"StrictParams", "passes[0].params: pass 'fill': the params validator of type 'StrictParams' threw: "},
        {"StrictUsages", "passes[0].uses: pass 'fill': the usage validator of type 'StrictUsages' threw: cannot tell"},
        {"OddParams", "passes[0].params: pass 'fill': the params validator of type 'OddParams' threw something "
                      "other than a std::exception"},
        {"OddUsages", "passes[0].uses: pass 'fill': the usage validator of type 'OddUsages' threw something other "
                      "than a std::exception"},
    };
    for (const auto& [type, expected] : cases) {
        try {
            (void)parseGraph(graphText(type), "lib.json", registry);
            ADD_FAILURE() << type << " loaded";
        } catch (const GraphError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(expected), std::string::npos) << what;
            EXPECT_EQ(what.find("malformed JSON"), std::string::npos) << what;
        }
    }
}

// What a type's plan validator finds is a diagnostic at the usage it names, or at the pass for
// one it cannot name, and what it throws is one at the pass; passes of other types, and the
// plan's inserted steps, are not asked.
TEST(PassValidators, APlanValidatorIsReportedAtTheUsageOrThePass) {
    PassRegistry registry = PassRegistry::withBuiltins();
    PassTypeInfo named = fillType();
    named.name = "PlanChecked";
    named.validatePlannedPass = [](const PlannedPass& pass, const Plan& plan) {
        EXPECT_EQ(pass.name, "fill");
        EXPECT_EQ(plan.passes().front().name, "fill");
        return std::vector<UsageError>{{0, "wants it cleared"}, {7, "wants a second usage"}};
    };
    registry.add(named);
    PassTypeInfo throwing = fillType();
    throwing.name = "PlanThrows";
    throwing.validatePlannedPass = [](const PlannedPass&, const Plan&) -> std::vector<UsageError> {
        throw std::runtime_error("cannot tell");
    };
    registry.add(throwing);
    PassTypeInfo odd = fillType();
    odd.name = "PlanThrowsOddly";
    odd.validatePlannedPass = [](const PlannedPass&, const Plan&) -> std::vector<UsageError> { throw 42; };
    registry.add(odd);
    const auto problems = [&](const std::string& type) {
        const GraphDesc g = parseGraph(graphText(type), "lib.json", registry);
        return plannedPassProblems(compile(g, headless(g)), g, registry).format();
    };
    EXPECT_EQ(problems("PlanChecked"), "lib.json: passes[0].uses.tex: pass 'fill', resource 'tex': wants it cleared\n"
                                       "lib.json: passes[0]: pass 'fill': wants a second usage\n");
    EXPECT_EQ(problems("PlanThrows"), "lib.json: passes[0]: pass 'fill': the plan validator of type 'PlanThrows' "
                                      "threw: cannot tell\n");
    EXPECT_EQ(problems("PlanThrowsOddly"), "lib.json: passes[0]: pass 'fill': the plan validator of type "
                                           "'PlanThrowsOddly' threw something other than a std::exception\n");
    EXPECT_EQ(problems("Generic"), "");
    // A renderer asks the same validators, and refuses the pass alike.
    PassLibrary lib = library();
    for (PassTypeInfo info : {throwing, odd})
        lib.add(info, [](const PassDesc& d) { return std::make_unique<FillPass>(d); });
    EXPECT_EQ(renderError(lib, "PlanThrows"), "pass 'fill': the validators of type 'PlanThrows' threw: cannot tell");
    EXPECT_EQ(renderError(lib, "PlanThrowsOddly"),
              "pass 'fill': the validators of type 'PlanThrowsOddly' threw something other than a std::exception");
}

// PassRegistry::add refuses a declaration the loader could not bind usages to, naming the type
// and the slot, and registers nothing.
TEST(PassValidators, AMalformedTypeIsRefusedWhenAdded) {
    PassRegistry registry = PassRegistry::withBuiltins();
    const auto refusal = [&](PassTypeInfo info) -> std::string {
        try {
            registry.add(std::move(info));
        } catch (const std::invalid_argument& e) {
            return e.what();
        }
        return "added";
    };
    PassTypeInfo info = fillType();
    info.name = "";
    EXPECT_EQ(refusal(info), "pass type with an empty name");
    info.name = "Generic";
    EXPECT_EQ(refusal(info), "pass type 'Generic' is already registered");
    info = fillType();
    info.slots[0].name = "";
    EXPECT_EQ(refusal(info), "pass type 'Fill': a slot with an empty name");
    info = fillType();
    info.slots[0].accesses.clear();
    EXPECT_EQ(refusal(info), "pass type 'Fill': slot 'target' allows no access");
    info = fillType();
    info.slots.push_back(info.slots[0]);
    EXPECT_EQ(refusal(info), "pass type 'Fill': duplicate slot 'target'");
    info = fillType();
    info.slots[0].as = BindAs::Storage;
    EXPECT_EQ(refusal(info), "pass type 'Fill': slot 'target' sets `as` on a non-shader stage");
    // Slots no usage could fill: every graph using the type would fail, blaming the graph.
    info = fillType();
    info.slots[0].stage = Stage::VertexInput;
    info.slots[0].accesses = {Access::Read, Access::Write};
    EXPECT_EQ(refusal(info), "pass type 'Fill': slot 'target' declares Write@VertexInput, which no resource can be "
                             "used as");
    info = fillType();
    info.slots[0].stage = Stage::Fragment;
    info.slots[0].as = BindAs::Sampled;
    info.slots[0].types = {ResourceType::Buffer};
    info.slots[0].accesses = {Access::Read};
    EXPECT_EQ(refusal(info), "pass type 'Fill': slot 'target' declares Read@Fragment as sampled, which no resource "
                             "of its types can be used as");
    info = fillType();
    info.slots[0].stage = Stage(42);
    EXPECT_EQ(refusal(info), "pass type 'Fill': slot 'target' holds an access, stage or binding outside its enum");
    info = fillType();
    info.acceptsAnyUsage = true;  // slots no usage would be bound to
    EXPECT_EQ(refusal(info), "pass type 'Fill': takes any usage and declares slots (a type does one or the other)");
    info.slots.clear();
    info.name = "AnyFill";
    EXPECT_EQ(refusal(info), "added");
    EXPECT_EQ(registry.find("Fill"), nullptr);
    EXPECT_EQ(refusal(fillType()), "added");
}

// A type the library has no recording code for runs as Generic, and the renderer says so as a
// warning, once per type: not again when a resize rebuilds the passes. A library of Generic
// alone asks for that and hears nothing.
TEST_F(ExecutorTest, APassTypeWithoutRecordingCodeIsWarnedOfOnce) {
    const auto sink = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(16);
    const auto previous = spdlog::default_logger();
    spdlog::set_default_logger(std::make_shared<spdlog::logger>("pass_library_test", sink));
    const PassLibrary registryOnly = library();  // declares Fill, parses the graph
    PassLibrary withoutFill;
    const PassLibrary builtins = PassLibrary::withBuiltins();
    for (const char* type : {"Generic", "TonemappingPass"})
        withoutFill.add(*builtins.registry().find(type), *builtins.factory(type));
    GraphDesc graph = parseGraph(graphText("Fill"), "<lib>", registryOnly.registry());
    const CompileOptions co = headless(graph);
    RendererOptions o;
    const PassLibrary* const libraries[] = {&withoutFill, &PassLibrary::genericOnly()};
    for (const PassLibrary* library : libraries) {
        o.passes = library;
        Renderer r(sharedDevice(), CompiledGraph(graph, co), o);
        r.renderFrame();
        r.resize(24, 16);
        r.renderFrame();
        r.waitIdle();
    }
    spdlog::set_default_logger(previous);
    std::vector<std::string> warnings;
    for (const auto& line : sink->last_formatted())
        if (line.find("[warning]") != std::string::npos) warnings.push_back(line);
    ASSERT_EQ(warnings.size(), 1u) << ::testing::PrintToString(sink->last_formatted());
    EXPECT_NE(warnings[0].find("pass 'fill' of type 'Fill' runs as Generic: the renderer's pass library has no "
                               "recording code for 'Fill'"),
              std::string::npos)
        << warnings[0];
}

// FrameData's key is the value's type: a bare number, pointer or string literal is refused at
// compile time, since `set(1.0)` would never be found by `get<float>()`.
struct Exposure {
    float ev = 0;
};
template <typename T>
concept Settable = requires(FrameData& data, T value) { data.set(value); };
template <typename T>
concept Gettable = requires(const FrameData& data) { data.template get<T>(); };
static_assert(Settable<Exposure> && Gettable<Exposure>);
static_assert(!Settable<double> && !Settable<const char*> && !Settable<int*>);
static_assert(!Gettable<float>);
// The renderer's FrameData is the one passes read: a copy or a move of it would hold values
// no pass sees (`auto data = renderer.frameData();`), so neither compiles.
static_assert(!std::is_copy_constructible_v<FrameData> && !std::is_copy_assignable_v<FrameData>);
static_assert(!std::is_move_constructible_v<FrameData> && !std::is_move_assignable_v<FrameData>);

TEST(FrameDataTest, FindsAValueByTheTypeItWasSetAs) {
    FrameData data;
    EXPECT_EQ(data.get<Exposure>(), nullptr);
    data.set(Exposure{2.5f});
    ASSERT_NE(data.get<Exposure>(), nullptr);
    EXPECT_EQ(data.get<Exposure>()->ev, 2.5f);
    data.set(Exposure{-1.0f});
    EXPECT_EQ(data.get<Exposure>()->ev, -1.0f);
}

}  // namespace
}  // namespace skygraph::test
