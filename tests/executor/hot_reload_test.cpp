// Hot reload: a broken graph and a broken shader each leave the last good version running, and
// edits a failure left unapplied take effect with the next change.
#include "executor_test_util.hpp"

#include <skygraph/hot_reload.hpp>
#include <skygraph/shader_compiler.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>

#include <unistd.h>

namespace skygraph::test {
namespace {

std::string graphWithColor(const std::string& color) {
    return R"({ "version": 1, "name": "reload", "resources": {
      "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",
                     "external": true, "final": "Present" } },
      "passes": [ { "name": "p", "type": "Generic", "uses": { "swapchain": "Write@ColorAttachment" },
                    "params": { "color": )" + color + " } } ] }";
}

void write(const std::filesystem::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary | std::ios::trunc) << text;
}

std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p);
    return std::string((std::istreambuf_iterator<char>(in)), {});
}

/// A renderer of graphWithColor("[1, 0, 0, 1]") loaded from a graph file, with the shared
/// generic_common.glsl copied into a shader folder of its own, and a HotReloader watching
/// both (the folder because it is the renderer's). The folder is removed at the end.
struct WatchedRenderer {
    explicit WatchedRenderer(const std::string& name)
        : dir(std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()))),
          shader(dir / "shaders" / "generic_common.glsl"), graphFile(dir / "g.json") {
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir / "shaders");
        std::filesystem::copy_file(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "shaders" / "generic_common.glsl",
                                   shader);
        write(graphFile, graphWithColor("[1, 0, 0, 1]"));
        GraphDesc graph = loadGraphFile(graphFile, PassRegistry::withBuiltins());
        const CompileOptions co = headless(graph);
        RendererOptions ro = genericOptions();
        ro.shaderDir = dir / "shaders";
        renderer = std::make_unique<Renderer>(sharedDevice(), CompiledGraph(std::move(graph), co), ro);
        reloader = std::make_unique<HotReloader>(*renderer, graphFile);  // watches the renderer's shaderDir
        EXPECT_EQ(renderer->shaderDir(), dir / "shaders");
    }
    ~WatchedRenderer() {
        reloader.reset();
        renderer->waitIdle();
        renderer.reset();
        std::error_code ignored;
        std::filesystem::remove_all(dir, ignored);
    }
    WatchedRenderer(const WatchedRenderer&) = delete;
    WatchedRenderer& operator=(const WatchedRenderer&) = delete;

    std::filesystem::path dir, shader, graphFile;
    std::unique_ptr<Renderer> renderer;
    std::unique_ptr<HotReloader> reloader;
};

