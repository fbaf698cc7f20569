// What TonemappingComputePass can write, checked when a graph loads (tonemapping_type.cpp) and
// when its pipeline is made (tonemapping_pass.cpp).
#pragma once

#include <vulkan/vulkan_core.h>

#include <algorithm>
#include <array>

namespace skygraph::passes {

/// Storage images cannot be sRGB, so the shader encodes sRGB itself and writes one of these.
/// B8G8R8A8_UNORM (the storage format surfaces offer) has no GLSL format qualifier: the device
/// must write it without one.
inline constexpr std::array kTonemappingComputeOutputs{VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_UNORM,
                                                       VK_FORMAT_A2B10G10R10_UNORM_PACK32,
                                                       VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT};
inline constexpr const char* kTonemappingComputeOutputNames =
    "R8G8B8A8_UNORM, B8G8R8A8_UNORM, A2B10G10R10_UNORM_PACK32, R16G16B16A16_SFLOAT or R32G32B32A32_SFLOAT";

[[nodiscard]] inline bool tonemappingComputeWrites(VkFormat format) {
    return std::find(kTonemappingComputeOutputs.begin(), kTonemappingComputeOutputs.end(), format) !=
           kTonemappingComputeOutputs.end();
}

}  // namespace skygraph::passes
