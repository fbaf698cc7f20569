// Lists of formats in the built-in pass types' messages.
#pragma once

#include <skygraph/format.hpp>

#include <vulkan/vulkan_core.h>

#include <span>
#include <string>

namespace skygraph::passes {

/// "R8G8B8A8_UNORM, R16G16B16A16_SFLOAT or R32G32B32A32_SFLOAT": `formats` by their
/// graph-file names.
[[nodiscard]] inline std::string formatNames(std::span<const VkFormat> formats) {
    std::string names;
    for (size_t i = 0; i < formats.size(); ++i) {
        names += i == 0 ? "" : i + 1 == formats.size() ? " or " : ", ";
        names += findFormat(formats[i])->name;
    }
    return names;
}

}  // namespace skygraph::passes
