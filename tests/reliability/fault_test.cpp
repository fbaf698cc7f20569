// Faults while a renderer runs: a broken shader, a graph edited to an invalid state, a
// watched file deleted, an environment image that is truncated or not an image, and an
// extent too large to allocate. Each must leave the last good state rendering, lose no
// frame (every renderFrame() call still renders one) and log one clear warning, however
// often the watcher polls.
#include "executor_test_util.hpp"

#include <skygraph/hdr_image.hpp>
#include <skygraph/hot_reload.hpp>

#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace skygraph::test {
namespace {

namespace fs = std::filesystem;

void write(const fs::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary | std::ios::trunc) << text;
}

std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

std::string graphWithColor(const std::string& color) {
    return R"({ "version": 1, "name": "fault", "resources": {
      "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",
                     "external": true, "final": "Present" } },
      "passes": [ { "name": "p", "type": "Generic", "uses": { "swapchain": "Write@ColorAttachment" },
                    "params": { "color": )" + color + " } } ] }";
}

/// Captures spdlog's warnings for the test's duration (the default logger is restored).
class WarningLog {
public:
    WarningLog() : sink_(std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(64)),
                   previous_(spdlog::default_logger()) {
        auto logger = std::make_shared<spdlog::logger>("fault_test", sink_);
        logger->set_level(spdlog::level::warn);
        spdlog::set_default_logger(logger);
    }
    ~WarningLog() { spdlog::set_default_logger(previous_); }
    std::vector<std::string> take() {
        auto lines = sink_->last_formatted();
        sink_ = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(64);
        spdlog::default_logger()->sinks() = {sink_};
        return lines;
    }

private:
    std::shared_ptr<spdlog::sinks::ringbuffer_sink_mt> sink_;
    std::shared_ptr<spdlog::logger> previous_;
};

