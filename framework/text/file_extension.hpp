// Files are told apart by extension in any case (".HDR" is a Radiance file, "x.KTX2" a KTX2
// output), as file managers and image tools do. Header-only, for the libraries and the tool;
// not installed.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace skygraph {

/// `text` in lower case ASCII.
[[nodiscard]] inline std::string lowercaseAscii(std::string text) {
    for (char& c : text)
        if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    return text;
}

/// The extension of `path` with its dot, in lower case ASCII: ".hdr" for "sky.HDR", "" for none.
[[nodiscard]] inline std::string lowercaseExtension(const std::filesystem::path& path) {
    return lowercaseAscii(path.extension().string());
}

/// Whether the file name of `path` is nothing but `extension` (".ktx2"; in any case), as in
/// `-o .ktx2`. std::filesystem reads such a name as a stem without an extension, so a check of
/// the extension alone would report the very extension the name shows as missing.
[[nodiscard]] inline bool fileNameIsOnlyExtension(const std::filesystem::path& path, std::string_view extension) {
    return lowercaseAscii(path.filename().string()) == extension;
}

}  // namespace skygraph
