// An environment re-bake beside running frames (docs/queues.md, "Background frames"): graphs/
// ibl.json with every pass on the compute queue runs as a background frame while a frame
// renderer keeps sampling the old environment cube; once finished, its cube is swapped in
// with importImage, which neither waits nor rebuilds. Lavapipe under synchronization
// validation: the frames, the bake's submits and semaphores, the swap and the old bake's
// destruction while frames that sampled it may still run all report nothing.
#include "analytic_environment.hpp"
#include "cube_probe.hpp"
#include "executor_test_util.hpp"

#include "app/environment_bake.hpp"
#include "app/environment_graph.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/pass.hpp>


namespace skygraph::test {
namespace {

constexpr uint32_t kCube = 32;

/// The frame: imports graphs/ibl.json's `environment` as it is exported at kCube^2.
const char* kFrameGraph = R"({
  "version": 1, "name": "probe_frame",
  "resources": {
    "environment": {"type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [32, 32], "mips": "full",
                    "external": true, "initial": "ShaderRead"},
    "probe": {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": [6, 1],
              "external": true, "final": "TransferSrc"}
  },
  "passes": [
    {"name": "probe", "type": "FaceProbe", "uses": {"environment": "Read@Compute", "probe": "Write@Compute"}}
  ]
})";

HdrImage uniformSky(float r, float g, float b) {
    const ImageData image = equirectImage([&](const Dir&) { return Dir(r, g, b); }, 64, 32);
    return HdrImage{image.width, image.height, image.rgba};
}

class BackgroundBake : public ExecutorTest {
protected:
    BackgroundBake() {
        // The six face centres, in Vulkan's face order.
        library_.add(CubeProbe::typeInfo("FaceProbe"), [](const PassDesc&) {
            return std::make_unique<CubeProbe>(
                std::vector<Dir>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}});
        });
        iblGraph_ = loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "ibl.json", library_.registry());
        // The prefiltered cube as large as the environment: its 6 levels need 32 texels.
        app::resizeEnvironmentGraph(iblGraph_, {kCube, kCube});
    }

    /// The probe frame of `graph` (kFrameGraph, or a copy probing with another pass type).
    std::unique_ptr<Renderer> frameRenderer(const std::string& graph = kFrameGraph) {
        CompileOptions co;
        co.readbacks = {"probe"};
        co.outputWidth = co.outputHeight = 16;
        RendererOptions ro;
        ro.passes = &library_;
        ro.framesInFlight = 2;
        return std::make_unique<Renderer>(
            sharedDevice(), CompiledGraph(parseGraph(graph, "<probe_frame>", library_.registry()), co), ro);
    }

    /// The probe frame, probing with a pass of type `type`.
    std::unique_ptr<Renderer> frameProbingWith(const std::string& type) {
        std::string graph = kFrameGraph;
        graph.replace(graph.find("FaceProbe"), 9, type);
        return frameRenderer(graph);
    }

    /// graphs/ibl.json baked from a sky of one colour, `environment` ready to share.
    app::EnvironmentBake bakeUniform(float r, float g, float b) {
        return app::bakeEnvironment(sharedDevice(), iblGraph_, uniformSky(r, g, b), products_, &library_);
    }

    /// The red channel of every face centre of the frame's last read-back.
    static std::vector<float> faceReds(const ImageData& probe) {
        std::vector<float> reds;
        for (uint32_t i = 0; i < 6; ++i) reds.push_back(probe.rgba[i * 4]);
        return reds;
    }

    PassLibrary library_ = PassLibrary::withBuiltins();
    GraphDesc iblGraph_;
    const std::set<std::string, std::less<>> products_{"environment"};
};

TEST_F(BackgroundBake, FramesSampleTheOldCubeUntilTheSwapThenTheNewOne) {
    app::EnvironmentBake first = bakeUniform(1, 0, 0);
    std::unique_ptr<Renderer> frame = frameRenderer();
    frame->importImage("environment", first.renderer->shareImage("environment"));
    frame->renderFrame();
    for (float red : faceReds(frame->readback())) EXPECT_NEAR(red, 1.0f, 1e-3f);

    app::EnvironmentBaker baker(sharedDevice(), iblGraph_, 64, 32, products_, &library_);
    // Three changes: the baker's two renderers take turns, the third bake reusing the first's
    // renderer while frames that sampled its cube may still be in flight.
    const float reds[] = {0.0f, 0.5f, 0.25f};
    for (float want : reds) {
        ASSERT_TRUE(baker.start(uniformSky(want, 0, 1)));
        EXPECT_FALSE(baker.start(uniformSky(1, 1, 1))) << "a second bake while the first is pending";
        // The frames go on with the old cube while the bake runs; lavapipe's one queue runs
        // them in submission order. Each swap attempt comes with a frame still in flight: the
        // swap must keep the old cube's views and the probe's old recording code alive for it.
        uint32_t framesDuringBake = 0;
        float before = faceReds(frame->readback())[0];
        do {
            frame->renderFrame();
            ++framesDuringBake;
            for (float red : faceReds(frame->readback())) EXPECT_NEAR(red, before, 1e-3f) << "frame " << framesDuringBake;
            frame->renderFrame();
        } while (!baker.swapInWhenFinished(*frame));
        EXPECT_GE(framesDuringBake, 1u);
        // The first bake may go at once: the frames that sampled its cube keep it alive.
        first.renderer.reset();
        frame->renderFrame();
        for (float red : faceReds(frame->readback())) EXPECT_NEAR(red, want, 2e-3f);
    }
    frame->waitIdle();
}

