// Names end up in terminals, logs, text plans, DOT graphs and XML. A control character in one
// (a JSON "\u0007" or "\n") would ring, break a line or make a file invalid. The graph loader
// refuses such names in graph files, where a name is an identifier that plans and code must
// find again; names and paths from scene and glTF files are valid as they are, and every
// message and log line shows them escaped instead. Header-only, for the libraries and the
// tool; not installed.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

namespace skygraph {

/// Why the loader refuses such names, for its messages.
inline constexpr const char* kPrintedNames = "names are printed in plans, DOT graphs and messages";

[[nodiscard]] constexpr bool isControlCharacter(char c) noexcept {
    return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
}

[[nodiscard]] inline bool hasControlCharacter(std::string_view name) noexcept {
    for (const char c : name)
        if (isControlCharacter(c)) return true;
    return false;
}

/// `name` with each control character written as JSON writes it (\u0007), for messages.
[[nodiscard]] inline std::string printableName(std::string_view name) {
    if (!hasControlCharacter(name)) return std::string(name);
    std::string out;
    for (const char c : name) {
        if (!isControlCharacter(c)) {
            out += c;
            continue;
        }
        char escaped[8];
        std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned char>(c));
        out += escaped;
    }
    return out;
}

}  // namespace skygraph
