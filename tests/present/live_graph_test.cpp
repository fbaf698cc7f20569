// `skygraph view`'s live graph (tools/app/live_graph.cpp) presenting to a window under
// validation: environment changes and sequences baked beside the frames, saved graphs, scenes
// and shaders, and rebuilds for a checkbox, each silent.
#include "present_fixture.hpp"

#include "app/live_graph.hpp"
#include "app/procedural_environment.hpp"

#include <skygraph/image_data.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/swapchain.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

namespace skygraph::test {
namespace {

/// `skygraph view`'s LiveGraph of graphs/raster.json with `scene`, presenting to a 96x64
/// window, two frames in flight, screenshots allowed; frame() polls and presents one frame.
struct LiveWindow {
    LiveWindow(Device& device, const std::string& scene) : LiveWindow(device, options(scene)) {}
    LiveWindow(Device& device, app::RenderOptions o)
        : live(device, std::move(o), 96, 64, false),
          swapchain(Swapchain::create(device, live.renderer().compiled(), swapchainOptions())) {
        live.presentTo(*swapchain);
    }
    static SwapchainOptions swapchainOptions() {
        SwapchainOptions o{96, 64, PresentMode::Fifo};
        o.extraUsage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT;  // screenshots read the presented image back, as in the view
        return o;
    }
    static app::RenderOptions options(const std::string& scene) {
        static const PassLibrary library = PassLibrary::withBuiltins();
        const std::filesystem::path root = SKYGRAPH_SOURCE_DIR;
        app::RenderOptions o;
        o.graph = root / "graphs/raster.json";
        o.scene = root / scene;
        o.framesInFlight = 2;
        o.passes = &library;
        return o;
    }
    void frame() {
        glfwPollEvents();
        live.poll();
        EXPECT_EQ(live.renderFrame(*swapchain), PresentStatus::Presented);
    }
    /// The next presented frame, read back as the view's screenshots are.
    ImageData screen() {
        EXPECT_TRUE(live.beginScreenshot()) << live.error();
        frame();
        live.renderer().waitIdle();
        ImageData image = live.renderer().readback();
        (void)live.finishScreenshot({});  // writes nothing (false), compiles the plan back
        EXPECT_EQ(live.error(), "");
        return image;
    }
    /// Plays the sequence at `seconds` until `done(stats)` holds, presenting a frame between
    /// each, for 300 frames at most.
    template <class Done>
    void playUntil(double seconds, Done done) {
        for (int i = 0; i < 300 && !done(live.sequence()->stats()); ++i) {
            frame();
            live.playSequence(seconds);
        }
        EXPECT_TRUE(done(live.sequence()->stats())) << "at " << seconds << " s";
    }
    /// Presents frames until the re-bake under way is swapped in, 100 at most; how many.
    int framesUntilRebaked() {
        int frames = 0;
        for (; live.rebaking() && frames < 100; ++frames) frame();
        return frames;
    }
    app::LiveGraph live;
    std::unique_ptr<Swapchain> swapchain;
};

/// The largest difference between two images' channels.
double largestDifference(const ImageData& a, const ImageData& b) {
    double most = 0.0;
    for (size_t i = 0; i < a.rgba.size() && i < b.rgba.size(); ++i)
        most = std::max(most, double(std::abs(a.rgba[i] - b.rgba[i])));
    return most;
}

/// A folder `name` of the temporary folder with a scene.json whose environment is a sequence
/// of four frames at 10 fps, sky_00.exr to sky_03.exr, in which the sun circles the sky (frame
/// 0 ahead, 1 to the right); the folder.
std::filesystem::path skySequenceScene(const std::string& name) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    app::writeProceduralSkySequence((dir / "sky_%02d.exr").string(), 4, 64);
    std::ofstream(dir / "scene.json") << R"({"environment": {"sequence": "sky_%02d.exr", "fps": 10}})";
    return dir;
}

/// The mean of an image's colour channels.
double meanColour(const ImageData& image) {
    double sum = 0.0;
    for (size_t i = 0; i < image.rgba.size(); ++i) sum += i % 4 == 3 ? 0.0 : image.rgba[i];
    return sum / (double(image.rgba.size()) * 0.75);
}

/// An environment file in the temporary folder, every texel `texel`; its path.
std::filesystem::path writeUniformSky(const std::string& name, uint32_t width, uint32_t height,
                                      std::array<float, 4> texel) {
    ImageData sky;
    sky.width = width;
    sky.height = height;
    sky.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    for (uint32_t i = 0; i < width * height; ++i) sky.rgba.insert(sky.rgba.end(), texel.begin(), texel.end());
    const std::filesystem::path file = std::filesystem::temp_directory_path() / name;
    writeHdr(file, sky);
    return file;
}

/// A copy of the shaders that renderers read (SKYGRAPH_SHADER_DIR) while it lives, for a test
/// to edit; the real ones again however the test ends, as later tests must read them.
struct ShaderDirForTheTest {
    ShaderDirForTheTest() : dir(std::filesystem::temp_directory_path() / ("skygraph-shaders-" + std::to_string(::getpid()))) {
        std::filesystem::remove_all(dir);
        std::filesystem::copy(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "shaders", dir,
                              std::filesystem::copy_options::recursive);
        if (const char* before = std::getenv("SKYGRAPH_SHADER_DIR")) previous = before;
        setenv("SKYGRAPH_SHADER_DIR", dir.c_str(), 1);
    }
    ~ShaderDirForTheTest() {
        if (previous) setenv("SKYGRAPH_SHADER_DIR", previous->c_str(), 1);
        else unsetenv("SKYGRAPH_SHADER_DIR");
        std::error_code ignored;
        std::filesystem::remove_all(dir, ignored);
    }
    ShaderDirForTheTest(const ShaderDirForTheTest&) = delete;
    ShaderDirForTheTest& operator=(const ShaderDirForTheTest&) = delete;
    std::filesystem::path dir;
    std::optional<std::string> previous;
};

/// The text of `file`.
std::string readText(const std::filesystem::path& file) {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// `skygraph view`'s environment change (LiveGraph::setEnvironmentFile): a file of the running
// one's size is re-baked on the compute queue beside the presented frames and swapped in
// between two of them, with no rebuild and no validation message.
TEST_F(Present, AnEnvironmentChangeIsRebakedBesideTheFrames) {
    LiveWindow w(*device_, "scenes/studio.json");
    app::LiveGraph& live = w.live;
    for (int i = 0; i < 3; ++i) w.frame();
    const Renderer* running = &live.renderer();
    const uint32_t reloads = live.reloads();
    const std::filesystem::path file =
        loadSceneFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "scenes/studio.json").environment->file;
    ASSERT_TRUE(live.setEnvironmentFile(file)) << live.error();
    EXPECT_TRUE(live.rebaking());
    const int frames = w.framesUntilRebaked();
    EXPECT_FALSE(live.rebaking()) << "not swapped in after " << frames << " frames";
    EXPECT_GE(frames, 1);
    EXPECT_EQ(&live.renderer(), running) << "the change rebuilt the renderer";
    EXPECT_EQ(live.reloads(), reloads + 1);
    for (int i = 0; i < 3; ++i) w.frame();
    live.renderer().waitIdle();
    expectSilent();
}

// A file of another size than the running equirect is resampled to it and re-baked beside
// the frames too: no rebuild, no hitch, no validation message.
TEST_F(Present, AnEnvironmentFileOfAnotherSizeIsResampledAndRebakedBesideTheFrames) {
    LiveWindow w(*device_, "scenes/studio.json");
    app::LiveGraph& live = w.live;
    for (int i = 0; i < 3; ++i) w.frame();
    const Renderer* running = &live.renderer();
    const uint32_t reloads = live.reloads();
    const auto equirect = live.renderer().graph().findResource("equirect")->extent.resolve(96, 64);
    // Neither the running size nor a multiple of it.
    const std::filesystem::path file =
        writeUniformSky("skygraph-other-size.hdr", equirect[0] / 2 + 3, equirect[1] / 2 + 1, {0.5f, 1.0f, 2.0f, 1.0f});
    ASSERT_TRUE(live.setEnvironmentFile(file)) << live.error();
    EXPECT_TRUE(live.rebaking()) << "re-baked beside the frames, not rebuilt";
    const int frames = w.framesUntilRebaked();
    EXPECT_FALSE(live.rebaking()) << "not swapped in after " << frames << " frames";
    EXPECT_EQ(&live.renderer(), running) << "the change rebuilt the renderer";
    EXPECT_EQ(live.reloads(), reloads + 1);
    for (int i = 0; i < 3; ++i) w.frame();
    live.renderer().waitIdle();
    std::filesystem::remove(file);
    expectSilent();
}

// The procedural sky has a skybox of its own (the scene's feature environment_file): a file
// loaded in its place rebuilds the plan, so that the sky drawn is the file's, as the lighting is.
TEST_F(Present, AnEnvironmentFileInPlaceOfTheProceduralSkyRebuildsWithItsSkybox) {
    LiveWindow w(*device_, "scenes/default.json");
    app::LiveGraph& live = w.live;
    for (int i = 0; i < 3; ++i) w.frame();
    ASSERT_TRUE(live.scene()->environment->procedural);
    ASSERT_FALSE(live.feature("environment_file"));
    const std::filesystem::path file =
        loadSceneFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "scenes/studio.json").environment->file;
    ASSERT_TRUE(live.setEnvironmentFile(file)) << live.error();
    EXPECT_FALSE(live.rebaking()) << "re-baked beside the frames under the procedural sky's skybox";
    EXPECT_TRUE(live.feature("environment_file"));
    EXPECT_FALSE(live.scene()->environment->procedural);
    for (int i = 0; i < 3; ++i) w.frame();
    live.renderer().waitIdle();
    expectSilent();
}

