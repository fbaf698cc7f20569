// The names of the files the commands write, checked before any work.
#pragma once

#include "printable_name.hpp"

#include <filesystem>
#include <string>
#include <string_view>

namespace skygraph::app {

/// Whether the file name of `path` is nothing but `extension` (".ktx2"; the name in any case), as
/// in `-o .ktx2`. std::filesystem reads such a name as a stem without an extension, so a check of
/// the extension alone would report the very extension the name shows as missing.
[[nodiscard]] inline bool fileNameIsOnlyExtension(const std::filesystem::path& path, std::string_view extension) {
    std::string name = path.filename().string();
    for (char& c : name)
        if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    return name == extension;
}

/// What is wrong with such an output `path`, given as `option`: "-o '.ktx2': the file name has
/// no stem, only an extension (e.g. sky.ktx2)", the example `exampleStem` before the name.
[[nodiscard]] inline std::string noStemMessage(std::string_view option, const std::filesystem::path& path,
                                               std::string_view exampleStem) {
    return std::string(option) + " '" + printableName(path.string()) +
           "': the file name has no stem, only an extension (e.g. " +
           printableName(std::string(exampleStem) + path.filename().string()) + ")";
}

}  // namespace skygraph::app
