// What UploadPass can fill, checked when a graph loads (upload_type.cpp) and again when a pass
// is created from a graph built in code (upload_pass.cpp).
#pragma once

#include <skygraph/graph.hpp>

#include <optional>
#include <string>

namespace skygraph::passes {

/// Why UploadPass cannot write `range` of `target` (nullopt: the whole resource), or nothing.
/// It copies mip 0 of every layer of an image: a usage naming more would leave the rest
/// undefined while the plan calls it written.
[[nodiscard]] inline std::optional<std::string> uploadTargetProblem(const ResourceDesc& target,
                                                                    const std::optional<SubresourceRange>& range) {
    if (!target.isImage()) return std::nullopt;
    const bool covers = range ? range->baseMip == 0 && range->mipCount == 1 && range->baseLayer == 0 &&
                                    range->layerCount == target.layers
                              : target.mips == 1;
    if (covers) return std::nullopt;
    return "UploadPass copies mip 0 of every layer: its usage of '" + target.name +
           "' must cover that and nothing else (\"mips\": [0, 1])";
}

}  // namespace skygraph::passes
