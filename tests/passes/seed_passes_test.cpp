// The built-in passes on lavapipe under synchronization validation, against the double-precision
// reference in include/skygraph/shading_math.hpp.
#include "pass_test_util.hpp"

#include <skygraph/pass.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/shading_math.hpp>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

namespace skygraph::test {
namespace {

const std::filesystem::path kSource = SKYGRAPH_SOURCE_DIR;

class SeedPasses : public ExecutorTest {
protected:
    ImageData renderRaster(const Scene& scene, uint32_t width, uint32_t height) {
        return renderRasterFrame(scene, width, height, 3);
    }
};

Scene skyOnlyScene() {
    Scene s;
    s.environment = SceneEnvironment{};  // procedural
    s.camera.position = {0.0, 1.0, 0.0};
    s.camera.yawDeg = 20.0;
    s.camera.pitchDeg = 10.0;
    s.camera.fovYDeg = 70.0;
    return s;
}

/// The expected 8-bit code of a pixel of the sky, computed in double.
double expectedSkyCode(const Scene& scene, uint32_t x, uint32_t y, uint32_t w, uint32_t h, int channel) {
    using namespace math;
    const auto r = cameraRotation(scene.camera.yawDeg, scene.camera.pitchDeg, scene.camera.rollDeg);
    const auto ndc = pixelToNdc<double>(x, y, w, h);
    const auto dir = glm::normalize(viewRayFromNdc(ndc, r, scene.camera.fovYDeg, double(w) / h));
    const auto rgb = tonemap(proceduralSky(dir), scene.exposureEv, ToneOperator::AcesNarkowicz);
    return srgbEncode(rgb[channel]) * 255.0;
}

TEST_F(SeedPasses, SkyAndTonemappingMatchTheReferenceWithinOneCode) {
    const Scene scene = skyOnlyScene();
    const uint32_t w = 48, h = 32;
    const ImageData image = renderRaster(scene, w, h);
    ASSERT_EQ(image.width, w);
    int worst = 0, compared = 0;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            // The sun disc's edge is a step: a pixel whose centre is within a pixel of it may
            // land on either side, so those are left out.
            const auto r = math::cameraRotation(scene.camera.yawDeg, scene.camera.pitchDeg, 0.0);
            const auto d = glm::normalize(math::viewRayFromNdc(math::pixelToNdc<double>(x, y, w, h), r,
                                                               scene.camera.fovYDeg, double(w) / h));
            const double toSun = std::acos(glm::dot(d, glm::normalize(glm::dvec3(0.35, 0.45, -0.82))));
            if (std::abs(toSun - math::radians(0.6)) < math::radians(70.0 / h * 2)) continue;
            for (int c = 0; c < 3; ++c) {
                const double got = image.pixel(x, y)[c] * 255.0;
                const int diff = int(std::lround(std::abs(got - expectedSkyCode(scene, x, y, w, h, c))));
                worst = std::max(worst, diff);
                ++compared;
            }
        }
    EXPECT_GT(compared, int(w * h * 3 * 9 / 10));
    EXPECT_LE(worst, 1) << "8-bit codes";
}

TEST_F(SeedPasses, DefaultSceneDrawsObjectsInFrontOfTheSky) {
    const Scene scene = loadSceneFile(kSource / "scenes/default.json");
    ASSERT_FALSE(scene.objects.empty());
    const ImageData withObjects = renderRaster(scene, 64, 48);
    writePng(std::filesystem::temp_directory_path() / "skygraph-default-scene-64x48.png", withObjects);
    Scene skyOnly = scene;
    skyOnly.objects.clear();
    const ImageData sky = renderRaster(skyOnly, 64, 48);
    int differing = 0;
    for (uint32_t y = 0; y < 48; ++y)
        for (uint32_t x = 0; x < 64; ++x)
            if (std::abs(withObjects.pixel(x, y)[0] - sky.pixel(x, y)[0]) > 2.0f / 255) ++differing;
    // The objects cover a good part of the frame, and the sky still shows somewhere.
    EXPECT_GT(differing, 64 * 48 / 10);
    EXPECT_LT(differing, 64 * 48);
}

// raster.json's two forward passes, edited so that both run and the second draws over the
// first's colour: its depth Write comes after the first's, so its load op neither clears nor
// loads, and its depth test would meet undefined values. Which pass is first depends on the
// features, so the loader accepts the file; the renderer refuses the plan, naming the pass.
// With ReadWrite the plan runs. (Had the second written the colour whole too, the first would
// be culled, and the second's Write would be the first use.)
TEST_F(SeedPasses, AForwardPassDepthWriteAfterAnotherPassIsRefused) {
    std::ifstream in(kSource / "graphs/raster.json");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string onlyWithoutSky = R"("if": "geometry && !skybox")";
    ASSERT_NE(text.find(onlyWithoutSky), std::string::npos);
    text.replace(text.find(onlyWithoutSky), onlyWithoutSky.size(), R"("if": "geometry")");
    const std::string iblColor = R"("hdr_color": "Write@ColorAttachment",
                "irradiance")";
    ASSERT_NE(text.find(iblColor), std::string::npos);
    text.replace(text.find(iblColor), iblColor.size(), R"("hdr_color": "ReadWrite@ColorAttachment",
                "irradiance")");
    const PassLibrary library = PassLibrary::withBuiltins();
    CompileOptions co;
    co.features = {{"geometry", true}, {"skybox", true}};
    const GraphDesc both = parseGraph(text, "raster.json", library.registry());
    try {
        (void)rendererAt(both, library, co, 32, 24);
        FAIL() << "a depth Write after another pass's was accepted";
    } catch (const ExecutorError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("pass 'forward_ibl', resource 'depth': ForwardPass tests depth"), std::string::npos)
            << what;
        EXPECT_NE(what.find("this Write is not the first use of the resource in the plan"), std::string::npos) << what;
    }
    // The same two passes, the second testing against what the first left.
    const std::string iblDepth = R"("name": "forward_ibl", "type": "ForwardPass", "if": "geometry && skybox",
      "uses": { "depth": "Write@DepthAttachment")";
    ASSERT_NE(text.find(iblDepth), std::string::npos);
    std::string readWrite = iblDepth;
    readWrite.replace(readWrite.find("Write@DepthAttachment"), 5, "ReadWrite");
    text.replace(text.find(iblDepth), iblDepth.size(), readWrite);
    Renderer renderer = rendererAt(parseGraph(text, "raster.json", library.registry()), library, co, 32, 24);
    renderer.frameData().set(loadSceneFile(kSource / "scenes/default.json"));
    renderer.renderFrame();
    renderer.waitIdle();
}

