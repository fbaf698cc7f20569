// `skygraph sky-sequence PATTERN`: writes a time-lapse of the procedural sky, the content
// environment sequences are tested and measured with (docs/scenes.md, "Sequences").
#pragma once

#include "cli_common.hpp"

namespace skygraph::cli {

/// Adds the `sky-sequence` subcommand to `parent` (which owns it).
[[nodiscard]] Command addSkySequenceCommand(CLI::App& parent);

}  // namespace skygraph::cli
