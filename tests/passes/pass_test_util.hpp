// Renders for the pass tests (tests/passes, tests/extremes): a graph's renderer at a size,
// the shipped raster frame of a scene, and the skybox's world-space view ray, on the shared
// validated device; and the constant image those tests feed as an environment.
#pragma once

#include "executor_test_util.hpp"

#include <skygraph/pass.hpp>
#include <skygraph/scene.hpp>

#include <glm/vec3.hpp>

namespace skygraph::test {

/// A renderer of `graph` at width x height on the shared device, reading back `readback`
/// (empty: the Present target, headless); it keeps a pointer to `library`, which must
/// outlive it.
inline Renderer rendererAt(const GraphDesc& graph, const PassLibrary& library, CompileOptions co, uint32_t width,
                           uint32_t height, const std::string& readback = {}) {
    co.outputWidth = width;
    co.outputHeight = height;
    if (readback.empty()) {
        co = headless(graph, std::move(co));
    } else {
        co.readbacks = {readback};
        co.presentReplacement = ExternalState::ShaderRead;  // headless: nothing presents
    }
    RendererOptions ro;
    ro.passes = &library;
    return Renderer(sharedDevice(), CompiledGraph(graph, std::move(co)), ro);
}

/// A w x h fp32 image of `c` everywhere (alpha 1): as an equirect, an environment of one
/// radiance in every direction.
inline ImageData constantImage(uint32_t w, uint32_t h, glm::vec3 c) {
    ImageData img;
    img.width = w;
    img.height = h;
    img.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    for (uint32_t i = 0; i < w * h; ++i) img.rgba.insert(img.rgba.end(), {c.r, c.g, c.b, 1.0f});
    return img;
}

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
    Renderer renderer = rendererAt(graph, library, co, width, height);
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
    Renderer renderer = rendererAt(graph, library, {}, width, height, "ray");
    renderer.frameData().set(scene);
    renderer.renderFrame();
    return renderer.readback();
}

}  // namespace skygraph::test
