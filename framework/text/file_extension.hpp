// Files are told apart by extension in any case (".HDR" is a Radiance file, "x.KTX2" a KTX2
// output), as file managers and image tools do. Header-only, for the libraries and the tool;
// not installed.
#pragma once

#include <filesystem>
#include <string>

namespace skygraph {

/// The extension of `path` with its dot, in lower case ASCII: ".hdr" for "sky.HDR", "" for none.
[[nodiscard]] inline std::string lowercaseExtension(const std::filesystem::path& path) {
    std::string extension = path.extension().string();
    for (char& c : extension)
        if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    return extension;
}

}  // namespace skygraph