// A rebuild while an environment file is still decoding (a checkbox clicked meanwhile) builds
// with that file rather than dropping it.
TEST_F(Present, ARebuildWhileAnEnvironmentFileDecodesBuildsWithTheFile) {
    LiveWindow w(*device_, "scenes/studio.json");
    app::LiveGraph& live = w.live;
    for (int i = 0; i < 3; ++i) w.frame();
    const std::filesystem::path file = writeUniformSky(
        "skygraph-decoding-" + std::to_string(::getpid()) + ".hdr", 64, 32, {0.75f, 0.75f, 0.75f, 0.75f});
    ASSERT_TRUE(live.setEnvironmentFile(file)) << live.error();
    ASSERT_TRUE(live.rebaking()) << "decoding beside the frames";
    ASSERT_TRUE(live.setFeature("skybox", false)) << live.error();
    EXPECT_FALSE(live.rebaking());
    EXPECT_EQ(live.scene()->environment->file, file) << "the rebuild dropped the file";
    EXPECT_TRUE(live.error().empty()) << live.error();
    for (int i = 0; i < 3; ++i) w.frame();
    live.renderer().waitIdle();
    std::filesystem::remove(file);
    expectSilent();
}

// The file is decoded on a thread of its own: setEnvironmentFile returns at once, and a file
// that cannot be read is reported once its decoding fails, naming it; the sky stays as it was.
TEST_F(Present, AnUnreadableEnvironmentFileIsReportedAndTheSkyStays) {
    LiveWindow w(*device_, "scenes/studio.json");
    app::LiveGraph& live = w.live;
    for (int i = 0; i < 3; ++i) w.frame();
    const Renderer* running = &live.renderer();
    const uint32_t reloads = live.reloads();
    const std::filesystem::path file = std::filesystem::temp_directory_path() / "skygraph-unreadable.exr";
    std::ofstream(file) << "not an EXR file";
    ASSERT_TRUE(live.setEnvironmentFile(file)) << live.error();
    EXPECT_TRUE(live.rebaking()) << "decoding beside the frames";
    const int frames = w.framesUntilRebaked();
    EXPECT_FALSE(live.rebaking()) << "still loading after " << frames << " frames";
    EXPECT_NE(live.error().find(file.string()), std::string::npos) << live.error();
    EXPECT_EQ(&live.renderer(), running) << "nothing was rebuilt";
    EXPECT_EQ(live.reloads(), reloads);
    for (int i = 0; i < 3; ++i) w.frame();
    live.renderer().waitIdle();
    std::filesystem::remove(file);
    expectSilent();
}

