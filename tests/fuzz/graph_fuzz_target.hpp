// One fuzz input through parseGraph + compile + the plan printers (graph_fuzz_target.cpp).
#pragma once

#include <string_view>

namespace skygraph::fuzz {

/// Loads `text` as a graph file and, if it loads, compiles it with several option sets.
/// Returns normally on a plan or a GraphError with diagnostics; aborts on anything else, so
/// that libFuzzer and the replay test both see the failure.
void runOneInput(std::string_view text);

}  // namespace skygraph::fuzz
