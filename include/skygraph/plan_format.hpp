// Printing plans: JSON (docs/graph-format.md, "Compiled plan"), a readable text listing, and
// graphviz DOT. Every function returns a new value the caller owns (no views into the plan)
// and reads its arguments during the call only.
#pragma once

#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

#include <nlohmann/json.hpp>

#include <string>

namespace skygraph {

[[nodiscard]] nlohmann::ordered_json planToJson(const Plan& plan);
[[nodiscard]] std::string planToText(const Plan& plan);
/// Scheduled passes as boxes, culled ones greyed with their reason, resources as ellipses;
/// with `setup` (planSetup of `plan`; may be null), its steps in a box of their own. `graph`
/// must be the graph `plan` was compiled from. The memory layout (Plan::memory()) is a box per
/// heap listing its placements in offset order, and a dashed "memory" edge from each resource
/// to the one that takes over its memory.
[[nodiscard]] std::string planToDot(const Plan& plan, const GraphDesc& graph, const Plan* setup = nullptr);
/// The memory layout as an SVG picture (UTF-8 XML): plan steps across, one column per pass;
/// byte offsets down, the heaps stacked with their sizes; one rectangle per placement over its
/// resource's lifetime (class "placement", coloured by the kind of resource, its name and size
/// written in when they fit, all of it in a tooltip); a dashed line at the peak live bytes; a
/// title with the heaps' bytes, the unaliased bytes and the peak. The same plan always gives the
/// same text.
[[nodiscard]] std::string planMemoryToSvg(const Plan& plan);

/// Full Vulkan names: "VK_PIPELINE_STAGE_2_COPY_BIT", one entry per set bit (in hex for bits
/// skygraph does not name).
[[nodiscard]] std::vector<std::string> stageMaskNames(VkPipelineStageFlags2 mask);
[[nodiscard]] std::vector<std::string> accessMaskNames(VkAccessFlags2 mask);
[[nodiscard]] std::string layoutName(VkImageLayout layout);

}  // namespace skygraph
