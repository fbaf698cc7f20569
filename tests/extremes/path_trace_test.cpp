// PathTracePass (docs/tradeoffs.md) on lavapipe under validation + synchronization validation:
// a white furnace whose answer is known in closed form, progressive accumulation across frames,
// and the shipped graphs/pathtrace.json end to end.
#include "pass_test_util.hpp"

#include "ibl_math.hpp"
#include <skygraph/pass.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/shading_math.hpp>

#include <cmath>
#include <cstdio>
#include <memory>

namespace skygraph::test {
namespace {

const std::filesystem::path kSource = SKYGRAPH_SOURCE_DIR;

// The path tracer lit by a (constant) equirect environment, accumulating `samples_per_frame`
// samples a frame.
constexpr const char* kFurnaceGraph = R"({
  "version": 1, "name": "furnace",
  "resources": {
    "accumulation": {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": "output",
                     "external": true, "final": "General"},
    "equirect":     {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": [2, 1],
                     "external": true, "initial": "ShaderRead"}
  },
  "passes": [
    {"name": "pathtrace", "type": "PathTracePass", "params": {"samples_per_frame": 64, "max_bounces": 4},
     "uses": {"accumulation": "ReadWrite@Compute", "equirect": "Read@Compute"}}
  ]
})";

constexpr uint32_t kWidth = 32, kHeight = 24;
constexpr double kEnvironment = 1.0;
constexpr double kAlbedo = 0.8, kRoughness = 0.5;

Scene furnaceScene() {
    Scene s;
    s.environment = SceneEnvironment{false, "unused.hdr", 0.0, EnvironmentSampling::Equirect};
    s.camera.position = {0.0, 0.0, 0.0};
    s.camera.fovYDeg = 60.0;
    SceneObject sphere;
    sphere.shape = Sphere{{0.0, 0.0, -3.0}, 1.0};
    sphere.material.baseColor = {kAlbedo, kAlbedo, kAlbedo};
    sphere.material.metallic = 0.0;
    sphere.material.roughness = kRoughness;
    s.objects.push_back(sphere);
    return s;
}

/// Where the ray through (x, y) meets the sphere: n.v there, or < 0 for a miss.
double sphereNv(double x, double y) {
    using namespace math;
    const auto d = glm::normalize(viewRayFromNdc(pixelToNdc<double>(x, y, kWidth, kHeight), Mat3<double>(1.0), 60.0,
                                                 double(kWidth) / kHeight));
    const glm::dvec3 c(0.0, 0.0, -3.0);
    const double dc = glm::dot(d, c), disc = dc * dc - (glm::dot(c, c) - 1.0);
    if (disc < 0.0) return -1.0;
    const glm::dvec3 hit = d * (dc - std::sqrt(disc));
    return glm::dot(glm::normalize(hit - c), -d);
}

/// A pixel whose whole footprint (its corners) lies on the sphere: the jittered samples all hit.
bool fullyOnSphere(uint32_t x, uint32_t y) {
    for (const double dx : {-0.5, 0.5})
        for (const double dy : {-0.5, 0.5})
            if (sphereNv(x + dx, y + dy) < 0.0) return false;
    return true;
}

/// The furnace's closed form: a convex Lambert + GGX object under a constant environment L
/// sees only the environment after one bounce, so it returns L (albedo + F0 A + B) with
/// (A, B) the split-sum integral at its n.v (tests/support/ibl_math.hpp). Averaged over
/// the pixel's footprint.
double expectedFurnace(uint32_t x, uint32_t y) {
    double sum = 0.0;
    int n = 0;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            const double nv = sphereNv(x - 0.5 + (i + 0.5) / 4.0, y - 0.5 + (j + 0.5) / 4.0);
            const auto ab = math::ibl::brdfIntegral(std::max(nv, 1e-4), kRoughness, 4096);
            sum += kEnvironment * (kAlbedo + 0.04 * ab.x + ab.y);
            ++n;
        }
    return sum / n;
}