/// graphs/raster.json and graphs/ibl.json copied into a new folder (`prefix` and the process
/// id) of the temporary folder, for a test that saves them; the folder.
std::filesystem::path copyOfTheGraphs(const std::string& prefix) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    for (const char* graph : {"raster.json", "ibl.json"})
        std::filesystem::copy_file(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / graph, dir / graph);
    return dir;
}

/// A LiveWindow's options with the copy's raster.json as the graph.
app::RenderOptions optionsForTheCopy(const std::filesystem::path& dir, const std::string& scene) {
    app::RenderOptions o = LiveWindow::options(scene);
    o.graph = dir / "raster.json";
    return o;
}

// A saved graph that does not load keeps its message on screen while an environment file is
// loaded and re-baked beside the frames: the save is still not built.
TEST_F(Present, ASaveThatDidNotBuildKeepsItsMessageThroughAnEnvironmentChange) {
    const std::filesystem::path root = SKYGRAPH_SOURCE_DIR;
    const std::filesystem::path dir = copyOfTheGraphs("skygraph-save-");
    LiveWindow w(*device_, optionsForTheCopy(dir, "scenes/studio.json"));
    app::LiveGraph& live = w.live;
    for (int i = 0; i < 3; ++i) w.frame();
    std::ofstream(dir / "raster.json", std::ios::trunc) << "{ \"version\": 1, \"passes\": [ ";
    w.frame();
    ASSERT_NE(live.error().find("raster.json"), std::string::npos) << live.error();
    const std::filesystem::path file = loadSceneFile(root / "scenes/studio.json").environment->file;
    ASSERT_TRUE(live.setEnvironmentFile(file)) << live.error();
    const int frames = w.framesUntilRebaked();
    EXPECT_FALSE(live.rebaking()) << "not swapped in after " << frames << " frames";
    EXPECT_NE(live.error().find("raster.json"), std::string::npos) << "the save's message went: " << live.error();
    live.renderer().waitIdle();
    std::filesystem::remove_all(dir);
    expectSilent();
}

