// The scene's camera in the form the passes push to shaders. Everything is computed in double
// and only then rounded, so that a camera far from the origin loses nothing it need not.
#pragma once

#include <skygraph/scene.hpp>
#include <skygraph/shading_math.hpp>

#include <vulkan/vulkan_core.h>

namespace skygraph::passes {

struct CameraView {
    math::Mat3<double> cameraToWorld;
    math::Vec3<double> position;
    double fovYDeg = 60.0;
    double nearPlane = 0.1;
    double aspect = 1.0;
};

inline CameraView cameraView(const Scene* scene, VkExtent2D area) {
    const SceneCamera camera = scene ? scene->camera : SceneCamera{};
    CameraView v;
    v.cameraToWorld = math::cameraRotation(camera.yawDeg, camera.pitchDeg, camera.rollDeg);
    v.position = {camera.position[0], camera.position[1], camera.position[2]};
    v.fovYDeg = camera.fovYDeg;
    v.nearPlane = camera.near;
    v.aspect = double(area.width) / double(std::max(1u, area.height));
    return v;
}

}  // namespace skygraph::passes
