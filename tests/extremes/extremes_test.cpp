// Numerics at the extremes (docs/tradeoffs.md), on lavapipe under validation + synchronization
// validation: every test asserts finite output, a stated error bound against the double
// reference of include/skygraph/shading_math.hpp, and (through ExecutorTest) no message.
// The camera 1e7 from the origin is tests/passes/far_camera_test.cpp's; the CPU reference's
// own hostile-input properties are tests/math's. Here: the GPU passes.
#include "pass_test_util.hpp"

#include <skygraph/pass.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/shading_math.hpp>

#include <cmath>
#include <cstdio>
#include <limits>

namespace skygraph::test {
namespace {

const std::filesystem::path kSource = SKYGRAPH_SOURCE_DIR;
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// TonemappingPass alone on an HDR image the test writes: fp32, so +inf, NaN and 1e38 reach
// the shader as they are. The output is fp32 UNORM-free, so the shader sRGB-encodes and the
// read-back carries the encoded value at full precision.
constexpr const char* kTonemapGraph = R"({
  "version": 1, "name": "tonemap_only",
  "resources": {
    "hdr":  {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": [8, 2],
             "external": true, "initial": "ShaderRead"},
    "ldr":  {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": [8, 2],
             "clear": {"color": [0, 0, 0, 0]}}
  },
  "passes": [
    {"name": "tonemap", "type": "TonemappingPass",
     "uses": {"hdr": "Read@Fragment", "ldr": "Write@ColorAttachment"}}
  ]
})";

// The environment passes at their smallest: a 2x1 equirect into a cube of 1x1 faces, then
// irradiance and the GGX prefilter into 1x1 faces.
constexpr const char* kTinyIblGraph = R"({
  "version": 1, "name": "tiny_ibl",
  "resources": {
    "equirect":    {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": [2, 1],
                    "external": true, "initial": "ShaderRead"},
    "environment": {"type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [1, 1],
                    "external": true, "final": "ShaderRead"},
    "irradiance":  {"type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [1, 1],
                    "external": true, "final": "ShaderRead"},
    "prefiltered": {"type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [1, 1],
                    "external": true, "final": "ShaderRead"}
  },
  "passes": [
    {"name": "equirect_to_cube", "type": "EquirectToCubemapPass", "params": {"supersample": 2},
     "uses": {"equirect": "Read@Compute", "environment": "Write@Compute"}},
    {"name": "irradiance", "type": "IrradiancePass", "params": {"samples": 256},
     "uses": {"environment": "Read@Compute", "irradiance": "Write@Compute"}},
    {"name": "prefilter", "type": "PrefilterPass", "params": {"samples": 256},
     "uses": {"environment": "Read@Compute", "prefiltered": "Write@Compute"}}
  ]
})";

bool finiteImage(const ImageData& img) {
    for (const float v : img.rgba)
        if (!std::isfinite(v)) return false;
    return true;
}

/// Angle between the GPU's ray and the double reference at pixel (x, y) in pixels (the
/// angle over the angular size of a pixel at the image centre), as far_camera_test.cpp.
double rayErrorPx(const ImageData& rays, const SceneCamera& cam, uint32_t x, uint32_t y) {
    using namespace math;
    const uint32_t w = rays.width, h = rays.height;
    const auto rot = cameraRotation(cam.yawDeg, cam.pitchDeg, cam.rollDeg);
    const glm::dvec3 want =
        glm::normalize(viewRayFromNdc(pixelToNdc<double>(x, y, w, h), rot, cam.fovYDeg, double(w) / h));
    const auto px = rays.pixel(x, y);
    const glm::dvec3 got = glm::normalize(glm::dvec3(px[0], px[1], px[2]));
    const double angle = 2.0 * std::atan2(glm::length(got - want), glm::length(got + want));
    const double pixelAngle = 2.0 * std::tan(radians(cam.fovYDeg) / 2.0) / h;
    return angle / pixelAngle;
}

class Extremes : public ExecutorTest {
protected:
    /// The worst sky-ray error over a 32x24 frame, in pixels; fails on a non-finite ray.
    double worstRayErrorPx(const SceneCamera& camera) {
        const uint32_t w = 32, h = 24;
        Scene s;
        s.environment = SceneEnvironment{};
        s.camera = camera;
        const ImageData rays = renderSkyRays(s, w, h);
        EXPECT_TRUE(finiteImage(rays));
        double worst = 0.0;
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) worst = std::max(worst, rayErrorPx(rays, camera, x, y));
        return worst;
    }

    /// graphs/raster.json for `scene` at w x h; returns `readback` (hdr_color or swapchain).
    ImageData renderRaster(const Scene& scene, uint32_t w, uint32_t h, const std::string& readback = "hdr_color",
                           void (*editGraph)(GraphDesc&) = nullptr, const ImageData* external = nullptr,
                           const std::string& externalName = {}) {
        const PassLibrary library = PassLibrary::withBuiltins();
        GraphDesc graph = loadGraphFile(kSource / "graphs/raster.json", library.registry());
        if (editGraph) editGraph(graph);
        CompileOptions co;
        co.features = sceneFeatures(scene);
        co.presentReplacement = ExternalState::TransferSrc;
        Renderer renderer = rendererAt(graph, library, co, w, h, readback);
        if (external) renderer.setExternalImage(externalName, *external);
        renderer.frameData().set(scene);
        renderer.renderFrame();
        return renderer.readback();
    }
};

