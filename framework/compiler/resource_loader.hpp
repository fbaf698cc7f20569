// One entry of a graph file's `resources`: its type, format, extent, mips, layers or size,
// clear value and external states, each checked.
#pragma once

#include "graph_file.hpp"

#include <skygraph/graph.hpp>

#include <string_view>

namespace skygraph {

/// Resource `name` from its entry `v` into `r` (default-constructed), reporting each problem
/// to `report`; what is wrong keeps its default.
void loadResource(std::string_view name, JsonValue v, FileProblems& report, ResourceDesc& r);

}  // namespace skygraph