TEST_F(ExecutorTest, HotReloadKeepsLastGoodGraphAndShaders) {
    WatchedRenderer watched("skygraph_reload");
    Renderer& r = *watched.renderer;
    HotReloader& reloader = *watched.reloader;
    const auto& shader = watched.shader;
    const auto& graphFile = watched.graphFile;
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 0, 0, 1.0, 0.0, 0.0, 1.0);
    EXPECT_EQ(reloader.poll(), HotReloader::Result::Unchanged);

    // A broken graph: the old plan keeps rendering.
    write(graphFile, "{ \"version\": 1, \"passes\": [ ");
    EXPECT_EQ(reloader.poll(), HotReloader::Result::Failed);
    EXPECT_NE(reloader.lastError().find("g.json"), std::string::npos) << reloader.lastError();
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 0, 0, 1.0, 0.0, 0.0, 1.0);

    // Fixed: the new plan runs.
    write(graphFile, graphWithColor("[0, 1, 0, 1]"));
    EXPECT_EQ(reloader.poll(), HotReloader::Result::Reloaded);
    EXPECT_EQ(r.plan().outputWidth(), 16u) << "the reloaded graph compiles with the renderer's options";
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 0, 0, 0.0, 1.0, 0.0, 1.0);

    // A broken shader: the old pipelines keep rendering.
    const std::string good = slurp(shader);
    write(shader, good + "\nthis is not glsl;\n");
    EXPECT_EQ(reloader.poll(), HotReloader::Result::Failed);
    EXPECT_NE(reloader.lastError().find("does not compile"), std::string::npos) << reloader.lastError();
    r.renderFrame();
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 0, 0, 0.0, 1.0, 0.0, 1.0);

    // A working edit of the shader is picked up.
    std::string edited = good;
    const std::string from = "vec4 genericOutput(vec4 acc) { return acc; }";
    ASSERT_NE(edited.find(from), std::string::npos);
    edited.replace(edited.find(from), from.size(), "vec4 genericOutput(vec4 acc) { return acc.bgra; }");
    write(shader, edited);
    EXPECT_EQ(reloader.poll(), HotReloader::Result::Reloaded);
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 0, 0, 0.0, 1.0, 0.0, 1.0);  // green stays green under bgra
    write(graphFile, graphWithColor("[1, 0, 0.5, 1]"));
    EXPECT_EQ(reloader.poll(), HotReloader::Result::Reloaded);
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 7, 7, 0.5, 0.0, 1.0, 1.0);  // red and blue swapped

    // The graph and an included shader edited between two polls: both edits take effect.
    write(shader, good);
    write(graphFile, graphWithColor("[1, 0, 0.25, 1]"));
    EXPECT_EQ(reloader.poll(), HotReloader::Result::Reloaded);
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 7, 7, 1.0, 0.0, 0.25, 1.0);  // the shader edit is not lost to the graph's

    // The graph and a shader edited together, the shader broken: neither takes effect...
    write(shader, good + "\nthis is not glsl;\n");
    write(graphFile, graphWithColor("[0, 0, 1, 1]"));
    EXPECT_EQ(reloader.poll(), HotReloader::Result::Failed);
    EXPECT_NE(reloader.lastError().find("does not compile"), std::string::npos) << reloader.lastError();
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 7, 7, 1.0, 0.0, 0.25, 1.0);  // the old graph with the old pipelines
    // ...and both do once the shader is fixed, though the graph was not saved again.
    write(shader, edited);
    EXPECT_EQ(reloader.poll(), HotReloader::Result::Reloaded);
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 7, 7, 1.0, 0.0, 0.0, 1.0);  // the new graph's blue, swapped to red

    // A shader edited while the graph is broken takes effect with the fixed graph, not from a
    // cache that does not see an edited include.
    write(graphFile, "{ \"version\": 1, \"passes\": [ ");
    write(shader, good);
    EXPECT_EQ(reloader.poll(), HotReloader::Result::Failed);
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 7, 7, 1.0, 0.0, 0.0, 1.0);
    write(graphFile, graphWithColor("[0, 0, 1, 1]"));
    EXPECT_EQ(reloader.poll(), HotReloader::Result::Reloaded);
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 7, 7, 0.0, 0.0, 1.0, 1.0);
}

// A watched path that is not there is refused, naming it: a typo would otherwise never reload.
TEST_F(ExecutorTest, HotReloadRefusesAPathThatDoesNotExist) {
    WatchedRenderer watched("hot_reload_missing");
    const std::pair<std::filesystem::path, std::filesystem::path> cases[] = {
        {watched.dir / "no_such_graph.json", {}}, {watched.graphFile, watched.dir / "no_such_shaders"}};
    for (const auto& [graph, shaders] : cases) {
        try {
            HotReloader reloader(*watched.renderer, graph, shaders);
            ADD_FAILURE() << "watched " << graph << " and " << shaders;
        } catch (const ExecutorError& e) {
            const std::string missing = (shaders.empty() ? graph : shaders).string();
            EXPECT_NE(std::string(e.what()).find("'" + missing + "' does not exist"), std::string::npos) << e.what();
        }
    }
}

// A save in place truncates the file and then writes it: polled in between, the empty graph or
// shader is not a change, so the save is one reload rather than a failed one and then another.
TEST_F(ExecutorTest, HotReloadSeesASaveInPlaceAsOneChange) {
    WatchedRenderer watched("skygraph_reload_in_place");
    Renderer& r = *watched.renderer;
    HotReloader& reloader = *watched.reloader;
    const auto& shader = watched.shader;
    const auto& graphFile = watched.graphFile;
    const std::string good = slurp(shader);

    for (const auto& file : {graphFile, shader}) {
        SCOPED_TRACE(file.filename().string());
        const std::string text = slurp(file);
        std::ofstream saving(file, std::ios::binary | std::ios::trunc);
        saving.flush();
        EXPECT_EQ(reloader.poll(), HotReloader::Result::Unchanged) << "the truncated file was taken for the save";
        EXPECT_EQ(reloader.lastError(), "");
        saving << (file == graphFile ? graphWithColor("[0, 1, 0, 1]") : text + "\n// saved again\n");
        saving.close();
        EXPECT_EQ(reloader.poll(), HotReloader::Result::Reloaded) << reloader.lastError();
        EXPECT_EQ(reloader.poll(), HotReloader::Result::Unchanged);
    }
    // Another file edited while one is half saved: nothing is reloaded until both are written,
    // so no reload reads the empty file with the edited one.
    {
        std::ofstream saving(shader, std::ios::binary | std::ios::trunc);
        saving.flush();
        write(graphFile, graphWithColor("[0, 0, 1, 1]"));
        EXPECT_EQ(reloader.poll(), HotReloader::Result::Unchanged);
        saving << good;
    }
    EXPECT_EQ(reloader.poll(), HotReloader::Result::Reloaded) << reloader.lastError();
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 0, 0, 0.0, 0.0, 1.0, 1.0);
}