// A save that presents a format the window's surface lacks is refused as the new renderer is
// made: its message shows and the last good frame goes on presenting, as for any broken save.
TEST_F(Present, ASavePresentingAFormatTheSurfaceLacksKeepsTheLastGoodFrame) {
    const std::filesystem::path dir = copyOfTheGraphs("skygraph-format-save-");
    LiveWindow w(*device_, optionsForTheCopy(dir, "scenes/studio.json"));
    for (int i = 0; i < 2; ++i) w.frame();
    std::string graph = readText(dir / "raster.json");
    const std::string srgb = R"("swapchain": { "type": "image2d", "format": "B8G8R8A8_SRGB")";
    ASSERT_NE(graph.find(srgb), std::string::npos);
    graph.replace(graph.find(srgb), srgb.size(),
                  R"("swapchain": { "type": "image2d", "format": "R16G16B16A16_SFLOAT")");
    std::ofstream(dir / "raster.json", std::ios::trunc) << graph;
    for (int i = 0; i < 3; ++i) w.frame();
    EXPECT_NE(w.live.error().find("the surface cannot present R16G16B16A16_SFLOAT"), std::string::npos)
        << w.live.error();
    EXPECT_EQ(w.swapchain->format(), VK_FORMAT_B8G8R8A8_SRGB);
    w.live.renderer().waitIdle();
    std::filesystem::remove_all(dir);
    expectSilent();
}