class PathTrace : public ExecutorTest {
protected:
    struct Stats {
        double meanError = 0.0, rmse = 0.0;
        int compared = 0;
    };
    /// Renders `frames` frames of the furnace and compares the sphere's pixels.
    Stats furnace(uint32_t frames, ImageData* out = nullptr) {
        const PassLibrary library = PassLibrary::withBuiltins();
        const GraphDesc graph = parseGraph(kFurnaceGraph, "furnace.json", library.registry());
        Renderer renderer = rendererAt(graph, library, {}, kWidth, kHeight);
        const float l = float(kEnvironment);
        renderer.setExternalImage("equirect", constantImage(2, 1, glm::vec3(l)));
        renderer.frameData().set(furnaceScene());
        for (uint32_t i = 0; i < frames; ++i) renderer.renderFrame();
        const ImageData img = renderer.readImage("accumulation").at(0);
        if (out) *out = img;
        Stats s;
        for (uint32_t y = 0; y < kHeight; ++y)
            for (uint32_t x = 0; x < kWidth; ++x) {
                if (!fullyOnSphere(x, y)) continue;
                const double err = img.pixel(x, y)[0] - expectedFurnace(x, y);
                s.meanError += err;
                s.rmse += err * err;
                ++s.compared;
            }
        s.meanError /= std::max(1, s.compared);
        s.rmse = std::sqrt(s.rmse / std::max(1, s.compared));
        return s;
    }

    /// The accumulation after four frames of `scene` in the furnace.
    ImageData traceFurnace(const Scene& scene) {
        const GraphDesc graph = parseGraph(kFurnaceGraph, "furnace.json", library_.registry());
        Renderer renderer = rendererAt(graph, library_, {}, kWidth, kHeight);
        renderer.setExternalImage("equirect", constantImage(2, 1, glm::vec3(float(kEnvironment))));
        renderer.frameData().set(scene);
        for (int i = 0; i < 4; ++i) renderer.renderFrame();
        return renderer.readImage("accumulation").at(0);
    }

    /// graphs/pathtrace.json with environment_file on, headless at 16x12: no objects, lit by a
    /// constant map of `radiance` turned by `rotationDeg`.
    std::unique_ptr<Renderer> environmentFileTracer(glm::vec3 radiance, double rotationDeg) {
        const GraphDesc graph = loadGraphFile(kSource / "graphs/pathtrace.json", library_.registry());
        CompileOptions co;
        co.features = {{"environment_file", true}};
        co.outputWidth = 16;
        co.outputHeight = 12;
        RendererOptions ro;
        ro.passes = &library_;
        auto renderer = std::make_unique<Renderer>(sharedDevice(), CompiledGraph(graph, headless(graph, co)), ro);
        renderer->setExternalImage("equirect", constantImage(2, 1, radiance));
        Scene scene;
        scene.environment = SceneEnvironment{false, "unused.hdr", rotationDeg, EnvironmentSampling::Equirect};
        renderer->frameData().set(scene);
        return renderer;
    }

    const PassLibrary library_ = PassLibrary::withBuiltins();
};

TEST_F(PathTrace, WhiteFurnaceConvergesToTheClosedForm) {
    ImageData img;
    const Stats few = furnace(1);
    const Stats many = furnace(16, &img);  // 64 and 1024 samples per pixel
    std::printf("furnace: 64 spp rmse %.4f, mean error %+.4f; 1024 spp rmse %.4f, mean error %+.4f (%d pixels)\n",
                few.rmse, few.meanError, many.rmse, many.meanError, many.compared);
    ASSERT_GT(many.compared, 100);
    // One sample's spread is ~0.8 (one of two lobes, each divided by 1/2): at 1024 spp a
    // pixel's standard error is ~0.025 and the mean over >100 pixels ~0.0025.
    EXPECT_LT(std::abs(many.meanError), 0.01);
    EXPECT_LT(many.rmse, 0.05);
    EXPECT_LT(many.rmse, few.rmse * 0.5) << "error must shrink as 1/sqrt(spp): 16x the samples, 1/4 the error";
    for (uint32_t y = 0; y < kHeight; ++y)
        for (uint32_t x = 0; x < kWidth; ++x) {
            const auto px = img.pixel(x, y);
            ASSERT_TRUE(std::isfinite(px[0]) && std::isfinite(px[1]) && std::isfinite(px[2]));
            EXPECT_EQ(px[3], 1024.0f) << "alpha counts the samples";
            if (x < 8 || x > 24) {  // the sphere spans columns 8.6 to 23.4: these rays all miss it
                EXPECT_NEAR(px[0], kEnvironment, 1e-5) << "a miss sees the environment exactly";
            }
        }
}