// A pass that reads its handles while recording (keepsSlotHandles() false) is kept across an
// import swap, pipelines and all, and still samples the new cube; one that may keep them is
// made again. Either way the BoundResources it was shown stay where they were (before, a kept
// pass's were freed by the swap, and a pass holding their addresses read freed memory).
TEST_F(BackgroundBake, ASwapKeepsAPassThatReadsItsHandlesWhileRecording) {
    CubeProbe::recordsAwayFromKeptSlots = 0;
    for (const bool keeps : {false, true}) {
        int made = 0;
        library_.add(CubeProbe::typeInfo(keeps ? "KeepingProbe" : "ReadingProbe"), [&made, keeps](const PassDesc&) {
            ++made;
            return std::make_unique<CubeProbe>(std::vector<Dir>{{1, 0, 0}}, keeps);
        });
        const std::unique_ptr<Renderer> probeFrame = frameProbingWith(keeps ? "KeepingProbe" : "ReadingProbe");
        Renderer& frame = *probeFrame;
        app::EnvironmentBake red = bakeUniform(1, 0, 0);
        app::EnvironmentBake blue = bakeUniform(0, 0, 1);
        frame.importImage("environment", red.renderer->shareImage("environment"));
        frame.renderFrame();
        EXPECT_NEAR(frame.readback().rgba[0], 1.0f, 1e-3f);
        const int before = made;
        frame.importImage("environment", blue.renderer->shareImage("environment"));
        frame.renderFrame();
        frame.renderFrame();
        EXPECT_NEAR(frame.readback().rgba[0], 0.0f, 1e-3f) << "the new cube, keeps " << keeps;
        EXPECT_EQ(made, keeps ? before + 1 : before) << "keeps " << keeps;
        EXPECT_EQ(CubeProbe::recordsAwayFromKeptSlots, 0) << "keeps " << keeps;
        frame.waitIdle();
    }
}

/// A CubeProbe whose pipelines fail once `failing` is set: a pass whose recording code cannot
/// be made again for a new image.
class FailingProbe final : public PassImplementation {
public:
    explicit FailingProbe(std::shared_ptr<const bool> failing)
        : failing_(std::move(failing)), probe_(std::vector<Dir>{{1, 0, 0}}) {}
    void createPipelines(const PipelineContext& ctx) override {
        if (*failing_) throw ExecutorError("the probe's pipelines failed");
        probe_.createPipelines(ctx);
    }
    void record(const RecordContext& ctx) override { probe_.record(ctx); }

private:
    std::shared_ptr<const bool> failing_;
    CubeProbe probe_;
};

