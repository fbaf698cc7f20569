// Messages point at a place in a JSON file by a path: `resources.depth.format`,
// `passes[2].uses.hdr_color`. Keys are names the user chose, and a name such as "gbuffer.normal"
// or "a[0]" would make such a path ambiguous, so those keys are written in brackets, quoted as
// JSON quotes strings: `resources["gbuffer.normal"].format`. Header-only, for the libraries and
// the tool; not installed.
#pragma once

#include <algorithm>
#include <optional>
#include <string>
#include <string_view>

namespace skygraph {

/// Whether `key` can follow a dot in a path and be read back as one key.
[[nodiscard]] constexpr bool isPlainPathKey(std::string_view key) noexcept {
    if (key.empty()) return false;
    for (const char c : key)
        if (c == '.' || c == '[' || c == ']' || c == '"' || c == '\\' || static_cast<unsigned char>(c) <= ' ' ||
            c == 0x7f)
            return false;
    return true;
}

/// The path of member `key` of the object at `parent` ("" is the file's root object).
[[nodiscard]] inline std::string jsonPathMember(std::string_view parent, std::string_view key) {
    std::string path(parent);
    if (isPlainPathKey(key)) {
        if (!path.empty()) path += '.';
        path += key;
        return path;
    }
    // Control characters stay as they are: every message shows them escaped (printable_name.hpp).
    path += "[\"";
    for (const char c : key) {
        if (c == '"' || c == '\\') path += '\\';
        path += c;
    }
    path += "\"]";
    return path;
}

/// The member key that `path` names at `at`, which points at its `.` or `[`, as
/// jsonPathMember() wrote it; `at` moves past it. Nothing when `at` starts no member (the end,
/// an array index).
[[nodiscard]] inline std::optional<std::string> readPathMember(std::string_view path, size_t& at) {
    if (path.substr(at).starts_with('.')) {
        const size_t begin = at + 1;
        const size_t end = std::min(path.find_first_of(".[", begin), path.size());
        if (end == begin) return std::nullopt;
        at = end;
        return std::string(path.substr(begin, end - begin));
    }
    if (!path.substr(at).starts_with("[\"")) return std::nullopt;
    std::string key;
    for (size_t i = at + 2; i < path.size(); ++i) {
        if (path[i] == '\\' && i + 1 < path.size()) {
            key += path[++i];
        } else if (path[i] == '"') {
            if (i + 1 >= path.size() || path[i + 1] != ']') return std::nullopt;
            at = i + 2;
            return key;
        } else {
            key += path[i];
        }
    }
    return std::nullopt;
}

}  // namespace skygraph
