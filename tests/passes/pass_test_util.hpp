// Renders for the pass tests (tests/passes, tests/extremes): the shipped raster frame of a
// scene, and the skybox's world-space view ray, on the shared validated device.
#pragma once

#include "executor_test_util.hpp"

#include <skygraph/pass.hpp>
#include <skygraph/scene.hpp>

namespace skygraph::test {

/// graphs/raster.json for `scene` (its features, then `overrides`), built-in passes, `frames`
/// frames; returns the Present target (the swapchain, B8G8R8A8_SRGB read back as byte / 255).
inline ImageData renderRasterFrame(const Scene& scene, uint32_t width, uint32_t height, int frames = 1,
                                   const FeatureValues& overrides = {}) {
    const PassLibrary library = PassLibrary::withBuiltins();
    const GraphDesc graph =
        loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs/raster.json", library.registry());
    CompileOptions co;
    co.features = sceneFeatures(scene);
    for (const auto& [name, on] : overrides) co.features[name] = on;
    co.presentReplacement = ExternalState::TransferSrc;
    co.outputWidth = width;
    co.outputHeight = height;
    RendererOptions ro;
    ro.width = width;
    ro.height = height;
    ro.passes = &library;
    Renderer renderer(sharedDevice(), graph, compile(graph, co), ro);
    renderer.frameData().set(scene);
    for (int i = 0; i < frames; ++i) renderer.renderFrame();
    return renderer.readback();
}

/// The skybox writing its world-space ray (`output: direction`) into an fp32 target, so the
/// read-back carries the ray at full float precision: one frame of `scene`'s camera.
inline ImageData renderSkyRays(const Scene& scene, uint32_t width, uint32_t height) {
    static constexpr const char* kGraph = R"({
      "version": 1, "name": "sky_direction",
      "resources": {
        "depth": {"type": "image2d", "format": "D32_SFLOAT", "extent": "output", "clear": {"depth": 0.0}},
        "ray":   {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": "output",
                  "clear": {"color": [0, 0, 0, 0]}}
      },
      "passes": [
        {"name": "sky", "type": "SkyboxPass", "params": {"output": "direction"},
         "uses": {"depth": "Read@DepthAttachment", "ray": "ReadWrite@ColorAttachment"}}
      ]
    })";
    const PassLibrary library = PassLibrary::withBuiltins();
    const GraphDesc graph = parseGraph(kGraph, "sky_direction.json", library.registry());
    CompileOptions co;
    co.outputWidth = width;
    co.outputHeight = height;
    co.exports = {{"ray", ExternalState::TransferSrc}};
    RendererOptions ro;
    ro.width = width;
    ro.height = height;
    ro.passes = &library;
    ro.readback = "ray";
    Renderer renderer(sharedDevice(), graph, compile(graph, co), ro);
    renderer.frameData().set(scene);
    renderer.renderFrame();
    return renderer.readback();
}

}  // namespace skygraph::test