// graphs/ibl.json beside the graph is part of the frame's graphs: a save of it builds and bakes
// again, and one that does not load is reported while the frames go on.
TEST_F(Present, ASavedEnvironmentGraphBakesTheEnvironmentAgain) {
    const std::filesystem::path dir = copyOfTheGraphs("skygraph-ibl-save-");
    std::string ibl;
    {
        std::ifstream in(dir / "ibl.json");
        ibl.assign(std::istreambuf_iterator<char>(in), {});
    }
    LiveWindow w(*device_, optionsForTheCopy(dir, "scenes/studio.json"));
    app::LiveGraph& live = w.live;
    const ImageData lit = w.screen();
    const Renderer* running = &live.renderer();
    const uint32_t reloads = live.reloads();

    std::ofstream(dir / "ibl.json", std::ios::trunc) << "{ \"version\": 1, \"passes\": [ ";
    w.frame();
    EXPECT_NE(live.error().find((dir / "ibl.json").string()), std::string::npos) << live.error();
    EXPECT_EQ(&live.renderer(), running) << "a graph that does not load replaced the running frames";

    // The irradiance integrated from 4 samples instead of 1024: the spheres' diffuse light changes.
    const std::string samples = "\"IrradiancePass\",\n      \"uses\": {\n        \"environment\": \"Read@Compute\",\n"
                                "        \"irradiance\": \"Write@Compute\"\n      },\n      \"params\": {\n        \"samples\": 1024";
    ASSERT_NE(ibl.find(samples), std::string::npos);
    ibl.replace(ibl.find(samples) + samples.size() - 4, 4, "4");
    std::ofstream(dir / "ibl.json", std::ios::trunc) << ibl;
    w.frame();
    EXPECT_EQ(live.error(), "");
    EXPECT_NE(&live.renderer(), running) << "the saved environment graph was not built";
    EXPECT_EQ(live.reloads(), reloads + 1);
    EXPECT_NE(w.screen().rgba, lit.rgba) << "the environment was not baked from the saved graph";
    live.renderer().waitIdle();
    std::filesystem::remove_all(dir);
    expectSilent();
}

// An environment graph saved beside the graph after the view started is built as a save of it.
TEST_F(Present, AnEnvironmentGraphSavedBesideTheGraphLaterIsBuilt) {
    const std::filesystem::path dir = copyOfTheGraphs("skygraph-ibl-later-");
    std::filesystem::rename(dir / "ibl.json", dir / "ibl.json.away");
    LiveWindow w(*device_, optionsForTheCopy(dir, "scenes/studio.json"));
    app::LiveGraph& live = w.live;
    const ImageData unlit = w.screen();
    const Renderer* running = &live.renderer();
    const uint32_t reloads = live.reloads();
    std::filesystem::rename(dir / "ibl.json.away", dir / "ibl.json");
    w.frame();
    EXPECT_EQ(live.error(), "");
    EXPECT_NE(&live.renderer(), running) << "the environment graph saved later was not built";
    EXPECT_EQ(live.reloads(), reloads + 1);
    EXPECT_NE(w.screen().rgba, unlit.rgba) << "the environment was not baked";
    live.renderer().waitIdle();
    std::filesystem::remove_all(dir);
    expectSilent();
}

// The environment is baked once, by a renderer of its own: an edit to one of its shaders (the
// watcher sees every edit in the shader folder) bakes it again in a rebuild. A broken one is
// reported and the frames go on; an edit to a frame shader only reloads the frame's pipelines.
TEST_F(Present, AnEditedEnvironmentShaderBakesTheEnvironmentAgain) {
    namespace fs = std::filesystem;
    {
        const ShaderDirForTheTest shaderDir;
        const fs::path& shaders = shaderDir.dir;
        LiveWindow w(*device_, "scenes/studio.json");
        app::LiveGraph& live = w.live;
        const ImageData lit = w.screen();
        const Renderer* running = &live.renderer();
        uint32_t reloads = live.reloads();

        std::ofstream(shaders / "passes/tonemap.frag", std::ios::app) << "\n// an edit to a frame shader\n";
        w.frame();
        EXPECT_EQ(&live.renderer(), running) << "a frame shader's edit baked the environment again";
        EXPECT_EQ(live.reloads(), reloads + 1);
        const ImageData same = w.screen();
        EXPECT_EQ(same.rgba, lit.rgba) << "a comment in a frame shader changed the frame";

        const fs::path cube = shaders / "passes/ibl/equirect_to_cube.comp";
        std::string source;
        {
            std::ifstream in(cube);
            source.assign(std::istreambuf_iterator<char>(in), {});
        }
        std::ofstream(cube, std::ios::app) << "\nthis is not GLSL\n";
        w.frame();
        EXPECT_EQ(&live.renderer(), running) << "a bake that failed replaced the running frames";
        EXPECT_NE(live.error().find("equirect_to_cube.comp"), std::string::npos) << live.error();
        // A checkbox meanwhile rebuilds from the running bake's shaders, as from the frame's.
        const bool compute = live.feature("compute_tonemap");
        ASSERT_TRUE(live.setFeature("compute_tonemap", !compute)) << live.error();
        ASSERT_TRUE(live.setFeature("compute_tonemap", compute)) << live.error();
        EXPECT_NE(live.error().find("equirect_to_cube.comp"), std::string::npos) << "the broken shader's message went";
        running = &live.renderer();
        reloads = live.reloads();
        std::ofstream(cube, std::ios::trunc) << source;  // undone: the bake that runs is on disk again
        w.frame();
        EXPECT_EQ(&live.renderer(), running) << "undoing the edit baked the environment again";
        EXPECT_EQ(live.error(), "") << "the undone edit's message stayed";

        // The environment cube black: the spheres lose their light; the sky, drawn from the
        // equirect (the scene's "sampling"), stays.
        const std::string sample = "vec4(sum / float(n * n), 1.0)";
        ASSERT_NE(source.find(sample), std::string::npos);
        source.replace(source.find(sample), sample.size(), "vec4(0.0, 0.0, 0.0, 1.0)");
        std::ofstream(cube, std::ios::trunc) << source;
        w.frame();
        EXPECT_NE(&live.renderer(), running) << "the edited environment shader was not baked";
        EXPECT_EQ(live.error(), "");
        EXPECT_EQ(live.reloads(), reloads + 2) << "the undo's reload and the bake";
        const ImageData dark = w.screen();
        EXPECT_LT(meanColour(dark), 0.9 * meanColour(lit)) << "the spheres are still lit by the old bake";
        live.renderer().waitIdle();
    }
    expectSilent();
}