// --- camera -------------------------------------------------------------------------------

// The skybox's ray comes from the rotation and the projection's x/y scale only, so the near
// plane must not enter it; the objects' reverse-Z depth keeps every fragment finite.
TEST_F(Extremes, NearPlanesFromOneMillionthToTenKeepRaysExactAndPixelsFinite) {
    Scene scene = loadSceneFile(kSource / "scenes/default.json");
    for (const double near : {1e-6, 1e-3, 1.0, 10.0}) {
        SceneCamera cam = scene.camera;
        cam.near = near;
        const double worst = worstRayErrorPx(cam);
        std::printf("near %.0e: worst sky ray error %.2e px\n", near, worst);
        EXPECT_LT(worst, 1e-3) << "near " << near;
        scene.camera.near = near;
        const ImageData hdr = renderRaster(scene, 32, 24);
        EXPECT_TRUE(finiteImage(hdr)) << "near " << near;
    }
}

// A pixel at fov 0.01 deg spans ~7e-6 rad at 24 rows, about 60 float ulps of a unit vector:
// the ray is still well inside the pixel (measured 1.4e-2 px on lavapipe; 2.2e-4 px at 1 deg,
// <= 3e-6 px from 60 deg up). docs/tradeoffs.md "Extremes" lists every measured bound.
TEST_F(Extremes, FieldsOfViewFromOneHundredthOfADegreeTo179Point9) {
    for (const double fov : {0.01, 1.0, 60.0, 179.0, 179.9}) {
        SceneCamera cam;
        cam.yawDeg = 37.0;
        cam.pitchDeg = -12.0;
        cam.fovYDeg = fov;
        const double worst = worstRayErrorPx(cam);
        std::printf("fov %g deg: worst sky ray error %.2e px\n", fov, worst);
        EXPECT_LT(worst, fov < 1.0 ? 0.05 : 1e-3) << "fov " << fov;
    }
}

TEST_F(Extremes, LookingStraightUpAndDownWithRoll) {
    for (const double pitch : {90.0, -90.0, 89.999, -89.999})
        for (const double roll : {0.0, 45.0, 180.0, -90.0}) {
            SceneCamera cam;
            cam.yawDeg = 123.0;
            cam.pitchDeg = pitch;
            cam.rollDeg = roll;
            cam.fovYDeg = 70.0;
            const double worst = worstRayErrorPx(cam);
            EXPECT_LT(worst, 1e-3) << "pitch " << pitch << ", roll " << roll;
        }
}

// --- tonemapping --------------------------------------------------------------------------

