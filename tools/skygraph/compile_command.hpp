// `skygraph compile GRAPH`: print the plan (text, JSON or graphviz DOT) and, with --memory-svg,
// draw its memory layout; or with --watch keep recompiling on every save and print how the plan
// changed.
#pragma once

#include "cli_common.hpp"

namespace skygraph::cli {

/// Adds the `compile` subcommand to `parent` (which owns it).
[[nodiscard]] Command addCompileCommand(CLI::App& parent);

}  // namespace skygraph::cli