// Every glTF file names its images "images[i]": two textured models uploaded in one frame must
// not share upload names (the second was refused: "another image has that name"). Both
// copies of the box stand in one place, so the second fails the depth test everywhere and the
// frame is the first copy's.
TEST_F(SeedPasses, TwoTexturedModelsInOneFrameRenderAsEachAlone) {
    const std::string box = R"({ "type": "gltf", "file": "/usr/share/assimp/models/glTF2/)";
    const auto scene = [&](const std::string& objects) {
        return parseScene(R"({ "camera": { "position": [0.0, 0.9, 2.6], "pitch_deg": -18.0, "fov_y_deg": 40.0 },
                               "environment": { "file": "procedural" }, "objects": [)" + objects + "] }",
                          "boxes.json", kSource);
    };
    const std::string binary = box + R"(BoxTextured-glTF-Binary/BoxTextured.glb" })";
    const ImageData one = renderRaster(scene(binary), 48, 32);
    // The .gltf's own copy of the box, drawn second: a model of its own, with its own images.
    const ImageData two = renderRaster(scene(binary + ", " + box + R"(BoxTextured-glTF/BoxTextured.gltf" })"), 48, 32);
    ASSERT_EQ(one.rgba.size(), two.rgba.size());
    size_t differing = 0;
    for (size_t i = 0; i < one.rgba.size(); ++i) differing += one.rgba[i] != two.rgba[i];
    EXPECT_EQ(differing, 0u);
    // The box covers part of the frame: the comparison sees its texture.
    const ImageData sky = renderRaster(scene(""), 48, 32);
    size_t boxValues = 0;
    for (size_t i = 0; i < one.rgba.size(); ++i) boxValues += std::abs(one.rgba[i] - sky.rgba[i]) > 0.01f;
    EXPECT_GT(boxValues, 48u * 32u / 10u);
}

TEST_F(SeedPasses, DebugViewsPassThroughInZeroToOne) {
    Scene scene = loadSceneFile(kSource / "scenes/default.json");
    scene.debugView = DebugView::Roughness;
    const ImageData image = renderRaster(scene, 32, 24);
    for (uint32_t y = 0; y < 24; ++y)
        for (uint32_t x = 0; x < 32; ++x)
            for (int c = 0; c < 3; ++c) {
                EXPECT_GE(image.pixel(x, y)[c], 0.0f);
                EXPECT_LE(image.pixel(x, y)[c], 1.0f);
            }
}

}  // namespace
}  // namespace skygraph::test