// A checkbox that drops every product of the environment's bake (geometry off, with a sky
// drawn from the equirect: nothing samples the bake) keeps the bake's shader sources: when it
// is turned back on, the bake is built from them, as any checkbox's rebuild is, so it works
// while a bake shader is broken on disk. An edit made while no bake ran is then baked, or
// reported, as one made while it ran would have been.
TEST_F(Present, ACheckboxThatDropsTheWholeBakeKeepsItsShaderSources) {
    namespace fs = std::filesystem;
    {
        const ShaderDirForTheTest shaderDir;
        LiveWindow w(*device_, "scenes/studio.json");
        app::LiveGraph& live = w.live;
        const ImageData lit = w.screen();
        const fs::path cube = shaderDir.dir / "passes/ibl/equirect_to_cube.comp";
        const std::string source = readText(cube);

        ASSERT_TRUE(live.setFeature("geometry", false)) << live.error();
        std::ofstream(cube, std::ios::app) << "\nthis is not GLSL\n";
        w.frame();  // the watcher sees the edit; no bake runs to read it
        ASSERT_TRUE(live.setFeature("geometry", true)) << live.error();
        EXPECT_EQ(live.error(), "") << "the bake came back from its sources, not from the broken file";
        w.frame();
        EXPECT_NE(live.error().find("equirect_to_cube.comp"), std::string::npos)
            << "the edit made while no bake ran is not reported once one runs: " << live.error();
        std::ofstream(cube, std::ios::trunc) << source;
        w.frame();
        EXPECT_EQ(live.error(), "") << "the undone edit's message stayed";
        EXPECT_EQ(w.screen().rgba, lit.rgba) << "the bake that came back is not the one that went";

        // A good edit made while no bake runs (the environment cube black) is baked once one
        // runs again: the spheres lose their light.
        ASSERT_TRUE(live.setFeature("geometry", false)) << live.error();
        std::string black = source;
        const std::string sample = "vec4(sum / float(n * n), 1.0)";
        ASSERT_NE(black.find(sample), std::string::npos);
        black.replace(black.find(sample), sample.size(), "vec4(0.0, 0.0, 0.0, 1.0)");
        std::ofstream(cube, std::ios::trunc) << black;
        w.frame();
        ASSERT_TRUE(live.setFeature("geometry", true)) << live.error();
        w.frame();
        EXPECT_EQ(live.error(), "");
        EXPECT_LT(meanColour(w.screen()), 0.9 * meanColour(lit)) << "the spheres are still lit by the old bake";
        live.renderer().waitIdle();
    }
    expectSilent();
}

