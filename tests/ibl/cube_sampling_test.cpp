// EquirectToCubemapPass against Vulkan's cube map face selection: a known function of
// direction goes into the faces, and a probe shader samples it back with a samplerCube at
// known directions (face centres, edges, corners, near-edge and generic directions). A face
// in the wrong slot or with a flipped axis moves the value by O(1). Lavapipe, validation on.
#include "analytic_environment.hpp"
#include "cube_probe.hpp"
#include "executor_test_util.hpp"

#include <skygraph/pass.hpp>

#include <cstdio>

namespace skygraph::test {
namespace {

/// f(d) = 0.5 + 0.5 d per channel: each channel tells one axis, so any orientation mistake
/// shows in the channel of the flipped axis.
Dir axisColour(const Dir& d) { return Dir(0.5) + 0.5 * d; }

std::vector<Dir> probeDirections() {
    std::vector<Dir> dirs = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},  {0, -1, 0},  {0, 0, 1},    {0, 0, -1},  // centres
                             {1, 1, 0},  {1, 0, -1}, {-1, -1, 0}, {0, 1, -1}, {0, -1, 1},   {-1, 0, 1},  // edges
                             {1, 1, 1},  {-1, 1, -1}, {1, -1, -1}, {-1, -1, 1},                          // corners
                             {1, 0.999, 0.3}, {0.999, 1, -0.3}, {0.2, -0.7, 1},  {-0.9, 0.35, -0.6},
                             {0.05, 0.02, -1}, {0.6, 0.8, 0.01}};
    for (auto& d : dirs) d = glm::normalize(d);
    return dirs;
}

std::string probeGraph(uint32_t probes, uint32_t faceSize, int supersample) {
    char text[2048];
    std::snprintf(text, sizeof text, R"({
  "version": 1, "name": "cube_probe",
  "resources": {
    "equirect": {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": [512, 256],
                 "external": true, "initial": "ShaderRead"},
    "environment": {"type": "cube", "format": "R32G32B32A32_SFLOAT", "extent": [%u, %u],
                    "external": true, "final": "ShaderRead"},
    "probe": {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": [%u, 1],
              "external": true, "final": "TransferSrc"}
  },
  "passes": [
    {"name": "to_cube", "type": "EquirectToCubemapPass", "params": {"supersample": %d},
     "uses": {"equirect": "Read@Compute", "environment": "Write@Compute"}},
    {"name": "probe", "type": "CubeProbe",
     "uses": {"environment": "Read@Compute", "probe": "Write@Compute"}}
  ]
})", faceSize, faceSize, probes, supersample);
    return text;
}

class CubeSampling : public ExecutorTest {};

TEST_F(CubeSampling, FacesFollowVulkanSelectionAtCentresEdgesAndCorners) {
    const std::vector<Dir> dirs = probeDirections();
    PassLibrary library = PassLibrary::withBuiltins();
    library.add(CubeProbe::typeInfo("CubeProbe"), [&](const PassDesc&) { return std::make_unique<CubeProbe>(dirs); });
    const uint32_t size = 64;
    const GraphDesc graph = parseGraph(probeGraph(uint32_t(dirs.size()), size, 4), "<probe>", library.registry());
    CompileOptions co;
    co.presentReplacement = ExternalState::TransferSrc;
    co.readbacks = {"probe"};
    co.outputWidth = co.outputHeight = 16;
    RendererOptions ro;
    ro.passes = &library;
    ro.framesInFlight = 1;
    Renderer renderer(sharedDevice(), CompiledGraph(graph, co), ro);
    renderer.setExternalImage("equirect", equirectImage(axisColour, 512, 256));
    renderer.renderFrame();
    const ImageData probe = renderer.readback();
    for (size_t i = 0; i < dirs.size(); ++i) {
        const Dir want = axisColour(dirs[i]);
        const Dir got = texel(probe, uint32_t(i), 0);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c], want[c], 0.01) << "direction " << i << " (" << dirs[i].x << ", " << dirs[i].y << ", "
                                               << dirs[i].z << ") channel " << c;
    }

    // The faces themselves, texel by texel, against the supersampled mean the pass estimates
    // (layer = Vulkan face index, s right and t down as the selection rules define them).
    const std::vector<ImageData> faces = renderer.readImage("environment");
    ASSERT_EQ(faces.size(), 6u);
    double worst = 0.0;
    for (int face = 0; face < 6; ++face)
        for (uint32_t y = 0; y < size; y += 3)
            for (uint32_t x = 0; x < size; x += 3) {
                const Dir want = math::ibl::cubeTexelMean(axisColour, face, int(x), int(y), int(size), 4);
                const Dir got = texel(faces[size_t(face)], x, y);
                for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(got[c] - want[c]));
            }
    EXPECT_LT(worst, 2e-3) << "largest texel error against the double reference";

    // A new environment into the same renderer (a re-import after frames have run, under
    // synchronization validation) replaces the old one everywhere.
    const auto flipped = [](const Dir& d) { return Dir(0.5) - 0.5 * d; };
    renderer.setExternalImage("equirect", equirectImage(flipped, 512, 256));
    renderer.renderFrame();
    const ImageData again = renderer.readback();
    for (size_t i = 0; i < dirs.size(); ++i)
        EXPECT_NEAR(texel(again, uint32_t(i), 0).x, flipped(dirs[i]).x, 0.01) << "direction " << i;
}

}  // namespace
}  // namespace skygraph::test