// Every operator at every exposure from -40 to +40 EV on +inf, NaN, -1e4, 65504, 1e38 (and
// ordinary values beside them in the same pixel): finite, in [0, 1], and within one 8-bit
// code of the double reference's tonemap + sRGB encode.
TEST_F(Extremes, HostileHdrInputsAtEveryExposureMatchTheReferenceWithinOneCode) {
    const float hostile[] = {kInf, kNaN, -1e4f, 65504.0f, 1e38f, -kInf, 0.0f, 1e-30f};
    const float ordinary[] = {0.18f, 1.0f};
    ImageData hdr;
    hdr.width = 8;
    hdr.height = 2;
    hdr.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    for (uint32_t y = 0; y < 2; ++y)
        for (const float v : hostile) hdr.rgba.insert(hdr.rgba.end(), {v, ordinary[y], y ? v : 0.5f, 1.0f});

    const PassLibrary library = PassLibrary::withBuiltins();
    const GraphDesc graph = parseGraph(kTonemapGraph, "tonemap_only.json", library.registry());
    CompileOptions co;
    co.readbacks = {"ldr"};
    co.outputWidth = 8;
    co.outputHeight = 2;
    RendererOptions ro;
    ro.passes = &library;
    ro.framesInFlight = 1;
    Renderer renderer(sharedDevice(), CompiledGraph(graph, co), ro);
    renderer.setExternalImage("hdr", hdr);
    const std::pair<Tonemapper, math::ToneOperator> operators[] = {
        {Tonemapper::AcesNarkowicz, math::ToneOperator::AcesNarkowicz},
        {Tonemapper::AcesHill, math::ToneOperator::AcesHill},
        {Tonemapper::KhronosPbrNeutral, math::ToneOperator::KhronosPbrNeutral},
        {Tonemapper::Passthrough, math::ToneOperator::Passthrough}};
    double worstCodes = 0.0;
    for (const auto& [tonemapper, reference] : operators)
        for (const double ev : {-40.0, -20.0, -8.0, 0.0, 8.0, 20.0, 40.0}) {
            Scene s;
            s.exposureEv = ev;
            s.tonemapper = tonemapper;
            renderer.frameData().set(s);
            renderer.renderFrame();
            const ImageData out = renderer.readback();
            for (uint32_t y = 0; y < 2; ++y)
                for (uint32_t x = 0; x < 8; ++x) {
                    const auto in = hdr.pixel(x, y);
                    const auto want = math::tonemap(math::Vec3<double>(in[0], in[1], in[2]), ev, reference);
                    for (int c = 0; c < 3; ++c) {
                        const float got = out.pixel(x, y)[c];
                        ASSERT_TRUE(std::isfinite(got)) << "op " << int(tonemapper) << " ev " << ev << " in " << in[c];
                        ASSERT_GE(got, 0.0f);
                        ASSERT_LE(got, 1.0f);
                        const double codes = std::abs(got - math::srgbEncode(want[c])) * 255.0;
                        worstCodes = std::max(worstCodes, codes);
                        EXPECT_LE(codes, 1.0) << "op " << int(tonemapper) << " ev " << ev << " in " << in[c];
                    }
                }
        }
    std::printf("hostile HDR inputs: worst %.3f 8-bit codes from the reference\n", worstCodes);
}

// --- output extents -----------------------------------------------------------------------

TEST_F(Extremes, OneByOneOutputRendersTheSceneFinite) {
    const Scene scene = loadSceneFile(kSource / "scenes/default.json");
    const ImageData hdr = renderRaster(scene, 1, 1);
    ASSERT_EQ(hdr.width, 1u);
    EXPECT_TRUE(finiteImage(hdr));
    const ImageData ldr = renderRaster(scene, 1, 1, "");
    ASSERT_EQ(ldr.width, 1u);
}

// The largest 2D extent the device allows is maxImageDimension2D along one axis: rendered
// as max x 1 and 1 x max (a max x max frame is 4 GiB of targets and minutes on lavapipe).
// One texel more is refused before anything is allocated, naming the resource and limit.
TEST_F(Extremes, LargestDimensionRendersAndOneMoreIsRefusedByName) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(sharedDevice().physicalDevice(), &props);
    const uint32_t most = props.limits.maxImageDimension2D;
    const Scene scene = loadSceneFile(kSource / "scenes/default.json");
    for (const auto& [w, h] : {std::pair{most, 1u}, std::pair{1u, most}}) {
        const ImageData hdr = renderRaster(scene, w, h);
        ASSERT_EQ(hdr.width, w);
        ASSERT_EQ(hdr.height, h);
        EXPECT_TRUE(finiteImage(hdr)) << w << "x" << h;
    }
    // One more: past a device limit below the format's 16384, the executor names the image;
    // past 16384 (lavapipe's limit is that), the compile refuses the output extent itself.
    try {
        (void)renderRaster(scene, most + 1, 1);
        FAIL() << "an output of " << most + 1 << "x1 was accepted";
    } catch (const DeviceCapacityError& e) {
        const std::string what = e.what();
        EXPECT_LT(most, 16384u) << what;
        EXPECT_NE(what.find("maxImageDimension2D"), std::string::npos) << what;
        EXPECT_NE(what.find("nothing was allocated"), std::string::npos) << what;
        EXPECT_NE(what.find("'depth'"), std::string::npos) << what;
    } catch (const GraphError& e) {
        const std::string what = e.what();
        EXPECT_GE(most, 16384u) << what;
        EXPECT_NE(what.find("the output extent " + std::to_string(most + 1) + "x1 is past 16384 a side"),
                  std::string::npos)
            << what;
    }
}

// --- environments at their smallest -------------------------------------------------------