// graphs/pathtrace.json as shipped (procedural sky, TonemappingPass reading the mean) on the
// default scene: clean under validation, finite, and the tonemapped frame shows the objects.
TEST_F(PathTrace, ShippedGraphRendersTheDefaultSceneCleanly) {
    const PassLibrary library = PassLibrary::withBuiltins();
    const GraphDesc graph = loadGraphFile(kSource / "graphs/pathtrace.json", library.registry());
    const Scene scene = loadSceneFile(kSource / "scenes/default.json");
    CompileOptions co;
    // Only the scene features pathtrace.json declares (as `skygraph render` does): the rest
    // are raster.json's, and the path tracer always traces the objects.
    for (const FeatureDecl& f : graph.features) co.features[f.name] = sceneFeatures(scene).at(f.name);
    co.presentReplacement = ExternalState::TransferSrc;
    Renderer renderer = rendererAt(graph, library, co, 32, 24);
    renderer.frameData().set(scene);
    for (int i = 0; i < 4; ++i) renderer.renderFrame();
    const ImageData ldr = renderer.readback();
    const ImageData hdr = renderer.readImage("accumulation").at(0);
    double lo = 1.0, hi = 0.0;
    for (uint32_t y = 0; y < 24; ++y)
        for (uint32_t x = 0; x < 32; ++x) {
            const auto px = hdr.pixel(x, y);
            ASSERT_TRUE(std::isfinite(px[0]) && std::isfinite(px[1]) && std::isfinite(px[2])) << x << "," << y;
            EXPECT_EQ(px[3], 4.0f);
            lo = std::min(lo, double(ldr.pixel(x, y)[0]));
            hi = std::max(hi, double(ldr.pixel(x, y)[0]));
        }
    EXPECT_GT(hi - lo, 0.1) << "a frame of one colour: the tonemap read nothing or the tracer drew nothing";
}

// graphs/pathtrace.json with environment_file on: the tracer reads the equirect the loader
// fills. A constant map and no objects: every pixel's mean is the constant exactly.
TEST_F(PathTrace, ShippedGraphTracesTheEnvironmentFileWhenBound) {
    const auto tracer = environmentFileTracer({0.25f, 0.5f, 2.0f}, 30.0);
    for (int i = 0; i < 2; ++i) tracer->renderFrame();
    const ImageData hdr = tracer->readImage("accumulation").at(0);
    for (uint32_t y = 0; y < 12; ++y)
        for (uint32_t x = 0; x < 16; ++x) {
            const auto px = hdr.pixel(x, y);
            EXPECT_NEAR(px[0], 0.25f, 1e-6) << x << "," << y;
            EXPECT_NEAR(px[1], 0.5f, 1e-6) << x << "," << y;
            EXPECT_NEAR(px[2], 2.0f, 1e-6) << x << "," << y;
            EXPECT_EQ(px[3], 2.0f);
        }
}

// New environment pixels start the mean over: after two frames of a map of 1 and one of a map
// of 3, every pixel is 3 from one sample, not a mean of both maps.
TEST_F(PathTrace, ANewEnvironmentImageStartsTheAccumulationOver) {
    const auto tracer = environmentFileTracer(glm::vec3(1.0f), 0.0);
    Renderer& renderer = *tracer;
    const auto expectEverywhere = [&](float radiance, float samples, const char* after) {
        const ImageData hdr = renderer.readImage("accumulation").at(0);
        for (uint32_t y = 0; y < 12; ++y)
            for (uint32_t x = 0; x < 16; ++x) {
                const auto px = hdr.pixel(x, y);
                ASSERT_NEAR(px[0], radiance, 1e-6) << after << " at " << x << "," << y;
                ASSERT_EQ(px[3], samples) << after << " at " << x << "," << y;
            }
    };
    for (int i = 0; i < 2; ++i) renderer.renderFrame();
    expectEverywhere(1.0f, 2.0f, "two frames of the first map");
    renderer.setExternalImage("equirect", constantImage(2, 1, glm::vec3(3.0f)));
    renderer.renderFrame();
    expectEverywhere(3.0f, 1.0f, "setExternalImage");
    renderer.updateExternalImage("equirect", constantImage(2, 1, glm::vec3(0.5f)));
    renderer.renderFrame();
    renderer.renderFrame();
    expectEverywhere(0.5f, 2.0f, "updateExternalImage");
}