// Moving the procedural sky's sun re-bakes its lighting beside the frames as a file change
// does; a second move while the first bake runs is baked after it, and nothing rebuilds.
TEST_F(Present, MovingTheSunRebakesTheSkysLightingBesideTheFrames) {
    LiveWindow w(*device_, "scenes/default.json");
    app::LiveGraph& live = w.live;
    for (int i = 0; i < 3; ++i) w.frame();
    const Renderer* running = &live.renderer();
    const uint32_t reloads = live.reloads();
    ASSERT_TRUE(live.setSunDirection({0.0, 1.0, 0.0})) << live.error();
    EXPECT_TRUE(live.rebaking());
    ASSERT_TRUE(live.setSunDirection({0.6, 0.8, 0.0})) << "queued behind the running bake";
    EXPECT_EQ(live.scene()->environment->sunDirection, (Vec3{0.6, 0.8, 0.0})) << "the skybox's sun moves at once";
    int frames = 0;
    while ((live.rebaking() || live.reloads() < reloads + 2) && frames < 200) {
        w.frame();
        ++frames;
    }
    EXPECT_FALSE(live.rebaking()) << "not swapped in after " << frames << " frames";
    EXPECT_EQ(live.reloads(), reloads + 2) << "two bakes: the first move, then the latest";
    EXPECT_EQ(&live.renderer(), running) << "moving the sun rebuilt the renderer";
    for (int i = 0; i < 3; ++i) w.frame();
    live.renderer().waitIdle();
    expectSilent();
}

// An environment sequence plays beside the frames: each frame due is decoded on the stream's
// thread, baked beside the frames and swapped in, and the sky fades to it from the frame
// before over one frame of the sequence; over an unreadable frame the sky holds the last one
// (never black), and playback loops. Nothing rebuilds, and validation stays silent.
TEST_F(Present, AnEnvironmentSequencePlaysBesideTheFramesAndHoldsOverAnUnreadableFrame) {
    const std::filesystem::path dir = skySequenceScene("skygraph-present-sequence");
    std::ofstream(sequenceFrameFile((dir / "sky_%02d.exr").string(), 2), std::ios::binary) << "not an EXR";
    LiveWindow w(*device_, (dir / "scene.json").string());
    app::LiveGraph& live = w.live;
    ASSERT_NE(live.sequence(), nullptr);
    const Renderer* running = &live.renderer();
    const uint32_t reloads = live.reloads();
    const auto screen = [&] { return w.screen(); };
    for (int i = 0; i < 3; ++i) w.frame();
    live.playSequence(0.0);  // playback starts: frame 0, baked with the renderer, is on screen
    const ImageData first = screen();

    w.playUntil(0.1, [](const app::SequenceStats& s) { return s.current == 1u; });
    EXPECT_LT(largestDifference(first, screen()), 1e-6) << "the fade starts from the frame shown before";
    w.frame();
    live.playSequence(0.15);  // half way: the fade lasts one frame of the sequence
    const ImageData half = screen();

    w.playUntil(0.2, [](const app::SequenceStats& s) { return s.failed == 1u; });
    const ImageData second = screen();
    EXPECT_GT(meanColour(second), 0.05) << "a sky, not black";
    EXPECT_GT(largestDifference(first, second), 0.2) << "the sun left the view: the sky changed with the frame";
    EXPECT_GT(largestDifference(first, half), 0.05) << "half way, neither frame";
    EXPECT_GT(largestDifference(half, second), 0.05) << "half way, neither frame";
    for (int i = 0; i < 3; ++i) {
        w.frame();
        live.playSequence(0.25);
    }
    EXPECT_EQ(live.sequence()->stats().current, 1u) << "the sky holds frame 1 over the unreadable frame 2";
    EXPECT_EQ(largestDifference(second, screen()), 0.0);

    w.playUntil(0.3, [](const app::SequenceStats& s) { return s.current == 3u; });
    w.playUntil(0.45, [](const app::SequenceStats& s) { return s.current == 0u && s.shown == 4u; });  // looped
    const app::SequenceStats stats = live.sequence()->stats();
    w.frame();
    live.playSequence(0.58);  // the fade from frame 3 is over; frame 1 is due, and fades in from frame 0 if swapped in
    EXPECT_LT(largestDifference(first, screen()), 1e-6) << "frame 0 again, as at the start";
    EXPECT_EQ(stats.shown, 4u) << "frames 0, 1, 3 and 0 again";
    EXPECT_EQ(stats.dropped, 1u);
    EXPECT_EQ(stats.late, 0u) << "playback's clock waited for every bake";
    EXPECT_EQ(&live.renderer(), running) << "playback rebuilt the renderer";
    EXPECT_EQ(live.reloads(), reloads) << "a sequence's frames are not reloads";
    live.renderer().waitIdle();
    std::filesystem::remove_all(dir);
    expectSilent();
}

