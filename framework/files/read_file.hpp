// Reading a whole file: the shader sources, the SPIR-V cache's entries and the files hot
// reload and `--watch` compare.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace skygraph::files {

/// The whole contents of `path`; nothing when it is not a regular file (never a FIFO, whose
/// read could block) or cannot be read.
[[nodiscard]] std::optional<std::string> readFile(const std::filesystem::path& path);

}  // namespace skygraph::files