// A glTF mesh traces as the analytic object it equals: a textured quad against the bounded
// plane of the same place and material, the texture's one sRGB texel decoded into the plane's
// linear base colour. Both draw the same random numbers (one pass name), so any difference is
// in the hit and the material, not noise.
TEST_F(PathTrace, AGltfQuadTracesAsTheAnalyticPlaneItEquals) {
    constexpr uint8_t kTexel = 231;  // sRGB 0.906: linear 0.799
    const double linear = std::pow((kTexel / 255.0 + 0.055) / 1.055, 2.4);
    auto quad = std::make_shared<TriangleMesh>();
    for (const float y : {-1.0f, 1.0f})
        for (const float x : {-1.0f, 1.0f})
            quad->vertices.push_back({{x, y, -3.0f}, {0, 0, 1}, {(x + 1) / 2, (1 - y) / 2}, {1, 0, 0, 1}});
    quad->indices = {0, 1, 2, 1, 3, 2};
    MeshPrimitive p;
    p.indexCount = 6;
    p.material.baseColor = {1.0, 1.0, 1.0, 1.0};
    p.material.metallic = 0.0;
    p.material.roughness = kRoughness;
    p.material.baseColorTexture.image = 0;
    quad->primitives = {p};
    quad->images.push_back({1, 1, {kTexel, kTexel, kTexel, 255}, "images[0]"});

    Scene mesh = furnaceScene();
    mesh.objects[0].shape = GltfModel{quad};
    Scene plane = furnaceScene();
    plane.objects[0].shape = Plane{{0.0, 0.0, -3.0}, {0.0, 0.0, 1.0}, 1.0};
    plane.objects[0].material.baseColor = {linear, linear, linear};
    const ImageData fromMesh = traceFurnace(mesh), fromPlane = traceFurnace(plane);
    double worst = 0.0;
    int onQuad = 0;
    for (uint32_t y = 0; y < kHeight; ++y)
        for (uint32_t x = 0; x < kWidth; ++x) {
            const double a = fromMesh.pixel(x, y)[0], b = fromPlane.pixel(x, y)[0];
            ASSERT_TRUE(std::isfinite(a)) << x << "," << y;
            worst = std::max(worst, std::abs(a - b));
            onQuad += std::abs(b - kEnvironment) > 0.05;
        }
    EXPECT_GT(onQuad, 20) << "the quad must cover pixels for the comparison to mean something";
    // The same paths up to float rounding at the edges' pixels, where a jittered ray may land
    // on one side of the edge for one and the other side for the other.
    int differing = 0;
    for (uint32_t y = 0; y < kHeight; ++y)
        for (uint32_t x = 0; x < kWidth; ++x) differing += std::abs(fromMesh.pixel(x, y)[0] - fromPlane.pixel(x, y)[0]) > 1e-3;
    EXPECT_LE(differing, 8) << "worst difference " << worst;
}

// A sphere a hundred thousand times larger than its distance from the camera is, near the
// camera, the plane it touches (the curvature moves it by 3.5e-4 at the frame's edge). Its
// least hit distance, a ten-thousandth of its radius, once passed over the near side (3 away)
// and met the far side from within: the sphere came out black where the plane is lit.
TEST_F(PathTrace, ALargeSphereTracesAsThePlaneItTouches) {
    constexpr double kRadius = 1e5;
    Scene sphere = furnaceScene();
    sphere.objects[0].shape = Sphere{{0.0, 0.0, -3.0 - kRadius}, kRadius};
    Scene plane = furnaceScene();
    plane.objects[0].shape = Plane{{0.0, 0.0, -3.0}, {0.0, 0.0, 1.0}, std::nullopt};
    const ImageData fromSphere = traceFurnace(sphere), fromPlane = traceFurnace(plane);
    double sphereSum = 0.0, planeSum = 0.0;
    for (uint32_t y = 0; y < kHeight; ++y)
        for (uint32_t x = 0; x < kWidth; ++x) {
            const double a = fromSphere.pixel(x, y)[0], b = fromPlane.pixel(x, y)[0];
            ASSERT_TRUE(std::isfinite(a)) << x << "," << y;
            sphereSum += a;
            planeSum += b;
            // The plane fills the view: it reflects less than the environment gives.
            EXPECT_LT(b, kEnvironment) << x << "," << y;
            EXPECT_NEAR(a, b, 0.1) << x << "," << y;
        }
    EXPECT_NEAR(sphereSum / planeSum, 1.0, 0.01);
}

}  // namespace
}  // namespace skygraph::test
