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

/// The length of the valid UTF-8 sequence at the start of `text` (1 to 4), or 0 where its first
/// byte starts none: a stray continuation byte, an overlong form, a surrogate, past U+10FFFF,
/// or cut short.
[[nodiscard]] constexpr size_t utf8SequenceLength(std::string_view text) noexcept {
    const auto byte = [&](size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char lead = byte(0);
    if (lead < 0x80) return 1;
    const size_t length = lead >= 0xc2 && lead <= 0xdf ? 2 : lead >= 0xe0 && lead <= 0xef ? 3 : lead >= 0xf0 && lead <= 0xf4 ? 4 : 0;
    if (length == 0 || text.size() < length) return 0;
    for (size_t i = 1; i < length; ++i)
        if ((byte(i) & 0xc0) != 0x80) return 0;
    // The second byte's range rules out overlong forms, surrogates and code points past U+10FFFF.
    if ((lead == 0xe0 && byte(1) < 0xa0) || (lead == 0xed && byte(1) > 0x9f) || (lead == 0xf0 && byte(1) < 0x90) ||
        (lead == 0xf4 && byte(1) > 0x8f))
        return 0;
    return length;
}

/// `name` with each control character written as JSON writes it (\u0007), and each byte that is
/// not part of valid UTF-8 as \xff, for messages: a terminal or a reader of the log that
/// decodes UTF-8 sees every byte.
[[nodiscard]] inline std::string printableName(std::string_view name) {
    bool plain = true;
    for (const char c : name) plain = plain && !isControlCharacter(c) && static_cast<unsigned char>(c) < 0x80;
    if (plain) return std::string(name);
    std::string out;
    for (size_t i = 0; i < name.size();) {
        const char c = name[i];
        const size_t length = utf8SequenceLength(name.substr(i));
        char escaped[8];
        if (length == 0) {
            std::snprintf(escaped, sizeof escaped, "\\x%02x", static_cast<unsigned char>(c));
            out += escaped;
            ++i;
        } else if (isControlCharacter(c)) {
            std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned char>(c));
            out += escaped;
            ++i;
        } else {
            out.append(name.substr(i, length));
            i += length;
        }
    }
    return out;
}

}  // namespace skygraph