// A rebuild (a checkbox, F1, a saved graph) goes on with playback: it bakes the environment
// from the frame on screen, or from the one being baked, and the clock and the stats carry on.
TEST_F(Present, AnEnvironmentSequencePlaysOnThroughARebuild) {
    const std::filesystem::path dir = skySequenceScene("skygraph-present-sequence-rebuild");
    LiveWindow w(*device_, (dir / "scene.json").string());
    app::LiveGraph& live = w.live;
    ASSERT_NE(live.sequence(), nullptr);
    for (int i = 0; i < 3; ++i) w.frame();
    live.playSequence(0.0);
    const ImageData first = w.screen();
    w.playUntil(0.1, [](const app::SequenceStats& s) { return s.current == 1u; });

    // Off and on again: two rebuilds, each baking frame 1, the frame on screen.
    const uint32_t reloads = live.reloads();
    ASSERT_TRUE(live.setFeature("compute_tonemap", !live.feature("compute_tonemap"))) << live.error();
    ASSERT_TRUE(live.setFeature("compute_tonemap", !live.feature("compute_tonemap"))) << live.error();
    EXPECT_EQ(live.reloads(), reloads + 2);
    ASSERT_NE(live.sequence(), nullptr);
    for (int i = 0; i < 3; ++i) {
        w.frame();
        live.playSequence(0.15);  // frame 1's time still: nothing to bake
    }
    EXPECT_FALSE(live.rebaking());
    app::SequenceStats stats = live.sequence()->stats();
    EXPECT_EQ(stats.current, 1u) << "playback started again";
    EXPECT_EQ(stats.shown, 2u);
    EXPECT_EQ(stats.dropped, 0u);
    EXPECT_GT(largestDifference(first, w.screen()), 0.2) << "the rebuild baked frame 0, not the frame on screen";

    // A rebuild while frame 2 is being baked bakes frame 2 itself.
    for (int i = 0; i < 300 && !live.rebaking(); ++i) {
        w.frame();
        live.playSequence(0.2);
    }
    ASSERT_TRUE(live.rebaking()) << "frame 2's bake never started";
    ASSERT_TRUE(live.setFeature("compute_tonemap", !live.feature("compute_tonemap"))) << live.error();
    EXPECT_FALSE(live.rebaking());
    stats = live.sequence()->stats();
    EXPECT_EQ(stats.current, 2u);
    EXPECT_EQ(stats.shown, 3u);
    w.playUntil(0.3, [](const app::SequenceStats& s) { return s.current == 3u; });
    stats = live.sequence()->stats();
    EXPECT_EQ(stats.shown, 4u) << "frames 0, 1, 2 and 3";
    EXPECT_EQ(stats.dropped, 0u);

    // The frame on screen cannot be read now: the rebuild bakes the first frame, and playback
    // starts again from it rather than refusing the rebuild.
    std::ofstream(sequenceFrameFile((dir / "sky_%02d.exr").string(), 3), std::ios::trunc) << "not an EXR";
    ASSERT_TRUE(live.setFeature("compute_tonemap", !live.feature("compute_tonemap"))) << live.error();
    EXPECT_EQ(live.error(), "");
    ASSERT_NE(live.sequence(), nullptr);
    EXPECT_EQ(live.sequence()->stats().current, 0u);
    EXPECT_EQ(live.sequence()->stats().shown, 1u);
    live.renderer().waitIdle();
    std::filesystem::remove_all(dir);
    expectSilent();
}

}  // namespace
}  // namespace skygraph::test
