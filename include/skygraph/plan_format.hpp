// Printing plans: JSON (docs/graph-format.md, "Compiled plan"), a readable text listing, and
// graphviz DOT.
#pragma once

#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

#include <nlohmann/json.hpp>

#include <string>

namespace skygraph {

[[nodiscard]] nlohmann::ordered_json planToJson(const Plan& plan);
[[nodiscard]] std::string planToText(const Plan& plan);
/// Scheduled passes as boxes, culled ones greyed with their reason, resources as ellipses;
/// with `setup` (planSetup of `plan`), its steps in a box of their own.
[[nodiscard]] std::string planToDot(const Plan& plan, const GraphDesc& graph, const Plan* setup = nullptr);

/// Full Vulkan names: "VK_PIPELINE_STAGE_2_COPY_BIT", one entry per set bit.
[[nodiscard]] std::vector<std::string> stageMaskNames(VkPipelineStageFlags2 mask);
[[nodiscard]] std::vector<std::string> accessMaskNames(VkAccessFlags2 mask);
[[nodiscard]] std::string layoutName(VkImageLayout layout);

}  // namespace skygraph
