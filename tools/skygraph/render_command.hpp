// `skygraph render [GRAPH]`: compile and render headless, writing the swapchain target (or
// another resource) to .png / .hdr / .exr; a progress bar counts the frames.
#pragma once

#include "cli_common.hpp"

namespace skygraph::cli {

/// Adds the `render` subcommand to `parent` (which owns it).
[[nodiscard]] Command addRenderCommand(CLI::App& parent);

}  // namespace skygraph::cli