// A 2x1 equirect map: the skybox's direct sampling at the poles and the seam. A constant
// map must come out constant (fp16 target: 1e-3 relative); two texels must stay between
// them (no wrap, pole or NaN artefact).
TEST_F(Extremes, EquirectOfTwoByOneTexelsThroughTheSkybox) {
    for (const bool twoColours : {false, true}) {
        ImageData map = constantImage(2, 1, {0.25f, 0.5f, 2.0f});
        if (twoColours) {
            map.rgba[4] = 4.0f;
            map.rgba[5] = 0.125f;
            map.rgba[6] = 0.0f;
        }
        struct View { double yaw, pitch; };
        for (const View v : {View{0, 90}, View{0, -90}, View{180, 0}, View{90, 0}, View{45, 30}}) {
            Scene s;
            s.environment = SceneEnvironment{false, "unused.hdr", 0.0, EnvironmentSampling::Equirect};
            s.camera.yawDeg = v.yaw;
            s.camera.pitchDeg = v.pitch;
            s.camera.fovYDeg = 90.0;
            const ImageData hdr = renderRaster(s, 16, 12, "hdr_color", nullptr, &map, "equirect");
            ASSERT_TRUE(finiteImage(hdr));
            for (uint32_t y = 0; y < hdr.height; ++y)
                for (uint32_t x = 0; x < hdr.width; ++x)
                    for (int c = 0; c < 3; ++c) {
                        const float got = hdr.pixel(x, y)[c];
                        const float a = map.rgba[c], b = map.rgba[4 + c];
                        const float lo = std::min(a, b), hi = std::max(a, b);
                        EXPECT_GE(got, lo * (1 - 1e-3f)) << "yaw " << v.yaw << " pitch " << v.pitch;
                        EXPECT_LE(got, hi * (1 + 1e-3f)) << "yaw " << v.yaw << " pitch " << v.pitch;
                    }
        }
    }
}

void useOneByOneEnvironmentCube(GraphDesc& g) {
    for (auto& r : g.resources)
        if (r.name == "environment") {
            r.extent = Extent{false, 1, 1, 1};
            r.mips = 1;
        }
}

// A cube of 1x1 faces sampled by the skybox: every face holds the constant, so every ray
// must return it (no seam-filtering or LOD artefact at the smallest cube).
TEST_F(Extremes, CubeOfOneByOneFacesThroughTheSkybox) {
    const glm::vec3 c{0.75f, 1.5f, 3.0f};
    const ImageData face = constantImage(1, 1, c);
    Scene s;
    s.environment = SceneEnvironment{false, "unused.hdr", 0.0, EnvironmentSampling::Cubemap};
    s.camera.pitchDeg = 45.0;
    s.camera.yawDeg = 45.0;
    s.camera.fovYDeg = 120.0;
    const ImageData hdr = renderRaster(s, 16, 12, "hdr_color", useOneByOneEnvironmentCube, &face, "environment");
    ASSERT_TRUE(finiteImage(hdr));
    for (uint32_t y = 0; y < hdr.height; ++y)
        for (uint32_t x = 0; x < hdr.width; ++x)
            for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(hdr.pixel(x, y)[ch], c[ch], c[ch] * 1e-3) << x << "," << y;
}

// The environment passes at their smallest: a constant 2x1 equirect becomes a constant cube
// of 1x1 faces, and the irradiance and GGX prefilter of a constant are that constant
// (half-float storage: 2e-3 relative). Two different texels give finite values between them.
TEST_F(Extremes, TwoByOneEquirectIntoOneByOneCubesThroughTheEnvironmentPasses) {
    const PassLibrary library = PassLibrary::withBuiltins();
    const GraphDesc graph = parseGraph(kTinyIblGraph, "tiny_ibl.json", library.registry());
    CompileOptions co;
    co.presentReplacement = ExternalState::TransferSrc;
    co.outputWidth = co.outputHeight = 16;
    RendererOptions ro;
    ro.passes = &library;
    ro.framesInFlight = 1;
    Renderer renderer(sharedDevice(), CompiledGraph(graph, co), ro);
    for (const bool twoColours : {false, true}) {
        ImageData map = constantImage(2, 1, {0.5f, 1.0f, 8.0f});
        if (twoColours) map.rgba[4] = 2.0f;  // red: 2 in one half of the sphere, 0.5 in the other
        renderer.setExternalImage("equirect", map);
        renderer.renderFrame();
        for (const char* product : {"environment", "irradiance", "prefiltered"}) {
            const std::vector<ImageData> faces = renderer.readImage(product);
            ASSERT_EQ(faces.size(), 6u) << product;
            for (size_t f = 0; f < 6; ++f) {
                ASSERT_EQ(faces[f].width, 1u);
                ASSERT_TRUE(finiteImage(faces[f])) << product << " face " << f;
                const auto px = faces[f].pixel(0, 0);
                for (int ch = 0; ch < 3; ++ch) {
                    const float a = map.rgba[ch], b = map.rgba[4 + ch];
                    if (!twoColours) {
                        EXPECT_NEAR(px[ch], a, a * 2e-3) << product << " face " << f << " channel " << ch;
                    } else {
                        EXPECT_GE(px[ch], std::min(a, b) * (1 - 2e-3f)) << product << " face " << f;
                        EXPECT_LE(px[ch], std::max(a, b) * (1 + 2e-3f)) << product << " face " << f;
                    }
                }
            }
        }
    }
}

}  // namespace
}  // namespace skygraph::test
