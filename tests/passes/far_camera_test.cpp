// The camera far from the origin (docs/conventions.md): the skybox's view ray comes from the
// rotation alone and the forward pass draws camera-relative, so nothing depends on the
// distance. Checked on lavapipe under synchronization validation against the double-precision
// reference.
#include "pass_test_util.hpp"

#include <skygraph/pass.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/shading_math.hpp>

#include <cmath>
#include <cstdio>

namespace skygraph::test {
namespace {

const std::filesystem::path kSource = SKYGRAPH_SOURCE_DIR;

class FarCamera : public ExecutorTest {};

/// Angle between the GPU's ray and the double reference at pixel (x, y), in pixels: the
/// angle over the angular size of a pixel at the image centre (the largest a pixel gets).
double rayErrorPx(const ImageData& rays, const Scene& s, uint32_t x, uint32_t y) {
    using namespace math;
    const uint32_t w = rays.width, h = rays.height;
    const auto rot = cameraRotation(s.camera.yawDeg, s.camera.pitchDeg, s.camera.rollDeg);
    const glm::dvec3 want =
        glm::normalize(viewRayFromNdc(pixelToNdc<double>(x, y, w, h), rot, s.camera.fovYDeg, double(w) / h));
    const auto px = rays.pixel(x, y);
    const glm::dvec3 got = glm::normalize(glm::dvec3(px[0], px[1], px[2]));
    const double angle = 2.0 * std::atan2(glm::length(got - want), glm::length(got + want));  // stable for tiny angles
    const double pixelAngle = 2.0 * std::tan(radians(s.camera.fovYDeg) / 2.0) / h;
    return angle / pixelAngle;
}

TEST_F(FarCamera, SkyRayWithinOneThousandthOfAPixelAtEveryDistance) {
    for (const double distance : {0.0, 1e3, 1e7}) {
        for (const double roll : {0.0, 30.0}) {
            Scene s;
            s.environment = SceneEnvironment{};
            s.camera.position = {distance, distance * 0.5, -distance};
            s.camera.near = 1e-5;
            s.camera.yawDeg = 37.0;
            s.camera.pitchDeg = -12.0;
            s.camera.rollDeg = roll;
            s.camera.fovYDeg = 60.0;
            const ImageData rays = renderSkyRays(s, 64, 48);
            double worst = 0.0;
            for (uint32_t y = 0; y < rays.height; ++y)
                for (uint32_t x = 0; x < rays.width; ++x) worst = std::max(worst, rayErrorPx(rays, s, x, y));
            std::printf("camera at %.0e, roll %.0f: worst ray error %.2e px\n", distance, roll, worst);
            EXPECT_LT(worst, 1e-3) << "distance " << distance << ", roll " << roll;
        }
    }
}

// That the bound can fail: tests/math's Camera.RotationOnlyRaysStayExactFarFromTheOrigin...
// measures the near-point unprojection in float at 1e7 at thousands of pixels off, against the
// same reference.

TEST_F(FarCamera, ObjectsRenderTheSameTenMillionUnitsAway) {
    Scene near = loadSceneFile(kSource / "scenes/default.json");
    near.camera.near = 1e-5;
    Scene far = near;
    const double offset = 1e7;
    for (double& c : far.camera.position) c += offset;
    for (SceneObject& o : far.objects) {
        if (auto* sphere = std::get_if<Sphere>(&o.shape)) {
            for (double& c : sphere->center) c += offset;
        } else {
            for (double& c : std::get<Plane>(o.shape).point) c += offset;
        }
    }
    const ImageData a = renderRasterFrame(near, 64, 48);
    const ImageData b = renderRasterFrame(far, 64, 48);
    int worst = 0;
    for (uint32_t y = 0; y < 48; ++y)
        for (uint32_t x = 0; x < 64; ++x)
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, int(std::lround(std::abs(a.pixel(x, y)[c] - b.pixel(x, y)[c]) * 255.0)));
    EXPECT_LE(worst, 1) << "8-bit codes between the scene at the origin and 1e7 away";
}

}  // namespace
}  // namespace skygraph::test