/// A renderer watched by a HotReloader over a private copy of the shaders.
class FaultTest : public ExecutorTest {
protected:
    void SetUp() override {
        ExecutorTest::SetUp();
        dir_ = fs::temp_directory_path() / ("skygraph_faults_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "shaders");
        fs::copy_file(fs::path(SKYGRAPH_SOURCE_DIR) / "shaders" / "generic_common.glsl", shader());
        write(graphFile(), graphWithColor("[1, 0, 0, 1]"));
        GraphDesc graph = loadGraphFile(graphFile(), PassRegistry::withBuiltins());
        CompileOptions options = headless(graph);
        RendererOptions ro = genericOptions();
        ro.shaderDir = dir_ / "shaders";
        renderer_ = std::make_unique<Renderer>(sharedDevice(), CompiledGraph(std::move(graph), std::move(options)), ro);
        reloader_ = std::make_unique<HotReloader>(*renderer_, graphFile(), dir_ / "shaders");
        renderer_->renderFrame();
        expectRed();
    }
    void TearDown() override {
        if (renderer_) renderer_->waitIdle();
        reloader_.reset();
        renderer_.reset();
        fs::remove_all(dir_);
        ExecutorTest::TearDown();
    }

    fs::path graphFile() const { return dir_ / "g.json"; }
    fs::path shader() const { return dir_ / "shaders" / "generic_common.glsl"; }

    void expectRed() { EXPECT_PIXEL_NEAR(renderer_->readback(), 3, 3, 1.0, 0.0, 0.0, 1.0); }

    /// Polls several times and renders between polls: the fault is reported once, every
    /// frame is rendered with the last good version, and the warning names `needle`.
    void expectOneWarningAndNoLostFrame(WarningLog& log, const std::string& needle) {
        const uint64_t before = renderer_->frameCount();
        EXPECT_EQ(reloader_->poll(), HotReloader::Result::Failed);
        for (int i = 0; i < 4; ++i) {
            renderer_->renderFrame();
            EXPECT_EQ(reloader_->poll(), HotReloader::Result::Unchanged) << "the fault is reported once";
        }
        EXPECT_EQ(renderer_->frameCount(), before + 4) << "a frame was lost";
        expectRed();
        const auto lines = log.take();
        ASSERT_EQ(lines.size(), 1u) << "expected one warning";
        EXPECT_NE(lines[0].find(needle), std::string::npos) << lines[0];
        EXPECT_NE(reloader_->lastError().find(needle), std::string::npos) << reloader_->lastError();
    }

    fs::path dir_;
    std::unique_ptr<Renderer> renderer_;
    std::unique_ptr<HotReloader> reloader_;
};

TEST_F(FaultTest, BrokenShaderKeepsTheLastGoodPipelines) {
    WarningLog log;
    const std::string good = read(shader());
    write(shader(), good + "\nthis is not glsl;\n");
    expectOneWarningAndNoLostFrame(log, "does not compile");
    write(shader(), good);
    EXPECT_EQ(reloader_->poll(), HotReloader::Result::Reloaded);
    renderer_->renderFrame();
    expectRed();
}

TEST_F(FaultTest, InvalidGraphEditKeepsTheLastGoodPlan) {
    WarningLog log;
    // Well-formed JSON, wrong graph: an unknown resource. The message names the file and path.
    std::string bad = graphWithColor("[0, 1, 0, 1]");
    bad.replace(bad.find("\"swapchain\": \"Write"), 11, "\"nowhere\"");
    write(graphFile(), bad);
    expectOneWarningAndNoLostFrame(log, "passes[0].uses.nowhere");
    EXPECT_NE(reloader_->lastError().find("g.json"), std::string::npos);
    write(graphFile(), graphWithColor("[0, 1, 0, 1]"));
    EXPECT_EQ(reloader_->poll(), HotReloader::Result::Reloaded);
    renderer_->renderFrame();
    EXPECT_PIXEL_NEAR(renderer_->readback(), 3, 3, 0.0, 1.0, 0.0, 1.0);
}

TEST_F(FaultTest, DeletedGraphFileKeepsTheLastGoodPlanUntilItIsBack) {
    WarningLog log;
    const std::string text = read(graphFile());
    fs::remove(graphFile());
    expectOneWarningAndNoLostFrame(log, "is gone");
    // A shader edit meanwhile goes to the running plan; the file is not reported gone again.
    write(shader(), read(shader()) + "\n// edited\n");
    EXPECT_EQ(reloader_->poll(), HotReloader::Result::Reloaded) << reloader_->lastError();
    renderer_->renderFrame();
    expectRed();
    EXPECT_TRUE(log.take().empty()) << "the file was reported gone again";
    // The same text back is a change too: it is loaded again.
    write(graphFile(), text);
    EXPECT_EQ(reloader_->poll(), HotReloader::Result::Reloaded);
    renderer_->renderFrame();
    expectRed();
    EXPECT_TRUE(log.take().empty());
}

TEST_F(FaultTest, DeletedShaderFileKeepsTheLastGoodPipelines) {
    WarningLog log;
    const std::string good = read(shader());
    fs::remove(shader());
    expectOneWarningAndNoLostFrame(log, "generic_common.glsl");
    write(shader(), good);
    EXPECT_EQ(reloader_->poll(), HotReloader::Result::Reloaded);
    renderer_->renderFrame();
    expectRed();
}

TEST_F(FaultTest, ExtentTooLargeIsRefusedBeforeAllocation) {
    WarningLog log;
    // Through the watcher: a graph edited to a resource no device can hold (256 layers of
    // 16384^2 RGBA32F = 1 TiB) fails against the memory cap; the old plan keeps running.
    write(graphFile(), R"({ "version": 1, "name": "fault", "resources": {
      "huge": { "type": "image2d_array", "format": "R32G32B32A32_SFLOAT", "extent": [16384, 16384],
                "layers": 256, "clear": { "color": [0, 0, 0, 0] } },
      "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",
                     "external": true, "final": "Present" } },
      "passes": [ { "name": "p", "type": "Generic", "params": { "color": [0, 1, 0, 1] },
                    "uses": { "huge": "Write@Transfer", "swapchain": "Write@ColorAttachment" } } ] })");
    expectOneWarningAndNoLostFrame(log, "over the memory cap");
    // Directly: an output size beyond the largest extent a graph's image takes, refused by the
    // compile before any device limit is asked.
    try {
        renderer_->resize(1u << 20, 16);
        FAIL() << "resize to 1048576x16 was accepted";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("resize to 1048576x16: "), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("the output extent 1048576x16 is past 16384 a side"), std::string::npos)
            << e.what();
    }
    const uint64_t before = renderer_->frameCount();
    renderer_->renderFrame();
    EXPECT_EQ(renderer_->frameCount(), before + 1);
    const ImageData img = renderer_->readback();
    EXPECT_EQ(img.width, 16u) << "the old size keeps rendering";
    EXPECT_PIXEL_NEAR(img, 3, 3, 1.0, 0.0, 0.0, 1.0);
}

