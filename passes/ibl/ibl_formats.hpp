// What the environment pipeline's shaders write, checked when a graph loads
// (environment_types.cpp) and when a pipeline is made (ibl_compute.cpp, which picks the GLSL
// format qualifier).
#pragma once

#include "../format_names.hpp"

#include <skygraph/graph.hpp>
#include <skygraph/pass_registry.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph::passes {

struct IblStorageFormat {
    VkFormat format;
    const char* qualifier;  ///< GLSL's layout qualifier for it
};

/// The float formats the shaders' format qualifiers name (a device may still lack storage
/// support for one: the renderer asks it).
inline constexpr std::array<IblStorageFormat, 4> kIblStorageFormats{{{VK_FORMAT_R16G16B16A16_SFLOAT, "rgba16f"},
                                                                     {VK_FORMAT_R32G32B32A32_SFLOAT, "rgba32f"},
                                                                     {VK_FORMAT_R16G16_SFLOAT, "rg16f"},
                                                                     {VK_FORMAT_R32G32_SFLOAT, "rg32f"}}};

/// The qualifier of `format`, or nullptr when the environment pipeline does not write it.
[[nodiscard]] inline const char* iblStorageQualifier(VkFormat format) noexcept {
    for (const IblStorageFormat& f : kIblStorageFormats)
        if (f.format == format) return f.qualifier;
    return nullptr;
}

/// Why pass type `type` cannot write `format`, a name from the format table.
[[nodiscard]] inline std::string iblStorageProblem(std::string_view type, std::string_view format) {
    std::array<VkFormat, kIblStorageFormats.size()> formats{};
    for (size_t i = 0; i < formats.size(); ++i) formats[i] = kIblStorageFormats[i].format;
    return std::string(type) + " writes " + formatNames(formats) + " storage images, not " + std::string(format);
}

/// A usage validator refusing a format the pass's storage slot `slot` cannot take.
[[nodiscard]] inline UsageValidator iblStorageFormatCheck(std::string type, std::string slot) {
    return [type = std::move(type), slot = std::move(slot)](const PassDesc& pass, const GraphDesc& graph) {
        std::vector<UsageError> problems;
        for (size_t i = 0; i < pass.uses.size(); ++i) {
            const ResourceDesc& r = graph.resources[pass.uses[i].resource];
            if (graph.slotName(pass.uses[i].slot) == slot && !iblStorageQualifier(r.format.format))
                problems.push_back({i, iblStorageProblem(type, r.format.name)});
        }
        return problems;
    };
}

}  // namespace skygraph::passes