// An import whose swap fails part way (here, the pipelines or the factory of the second pass
// made again for the new image, after the first was made again) leaves the renderer running
// the old image, with the framebuffers, barriers and recording code built for it, the first
// pass's included; a later import succeeds. Either way validation is silent.
TEST_F(BackgroundBake, AnImportThatFailsPartWayKeepsTheOldImage) {
    library_.add(CubeProbe::typeInfo("RemadeProbe"), [](const PassDesc&) {
        return std::make_unique<CubeProbe>(std::vector<Dir>{{1, 0, 0}}, true);
    });
    const auto firstProbe = [](Renderer& frame) { return frame.readImage("probe_first").at(0).rgba[0]; };
    for (const bool factoryThrows : {false, true}) {
        const auto failing = std::make_shared<bool>(false);
        const std::string type = factoryThrows ? "UnmadeProbe" : "FailingProbe";
        library_.add(CubeProbe::typeInfo(type), [failing, factoryThrows](const PassDesc&) -> std::unique_ptr<PassImplementation> {
            if (*failing && factoryThrows) throw ExecutorError("the probe cannot be made");
            return std::make_unique<FailingProbe>(failing);
        });
        std::string graph = kFrameGraph;
        graph.replace(graph.find("FaceProbe"), 9, type);
        graph.replace(graph.find(R"("probe": {)"), 0, R"("probe_first": {"type": "image2d", "format": "R32G32B32A32_SFLOAT",
            "extent": [6, 1], "external": true, "final": "TransferSrc"}, )");
        graph.replace(graph.find(R"({"name": "probe")"), 0, R"({"name": "first", "type": "RemadeProbe", "uses": [
            {"resource": "environment", "access": "Read", "stage": "Compute"},
            {"resource": "probe_first", "access": "Write", "stage": "Compute", "slot": "probe"}]}, )");
        const std::unique_ptr<Renderer> probeFrame = frameRenderer(graph);
        Renderer& frame = *probeFrame;
        app::EnvironmentBake red = bakeUniform(1, 0, 0);
        app::EnvironmentBake blue = bakeUniform(0, 0, 1);
        frame.importImage("environment", red.renderer->shareImage("environment"));
        frame.renderFrame();
        ASSERT_NEAR(frame.readback().rgba[0], 1.0f, 1e-3f);
        ASSERT_NEAR(firstProbe(frame), 1.0f, 1e-3f);
        *failing = true;
        EXPECT_THROW(frame.importImage("environment", blue.renderer->shareImage("environment")), ExecutorError)
            << "factory throws " << factoryThrows;
        // The blue bake is gone: a frame that still used any of its image would be a
        // use after free, which validation reports.
        blue = {};
        for (int i = 0; i < 3; ++i) {
            frame.renderFrame();
            EXPECT_NEAR(frame.readback().rgba[0], 1.0f, 1e-3f) << "the old cube, factory throws " << factoryThrows;
        }
        EXPECT_NEAR(firstProbe(frame), 1.0f, 1e-3f) << "the first pass's old recording code, factory throws "
                                                    << factoryThrows;
        // A rebuild installs the import that succeeded, not the one that failed.
        *failing = false;
        frame.resize(8, 8);
        frame.renderFrame();
        EXPECT_NEAR(frame.readback().rgba[0], 1.0f, 1e-3f) << "after a rebuild, factory throws " << factoryThrows;
        app::EnvironmentBake green = bakeUniform(0, 1, 0);
        frame.importImage("environment", green.renderer->shareImage("environment"));
        frame.renderFrame();
        frame.renderFrame();
        EXPECT_NEAR(frame.readback().rgba[1], 1.0f, 1e-3f) << "factory throws " << factoryThrows;
        EXPECT_NEAR(frame.readImage("probe_first").at(0).rgba[1], 1.0f, 1e-3f) << "factory throws " << factoryThrows;
        frame.waitIdle();
    }
}

TEST_F(BackgroundBake, ProductsAreNotSharedBeforeTheBackgroundFrameIsFinished) {
    app::EnvironmentBake bake = bakeUniform(0, 1, 0);
    bake.renderer->renderFrameInBackground();  // one submit on the graphics queue: submitted whole
    EXPECT_TRUE(bake.renderer->finishBackgroundFrame());

    GraphDesc onCompute = iblGraph_;
    for (PassDesc& pass : onCompute.passes) pass.queue = QueueKind::Compute;
    app::EnvironmentBake background = app::bakeEnvironment(sharedDevice(), onCompute, uniformSky(0, 1, 0), products_, &library_);
    background.renderer->renderFrameInBackground();
    try {
        (void)background.renderer->shareImage("environment");
        ADD_FAILURE() << "shared an image whose background frame was not finished";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("finishBackgroundFrame"), std::string::npos) << e.what();
    }
    background.renderer->waitIdle();  // submits the held submit, waiting
    EXPECT_TRUE(background.renderer->finishBackgroundFrame());
    (void)background.renderer->shareImage("environment");
}

// Background frames in a row with two in flight: each frame follows the whole of the one
// before, its held last submit included (the final transitions of the products and the frame
// end that the next frame's first accesses wait for). The held submit goes to the queue
// before the next frame's submits, so synchronization validation sees every frame's accesses
// ordered after the previous frame's, and each frame bakes what its equirect says.
TEST_F(BackgroundBake, BackgroundFramesInARowEachFollowTheWholeOfTheOneBefore) {
    GraphDesc onCompute = iblGraph_;
    for (PassDesc& pass : onCompute.passes) pass.queue = QueueKind::Compute;
    ASSERT_TRUE(app::setEquirectExtent(onCompute, 64, 32));
    CompileOptions co;
    co.outputs = products_;
    co.memory = sharedDevice().memoryModel();
    co.queueFamilies = sharedDevice().queueFamilies();
    RendererOptions ro;
    ro.framesInFlight = 2;
    ro.passes = &library_;
    Renderer bake(sharedDevice(), CompiledGraph(onCompute, co), ro);
    ASSERT_GT(bake.plan().submits().size(), 1u) << "a held last submit needs a plan of several submits";
    bake.setExternalImage("equirect", app::toImageData(uniformSky(0, 0, 1)));
    for (int frame = 0; frame < 3; ++frame) bake.renderFrameInBackground();
    bake.waitIdle();
    EXPECT_TRUE(bake.finishBackgroundFrame());
    const std::vector<ImageData> cube = bake.readImage("environment");
    ASSERT_FALSE(cube.empty());
    const auto centre = cube[0].pixel(kCube / 2, kCube / 2);
    EXPECT_NEAR(centre[0], 0.0f, 2e-3f);
    EXPECT_NEAR(centre[2], 1.0f, 2e-3f);
}

}  // namespace
}  // namespace skygraph::test
