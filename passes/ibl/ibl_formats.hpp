// What the environment pipeline's shaders write, checked when a graph loads
// (environment_types.cpp; the renderer runs the same check on a graph built in code) and, for
// the format, when a pipeline is made (ibl_compute.cpp, which picks the GLSL format qualifier).
#pragma once

#include "../format_names.hpp"

#include <skygraph/graph.hpp>
#include <skygraph/pass_registry.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
#include <optional>
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

/// Why pass type `type` cannot write `range` (nullopt: the whole resource) of `target` through
/// its storage slot `slot`, or nothing. Its storage view is the usage's first mip level alone,
/// so a usage of more would leave the others undefined while the plan calls them written.
/// `repeated`: the slot takes one usage per level (PrefilterPass), else one usage in all.
[[nodiscard]] inline std::optional<std::string> iblStorageMipProblem(std::string_view type, std::string_view slot,
                                                                     bool repeated, const ResourceDesc& target,
                                                                     const std::optional<SubresourceRange>& range) {
    std::string covered;
    if (range) {
        if (range->mipCount == 1) return std::nullopt;
        covered = "mips [" + std::to_string(range->baseMip) + ", " + std::to_string(range->mipCount) + "]";
    } else {
        // Without an output size the length is known unless it is a full chain of the output's.
        const bool chainOfOutput = target.mips == 0 && target.extent.relativeToOutput;
        if (!chainOfOutput && target.mipCount(1, 1) == 1) return std::nullopt;
        covered = target.mips == 0 ? "its whole mip chain (\"mips\": \"full\")"
                                   : "all " + std::to_string(target.mips) + " of its mips";
    }
    return std::string(type) + " writes one mip per usage of slot '" + std::string(slot) + "': the usage of '" +
           target.name + "' covers " + covered + "; " +
           (repeated ? "give one usage per mip (\"mips\": [m, 1])" : "name one mip (\"mips\": [m, 1])");
}

/// A usage validator for the pass type `type`'s storage slot `slot`: refuses a format the shaders
/// cannot write and a usage of more than one mip level (iblStorageMipProblem).
[[nodiscard]] inline UsageValidator iblStorageCheck(std::string type, std::string slot, bool repeated = false) {
    return [type = std::move(type), slot = std::move(slot), repeated](const PassDesc& pass, const GraphDesc& graph) {
        std::vector<UsageError> problems;
        for (size_t i = 0; i < pass.uses.size(); ++i) {
            if (graph.slotName(pass.uses[i].slot) != slot) continue;
            const ResourceDesc& r = graph.resources[pass.uses[i].resource];
            if (!iblStorageQualifier(r.format.format)) problems.push_back({i, iblStorageProblem(type, r.format.name)});
            if (auto problem = iblStorageMipProblem(type, slot, repeated, r, pass.uses[i].usage.range))
                problems.push_back({i, std::move(*problem)});
        }
        return problems;
    };
}

}  // namespace skygraph::passes
