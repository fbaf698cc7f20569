// The names of the files the commands write, checked before any work.
#pragma once

#include "printable_name.hpp"

#include <filesystem>
#include <string>
#include <string_view>

namespace skygraph::app {

/// What is wrong with an output `path` whose name is only an extension (fileNameIsOnlyExtension),
/// given as `option`: "-o '.ktx2': the file name has no stem, only an extension (e.g.
/// sky.ktx2)", the example `exampleStem` before the name.
[[nodiscard]] inline std::string noStemMessage(std::string_view option, const std::filesystem::path& path,
                                               std::string_view exampleStem) {
    return std::string(option) + " '" + printableName(path.string()) +
           "': the file name has no stem, only an extension (e.g. " +
           printableName(std::string(exampleStem) + path.filename().string()) + ")";
}

}  // namespace skygraph::app
