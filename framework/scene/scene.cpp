// What a loaded scene means for the frame: graph features, the tonemapper, names.
#include <skygraph/scene.hpp>

#include "printable_name.hpp"
#include "shipped_names.hpp"

#include <cmath>
#include <numbers>

namespace skygraph {

FeatureValues sceneFeatures(const Scene& scene) {
    const bool file = scene.environment && !scene.environment->procedural;
    using namespace shipped;
    return {{std::string(kGeometryFeature), !scene.objects.empty()},
            {std::string(kSkyboxFeature), scene.environment.has_value()},
            {std::string(kEnvironmentFileFeature), file},
            // The procedural sky is evaluated per pixel; only a file is sampled either way.
            {std::string(kSampleCubemapFeature),
             file && scene.environment->sampling == EnvironmentSampling::Cubemap},
            // A sequence of one frame is a still.
            {std::string(kEnvironmentSequenceFeature),
             file && scene.environment->sequence && scene.environment->sequence->count > 1}};
}

std::vector<std::string> explainSceneFeatures(const Scene& scene) {
    using namespace shipped;
    const std::string geometry(kGeometryFeature), skybox(kSkyboxFeature);
    const std::string environmentFile(kEnvironmentFileFeature), sampleCubemap(kSampleCubemapFeature);
    std::vector<std::string> lines;
    const size_t n = scene.objects.size();
    lines.push_back(n ? geometry + " = on: the scene has " + std::to_string(n) + (n == 1 ? " object" : " objects")
                      : geometry + " = off: the scene has no objects (no forward pass, no depth)");
    if (!scene.environment)
        lines.push_back(skybox + " = off: the scene has no environment (no skybox, no IBL)");
    else if (scene.environment->procedural)
        lines.push_back(skybox + " = on, " + environmentFile + " = off, " + sampleCubemap +
                        " = off: environment is the procedural sky, evaluated per pixel");
    else
        lines.push_back(skybox + " = on, " + environmentFile + " = on: environment is '" +
                        printableName(scene.environment->file.string()) + "', sampled " +
                        (scene.environment->sampling == EnvironmentSampling::Cubemap
                             ? "through a cubemap (" + sampleCubemap + " = on)"
                             : "directly as equirect (" + sampleCubemap + " = off)"));
    if (scene.environment && scene.environment->sequence && scene.environment->sequence->count > 1)
        lines.push_back(std::string(kEnvironmentSequenceFeature) + " = on: the environment is a sequence of " +
                        std::to_string(scene.environment->sequence->count) + " frames at " +
                        std::to_string(scene.environment->sequence->fps) + " fps, '" +
                        printableName(scene.environment->sequence->pattern) + "'");
    return lines;
}

Tonemapper effectiveTonemapper(const Scene& scene) noexcept {
    return scene.debugView != DebugView::None ? Tonemapper::Passthrough : scene.tonemapper;
}

std::string_view toString(Tonemapper t) noexcept {
    switch (t) {
        case Tonemapper::AcesNarkowicz: return "aces_narkowicz";
        case Tonemapper::AcesHill: return "aces_hill";
        case Tonemapper::KhronosPbrNeutral: return "khronos_pbr_neutral";
        case Tonemapper::Passthrough: return "passthrough";
    }
    return "?";
}

std::string_view toString(DebugView v) noexcept {
    switch (v) {
        case DebugView::None: return "none";
        case DebugView::Normal: return "normal";
        case DebugView::Metallic: return "metallic";
        case DebugView::Roughness: return "roughness";
        case DebugView::Ao: return "ao";
    }
    return "?";
}

std::string_view toString(EnvironmentSampling s) noexcept {
    return s == EnvironmentSampling::Equirect ? "equirect" : "cubemap";
}

Vec3 cameraForward(const SceneCamera& camera) noexcept {
    const double yaw = camera.yawDeg * std::numbers::pi / 180.0;
    const double pitch = camera.pitchDeg * std::numbers::pi / 180.0;
    return {-std::sin(yaw) * std::cos(pitch), std::sin(pitch), -std::cos(yaw) * std::cos(pitch)};
}

}  // namespace skygraph