/// The environment image as the embedding API loads it: loadHdrImage, then
/// Renderer::setExternalImage. A bad file fails at the load and must not disturb the
/// renderer; a good image of the wrong size is refused by the renderer, which keeps the old.
TEST_F(ExecutorTest, BadEnvironmentImageLeavesTheRendererUntouched) {
    const fs::path lights = "/usr/share/blender/datafiles/studiolights/world";
    const HdrImage real = loadHdrImage(lights / "forest.exr");
    ASSERT_GE(real.width, 8u);
    // An 8x4 image of the real file's pixels (every n-th), as the graph's external `env`.
    ImageData env;
    env.width = 8;
    env.height = 4;
    for (uint32_t y = 0; y < env.height; ++y)
        for (uint32_t x = 0; x < env.width; ++x)
            for (uint32_t c = 0; c < 4; ++c)
                env.rgba.push_back(real.rgba[(size_t(y * (real.height / 4)) * real.width + x * (real.width / 8)) * 4 + c]);
    GraphDesc graph = parseGraph(R"({ "version": 1, "name": "env", "resources": {
        "env": { "type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": [8, 4], "external": true,
                 "final": "TransferSrc" },
        "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true,
                       "final": "Present" } },
      "passes": [ { "name": "sky", "type": "Generic",
                    "uses": { "env": "Read@Fragment", "swapchain": "Write@ColorAttachment" } } ] })",
                                 "<test>", PassRegistry::withBuiltins());
    CompileOptions co = headless(graph);
    co.readbacks = {"env"};
    Renderer r(sharedDevice(), CompiledGraph(std::move(graph), co), genericOptions());
    r.setExternalImage("env", env);
    r.renderFrame();
    const ImageData shown = r.readback();
    ASSERT_EQ(shown.rgba.size(), env.rgba.size());
    for (size_t i = 0; i < env.rgba.size(); ++i) ASSERT_FLOAT_EQ(shown.rgba[i], env.rgba[i]) << i;

    const fs::path dir = fs::temp_directory_path() / ("skygraph_env_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string bytes = read(lights / "forest.exr");
    write(dir / "truncated.exr", bytes.substr(0, bytes.size() / 3));
    write(dir / "text.hdr", "#?RADIANCE\nthis is not an image\n");
    write(dir / "png.exr", "\x89PNG\r\n\x1a\n0000");
    for (const char* name : {"truncated.exr", "text.hdr", "png.exr", "missing.hdr"}) {
        try {
            (void)loadHdrImage(dir / name);
            ADD_FAILURE() << name << " loaded";
        } catch (const ImageError& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
        r.renderFrame();
    }
    // A real image of the wrong size: refused by the renderer, old contents kept.
    ImageData wrong = env;
    wrong.width = 4;
    EXPECT_THROW(r.setExternalImage("env", wrong), ExecutorError);
    const uint64_t before = r.frameCount();
    r.renderFrame();
    EXPECT_EQ(r.frameCount(), before + 1);
    const ImageData after = r.readback();
    for (size_t i = 0; i < env.rgba.size(); ++i) ASSERT_FLOAT_EQ(after.rgba[i], env.rgba[i]) << i;
    r.waitIdle();
    fs::remove_all(dir);
}

}  // namespace
}  // namespace skygraph::test