// A pass library may declare a type under a built-in's name; its factory records it, and the
// reloader without a registry of its own parses reloaded graphs against that declaration, not
// the built-in one, which would refuse them.
TEST_F(ExecutorTest, HotReloadParsesWithTheLibrarysDeclarationOfABuiltInName) {
    PassLibrary library = PassLibrary::genericOnly();
    PassTypeInfo tonemapping;
    tonemapping.name = "TonemappingPass";
    tonemapping.slots.push_back(SlotDecl{"target", Stage::ColorAttachment, {Access::Write}});
    library.add(tonemapping, *PassLibrary::genericOnly().factory("Generic"));
    const auto graphText = [](const std::string& color) {
        return R"({ "version": 1, "name": "own", "resources": {
          "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",
                         "external": true, "final": "Present" } },
          "passes": [ { "name": "tone", "type": "TonemappingPass", "uses": { "swapchain": "Write@ColorAttachment" },
                        "params": { "color": )" + color + " } } ] }";
    };
    const auto dir = std::filesystem::temp_directory_path() / ("skygraph_reload_own_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir / "shaders");  // watched, and empty
    const auto graphFile = dir / "g.json";
    write(graphFile, graphText("[1, 0, 0, 1]"));
    {
        GraphDesc graph = loadGraphFile(graphFile, library.registry());
        const CompileOptions co = headless(graph);
        RendererOptions ro = genericOptions();
        ro.passes = &library;
        Renderer r(sharedDevice(), CompiledGraph(std::move(graph), co), ro);
        HotReloader reloader(r, graphFile, dir / "shaders");
        write(graphFile, graphText("[0, 1, 0, 1]"));
        EXPECT_EQ(reloader.poll(), HotReloader::Result::Reloaded) << reloader.lastError();
        r.renderFrame();
        EXPECT_PIXEL_NEAR(r.readback(), 0, 0, 0.0, 1.0, 0.0, 1.0);
        r.waitIdle();
    }
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace skygraph::test

namespace skygraph::test {
namespace {

TEST(ShaderCompilerTest, CompilesShippedPassShadersWithIncludes) {
    ShaderCompiler sc({});
    const auto dir = ShaderCompiler::defaultIncludeDir();
    int compiled = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir / "passes")) {
        if (!e.is_regular_file()) continue;  // passes/ibl/ and the like hold more shaders
        const auto ext = e.path().extension().string();
        const VkShaderStageFlagBits stage = ext == ".vert"   ? VK_SHADER_STAGE_VERTEX_BIT
                                            : ext == ".frag" ? VK_SHADER_STAGE_FRAGMENT_BIT
                                                             : VK_SHADER_STAGE_COMPUTE_BIT;
        EXPECT_FALSE(sc.compileFile(stage, std::filesystem::relative(e.path(), dir)).empty()) << e.path();
        ++compiled;
    }
    EXPECT_GT(compiled, 0);
    EXPECT_THROW((void)sc.compileFile(VK_SHADER_STAGE_VERTEX_BIT, "passes/missing.vert"), ExecutorError);
    EXPECT_THROW((void)sc.compile(VK_SHADER_STAGE_VERTEX_BIT, "#version 450\nvoid main() { x; }\n", "bad"),
                 ExecutorError);
    const uint32_t before = sc.compilations();
    (void)sc.compile(VK_SHADER_STAGE_COMPUTE_BIT, "#version 450\nlayout(local_size_x=1) in;\nvoid main(){}\n", "a");
    (void)sc.compile(VK_SHADER_STAGE_COMPUTE_BIT, "#version 450\nlayout(local_size_x=1) in;\nvoid main(){}\n", "a");
    EXPECT_EQ(sc.compilations(), before + 1) << "the second compile comes from the cache";
}

}  // namespace
}  // namespace skygraph::test
