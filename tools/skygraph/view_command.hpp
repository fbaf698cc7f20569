// `skygraph view [GRAPH]`: the frame of `render`, presented in a window until it is closed (or
// for --frames frames), through the executor's swapchain.
#pragma once

#include "cli_common.hpp"

namespace skygraph::cli {

/// Adds the `view` subcommand to `parent` (which owns it).
[[nodiscard]] Command addViewCommand(CLI::App& parent);

}  // namespace skygraph::cli
