// `skygraph check GRAPH...`: every feature combination of each graph compiled, compared with its
// reviewed golden plan, verified by the plan verifier and run under validation; a table, and
// JUnit XML for CI. Exit 0 only when every case passes.
#pragma once

#include "cli_common.hpp"

namespace skygraph::cli {

/// Adds the `check` subcommand to `parent` (which owns it).
[[nodiscard]] Command addCheckCommand(CLI::App& parent);

}  // namespace skygraph::cli
