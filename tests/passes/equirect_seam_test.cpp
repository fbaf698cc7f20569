// Direct equirect sampling at the seam (u = 0/1, behind the default view) and at the poles:
// the skybox's image must follow the environment's function of direction there as everywhere,
// with no line or pinch. The environment is a smooth function of direction, so the truth is
// known at every pixel; the HDR target (fp16) is read back and compared.
#include "analytic_environment.hpp"
#include "pass_test_util.hpp"

#include <skygraph/pass.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/shading_math.hpp>

#include <cmath>
#include <cstdio>

namespace skygraph::test {
namespace {

const std::filesystem::path kSource = SKYGRAPH_SOURCE_DIR;

/// The environment: smooth and different along every axis, positive.
glm::dvec3 field(const glm::dvec3& d) { return 0.5 * (d + 1.0) + glm::dvec3(0.1); }

class EquirectSampling : public ExecutorTest {};

TEST_F(EquirectSampling, SeamAndPolesFollowTheEnvironment) {
    const PassLibrary library = PassLibrary::withBuiltins();
    GraphDesc graph = loadGraphFile(kSource / "graphs/raster.json", library.registry());
    const uint32_t mapW = 256, mapH = 128, w = 64, h = 48;
    for (auto& r : graph.resources)
        if (r.name == "equirect") r.extent = Extent{false, 1, mapW, mapH};
    CompileOptions co;
    co.features = {{"geometry", false}, {"environment_file", true}, {"sample_cubemap", false}};
    Renderer renderer = rendererAt(graph, library, co, w, h, "hdr_color");
    renderer.setExternalImage("equirect", equirectImage(field, mapW, mapH));
    // Bilinear filtering of a 256 x 128 map misses a smooth field by at most ~(pi/128)^2/8 of
    // its curvature, and fp16 stores ~1e-3 relative: 4e-3 covers both; a seam line of the
    // wrong texels or a pole pinch misses by > 0.05.
    const double tolerance = 4e-3;
    struct View { double yaw, pitch; const char* what; };
    for (const View v : {View{180.0, 0.0, "seam"}, View{180.0, 89.0, "north pole"}, View{0.0, -89.0, "south pole"},
                         View{90.0, 45.0, "oblique"}}) {
        Scene s;
        s.environment = SceneEnvironment{false, "unused.hdr", 0.0, EnvironmentSampling::Equirect};
        s.camera.yawDeg = v.yaw;
        s.camera.pitchDeg = v.pitch;
        s.camera.fovYDeg = 90.0;
        renderer.frameData().set(s);
        renderer.renderFrame();
        const ImageData img = renderer.readback();
        const auto rot = math::cameraRotation(v.yaw, v.pitch, 0.0);
        double worst = 0.0;
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                const auto d = glm::normalize(
                    math::viewRayFromNdc(math::pixelToNdc<double>(x, y, w, h), rot, 90.0, double(w) / h));
                const auto want = field(d);
                for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(img.pixel(x, y)[c] - want[c]));
            }
        std::printf("%s: worst %.2e\n", v.what, worst);
        EXPECT_LT(worst, tolerance) << v.what;
    }
}

}  // namespace
}  // namespace skygraph::test
