// What TonemappingComputePass can write, checked when a graph loads (tonemapping_type.cpp) and
// when its pipeline is made (tonemapping_pass.cpp).
#pragma once

#include "../format_names.hpp"

#include <vulkan/vulkan_core.h>

#include <algorithm>
#include <array>
#include <string>
#include <string_view>

namespace skygraph::passes {

/// Storage images cannot be sRGB, so the shader encodes sRGB itself and writes one of these.
/// B8G8R8A8_UNORM (the storage format surfaces offer) has no GLSL format qualifier: the device
/// must write it without one.
inline constexpr std::array kTonemappingComputeOutputs{VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_UNORM,
                                                       VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT};

/// "R8G8B8A8_UNORM, ... or R32G32B32A32_SFLOAT": the formats above by their graph-file names.
[[nodiscard]] inline std::string tonemappingComputeOutputNames() {
    return formatNames(kTonemappingComputeOutputs);
}

/// Why TonemappingComputePass cannot write `format`, a name from the format table.
[[nodiscard]] inline std::string tonemappingComputeOutputProblem(std::string_view format) {
    return "TonemappingComputePass writes " + tonemappingComputeOutputNames() +
           " storage images (it encodes sRGB itself), not " + std::string(format);
}

[[nodiscard]] inline bool tonemappingComputeWrites(VkFormat format) {
    return std::find(kTonemappingComputeOutputs.begin(), kTonemappingComputeOutputs.end(), format) !=
           kTonemappingComputeOutputs.end();
}

}  // namespace skygraph::passes
